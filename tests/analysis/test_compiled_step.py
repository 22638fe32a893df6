"""The compiled arithmetic of a step (:mod:`bearingfw.analysis.hht_kernels`) against the same
formulas written in numpy, and the compiled back-substitution against SuperLU's."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from bearingfw.analysis import hht, hht_kernels
from bearingfw.analysis.energy import Energy, accumulate


def _close(a, b, rel=1e-13):
    a, b = np.asarray(a), np.asarray(b)
    scale = max(float(np.max(np.abs(b))), 1e-300)
    assert np.max(np.abs(a - b)) <= rel * scale, np.max(np.abs(a - b)) / scale


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("symmetric", [True, False])
def test_back_substitution_is_superlus_solve(seed, symmetric):
    rng = np.random.default_rng(seed)
    n = 60 + 40 * seed
    A = sp.random(n, n, density=0.05, random_state=seed, format="csc")
    A = A + A.T if symmetric else A
    A = (A + sp.diags(rng.uniform(0.5, 2.0, n) * (1.0 + abs(A).sum(axis=1).A1))).tocsc()  # non-singular
    factors = hht.factor(A)
    assert factors._compiled
    for _ in range(3):
        b = rng.normal(size=n)
        x = factors.solve(b)
        _close(x, factors.lu.solve(b))
        _close(A @ x, b, rel=1e-12)
    # several right-hand sides (and anything but a contiguous float vector) go to SuperLU itself
    B = rng.normal(size=(n, 3))
    np.testing.assert_array_equal(factors.solve(B), factors.lu.solve(B))


def test_a_wrong_permutation_would_be_seen():
    """The check above can fail: the same factors with ``perm_c`` applied the other way round."""
    rng = np.random.default_rng(5)
    n = 80
    A = (sp.random(n, n, density=0.05, random_state=5) + sp.eye(n) * 4.0).tocsc()
    factors = hht.factor(A)
    arrays = list(factors._arrays)
    arrays[7] = np.argsort(arrays[7]).astype(np.uint32)
    b = rng.normal(size=n)
    out = np.empty(n)
    hht_kernels.back_substitute(*arrays, b, out)
    assert not np.allclose(out, factors.lu.solve(b), rtol=1e-6)


def _csr(A):
    A = sp.csr_matrix(A)
    return A.indptr.astype(np.uint32), A.indices.astype(np.uint32), A.data.astype(float)


@pytest.mark.parametrize("alpha", [0.0, -0.05, -0.3])
@pytest.mark.parametrize("bearings", [True, False])
def test_predict_and_commit_are_the_numpy_formulas(alpha, bearings):
    rng = np.random.default_rng(7)
    n, m, h = 50, 6, 0.005
    beta, gamma = (1 - alpha) ** 2 / 4, 0.5 - alpha
    M = sp.random(n, n, density=0.1, random_state=1) + sp.eye(n)
    K = sp.random(n, n, density=0.1, random_state=2) + sp.eye(n) * 3
    Bt = sp.random(n, m, density=0.2, random_state=3)
    vec = lambda: rng.normal(size=n)  # noqa: E731
    xva_n, products_n = rng.normal(size=(3, n)), rng.normal(size=(2, 3, n))
    T = hht._predictors(hht.Scheme(alpha), h)
    weights = rng.normal(size=6)
    load_n, load1, Bt_phi_n = vec(), vec(), vec()

    out = np.empty((3, n))
    hht_kernels.predict(xva_n, products_n, T, weights, load1, load_n, Bt_phi_n, 1 + alpha, alpha, out)
    xt, vt = T @ xva_n
    r = weights @ products_n.reshape(6, -1) + (1 + alpha) * load1 - alpha * load_n + alpha * Bt_phi_n
    _close(out[0], r)
    _close(out[1], xt)
    _close(out[2], vt)

    x, phi = vec(), rng.normal(size=m)
    Cv_n, Ma_n, G_n, rho_n, ae_n = vec(), vec(), vec(), vec(), vec()
    a0, a1 = 0.3, 0.002
    rows, terms = np.empty((hht_kernels.ROWS, n)), np.empty(7)
    hht_kernels.commit(
        x, xt, vt, xva_n, products_n, T, *_csr(sp.vstack([M, K])), *_csr(Bt), phi, bearings,
        load_n, load1, Cv_n, Ma_n, Bt_phi_n, G_n, rho_n, ae_n, beta * h * h, gamma * h, a0, a1, alpha, rows, terms,
    )  # fmt: skip
    a = (x - xt) / (beta * h * h)
    v = vt + a * gamma * h
    Mx, Kx = M @ x, K @ x
    (Mxt, Mvt), (Kxt, Kvt) = T @ products_n[0], T @ products_n[1]
    Ma, Ka = (Mx - Mxt) / (beta * h * h), (Kx - Kxt) / (beta * h * h)
    Mv, Kv = Mvt + Ma * gamma * h, Kvt + Ka * gamma * h
    Bt_phi = Bt @ phi if bearings else Bt_phi_n
    Cv = a0 * Mv + a1 * Kv
    G = Cv + Kx + Bt_phi - load1
    rho = -alpha * (G - G_n)
    ae = (a + alpha * ae_n) / (1 + alpha)
    for got, want in zip(rows, [x, v, a, Mx, Mv, Ma, Kx, Kv, Ka, Bt_phi, Cv, G, rho, ae], strict=True):
        _close(got, want, rel=1e-12)
    dx = x - xva_n[0]
    trap = lambda f0, f1: 0.5 * dx @ (f0 + f1)  # noqa: E731
    want = [0.5 * v @ Mv, 0.5 * x @ Kx, trap(Cv_n, Cv), trap(Bt_phi_n, Bt_phi), trap(load_n, load1), trap(Ma_n, Ma), trap(rho_n, rho)]
    _close(terms, want, rel=1e-12)
    # and the energy they make
    before = Energy(kinetic=1.0, strain=2.0, damping=3.0, bearings=4.0, input=5.0, numerical=6.0)
    after = accumulate(before, terms.tolist())
    assert after.kinetic == terms[0] and after.strain == terms[1]
    assert after.damping == pytest.approx(3.0 + want[2], rel=1e-12)
    assert after.numerical == pytest.approx(6.0 + want[5] - (want[0] - 1.0) - want[6], rel=1e-12)


def test_a_law_answering_with_read_only_arrays_runs_as_with_writable_ones(monkeypatch):
    """A law may answer with shared, frozen arrays; the compiled kernels type those apart, so the
    step hands them over writable (bearingfw.jit.kernel_array): the run is the same to the bit."""
    from bearingfw.laws.coulomb import RegularizedCoulomb

    model = _planar_deck()
    writable = _run(model, seed=3, steps=81)
    respond = RegularizedCoulomb.respond

    def frozen(self, *args, **kwargs):
        response = respond(self, *args, **kwargs)
        for array in (response.force, response.tangent, response.dforce_dnormal):
            array.setflags(write=False)
        return response

    monkeypatch.setattr(RegularizedCoulomb, "respond", frozen)
    read_only = _run(model, seed=3, steps=81)
    assert read_only.completed and writable.stats["iterations"] > 0
    for key in writable.keys():
        assert np.array_equal(writable[key], read_only[key], equal_nan=True), key


def test_factors_refuse_a_vector_of_another_size_and_take_a_read_only_one():
    A = (sp.random(50, 50, density=0.1, random_state=2) + sp.eye(50) * 5.0).tocsc()
    factors = hht.factor(A)
    for n in (49, 51):
        with pytest.raises(ValueError):
            factors.solve(np.ones(n))
    b = np.linspace(0.0, 1.0, 50)
    b.setflags(write=False)
    _close(factors.solve(b), factors.lu.solve(b))


def _planar_deck():
    """The kernel tests' deck with every sliding bearing planar: one law group, whose arrays the
    step takes as they come."""
    import attrs
    from kernel_models import deck_model

    from bearingfw.analysis import gravity

    deck = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    model = attrs.evolve(deck, connectors=[attrs.evolve(c, kind="planar", guided=None) if c.law else c for c in deck.connectors])
    assert len(gravity(model).system.connectors.groups) == 1
    return model


def _run(model, seed: int, steps: int, bearings: str = "set-after-dead-load"):
    from kernel_models import band_limited_noise

    from bearingfw.analysis import ConnectorResponse, Rayleigh, TransientSettings, gravity, solve_transient

    ag = band_limited_noise(steps, 0.01, seed=seed, amplitude=[4.0, 3.0, 2.0])
    return solve_transient(
        model, ag, 0.01, preload=gravity(model, bearings=bearings), damping=Rayleigh(0.21, 0.00208),
        recorders=[ConnectorResponse()], settings=TransientSettings(dt_integration=0.005),
    )  # fmt: skip


@pytest.mark.parametrize("answer", ["strided", "frozen"])
@pytest.mark.parametrize("bearings", ["set-after-dead-load", "active"])
def test_a_law_answering_with_strided_or_frozen_arrays_runs_as_with_plain_ones(answer, bearings, monkeypatch):
    """The law protocol asks for arrays of a shape, not a layout: a view of a wider work array, or a
    frozen array (also as the preload's law forces, with bearings active under the dead load)."""
    from bearingfw.laws.coulomb import RegularizedCoulomb
    from bearingfw.protocol import LawResponse

    model = _planar_deck()

    plain = _run(model, seed=5, steps=61, bearings=bearings)
    respond = RegularizedCoulomb.respond

    def odd(self, *args, **kwargs):
        r = respond(self, *args, **kwargs)
        if answer == "frozen":
            for array in (r.force, r.tangent, r.dforce_dnormal):
                array.setflags(write=False)
            return r
        n, dims = r.force.shape
        work = np.zeros((n, 2 * dims))  # the force a column view of a wider array
        work[:, :dims] = r.force
        tangent = np.zeros((n, dims, 2 * dims))
        tangent[:, :, :dims] = r.tangent
        return LawResponse(work[:, :dims], tangent[:, :, :dims], r.state, dforce_dnormal=r.dforce_dnormal)

    monkeypatch.setattr(RegularizedCoulomb, "respond", odd)
    other = _run(model, seed=5, steps=61, bearings=bearings)
    assert other.completed and plain.stats["iterations"] > 0
    for key in plain.keys():
        assert np.array_equal(plain[key], other[key], equal_nan=True), key


def test_factors_too_large_to_copy_are_solved_by_superlu(monkeypatch):
    A = (sp.random(40, 40, density=0.1, random_state=4) + sp.eye(40) * 5.0).tocsc()
    monkeypatch.setattr(hht.Factors, "MAX_COPIED", 10)
    factors = hht.factor(A)
    assert not factors._compiled
    b = np.linspace(1.0, 2.0, 40)
    np.testing.assert_array_equal(factors.solve(b), factors.lu.solve(b))
