"""Members: 3D frame elements, truss bars (hangers) and rigid links (offsets).

Local axes of a frame element: ``x`` from node ``i`` to node ``j``; ``y = normalize(v x x)`` and
``z = x x y``, where ``v`` is the element's ``orientation``, any vector in the local x-z plane.
When ``orientation`` is not given, ``v`` is the global Z (so for a horizontal member local z is
vertical up and ``Iy`` governs vertical bending: along X, ``y = Y``; along Y, ``y = -X``). For a
vertical or near-vertical member (axis within 1e-3 rad of global Z,
:data:`~bearingfw.model.assembly.NEAR_VERTICAL`) ``v = -X``: a member pointing up has local
``y = +Y`` and ``z = -X`` (pointing down: ``y = -Y``, ``z = -X``), and a slightly tilted one
axes within its tilt of those, whichever way it leans (a pier's axes do not depend on
round-off in its coordinates).
"""

from __future__ import annotations

import attrs

from bearingfw.model._fields import ModelError, choice, name_field, node_ref, owner_of, vector3
from bearingfw.model.materials import Material
from bearingfw.model.sections import Section
from bearingfw.parameters import parameter

__all__ = ["FrameElement", "TrussElement", "RigidLink", "MASS_OPTIONS"]

MASS_OPTIONS = ("consistent", "lumped")


def _instance_of(kind: type, label: str):
    def check(instance, attribute, value):
        if not isinstance(value, kind):
            raise ModelError(f"{owner_of(instance)}: field {attribute.name!r} must be a {label}, got {value!r}")

    return check


def _distinct_nodes(instance):
    if instance.i == instance.j:
        raise ModelError(
            f"{type(instance).__name__} {instance.name!r}: fields 'i' and 'j' name the same node {instance.i!r}"
        )


@attrs.frozen
class FrameElement:
    """A two-node 3D beam: axial, torsion (St-Venant) and bending in two planes.

    ``shear_deformation=True`` gives the Timoshenko stiffness (needs the section's shear areas);
    the mass matrix is the Euler-Bernoulli one in either case. ``mass`` chooses the consistent
    (cubic Hermitian) or lumped (half the member at each node, no rotary inertia in bending)
    mass matrix. ``added_mass`` is non-structural mass per length (superimposed dead load: deck
    finishes, barriers): it enters the mass matrix and the gravity load like the member's own.
    """

    name: str = name_field()
    i: str = node_ref("start node")
    j: str = node_ref("end node")
    section: Section = attrs.field(validator=_instance_of(Section, "Section"))
    material: Material = attrs.field(validator=_instance_of(Material, "Material"))
    orientation: tuple[float, float, float] | None = vector3(
        default=None, nonzero=True, optional=True, doc="a vector in the local x-z plane"
    )
    shear_deformation: bool = attrs.field(default=False, validator=attrs.validators.instance_of(bool))
    mass: str = choice(MASS_OPTIONS, default="consistent", doc="mass matrix")
    added_mass: float = parameter(low=0.0, default=0.0, unit="kg/m", doc="non-structural mass per length")

    def __attrs_post_init__(self):
        _distinct_nodes(self)
        if self.shear_deformation and (self.section.Avy is None or self.section.Avz is None):
            raise ModelError(
                f"FrameElement {self.name!r}: field 'shear_deformation' needs the shear areas Avy and Avz "
                f"of section {self.section.name!r}"
            )


@attrs.frozen
class TrussElement:
    """A pin-ended bar carrying axial force only (hangers, truss members)."""

    name: str = name_field()
    i: str = node_ref("start node")
    j: str = node_ref("end node")
    area: float = parameter(low=0.0, low_open=True, unit="m^2", doc="cross-section area")
    material: Material = attrs.field(validator=_instance_of(Material, "Material"))
    mass: str = choice(MASS_OPTIONS, default="consistent", doc="mass matrix")
    added_mass: float = parameter(low=0.0, default=0.0, unit="kg/m", doc="non-structural mass per length")

    def __attrs_post_init__(self):
        _distinct_nodes(self)


@attrs.frozen
class RigidLink:
    """A rigid offset: the ``slave`` node's six DOFs follow the ``master`` node as a rigid body.

    ``u_s = u_m + theta_m x (X_s - X_m)`` and ``theta_s = theta_m``. It is imposed as a
    constraint (no stiffness number), e.g. girder axis (master) to bearing soffit (slave).
    """

    name: str = name_field()
    master: str = node_ref("master node")
    slave: str = node_ref("slave node")

    def __attrs_post_init__(self):
        if self.master == self.slave:
            raise ModelError(f"RigidLink {self.name!r}: fields 'master' and 'slave' name the same node {self.master!r}")
