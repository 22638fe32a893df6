"""Compiled kernels: numba's ``njit`` with one explicit signature, cached on disk where it can be.

The kernels of the time step (:mod:`bearingfw.analysis.hht_kernels`) and of the friction laws
(:mod:`bearingfw.laws.friction_kernel`) are plain loops over arrays, compiled once per install:
numba writes the machine code next to the module (``__pycache__``) or, where that is read-only,
into the user's cache directory (``NUMBA_CACHE_DIR``). Where neither can be written, the kernel
is compiled in memory in each process instead (a few seconds) rather than failing the import.
"""

from __future__ import annotations

from numba import njit

__all__ = ["kernel"]


def kernel(signature: str):
    """Decorator: compile ``function`` for ``signature`` (numba's string form), cached on disk."""

    def decorate(function):
        try:
            return njit(signature, cache=True)(function)
        except RuntimeError:  # numba: "cannot cache function ...: no locator available"
            return njit(signature)(function)

    return decorate
