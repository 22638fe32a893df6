"""Field helpers shared by the model description classes.

Numbers go through :func:`bearingfw.parameter` (range-checked reals, ``optional=True`` where
``None`` means "not given"). This module adds what the model needs on top: names, node
references, 3-vectors and choices. Every
error is a :class:`ModelError` (a :class:`bearingfw.ParameterError`) naming the object and the
field.
"""

from __future__ import annotations

import math
from typing import Any

import attrs
import numpy as np

from bearingfw.parameters import ParameterError, choice, owner_of

__all__ = ["ModelError", "name_field", "node_ref", "vector3", "choice", "owner_of"]  # choice, owner_of: re-exported


class ModelError(ParameterError):
    """A model description is inconsistent: a bad field, an unknown reference, a duplicate name."""


def _check_name(instance, attribute, value):
    if not isinstance(value, str) or not value.strip():
        raise ModelError(
            f"{type(instance).__name__}: field {attribute.name!r} must be a non-empty string, got {value!r}"
        )


def name_field(doc: str = "unique name"):
    """A required non-empty string (the object's name)."""
    return attrs.field(validator=_check_name, metadata={"doc": doc})


def node_ref(doc: str = "name of a node"):
    """A reference to a node by name; the :class:`~bearingfw.model.Model` checks that it exists."""

    def check(instance, attribute, value):
        if not isinstance(value, str) or not value.strip():
            raise ModelError(
                f"{owner_of(instance)}: field {attribute.name!r} must be a node name (string), got {value!r}"
            )

    return attrs.field(validator=check, metadata={"doc": doc})


def _to_vector(value: Any) -> Any:
    if value is None or isinstance(value, str):
        return value
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return value
    if arr.shape != (3,):
        return value
    return tuple(float(v) for v in arr)


def vector3(*, default: Any = attrs.NOTHING, nonzero: bool = False, optional: bool = False, doc: str = ""):
    """A 3-vector stored as a tuple of floats (finite; non-zero on request; ``None`` if optional)."""

    def check(instance, attribute, value):
        if value is None and optional:
            return
        ok = isinstance(value, tuple) and len(value) == 3 and all(math.isfinite(v) for v in value)
        if not ok:
            raise ModelError(f"{owner_of(instance)}: field {attribute.name!r} must be 3 finite numbers, got {value!r}")
        if nonzero and math.hypot(*value) == 0.0:
            raise ModelError(f"{owner_of(instance)}: field {attribute.name!r} must be a non-zero vector")

    return attrs.field(default=default, converter=_to_vector, validator=check, metadata={"doc": doc})
