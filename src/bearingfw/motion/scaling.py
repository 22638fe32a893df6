"""Scaling targets: PGA_H10 (the intensity degrees), PGA, Sa(T, 5 %) or the record as recorded.

A :class:`ScaleTarget` says what a record is scaled to; :func:`scale_factor` is the one factor
that does it and :func:`scale_record` applies it. Every measure here is positively homogeneous
(a linear filter or oscillator, then a norm or a geometric mean), so one factor is exact.

=========== ================================================================================
kind        the record's measure that becomes ``value`` (m/s^2)
=========== ================================================================================
pga_h10     PGA_H10: peak of the resultant of both horizontals low-passed at 10 Hz
            (:func:`~bearingfw.motion.pga_h10`). The intensity levels D_0 .. D_IV resolve to
            this kind with ``level`` set, and their degree is then checked.
pga         PGA: peak of the resultant of both horizontals, unfiltered,
            ``max_k sqrt(h1_k^2 + h2_k^2)`` (a single horizontal's own peak when the other is zero).
sa          Sa(T, 5 %): pseudo-spectral acceleration at ``period`` T of the horizontals: the
            geometric mean ``sqrt(Sa_h1 Sa_h2)`` of the two horizontal components' spectra, or a
            single horizontal's own Sa when the other is zero (a record with one horizontal
            component). ``period`` None means "the structure's first mode": the caller
            resolves it (:meth:`ScaleTarget.with_period`) before scaling.
as-recorded the record unchanged (factor 1); ``value`` and ``period`` are not given.
=========== ================================================================================
"""

from __future__ import annotations

import re
from typing import Any

import attrs
import numpy as np

from bearingfw.motion.intensity import (
    DEFAULT_LEVELS,
    LEVEL_NAMES,
    IntensityLevels,
    checked_level,
    level_name,
)
from bearingfw.motion.metrics import DEFAULT_DAMPING, record_pga_h10, response_spectrum
from bearingfw.motion.record import Record
from bearingfw.parameters import ParameterError, choice, parameter
from bearingfw.plugins.contracts import IntensityScale

__all__ = [
    "SA_DAMPING",
    "SCALE_KINDS",
    "ScaleTarget",
    "horizontal_pga",
    "horizontal_sa",
    "horizontal_spectrum",
    "parse_target",
    "scale_factor",
    "scale_record",
]

#: The kinds of :class:`ScaleTarget` (module docstring).
SCALE_KINDS = ("pga_h10", "pga", "sa", "as-recorded")

#: Damping ratio of the Sa(T) a target names (5 %).
SA_DAMPING = DEFAULT_DAMPING


def _default_label(target: ScaleTarget) -> str:
    if target.kind == "as-recorded" or not isinstance(target.value, float):
        return str(target.kind)  # a missing or bad value is reported by the checks, not here
    if target.kind == "pga_h10":
        return f"PGA_H10={target.value:g}"  # the cell names of plain PGA_H10 values so far
    if target.kind == "pga":
        return f"pga={target.value:g}"
    period = f"{target.period:g}s" if isinstance(target.period, float) else "T1"
    return f"sa={target.value:g}@{period}"


def _default_level(target: ScaleTarget) -> str | None:
    return target.label if target.kind == "pga_h10" and target.label in LEVEL_NAMES else None


def _check_label(instance, attribute, value):
    if not isinstance(value, str) or not value.strip():
        raise ParameterError(f"ScaleTarget: parameter 'label' must be a non-empty text, got {value!r}")


def _check_level(instance, attribute, value):
    if value is None:
        return
    if value not in LEVEL_NAMES:
        raise ParameterError(f"ScaleTarget: parameter 'level' must be one of {', '.join(LEVEL_NAMES)} or None, got {value!r}")
    if instance.kind != "pga_h10":
        raise ParameterError(f"ScaleTarget: a 'level' ({value}) goes with kind 'pga_h10', not {instance.kind!r}")


@attrs.frozen
class ScaleTarget:
    """What a record is scaled to (module docstring): ``kind``, ``value`` (m/s^2), ``period`` (s,
    "sa" only; None = the structure's first mode, resolved by the caller), ``label`` (the cell's
    name; default ``PGA_H10=0.46``, ``pga=2``, ``sa=2@0.5s``, ``sa=2@T1``, ``as-recorded``) and
    ``level`` (D_0 .. D_IV for a level's PGA_H10, whose degree :func:`scale_record` checks; default:
    the label if it is a level name and the kind "pga_h10").
    """

    kind: str = choice(SCALE_KINDS, doc="what the record is scaled to")
    value: float | None = parameter(optional=True, low=0.0, low_open=True, unit="m/s^2", doc="target of the measure")
    period: float | None = parameter(optional=True, low=0.0, low_open=True, unit="s", doc="period of Sa (kind 'sa')")
    label: str = attrs.field(default=attrs.Factory(_default_label, takes_self=True), validator=_check_label)
    level: str | None = attrs.field(default=attrs.Factory(_default_level, takes_self=True), validator=_check_level)

    def __attrs_post_init__(self):
        if self.kind == "as-recorded":
            if self.value is not None or self.period is not None:
                raise ParameterError("ScaleTarget: kind 'as-recorded' takes no 'value' and no 'period' (the factor is 1)")
            return
        if self.value is None:
            raise ParameterError(f"ScaleTarget: kind {self.kind!r} needs a 'value' > 0 (m/s^2)")
        if self.kind != "sa" and self.period is not None:
            raise ParameterError(f"ScaleTarget: 'period' goes with kind 'sa', not {self.kind!r}")

    @classmethod
    def for_level(cls, level: Any, levels: IntensityLevels = DEFAULT_LEVELS) -> ScaleTarget:
        """The PGA_H10 of intensity level ``level`` (``"D_II"``, ``"d2"``, ...) in ``levels``."""
        name = level_name(level)
        return cls(kind="pga_h10", value=levels[name], label=name, level=name)

    @property
    def needs_period(self) -> bool:
        """True for an Sa target whose period is still "the structure's first mode"."""
        return self.kind == "sa" and self.period is None

    def with_period(self, period: float) -> ScaleTarget:
        """The target with its Sa period set (the label stays, e.g. ``sa=2@T1``)."""
        if self.kind != "sa":
            raise ParameterError(f"ScaleTarget {self.label!r}: only an 'sa' target has a period")
        return attrs.evolve(self, period=period)

    def describe(self) -> str:
        """A phrase for printouts: ``PGA_H10 = 0.46 m/s^2 (level D_II)``, ``Sa(0.5 s, 5 %) = 2 m/s^2``."""
        if self.kind == "as-recorded":
            return "as recorded (factor 1)"
        if self.kind == "pga_h10":
            return f"PGA_H10 = {self.value:g} m/s^2" + (f" (level {self.level})" if self.level else "")
        if self.kind == "pga":
            return f"PGA = {self.value:g} m/s^2 (horizontal resultant)"
        period = "T1" if self.period is None else f"{self.period:g} s"
        return f"Sa({period}, {SA_DAMPING:.0%}) = {self.value:g} m/s^2 (horizontals' geometric mean)"

    def to_dict(self) -> dict:
        """Plain data (for a cell's digest and JSON files)."""
        return attrs.asdict(self)


_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_TARGET = re.compile(
    rf"^(?P<kind>pga_h10|pga|sa)\s*=\s*(?P<value>{_NUMBER})\s*(?:@\s*(?P<period>{_NUMBER}|T1)\s*s?)?$", re.IGNORECASE
)


def parse_target(text: str, levels: IntensityLevels = DEFAULT_LEVELS) -> ScaleTarget:
    """A target from text: ``as-recorded``, a level (``D_II``), ``pga_h10=0.46``, ``pga=2``,
    ``sa=2@0.5`` (or ``sa=2@0.5s``; ``sa=2@T1`` leaves the period to the caller); m/s^2 and s."""
    raw = str(text).strip()
    if raw.lower().replace("_", "-") == "as-recorded":
        return ScaleTarget(kind="as-recorded")
    found = _TARGET.match(raw)
    if found is None:
        try:
            return ScaleTarget.for_level(raw, levels)
        except ParameterError:
            raise ParameterError(
                f"scale target {text!r} not understood; write as-recorded, a level ({', '.join(LEVEL_NAMES)}), "
                "pga_h10=VALUE, pga=VALUE or sa=VALUE@PERIOD (m/s^2 and s; sa=VALUE@T1 for the first mode)"
            ) from None
    kind, period = found["kind"].lower(), found["period"]
    if kind != "sa" and period is not None:
        raise ParameterError(f"scale target {text!r}: '@PERIOD' goes with sa=VALUE@PERIOD only")
    if kind == "sa" and period is None:
        raise ParameterError(f"scale target {text!r}: Sa needs a period, e.g. sa={found['value']}@0.5 (s) or @T1")
    return ScaleTarget(
        kind=kind, value=float(found["value"]), period=None if period is None or period.upper() == "T1" else float(period)
    )


def horizontal_pga(record: Record) -> float:
    """PGA (m/s^2): peak of the unfiltered horizontal resultant, ``max_k sqrt(h1_k^2 + h2_k^2)``."""
    return float(np.max(np.hypot(record.h1, record.h2)))


def _horizontals(record: Record) -> list[tuple[str, np.ndarray]]:
    return [(name, values) for name, values in zip(record.names[:2], (record.h1, record.h2)) if np.any(values)]


def horizontal_spectrum(record: Record, periods, damping: float = SA_DAMPING) -> np.ndarray:
    """Sa(T) (m/s^2) of the horizontals at each of ``periods``: the geometric mean of both
    components' pseudo-spectral accelerations, or the one non-zero horizontal's own (module
    docstring); zeros if both horizontals are zero."""
    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    horizontals = _horizontals(record)
    if not horizontals:
        return np.zeros(periods.size)
    sa = np.vstack([response_spectrum(values, record.dt, periods, damping).psa for _, values in horizontals])
    return np.prod(sa, axis=0) ** (1.0 / len(horizontals))


def horizontal_sa(record: Record, period: float, damping: float = SA_DAMPING) -> float:
    """Sa(T) (m/s^2) of the horizontals at one period (:func:`horizontal_spectrum`)."""
    if not _horizontals(record):
        raise ParameterError(f"{record.title}: no horizontal motion (x and y are zero): Sa of the horizontals is zero")
    return float(horizontal_spectrum(record, [period], damping)[0])


def _measure(record: Record, target: ScaleTarget) -> tuple[float, str]:
    if target.kind == "pga_h10":
        return record_pga_h10(record), "PGA_H10"
    if target.kind == "pga":
        return horizontal_pga(record), "PGA (horizontal resultant)"
    if target.period is None:
        raise ParameterError(
            f"scale target {target.label!r}: the Sa period is 'the structure's first mode', which must be resolved "
            "to a number (ScaleTarget.with_period) before scaling"
        )
    return horizontal_sa(record, target.period), f"Sa({target.period:g} s, {SA_DAMPING:.0%})"


def scale_factor(record: Record, target: ScaleTarget) -> float:
    """The factor that makes ``record``'s measure (``target.kind``) equal ``target.value``; 1 for as-recorded."""
    if not isinstance(target, ScaleTarget):
        raise TypeError(f"scale_factor: expected a bearingfw.motion.ScaleTarget, got {target!r}")
    if target.kind == "as-recorded":
        return 1.0
    current, what = _measure(record, target)
    if not current > 0:
        raise ParameterError(f"{record.title}: its {what} is zero (no horizontal motion), it cannot be scaled to {target.label}")
    return target.value / current


def scale_record(record: Record, target: ScaleTarget, scale: IntensityScale | None = None) -> Record:
    """``record`` times :func:`scale_factor`; the metadata say the target (``target``,
    ``target_kind``, and ``target_pga_h10`` / ``target_pga`` / ``target_sa`` with ``target_period``).

    A level's target (``target.level``) is checked as :func:`~bearingfw.motion.scale_to_level`
    does: the scaled record must be of the level's degree on ``scale`` (default scale), else
    :class:`~bearingfw.motion.IntensityMismatchError`.
    """
    factor = scale_factor(record, target)
    extra: dict[str, Any] = {"target": target.label, "target_kind": target.kind}
    if target.kind != "as-recorded":
        extra[f"target_{target.kind}"] = target.value
    if target.kind == "sa":
        extra["target_period"] = target.period
    scaled = record.scaled(factor, **extra)
    if target.level is not None:
        return checked_level(record, scaled, target.level, target.value, scale)
    return scaled
