"""Static equilibrium with active friction bearings (``bearings="active"``) under gravity.

A friction law has no capacity, so zero force and tangent, without contact: at the undeformed
geometry every ``N`` is zero. Newton must still find the equilibrium in which each bearing sticks
below ``mu N`` or slides at ``mu N``, with ``N`` following the vertical springs.
"""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import deck_model

from bearingfw.analysis import gravity
from bearingfw.bridges import reference_bridge

TOL = 1e-10  # solve_static's default tolerance


def check_equilibrium(res):
    """Recompute the laws from their virgin state at the solution: the free-DOF residual is within the
    static tolerance, the reactions carry the weight, and every bearing is in contact and sticks below
    ``mu N`` or slides at it. Returns whether each friction bearing slides."""
    system = res.system
    ops = system.connectors
    N = ops.normal_forces(ops.V @ res.u)
    responses = ops.respond(ops.initial_states(), ops.B @ res.u, N, 1.0)
    f_law = ops.forces(responses)
    np.testing.assert_allclose(f_law, res.law_forces, rtol=0, atol=1e-12 * np.abs(f_law).max())
    residual = system.K_free @ res.q + system.B_free.T @ f_law - system.T.T @ res.load
    scale = np.abs(res.load).sum() + np.abs(f_law).sum()
    assert np.abs(residual).max() <= TOL * scale
    weight = -res.load[2::6].sum()
    assert res.reaction_resultant()[2] == pytest.approx(weight, rel=1e-9)
    sliding = []
    for g, r in zip(ops.groups, responses, strict=True):
        force = np.linalg.norm(np.asarray(r.force).reshape(g.n, g.dims), axis=1)
        capacity = np.broadcast_to(np.asarray(g.law.mu, dtype=float), (g.n,)) * N[g.springs]
        assert np.all(N[g.springs] > 0)
        assert np.all(force <= capacity * (1 + 1e-12))
        sliding.append(force >= capacity * (1 - 1e-9))
    return np.concatenate(sliding)


def test_reference_bridge_m2_with_active_bearings_reaches_equilibrium():
    """Regression: Newton started from the load carried with every friction bearing free (zero tangent
    at N = 0) and cycled between slip patterns (50 iterations, residual 1.4e6 N of 4.7e7 N)."""
    model = reference_bridge("M2")
    res = gravity(model, bearings="active")
    assert res.bearings == "active"
    assert res.iterations <= 8
    assert {g.law.name for g in res.system.connectors.groups} == {"regularized-coulomb"}
    # the girder ends' dead-load movements make some of the bearings slide
    sliding = check_equilibrium(res)
    assert 0 < sliding.sum() < sliding.size


def test_deck_on_friction_bearings_converges_in_few_iterations():
    """A two-span deck on regularized-Coulomb bearings (mu = 0.01: the dead-load end movements slide
    several of them) converges in a few iterations; before, Newton cycled and gave up after 50."""
    res = gravity(deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.01}), bearings="active")
    assert res.iterations <= 5
    sliding = check_equilibrium(res)
    assert sliding.any()
    assert any(np.any(s["slip"]) for s in res.law_states)


@pytest.mark.parametrize("mu", [0.005, 0.02, 0.04, 0.1])
@pytest.mark.parametrize("k", [4e7, 4e8, 4e9])
def test_deck_on_friction_bearings_over_a_range_of_parameters(k, mu):
    res = gravity(deck_model("regularized-coulomb", {"k": k, "mu": mu}), bearings="active")
    assert res.iterations <= 8
    check_equilibrium(res)
