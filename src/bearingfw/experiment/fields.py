"""Validated attrs fields of the experiment file's tables: lists of names, texts, flags, tables, reals.

The numeric fields come from :mod:`bearingfw.parameters` (``parameter``, ``integer_parameter``,
``choice``); these are the kinds a TOML file adds. Every validator raises
:class:`~bearingfw.experiment.fields.SpecError` with the class and field name, which the loader
(:func:`bearingfw.experiment.spec.from_table`) turns into the key's path.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping
from typing import Any

import attrs

from bearingfw.parameters import ParameterError, owner_of

__all__ = [
    "NAME",
    "NAME_LENGTH",
    "SpecError",
    "flag_field",
    "listish",
    "names_field",
    "reals",
    "reals_field",
    "table_field",
    "text_field",
]

#: Models, records and intensities name files of the results store: keep them portable, and short
#: enough that a cell's path and a figure's file name stay within a file system's 255 bytes per name.
NAME_LENGTH = 64
NAME = re.compile(rf"^[A-Za-z0-9][A-Za-z0-9._+-]{{0,{NAME_LENGTH - 1}}}$")


class SpecError(ParameterError):
    """The experiment file is malformed; the message starts with the key's path."""


def listish(value: Any) -> Any:
    """A TOML array as a tuple (anything else unchanged, for the validator to refuse)."""
    return tuple(value) if isinstance(value, list) else value


def reals(value: Any) -> Any:
    """A TOML array of numbers as a tuple of floats (booleans and other items left for the validator)."""
    if isinstance(value, list):
        return tuple(float(v) if isinstance(v, numbers.Real) and not isinstance(v, bool) else v for v in value)
    return value


def names_field(*, default: Any = (), optional: bool = False, allowed: tuple[str, ...] | None = None, doc: str = ""):
    """A list of distinct non-empty strings (stored as a tuple); ``None`` if optional and not given."""

    def check(instance, attribute, value):
        if value is None and optional:
            return
        ok = isinstance(value, tuple) and all(isinstance(v, str) and v for v in value)
        if not ok:
            raise SpecError(f"{owner_of(instance)}: field {attribute.name!r} must be a list of names, got {value!r}")
        if len(set(value)) != len(value):
            raise SpecError(f"{owner_of(instance)}: field {attribute.name!r} names an item twice: {list(value)!r}")
        if allowed is not None:
            bad = [v for v in value if v not in allowed]
            if bad:
                raise SpecError(
                    f"{owner_of(instance)}: field {attribute.name!r} has {bad[0]!r}; allowed: {', '.join(allowed)}"
                )

    return attrs.field(default=default, converter=listish, validator=check, metadata={"doc": doc})


def text_field(*, default: Any = attrs.NOTHING, optional: bool = False, pattern: re.Pattern | None = None,
               hint: str = "", doc: str = ""):
    """A string (matching ``pattern`` if given); ``None`` if optional and not given."""

    def check(instance, attribute, value):
        if value is None and optional:
            return
        if not isinstance(value, str) or (pattern is not None and not pattern.match(value)):
            raise SpecError(
                f"{owner_of(instance)}: field {attribute.name!r} must be {hint or 'a string'}, "
                f"got {type(value).__name__} {value!r}"
            )

    if optional and default is attrs.NOTHING:
        default = None
    return attrs.field(default=default, validator=check, metadata={"doc": doc})


def flag_field(default: bool, doc: str = ""):
    """A boolean (TOML true/false; not 0/1)."""

    def check(instance, attribute, value):
        if not isinstance(value, bool):
            raise SpecError(f"{owner_of(instance)}: field {attribute.name!r} must be true or false, got {value!r}")

    return attrs.field(default=default, validator=check, metadata={"doc": doc})


def table_field(doc: str = ""):
    """A table of keyword arguments (string keys), stored as a plain dict."""

    def check(instance, attribute, value):
        if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
            raise SpecError(f"{owner_of(instance)}: field {attribute.name!r} must be a table, got {value!r}")

    return attrs.field(factory=dict, converter=lambda v: dict(v) if isinstance(v, Mapping) else v, validator=check,
                       metadata={"doc": doc})


def reals_field(*, what: str, unit: str, doc: str = "", high: float | None = None, why: str = ""):
    """An optional list of distinct finite values > 0 and, given ``high``, at most ``high`` (``what``,
    ``unit`` and ``why``, the reason for the bound, go into the message)."""

    def check(instance, attribute, value):
        if value is None:
            return
        ok = isinstance(value, tuple) and value and all(
            isinstance(v, float) and math.isfinite(v) and v > 0 and (high is None or v <= high) for v in value)
        if not ok:
            bound = "" if high is None else f" and <= {high:g}"
            raise SpecError(f"{owner_of(instance)}: field {attribute.name!r} must be a list of {what} values > 0"
                            f"{bound} ({unit}{', ' + why if why and high is not None else ''}), got {value!r}")
        if len(set(value)) != len(value):
            raise SpecError(f"{owner_of(instance)}: field {attribute.name!r} gives a value twice: {list(value)!r}")

    return attrs.field(default=None, converter=reals, validator=check, metadata={"doc": doc, "unit": unit})
