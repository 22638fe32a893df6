"""What a step reuses instead of recomputing (issue 16), checked against recomputing it: the
predictor's LU factors (those of the last Newton correction of the step before) and the sparse
products made through scipy's kernel directly; both must give the same bits."""

from __future__ import annotations

import attrs
import numpy as np
import pytest
import scipy.sparse as sp
from kernel_models import band_limited_noise, deck_model

from bearingfw.analysis import ConnectorResponse, Rayleigh, TransientSettings, gravity, hht, solve_transient
from bearingfw.laws.elastic import LinearSpring


@pytest.mark.parametrize("fmt", ["csr", "csc"])
def test_direct_sparse_products_are_scipys_bits(fmt):
    rng = np.random.default_rng(4)
    A = sp.random(300, 250, density=0.03, random_state=5, format=fmt)
    fast = hht._Sparse(A)
    for _ in range(5):
        x = rng.normal(size=250) * 10.0 ** rng.integers(-6, 6)
        assert np.array_equal(fast @ x, A @ x)
    X = rng.normal(size=(250, 3))  # not a vector: the matrix's own product
    assert np.array_equal(fast @ X, A @ X)
    assert np.array_equal(fast @ np.arange(250), A @ np.arange(250))  # integers: likewise
    with pytest.raises(ValueError):
        fast @ np.ones(7)  # a wrong length still fails as scipy fails


def _run(model, ag, strip: bool, counter: list):
    """The run, optionally with the state's factors withheld from every step (so the predictor
    factorises its matrix again); ``counter`` collects how often the factors were reused."""
    step, solve_factored = hht.step, hht._solve_factored

    def counted_solve(factors, g):
        counter.append(1)
        return solve_factored(factors, g)

    def stripped(p, op, s, *args, **kwargs):
        return step(p, op, attrs.evolve(s, jacobian=None), *args, **kwargs)

    hht._solve_factored = counted_solve
    if strip:
        hht.step = stripped
    try:
        pre = gravity(model)
        return solve_transient(
            model, ag, 0.01, preload=pre, damping=Rayleigh(0.21, 0.00208), recorders=[ConnectorResponse()],
            settings=TransientSettings(dt_integration=0.005),
        )
    finally:
        hht.step, hht._solve_factored = step, solve_factored


@pytest.mark.parametrize(
    "model",
    [
        deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}),  # every spring coupled
        deck_model("linear-spring", {"k": 4e8}),  # no coupling
    ],
    ids=["coulomb", "spring"],
)
def test_the_predictor_reusing_the_last_factors_equals_factorising_again(model, monkeypatch):
    # the spring through Newton, as a nonlinear law without dF/dN goes (declared linear, it is folded into
    # the factorised matrix and no predictor runs: tests/analysis/test_linear_laws.py)
    monkeypatch.setattr(LinearSpring, "linear", False)
    # the Python iteration's reuse (the compiled one's: tests/analysis/test_compiled_newton.py)
    monkeypatch.setattr(hht, "COMPILED_NEWTON", False)
    ag = band_limited_noise(121, 0.01, seed=7, amplitude=[4.0, 3.0, 2.0])
    reused, fresh = [], []
    a = _run(model, ag, False, reused)
    b = _run(model, ag, True, fresh)
    assert len(reused) > 100 and not fresh  # the factors were reused, and only in the first run
    for key in a.keys():
        assert np.array_equal(a[key], b[key], equal_nan=True), key
    assert a.stats["iterations"] == b.stats["iterations"]
    for column in a.energy:
        assert np.array_equal(a.energy[column], b.energy[column]), column


def test_factors_of_another_step_size_are_not_reused(monkeypatch):
    """After a halved step the operator differs: the predictor must not solve with the factors of
    the other step size (the state names the operator they belong to)."""
    monkeypatch.setattr(hht, "COMPILED_NEWTON", False)  # the Python iteration's factors
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    pre = gravity(model)
    from bearingfw.analysis.transient import build_problem

    p = build_problem(pre.system, pre, Rayleigh(0.21, 0.00208), TransientSettings())
    op_h, op_half = hht.build_operator(p, 0.01), hht.build_operator(p, 0.005)
    n = p.M.shape[0]
    s = hht.initial_state(p, tuple(pre.law_states), np.zeros(n), np.zeros(n))
    load = np.random.default_rng(1).normal(size=n) * 1e5
    s, _, _ = hht.step(p, op_h, s, 0.01, load)
    s, _, _ = hht.step(p, op_h, s, 0.02, load)
    assert s.jacobian is not None and s.jacobian[0] is op_h
    assert hht._factors_for(s, op_h) is not None
    assert hht._factors_for(s, op_half) is None
    # tangents other than those the factors were formed from (a state edited by hand): not reused
    assert hht._factors_for(attrs.evolve(s, tangents=list(s.tangents)), op_h) is None
