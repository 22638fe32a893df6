"""Validated parameters for user-facing attrs classes (laws, and later model objects).

``parameter(...)`` returns an attrs field that accepts any real number (int, float, numpy
scalar; not bool, not str), stores it as ``float``, and rejects values outside the allowed
range with a :class:`ParameterError` that names the parameter and the range. The range and unit
are kept in the field's metadata so that ``bearingfw plugins`` can list them.

Example::

    @attrs.frozen
    class MyLaw:
        k: float = parameter(low=0.0, low_open=True, unit="N/m", doc="stiffness")
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable
from typing import Any

import attrs
import numpy as np

__all__ = [
    "ParameterError",
    "check_per_bearing",
    "choice",
    "describe_range",
    "dims_parameter",
    "integer_parameter",
    "owner_of",
    "parameter",
]


class ParameterError(ValueError):
    """A parameter is missing, unknown, of the wrong type or outside its allowed range."""


def describe_range(name: str, low, high, low_open: bool, high_open: bool) -> str:
    """Human-readable allowed range, e.g. ``0 <= mu < 1`` or ``k > 0``."""
    left = "" if low is None else f"{low:g} {'<' if low_open else '<='} "
    right = "" if high is None else f" {'<' if high_open else '<='} {high:g}"
    if low is not None and high is None:
        return f"{name} {'>' if low_open else '>='} {low:g}"
    if low is None and high is None:
        return f"{name} finite"
    return f"{left}{name}{right}"


def _to_float(value: Any) -> Any:
    # Leave anything that is not a real number untouched so that the validator can name it.
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    return value


def _to_floats(value: Any) -> Any:
    """A scalar as :func:`_to_float`; a non-empty 1-D sequence of real numbers as a read-only float array."""
    if isinstance(value, (list, tuple, np.ndarray)):
        array = np.asarray(value)
        if array.ndim == 1 and array.size and (array.dtype.kind in "iuf"):
            array = array.astype(float)  # a copy: the caller's array stays theirs
            array.setflags(write=False)
            return array
        return value
    return _to_float(value)


def owner_of(instance) -> str:
    """How an error names the object: a law by its registry key, anything else by class and name."""
    name = getattr(instance, "name", None)
    if isinstance(name, str) and name and name == getattr(type(instance), "name", None):
        return name
    kind = type(instance).__name__
    return f"{kind} {name!r}" if isinstance(name, str) and name else kind


def parameter(
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    default: Any = attrs.NOTHING,
    optional: bool = False,
    unit: str = "",
    doc: str = "",
    typical: float | None = None,
    per_bearing: bool = False,
):
    """An attrs field for a finite real parameter within ``[low, high]`` (ends open on request).

    ``optional=True`` makes ``None`` (then the default) mean "not given". ``typical`` is a
    representative magnitude (e.g. 4e8 for a bearing's stiffness in N/m); the hypothesis
    strategies of :mod:`bearingfw.testing` draw around it when the range is open.
    ``per_bearing=True`` also accepts a 1-D array of such numbers, one per connector of the law
    (stored read-only as float64; see :func:`check_per_bearing` and :mod:`bearingfw.protocol`).
    """
    if optional and default is attrs.NOTHING:
        default = None

    def outside(value: float) -> bool:
        bad = not math.isfinite(value)
        bad |= low is not None and (value <= low if low_open else value < low)
        bad |= high is not None and (value >= high if high_open else value > high)
        return bad

    def check(instance, attribute, value):
        if optional and value is None:
            return
        name = attribute.name
        allowed = describe_range(name, low, high, low_open, high_open)
        if per_bearing and isinstance(value, np.ndarray) and value.dtype == float:
            bad = [i for i, v in enumerate(value.tolist()) if outside(v)]
            if bad:
                raise ParameterError(
                    f"{owner_of(instance)}: parameter {name!r}[{bad[0]}] = {float(value[bad[0]])!r} is outside the "
                    f"allowed range {allowed} ({len(bad)} of {value.size} values are)"
                )
            return
        if not isinstance(value, float):
            what = "a real number or a 1-D array of real numbers (one per bearing)" if per_bearing else "a real number"
            raise ParameterError(
                f"{owner_of(instance)}: parameter {name!r} must be {what} ({allowed})"
                f"{' or None' if optional else ''}, got {type(value).__name__} {value!r}"
            )
        if outside(value):
            raise ParameterError(
                f"{owner_of(instance)}: parameter {name!r} = {value!r} is outside the allowed range {allowed}"
            )

    return attrs.field(
        default=default,
        converter=_to_floats if per_bearing else _to_float,
        validator=check,
        # attrs' generated __eq__ cannot compare arrays: compare per-bearing values element-wise.
        # (and leave them out of the hash: an array is not hashable).
        eq=attrs.cmp_using(eq=_same_values) if per_bearing else True,
        hash=False if per_bearing else None,
        # "{name}" is filled in by whoever lists the parameter under its own name.
        metadata={
            "range": describe_range("{name}", low, high, low_open, high_open),
            "unit": unit,
            "doc": doc,
            "bounds": (low, high, low_open, high_open),
            "typical": typical,
            "per_bearing": per_bearing,
        },
    )


def _same_values(a, b) -> bool:
    return bool(np.array_equal(np.asarray(a), np.asarray(b)))


def check_per_bearing(law: Any, n: int) -> None:
    """Raise a :class:`ParameterError` if a per-bearing parameter of ``law`` is an array whose
    length is not ``n`` (the number of connectors ``respond`` or ``initial_state`` was given)."""
    for field in attrs.fields(type(law)):
        if not field.metadata.get("per_bearing"):
            continue
        value = getattr(law, field.name)
        if isinstance(value, np.ndarray) and value.shape != (n,):
            raise ParameterError(
                f"{owner_of(law)}: parameter {field.name!r} holds {value.size} per-bearing values but the law "
                f"was called for {n} connector(s)"
            )


def dims_parameter(default: int = 1):
    """The ``dims`` field of a law: 1 (guided bearing) or 2 (free sliding), set by the connector."""

    def check(instance, attribute, value):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value not in (1, 2):
            raise ParameterError(f"{owner_of(instance)}: parameter 'dims' must be 1 or 2, got {value!r}")

    return attrs.field(
        default=default,
        validator=check,
        metadata={"range": "1 or 2", "unit": "", "doc": "shear directions governed together (set by the connector kind)"},
    )


def integer_parameter(*, low: int, high: int, default: Any = attrs.NOTHING, doc: str = ""):
    """An attrs field holding a whole number within ``[low, high]`` (not a bool, not a float)."""

    def check(instance, attribute, value):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not low <= value <= high:
            raise ParameterError(
                f"{owner_of(instance)}: parameter {attribute.name!r} must be an integer with "
                f"{low} <= {attribute.name} <= {high}, got {value!r}"
            )

    return attrs.field(
        default=default,
        converter=lambda v: int(v) if isinstance(v, numbers.Integral) and not isinstance(v, bool) else v,
        validator=check,
        metadata={"range": f"{low} <= {{name}} <= {high}", "unit": "", "doc": doc},
    )


def choice(options: Iterable[str], *, default: Any = attrs.NOTHING, optional: bool = False, doc: str = ""):
    """An attrs field holding one of ``options`` (case-insensitive on input, stored lower-case).

    ``optional=True`` also accepts ``None`` (not given).
    """
    options = tuple(options)

    def convert(value):
        return value.lower() if isinstance(value, str) else value

    def check(instance, attribute, value):
        if value is None and optional:
            return
        if value not in options:
            allowed = ", ".join(map(repr, options))
            raise ParameterError(
                f"{owner_of(instance)}: parameter {attribute.name!r} must be one of {allowed}, got {value!r}"
            )

    return attrs.field(
        default=default, converter=convert, validator=check, metadata={"doc": doc, "range": " | ".join(options)}
    )
