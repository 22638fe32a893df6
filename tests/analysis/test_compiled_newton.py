"""The fast path's compiled Newton iteration (:mod:`bearingfw.analysis.hht_newton`, issue 16)
against the Python iteration it replaces, on the cases that take different branches of it: every
spring coupled, some coupled (a linear spring beside a friction bearing), uplift gaps, per-bearing
parameters, differential support motion. Also: it really runs (no Python law call per step), a
law whose compiled function declines falls back to the Python iteration, and the predictor's
reused factors give the bits of factorising again."""

from __future__ import annotations

import attrs
import numpy as np
import pytest
from kernel_models import band_limited_noise, connector_chain, deck_model, friction_oscillator, with_uplift

from bearingfw.analysis import ConnectorResponse, ElementForces, Rayleigh, gravity, hht, solve_transient
from bearingfw.analysis.excitation import SupportMotion, support_groups
from bearingfw.jit import DECLINED, law_kernel
from bearingfw.laws.coulomb import RegularizedCoulomb
from bearingfw.model import build_system

DT = 0.005


def _per_bearing(model):
    """The deck with a different friction coefficient on every sliding bearing (one law object, arrays)."""
    connectors = []
    for k, c in enumerate(model.connectors):
        if c.kind != "join":
            c = attrs.evolve(c, law_params={"k": 4e8, "mu": 0.03 + 0.005 * k})
        connectors.append(c)
    return attrs.evolve(model, connectors=tuple(connectors))


def _delayed(system, ag):
    groups = support_groups(system)
    delayed = {}
    for k, g in enumerate(groups):  # the wave reaches group k after 3 k steps
        delayed[g] = np.zeros_like(ag)
        delayed[g][3 * k :] = ag[: ag.shape[0] - 3 * k]
    return SupportMotion(groups, delayed, baseline="none")


COULOMB = {"k": 4e8, "mu": 0.04}
CASES = {
    # every spring coupled (AXIAL and PLANAR groups, a JOIN bearing)
    "deck": lambda: (build_system(deck_model("regularized-coulomb", COULOMB)), [6.0, 4.0, 3.0]),
    # vertical shaking beyond g: the gaps open and close
    "uplift": lambda: (build_system(with_uplift(deck_model("regularized-coulomb", COULOMB))), [5.0, 3.0, 14.0]),
    "per-bearing": lambda: (build_system(_per_bearing(deck_model("regularized-coulomb", COULOMB))), [6.0, 4.0, 3.0]),
    # a plugin's compiled law (no dF/dN: N follows the law forces, linearised)
    "bouc-wen": lambda: (
        build_system(deck_model("bouc-wen", {"k": 4e8, "alpha": 0.05, "uy": 2e-4, "A": 1.0, "beta": 0.5, "gamma": 0.5, "n": 2.0})),
        [6.0, 4.0, 3.0],
    ),
    # a plugin's friction law with N in its stiffness too (dF/dN in stick and in slip)
    "pendulum": lambda: (
        build_system(deck_model("friction-pendulum", {"k": 4e8, "R": 2.24, "mu": 0.05})), [6.0, 4.0, 3.0],
    ),
    "lead-rubber": lambda: (
        build_system(deck_model("elastomeric-plasticity", {"k": 1.5e7, "qd": 1.5e5, "alpha": 0.1})), [4.0, 3.0, 2.0],
    ),
    # many bearing directions (52): a larger reduced system
    "large": lambda: (
        build_system(connector_chain([2e4] * 52, [("regularized-coulomb", {"k": 4e8, "mu": 0.05 + 0.002 * (k % 7)})
                                                  for k in range(52)], 1e9)),
        [6.0, 0.0, 3.0],
    ),
    # a linear spring (not folded: the run has a nonlinear law) beside a friction bearing: some springs coupled
    "partly-coupled": lambda: (build_system(friction_oscillator(1e5, 1e6, 1e9, 0.1)), [8.0, 0.0, 4.0]),
}


def _run(system, ground, compiled: bool, monkeypatch, counter: list | None = None):
    monkeypatch.setattr(hht, "COMPILED_NEWTON", compiled)
    python = hht._solve_fast_python

    def counted(*args, **kwargs):
        if counter is not None:
            counter.append(1)
        return python(*args, **kwargs)

    monkeypatch.setattr(hht, "_solve_fast_python", counted)
    names = [e.name for e in system.model.elements][:2]
    recorders = [ConnectorResponse(name="b")] + ([ElementForces(names, name="s")] if names else [])
    return solve_transient(system, ground, DT, preload=gravity(system), damping=Rayleigh(0.21, 0.00208), recorders=recorders)


def _compare(a, b, rel=1e-7):
    """The Newton tolerance bounds how far two converged iterations may differ (1e-8 of the motion)."""
    for key in ("b.force", "b.displacement", "b.normal_force", "s"):
        if key not in b.keys():
            continue
        scale = np.nanmax(np.abs(b[key]))
        assert scale > 0, key
        assert np.nanmax(np.abs(a[key] - b[key])) <= rel * scale, (key, np.nanmax(np.abs(a[key] - b[key])) / scale)


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_compiled_iteration_gives_the_python_iterations_response(case, monkeypatch):
    plugin = {"bouc-wen": "bearingfw_boucwen", "pendulum": "bearingfw_pendulum", "lead-rubber": "bearingfw_elastomeric"}
    if case in plugin:
        pytest.importorskip(plugin[case])
    system, amplitude = CASES[case]()
    ag = band_limited_noise(401, DT, seed=11, amplitude=amplitude)
    python_calls, compiled_calls = [], []
    reference = _run(system, ag, False, monkeypatch, python_calls)
    compiled = _run(system, ag, True, monkeypatch, compiled_calls)
    assert len(python_calls) >= 400 and not compiled_calls  # each ran its own iteration
    slip = np.nanmax(np.abs(np.diff(reference["b.slip"], axis=0))) if "b.slip" in reference.keys() else 1.0
    assert slip > 1e-6  # the bearings slid: Newton had work to do
    _compare(compiled, reference)
    assert abs(compiled.stats["iterations"] - reference.stats["iterations"]) <= 0.05 * reference.stats["iterations"]
    assert compiled.stats["balance_error"] < 1e-8
    if case == "uplift":
        assert np.nanmin(reference["b.normal_force"]) <= 0.0  # a gap opened


def test_the_compiled_iteration_under_differential_support_motion(monkeypatch):
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    motion = _delayed(system, band_limited_noise(301, DT, seed=5, amplitude=[6.0, 4.0, 2.0]))
    calls = []
    reference = _run(system, motion, False, monkeypatch)
    compiled = _run(system, motion, True, monkeypatch, calls)
    assert not calls
    _compare(compiled, reference)


@law_kernel
def _declining(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    return DECLINED


@law_kernel
def _raising(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    raise ValueError("boom")  # numba prints it and the function returns 0


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")  # the exception numba printed
@pytest.mark.parametrize("function", [_declining, _raising], ids=["declines", "raises"])
def test_a_compiled_law_that_does_not_answer_is_solved_in_python(function, monkeypatch):
    """Every step falls back to the Python iteration, and the run is the Python run, bit for bit. An
    exception cannot leave a C-callable function: it returns 0, which is not ANSWERED, so the
    half-written answer is never used."""
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    ag = band_limited_noise(151, DT, seed=3, amplitude=[6.0, 4.0, 3.0])
    reference = _run(system, ag, False, monkeypatch)
    compiled = RegularizedCoulomb.compiled
    monkeypatch.setattr(RegularizedCoulomb, "compiled", lambda self, n: attrs.evolve(compiled(self, n), function=function))
    calls = []
    fallen_back = _run(system, ag, True, monkeypatch, calls)
    assert len(calls) >= 150
    for key in reference.keys():
        assert np.array_equal(reference[key], fallen_back[key], equal_nan=True), key


@pytest.mark.parametrize(
    "broken",
    [
        lambda self, n: 1 / 0,  # compiled() raises
        lambda self, n: "not a compiled law",
        lambda self, n: attrs.evolve(COMPILED(self, n), pack=lambda state: np.zeros(1)),  # a state of the wrong size
    ],
    ids=["raises", "wrong-type", "wrong-state-size"],
)
def test_a_law_whose_compiled_function_cannot_be_used_runs_in_python_with_a_warning(broken, monkeypatch):
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    ag = band_limited_noise(101, DT, seed=3, amplitude=[6.0, 4.0, 3.0])
    reference = _run(system, ag, False, monkeypatch)
    monkeypatch.setattr(RegularizedCoulomb, "compiled", broken)
    with pytest.warns(RuntimeWarning, match="regularized-coulomb.*compiled function cannot be used"):
        result = _run(system, ag, True, monkeypatch)
    for key in reference.keys():
        assert np.array_equal(reference[key], result[key], equal_nan=True), key


COMPILED = RegularizedCoulomb.compiled


def test_a_run_with_a_law_without_a_compiled_function_runs_in_python(monkeypatch):
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    monkeypatch.delattr(RegularizedCoulomb, "compiled")
    p, _ = _problem(system)
    assert p.compiled is None


def _problem(system):
    pre = gravity(system)
    from bearingfw.analysis.transient import TransientSettings, build_problem

    return build_problem(pre.system, pre, Rayleigh(0.21, 0.00208), TransientSettings()), pre


def test_the_predictors_reused_factors_are_those_of_factorising_again(monkeypatch):
    """The compiled predictor solves with the last correction's LU factors when its matrix is that
    one; withholding them (so that it factorises the same matrix again) changes no bit."""
    monkeypatch.setattr(hht, "COMPILED_NEWTON", True)
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    p, pre = _problem(system)
    assert p.compiled is not None
    op = hht.build_operator(p, DT)
    n = p.M.shape[0]
    loads = np.random.default_rng(2).normal(size=(120, n)) * 3e5
    runs = []
    for strip in (False, True):
        s = hht.initial_state(p, tuple(pre.law_states), np.zeros(n), np.zeros(n))
        reused = 0
        for k in range(120):
            if s.jacobian is not None and s.jacobian[0] == "reduced" and s.jacobian[1] is op:
                reused += 1
                if strip:  # the same matrix, factorised again: its factors dropped
                    s = attrs.evolve(s, jacobian=s.jacobian[:1] + (None,) + s.jacobian[2:])
            s, _, _ = hht.step(p, op, s, DT * (k + 1), loads[k])
        runs.append(s)
        assert reused > 100
    assert np.array_equal(runs[0].x, runs[1].x) and np.array_equal(runs[0].f, runs[1].f)
