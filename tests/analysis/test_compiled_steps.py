"""Runs of steps in one compiled call (:mod:`bearingfw.analysis.hht_steps`, issue 16) against the
time loop stepping through :func:`bearingfw.analysis.hht.step`: every recorded array, the energy
table and the statistics, for each kind of run it takes (no laws, linear laws folded, compiled
laws with Newton), with step halvings, failed runs, and a recorder that stops a run."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import band_limited_noise, cantilever_model, deck_model, with_uplift

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
from bearingfw.model import build_system

DT = 0.005
COULOMB = {"k": 4e8, "mu": 0.04}

CASES = {
    "no-laws": (lambda: cantilever_model(), "NO_LAWS"),
    "folded": (lambda: deck_model("linear-spring", {"k": 4e8}), "FOLDED"),
    "frictionless": (lambda: deck_model("frictionless"), "FOLDED"),
    "coulomb": (lambda: deck_model("regularized-coulomb", COULOMB), "NEWTON"),
    "uplift": (lambda: with_uplift(deck_model("regularized-coulomb", COULOMB)), "NEWTON"),
}


def _recorders(model, every: int = 1):
    recorders = [NodalResponse([model.nodes[-1].name], "acceleration", name="tip", every=every)]
    elements = [e.name for e in model.elements][:2]
    recorders.append(ElementForces(elements, name="forces", every=every))
    if model.connectors:
        recorders.append(ConnectorResponse(name="bearings", every=every))
    return recorders


def _run(model, ag, compiled: bool, monkeypatch, settings=None, every: int = 1, recorders=None, alpha=None):
    """``solve_transient`` with the compiled steps on or off; also how many steps went through ``hht.step``."""
    monkeypatch.setattr(hht, "COMPILED_STEPS", compiled)
    step, calls = hht.step, []

    def counted(*args, **kwargs):
        calls.append(1)
        return step(*args, **kwargs)

    monkeypatch.setattr(hht, "step", counted)
    system = build_system(model)
    settings = settings or TransientSettings(alpha=-0.05 if alpha is None else alpha)
    result = solve_transient(
        system, ag, DT, preload=gravity(system), damping=Rayleigh(0.21, 0.00208), settings=settings,
        recorders=_recorders(model, every) if recorders is None else recorders,
    )  # fmt: skip
    return result, len(calls)


def _same(a, b, rel: float) -> None:
    """Equal results: arrays to ``rel`` of their largest value (0: bit for bit), statistics exactly."""
    assert sorted(a.keys()) == sorted(b.keys())
    for key in a.keys():
        x, y = np.asarray(a[key], dtype=float), np.asarray(b[key], dtype=float)
        assert x.shape == y.shape, key
        scale = np.nanmax(np.abs(y), initial=0.0)
        assert np.array_equal(np.isnan(x), np.isnan(y)), key
        assert np.nanmax(np.abs(x - y), initial=0.0) <= rel * scale, (key, np.nanmax(np.abs(x - y)) / scale)
    scale = np.max(np.abs(b.energy["input"]), initial=0.0)  # the imbalance is round-off of the others
    for column in a.energy:
        assert np.max(np.abs(a.energy[column] - b.energy[column]), initial=0.0) <= rel * scale, column
    for key in ("steps", "substeps", "subdivisions", "iterations", "max_iterations", "failed_iterations", "backtracks"):
        assert a.stats[key] == b.stats[key], key
    assert a.uplift == b.uplift or rel > 0


@pytest.mark.parametrize("alpha", [0.0, -0.05], ids=["alpha0", "alpha-0.05"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_compiled_steps_give_the_steps_of_the_python_loop(case, alpha, monkeypatch):
    """Folded linear laws compute ``phi = K_l (d - d_0)`` as a loop where numpy calls BLAS: round-off
    apart (1e-12), every other run is the same bit for bit. The compiled run really ran: no step
    went through ``hht.step``."""
    make, mode = CASES[case]
    model = make()
    ag = band_limited_noise(301, DT, seed=7, amplitude=[6.0, 4.0, 14.0 if case == "uplift" else 3.0])
    python, python_steps = _run(model, ag, False, monkeypatch, alpha=alpha)
    compiled, compiled_steps = _run(model, ag, True, monkeypatch, alpha=alpha)
    assert python_steps == 300 and compiled_steps == 0
    _same(compiled, python, 0.0 if mode == "NEWTON" else 1e-12)
    assert compiled.stats["balance_error"] < 1e-9
    if case == "uplift":
        assert any(v["lift_offs"] for v in python.uplift.values())  # a gap opened
        assert compiled.uplift == python.uplift


def test_each_case_runs_in_the_mode_it_is_named_for(monkeypatch):
    from bearingfw.analysis import hht_steps
    from bearingfw.analysis.transient import build_problem

    for case, (make, mode) in CASES.items():
        system = build_system(make())
        pre = gravity(system)
        p = build_problem(system, pre, Rayleigh(0.21, 0.00208), TransientSettings())
        plan = hht.steps_plan(p, hht.build_operator(p, DT))
        assert plan is not None and plan.mode == getattr(hht_steps, mode), case


def test_a_step_the_compiled_run_cannot_finish_is_halved_as_before(monkeypatch):
    """One Newton iteration allowed: the compiled run stops at each step that needs more, the Python
    step halves it, and the compiled steps go on; the run is the Python loop's, bit for bit."""
    model = deck_model("regularized-coulomb", COULOMB)
    ag = band_limited_noise(201, DT, seed=3, amplitude=[6.0, 4.0, 3.0])
    settings = TransientSettings(max_iterations=2)
    python, python_steps = _run(model, ag, False, monkeypatch, settings=settings)
    compiled, through_step = _run(model, ag, True, monkeypatch, settings=settings)
    assert python.stats["subdivisions"] > 5 and 0 < through_step < python_steps
    _same(compiled, python, 0.0)


def test_a_run_that_fails_fails_at_the_same_step_with_the_same_partial_result(monkeypatch):
    model = deck_model("regularized-coulomb", COULOMB)
    ag = band_limited_noise(201, DT, seed=3, amplitude=[6.0, 4.0, 3.0])
    settings = TransientSettings(max_iterations=2, max_halvings=0)
    errors = []
    for compiled in (False, True):
        with pytest.raises(TransientError) as info:
            _run(model, ag, compiled, monkeypatch, settings=settings)
        errors.append(info.value)
    python, compiled = errors
    assert compiled.time == python.time and compiled.last_converged == python.last_converged > 0
    assert str(compiled) == str(python)
    _same(compiled.result, python.result, 0.0)


class _Stopping(ElementStress):
    """A stress recorder that raises the first time it samples past ``t = 0.4`` s (mid-way through a
    compiled call); then it samples again, so that the run keeps a partial result."""

    def bind(self, ctx):
        probe = super().bind(ctx)
        sample, raised = probe.sample, []

        def stopping(s):
            if s.t > 0.4 and not raised:
                raised.append(s.t)
                raise RuntimeError("recorder stopped")
            sample(s)

        probe.sample = stopping
        return probe


def test_a_recorder_that_raises_stops_the_run_where_the_python_loop_stops(monkeypatch):
    model = deck_model("regularized-coulomb", COULOMB)
    ag = band_limited_noise(201, DT, seed=3, amplitude=[6.0, 4.0, 3.0])
    errors = []
    for compiled in (False, True):
        recorders = [ConnectorResponse(name="bearings"), _Stopping(["GA0"], name="stress")]
        with pytest.raises(TransientError, match="recorder stopped") as info:
            _run(model, ag, compiled, monkeypatch, recorders=recorders)
        errors.append(info.value)
    python, compiled = errors
    assert compiled.time == python.time and compiled.last_converged == python.last_converged
    assert str(compiled) == str(python)
    assert compiled.result is not None and python.result is not None
    _same(compiled.result, python.result, 0.0)


def test_thinned_recorders_and_progress_are_those_of_the_python_loop(monkeypatch):
    model = deck_model("regularized-coulomb", COULOMB)
    ag = band_limited_noise(251, DT, seed=5, amplitude=[6.0, 4.0, 3.0])
    runs = []
    for compiled in (False, True):
        reported = []
        monkeypatch.setattr(hht, "COMPILED_STEPS", compiled)
        system = build_system(model)
        result = solve_transient(system, ag, DT, recorders=_recorders(model, every=7), progress=reported.append)
        runs.append((result, reported))
    (python, python_progress), (compiled, compiled_progress) = runs
    assert compiled_progress == python_progress and len(python_progress) == 100
    assert python["tip.time"].size == 250 // 7 + 1
    _same(compiled, python, 0.0)


@pytest.mark.parametrize("nodal", [False, True], ids=["ground", "ground+nodal"])
def test_the_loads_of_a_run_of_steps_are_those_of_each_instant(nodal):
    """``Excitation.loads`` (array operations) gives, bit for bit, ``load(t)`` at each time: at the
    samples, between them (sub-steps), before the start and past the end."""
    from bearingfw.analysis.excitation import build_excitation

    model = deck_model("regularized-coulomb", COULOMB)
    system = build_system(model)
    ag = band_limited_noise(41, 0.01, seed=2, amplitude=[6.0, 4.0, 3.0])
    loads = None
    if nodal:
        loads = np.zeros(system.n_dof)
        loads[::7] = 1e3
    exc = build_excitation(system, ag, 0.01, loads, preload=gravity(system))
    times = [-0.01, 0.0, 0.0025, 0.005, 0.01, 0.0175, 0.2, 0.3999, 0.4, 0.45]
    rows = exc.loads(times)
    assert rows.shape == (len(times), system.n_free)
    for t, row in zip(times, rows, strict=True):
        assert np.array_equal(row, exc.load(t)), t
    assert np.abs(rows).max() > 0


def test_an_error_inside_a_compiled_run_leaves_the_steps_to_python(monkeypatch):
    """Whatever a compiled run raises, the Python steps solve those steps (and report an error at
    the step where it happens): the run is the Python loop's."""
    model = deck_model("regularized-coulomb", COULOMB)
    ag = band_limited_noise(121, DT, seed=4, amplitude=[6.0, 4.0, 3.0])
    python, _ = _run(model, ag, False, monkeypatch)
    calls = []

    def broken(*args, **kwargs):
        calls.append(1)
        raise FloatingPointError("inside the compiled run")

    monkeypatch.setattr(hht, "advance_steps", broken)
    compiled, through_step = _run(model, ag, True, monkeypatch)
    assert calls and through_step == 120
    _same(compiled, python, 0.0)


def test_each_state_of_a_compiled_run_has_its_own_arrays(monkeypatch):
    """A recorder that keeps every k-th state keeps that state's arrays only, not the whole run of steps."""
    from bearingfw.analysis.transient import build_problem

    system = build_system(deck_model("regularized-coulomb", COULOMB))
    pre = gravity(system)
    p = build_problem(system, pre, Rayleigh(0.21, 0.00208), TransientSettings())
    plan = hht.steps_plan(p, hht.build_operator(p, DT))
    n = p.M.shape[0]
    start = hht.initial_state(p, tuple(pre.law_states), np.zeros(n), np.zeros(n))
    times = [DT * (k + 1) for k in range(6)]
    loads = np.random.default_rng(1).normal(size=(6, n)) * 1e5
    states, _, _ = hht.advance_steps(plan, start, times, loads)
    assert len(states) == 6
    for a, b in zip(states, states[1:]):
        for field in ("x", "v", "a", "ae", "products"):
            assert not np.shares_memory(getattr(a, field), getattr(b, field)), field
    assert states[2].x.base is None or states[2].x.base.size <= 14 * n  # one step's rows
