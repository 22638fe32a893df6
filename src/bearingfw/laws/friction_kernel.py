"""The friction return map (:func:`bearingfw.laws.friction_return_map`) compiled with numba.

One connector per iteration of a plain loop, with the formulas of
:mod:`bearingfw.laws.coulomb`'s docstring written as its former numpy code evaluated them (the
same operations in the same order, so the same bits): a law call of a few connectors cost 50-70
us of numpy dispatch for a few hundred floating-point operations (issue 16). The kernel has one
explicit signature (C-contiguous float64 arrays), compiled once and cached on disk
(:func:`bearingfw.jit.kernel`); the laws
import this module at their first ``respond``.
"""

from __future__ import annotations

import math

import numpy as np

from bearingfw.jit import kernel

_SIGNATURE = (
    "Tuple((float64[:, ::1], float64[:, ::1], float64[:, ::1], boolean[::1], float64[:, :, ::1]))"
    "(float64[::1], float64[:, ::1], float64[:, ::1], float64[::1])"
)


@kernel(_SIGNATURE)
def return_map(k, u, slip, capacity):
    """``(force, new slip, direction, sliding, tangent)`` for stick stiffnesses ``k`` (n,), law
    displacements ``u`` and slips ``slip`` (n, dims) and slip-surface radii ``capacity`` (n,)."""
    n, dims = u.shape
    force = np.empty((n, dims))
    new_slip = np.empty((n, dims))
    direction = np.empty((n, dims))
    sliding = np.empty(n, dtype=np.bool_)
    tangent = np.empty((n, dims, dims))
    trial = np.empty(dims)
    for c in range(n):
        kc = k[c]
        for j in range(dims):
            trial[j] = kc * (u[c, j] - slip[c, j])
        if dims == 1:
            norm = abs(trial[0])
        else:
            total = 0.0
            for j in range(dims):
                total += trial[j] * trial[j]
            norm = math.sqrt(total)
        slides = norm > capacity[c] or capacity[c] <= 0.0
        safe = norm if slides and norm > 0.0 else 1.0
        scale = capacity[c] / safe if slides else 1.0
        sliding[c] = slides
        for j in range(dims):
            force[c, j] = trial[j] * scale
            new_slip[c, j] = u[c, j] - force[c, j] / kc if slides else slip[c, j]
            direction[c, j] = trial[j] / safe
        kscale = kc * scale
        for a in range(dims):
            for b in range(dims):
                # I - sliding (n n^T), as numpy formed it (a sticking bearing subtracts 0 * n_a n_b)
                outer = direction[c, a] * direction[c, b]
                projector = (1.0 if a == b else 0.0) - (outer if slides else 0.0 * outer)
                tangent[c, a, b] = kscale * projector
    return force, new_slip, direction, sliding, tangent
