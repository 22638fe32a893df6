"""Compiled kernels: numba's ``njit`` with one explicit signature, cached on disk where it can be.

The kernels of the time step (:mod:`bearingfw.analysis.hht_kernels`) and of the friction laws
(:mod:`bearingfw.laws.friction_kernel`) are plain loops over arrays, compiled once per install:
numba writes the machine code next to the module (``__pycache__``) or, where that is read-only,
into the user's cache directory (``NUMBA_CACHE_DIR``). Where neither can be written, the kernel
is compiled in memory in each process instead (a few seconds) rather than failing the import.
"""

from __future__ import annotations

import numpy as np

__all__ = ["kernel", "kernel_array"]


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
