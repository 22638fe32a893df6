"""The regularized Coulomb law's shortcuts (every connector sticking, every connector sliding) give
the bits of its general return map: a connector's response does not depend on what the other
connectors of the same call do (issue 16: the kernel calls the law once for all its connectors)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bearingfw.laws import RegularizedCoulomb

K, MU = 4e8, 0.04


def _alone(law, slip, u, normal):
    """Each connector's response from a call with one more connector out of contact (``N < 0``),
    which takes the law through its general branch (selections per connector)."""
    out = []
    dims = u.shape[1]
    for i in range(u.shape[0]):
        if np.ndim(law.k) or np.ndim(law.mu):  # per-bearing parameters: the pair's own
            k = np.array([np.ravel(law.k)[i if np.ndim(law.k) else 0], K])
            mu = np.array([np.ravel(law.mu)[i if np.ndim(law.mu) else 0], MU])
            pair_law = RegularizedCoulomb(k=k, mu=mu, dims=dims)
        else:
            pair_law = law
        out.append(
            pair_law.respond(
                {"slip": np.vstack([slip[i : i + 1], np.zeros((1, dims))])},
                np.vstack([u[i : i + 1], np.full((1, dims), 1e-3)]),
                np.array([normal[i], -1.0]),
                0.01,
            )
        )
    return out


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(1, 6),
    dims=st.sampled_from([1, 2]),
    regime=st.sampled_from(["stick", "slide"]),
    per_bearing=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)
def test_all_stick_and_all_slide_give_the_bits_of_the_general_map(n, dims, regime, per_bearing, seed):
    rng = np.random.default_rng(seed)
    k = rng.uniform(1e8, 1e9, n) if per_bearing else K
    mu = rng.uniform(0.01, 0.1, n) if per_bearing else MU
    law = RegularizedCoulomb(k=k, mu=mu, dims=dims)
    slip = rng.normal(size=(n, dims)) * 1e-3
    normal = rng.uniform(1e5, 3e6, n)
    yield_u = (np.asarray(mu) * normal / np.asarray(k)).reshape(-1, 1) * np.ones((1, dims))
    direction = rng.normal(size=(n, dims))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    factor = rng.uniform(0.05, 0.6, (n, 1)) if regime == "stick" else rng.uniform(1.5, 30.0, (n, 1))
    u = slip + direction * factor * yield_u / np.sqrt(dims)
    together = law.respond({"slip": slip}, u, normal, 0.01)
    for i, pair in enumerate(_alone(law, slip, u, normal)):
        for field, a, b in (
            ("force", together.force[i], pair.force[0]),
            ("tangent", together.tangent[i], pair.tangent[0]),
            ("slip", together.state["slip"][i], pair.state["slip"][0]),
            ("dforce_dnormal", together.dforce_dnormal[i], pair.dforce_dnormal[0]),
        ):
            assert np.array_equal(a, b), (regime, field, i, a, b)
    sliding = np.linalg.norm(together.state["slip"] - slip, axis=1) > 0
    assert sliding.all() if regime == "slide" else not sliding.any()


@pytest.mark.parametrize("dims", [1, 2])
def test_all_sliding_tangent_and_dforce_dnormal_are_the_closed_forms(dims):
    """Every connector sliding (the shortcut): tangent ``k (mu N / |F_trial|) (I - n n^T)`` (zero in
    1-D) and ``dF/dN = mu n``, by hand."""
    law = RegularizedCoulomb(k=K, mu=MU, dims=dims)
    u = np.array([[3e-3, -1e-3][:dims], [-2e-3, 4e-3][:dims]])
    normal = np.array([1e6, 2e6])
    r = law.respond(law.initial_state(2), u, normal, 0.01)
    for i in range(2):
        trial = K * u[i]
        n = trial / np.linalg.norm(trial)
        expected = K * (MU * normal[i] / np.linalg.norm(trial)) * (np.eye(dims) - np.outer(n, n))
        np.testing.assert_allclose(r.tangent[i], expected, rtol=1e-14, atol=1e-6)
        np.testing.assert_allclose(r.force[i], MU * normal[i] * n, rtol=1e-14)
        np.testing.assert_allclose(r.dforce_dnormal[i], MU * n, rtol=1e-14)
        np.testing.assert_allclose(r.state["slip"][i], u[i] - MU * normal[i] * n / K, rtol=1e-12)
