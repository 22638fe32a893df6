"""The linear spring (and free sliding, a spring of zero stiffness) as a compiled law
(:func:`bearingfw.jit.law_kernel`), for the compiled Newton iteration of a time step."""

from __future__ import annotations

from numba import carray

from bearingfw.jit import ANSWERED, law_kernel


@law_kernel
def linear_spring(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    """``F = k u`` with ``k`` per connector (``parameters``), tangent ``k I``; no state."""
    k = carray(parameters, (n,))
    size = n * dims
    u_, f, t, e = carray(u, (size,)), carray(force, (size,)), carray(tangent, (size * dims,)), carray(dforce_dnormal, (size,))
    for c in range(n):
        for a in range(dims):
            i = c * dims + a
            f[i] = k[c] * u_[i] if k[c] != 0.0 else 0.0  # free sliding: zero, also for an infinite u
            e[i] = 0.0
            for b in range(dims):
                t[i * dims + b] = k[c] if a == b else 0.0
    return ANSWERED
