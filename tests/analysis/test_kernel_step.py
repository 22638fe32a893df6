"""The kernel step's bookkeeping (issue 16): the products it carries instead of recomputing them,
the predictor with dF/dN, and a law response of the wrong shape stopping a run with the law's name."""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np
import pytest
from kernel_models import band_limited_noise, deck_model, friction_oscillator, registry_with

import bearingfw
from bearingfw.analysis import Rayleigh, TransientError, TransientSettings, gravity, hht, solve_transient
from bearingfw.analysis.transient import build_problem
from bearingfw.model import ModelError


def test_the_carried_products_are_m_and_k_times_the_state():
    """``State.products`` (M and K times x, v, a, updated from one sparse product per step) equal the
    fresh products after 150 steps of a sliding deck, to round-off."""
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    pre = gravity(model)
    p = build_problem(pre.system, pre, Rayleigh(0.3, 0.002), TransientSettings())
    op = hht.build_operator(p, 0.01)
    s = hht.initial_state(p, tuple(pre.law_states), np.zeros(p.M.shape[0]), np.zeros(p.M.shape[0]))
    rng_load = np.random.default_rng(0).normal(size=(150, p.M.shape[0])) * 1e4
    for n in range(150):
        s, _, _ = hht.step(p, op, s, 0.01 * (n + 1), rng_load[n])
    for k, (A, name) in enumerate(((p.M, "M"), (p.K, "K"))):
        for j, q in enumerate((s.x, s.v, s.a)):
            fresh = A @ q
            assert np.max(np.abs(s.products[k, j] - fresh)) <= 1e-9 * np.max(np.abs(fresh)), (name, j)
    assert np.max(np.abs(s.x)) > 1e-4  # it moved


def _iterations(model, ag, dt, strip_coupling: bool):
    """Newton iterations per step of a run, optionally with the predictor's dF/dN withheld."""
    original, counts = hht.step, []

    def counted(p, op, s, *args, **kwargs):
        if strip_coupling:
            s = attrs.evolve(s, coupling=None)
        state, iterations, backtracks = original(p, op, s, *args, **kwargs)
        counts.append(iterations)
        return state, iterations, backtracks

    compiled_steps = hht.COMPILED_STEPS
    hht.step, hht.COMPILED_STEPS = counted, False  # every step through hht.step, which is counted here
    try:
        res = solve_transient(model, ag, dt, recorders=[bearingfw.analysis.ConnectorResponse(["friction"])])
    finally:
        hht.step, hht.COMPILED_STEPS = original, compiled_steps
    return np.array(counts), res


def test_a_bearing_sliding_under_a_changing_normal_force_converges_at_its_first_law_call():
    """A 1-D friction bearing kept sliding while the vertical shaking changes its normal force: the
    predictor with dF/dN is exact for it, so the sliding steps take one law call instead of two;
    the response is the same to the Newton tolerance."""
    model = friction_oscillator(1e5, 1e6, 1e9, 0.1)
    t = 0.005 * np.arange(801)
    ag = np.zeros((t.size, 3))
    ag[:, 0] = 6.0 * np.sin(2 * np.pi * 1.0 * t)  # far above mu g: slides most of each cycle
    ag[:, 2] = 3.0 * np.sin(2 * np.pi * 3.3 * t)
    with_e, res = _iterations(model, ag, 0.005, strip_coupling=False)
    without_e, ref = _iterations(model, ag, 0.005, strip_coupling=True)
    slip = res["connectors.slip"][:, 0, 0]
    sliding = np.abs(np.diff(slip)) > 1e-9
    assert sliding.mean() > 0.5
    assert np.mean(with_e[sliding] == 1) > 0.8 and np.mean(without_e[sliding] == 1) < 0.2
    assert with_e.sum() < 0.8 * without_e.sum()
    scale = np.max(np.abs(ref["connectors.force"]))
    assert np.max(np.abs(res["connectors.force"] - ref["connectors.force"])) <= 1e-7 * scale


@attrs.frozen
class FlatForce:
    """A test-only law with a bug: its force has one column whatever ``dims``."""

    name: ClassVar[str] = "test-flat-force"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        tangent = self.k * np.broadcast_to(np.eye(self.dims), (u.shape[0], self.dims, self.dims)).copy()
        return bearingfw.LawResponse(self.k * u.sum(axis=1), tangent, state)


def test_a_law_returning_a_wrong_shape_stops_the_run_with_its_name():
    with registry_with([FlatForce], "test-flat", "bfw_test_flat_force") as registry:
        model = deck_model("test-flat-force", {"k": 4e8})
        ag = band_limited_noise(11, 0.01, seed=1, amplitude=[1.0, 1.0, 0.5])
        with pytest.raises((TransientError, ModelError)) as info:
            solve_transient(model, ag, 0.01, registry=registry)
    assert "law 'test-flat-force'" in str(info.value) and "'force' of shape" in str(info.value)
