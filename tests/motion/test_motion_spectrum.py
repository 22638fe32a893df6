"""The response spectrum's recursion against closed forms and a brute-force ODE integration."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from bearingfw.motion import response_spectrum, sdof_response
from bearingfw.parameters import ParameterError


def smooth_ramp(t, rise):
    """0 -> 1 over ``rise`` s (half cosine), then 1: a harmonic input that starts without a jolt."""
    x = np.minimum(t / rise, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * x)


@pytest.mark.parametrize("forcing_period", [0.5, 0.8, 0.3])  # resonance, below, above
def test_psa_of_a_harmonic_input_is_the_steady_state_amplitude(forcing_period):
    # u'' + 2 z w u' + w^2 u = -A sin(W t): steady amplitude A / (w^2 sqrt((1 - r^2)^2 + (2 z r)^2)),
    # r = W / w, so psa = w^2 max|u| = A / sqrt(...); at resonance A / (2 z) = 10 A. The input
    # ramps in over 15 s so that the start-up transient is negligible.
    dt, amplitude, period, zeta = 0.002, 1.3, 0.5, 0.05
    t = np.arange(int(60 / dt) + 1) * dt
    a = amplitude * smooth_ramp(t, 15.0) * np.sin(2 * np.pi / forcing_period * t)
    r = period / forcing_period
    exact = amplitude / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)
    assert response_spectrum(a, dt, [period], zeta).psa[0] == pytest.approx(exact, rel=2e-3)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2])
def test_after_a_pulse_the_oscillator_vibrates_freely(zeta):
    # Free vibration x(t) = exp(-z w t) (A cos wd t + B sin wd t): one damped period Td later the
    # response is exp(-z w Td) times as large, half a period later the negative of exp(-z w Td / 2).
    # Td = 0.5 s is 100 steps, so the samples fall on those instants exactly.
    dt, damped_period = 0.005, 0.5
    period = damped_period * math.sqrt(1 - zeta**2)
    w = 2 * np.pi / period
    a = np.zeros(2000)
    a[1:6] = [0.5, 1.0, -0.3, 0.8, 0.2]  # a pulse, then nothing
    u = sdof_response(a, dt, [period], zeta)[0]
    k0, full, half = 10, 100, 50
    for j in range(1, 15):
        assert u[k0 + j * full] == pytest.approx(u[k0] * math.exp(-zeta * w * damped_period * j), rel=1e-9, abs=1e-15)
    assert u[k0 + half] == pytest.approx(-u[k0] * math.exp(-zeta * w * damped_period / 2), rel=1e-9)
    if zeta == 0.0:  # undamped: the amplitude stays
        tail = u[200:]
        assert np.max(tail) == pytest.approx(-np.min(tail), rel=1e-3)


def brute_force(a, dt, period, zeta, t_eval):
    """The same oscillator by an adaptive Runge-Kutta (DOP853) on the linearly interpolated input."""
    w = 2 * np.pi / period
    # The recursion's input ramps from 0 to a[0] during the step before t = 0; start there.
    values = [0.0, *map(float, a)]
    last = len(values) - 2

    def rhs(t, x):
        s = (t + dt) / dt
        k = min(max(int(s), 0), last)
        ground = values[k] + (s - k) * (values[k + 1] - values[k])
        return [x[1], -ground - 2 * zeta * w * x[1] - w * w * x[0]]

    solution = solve_ivp(rhs, (-dt, (a.size - 1) * dt), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-14,
                         t_eval=t_eval, max_step=dt)
    return solution.y[0]


def test_the_recursion_is_exact_at_the_samples_against_a_brute_force_integration():
    dt = 0.01
    rng = np.random.default_rng(3)
    a = np.concatenate([[0.0], rng.normal(size=150)])
    periods = [0.05, 0.3, 1.5]
    u = sdof_response(a, dt, periods, 0.05)
    for row, period in zip(u, periods):
        reference = brute_force(a, dt, period, 0.05, np.arange(a.size) * dt)
        assert row == pytest.approx(reference, abs=1e-7 * np.max(np.abs(reference)))


@pytest.mark.parametrize("period", [0.03, 0.15, 0.8])
def test_spectral_peaks_agree_with_a_finely_sampled_brute_force_integration(period):
    # The spectrum's sub-steps (<= T / 10) bound the peak missed between samples; a 50-fold finer
    # brute-force sampling sees the true peak.
    dt = 0.01
    rng = np.random.default_rng(8)
    a = np.concatenate([[0.0], np.convolve(rng.normal(size=150), np.ones(3) / 3, mode="same")])
    fine = np.arange((a.size - 1) * 50 + 1) * (dt / 50)
    exact = np.max(np.abs(brute_force(a, dt, period, 0.05, fine)))
    assert response_spectrum(a, dt, [period]).sd[0] == pytest.approx(exact, rel=0.01)


def test_zero_period_limit_is_the_peak_ground_acceleration():
    # A stiff oscillator follows the ground: psa -> PGA as T -> 0 (smooth input on the scale of dt).
    dt = 0.005
    t = np.arange(1500) * dt
    a = 2.0 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.3 * t)
    psa = response_spectrum(a, dt, [0.002, 0.005]).psa
    assert psa == pytest.approx(np.full(2, np.max(np.abs(a))), rel=2e-3)


def test_spectrum_vectorised_over_periods_equals_one_period_at_a_time():
    rng = np.random.default_rng(1)
    a = rng.normal(size=500)
    periods = np.geomspace(0.02, 4.0, 25)
    together = response_spectrum(a, 0.01, periods).psa
    alone = [response_spectrum(a, 0.01, [T]).psa[0] for T in periods]
    assert together == pytest.approx(alone, rel=1e-12)


def test_spectrum_input_errors():
    with pytest.raises(ParameterError, match="periods must be one or more finite values > 0 s"):
        response_spectrum(np.ones(10), 0.01, [0.1, -1.0])
    with pytest.raises(ParameterError, match="periods"):
        response_spectrum(np.ones(10), 0.01, [])
    with pytest.raises(ParameterError, match="damping ratio must satisfy 0 <= damping < 1"):
        sdof_response(np.ones(10), 0.01, [0.1], damping=1.0)
    # A coarse, long record down to short periods would need billions of sub-steps: refused with
    # the period to use instead of a MemoryError.
    with pytest.raises(ParameterError, match=r"sub-steps \(limit 2e\+07\); use periods T >="):
        response_spectrum(np.ones(10_000), 100.0, [0.02])
