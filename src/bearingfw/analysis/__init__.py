"""Analyses on an assembled model: static (gravity preload), modal (eigen, MAC), element results,
transient (HHT-alpha time history with recorders and an energy balance).

Every analysis takes a :class:`~bearingfw.model.Model` (assembled on the fly, laws from the
installed plugins or from ``registry=``) or an already built :class:`~bearingfw.model.System`.
"""

from bearingfw.analysis.damping import Rayleigh, damping_ratio_from_log_decrement, rayleigh_from_ratios
from bearingfw.analysis.energy import ENERGY_COLUMNS, Energy
from bearingfw.analysis.excitation import SupportMotion, support_groups
from bearingfw.analysis.history import TransientResult
from bearingfw.analysis.modal import (
    DEFAULT_SHIFT,
    LABELS,
    ModalResult,
    automac,
    eigen,
    energy_shares,
    initial_tangent,
    label_modes,
    mac,
    movable_mass,
    participation,
    solve_modal,
)
from bearingfw.analysis.recorders import ConnectorResponse, ElementForces, ElementStress, NodalResponse, SupportResponse
from bearingfw.analysis.results import (
    SECTION_COMPONENTS,
    SectionForces,
    Stresses,
    element_stresses,
    principal_stress,
    section_forces,
    section_stresses,
)
from bearingfw.analysis.static import (
    BEARINGS,
    ConvergenceError,
    StaticResult,
    StiffnessRangeError,
    factorize,
    gravity,
    recover_connector_forces,
    solve_static,
)
from bearingfw.analysis.transient import TransientError, TransientSettings, initial_acceleration, solve_transient

__all__ = [
    "support_groups",
    "BEARINGS",
    "ConnectorResponse",
    "DEFAULT_SHIFT",
    "ENERGY_COLUMNS",
    "ElementForces",
    "ElementStress",
    "Energy",
    "LABELS",
    "ConvergenceError",
    "ModalResult",
    "NodalResponse",
    "Rayleigh",
    "SECTION_COMPONENTS",
    "SectionForces",
    "StiffnessRangeError",
    "SupportMotion",
    "SupportResponse",
    "StaticResult",
    "Stresses",
    "TransientError",
    "TransientResult",
    "TransientSettings",
    "automac",
    "damping_ratio_from_log_decrement",
    "eigen",
    "element_stresses",
    "energy_shares",
    "factorize",
    "gravity",
    "initial_acceleration",
    "initial_tangent",
    "label_modes",
    "mac",
    "movable_mass",
    "solve_modal",
    "participation",
    "principal_stress",
    "rayleigh_from_ratios",
    "recover_connector_forces",
    "section_forces",
    "section_stresses",
    "solve_static",
    "solve_transient",
]
