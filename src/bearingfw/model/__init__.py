"""The FE model: a validated description (nodes, members, connectors, ...) and its assembly.

Describe a structure with the attrs classes below, put them in a :class:`Model`, then
:func:`build_system` assembles it for the analyses in :mod:`bearingfw.analysis`::

    from bearingfw.model import Connector, FrameElement, Material, Model, NodalMass, Node, Section, Support
    from bearingfw.analysis import gravity, solve_modal

    concrete = Material("C30/37", 33e9, density=2500.0)
    pier = Section.rectangle("pier", 1.4, 1.4)
    model = Model(
        nodes=[Node("base", 0, 0, 0), Node("top", 0, 0, 5.9), Node("deck", 0, 0, 5.9)],
        elements=[FrameElement("pier", "base", "top", pier, concrete)],
        connectors=[Connector("3B", "top", "deck", "planar", law="linear-spring",
                              law_params={"k": 4e8}, vertical_stiffness=5e9)],
        supports=[Support("base")],
        masses=[NodalMass("deck", 2e5)],
    )
    preload = gravity(model)                 # bearing normal forces, committed law states
    modes = solve_modal(preload.system, 3, preload=preload)

Units SI; global z is vertical (up). Names: nodes, elements, connectors and rigid links are
looked up by name (``model.connector("3B")``).
"""

from bearingfw.model._fields import ModelError
from bearingfw.model.assembly import FrameArrays, TrussArrays
from bearingfw.model.connectors import (
    Connector,
    ConnectorKind,
    ConnectorOperators,
    LawGroup,
    axes_from_rotation,
    build_connector_operators,
    connector_frame,
    normal_force,
)
from bearingfw.model.constraints import Constraints
from bearingfw.model.dofs import DofMap
from bearingfw.model.elements import FrameElement, RigidLink, TrussElement
from bearingfw.model.equations import Equation
from bearingfw.model.materials import Material
from bearingfw.model.model import Model
from bearingfw.model.nodes import COMPONENTS, FIXED, PINNED, NodalLoad, NodalMass, Node, Support
from bearingfw.model.sections import Section, StressPoint, rectangle_torsion
from bearingfw.model.system import DIRECTIONS, System, as_system, build_system

__all__ = [
    "COMPONENTS",
    "Connector",
    "ConnectorKind",
    "ConnectorOperators",
    "Constraints",
    "DIRECTIONS",
    "DofMap",
    "Equation",
    "FIXED",
    "FrameArrays",
    "FrameElement",
    "LawGroup",
    "Material",
    "Model",
    "ModelError",
    "NodalLoad",
    "NodalMass",
    "Node",
    "PINNED",
    "RigidLink",
    "Section",
    "StressPoint",
    "Support",
    "System",
    "TrussArrays",
    "TrussElement",
    "as_system",
    "axes_from_rotation",
    "build_connector_operators",
    "build_system",
    "connector_frame",
    "normal_force",
    "rectangle_torsion",
]
