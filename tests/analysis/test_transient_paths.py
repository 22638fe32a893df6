"""Fast (condensed) and general (full Newton) paths, step subdivision, failure, integration step."""

from __future__ import annotations

import importlib.metadata as metadata
import sys
import types

import numpy as np
import pytest
from kernel_models import deck_model
from transient_models import BrittleSpring, LyingSpring, band_limited_noise, connector_chain, rel_err

import bearingfw
from bearingfw.analysis import (
    ConnectorResponse,
    ElementForces,
    ElementStress,
    NodalResponse,
    Rayleigh,
    TransientError,
    TransientSettings,
    gravity,
    solve_transient,
)
from bearingfw.parameters import ParameterError
from bearingfw.plugins import load_registry


@pytest.fixture(scope="module")
def test_laws():
    """The installed plugins plus a test plugin with the two test-only laws."""
    module = types.ModuleType("bearingfw_transient_test_plugin")

    @bearingfw.hookimpl
    def bearingfw_register_laws():
        return [LyingSpring, BrittleSpring]

    module.bearingfw_register_laws = bearingfw_register_laws
    sys.modules[module.__name__] = module
    eps = list(metadata.entry_points(group="bearingfw"))
    eps.append(metadata.EntryPoint(name="transient-test-laws", value=module.__name__, group="bearingfw"))
    try:
        yield load_registry(eps)
    finally:
        sys.modules.pop(module.__name__, None)


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
    assert fast.energy_error < 0.05  # alpha = -0.05 dissipates some of this broadband input numerically
    assert fast.stats["max_iterations"] > 2


def test_friction_deck_energy_balance_with_average_acceleration(friction_deck):
    model, pre, ag = friction_deck
    res = solve_transient(
        model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208), settings=TransientSettings(alpha=0.0)
    )
    assert res.energy_error < 1e-6
    assert res.energy["bearings"][-1] > 0.05 * res.energy["input"][-1]


def test_a_step_that_does_not_converge_is_halved_and_gives_the_small_step_answer(test_laws):
    """A zero reported tangent makes Newton a fixed-point iteration with contraction
    (1 + alpha) k beta h^2 / m: 2.1 at h = 0.01 s (diverges), 0.52 at h / 2 (converges)."""
    model = connector_chain([1.0e4], [("test-lying-spring", {"k": 8.0e8})], [1.0e9])
    honest = connector_chain([1.0e4], [("linear-spring", {"k": 8.0e8})], [1.0e9])
    ag = band_limited_noise(101, 0.01, seed=3, amplitude=[2.0, 0.0, 0.0])
    rec = [NodalResponse(["m1"], components=["ux"])]
    settings = TransientSettings(alpha=0.0, max_iterations=60)
    lying = solve_transient(model, ag, 0.01, settings=settings, recorders=rec, registry=test_laws)
    assert lying.stats["subdivisions"] == 100 and lying.stats["substeps"] == 200
    fine = solve_transient(
        honest, ag, 0.01, settings=TransientSettings(alpha=0.0, dt_integration=0.005), recorders=rec
    )
    assert lying.time.size == 101  # recorded at the nominal steps only
    assert rel_err(lying["displacement"], fine["displacement"][::2]) < 1e-7
    # the energy is accumulated over the sub-steps: with alpha = 0 the balance stays exact
    assert lying.energy_error < 1e-6


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
