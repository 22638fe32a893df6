"""bearingfw.jit.kernel: cached where numba can write its cache, compiled in memory where it cannot."""

from __future__ import annotations

import numba

import bearingfw.jit as jit


def _twice(x):
    return 2.0 * x


def test_a_kernel_is_compiled_for_its_signature_and_cached():
    compiled = jit.kernel("float64(float64)")(_twice)
    assert compiled(3.0) == 6.0
    assert compiled.signatures == [(numba.float64,)]
    assert compiled.stats.cache_path is not None  # numba's cache directory for this file


def test_without_a_writable_cache_the_kernel_is_compiled_in_memory(monkeypatch):
    real = numba.njit

    def no_locator(*args, **kwargs):  # what numba raises when no cache directory can be written
        if kwargs.get("cache"):
            raise RuntimeError("cannot cache function '_twice': no locator available for file 'x.py'")
        return real(*args, **kwargs)

    monkeypatch.setattr(numba, "njit", no_locator)
    compiled = jit.kernel("float64(float64)")(_twice)
    assert compiled(4.0) == 8.0
    assert compiled.stats.cache_path is None
