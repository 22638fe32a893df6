"""The paper's findings (section 4.1), checked on a matrix: what the default study should show.

The paper compares maximum principal stresses at S1 (mid main span) and 3B (over a sliding
bearing) and the forces in bearing 3B for M0 (frictionless), M1 (springs K_s) and M2
(regularized Coulomb, mu = 0.04). Stated as testable inequalities (the bearingfw design notes):

1. D_0: M1 and M2 within 15 % of each other at S1 and at 3B (the bearings stick);
2. D_0: M0 below 0.7 x M1 at S1 and below 0.3 x M1 at 3B (the paper: about a half, a tenth);
3. the M0/M1 ratios equal under D_0 and D_II (both models linear);
4. D_II: M2 at 3B below 0.7 x M1 (friction caps the force the girder gets);
5. M2's maximum friction ratio abs(F)/N at 3B equals mu under D_II, D_III and D_IV (it slides).

The paper's linearity argument (3) holds for the dynamic part of the stress (the total adds
the same dead-load stress at every intensity), so the stress findings are checked on the
``stress_dynamic`` family by default; :func:`paper_findings` takes another family to show the
totals.
"""

from __future__ import annotations

import math

import attrs

from bearingfw.experiment.matrices import Matrices

__all__ = ["Finding", "applies", "paper_findings"]

#: Relative tolerance of the equalities (3, 5): round-off of a converged Newton solution.
EQUAL = 1e-6


@attrs.frozen
class Finding:
    """One statement, what the matrix shows, and whether it holds (None: the matrix lacks the data)."""

    statement: str
    measured: str
    holds: bool | None


def applies(matrices: Matrices, family: str = "stress_dynamic") -> bool:
    """True when the matrix has what the findings compare (M0, M1, M2, D_0, D_II, S1, 3B)."""
    needed = {f"{family}.S1", f"{family}.3B", "friction_ratio.3B"}
    return (
        {"M0", "M1", "M2"} <= set(matrices.models)
        and {"D_0", "D_II"} <= set(matrices.intensities)
        and needed <= set(matrices.metrics)
    )


def _ratio(m: Matrices, metric: str, a: str, b: str, level: str) -> float:
    x, y = m.value(metric, a, level), m.value(metric, b, level)
    return x / y if math.isfinite(x) and math.isfinite(y) and y != 0 else math.nan


def _check(statement: str, measured: str, value: float, test) -> Finding:
    return Finding(statement, measured, None if not math.isfinite(value) else bool(test(value)))


def paper_findings(matrices: Matrices, mu: float = 0.04, family: str = "stress_dynamic") -> list[Finding]:
    """The findings of the module docstring on ``matrices`` (stresses of ``family``)."""
    if not applies(matrices, family):
        return []
    out = []
    for where in ("S1", "3B"):
        metric = f"{family}.{where}"
        r = _ratio(matrices, metric, "M2", "M1", "D_0")
        out.append(_check(f"D_0, {where}: M1 and M2 within 15 %", f"M2/M1 = {r:.3f}", r, lambda v: abs(v - 1) <= 0.15))
    for where, bound in (("S1", 0.7), ("3B", 0.3)):
        metric = f"{family}.{where}"
        r = _ratio(matrices, metric, "M0", "M1", "D_0")
        out.append(_check(f"D_0, {where}: M0 below {bound} x M1", f"M0/M1 = {r:.3f}", r, lambda v, b=bound: v < b))
    for where in ("S1", "3B"):
        metric = f"{family}.{where}"
        r0, r2 = _ratio(matrices, metric, "M0", "M1", "D_0"), _ratio(matrices, metric, "M0", "M1", "D_II")
        diff = abs(r2 / r0 - 1) if math.isfinite(r0) and math.isfinite(r2) and r0 else math.nan
        out.append(_check(f"{where}: M0/M1 the same under D_0 and D_II (linear models)",
                          f"{r0:.6f} and {r2:.6f}", diff, lambda v: v <= EQUAL))
    r = _ratio(matrices, f"{family}.3B", "M2", "M1", "D_II")
    out.append(_check("D_II, 3B: M2 below 0.7 x M1", f"M2/M1 = {r:.3f}", r, lambda v: v < 0.7))
    for level in ("D_II", "D_III", "D_IV"):
        if level not in matrices.intensities:
            continue
        value = matrices.value("friction_ratio.3B", "M2", level)
        out.append(_check(f"{level}: M2's maximum friction ratio at 3B equals mu = {mu:g}",
                          f"max abs(F)/N = {value:.6g}", value, lambda v: abs(v / mu - 1) <= EQUAL))
    return out
