"""Damping helpers, settings and recorder validation, result files, inputs."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.sparse as sp
from kernel_models import deck_model
from transient_models import COLUMN_K, COLUMN_MASS, band_limited_noise, column_sdof, connector_chain, rel_err

from bearingfw.analysis import (
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


def test_tie_forces_carry_the_inertia_of_the_tied_direction():
    """A mass on a guided bearing (x by a spring, y tied, z a spring): the guide (tie) pushes the
    mass with the whole ground acceleration in y, so its force is -m a_g,y (the connector force
    resists the relative displacement: the force on the mass is -F)."""
    m = 1.0e4
    model = connector_chain([m], [("linear-spring", {"k": 4.0e6})], [1.0e9])
    ag = band_limited_noise(101, 0.01, seed=8, amplitude=[1.0, 2.0, 0.5])
    res = solve_transient(model, ag, 0.01, damping=Rayleigh(0.3, 0.001), recorders=[ConnectorResponse()])
    force = res["connectors.force"][:, 0]
    assert rel_err(force[:, 1], -m * ag[:, 1]) < 1e-9
    # the friction ratio counts the law's direction only, not the guide's reaction
    N = res["connectors.normal_force"][:, 0]
    assert rel_err(res["connectors.friction_ratio"][:, 0], np.abs(force[:, 0]) / N) < 1e-12
    assert np.max(np.hypot(force[:, 0], force[:, 1]) / N) > 2 * np.max(np.abs(force[:, 0]) / N)
