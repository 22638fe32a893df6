"""``friction-pendulum`` as a compiled law (:func:`bearingfw.jit.law_kernel`), for the compiled
Newton iteration of a time step: the formulas of :func:`bearingfw_pendulum.law.pendulum_response`
in the order it evaluates them, per connector, with regularized-coulomb's compiled return map
(:func:`bearingfw.laws.friction_kernel.connector`) for the friction part. Imported by
``FrictionPendulum.compiled``, not when the plugin is registered (numba's import is not free)."""

from __future__ import annotations

import numpy as np
from numba import carray

from bearingfw.jit import ANSWERED, DECLINED, law_kernel
from bearingfw.laws.friction_kernel import connector


@law_kernel
def friction_pendulum(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    """``parameters``: ``k``, ``R``, ``mu`` per connector; the state the slip ``(n, dims)``. Declines a
    connector whose pendulum stiffness ``N / R`` reaches ``k`` (``respond`` raises the error)."""
    p = carray(parameters, (3 * n,))
    k, R, mu = p[:n], p[n : 2 * n], p[2 * n :]
    size = n * dims
    u_, slip, N = carray(u, (size,)), carray(state, (size,)), carray(normal_force, (n,))
    f, t, e, s = carray(force, (size,)), carray(tangent, (size * dims,)), carray(dforce_dnormal, (size,)), carray(new_state, (size,))
    direction, trial = np.empty(dims), np.empty(dims)
    for c in range(n):
        contact = N[c] > 0.0
        load = N[c] if contact else 0.0
        gravity = load / R[c]  # the pendulum stiffness N / R
        if gravity >= k[c]:
            return DECLINED
        a, b = c * dims, (c + 1) * dims
        slides = connector(k[c] - gravity, mu[c] * load, u_[a:b], slip[a:b], dims, f[a:b], s[a:b], direction,
                           t[a * dims : b * dims], trial)  # fmt: skip
        for j in range(dims):
            f[a + j] = f[a + j] + gravity * u_[a + j]
            for q in range(dims):
                i = (a + j) * dims + q
                t[i] = t[i] + (gravity if j == q else gravity * 0.0)
            if slides and contact:
                e[a + j] = mu[c] * direction[j] + u_[a + j] / R[c]
            elif contact:
                e[a + j] = slip[a + j] / R[c]
            else:
                e[a + j] = 0.0
    return ANSWERED
