"""Fast (condensed) and general (full Newton) paths, line search, step subdivision, failure,
integration step, the sparse branch, a preload with active bearings."""

from __future__ import annotations

import attrs
import numpy as np
import pytest
from kernel_models import band_limited_noise, connector_chain, deck_model, registry_with_test_laws, rel_err

from bearingfw.analysis import (
    ConnectorResponse,
    ElementForces,
    ElementStress,
    NodalResponse,
    Rayleigh,
    TransientError,
    TransientSettings,
    gravity,
    hht,
    solve_transient,
)
from bearingfw.parameters import ParameterError


@pytest.fixture(scope="module")
def test_laws():
    """The installed plugins plus a test plugin with the test-only laws."""
    with registry_with_test_laws() as registry:
        yield registry


@pytest.fixture(scope="module")
def friction_deck():
    """The two-span twin-girder deck on regularized-Coulomb bearings, strong 3-component shaking."""
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    pre = gravity(model)
    ag = band_limited_noise(301, 0.01, seed=11, amplitude=[3.0, 2.5, 2.0])
    return model, pre, ag


def test_fast_and_general_paths_agree(friction_deck):
    """Both paths solve the same equations: they agree to the convergence tolerance. (At the
    default tolerances, 1e-8 / 1e-10, displacements and forces agree to ~5e-10 and the friction
    ratio of a lightly loaded bearing to ~2e-8 of the largest ratio; tighter tolerances here.)"""
    model, pre, ag = friction_deck
    recorders = [
        ConnectorResponse(),
        ElementStress(["GA2", "GB4", "pier2B"]),
        ElementForces(["X4", "GA3"]),
        NodalResponse(["GA4", "GB4", "S1B"], "acceleration", total=True),
        NodalResponse(["GA4", "GB6"], "displacement", components=("ux", "uy", "uz", "rx"), name="disp"),
    ]
    runs = {
        path: solve_transient(
            model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208),
            settings=TransientSettings(path=path, tol_force=1e-10, tol_displacement=1e-12), recorders=recorders,
        )
        for path in ("fast", "general")
    }
    fast, general = runs["fast"], runs["general"]
    assert fast.keys() == general.keys()
    for key in fast.keys():
        assert rel_err(fast[key], general[key]) < 1e-8, key
    for col in ("kinetic", "strain", "damping", "bearings", "input"):
        assert rel_err(fast.energy[col], general.energy[col]) < 1e-8, col
    # the problem is nonlinear where it matters: bearings slip and N moves
    assert np.nanmax(np.abs(fast["connectors.slip"])) > 1e-4
    N = fast["connectors.normal_force"][:, 3:]
    assert np.all(np.ptp(N, axis=0) > 0.2 * N[0])
    assert fast.stats["max_iterations"] > 2
    # energy at alpha = -0.05: the imbalance is the scheme's numerical dissipation and nothing else;
    # it removes energy (it does not create it) and stays small for this broadband input
    for res in (fast, general):
        assert res.balance_error < 1e-8
        assert_numerical_dissipation(res, at_most=0.02)


def assert_numerical_dissipation(res, at_most: float) -> None:
    """HHT alpha < 0: the imbalance is positive at the end (energy lost, not created), never more
    than a trace below zero on the way (the scheme's dissipation is not monotone step by step),
    at most ``at_most`` of the input, and its split explains it (``numerical``)."""
    imbalance, top = res.energy["imbalance"], np.max(np.abs(res.energy["input"]))
    assert 0 < imbalance[-1] <= at_most * top
    assert np.min(imbalance) > -1e-4 * top
    assert 0 < res.numerical_dissipation <= at_most
    assert res.stats["alpha"] < 0 and res.stats["balance_error"] == res.balance_error


@pytest.mark.parametrize("path", ["fast", "general"])
def test_friction_deck_energy_balance_with_average_acceleration(friction_deck, path):
    """alpha = 0: no numerical dissipation, the discrete balance is exact (Newton tolerance)."""
    model, pre, ag = friction_deck
    res = solve_transient(
        model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208), settings=TransientSettings(alpha=0.0, path=path)
    )
    assert res.energy_error < 1e-8
    assert np.all(np.abs(res.energy["numerical"]) < 1e-12 * np.max(res.energy["input"]))
    assert res.energy["bearings"][-1] > 0.05 * res.energy["input"][-1]


@pytest.fixture(scope="module")
def stiff_stick_deck():
    """The deck on regularized Coulomb with a stiff stick (k = 4e10 N/m: stick/slip switches at
    nearly every step), 2 s of horizontal shaking."""
    model = deck_model("regularized-coulomb", {"k": 4e10, "mu": 0.04})
    ag = band_limited_noise(201, 0.01, seed=0, amplitude=[2.0, 1.5, 0.0])
    return model, gravity(model), ag


def test_stiff_stick_converges_without_step_halving_and_both_paths_agree(stiff_stick_deck):
    """A full Newton correction from stick overshoots into slip (zero tangent) and back: without
    a line search the iterates alternate between two states and only halving the step helped
    (hundreds of halvings for 200 steps). With it every step converges at its full size."""
    model, pre, ag = stiff_stick_deck
    recorders = [ConnectorResponse(), NodalResponse(["GA4", "GB6"], "acceleration")]
    tight = {"tol_force": 1e-10, "tol_displacement": 1e-12}
    runs = {
        path: solve_transient(
            model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208),
            settings=TransientSettings(path=path, **tight), recorders=recorders,
        )
        for path in ("fast", "general")
    }
    for res in runs.values():
        assert res.stats["subdivisions"] == 0 and res.stats["failed_iterations"] == 0
        assert res.stats["backtracks"] > 0  # the line search did the work
        assert res.stats["iterations"] < 10 * res.stats["substeps"]
        assert res.balance_error < 1e-8
    fast, general = runs["fast"], runs["general"]
    for key in fast.keys():
        # the friction ratio of a lightly loaded bearing amplifies the tolerance (see above)
        assert rel_err(fast[key], general[key]) < (1e-7 if key.endswith("friction_ratio") else 1e-8), key
    assert np.nanmax(np.abs(fast["connectors.slip"])) > 1e-4  # it does slip


def test_a_wrong_tangent_is_rescued_by_the_line_search(test_laws):
    """A zero reported tangent makes Newton a fixed-point iteration with contraction
    (1 + alpha) k beta h^2 / m: 2.1 at h = 0.01 s, which diverges; halving each correction
    (the line search) turns it into a contraction, so the step converges at its full size and
    gives the honest spring's answer."""
    model = connector_chain([1.0e4], [("test-lying-spring", {"k": 8.0e8})], [1.0e9])
    honest = connector_chain([1.0e4], [("linear-spring", {"k": 8.0e8})], [1.0e9])
    ag = band_limited_noise(51, 0.01, seed=3, amplitude=[2.0, 0.0, 0.0])
    rec = [NodalResponse(["m1"], components=["ux"])]
    settings = TransientSettings(alpha=0.0, max_iterations=60)
    exact = solve_transient(honest, ag, 0.01, settings=settings, recorders=rec)
    for path in ("fast", "general"):
        lying = solve_transient(
            model, ag, 0.01, settings=attrs.evolve(settings, path=path), recorders=rec, registry=test_laws
        )
        assert lying.stats["subdivisions"] == 0 and lying.stats["backtracks"] > 0
        assert rel_err(lying["displacement"], exact["displacement"]) < 1e-7
        assert lying.energy_error < 1e-8


def test_a_step_that_does_not_converge_is_halved_and_gives_the_small_step_answer(test_laws):
    """A law that fails (non-finite force) for steps above 6 ms: every 10 ms step is halved once,
    and the answer is the one of a 5 ms integration step."""
    model = connector_chain([1.0e4], [("test-step-limited-spring", {"k": 8.0e8, "dt_max": 0.006})], [1.0e9])
    honest = connector_chain([1.0e4], [("linear-spring", {"k": 8.0e8})], [1.0e9])
    ag = band_limited_noise(101, 0.01, seed=3, amplitude=[2.0, 0.0, 0.0])
    rec = [NodalResponse(["m1"], components=["ux"])]
    limited = solve_transient(model, ag, 0.01, settings=TransientSettings(alpha=0.0), recorders=rec, registry=test_laws)
    assert limited.stats["subdivisions"] == 100 and limited.stats["substeps"] == 200
    assert limited.stats["failed_iterations"] == 100  # each 10 ms attempt fails at its first law call
    fine = solve_transient(
        honest, ag, 0.01, settings=TransientSettings(alpha=0.0, dt_integration=0.005), recorders=rec
    )
    assert limited.time.size == 101  # recorded at the nominal steps only
    assert rel_err(limited["displacement"], fine["displacement"][::2]) < 1e-10
    # the energy is accumulated over the sub-steps: with alpha = 0 the balance stays exact
    assert limited.energy_error < 1e-8


@pytest.mark.parametrize("path", ["fast", "general"])
def test_a_failed_step_reports_its_true_force_residual(test_laws, path):
    """The fast path's linearised residual c |K_t g| is zero for a zero tangent: a failure must
    report the residual of the displacement it stopped at, as the general path does, and say
    that step halving was off rather than "after 0 halvings"."""
    model = connector_chain([1.0e4], [("test-lying-spring", {"k": 8.0e8})], [1.0e9])
    ag = np.zeros((11, 3))
    ag[:, 0] = 2.0  # a step: the first time step moves the bearing by ~1e-4 m
    settings = TransientSettings(max_iterations=2, max_halvings=0, path=path)
    with pytest.raises(TransientError) as info:
        solve_transient(model, ag, 0.01, settings=settings, registry=test_laws)
    err = info.value
    assert np.isfinite(err.residual) and err.residual > 0.1  # before: 0 on the fast path
    assert f"relative force residual {err.residual:.3g}" in str(err)
    assert "max_halvings = 0" in str(err) and "after 0 halvings" not in str(err)
    assert err.connectors == ("c1",)


def test_failure_names_time_connectors_residual_and_keeps_the_results(test_laws):
    model = connector_chain(
        [1.0e4, 1.0e4],
        [("linear-spring", {"k": 4.0e7}), ("test-brittle-spring", {"k": 2.0e7, "limit": 2e-3})],
        [1.0e9, 1.0e9],
    )
    t = 0.01 * np.arange(301)
    ag = np.zeros((t.size, 3))
    ag[:, 0] = 3.0 * t  # a ramp: the top bearing stretches until it breaks
    with pytest.raises(TransientError) as info:
        solve_transient(
            model, ag, 0.01, registry=test_laws, settings=TransientSettings(max_halvings=3),
            recorders=[ConnectorResponse(), NodalResponse(["m2"], components=["ux"], every=5)],
        )
    err = info.value
    assert err.connectors == ("c2",)
    assert 0.0 < err.last_converged < err.time < 3.0
    assert err.residual == np.inf  # a non-finite law force
    assert f"t = {err.time:.6g} s" in str(err) and "c2" in str(err)
    assert "connectors still moving: c2 (law 'test-brittle-spring')" in str(err)  # the law is named too
    res = err.result
    assert not res.completed and res.message == str(err)
    # everything up to the last converged instant is kept, the final partial instant included
    assert res.time[-1] == pytest.approx(err.last_converged) and res["connectors.time"][-1] == res.time[-1]
    stretch = res["connectors.displacement"][:, 1, 0]
    assert np.max(np.abs(stretch)) <= 2e-3 and np.max(np.abs(stretch)) > 1.9e-3
    assert res["displacement.time"][-1] == pytest.approx(err.last_converged)
    assert np.allclose(np.diff(res["displacement.time"][:-1]), 0.05)
    assert res.stats["subdivisions"] >= 3


def test_integration_step_divides_the_record_step_with_linear_interpolation():
    model = connector_chain([1.0e4], [("linear-spring", {"k": 4.0e7})], [1.0e9])
    fine_t = 0.005 * np.arange(401)
    fine = np.zeros((fine_t.size, 3))
    fine[:, 0] = np.interp(fine_t, fine_t[::2], np.sin(7.0 * fine_t[::2]))  # piecewise linear at 0.01 s
    coarse = fine[::2]
    rec = [NodalResponse(["m1"], components=["ux"])]
    a = solve_transient(model, coarse, 0.01, settings=TransientSettings(dt_integration=0.005), recorders=rec)
    b = solve_transient(model, fine, 0.005, recorders=rec)
    assert a.time.size == b.time.size == 401
    assert rel_err(a["displacement"], b["displacement"]) < 1e-12
    with pytest.raises(ParameterError, match=r"'dt_integration' = 0.003 must divide"):
        solve_transient(model, coarse, 0.01, settings=TransientSettings(dt_integration=0.003))


def test_a_law_exception_keeps_the_partial_result(test_laws):
    """A law that raises (a bug, not non-convergence): the run stops with a TransientError that
    holds the result up to the last converged instant and the law's exception as its cause."""
    model = connector_chain([1.0e4], [("test-grumpy-spring", {"k": 2.0e7, "limit": 2e-3})], [1.0e9])
    t = 0.01 * np.arange(201)
    ag = np.zeros((t.size, 3))
    ag[:, 0] = 3.0 * t
    with pytest.raises(TransientError) as info:
        solve_transient(model, ag, 0.01, registry=test_laws, recorders=[ConnectorResponse()])
    err = info.value
    assert isinstance(err.__cause__, ValueError) and "test-grumpy-spring" in str(err.__cause__)
    assert "ValueError" in str(err) and f"results kept up to t = {err.last_converged:.6g} s" in str(err)
    assert 0 < err.last_converged <= err.time < 2.0 and np.isnan(err.residual) and err.connectors == ()
    res = err.result
    assert not res.completed and res.time[-1] == pytest.approx(err.last_converged)
    assert np.max(np.abs(res["connectors.law_displacement"][:, 0, 0])) <= 2e-3
    # a law state with a "slip" entry but no slip() member: no slip is reported
    assert np.all(np.isnan(res["connectors.slip"]))


def test_a_progress_callback_exception_keeps_the_partial_result():
    model = connector_chain([1.0e4], [("linear-spring", {"k": 4.0e7})], [1.0e9])
    ag = band_limited_noise(201, 0.01, seed=4, amplitude=[1.0, 0.0, 0.0])

    def progress(fraction):
        if fraction >= 0.5:
            raise KeyError("the display went away")

    with pytest.raises(TransientError) as info:
        solve_transient(model, ag, 0.01, progress=progress, recorders=[NodalResponse(["m1"], components=["ux"])])
    err = info.value
    assert isinstance(err.__cause__, KeyError)
    assert err.last_converged == pytest.approx(1.0) and err.result.time.size == 101
    assert err.result["displacement"].shape == (101, 1, 1)


def test_sparse_products_above_the_dense_threshold_agree_with_the_general_path():
    """A model above DENSE_BELOW free DOFs takes the sparse branch of the per-step products (and
    of the stacked [B; V] operator): the fast path still agrees with the general one."""
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}, per_span=10)
    pre = gravity(model)
    assert pre.system.n_free > hht.DENSE_BELOW
    ag = band_limited_noise(151, 0.01, seed=11, amplitude=[3.0, 2.5, 2.0])
    recorders = [ConnectorResponse(), NodalResponse(["GA10", "GB15"], "acceleration"), ElementForces(["GA3", "X10"])]
    runs = {
        path: solve_transient(
            model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208), recorders=recorders,
            settings=TransientSettings(path=path, tol_force=1e-10, tol_displacement=1e-12),
        )
        for path in ("fast", "general")
    }
    fast, general = runs["fast"], runs["general"]
    for key in fast.keys():
        assert rel_err(fast[key], general[key]) < (1e-7 if key.endswith("friction_ratio") else 1e-8), key
    assert np.nanmax(np.abs(fast["connectors.slip"])) > 1e-5
    assert fast.balance_error < 1e-8 and general.balance_error < 1e-8


def test_transient_from_a_preload_with_active_bearings():
    """``bearings="active"``: the laws carried the dead load (their state and forces are not zero
    at the start). At rest under zero excitation nothing moves; under shaking both paths agree."""
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    pre = gravity(model, bearings="active")
    assert np.max(np.abs(pre.law_forces)) > 1e3  # the start is a loaded state, not the virgin one
    rec = [ConnectorResponse(), NodalResponse(["GA4", "GB6"], components=["ux", "uy", "uz", "ry"])]
    rest = solve_transient(model, np.zeros((101, 3)), 0.01, preload=pre, recorders=rec)
    assert np.max(np.abs(rest["displacement"])) < 1e-12
    force = rest["connectors.force"]
    assert np.max(np.abs(force - force[0])) < 1e-9 * np.max(np.abs(force[0]))
    slip = rest["connectors.slip"]  # bearings that slid under the dead load sit on the yield surface:
    assert np.nanmax(np.abs(slip - slip[0])) < 1e-12 * np.nanmax(np.abs(slip))  # round-off only
    assert rest.stats["max_iterations"] <= 2 and rest.energy["input"][-1] == 0
    ag = band_limited_noise(151, 0.01, seed=11, amplitude=[3.0, 2.5, 2.0])
    runs = {
        path: solve_transient(
            model, ag, 0.01, preload=pre, recorders=rec,
            settings=TransientSettings(path=path, tol_force=1e-10, tol_displacement=1e-12),
        )
        for path in ("fast", "general")
    }
    for key in runs["fast"].keys():
        tol = 1e-7 if key.endswith("friction_ratio") else 1e-8
        assert rel_err(runs["fast"][key], runs["general"][key]) < tol, key
    assert np.nanmax(np.abs(runs["fast"]["connectors.slip"] - rest["connectors.slip"][0])) > 1e-5
