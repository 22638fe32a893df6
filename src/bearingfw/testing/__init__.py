"""Tools for testing bearing laws, ours and third parties': drive, strategies, conformance suite."""

from bearingfw.testing.conformance import (
    ConformanceError,
    applicable_checks,
    check_law,
    make_context,
    parametrize_with_checks,
)
from bearingfw.testing.drive import drive, run_history
from bearingfw.testing.strategies import (
    closed_cycles,
    displacement_paths,
    law_parameters,
    laws,
    normal_force_histories,
)

__all__ = [
    "ConformanceError",
    "applicable_checks",
    "check_law",
    "closed_cycles",
    "displacement_paths",
    "drive",
    "law_parameters",
    "laws",
    "make_context",
    "normal_force_histories",
    "parametrize_with_checks",
    "run_history",
]
