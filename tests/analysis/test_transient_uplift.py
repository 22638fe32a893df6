"""Uplift: compression-only vertical springs (``Connector(uplift=True)``) in statics, modes and time
histories; lift-off against closed forms, no tension, the energy balance, the uplift summary."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import band_limited_noise, deck_model, rel_err, with_uplift

from bearingfw.analysis import (
    ConnectorResponse,
    NodalResponse,
    Rayleigh,
    TransientResult,
    TransientSettings,
    gravity,
    solve_modal,
    solve_static,
    solve_transient,
)
from bearingfw.model import Connector, Model, ModelError, NodalLoad, NodalMass, Node, Support

G = 9.81


# --- a mass on a compression-only spring, thrown up: closed-form contact times ------------------------
MASS, KV = 1000.0, 1e7  # omega = 100 rad/s; dead-load compression m g / kv ~ 1 mm
PULL, PULL_END, DT, DURATION = 2 * MASS * G, 0.05, 1e-4, 0.4


def bouncing_mass() -> Model:
    spring = Connector("b", "g", "m", "axial", law="linear-spring", law_params={"k": 1e6}, vertical_stiffness=KV,
                       uplift=True)
    return Model([Node("g", 0, 0, 0), Node("m", 0, 0, 0)], connectors=[spring], supports=[Support("g")],
                 masses=[NodalMass("m", MASS)])


def bounce_times() -> dict[str, float]:
    """The mass rests on the spring (``d_s = -m g / kv``); ``F = 2 m g`` up from t = 0 to ``t_F``.

    Closed (d <= 0): ``d = d_s + (F / kv)(1 - cos w t)`` until it reaches 0 at ``t1`` (``cos w t1 =
    1 - m g / F``); then free flight, up at ``(F - m g) / m`` until ``t_F``, then ``-g``, until it
    lands at ``t2`` with ``v2``; closed again, ``d - d_s = -d_s cos w s + (v2 / w) sin w s``, until it
    leaves at ``t3 = t2 + (2 pi + 2 theta) / w`` (``theta = atan2(v2 / w, -d_s)``) with ``-v2``
    (elastic), and lands at ``t4 = t3 + 2 |v2| / g``. The load, sampled every ``DT`` and linear in
    between, ends with a ramp over one step: the same impulse as a step at ``t_F + DT / 2``.
    """
    w, ds = np.sqrt(KV / MASS), -MASS * G / KV
    t1 = np.arccos(1 - MASS * G / PULL) / w
    v1 = PULL / KV * w * np.sin(w * t1)
    t_f = PULL_END + DT / 2
    up = (PULL - MASS * G) / MASS
    d_f, v_f = v1 * (t_f - t1) + up * (t_f - t1) ** 2 / 2, v1 + up * (t_f - t1)
    flight = (v_f + np.sqrt(v_f**2 + 2 * G * d_f)) / G
    t2, v2 = t_f + flight, v_f - G * flight
    t3 = t2 + (2 * np.pi + 2 * np.arctan2(v2 / w, -ds)) / w
    return {"t1": t1, "t2": t2, "t3": t3, "t4": t3 + 2 * abs(v2) / G, "peak": d_f + v_f**2 / (2 * G)}


@pytest.fixture(scope="module")
def bounce():
    pre = gravity(bouncing_mass())
    system = pre.system
    n = int(round(DURATION / DT)) + 1
    t = DT * np.arange(n)
    loads = np.zeros((n, system.n_dof))
    loads[t <= PULL_END + 1e-12, system.dofmap.dof("m", "uz")] = PULL
    return solve_transient(
        system, np.zeros((n, 3)), DT, preload=pre, nodal_loads=loads, recorders=[ConnectorResponse()],
        settings=TransientSettings(alpha=0.0),  # fast path (the general one agrees: the tremor test below)
    )


def test_a_mass_thrown_off_its_spring_lifts_and_lands_at_the_closed_form_times(bounce):
    dz = bounce["connectors.displacement"][:, 0, 2]  # total d_z: > 0 lifted
    t = bounce.time
    edges = np.flatnonzero(np.diff(dz > 0))
    crossings = t[edges] + (t[1] - t[0]) * dz[edges] / (dz[edges] - dz[edges + 1])
    exact = bounce_times()
    np.testing.assert_allclose(crossings, [exact[k] for k in ("t1", "t2", "t3", "t4")], rtol=0, atol=2e-6)
    assert np.max(bounce["connectors.gap"]) == pytest.approx(exact["peak"], rel=1e-5)
    summary = bounce.uplift["b"]
    assert summary["lift_offs"] == 2
    lifted = (exact["t2"] - exact["t1"]) + (exact["t4"] - exact["t3"])
    assert summary["lifted_time"] == pytest.approx(lifted, abs=2e-6)
    assert summary["peak_gap"] == pytest.approx(exact["peak"], rel=1e-5)


def test_while_lifted_the_bearing_carries_nothing_and_the_gap_is_elastic(bounce):
    N = bounce["connectors.normal_force"][:, 0]
    lifted = bounce["connectors.lifted"][:, 0]
    assert np.all(N >= 0.0)  # never tension
    assert np.all(N[lifted] == 0.0) and np.all(N[~lifted] > 0.0)
    assert np.all(np.isnan(bounce["connectors.friction_ratio"][lifted, 0]))
    gap = np.maximum(bounce["connectors.displacement"][:, 0, 2], 0)
    np.testing.assert_allclose(bounce["connectors.gap"][:, 0], gap, rtol=1e-12, atol=1e-15)
    # alpha = 0: the energy balance is exact; the gap's energy is in the bearings' column
    assert bounce.energy_error < 1e-9
    assert bounce.stats["max_iterations"] <= 3


# --- statics and modes: the bearings closed ---------------------------------------------------------------
def test_gravity_and_modes_take_uplift_bearings_closed():
    plain = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    lifting = with_uplift(plain)
    a, b = gravity(plain), gravity(lifting)
    assert rel_err(b.u, a.u) < 1e-12 and rel_err(b.normal_forces, a.normal_forces) < 1e-12
    assert rel_err(b.connector_forces, a.connector_forces) < 1e-12
    gaps = b.system.connectors.gap_rows
    assert gaps.size == 5 and np.all(b.law_reference[gaps] == 0.0)  # the gap law sees the total d_z
    np.testing.assert_allclose(-b.law_forces[gaps], b.normal_forces[b.system.connectors.gap_group.connectors], rtol=1e-12)
    fa = solve_modal(plain, 6, preload=a).frequencies
    fb = solve_modal(lifting, 6, preload=b).frequencies
    np.testing.assert_allclose(fb, fa, rtol=1e-10)
    # active bearings reach the same closed equilibrium through the gap law
    c = gravity(with_uplift(deck_model("linear-spring", {"k": 4e8})), bearings="active")
    d = gravity(deck_model("linear-spring", {"k": 4e8}), bearings="active")
    assert rel_err(c.u, d.u) < 1e-9


def test_a_static_load_that_pulls_an_uplift_bearing_is_refused_or_lifts_it():
    model = with_uplift(deck_model("linear-spring", {"k": 4e8}), names=("1B",))
    up = [NodalLoad("GB0", fz=3e6)]  # lifts the girder end over bearing 1B
    with pytest.raises(ModelError, match=r"pulls the uplift bearing\(s\) '1B' \(tension .* N\), which cannot carry"):
        gravity(model, loads=up)
    active = solve_static(model, up, g=G, bearings="active")
    assert active.normal_force("1B") == 0.0  # lifted: the gap open, no tension
    assert active.displacement("S1B", "uz") - active.displacement("P1B", "uz") > 0


# --- a deck under a strong vertical tremor ----------------------------------------------------------------
@pytest.fixture(scope="module")
def tremor():
    model = with_uplift(deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}))
    pre = gravity(model)
    ag = band_limited_noise(401, 0.005, seed=5, amplitude=[3.0, 2.0, 15.0])
    runs = {
        (path, alpha): solve_transient(
            model, ag, 0.005, preload=pre, damping=Rayleigh(0.2, 0.002), recorders=[ConnectorResponse()],
            settings=TransientSettings(path=path, alpha=alpha, tol_force=1e-10, tol_displacement=1e-12),
        )
        for path, alpha in (("fast", 0.0), ("general", 0.0), ("fast", -0.05))
    }
    return model, runs


def test_a_strong_vertical_tremor_lifts_bearings_without_tension(tremor):
    model, runs = tremor
    res = runs["fast", 0.0]
    lifting = [k for k, c in enumerate(model.connectors) if c.uplift]
    N = res["connectors.normal_force"][:, lifting]
    lifted = res["connectors.lifted"][:, lifting]
    assert np.all(N >= 0.0)
    assert np.all(N[lifted] == 0.0) and np.all(N[~lifted] > 0.0)
    assert np.all(np.isnan(res["connectors.friction_ratio"][:, lifting][lifted]))
    assert np.nanmax(res["connectors.friction_ratio"]) <= 0.04 * (1 + 1e-9)
    # the uplift summary counts every lift-off (the recorder samples every step here)
    counts = np.sum(~lifted[:-1] & lifted[1:], axis=0)
    assert all(res.uplift[model.connectors[k].name]["lift_offs"] == n for k, n in zip(lifting, counts, strict=True))
    assert sum(counts) >= 20 and all(n > 0 for n in counts)
    peaks = [res.uplift[model.connectors[k].name]["peak_gap"] for k in lifting]
    np.testing.assert_allclose(peaks, np.max(res["connectors.gap"][:, lifting], axis=0), rtol=1e-12)
    # no law force (friction) while lifted; a guided bearing's guide (a tie) still holds it sideways
    law_directions = ~np.isnan(res["connectors.law_displacement"][0, lifting])  # (bearings, 3)
    force = res["connectors.force"][:, lifting]
    assert np.all(np.where(law_directions[None] & lifted[..., None], force, 0.0) == 0.0)


def test_uplift_keeps_the_energy_balance_and_both_paths_agree(tremor):
    _, runs = tremor
    fast, general = runs["fast", 0.0], runs["general", 0.0]
    for res in runs.values():
        assert res.balance_error < 1e-8
    assert fast.energy_error < 1e-8  # alpha = 0: no numerical dissipation either
    assert runs["fast", -0.05].energy_error < 0.05  # HHT's dissipation of the impacts' high frequencies
    for key in ("connectors.force", "connectors.displacement", "connectors.gap", "connectors.slip"):
        assert rel_err(fast[key], general[key]) < 1e-6, key
    assert fast.uplift.keys() == general.uplift.keys()
    for name, tally in fast.uplift.items():
        assert tally == pytest.approx(general.uplift[name], rel=1e-6), name


def test_uplift_bearings_that_stay_closed_answer_like_linear_springs():
    """Weak shaking: nothing lifts; only the stiffness-proportional damping differs (the uplift
    springs are laws, which Rayleigh's K part leaves out), so with mass-proportional damping alone
    the responses agree to the solver's tolerance."""
    plain = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    ag = band_limited_noise(201, 0.01, seed=2, amplitude=[1.0, 1.0, 1.0])
    rec = [ConnectorResponse(), NodalResponse(["GA4", "GB4"], "acceleration")]
    settings = TransientSettings(tol_force=1e-10, tol_displacement=1e-12)
    a = solve_transient(plain, ag, 0.01, recorders=rec, damping=Rayleigh(0.3, 0.0), settings=settings)
    b = solve_transient(with_uplift(plain), ag, 0.01, recorders=rec, damping=Rayleigh(0.3, 0.0), settings=settings)
    assert not b["connectors.lifted"].any() and all(v["lift_offs"] == 0 for v in b.uplift.values())
    for key in a.keys():
        assert rel_err(b[key], a[key]) < 1e-7, key
    assert a.uplift == {} and "connectors.gap" not in a.keys()


def test_the_uplift_summary_is_saved_with_the_result(tremor, tmp_path):
    _, runs = tremor
    res = runs["fast", -0.05]
    back = TransientResult.load(res.save(tmp_path / "uplift"))
    assert back.uplift == res.uplift and back["connectors.lifted"].dtype == bool


# --- the reference bridge ------------------------------------------------------------------------------
def test_the_reference_bridge_puts_uplift_on_its_sliding_bearings_only_when_asked():
    from bearingfw.bridges import BridgeParameters
    from bearingfw.bridges.layout import BEARINGS
    from bearingfw.bridges.reference import bridge_model
    from bearingfw.parameters import ParameterError

    laws = {b: ("linear-spring", {"k": 4e8}) for b in BEARINGS}
    assert not any(c.uplift for c in bridge_model(BridgeParameters(), laws).connectors)  # the default: off
    lifting = bridge_model(BridgeParameters(uplift=True), laws)
    assert {c.name for c in lifting.connectors if c.uplift} == {b for b in BEARINGS if b != "4A"}  # 4A: JOIN
    a, b = gravity(bridge_model(BridgeParameters(), laws)), gravity(lifting)
    assert rel_err(b.normal_forces, a.normal_forces) < 1e-9 and np.all(b.normal_forces > 0)
    with pytest.raises(ParameterError, match="field 'uplift' must be true or false"):
        BridgeParameters(uplift="yes")
