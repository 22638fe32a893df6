"""Damping helpers, settings and recorder validation, result files, inputs."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.sparse as sp
from kernel_models import COLUMN_K, COLUMN_MASS, band_limited_noise, column_sdof, connector_chain, deck_model, rel_err

from bearingfw import create_law
from bearingfw.analysis import (
    ENERGY_COLUMNS,
    ConnectorResponse,
    ElementForces,
    ElementStress,
    NodalResponse,
    Rayleigh,
    TransientResult,
    TransientSettings,
    damping_ratio_from_log_decrement,
    gravity,
    initial_acceleration,
    rayleigh_from_ratios,
    section_forces,
    solve_transient,
)
from bearingfw.model import ModelError
from bearingfw.parameters import ParameterError


# ---- damping ----------------------------------------------------------------------------------
def test_paper_log_decrements_give_its_damping_ratios():
    assert round(100 * damping_ratio_from_log_decrement(0.13), 1) == 2.1
    assert round(100 * damping_ratio_from_log_decrement(0.17), 1) == 2.7
    # the exact relation: the decay per cycle of a viscous SDOF is exp(2 pi zeta / sqrt(1 - zeta^2))
    zeta = damping_ratio_from_log_decrement(0.4)
    assert 2 * math.pi * zeta / math.sqrt(1 - zeta**2) == pytest.approx(0.4, rel=1e-14)
    with pytest.raises(ParameterError, match="delta"):
        damping_ratio_from_log_decrement(-0.1)


def test_paper_rayleigh_coefficients_from_its_ratios():
    a0, a1 = rayleigh_from_ratios(1.50, 0.021, 3.36, 0.027)
    assert a0 == pytest.approx(0.21, abs=0.005)  # paper: alpha = 0.21 1/s (0.2106)
    assert a1 == pytest.approx(0.00208, abs=0.00001)  # paper: beta = 0.00208 s (0.0020853, truncated there)
    damping = Rayleigh.from_ratios(1.50, 0.021, 3.36, 0.027)
    assert (damping.alpha, damping.beta) == (a0, a1)
    assert damping.ratio(1.50) == pytest.approx(0.021, rel=1e-12)
    assert damping.ratio(3.36) == pytest.approx(0.027, rel=1e-12)
    # Rayleigh's curve is convex: between the two frequencies it lies below the chord
    assert damping.ratio(2.2) < 0.021 + (2.2 - 1.50) / (3.36 - 1.50) * (0.027 - 0.021)


def test_rayleigh_validation():
    with pytest.raises(ParameterError, match=r"'alpha' = -0.1 is outside the allowed range alpha >= 0"):
        Rayleigh(-0.1, 0.0)
    with pytest.raises(ParameterError, match="f1 and f2 must differ"):
        rayleigh_from_ratios(2.0, 0.02, 2.0, 0.03)
    with pytest.raises(ParameterError, match="negative coefficient"):
        rayleigh_from_ratios(1.0, 0.05, 10.0, 0.001)
    with pytest.raises(ParameterError, match="zeta1"):
        rayleigh_from_ratios(1.0, 1.5, 2.0, 0.02)


def test_stiffness_proportional_damping_uses_the_linear_structure_only():
    """A mass on a linear-spring bearing: its stiffness is a law, so beta adds no damping to it
    (free decay identical with and without beta); on a column (stiffness in K_free) it does."""
    ag = band_limited_noise(201, 0.01, seed=5, amplitude=[2.0, 2.0, 0.0])
    rec = [NodalResponse(["m1"], components=["ux"])]
    on_law = connector_chain([1.0e4], [("linear-spring", {"k": 4e6})], [1e9])
    a = solve_transient(on_law, ag, 0.01, damping=Rayleigh(0.1, 0.0), recorders=rec)
    b = solve_transient(on_law, ag, 0.01, damping=Rayleigh(0.1, 0.01), recorders=rec)
    assert rel_err(b["displacement"], a["displacement"]) < 1e-12
    rec = [NodalResponse(["top"], components=["uy"])]
    a = solve_transient(column_sdof(), ag, 0.01, damping=Rayleigh(0.1, 0.0), recorders=rec)
    b = solve_transient(column_sdof(), ag, 0.01, damping=Rayleigh(0.1, 0.01), recorders=rec)
    assert rel_err(b["displacement"], a["displacement"]) > 0.05


# ---- settings ---------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"alpha": 0.1}, r"parameter 'alpha' = 0.1 is outside the allowed range -0.333333 <= alpha <= 0"),
        ({"alpha": -0.5}, r"'alpha'"),
        ({"tol_force": 0.0}, r"'tol_force' = 0.0 is outside the allowed range 0 < tol_force <= 0.01"),
        ({"max_iterations": 0}, r"'max_iterations' must be an integer with 1 <= max_iterations <= 1000, got 0"),
        ({"max_iterations": 2.5}, r"'max_iterations' must be an integer"),
        ({"max_halvings": True}, r"'max_halvings' must be an integer"),
        ({"path": "quick"}, r"parameter 'path' must be one of 'fast', 'general', got 'quick'"),
        ({"dt_integration": -0.01}, r"'dt_integration'"),
    ],
)
def test_settings_are_validated_with_clear_messages(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        TransientSettings(**kwargs)


def test_settings_defaults():
    s = TransientSettings()
    assert (s.alpha, s.tol_force, s.tol_displacement, s.max_iterations, s.max_halvings, s.path) == (
        -0.05, 1e-8, 1e-10, 25, 6, "fast",
    )
    assert s.dt_integration is None


# ---- inputs -----------------------------------------------------------------------------------
def test_input_checks():
    model = column_sdof()
    with pytest.raises(ParameterError, match=r"shape \(steps, 3\)"):
        solve_transient(model, np.zeros((10, 2)), 0.01)
    with pytest.raises(ParameterError, match="'dt'"):
        solve_transient(model, np.zeros((10, 3)), 0.0)
    with pytest.raises(ParameterError, match="non-finite"):
        solve_transient(model, np.full((10, 3), np.nan), 0.01)
    pre = gravity(model)
    with pytest.raises(ParameterError, match="another Model"):
        solve_transient(column_sdof(), np.zeros((10, 3)), 0.01, preload=pre)
    with pytest.raises(ParameterError, match="'nodal_loads' must have shape"):
        solve_transient(model, np.zeros((10, 3)), 0.01, preload=pre, nodal_loads=np.zeros(5))
    with pytest.raises(ParameterError, match="share a name"):
        solve_transient(model, np.zeros((10, 3)), 0.01, preload=pre, recorders=[ConnectorResponse(), ConnectorResponse()])
    with pytest.raises(ModelError, match="no node named|unknown node"):
        solve_transient(model, np.zeros((10, 3)), 0.01, preload=pre, recorders=[NodalResponse(["nowhere"])])


def test_recorder_validation():
    with pytest.raises(ParameterError, match="'every' must be an integer"):
        ConnectorResponse(every=0)
    with pytest.raises(ParameterError, match="non-empty list of names"):
        ElementStress([])
    with pytest.raises(ParameterError, match="'name'"):
        ElementForces(["a"], name="bad.name")
    with pytest.raises(ParameterError, match="'components'"):
        NodalResponse(["a"], components=["uq"])
    with pytest.raises(ParameterError, match="'quantity' must be one of"):
        NodalResponse(["a"], quantity="jerk")
    model = deck_model("linear-spring", {"k": 4e8})
    pre = gravity(model)
    with pytest.raises(ModelError, match="no recovery point"):
        solve_transient(model, np.zeros((3, 3)), 0.01, preload=pre, recorders=[ElementStress(["GA1"], points=["nope"])])


def test_dynamic_nodal_load_history_and_initial_acceleration():
    """A nodal force history on the excitation grid; a load present at t = 0 gives a0 = F / m."""
    model = column_sdof()
    n, dt = 201, 0.01
    t = dt * np.arange(n)
    system = gravity(model).system
    loads = np.zeros((n, system.n_dof))
    loads[:, system.dofmap.dof("top", "uy")] = 1e4 * (1 + np.sin(5 * t))
    res = solve_transient(
        model, np.zeros((n, 3)), dt, nodal_loads=loads, settings=TransientSettings(alpha=0.0),
        recorders=[NodalResponse(["top"], "acceleration", ["uy"])],
    )
    assert res["acceleration"][0, 0, 0] == pytest.approx(1e4 / COLUMN_MASS, rel=1e-12)
    assert res.energy_error < 1e-9 and res.energy["input"][-1] > 0
    # equivalently, the same force as ground motion: -m a_g = F
    res_g = solve_transient(
        model, np.column_stack([0 * t, -loads[:, system.dofmap.dof("top", "uy")] / COLUMN_MASS, 0 * t]), dt,
        settings=TransientSettings(alpha=0.0), recorders=[NodalResponse(["top"], "acceleration", ["uy"])],
    )
    assert rel_err(res_g["acceleration"], res["acceleration"]) < 1e-9


def test_initial_acceleration_of_massless_dofs_follows_statically():
    M = sp.csr_matrix(np.diag([2.0, 0.0]))
    K = sp.csr_matrix(np.array([[3.0, -1.0], [-1.0, 4.0]]))
    a = initial_acceleration(M, K, np.array([4.0, 0.0]))
    assert a[0] == pytest.approx(2.0) and a[1] == pytest.approx(0.5)  # K_ss a_s = -K_sm a_m
    assert np.all(initial_acceleration(M, K, np.zeros(2)) == 0.0)


# ---- recorders and results ---------------------------------------------------------------------
@pytest.fixture(scope="module")
def deck_run():
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    pre = gravity(model)
    ag = band_limited_noise(121, 0.01, seed=9, amplitude=[2.5, 2.0, 1.5])
    fractions = []
    res = solve_transient(
        model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208), progress=fractions.append,
        recorders=[
            ConnectorResponse(["1B", "2A", "2B"], every=3),
            ElementForces(["GA2"], every=2),
            ElementStress(["GA2"], points=["top", "bottom"]),
            NodalResponse(["GA4"], "acceleration", total=True),
            NodalResponse(["GA4"], "acceleration", name="relative_acc"),
            NodalResponse(["GA4"], "displacement", total=True, name="total_disp"),
            NodalResponse(["GA4"], "velocity", total=True, name="abs_vel"),
            NodalResponse(["GA4"], "velocity", name="rel_vel"),
        ],
    )
    return model, pre, ag, res, fractions


def test_recorders_decimate_and_add_the_ground_motion(deck_run):
    model, pre, ag, res, fractions = deck_run
    assert np.allclose(res["connectors.time"], 0.03 * np.arange(41))
    assert np.allclose(res["section_forces.time"], 0.02 * np.arange(61))
    assert res["connectors.force"].shape == (41, 3, 3) and res["stress.GA2"].shape == (121, 2, 2)
    assert res.recorders["stress"]["points"] == {"GA2": ["top", "bottom"]}
    # absolute = relative + ground (translations along global axes)
    assert rel_err(res["acceleration"][:, 0, :3], res["relative_acc"][:, 0, :3] + ag) < 1e-12
    vg = np.concatenate([np.zeros((1, 3)), np.cumsum(0.005 * (ag[1:] + ag[:-1]), axis=0)])
    assert rel_err(res["abs_vel"][:, 0, :3], res["rel_vel"][:, 0, :3] + vg) < 1e-12
    # total displacement starts at the dead-load deflection
    assert res["total_disp"][0, 0, 2] == pytest.approx(pre.displacement("GA4", "uz"), rel=1e-12)
    # the section-force recorder equals the kernel's section_forces at the total displacement
    u_end = pre.u + pre.system.expand(np.zeros(pre.system.n_free))
    assert rel_err(res["section_forces"][0], section_forces(pre.system, u_end, ["GA2"], g=pre.g).values) < 1e-12
    # progress: increasing fractions ending at 1
    assert fractions[-1] == 1.0 and np.all(np.diff(fractions) > 0) and len(fractions) == 100


def test_connector_response_by_kind(deck_run):
    """Friction ratio and slip exist for law bearings only (a JOIN has neither); the PLANAR friction
    bearing's ratio never exceeds mu; every bearing stays in compression."""
    model, pre, ag, res, _ = deck_run
    assert np.nanmax(res["connectors.friction_ratio"][:, 0]) <= 0.04 * (1 + 1e-9)  # 1B: PLANAR friction
    assert np.all(np.isnan(res["connectors.friction_ratio"][:, 1]))  # 2A: JOIN, no law
    assert np.all(np.isnan(res["connectors.slip"][:, 1]))
    assert np.all(res["connectors.normal_force"] > 0)


def test_result_file_round_trip_opens_with_plain_numpy(deck_run, tmp_path):
    res = deck_run[3]
    path = res.save(tmp_path / "run")
    assert path.name == "run.npz"
    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta"]))
        assert meta["completed"] and meta["recorders"]["connectors"]["connectors"] == ["1B", "2A", "2B"]
        assert np.array_equal(z["connectors.friction_ratio"], res["connectors.friction_ratio"], equal_nan=True)
        assert np.array_equal(z["energy.imbalance"], res.energy["imbalance"])
    back = TransientResult.load(path)
    assert back.keys() == res.keys() and back.stats == res.stats and back.settings == res.settings
    for key in res.keys():
        assert np.array_equal(back[key], res[key], equal_nan=True)
    assert back.energy_error == res.energy_error
    with pytest.raises(KeyError, match="no recorded array 'nothing'"):
        res["nothing"]


def test_column_lateral_stiffness_is_the_sdof_one():
    """The test SDOF: its free period is 2 pi sqrt(m / (3 E I / h^3)) (massless column, tip mass)."""
    from bearingfw.analysis import solve_modal

    modes = solve_modal(column_sdof(), 2)
    assert modes.frequencies[modes.dominant("y")] == pytest.approx(np.sqrt(COLUMN_K / COLUMN_MASS) / (2 * np.pi), rel=1e-9)


@pytest.mark.parametrize("alpha", [0.0, -0.05, -1 / 3])
def test_tie_forces_carry_the_inertia_of_the_tied_direction(alpha):
    """A mass on a guided bearing (x by a spring, y tied, z a spring): the guide (tie) pushes the
    mass with the whole ground acceleration in y, so its force is -m a_g,y (the connector force
    resists the relative displacement: the force on the mass is -F)."""
    m = 1.0e4
    model = connector_chain([m], [("linear-spring", {"k": 4.0e6})], [1.0e9])
    ag = band_limited_noise(101, 0.01, seed=8, amplitude=[1.0, 2.0, 0.5])
    res = solve_transient(
        model, ag, 0.01, damping=Rayleigh(0.3, 0.001), settings=TransientSettings(alpha=alpha),
        recorders=[ConnectorResponse()],
    )
    force = res["connectors.force"][:, 0]
    assert rel_err(force[:, 1], -m * ag[:, 1]) < 1e-9
    # the friction ratio counts the law's direction only, not the guide's reaction
    N = res["connectors.normal_force"][:, 0]
    assert rel_err(res["connectors.friction_ratio"][:, 0], np.abs(force[:, 0]) / N) < 1e-12
    assert np.max(np.hypot(force[:, 0], force[:, 1]) / N) > 2 * np.max(np.abs(force[:, 0]) / N)


def tied_pair_reference(ag: np.ndarray, dt: float, alpha: float, m1: float, m2: float, k: float, a0: float):
    """HHT of two masses tied together in x, written with the tie's force as a Lagrange multiplier.

    ``m1`` on a spring ``k`` to the ground, ``m2`` tied to ``m1``; mass-proportional damping
    ``a0 M``; relative to the ground. The scheme weights every force but the relative inertia,
    the tie's force ``P`` (on ``m2``) included::

        m2 a_{n+1} + c (a0 m2 v_{n+1} + m2 ag_{n+1} - P_{n+1}) - alpha (a0 m2 v_n + m2 ag_n - P_n) = 0

    and the sum of both masses' equations is the tied pair's SDOF. Returns x and P per step.
    """
    ga, be, c = 0.5 - alpha, (1 - alpha) ** 2 / 4, 1 + alpha
    mt = m1 + m2
    n = ag.shape[0]
    x, P = np.zeros(n), np.zeros(n)
    v, a = 0.0, -ag[0, 0]
    P[0] = m2 * (a + ag[0, 0])
    for i in range(n - 1):
        xt = x[i] + dt * v + (0.5 - be) * dt**2 * a
        vt = v + (1 - ga) * dt * a
        lhs = mt + c * (a0 * mt * ga * dt + k * be * dt**2)
        rhs = -c * (a0 * mt * vt + k * xt + mt * ag[i + 1, 0]) + alpha * (a0 * mt * v + k * x[i] + mt * ag[i, 0])
        a1 = rhs / lhs
        v1 = vt + ga * dt * a1
        x[i + 1] = xt + be * dt**2 * a1
        P[i + 1] = (m2 * a1 + c * (a0 * m2 * v1 + m2 * ag[i + 1, 0]) - alpha * (a0 * m2 * v + m2 * ag[i, 0] - P[i])) / c
        a, v = a1, v1
    return x, P


@pytest.mark.parametrize("alpha", [0.0, -0.05, -1 / 3])
def test_tie_force_between_moving_masses_is_the_one_of_the_weighted_equilibrium(alpha):
    """``m2`` tied in x to ``m1``, which moves on a spring: the tie carries ``m2``'s inertia. With
    alpha < 0 the multipliers must come from the alpha-weighted equation the scheme solved (the
    equilibrium at t_{n+1} is not satisfied by HHT's accelerations: its least-squares multipliers
    were off by 5 % at alpha = -0.05 and 33 % at -1/3)."""
    m1, m2, k = 1.0e4, 3.0e3, 4.0e6
    damping = Rayleigh(0.3, 0.001)  # beta acts on the vertical springs only (the x spring is a law)
    model = connector_chain([m1, m2], [("linear-spring", {"k": k}), ("fixed", {})], [1.0e9, 1.0e9])
    ag = band_limited_noise(201, 0.01, seed=8, amplitude=[2.0, 1.0, 0.5])
    res = solve_transient(
        model, ag, 0.01, damping=damping, settings=TransientSettings(alpha=alpha),
        recorders=[ConnectorResponse(), NodalResponse(["m2"], components=["ux"])],
    )
    x, P = tied_pair_reference(ag, 0.01, alpha, m1, m2, k, damping.alpha)
    assert rel_err(res["displacement"][:, 0, 0], x) < 1e-9
    assert rel_err(res["connectors.force"][:, 1, 0], -P) < 1e-9  # resisting convention: -(force on m2)
    assert rel_err(res["connectors.force"][:, 1, 1], -m2 * ag[:, 1]) < 1e-9
    assert rel_err(res["connectors.force"][:, 0, 1], -(m1 + m2) * ag[:, 1]) < 1e-9


# ---- result keys, file format -------------------------------------------------------------------
def test_any_recorder_name_saves_and_clashing_keys_are_refused(tmp_path):
    """np.savez(file, **arrays) broke on a key "file" and dropped "allow_pickle": the file is
    written member by member now; keys that would clash are refused when the recorder is made."""
    model = connector_chain([1.0e4], [("regularized-coulomb", {"k": 4e7, "mu": 0.05})], [1.0e9])
    ag = band_limited_noise(51, 0.01, seed=1, amplitude=[3.0, 0.0, 0.0])
    recorders = [ConnectorResponse(name="file"), NodalResponse(["m1"], name="allow_pickle"), NodalResponse(["m1"], name="meta_")]
    res = solve_transient(model, ag, 0.01, recorders=recorders)
    back = TransientResult.load(res.save(tmp_path / "keys"))
    assert back.keys() == res.keys() and "file.force" in back.keys() and "allow_pickle" in back.keys()
    for key in res.keys():
        assert np.array_equal(back[key], res[key], equal_nan=True)
    with pytest.raises(ParameterError, match=r"'time'.*sample times"):
        ElementStress(["GA1", "time"])
    for reserved in ("time", "meta", "energy"):
        with pytest.raises(ParameterError, match="'name'"):
            NodalResponse(["m1"], name=reserved)

    class Custom:  # a duck-typed recorder must obey the same key rules
        label, every = "meta", 1

        def bind(self, ctx):
            raise AssertionError("not reached")

    with pytest.raises(ParameterError, match="not valid result keys"):
        solve_transient(model, ag, 0.01, recorders=[Custom()])
    clash = TransientResult(time=np.zeros(2), data={"energy.kinetic": np.zeros(2)}, energy={}, stats={})
    with pytest.raises(ValueError, match="clash"):
        clash.save(tmp_path / "clash")


def test_meta_is_strict_json_with_null_for_non_finite_numbers(tmp_path):
    res = TransientResult(
        time=np.zeros(2), data={}, energy={}, stats={"residual": float("inf"), "ratio": np.float64("nan"), "n": np.int64(3)},
        settings={"rayleigh": [0.0, np.nan]},
    )
    path = res.save(tmp_path / "strict")

    def refuse(token):
        raise AssertionError(f"non-standard JSON token {token}")

    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta"]), parse_constant=refuse)
    assert meta["stats"] == {"residual": None, "ratio": None, "n": 3} and meta["settings"]["rayleigh"] == [0.0, None]


# ---- what the recorders report ------------------------------------------------------------------
def test_slip_comes_from_the_law_and_hysteresis_uses_the_law_displacement():
    """``.slip`` is the law's ``slip(state)`` (Bouc-Wen here: its state keeps no "slip" entry), NaN
    for a law without ``slip``; ``.law_displacement`` is what the law sees (zero at the preload of
    a bearing set after the dead load), ``.displacement`` the connector's relative displacement.
    The check replays the law along the recorded law displacements (the protocol: the committed
    state is the response's at the converged displacement) and asks it for its slip."""
    params = {"k": 5e7, "alpha": 0.05, "uy": 2e-3, "A": 1.0, "beta": 0.5, "gamma": 0.5, "n": 1.0}
    model = connector_chain([1.0e4, 1.0e4], [("bouc-wen", params), ("linear-spring", {"k": 4e7})], [1.0e9, 1.0e9])
    pre = gravity(model)
    ag = band_limited_noise(201, 0.01, seed=6, amplitude=[6.0, 0.0, 1.0])
    res = solve_transient(model, ag, 0.01, preload=pre, recorders=[ConnectorResponse()])
    law = create_law("bouc-wen", dims=1, **params)
    state = law.initial_state(1)
    expected = [law.slip(state)[0, 0]]
    u, N = res["connectors.law_displacement"][:, 0, :1], res["connectors.normal_force"][:, 0]
    for k in range(1, res.time.size):
        state = law.respond(state, u[k][None], N[k : k + 1], 0.01).state
        expected.append(law.slip(state)[0, 0])
    slip = res["connectors.slip"]
    assert rel_err(slip[:, 0, 0], expected) < 1e-9
    assert np.max(np.abs(slip[:, 0, 0])) > 0.5 * params["uy"]  # it yields
    assert np.all(np.isnan(slip[:, 0, 1:])) and np.all(np.isnan(slip[:, 1]))  # tied / vertical; no slip()
    # law displacement: the law's directions only, zero at the start; the relative displacement
    # also holds the dead-load part (here the vertical sag, outside the law's direction)
    law_disp = res["connectors.law_displacement"]
    assert np.all(law_disp[0, :, 0] == 0.0) and np.all(np.isnan(law_disp[:, :, 1:]))
    rel = res["connectors.displacement"]
    dead = (pre.system.connectors.D @ pre.u).reshape(-1, 3)
    # (the laws' d and the recorded B x differ by the Newton tolerance on the fast path)
    assert rel_err(rel[:, :, 0] - dead[None, :, 0], law_disp[:, :, 0]) < 1e-8
    assert np.all(np.abs(dead[:, 2]) > 0)
    assert res.recorders["connectors"]["units"]["law_displacement"] == "m"


def test_law_displacement_starts_at_zero_where_the_dead_load_moved_the_bearing(deck_run):
    """On the deck the dead load rotates the girder ends, which moves the soffit bearings
    horizontally: ``.displacement`` starts there, ``.law_displacement`` (what the law sees, the
    hysteresis axis) at zero; the two differ by that constant offset."""
    res = deck_run[3]
    rel, law = res["connectors.displacement"], res["connectors.law_displacement"]
    governed = ~np.isnan(law[0])
    assert governed[0, :2].all() and not governed[1].any() and governed[2].tolist() == [False, True, False]
    assert np.all(law[0][governed] == 0.0) and np.max(np.abs(rel[0][governed])) > 1e-4
    offset = rel - law
    assert np.max(np.abs(offset - offset[0])[:, governed]) < 1e-8 * np.max(np.abs(rel[:, governed]))


def test_section_forces_at_any_time_are_the_kernels_of_the_recorded_displacement():
    """The recorder's linear map, read off the kernel once, against the kernel's own
    ``section_forces`` at the recorded total displacement, late in a nonlinear run."""
    from bearingfw.model import COMPONENTS

    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    pre = gravity(model)
    nodes = [n.name for n in model.nodes]
    elements = ["GA2", "X4", "pier2B"]
    ag = band_limited_noise(161, 0.01, seed=11, amplitude=[3.0, 2.5, 2.0])
    res = solve_transient(
        model, ag, 0.01, preload=pre,
        recorders=[ElementForces(elements), NodalResponse(nodes, components=COMPONENTS, total=True, name="u")],
    )
    system = pre.system
    dofs = system.dofmap.dofs(nodes, COMPONENTS)
    for k in (40, 100, 160):
        u = np.zeros(system.n_dof)
        u[dofs] = res["u"][k].reshape(-1)
        kernel = section_forces(system, u, elements, g=pre.g).values
        assert rel_err(res["section_forces"][k], kernel) < 1e-10, k
        assert rel_err(res["section_forces"][k], res["section_forces"][0]) > 1e-3  # it moved


def test_nodal_response_describes_what_total_adds(deck_run):
    res = deck_run[3]
    assert "relative to the ground" in res.recorders["total_disp"]["reference"]
    assert "dead-load" in res.recorders["total_disp"]["reference"]
    assert res.recorders["acceleration"]["reference"].startswith("absolute")
    assert res.recorders["rel_vel"]["reference"] == "relative to the ground"


def test_energy_table_and_stats_carry_the_numerical_dissipation(deck_run):
    res = deck_run[3]
    assert set(res.energy) == {"time", *ENERGY_COLUMNS} and "numerical" in ENERGY_COLUMNS
    assert res.stats["alpha"] == -0.05 == res.settings["alpha"]
    assert res.balance_error < 1e-8 < res.numerical_dissipation
    assert res.stats["setup_time"] + res.stats["loop_time"] <= res.stats["wall_time"] + 1e-9
    assert res.stats["failed_iterations"] == 0 and res.stats["backtracks"] >= 0


def test_linear_laws_converge_at_the_first_law_call_of_each_step(monkeypatch):
    """The fast path's predictor linearises the laws with the last step's tangent: exact for a
    linear law, so each step needs one law call (it needed two with the last forces held); the
    first step has no last tangent yet and takes two. (Through Newton: a law that declares
    ``linear`` is folded into the matrix instead, tests/analysis/test_linear_laws.py.)"""
    from bearingfw.laws.elastic import LinearSpring

    monkeypatch.setattr(LinearSpring, "linear", False)
    model = deck_model("linear-spring", {"k": 4e8})
    ag = band_limited_noise(200, 0.01, seed=3, amplitude=(1.0, 1.0, 0.5))
    result = solve_transient(model, ag, 0.01, damping=Rayleigh(0.2, 0.002))
    assert result.stats["steps"] == 199
    assert result.stats["iterations"] == 199 + 1


def test_multiplier_map_gives_the_multipliers_of_the_full_residual():
    """Recorders read tie forces from a precomputed linear map; it must equal solving the Gram
    system for the full-DOF residual, for any state (both are linear in it)."""
    from bearingfw.analysis.excitation import build_excitation
    from bearingfw.analysis.recorders import Context, Snapshot

    preload = gravity(deck_model("linear-spring", {"k": 4e8}))
    system = preload.system
    ag = band_limited_noise(20, 0.01, seed=4, amplitude=(1.0, 1.0, 0.5))
    nodal = np.random.default_rng(9).normal(size=system.n_dof) * (system.M.diagonal() > 0)
    ctx = Context(system, preload, build_excitation(system, ag, 0.01), 0.3, 0.004)
    rng = np.random.default_rng(8)
    n, m = system.n_free, system.connectors.n_governed
    snap = Snapshot(0.05, rng.normal(size=n), rng.normal(size=n), rng.normal(size=n), rng.normal(size=m), (),
                    rng.normal(size=3), rng.normal(size=3), nodal, a_equilibrium=rng.normal(size=n))  # fmt: skip
    rows = np.arange(len(system.constraints.equations))
    expected = system.constraints.multipliers(ctx.full_residual(snap))
    got = ctx.multiplier_map(rows).dynamic(snap, ctx.a0, ctx.a1, preload.law_forces)
    np.testing.assert_allclose(got, expected, rtol=1e-8, atol=1e-9 * np.abs(expected).max())
