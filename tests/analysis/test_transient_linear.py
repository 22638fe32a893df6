"""Linear transient response against closed forms: HHT accuracy, order, damping, scaling.

The SDOF is a mass on a massless cantilever column (stiffness ``3 E I / h^3`` in y; the tip
rotation is a massless DOF that the solver condenses in time). Free vibration is started by
releasing a static lateral load: the preload carries gravity plus ``P``, the transient applies
``-P`` from ``t = 0``.

HHT reference numbers (Hilber, Hughes & Taylor 1977): the scheme's amplification matrix for
``m a + c v + k u = 0`` is built below from the three defining equations (Newmark updates and the
alpha-weighted equilibrium), independently of the solver. Its principal eigenvalue pair
``exp(h (-sigma_h +- i omega_h))`` gives the algorithmic frequency and decay, i.e. the known
period elongation and algorithmic damping of HHT at this ``omega h``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from kernel_models import COLUMN_K, COLUMN_MASS, column_sdof, deck_model, rel_err

from bearingfw.analysis import (
    ConnectorResponse,
    ElementStress,
    NodalResponse,
    Rayleigh,
    TransientSettings,
    gravity,
    solve_static,
    solve_transient,
)
from bearingfw.model import NodalLoad

OMEGA = np.sqrt(COLUMN_K / COLUMN_MASS)  # 13.4 rad/s, 2.14 Hz
DAMPING = Rayleigh.from_ratios(1.0, 0.02, 5.0, 0.03)
ZETA = DAMPING.alpha / (2 * OMEGA) + DAMPING.beta * OMEGA / 2  # 1.8 %: c = alpha m + beta k (all of k is in K_free)
P = 0.01 * COLUMN_K  # release load: u0 = 1 cm
U0 = P / COLUMN_K
RECORDS = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"


def amplification(h: float, alpha: float, m: float, c: float, k: float) -> np.ndarray:
    """HHT amplification matrix of (u, v, a) for ``m a + c v + k u = 0`` with step ``h``."""
    gamma, beta = 0.5 - alpha, (1 - alpha) ** 2 / 4
    new = np.array([[1, 0, -beta * h * h], [0, 1, -gamma * h], [(1 + alpha) * k, (1 + alpha) * c, m]])
    old = np.array([[1, h, (0.5 - beta) * h * h], [0, 1, (1 - gamma) * h], [alpha * k, alpha * c, 0]])
    return np.linalg.solve(new, old)


def algorithmic(h: float, alpha: float, m: float, c: float, k: float) -> tuple[float, float]:
    """(omega_h, sigma_h): damped frequency and decay rate of the scheme's principal roots."""
    lam = np.linalg.eigvals(amplification(h, alpha, m, c, k))
    lam = lam[np.argmax(np.abs(lam.imag))]
    return abs(np.angle(lam)) / h, -np.log(abs(lam)) / h


def free_vibration(dt: float, alpha: float, duration: float = 4.0):
    model = column_sdof()
    pre = solve_static(model, [NodalLoad("top", fy=P)], g=9.81)
    steps = int(round(duration / dt)) + 1
    res = solve_transient(
        model, np.zeros((steps, 3)), dt, preload=pre, nodal_loads=[NodalLoad("top", fy=-P)], damping=DAMPING,
        settings=TransientSettings(alpha=alpha),
        recorders=[NodalResponse(["top"], components=["uy"], total=True)],
    )
    return res.time, res["displacement"][:, 0, 0], res


def exact_free(t):
    wd = OMEGA * np.sqrt(1 - ZETA**2)
    return U0 * np.exp(-ZETA * OMEGA * t) * (np.cos(wd * t) + ZETA / np.sqrt(1 - ZETA**2) * np.sin(wd * t))


@pytest.mark.parametrize("alpha", [0.0, -0.05, -1 / 3])
def test_free_vibration_is_the_hht_recursion_and_converges_at_second_order(alpha):
    c = DAMPING.alpha * COLUMN_MASS + DAMPING.beta * COLUMN_K
    errors = []
    for dt in (0.02, 0.01, 0.005):
        t, y, res = free_vibration(dt, alpha)
        # 1. the solver is exactly the HHT recursion of the SDOF (the massless rotation condensed)
        A = amplification(dt, alpha, COLUMN_MASS, c, COLUMN_K)
        z = np.array([U0, 0.0, -COLUMN_K * U0 / COLUMN_MASS])
        discrete = [z[0]]
        for _ in range(t.size - 1):
            z = A @ z
            discrete.append(z[0])
        assert rel_err(y, discrete) < 1e-10
        # 2. it differs from the closed form by what HHT's period elongation and algorithmic
        #    damping explain: the closed form with (omega_h, sigma_h) substituted
        wh, sh = algorithmic(dt, alpha, COLUMN_MASS, c, COLUMN_K)
        hht_form = U0 * np.exp(-sh * t) * (np.cos(wh * t) + sh / wh * np.sin(wh * t))
        exact = exact_free(t)
        explained = np.max(np.abs(hht_form - exact))
        assert np.max(np.abs(y - hht_form)) < 0.02 * explained + 1e-5 * U0
        errors.append(np.max(np.abs(y - exact)))
        assert errors[-1] <= 1.02 * explained + 1e-5 * U0
        if alpha == 0.0:
            assert res.energy_error < 1e-9  # Newmark average acceleration: exact discrete balance
    # 3. second order: halving dt divides the error by 4
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.7) & (ratios < 4.3)), ratios


def test_hht_dissipation_is_numerical_energy_loss_and_grows_with_alpha():
    """With alpha < 0 the energy imbalance is the scheme's dissipation: positive, more for more negative alpha."""
    lost = []
    for alpha in (0.0, -0.1, -1 / 3):
        _, _, res = free_vibration(0.05, alpha)  # coarse: omega h = 0.67
        lost.append(res.energy["imbalance"][-1] / res.energy["input"].max())
        # the split: the column "numerical" is that loss, to round-off
        assert res.balance_error < 1e-12
        assert res.numerical_dissipation == pytest.approx(lost[-1], abs=1e-12)
    assert abs(lost[0]) < 1e-10 and 0 < lost[1] < lost[2]


def harmonic_base(dt: float, alpha: float, duration: float = 4.0):
    model = column_sdof()
    steps = int(round(duration / dt)) + 1
    t = dt * np.arange(steps)
    ag = np.zeros((steps, 3))
    ag[:, 1] = 2.0 * np.sin(0.6 * OMEGA * t)
    res = solve_transient(
        model, ag, dt, damping=DAMPING, settings=TransientSettings(alpha=alpha),
        recorders=[NodalResponse(["top"], components=["uy"]), NodalResponse(["top"], "acceleration", ["uy"], total=True)],
    )
    return t, res


def exact_harmonic(t, A, w):
    """u'' + 2 zeta W u' + W^2 u = -A sin(w t) from rest: steady state plus the free response that fits u(0) = u'(0) = 0."""
    W, z = OMEGA, ZETA
    D = (W**2 - w**2) ** 2 + (2 * z * W * w) ** 2
    # steady state u_p = a sin(w t) + b cos(w t)
    a, b = -A * (W**2 - w**2) / D, A * 2 * z * W * w / D
    wd = W * np.sqrt(1 - z**2)
    c1 = -b
    c2 = -(a * w + z * W * c1) / wd
    up = a * np.sin(w * t) + b * np.cos(w * t)
    uh = np.exp(-z * W * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    acc = -a * w**2 * np.sin(w * t) - b * w**2 * np.cos(w * t)
    acc_h = np.exp(-z * W * t) * (
        (z * W) ** 2 * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
        - 2 * z * W * wd * (-c1 * np.sin(wd * t) + c2 * np.cos(wd * t))
        - wd**2 * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    )
    return up + uh, acc + acc_h


@pytest.mark.parametrize("alpha", [0.0, -0.05])
def test_harmonic_base_motion_converges_to_the_closed_form_at_second_order(alpha):
    errors = []
    for dt in (0.02, 0.01, 0.005):
        t, res = harmonic_base(dt, alpha)
        u, acc = exact_harmonic(t, 2.0, 0.6 * OMEGA)
        y = res["displacement"][:, 0, 0]
        errors.append(np.max(np.abs(y - u)) / np.max(np.abs(u)))
        # absolute acceleration = relative + ground: the recorder adds the ground motion
        total = acc + 2.0 * np.sin(0.6 * OMEGA * t)
        assert rel_err(res["acceleration"][:, 0, 0], total) < 60 * errors[-1]
    # the phase error of the free part, (omega h)^2 / 12 per radian over omega t = 54 rad, bounds it
    assert errors[-1] < (OMEGA * 0.005) ** 2 / 12 * OMEGA * 4.0
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.6) & (ratios < 4.4)), ratios


def chuetsu_window(seconds: float = 6.0, start: float = 17.0):
    """A window of the real Chuetsu-oki record (PEER RSN4843), EW/NS/UD as x/y/z, m/s^2."""
    from bearingfw.motion import read_record

    rec = read_record([RECORDS / f"RSN4843_CHUETSU_65006{c}.AT2" for c in ("EW", "NS", "UD")])
    i0, n = int(start / rec.dt), int(seconds / rec.dt)
    return np.column_stack([rec.h1, rec.h2, rec.v])[i0 : i0 + n], rec.dt


def test_linear_bearings_scale_exactly_with_the_excitation():
    """Frictionless, linear-spring and fixed bearings: every dynamic quantity scales with the record."""
    model = deck_model("frictionless")
    model = model.with_law("linear-spring", {"k": 4e8}, connectors=["3A", "3B"]).with_law("fixed", connectors=["2B"])
    pre = gravity(model)
    ag, dt = chuetsu_window()
    recorders = [
        ConnectorResponse(),
        NodalResponse(["GA4", "GB6"], "acceleration", total=True),
        NodalResponse(["GA4"], "displacement", name="disp"),
    ]
    runs = [
        solve_transient(pre.system, s * ag, dt, preload=pre, damping=Rayleigh(0.21, 0.00208), recorders=recorders)
        for s in (1.0, 2.5)
    ]
    # connector quantities are total: subtract the preload's (not the first sample, which already
    # carries the inertia of the record's first acceleration in the tied directions)
    dead = {
        "connectors.force": pre.connector_forces,
        "connectors.displacement": (pre.system.connectors.D @ pre.u).reshape(-1, 3),
    }
    for key in ("connectors.force", "connectors.displacement", "acceleration", "disp"):
        d = dead.get(key, 0.0)
        assert rel_err(runs[1][key] - d, 2.5 * (runs[0][key] - d)) < 1e-9, key
    assert runs[1].energy["input"][-1] == pytest.approx(2.5**2 * runs[0].energy["input"][-1], rel=1e-9)
    assert runs[0].stats["max_iterations"] <= 2  # linear laws: one Newton correction and its check
    assert runs[0].energy_error < 0.01


def test_section_forces_scale_exactly_and_stress_is_total():
    from bearingfw.analysis import ElementForces, element_stresses

    model = deck_model("linear-spring", {"k": 4e8})
    pre = gravity(model)
    ag, dt = chuetsu_window(3.0, start=19.0)
    recorders = [ElementForces(["GA2", "X4", "pier2B"]), ElementStress(["GA2"])]
    runs = [solve_transient(pre.system, s * ag, dt, preload=pre, recorders=recorders) for s in (1.0, -3.0)]
    f0 = runs[0]["section_forces"]
    assert rel_err(runs[1]["section_forces"] - f0[0], -3.0 * (f0 - f0[0])) < 1e-9
    # at t = 0 the total stress is the dead-load stress of the preload
    dead = element_stresses(pre.system, pre.u, ["GA2"], g=pre.g)["GA2"].sigma1
    assert rel_err(runs[0]["stress.GA2"][0], dead) < 1e-12
    assert np.max(np.abs(runs[0]["stress.GA2"] - dead)) > 1e-3 * np.max(np.abs(dead))  # and it does move
