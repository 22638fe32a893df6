"""The data types of the hooks that contribute data: record readers, intensity scales, presets.

They live in the plugin layer (the lowest one) so that the registry can check a contribution
without importing :mod:`bearingfw.motion`; :mod:`bearingfw.motion` re-exports both.

- :class:`RecordReader` describes one file format. The registry accepts any object with the same
  members (``name``, ``suffixes``, ``read``, optionally ``sniff`` and ``description``); this
  class is the convenient way to make one.
- :class:`IntensityScale` is a scale *as data*: degree labels and, for each degree, the inclusive
  upper bound of PGA_H10 as a piecewise-linear function of the duration t_Ha. The registry
  accepts only instances of this class, because classification must mean the same thing for
  every scale.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.parameters import ParameterError

__all__ = ["BearingPreset", "IntensityScale", "PresetBearing", "RecordReader", "BOUNDARY_RTOL", "check_suffixes"]

#: Relative tolerance of a degree boundary: a PGA_H10 within rounding of a boundary is *on* it
#: and so belongs to the lower degree (the bounds are inclusive).
BOUNDARY_RTOL = 1e-9


def _non_empty_name(instance, attribute, value):
    if not isinstance(value, str) or not value.strip():
        raise ParameterError(f"{type(instance).__name__}: {attribute.name!r} must be a non-empty string, got {value!r}")


def check_suffixes(reader_name: str, value: Any) -> tuple[str, ...]:
    """A reader's ``suffixes`` checked (a tuple or list of endings like ``".at2"``) and lower-cased.

    The one check for :class:`RecordReader` and for the duck-typed readers the registry accepts.
    """
    ok = isinstance(value, (tuple, list)) and all(isinstance(s, str) and s.startswith(".") and len(s) > 1 for s in value)
    if not ok:
        raise ParameterError(
            f"record reader {reader_name!r}: 'suffixes' must be a tuple of file-name endings with a leading dot, "
            f"e.g. ('.at2',), got {value!r}"
        )
    return tuple(s.lower() for s in value)


def _suffix_tuple(value: Any) -> Any:
    # One ending given as a string is a common slip; lower-case so that matching is by case-folded names.
    if isinstance(value, str):
        value = (value,)
    try:
        return tuple(s.lower() if isinstance(s, str) else s for s in value)
    except TypeError:
        return value


def _check_suffixes(instance, attribute, value):
    check_suffixes(instance.name, value)


def _check_callable(instance, attribute, value):
    if value is None and attribute.name == "sniff":
        return
    if not callable(value):
        raise ParameterError(f"record reader {instance.name!r}: {attribute.name!r} must be callable, got {value!r}")


@attrs.frozen
class RecordReader:
    """One acceleration-file format.

    ``read(path, *, dt=None, units=None)`` returns a list of :class:`bearingfw.motion.Trace`, one
    per acceleration component in the file, in the file's order (a PEER ``.AT2`` file holds one,
    a column file or an ``.npz`` archive may hold all three). ``dt`` (s) and ``units`` (``"g"``,
    ``"m/s^2"`` or ``"cm/s^2"``) are the user's overrides for formats that do not say; a reader
    for a format that does may check them against the file. A malformed file raises
    :class:`bearingfw.motion.RecordFormatError` naming the file and the line.

    A file is given to a reader whose ``suffixes`` match its name (case-insensitive); ``sniff(path)``,
    when given, confirms the choice, and is also asked for files whose suffix no reader claims.
    """

    name: str = attrs.field(validator=_non_empty_name)
    suffixes: tuple[str, ...] = attrs.field(converter=_suffix_tuple, validator=_check_suffixes)
    read: Callable[..., Sequence[Any]] = attrs.field(validator=_check_callable)
    sniff: Callable[[Path], bool] | None = attrs.field(default=None, validator=_check_callable)
    description: str = ""


def _float_tuple(value: Any) -> Any:
    try:
        return tuple(float(v) if isinstance(v, numbers.Real) and not isinstance(v, bool) else v for v in value)
    except TypeError:
        return value


def _table(value: Any) -> Any:
    try:
        return tuple(_float_tuple(row) for row in value)
    except TypeError:
        return value


def _label_tuple(value: Any) -> Any:
    # tuple("abc") would be ('a', 'b', 'c'): leave a string for the validator to reject.
    if isinstance(value, str):
        return value
    try:
        return tuple(value)
    except TypeError:
        return value


def _check_degrees(instance, attribute, value):
    ok = isinstance(value, tuple) and value and all(isinstance(d, str) and d.strip() for d in value)
    if not ok or len(set(value)) != len(value):
        raise ParameterError(
            f"intensity scale {instance.name!r}: 'degrees' must be distinct non-empty labels, e.g. ('0', 'I', 'II'), got {value!r}"
        )


def _check_durations(instance, attribute, value):
    ok = isinstance(value, tuple) and len(value) >= 1 and all(isinstance(t, float) and math.isfinite(t) and t >= 0 for t in value)
    if not ok or any(b <= a for a, b in zip(value, value[1:])):
        raise ParameterError(
            f"intensity scale {instance.name!r}: 'durations' must be t_Ha breakpoints in s, finite, >= 0 and "
            f"strictly increasing, got {value!r}"
        )


def _check_bounds(instance, attribute, value):
    rows, cols = len(instance.degrees), len(instance.durations)
    shape_ok = isinstance(value, tuple) and len(value) == rows and all(isinstance(r, tuple) and len(r) == cols for r in value)
    if not shape_ok:
        raise ParameterError(
            f"intensity scale {instance.name!r}: 'bounds' must have one row per degree ({rows}) and one value per "
            f"duration breakpoint ({cols}), got {value!r}"
        )
    if not all(isinstance(b, float) and math.isfinite(b) and b > 0 for row in value for b in row):
        raise ParameterError(f"intensity scale {instance.name!r}: every bound must be a finite number > 0 (m/s^2), got {value!r}")
    for j, t in enumerate(instance.durations):
        column = [row[j] for row in value]
        if any(b <= a for a, b in zip(column, column[1:])):
            raise ParameterError(
                f"intensity scale {instance.name!r}: at t_Ha = {t:g} s the upper bounds {column} must increase "
                f"strictly from degree {instance.degrees[0]} to degree {instance.degrees[-1]}"
            )


@attrs.frozen
class IntensityScale:
    """A ground-motion intensity scale in the (t_Ha, PGA_H10) plane, as data.

    ``bounds[i][j]`` is the inclusive upper bound of PGA_H10 (m/s^2) of degree ``degrees[i]`` at
    ``t_Ha = durations[j]`` (s). Between breakpoints a bound is linear in t_Ha; before the first
    and after the last it is constant. The degree of a record is the first degree whose bound at
    the record's t_Ha is >= its PGA_H10; above the last bound it is ``"above " + degrees[-1]``.

    A single-breakpoint scale (``durations=(0.0,)``) does not depend on the duration at all.
    """

    name: str = attrs.field(validator=_non_empty_name)
    degrees: tuple[str, ...] = attrs.field(converter=_label_tuple, validator=_check_degrees)
    durations: tuple[float, ...] = attrs.field(converter=_float_tuple, validator=_check_durations)
    bounds: tuple[tuple[float, ...], ...] = attrs.field(converter=_table, validator=_check_bounds)
    description: str = ""

    @property
    def above(self) -> str:
        """The label of a PGA_H10 beyond the last degree, e.g. ``"above IV"``."""
        return f"above {self.degrees[-1]}"

    @property
    def labels(self) -> tuple[str, ...]:
        """Every possible classification, lowest first, ``above`` last."""
        return (*self.degrees, self.above)

    def upper_bounds(self, t_ha: float) -> np.ndarray:
        """Upper bound of each degree (m/s^2) at duration ``t_ha`` (s), shape ``(len(degrees),)``."""
        t = float(t_ha)
        if not math.isfinite(t) or t < 0:
            raise ParameterError(f"intensity scale {self.name!r}: t_Ha must be finite and >= 0 s, got {t_ha!r}")
        # np.interp holds the end values outside the breakpoints: the constant branches of the table.
        return np.array([np.interp(t, self.durations, row) for row in self.bounds])

    def degree(self, pga_h10: float, t_ha: float) -> str:
        """The degree of a motion with peak ``pga_h10`` (m/s^2) and duration ``t_ha`` (s)."""
        pga = float(pga_h10)
        if not math.isfinite(pga) or pga < 0:
            raise ParameterError(f"intensity scale {self.name!r}: PGA_H10 must be finite and >= 0 m/s^2, got {pga_h10!r}")
        for label, bound in zip(self.degrees, self.upper_bounds(t_ha)):
            if pga <= bound * (1.0 + BOUNDARY_RTOL):  # inclusive upper bound, robust to rounding
                return label
        return self.above

    def to_dict(self) -> dict[str, Any]:
        """Plain data (JSON-ready); :meth:`from_dict` reads it back."""
        return {
            "name": self.name,
            "description": self.description,
            "degrees": list(self.degrees),
            "durations": list(self.durations),
            "bounds": [list(row) for row in self.bounds],
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> IntensityScale:
        """The scale of :meth:`to_dict`'s data; unknown or missing fields are named."""
        if not isinstance(data, dict):
            raise ParameterError(f"intensity scale: expected a mapping of fields, got {data!r}")
        fields = {f.name: f for f in attrs.fields(cls)}
        name = data.get("name", "?")
        unknown = sorted(set(data) - set(fields))
        if unknown:
            raise ParameterError(
                f"intensity scale {name!r}: unknown field(s) {', '.join(map(repr, unknown))}; fields: {', '.join(fields)}"
            )
        missing = [f for f, field in fields.items() if field.default is attrs.NOTHING and f not in data]
        if missing:
            raise ParameterError(f"intensity scale {name!r}: missing field(s) {', '.join(map(repr, missing))}")
        return cls(**data)


@attrs.frozen
class PresetBearing:
    """What a preset knows of one sliding bearing when it chooses its law.

    ``ks``: the stick stiffness K_s (N/m); ``friction``: the friction coefficient mu;
    ``dead_load``: the bearing's compressive normal force under the dead load (N), given only to
    presets that declare ``needs_dead_load`` (else None).
    """

    name: str
    ks: float
    friction: float
    dead_load: float | None = None


@attrs.frozen
class BearingPreset:
    """A named bearing model: ``law(PresetBearing) -> (law name, parameters)``, or None for a
    fixed (JOIN) bearing. ``needs_dead_load``: ``law`` reads ``PresetBearing.dead_load``."""

    name: str = attrs.field(validator=_non_empty_name)
    description: str = attrs.field(validator=attrs.validators.instance_of(str))
    law: Callable[[PresetBearing], tuple[str, dict] | None] = attrs.field(validator=_check_callable)
    needs_dead_load: bool = attrs.field(default=False, validator=attrs.validators.instance_of(bool))
