"""A Coulomb oscillator under harmonic base motion: Den Hartog's steady state, and sticking.

The oscillator is a mass on a linear spring ``k`` with a regularized-Coulomb bearing in parallel
(stick stiffness ``k_c = 1000 k``, friction force ``F = mu N``, ``N`` half the weight). Under
the ground acceleration ``A sin(w t)`` the relative motion obeys ``m x'' + k x + F sgn(x') = -m A sin(w t)``:
a harmonic force of amplitude ``P0 = m A``.

Den Hartog's exact steady state without stops (J. P. Den Hartog, "Forced vibrations with
combined viscous and Coulomb damping", Phil. Mag. ser. 7, vol. 9, no. 59, pp. 801-817, 1930;
also in his *Mechanical Vibrations*, 4th ed., 1956, section 8.x on Coulomb damping)::

    X / (P0 / k) = sqrt(V0^2 - (F / P0)^2 U^2),   V0 = 1 / (1 - r^2),   U = sin(pi / r) / (r (1 + cos(pi / r)))

with ``r = w / w_n``. The test re-derives it: the half cycle from ``x = X`` to ``x = -X`` (both
at rest) is linear with the constant friction force, and its two-point boundary value problem
gives ``X`` (:func:`den_hartog_by_half_cycle`), which must equal the formula.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import fsolve
from kernel_models import friction_oscillator

from bearingfw.analysis import ConnectorResponse, NodalResponse, TransientSettings, gravity, solve_transient

M, K = 1000.0, 4.0e5
MU = 0.3
W_N = np.sqrt(K / M)


def den_hartog(r: float, f: float) -> float:
    """``X k / P0`` of the continuous-slip steady state (module docstring), ``f = F / P0``."""
    V0 = 1.0 / (1.0 - r**2)
    U = np.sin(np.pi / r) / (r * (1.0 + np.cos(np.pi / r)))
    return float(np.sqrt(V0**2 - f**2 * U**2))


def den_hartog_by_half_cycle(r: float, f: float) -> float:
    """``X k / P0`` from the half-cycle boundary value problem (k = m = P0 = 1, w_n = 1).

    Moving down (x' < 0) friction acts up: x'' + x = cos(r t + phi) + f. With y = x - f the
    solution is y = a cos t + b sin t + cos(r t + phi) / (1 - r^2); require x(0) = X, x'(0) = 0,
    x(pi / r) = -X, x'(pi / r) = 0 (a symmetric non-stop cycle).
    """
    T = np.pi / r
    D = 1.0 / (1.0 - r**2)

    def equations(z):
        a, b, X, phi = z
        y = lambda t: a * np.cos(t) + b * np.sin(t) + D * np.cos(r * t + phi)  # noqa: E731
        dy = lambda t: -a * np.sin(t) + b * np.cos(t) - D * r * np.sin(r * t + phi)  # noqa: E731
        return [y(0) - (X - f), dy(0), y(T) - (-X - f), dy(T)]

    a, b, X, phi = fsolve(equations, [0.1, 0.1, abs(D), 0.3], xtol=1e-13)
    return abs(float(X))


@pytest.mark.parametrize("r, f", [(0.8, 0.3), (1.5, 0.3), (2.0, 0.2)])
def test_den_hartog_formula_solves_the_half_cycle(r, f):
    assert den_hartog(r, f) == pytest.approx(den_hartog_by_half_cycle(r, f), rel=1e-9)


def run(r: float, amplitude: float, cycles: int, per_cycle: int, k_stick: float = 1e3 * K, alpha: float = -0.05):
    model = friction_oscillator(M, K, k_stick, MU)
    pre = gravity(model)
    w = r * W_N
    dt = 2 * np.pi / w / per_cycle
    t = dt * np.arange(cycles * per_cycle + 1)
    ag = np.zeros((t.size, 3))
    ag[:, 0] = amplitude * np.sin(w * t)
    res = solve_transient(
        model, ag, dt, preload=pre, settings=TransientSettings(alpha=alpha),
        recorders=[ConnectorResponse(["friction"]), NodalResponse(["m"], components=["ux"])],
    )
    return pre, res


def test_continuous_slip_reaches_den_hartog_amplitude(alpha=-0.05):
    r, f, per = 0.8, 0.3, 100
    pre = gravity(friction_oscillator(M, K, 1e3 * K, MU))
    F = MU * pre.normal_force("friction")
    assert F == pytest.approx(MU * M * 9.81 / 2, rel=1e-9)  # half the weight on each connector
    P0 = F / f
    _, res = run(r, P0 / M, cycles=40, per_cycle=per, alpha=alpha)
    x = res["displacement"][:, 0, 0]
    amplitude = np.max(np.abs(x[-3 * per :]))
    expected = den_hartog(r, f) * P0 / K
    assert amplitude == pytest.approx(expected, rel=0.02)
    # it slips continuously: the friction force sits on mu N except at the reversals
    ratio = res["connectors.friction_ratio"][-3 * per :, 0]
    assert np.max(ratio) == pytest.approx(MU, rel=1e-9)
    assert np.mean(ratio > (1 - 1e-9) * MU) > 0.9
    slip = res["connectors.slip"][-3 * per :, 0, 0]
    assert np.ptp(slip) == pytest.approx(2 * amplitude, rel=0.01)
    assert res.energy_error < 0.01 and res.balance_error < 1e-8
    assert res.energy["bearings"][-1] > 0.5 * res.energy["input"][-1]  # friction dissipates most of the input


def test_no_slip_while_the_peak_inertia_force_stays_below_mu_n():
    pre = gravity(friction_oscillator(M, K, 1e3 * K, MU))
    capacity = MU * pre.normal_force("friction")
    amplitude = 0.8 * capacity / M  # peak inertia force m A = 0.8 mu N
    _, res = run(0.8, amplitude, cycles=10, per_cycle=100)
    assert np.all(res["connectors.slip"][:, 0, 0] == 0.0)
    assert np.nanmax(res["connectors.friction_ratio"]) < MU
    # stuck: the mass rides with the ground on the stiff stick spring
    assert np.max(np.abs(res["displacement"])) < 1.05 * M * amplitude / (K + 1e3 * K)
    # and just above the capacity it does slip
    _, res = run(0.8, 1.2 * capacity / M, cycles=3, per_cycle=100)
    assert np.max(np.abs(res["connectors.slip"][:, 0, 0])) > 0


@pytest.mark.slow
def test_den_hartog_above_resonance_with_a_stiffer_stick():
    """r = 1.5: the stick phases at the reversals matter more; k_c = 1e4 k and 400 steps per cycle."""
    r, f, per = 1.5, 0.3, 400
    pre = gravity(friction_oscillator(M, K, 1e4 * K, MU))
    P0 = MU * pre.normal_force("friction") / f
    _, res = run(r, P0 / M, cycles=40, per_cycle=per, k_stick=1e4 * K)
    amplitude = np.max(np.abs(res["displacement"][-3 * per :, 0, 0]))
    assert amplitude == pytest.approx(den_hartog(r, f) * P0 / K, rel=0.02)
    assert res.energy_error < 0.01 and res.balance_error < 1e-8


def test_the_balance_error_exposes_a_scheme_error_that_the_imbalance_blurs(monkeypatch):
    """Dropping HHT's alpha-weighting of the law forces (a plausible slip in ``effective_rhs``)
    changes the response by a quarter here. The imbalance of the correct run is HHT's numerical
    dissipation, so ``energy_error`` alone cannot tell a 1e-5 error from a real one; the split
    can: the correct run balances to round-off, the wrong one does not."""
    from bearingfw.analysis import hht

    r, f, per = 0.8, 0.3, 100
    P0 = MU * gravity(friction_oscillator(M, K, 1e3 * K, MU)).normal_force("friction") / f
    _, good = run(r, P0 / M, cycles=5, per_cycle=per)
    assert good.balance_error < 1e-12 and good.numerical_dissipation > 0
    original = hht.effective_rhs

    def without_law_weighting(p, s, h, load1):
        rhs, xt, vt = original(p, s, h, load1)
        return rhs - p.scheme.alpha * s.Bt_phi, xt, vt

    monkeypatch.setattr(hht, "effective_rhs", without_law_weighting)
    monkeypatch.setattr(hht, "COMPILED_STEPS", False)  # every step through hht.step, which calls the mutant
    _, bad = run(r, P0 / M, cycles=5, per_cycle=per)
    assert bad.balance_error > 1e-3
