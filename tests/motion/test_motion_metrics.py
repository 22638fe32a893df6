"""Ground-motion measures against closed forms."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from scipy import signal

from bearingfw.motion import (
    DEFAULT_DAMPING,
    G,
    H10_FILTER,
    Record,
    arias_intensity,
    band_energy_fraction,
    dominant_frequency,
    fourier_spectrum,
    lowpass,
    peak,
    pga_h10,
    record_summary,
    response_spectrum,
    t_ha,
)
from bearingfw.parameters import ParameterError


def sine(f, amplitude, duration, dt, phase=0.0):
    t = np.arange(int(round(duration / dt)) + 1) * dt
    return t, amplitude * np.sin(2 * np.pi * f * t + phase)


@pytest.mark.parametrize("dt", [0.002, 0.005])
def test_pga_h10_removes_25_hz_and_keeps_3_hz(dt):
    t, low = sine(3.0, 0.3, 10.0, dt)
    _, high = sine(25.0, 0.2, 10.0, dt, phase=0.4)
    h1 = low + high
    assert peak(h1) > 0.4  # unfiltered, the 25 Hz sine adds to the peak
    assert pga_h10(h1, np.zeros_like(h1), dt) == pytest.approx(0.3, rel=0.01)
    # The same on the other horizontal: the measure treats both alike.
    assert pga_h10(np.zeros_like(h1), h1, dt) == pytest.approx(0.3, rel=0.01)


@pytest.mark.parametrize("f, gain", [(10.0, 0.5), (12.0, 1 / (1 + 1.2**8)), (8.0, 1 / (1 + 0.8**8))])
def test_pga_h10_filter_gain_is_that_of_a_4th_order_butterworth_run_twice(f, gain):
    # The decision: a 4th-order Butterworth at 10 Hz, forward and backward: 1 / (1 + (f/10)^8)
    # in amplitude; a 2nd-order pair would give 0.33 at 12 Hz and 0.71 at 8 Hz.
    dt = 0.001  # fine: the digital filter's frequency warping stays below 0.5 %
    t, a = sine(f, 1.0, 12.0, dt)
    filtered = lowpass(a, dt)
    middle = slice(t.size // 4, 3 * t.size // 4)
    assert np.max(np.abs(filtered[middle])) == pytest.approx(gain, rel=5e-3)
    assert pga_h10(a, np.zeros_like(a), dt) == pytest.approx(gain, rel=5e-3)
    assert H10_FILTER.gain(f) == pytest.approx(gain, rel=1e-12)


def test_pga_h10_filter_is_described_once_and_reported():
    spec = H10_FILTER.to_dict()
    assert (spec["cutoff_hz"], spec["order_per_pass"], spec["passes"], spec["overall_order"]) == (10.0, 4, 2, 8)
    assert spec["gain_at_cutoff"] == 0.5 and spec["minus_3db_hz"] == pytest.approx(8.9568, abs=1e-4)
    t, a = sine(3.0, 0.3, 10.0, 0.005)
    record = Record(h1=a, h2=a, v=a, dt=0.005)
    assert record_summary(record)["pga_h10_filter"] == spec
    # Zero phase: the filtered 3 Hz sine is the sine times the gain, not shifted.
    middle = slice(500, 1500)
    np.testing.assert_allclose(lowpass(a, 0.005)[middle], H10_FILTER.gain(3.0) * a[middle], atol=1e-3 * 0.3)


def test_pga_h10_is_the_peak_of_the_resultant():
    dt = 0.005
    t, a = sine(2.0, 0.4, 8.0, dt)
    # In phase: the resultant peak is sqrt(2) times a component peak.
    assert pga_h10(a, a, dt) == pytest.approx(0.4 * math.sqrt(2), rel=0.01)
    # Circular motion: the resultant is constant, equal to the amplitude.
    b = 0.4 * np.cos(2 * np.pi * 2.0 * t)
    assert pga_h10(a, b, dt) == pytest.approx(0.4, rel=0.01)


@pytest.mark.parametrize("f, amplitude, cycles, dt", [(2.0, 0.5, 20, 0.01), (7.5, 1.3, 45, 0.002)])
def test_arias_intensity_of_a_sine(f, amplitude, cycles, dt):
    duration = cycles / f
    _, a = sine(f, amplitude, duration, dt)
    expected = math.pi * amplitude**2 * duration / (4 * G)  # pi/(2g) * A^2 T / 2
    assert arias_intensity(a, dt) == pytest.approx(expected, rel=1e-3)
    # The horizontal Arias intensity sums both components.
    assert arias_intensity(np.vstack([a, 2 * a]), dt) == pytest.approx(5 * expected, rel=1e-3)


@settings(max_examples=30, deadline=None)
@given(
    dt=st.sampled_from([0.002, 0.005, 0.01]),
    samples=st.integers(100, 1500),
    fives=st.integers(1, 40),
    start=st.integers(20, 300),
)
def test_t_ha_of_a_boxcar_sine_is_90_percent_of_its_length(dt, samples, fives, start):
    # sin^2 makes the Husid curve ripple around a straight line by up to 1/(4 pi f) s. With a
    # whole multiple of 5 cycles in the boxcar, the 5 % and 95 % points (and the end) fall on
    # the line, so the only error left is the sampling.
    length = samples * dt
    f = 5 * fives / length
    assume(0.5 <= f <= 0.2 / dt)
    k = np.arange(start + samples + 200)
    inside = (k >= start) & (k < start + samples)
    a = np.where(inside, np.sin(2 * np.pi * f * (k - start) * dt), 0.0)
    assert abs(t_ha(a, np.zeros_like(a), dt) - 0.9 * length) <= dt
    assert abs(t_ha(np.zeros_like(a), -a, dt) - 0.9 * length) <= dt
    assert abs(t_ha(a, a, dt) - 0.9 * length) <= dt


def test_fourier_spectrum_of_a_sine_and_its_dominant_frequency():
    dt = 0.005
    t, a = sine(4.0, 1.0, 20.0, dt)
    _, b = sine(12.0, 0.3, 20.0, dt)
    f, amplitude = fourier_spectrum(a + b, dt)
    assert f[1] - f[0] == pytest.approx(1 / (t.size * dt))
    # |A(f0)| of a sine of amplitude A over T seconds is A T / 2.
    assert amplitude.max() == pytest.approx(1.0 * 20.0 / 2, rel=0.02)
    assert dominant_frequency(a + b, dt) == pytest.approx(4.0, abs=f[1])
    assert band_energy_fraction(a + b, dt, 3.5, 4.5) == pytest.approx(1 / (1 + 0.3**2), rel=0.01)


def sdof_closed_form(t, period, zeta, amplitude, forcing):
    """u(t) of u'' + 2 zeta w u' + w^2 u = -A sin(W t) from rest: steady state plus free decay."""
    w, W = 2 * np.pi / period, 2 * np.pi * forcing
    wd = w * math.sqrt(1 - zeta**2)
    det = (w**2 - W**2) ** 2 + (2 * zeta * w * W) ** 2
    C = -amplitude * (w**2 - W**2) / det  # u_p = C sin(W t) + D cos(W t)
    D = amplitude * 2 * zeta * w * W / det
    E = -D  # u(0) = 0
    F = (zeta * w * E - C * W) / wd  # u'(0) = 0
    return C * np.sin(W * t) + D * np.cos(W * t) + np.exp(-zeta * w * t) * (E * np.cos(wd * t) + F * np.sin(wd * t))


@pytest.mark.parametrize("zeta", [0.05, 0.02])
def test_response_spectrum_of_a_harmonic_input_matches_the_closed_form(zeta):
    dt, amplitude, forcing = 0.002, 0.8, 2.0
    t, a = sine(forcing, amplitude, 12.0, dt)
    periods = np.array([0.08, 0.25, 0.5, 0.7, 1.5, 3.0])
    spectrum = response_spectrum(a, dt, periods, damping=zeta)
    for T, sd in zip(periods, spectrum.sd):
        exact = np.max(np.abs(sdof_closed_form(t, T, zeta, amplitude, forcing)))
        assert sd == pytest.approx(exact, rel=5e-4), T
    assert spectrum.psa == pytest.approx((2 * np.pi / periods) ** 2 * spectrum.sd)


def test_response_spectrum_default_damping_is_five_percent():
    dt, amplitude, forcing = 0.002, 0.8, 2.0
    t, a = sine(forcing, amplitude, 12.0, dt)
    periods = np.array([0.25, 0.5, 1.5])
    spectrum = response_spectrum(a, dt, periods)
    assert DEFAULT_DAMPING == 0.05 and spectrum.damping == 0.05
    for T, sd in zip(periods, spectrum.sd):
        assert sd == pytest.approx(np.max(np.abs(sdof_closed_form(t, T, 0.05, amplitude, forcing))), rel=5e-4)


def test_response_spectrum_tends_to_pga_at_short_periods():
    # Content well below 1/T: the oscillator follows the ground (the piecewise-linear input has
    # kinks at the samples, so the signal must be smooth on the scale of dt for this to hold).
    dt = 0.005
    rng = np.random.default_rng(5)
    a = np.convolve(rng.normal(size=2000), np.hanning(41), mode="same")  # smooth, band-limited
    spectrum = response_spectrum(a, dt, periods=[0.005, 0.01, 0.02])
    assert spectrum.psa == pytest.approx(np.full(3, peak(a)), rel=0.01)


def finely_sampled_reference(a, dt, period, zeta, sub=50):
    """Peak |u| by scipy's lsim on the linearly interpolated input sampled every dt / sub."""
    w = 2 * np.pi / period
    t = np.arange(a.size) * dt
    fine = np.arange((a.size - 1) * sub + 1) * (dt / sub)
    _, u, _ = signal.lsim(([-1.0], [1.0, 2 * zeta * w, w * w]), np.interp(fine, t, a), fine)
    return np.max(np.abs(u))


@pytest.mark.parametrize("steps_per_period", [2.0, 2.5, 3.0])
def test_response_spectrum_is_accurate_at_periods_of_a_few_steps(steps_per_period):
    # Sampled once per step, the response at T = 2 dt lost half its peak: sub-stepping keeps it.
    dt = 0.01
    rng = np.random.default_rng(11)
    a = np.concatenate([np.zeros(5), rng.normal(size=400)])
    period = steps_per_period * dt
    exact = finely_sampled_reference(a, dt, period, 0.05)
    assert response_spectrum(a, dt, [period]).sd[0] == pytest.approx(exact, rel=0.03)


def test_measures_reject_bad_input():
    with pytest.raises(ParameterError, match="dt"):
        pga_h10(np.ones(10), np.ones(10), 0.0)
    with pytest.raises(ParameterError, match="zero everywhere"):
        t_ha(np.zeros(10), np.zeros(10), 0.01)
    with pytest.raises(ParameterError, match="damping"):
        response_spectrum(np.ones(10), 0.01, damping=1.5)
