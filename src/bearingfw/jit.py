"""Compiled kernels: numba's ``njit`` with one explicit signature, cached on disk where it can be.

The kernels of the time step (:mod:`bearingfw.analysis.hht_kernels`) and of the friction laws
(:mod:`bearingfw.laws.friction_kernel`) are plain loops over arrays, compiled once per install:
numba writes the machine code next to the module (``__pycache__``) or, where that is read-only,
into the user's cache directory (``NUMBA_CACHE_DIR``). Where neither can be written, the kernel
is compiled in memory in each process instead (a few seconds) rather than failing the import.

Compiled laws (:class:`bearingfw.protocol.CompiledLaw`): a law's arithmetic as a C-callable
function of one common signature (:func:`law_signature`, :func:`law_kernel`), which the compiled
Newton iteration of a time step (:mod:`bearingfw.analysis.hht_newton`) calls through its address,
so that iteration is compiled once for every law and cached.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ANSWERED", "DECLINED", "kernel", "kernel_array", "law_kernel", "law_signature"]


def kernel(signature: str):
    """Decorator: compile ``function`` for ``signature`` (numba's string form), cached on disk."""

    from numba import njit  # here, not at the top: kernel_array's users need not import numba

    def decorate(function):
        try:
            return njit(signature, cache=True)(function)
        except RuntimeError:  # numba: "cannot cache function ...: no locator available"
            return njit(signature)(function)

    return decorate


def kernel_array(a) -> np.ndarray:
    """``a`` as a kernel's signature takes it: a writable, C-contiguous float64 array (itself when it
    is one already). numba types a read-only or strided array apart, and what reaches a kernel may be
    either: a frozen parameter array, a law's shared answer, a view of a column."""
    if type(a) is np.ndarray and a.dtype == np.float64 and a.flags.writeable and a.flags.c_contiguous:
        return a
    return np.array(a, dtype=np.float64, order="C")


def law_signature():
    """The signature of a compiled law (:class:`bearingfw.protocol.CompiledLaw`), in C terms::

        int64 respond(double *parameters, double *state, double *u, double *normal_force,
                      intp n, intp dims, double dt,
                      double *force, double *tangent, double *dforce_dnormal, double *new_state)

    ``u``, ``force``, ``dforce_dnormal``: ``n * dims``; ``tangent``: ``n * dims * dims`` (each
    connector's block row by row); ``normal_force``: ``n``, already ``>= 0``; ``state`` and
    ``new_state``: the law's packed state; ``parameters``: the law's own. It returns
    :data:`ANSWERED` when it answered; anything else (:data:`DECLINED`) has the step solved with the
    law's Python ``respond`` instead. An exception that escapes a compiled function makes it
    return 0 (numba prints it and goes on), so 0 must not mean "answered"."""
    from numba import types

    p = types.CPointer(types.float64)
    return types.int64(p, p, p, p, types.intp, types.intp, types.float64, p, p, p, p)


#: What a compiled law returns when it answered, and when it hands the call back to ``respond``.
ANSWERED, DECLINED = 1, 2


def law_kernel(function):
    """Decorator: ``function`` as a compiled law of :func:`law_signature` (a numba ``cfunc``,
    cached on disk where it can be). Inside it, ``numba.carray(pointer, shape)`` views a pointer
    as an array. Floating-point errors follow numpy (a division by zero gives inf or NaN, which
    the step detects) instead of raising, which a C-callable function could not report."""
    from numba import cfunc

    try:
        return cfunc(law_signature(), cache=True, error_model="numpy")(function)
    except RuntimeError:  # no cache locator: compiled in memory
        return cfunc(law_signature(), error_model="numpy")(function)
