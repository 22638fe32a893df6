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
from bearingfw.experiment.metrics import metric_family
from bearingfw.experiment.spec import FindingSpec

__all__ = ["DEFAULT_TOLERANCE", "Finding", "check_findings", "explain", "finding_statement"]

#: Relative tolerance of ``equals`` when none is given: round-off of a converged Newton solution.
DEFAULT_TOLERANCE = 1e-6


@attrs.frozen
class Finding:
    """One statement, what the matrix shows, and whether it holds (None: the matrix lacks the data)."""

    statement: str
    measured: str
    holds: bool | None
    group: str = "Findings"
    #: Why it does not hold, computed from the run's matrices (:func:`explain`); empty when it holds.
    explanation: str = ""


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
    """Every declared finding checked on ``matrices``, in the order declared; each one that does not hold
    carries its :func:`explain` text."""
    out = []
    for spec in specs:
        for finding in _check(spec, matrices):
            if finding.holds is False:
                levels = spec.level if spec.test == "same" else (_level_of(spec, finding.statement),)
                finding = attrs.evolve(finding, explanation=explain(spec, matrices, levels))
            out.append(finding)
    return tuple(out)


# ---- why a finding does not hold ------------------------------------------------------------------------
#: A bearing whose peak slip exceeds this (m) slid; below it, round-off of a stuck bearing.
SLIP_TOLERANCE = 1e-6
#: Friction ratios within this (relative) of a model's largest one are "at its cap".
CAP_TOLERANCE = 1e-3


def _level_of(spec: FindingSpec, statement: str) -> str:
    """The level a per-level finding was checked at (its statement names it, else the first)."""
    for level in spec.level:
        if finding_statement(spec, level) == statement:
            return level
    return spec.level[0]


def _items(m: Matrices, family: str) -> list[str]:
    return [metric.partition(".")[2] for metric in m.metrics if metric_family(metric) == family]


def _number(m: Matrices, metric: str, model: str, level: str) -> float:
    value = m.value(metric, model, level)
    return math.nan if value is None else float(value)


def _friction(m: Matrices, model: str, level: str) -> dict | None:
    """The bearings of ``model`` that slid at ``level``, its cap abs(F)/N, and the demand of those that did not."""
    bearings = [b for b in _items(m, "slip") if f"friction_ratio.{b}" in m.values]
    if not bearings:
        return None
    slip = {b: _number(m, f"slip.{b}", model, level) for b in bearings}
    ratio = {b: _number(m, f"friction_ratio.{b}", model, level) for b in bearings}
    governed = [b for b in bearings if math.isfinite(ratio[b])]
    if not governed:
        return None
    slid = [b for b in governed if math.isfinite(slip[b]) and slip[b] > SLIP_TOLERANCE]
    cap = max((ratio[b] for b in slid), default=math.nan)
    return {"bearings": governed, "slid": slid, "slip": slip, "ratio": ratio, "cap": cap,
            "friction": any(math.isfinite(slip[b]) for b in governed)}


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def _span(values: Sequence[float], digits: int = 2, scale: float = 1.0) -> str:
    lo, hi = min(values) * scale, max(values) * scale
    return f"{lo:.{digits}f}" if round(lo, digits) == round(hi, digits) else f"{lo:.{digits}f}-{hi:.{digits}f}"


def _friction_text(m: Matrices, models: Sequence[str], level: str) -> str | None:
    """Which bearings slid under each model, at what friction ratio, against what the others demand."""
    seen = {model: _friction(m, model, level) for model in models}
    if not any(f is not None for f in seen.values()):
        return None
    parts = []
    caps = {}
    for model, f in seen.items():
        if f is None:
            continue
        if f["slid"]:
            caps[model] = f["cap"]
            slips = [f["slip"][b] for b in f["slid"]]
            parts.append(
                f"{model} slid at {len(f['slid'])} of {_count(len(f['bearings']), 'bearing')} at {level} "
                f"({', '.join(f['slid'])}: peak slip {_span(slips, 2, 1e3)} mm, abs(F)/N at its cap {f['cap']:.3g})")
        elif f["friction"]:
            peak = max(f["ratio"][b] for b in f["bearings"])
            parts.append(f"{model} slid at no bearing at {level} (peak abs(F)/N {peak:.3g})")
    for model, f in seen.items():
        if f is None or f["friction"] or not caps:
            continue
        for other, cap in caps.items():
            over = sorted((b for b in f["bearings"] if f["ratio"][b] > cap * (1 + CAP_TOLERANCE)),
                          key=lambda b: -f["ratio"][b])
            if over:
                demand = ", ".join(f"{b} {f['ratio'][b]:.3g}" for b in over)
                parts.append(f"{model} (no slip) needs abs(F)/N above {other}'s cap {cap:.3g} at "
                             f"{_count(len(over), 'bearing')} ({demand})")
            else:
                peak = max(f["ratio"][b] for b in f["bearings"])
                parts.append(f"{model} (no slip) needs at most abs(F)/N {peak:.3g}, within {other}'s cap {cap:.3g}")
    return "; ".join(parts) if parts else None


def _elsewhere(m: Matrices, spec: FindingSpec, level: str) -> str | None:
    """The same ratio at the family's other items: is the departure local or everywhere?"""
    family, _, item = spec.metric.partition(".")
    others = [i for i in _items(m, family) if i != item]
    ratios = []
    for other in others:
        a, b = (_number(m, f"{family}.{other}", name, level) for name in spec.models)
        if math.isfinite(a) and math.isfinite(b) and b != 0:
            ratios.append(f"{other} {a / b:.2f}")
    if not ratios:
        return None
    return f"{spec.subject} of {family} at {level} elsewhere: {', '.join(ratios)}"


#: The family of whole-structure responses whose ratio says whether two models differ everywhere.
GLOBAL_FAMILY = "deck_acceleration"


def _global(m: Matrices, spec: FindingSpec, level: str) -> str | None:
    """The two models' ratio of the peak deck accelerations per direction (what moves the whole deck)."""
    if metric_family(spec.metric) == GLOBAL_FAMILY:
        return None
    ratios = []
    for item in _items(m, GLOBAL_FAMILY):
        a, b = (_number(m, f"{GLOBAL_FAMILY}.{item}", name, level) for name in spec.models)
        if math.isfinite(a) and math.isfinite(b) and b != 0:
            ratios.append(f"{item} {a / b:.2f}")
    return f"{spec.subject} of the peak {GLOBAL_FAMILY} at {level}: {', '.join(ratios)}" if ratios else None


def explain(spec: FindingSpec, matrices: Matrices, levels: Sequence[str]) -> str:
    """Why ``spec`` does not hold at ``levels``: the quantities of the run that decide it, as text.

    Generic, from the matrices any run has: for a ratio of two models, the bearings each model
    slid at (peak slip, and the friction ratio abs(F)/N they slid at: the model's cap) against the
    friction ratio the non-sliding model asks of the same bearings, the same ratio at the
    family's other items (one place or everywhere) and of the peak deck accelerations per direction
    (which motion the two models share); for a ``same`` test, the spread of the values;
    for one model's value, that value against the bound and, for a bearing item, its slip.
    """
    parts: list[str] = []
    family, _, item = spec.metric.partition(".")
    if spec.test == "same":
        values = [_quantity(matrices, spec, level) for level in levels]
        parts.append(f"{spec.subject} varies by {max(values) / min(values) - 1:.2%} across {', '.join(levels)}"
                     if min(values) > 0 else f"{spec.subject} = {', '.join(f'{v:.4g}' for v in values)}")
        models = spec.models or (spec.model,)
        for level in levels:
            text = _friction_text(matrices, models, level)
            if text:
                parts.append(text)
        return "; ".join(parts)
    level = levels[0]
    x = _quantity(matrices, spec, level)
    side = {"within": f"abs(x - 1) = {abs(x - 1):.3f} > {spec.bound:g}", "below": f"{x:.4g} >= {spec.bound:g}",
            "above": f"{x:.4g} <= {spec.bound:g}", "equals": f"{x:.6g} != {spec.bound:g}"}[spec.test]
    parts.append(side)
    if spec.models is not None:
        text = _friction_text(matrices, spec.models, level)
        if text:
            parts.append(text)
        for text in (_elsewhere(matrices, spec, level), _global(matrices, spec, level)):
            if text:
                parts.append(text)
    else:
        slip = _number(matrices, f"slip.{item}", spec.model, level)
        if math.isfinite(slip):
            parts.append(f"{item} of {spec.model} " + (f"slid {slip * 1e3:.3g} mm" if slip > SLIP_TOLERANCE
                                                      else "did not slide (it stuck)") + f" at {level}")
        text = _friction_text(matrices, (spec.model,), level)
        if text:
            parts.append(text)
    return "; ".join(parts)
