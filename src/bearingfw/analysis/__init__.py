"""Analyses on an assembled model: static (gravity preload), modal (eigen, MAC), element results.

Every analysis takes a :class:`~bearingfw.model.Model` (assembled on the fly, laws from the
installed plugins or from ``registry=``) or an already built :class:`~bearingfw.model.System`.
"""

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
    factorize,
    gravity,
    recover_connector_forces,
    solve_static,
)

__all__ = [
    "BEARINGS",
    "DEFAULT_SHIFT",
    "LABELS",
    "ConvergenceError",
    "ModalResult",
    "SECTION_COMPONENTS",
    "SectionForces",
    "StaticResult",
    "Stresses",
    "automac",
    "eigen",
    "element_stresses",
    "energy_shares",
    "factorize",
    "gravity",
    "initial_tangent",
    "label_modes",
    "mac",
    "movable_mass",
    "solve_modal",
    "participation",
    "principal_stress",
    "recover_connector_forces",
    "section_forces",
    "section_stresses",
    "solve_static",
]
