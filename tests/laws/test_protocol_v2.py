"""The built-in laws on protocol v2: flags, per-bearing parameters, dF/dN, and no capacity means no force."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bearingfw import ParameterError, create_law
from bearingfw.laws import Fixed, Frictionless, LinearSpring, RegularizedCoulomb
from bearingfw.protocol import OPTIONAL_FLAGS, law_flag
from bearingfw.testing import displacement_paths, normal_force_histories, run_history

K, MU, N = 4e8, 0.04, 2e6
U_YIELD = MU * N / K


@pytest.mark.parametrize(
    "cls, declared",
    [
        (Frictionless, {"friction", "linear"}),
        (Fixed, set()),
        (LinearSpring, {"per_bearing", "linear"}),
        (RegularizedCoulomb, {"per_bearing", "friction", "normal_coupling"}),
    ],
)
def test_the_built_in_laws_declare_their_flags(cls, declared):
    assert {flag for flag in OPTIONAL_FLAGS if law_flag(cls, flag)} == declared


def coulomb_before_protocol_v2(law, state, u, normal_force):
    """The regularized-coulomb arithmetic as it was before per-bearing parameters and the mu = 0 fix."""
    slip = state["slip"]
    capacity = law.mu * np.maximum(np.asarray(normal_force, dtype=float), 0.0)
    trial = law.k * (u - slip)
    trial_norm = np.sqrt(np.einsum("ij,ij->i", trial, trial))
    sliding = trial_norm > capacity
    safe_norm = np.where(sliding, trial_norm, 1.0)
    scale = np.where(sliding, capacity / safe_norm, 1.0)
    force = trial * scale[:, None]
    new_slip = np.where(sliding[:, None], u - force / law.k, slip)
    direction = trial / safe_norm[:, None]
    projector = np.eye(law.dims) - sliding[:, None, None] * np.einsum("ij,ik->ijk", direction, direction)
    return force, law.k * scale[:, None, None] * projector, new_slip


@given(dims=st.sampled_from([1, 2]), mu=st.floats(1e-3, 0.9), k=st.floats(1e6, 1e10), data=st.data())
def test_coulomb_with_friction_capacity_is_bit_identical_to_before(dims, mu, k, data):
    law = RegularizedCoulomb(k=k, mu=mu, dims=dims)
    path = data.draw(displacement_paths(dims, mu * N / k, max_steps=30))
    normal = data.draw(normal_force_histories(len(path), 1e3, 5e6))
    state = law.initial_state(1)
    for u, n in zip(path, normal):
        response = law.respond(state, u[None, :], np.array([n]), 0.01)
        force, tangent, slip = coulomb_before_protocol_v2(law, state, u[None, :], np.array([n]))
        np.testing.assert_array_equal(response.force, force)
        np.testing.assert_array_equal(response.tangent, tangent)
        np.testing.assert_array_equal(response.state["slip"], slip)
        state = response.state


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize("mu, normal", [(0.0, N), (MU, 0.0), (MU, -5e5)])
def test_without_friction_capacity_force_and_tangent_are_zero_even_at_the_slip_point(dims, mu, normal):
    """mu = 0 or N <= 0: the force is identically zero, so its tangent is zero too, also at u = u_p."""
    law = RegularizedCoulomb(k=K, mu=mu, dims=dims)
    state = law.initial_state(2)
    u = np.zeros((2, dims))
    u[1, 0] = 3e-3
    response = law.respond(state, u, np.full(2, normal), 0.01)
    np.testing.assert_array_equal(response.force, np.zeros((2, dims)))
    np.testing.assert_array_equal(response.tangent, np.zeros((2, dims, dims)))
    np.testing.assert_array_equal(response.dforce_dnormal, np.zeros((2, dims)))
    assert np.all(np.isfinite(response.state["slip"]))
    # and the finite-difference tangent at u = 0 is zero as well
    step = 1e-7
    ahead = law.respond(state, u + step, np.full(2, normal), 0.01).force
    np.testing.assert_array_equal(ahead, np.zeros((2, dims)))


def test_the_tangent_at_the_origin_is_still_k_when_there_is_capacity():
    law = RegularizedCoulomb(k=K, mu=MU, dims=2)
    response = law.respond(law.initial_state(1), np.zeros((1, 2)), np.array([N]), 0.01)
    np.testing.assert_array_equal(response.tangent[0], K * np.eye(2))


def force_of(law, state, u, normal):
    return law.respond(state, u, normal, 0.01).force


@given(
    dims=st.sampled_from([1, 2]),
    mu=st.floats(0.01, 0.6),
    ratio=st.floats(0.0, 4.0),  # |trial force| / (mu N): stick below 1, slip above
    angle=st.floats(0.0, 2 * np.pi),
    slip=st.floats(-5e-3, 5e-3),
    normal=st.floats(1e4, 5e6),
)
def test_dforce_dnormal_matches_finite_differences(dims, mu, ratio, angle, slip, normal):
    law = RegularizedCoulomb(k=K, mu=mu, dims=dims)
    h = 1e-6 * normal
    # Away from the stick/slip boundary both N +- h fall on the same branch, on which F is affine in N:
    # the central difference is then exact up to round-off.
    if abs(ratio - 1.0) * normal <= 4 * h:
        return
    direction = np.array([np.cos(angle), np.sin(angle)])[:dims] if dims == 2 else np.array([1.0 if angle < np.pi else -1.0])
    state = {"slip": np.full((1, dims), slip)}
    u = state["slip"] + ratio * mu * normal / K * direction[None, :]
    response = law.respond(state, u, np.array([normal]), 0.01)
    difference = (force_of(law, state, u, np.array([normal + h])) - force_of(law, state, u, np.array([normal - h]))) / (2 * h)
    np.testing.assert_allclose(response.dforce_dnormal, difference, rtol=1e-6, atol=1e-9 * mu)
    # mu n in slip (n carries the round-off of u - u_p, small next to a large slip u_p), zero in stick
    expected = mu * direction[None, :] if ratio > 1 else np.zeros((1, dims))
    np.testing.assert_allclose(response.dforce_dnormal, expected, rtol=0, atol=1e-9 * mu)


def test_dforce_dnormal_in_1d_slip_is_mu_times_the_sign():
    law = RegularizedCoulomb(k=K, mu=MU)
    u = np.array([[3 * U_YIELD], [-3 * U_YIELD], [0.5 * U_YIELD]])
    response = law.respond(law.initial_state(3), u, np.full(3, N), 0.01)
    np.testing.assert_array_equal(response.dforce_dnormal, [[MU], [-MU], [0.0]])


@pytest.mark.parametrize("dims", [1, 2])
@given(data=st.data())
def test_coulomb_with_per_bearing_arrays_equals_separate_laws(dims, data):
    n = 3
    k = np.array(data.draw(st.lists(st.floats(1e7, 1e9), min_size=n, max_size=n)))
    mu = np.array(data.draw(st.lists(st.floats(0.0, 0.5), min_size=n, max_size=n)))
    normal = np.array(data.draw(st.lists(st.floats(-1e5, 4e6), min_size=n, max_size=n)))
    path = data.draw(displacement_paths(dims, 1e-3, n=n, max_steps=12))
    steps = len(path)
    together = RegularizedCoulomb(k=k, mu=mu, dims=dims)
    forces, tangents, state = run_history(together, path, np.tile(normal, (steps, 1)), n=n)
    for i in range(n):
        alone = RegularizedCoulomb(k=k[i], mu=mu[i], dims=dims)
        f, t, s = run_history(alone, path[:, i : i + 1], np.full((steps, 1), normal[i]), n=1)
        np.testing.assert_array_equal(forces[:, i], f[:, 0])
        np.testing.assert_array_equal(tangents[:, i], t[:, 0])
        np.testing.assert_array_equal(state["slip"][i], s["slip"][0])


def test_linear_spring_with_per_bearing_stiffness():
    law = create_law("linear-spring", k=[1e8, 2e8, 4e8], dims=2)
    u = np.array([[1e-3, -1e-3], [2e-3, 0.0], [0.0, 5e-4]])
    response = law.respond(law.initial_state(3), u, np.zeros(3), 0.01)
    np.testing.assert_array_equal(response.force, [[1e5, -1e5], [4e5, 0.0], [0.0, 2e5]])
    np.testing.assert_array_equal(response.tangent, [k * np.eye(2) for k in (1e8, 2e8, 4e8)])
    # a scalar gives the same bits as one value per connector
    scalar = create_law("linear-spring", k=2e8, dims=2).respond({}, u, np.zeros(3), 0.01)
    same = create_law("linear-spring", k=[2e8] * 3, dims=2).respond({}, u, np.zeros(3), 0.01)
    np.testing.assert_array_equal(scalar.force, same.force)
    np.testing.assert_array_equal(scalar.tangent, same.tangent)


@pytest.mark.parametrize("name, params", [("linear-spring", {"k": [1e8, 2e8]}), ("regularized-coulomb", {"k": 4e8, "mu": [0.02, 0.04]})])
def test_a_per_bearing_array_of_the_wrong_length_is_refused_by_name(name, params):
    law = create_law(name, **params)
    field = "mu" if "mu" in params else "k"
    message = f"{name}: parameter '{field}' holds 2 per-bearing values but the law was called for 3 connector"
    with pytest.raises(ParameterError, match=message):
        law.respond(law.initial_state(2), np.zeros((3, 1)), np.ones(3), 0.01)
    with pytest.raises(ParameterError, match=message):
        law.initial_state(3)


def test_a_per_bearing_value_outside_the_range_names_its_index():
    with pytest.raises(ParameterError, match=r"'mu'\[1\] = 1.5 is outside the allowed range 0 <= mu < 1"):
        create_law("regularized-coulomb", k=4e8, mu=[0.04, 1.5])
