"""Eq. 11 (the paper's SDOF estimate of K_s) and measured damping (decrements, Rayleigh)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from bearingfw import tuning
from bearingfw.analysis import damping
from bearingfw.parameters import ParameterError
from bearingfw.tuning import frequency_ratio, ks_eq11


def test_eq11_with_the_papers_inputs_gives_462_mn_per_m():
    assert ks_eq11(147e6, 1.87, 2.48) == pytest.approx(462e6, abs=1e6)


@given(kc=st.floats(1e6, 1e10), ratio=st.floats(1e-3, 1e3))
def test_eq11_inverts_the_frame_frequency_ratio_eq10(kc, ratio):
    ks = kc * ratio
    f_a = 1.7
    assert ks_eq11(kc, f_a, f_a * frequency_ratio(kc, ks)) == pytest.approx(ks, rel=1e-6)


@pytest.mark.parametrize("f_b", [1.5, 1.87 * 1.4143, 10.0])
def test_eq11_rejects_ratios_a_spring_cannot_reach(f_b):
    with pytest.raises(ParameterError, match=r"f_b / f_a"):
        ks_eq11(147e6, 1.87, f_b)


def test_eq11_names_a_bad_input():
    with pytest.raises(ParameterError, match="k_c"):
        ks_eq11(-1.0, 1.87, 2.48)


def test_damping_comes_from_the_transient_module_not_a_copy():
    assert tuning.rayleigh_from_ratios is damping.rayleigh_from_ratios
    assert tuning.damping_ratio_from_log_decrement is damping.damping_ratio_from_log_decrement


def test_rayleigh_from_the_papers_ratios():
    alpha, beta = tuning.rayleigh_from_ratios(1.50, 0.021, 3.36, 0.027)
    assert alpha == pytest.approx(0.21, abs=0.005)
    assert beta == pytest.approx(0.00208, abs=0.00002)
    # and it gives back the ratios it was built from
    for f, zeta in ((1.50, 0.021), (3.36, 0.027)):
        w = 2 * 3.141592653589793 * f
        assert alpha / (2 * w) + beta * w / 2 == pytest.approx(zeta, rel=1e-12)


@pytest.mark.parametrize("delta, ratio", [(0.13, 0.021), (0.17, 0.027)])
def test_the_papers_decrements_give_its_ratios(delta, ratio):
    assert tuning.damping_ratio_from_log_decrement(delta) == pytest.approx(ratio, abs=0.0005)
