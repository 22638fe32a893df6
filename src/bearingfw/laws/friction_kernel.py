"""The friction return map (:func:`bearingfw.laws.friction_return_map`) compiled with numba.

One connector per iteration of a plain loop, with the formulas of
:mod:`bearingfw.laws.coulomb`'s docstring written as its former numpy code evaluated them (the
same operations in the same order, so the same bits): a law call of a few connectors cost 50-70
us of numpy dispatch for a few hundred floating-point operations (issue 16). The kernel has one
explicit signature (C-contiguous float64 arrays), compiled once and cached on disk
(:func:`bearingfw.jit.kernel`); the laws import this module at their first ``respond``.

:func:`regularized_coulomb` is the same map as a compiled law (:func:`bearingfw.jit.law_kernel`)
for the compiled Newton iteration of a time step; both call :func:`connector`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, njit

from bearingfw.jit import ANSWERED, kernel, law_kernel

_SIGNATURE = (
    "Tuple((float64[:, ::1], float64[:, ::1], float64[:, ::1], boolean[::1], float64[:, :, ::1]))"
    "(float64[::1], float64[:, ::1], float64[:, ::1], float64[::1])"
)


@njit(cache=True, inline="always")
def connector(kc, capacity, u, slip, dims, force, new_slip, direction, tangent, trial):
    """The return map of one connector on flat views of its ``dims`` values (its ``dims x dims``
    tangent block row by row); ``trial`` scratch of ``dims``. Returns whether it slides."""
    for j in range(dims):
        trial[j] = kc * (u[j] - slip[j])
    if dims == 1:
        norm = abs(trial[0])
    else:
        total = 0.0
        for j in range(dims):
            total += trial[j] * trial[j]
        norm = math.sqrt(total)
    slides = norm > capacity or capacity <= 0.0
    safe = norm if slides and norm > 0.0 else 1.0
    scale = capacity / safe if slides else 1.0
    for j in range(dims):
        force[j] = trial[j] * scale
        new_slip[j] = u[j] - force[j] / kc if slides else slip[j]
        direction[j] = trial[j] / safe
    kscale = kc * scale
    for a in range(dims):
        for b in range(dims):
            # I - sliding (n n^T), as numpy formed it (a sticking bearing subtracts 0 * n_a n_b)
            outer = direction[a] * direction[b]
            projector = (1.0 if a == b else 0.0) - (outer if slides else 0.0 * outer)
            tangent[a * dims + b] = kscale * projector
    return slides


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
        sliding[c] = connector(
            k[c], capacity[c], u[c], slip[c], dims, force[c], new_slip[c], direction[c], tangent[c].reshape(-1), trial
        )
    return force, new_slip, direction, sliding, tangent


@law_kernel
def regularized_coulomb(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    """:class:`~bearingfw.laws.coulomb.RegularizedCoulomb` as a compiled law: ``parameters`` are
    ``k`` then ``mu`` per connector, the state the slip ``(n, dims)``; ``dF/dN = mu n`` in slip."""
    k, mu = carray(parameters, (n,)), carray(parameters, (2 * n,))[n:]
    size = n * dims
    u_, slip, N = carray(u, (size,)), carray(state, (size,)), carray(normal_force, (n,))
    f, t, e, s = carray(force, (size,)), carray(tangent, (size * dims,)), carray(dforce_dnormal, (size,)), carray(new_state, (size,))
    direction, trial = np.empty(dims), np.empty(dims)
    for c in range(n):
        a, b = c * dims, (c + 1) * dims
        capacity = mu[c] * max(N[c], 0.0)
        slides = connector(k[c], capacity, u_[a:b], slip[a:b], dims, f[a:b], s[a:b], direction, t[a * dims : b * dims], trial)
        for j in range(dims):
            e[a + j] = mu[c] * direction[j] if slides and N[c] > 0.0 else 0.0
    return ANSWERED
