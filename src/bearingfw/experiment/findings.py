"""Findings: the statements an experiment declares (``[[findings]]``), checked on its matrices.

Each :class:`~bearingfw.experiment.spec.FindingSpec` reads one metric at one or more intensities,
of a ratio of two models (A/B at the same intensity) or of one model's value, and makes one
test (``within``, ``below``, ``above``, ``equals``, ``same``: the spec's docstring). A statement
that names several levels is checked at each (one :class:`Finding` per level), except ``same``,
which compares them. A finding holds, fails, or cannot be judged (``holds`` None: a value the
matrix lacks, a failed or missing cell, a zero divisor). The built-in study declares its own
findings this way (:mod:`bearingfw.bridges.paper_study`); a user's file does the same.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import attrs

from bearingfw.experiment.matrices import Matrices
from bearingfw.experiment.spec import FindingSpec

__all__ = ["DEFAULT_TOLERANCE", "Finding", "check_findings", "finding_statement"]

#: Relative tolerance of ``equals`` when none is given: round-off of a converged Newton solution.
DEFAULT_TOLERANCE = 1e-6


@attrs.frozen
class Finding:
    """One statement, what the matrix shows, and whether it holds (None: the matrix lacks the data)."""

    statement: str
    measured: str
    holds: bool | None
    group: str = "Findings"


def _quantity(m: Matrices, spec: FindingSpec, level: str) -> float:
    """The finding's number at ``level``: the ratio A/B, or A's value (NaN where undefined)."""
    if spec.model is not None:
        return m.value(spec.metric, spec.model, level)
    a, b = (m.value(spec.metric, name, level) for name in spec.models)
    return a / b if math.isfinite(a) and math.isfinite(b) and b != 0 else math.nan


def _written(spec: FindingSpec) -> str:
    """A statement written from the fields, when the spec gives no ``name``."""
    test, bound = spec.test, spec.bound
    if spec.models is not None:
        a, b = spec.models
        words = {
            "within": f"{a} and {b} within {bound:.4g} of each other (ratio)",
            "below": f"{a} below {bound:g} x {b}",
            "above": f"{a} above {bound:g} x {b}",
            "equals": f"{a}/{b} equals {bound:g}",
            "same": f"{a}/{b} the same under {' and '.join(spec.level)}",
        }[test]
    else:
        words = {
            "within": f"{spec.model} within {bound:g} of 1",
            "below": f"{spec.model} below {bound:g}",
            "above": f"{spec.model} above {bound:g}",
            "equals": f"{spec.model} equals {bound:g}",
            "same": f"{spec.model} the same under {' and '.join(spec.level)}",
        }[test]
    where = "" if test == "same" else "{level}, "
    return f"{where}{spec.metric}: {words}"


def finding_statement(spec: FindingSpec, level: str | None = None) -> str:
    """The statement as reported: ``name`` (or one written from the fields) with ``{level}`` filled in."""
    text = spec.name if spec.name is not None else _written(spec)
    return text.replace("{level}", level if level is not None else ", ".join(spec.level))


def _measured(spec: FindingSpec, x: float) -> str:
    if spec.models is not None:
        return f"{spec.subject} = {x:.3f}"
    return f"{spec.metric} of {spec.model} = {x:.6g}"


def _holds(spec: FindingSpec, x: float) -> bool:
    test, bound = spec.test, spec.bound
    if test == "within":
        return abs(x - 1.0) <= bound
    if test == "below":
        return x < bound
    if test == "above":
        return x > bound
    tolerance = DEFAULT_TOLERANCE if spec.tolerance is None else spec.tolerance
    return abs(x - bound) <= (tolerance * abs(bound) if bound != 0 else tolerance)


def _check(spec: FindingSpec, matrices: Matrices) -> list[Finding]:
    if spec.test == "same":
        values = [_quantity(matrices, spec, level) for level in spec.level]
        measured = " and ".join(f"{v:.6f}" for v in values)
        first = values[0]
        usable = all(math.isfinite(v) for v in values) and first != 0
        holds = all(abs(v / first - 1.0) <= spec.same for v in values[1:]) if usable else None
        return [Finding(finding_statement(spec), measured, holds, spec.group)]
    out = []
    for level in spec.level:
        x = _quantity(matrices, spec, level)
        holds = bool(_holds(spec, x)) if math.isfinite(x) else None
        out.append(Finding(finding_statement(spec, level), _measured(spec, x), holds, spec.group))
    return out


def check_findings(specs: Sequence[FindingSpec], matrices: Matrices) -> tuple[Finding, ...]:
    """Every declared finding checked on ``matrices``, in the order declared."""
    return tuple(f for spec in specs for f in _check(spec, matrices))
