"""Tools for testing bearing laws, ours and third parties': drive, strategies, the conformance kit."""

from bearingfw.testing.conformance import (
    ConformanceError,
    applicable_checks,
    call_compiled,
    check_law,
    make_context,
    parametrize_with_checks,
)
from bearingfw.testing.drive import drive, path_velocities, run_history
from bearingfw.testing.strategies import (
    closed_cycles,
    contact_force_histories,
    displacement_paths,
    histories,
    law_parameters,
    laws,
    normal_force_histories,
    per_bearing_laws,
    unit_arrays,
    velocity_histories,
)

__all__ = [
    "ConformanceError",
    "applicable_checks",
    "call_compiled",
    "check_law",
    "closed_cycles",
    "contact_force_histories",
    "displacement_paths",
    "drive",
    "histories",
    "law_parameters",
    "laws",
    "make_context",
    "normal_force_histories",
    "parametrize_with_checks",
    "path_velocities",
    "per_bearing_laws",
    "run_history",
    "unit_arrays",
    "velocity_histories",
]
