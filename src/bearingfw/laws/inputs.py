"""The check every built-in law makes of its ``respond()`` arguments (a law of a plugin may use it too).

Numpy broadcasting turns a wrong shape into a plausible answer (a ``dims = 1`` law given ``u``
of shape ``(3,)`` returned a ``(3, 3)`` force), and a NaN normal force compared as "no
sliding" gave a sticking bearing. Both are refused here with the law's name. The kernel calls
a law tens of thousands of times per analysis, so the check compares shapes and makes one pass
over the normal forces only; non-finite displacements are not refused but propagate to a
non-finite force, which the kernel's step control detects.
"""

from __future__ import annotations

import math

import numpy as np

from bearingfw.parameters import ParameterError

__all__ = ["respond_inputs", "velocity_input"]

_sum = np.add.reduce
#: below this many connectors the normal forces are summed as Python floats
_SMALL = 256


def respond_inputs(law, u, normal_force) -> tuple[np.ndarray, np.ndarray]:
    """``u`` as a float ``(n, dims)`` array and ``normal_force`` as a float ``(n,)`` array, checked.

    Raises :class:`~bearingfw.parameters.ParameterError` naming the law, the argument, the
    expected shape and the shape given, or the first connector whose normal force is not finite
    (NaN, or infinite: no friction capacity can be derived from it).
    """
    u = np.asarray(u, dtype=float)
    normal = np.asarray(normal_force, dtype=float)
    dims = law.dims
    if u.ndim != 2 or u.shape[1] != dims:
        raise ParameterError(
            f"law {law.name!r}: respond() argument 'u' must have shape (n, {dims}) (n connectors, dims = {dims} "
            f"directions), got shape {u.shape}"
        )
    if normal.shape != (u.shape[0],):
        raise ParameterError(
            f"law {law.name!r}: respond() argument 'normal_force' must have shape ({u.shape[0]},), one value per "
            f"connector of 'u' {u.shape}, got shape {normal.shape}"
        )
    # One sum: a NaN or an infinity makes it non-finite (a sum that merely overflows is then looked
    # at element by element); of Python floats for a few connectors, where numpy's reduction costs more.
    total = sum(normal.tolist()) if normal.size <= _SMALL else _sum(normal)
    if not math.isfinite(total) and not np.isfinite(normal).all():
        k = int(np.flatnonzero(~np.isfinite(normal))[0])
        raise ParameterError(
            f"law {law.name!r}: respond() argument 'normal_force' is {normal[k]} at connector {k}; it must be a "
            "finite number of newtons (compression > 0, uplift <= 0)"
        )
    return u, normal


def velocity_input(law, velocity, u: np.ndarray) -> np.ndarray:
    """``velocity`` (the trial velocity a law that ``uses_velocity`` is given) as a float array of
    the shape of ``u``, or a :class:`~bearingfw.parameters.ParameterError` naming the law and the
    argument (numpy would broadcast a wrong shape into a plausible answer)."""
    velocity = np.asarray(velocity, dtype=float)
    if velocity.shape != u.shape:
        raise ParameterError(
            f"law {law.name!r}: respond() argument 'velocity' must have the shape of 'u', {u.shape}, got shape "
            f"{velocity.shape}"
        )
    return velocity
