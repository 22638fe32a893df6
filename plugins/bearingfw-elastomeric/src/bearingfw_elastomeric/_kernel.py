"""``elastomeric-plasticity`` as a compiled law (:func:`bearingfw.jit.law_kernel`), for the compiled
Newton iteration of a time step: the formulas of ``ElastomericPlasticity.respond`` in the order it
evaluates them, one connector at a time. Imported by ``ElastomericPlasticity.compiled``, not when the
plugin is registered (numba's import is not free)."""

from __future__ import annotations

import math

from numba import carray

from bearingfw.jit import ANSWERED, law_kernel


@law_kernel
def elastomeric_plasticity(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    """``parameters``: ``k``, ``qd``, ``alpha`` per connector; the state the plastic displacement
    ``(n, dims)``. The normal force plays no part."""
    p = carray(parameters, (3 * n,))
    k, qd, alpha = p[:n], p[n : 2 * n], p[2 * n :]
    size_ = n * dims
    u_, plastic, f = carray(u, (size_,)), carray(state, (size_,)), carray(force, (size_,))
    t, e, s = carray(tangent, (size_ * dims,)), carray(dforce_dnormal, (size_,)), carray(new_state, (size_,))
    for c in range(n):
        a = c * dims
        hysteretic = (1.0 - alpha[c]) * k[c]
        if dims == 1:
            size = abs(hysteretic * (u_[a] - plastic[a]))
        else:
            size = math.hypot(hysteretic * (u_[a] - plastic[a]), hysteretic * (u_[a + 1] - plastic[a + 1]))
        yielding = size > qd[c]
        scale = qd[c] / size if yielding else 1.0
        divisor = size if yielding else 1.0
        alpha_k = alpha[c] * k[c]
        for i in range(dims):
            elastic = u_[a + i] - plastic[a + i]
            trial = hysteretic * elastic
            f[a + i] = alpha_k * u_[a + i] + trial * scale
            s[a + i] = plastic[a + i] + (1.0 - scale) * elastic
            e[a + i] = 0.0
        for i in range(dims):
            for j in range(dims):
                di = hysteretic * (u_[a + i] - plastic[a + i]) / divisor
                dj = hysteretic * (u_[a + j] - plastic[a + j]) / divisor
                identity = 1.0 if i == j else 0.0
                projector = identity - (1.0 if yielding else 0.0) * (di * dj)
                t[(a + i) * dims + j] = alpha_k * identity + (hysteretic * scale) * projector
    return ANSWERED
