"""The compression-only gap of uplift connectors (:class:`~bearingfw.model.connectors.CompressionOnlyGap`)
as a compiled law (:func:`bearingfw.jit.law_kernel`), for the compiled Newton iteration of a time step."""

from __future__ import annotations

from numba import carray

from bearingfw.jit import ANSWERED, law_kernel


@law_kernel
def compression_only_gap(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    """``kv d_z`` and ``kv`` while closed (``d_z <= 0``), zero when open; ``parameters``: ``kv``."""
    kv = carray(parameters, (n,))
    d, f, t, e = carray(u, (n,)), carray(force, (n,)), carray(tangent, (n,)), carray(dforce_dnormal, (n,))
    for c in range(n):
        closed = d[c] <= 0.0
        f[c] = kv[c] * d[c] if closed else 0.0
        t[c] = kv[c] if closed else 0.0
        e[c] = 0.0
    return ANSWERED
