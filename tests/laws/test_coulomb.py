"""Regularized Coulomb friction: the properties that make it the paper's M2."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bearingfw import ParameterError, create_law
from bearingfw.laws import RegularizedCoulomb
from bearingfw.testing import displacement_paths, drive, law_parameters, normal_force_histories, run_history

K, MU, N = 4e8, 0.04, 2e6  # the paper's tuned bearing: K_s = 400 MN/m, mu = 0.04
U_YIELD = MU * N / K


def elastic_perfectly_plastic(u, k, yield_force):
    """Reference: the textbook incremental EPP spring (force updated by increments, then clipped)."""
    force, previous, out = 0.0, 0.0, []
    for x in u:
        force = float(np.clip(force + k * (x - previous), -yield_force, yield_force))
        previous = x
        out.append(force)
    return np.array(out)


@given(params=law_parameters(RegularizedCoulomb, dims=1), normal=st.floats(1e4, 5e6), data=st.data())
def test_1d_with_constant_normal_force_is_an_elastic_perfectly_plastic_spring(params, normal, data):
    law = RegularizedCoulomb(**params)
    path = data.draw(displacement_paths(1, max(params["mu"], 1e-3) * normal / params["k"]))[:, 0]
    expected = elastic_perfectly_plastic(path, params["k"], params["mu"] * normal)
    # The law stores the slip, so its elastic part u - u_p carries the round-off of u itself.
    roundoff = 8 * np.finfo(float).eps * params["k"] * np.max(np.abs(path))
    np.testing.assert_allclose(drive(law, path, normal), expected, rtol=1e-9, atol=1e-9 * params["mu"] * normal + roundoff)


@given(path=displacement_paths(2, U_YIELD, max_steps=40), data=st.data())
def test_2d_force_stays_on_or_inside_the_circle_and_slip_follows_the_force(path, data):
    law = RegularizedCoulomb(k=K, mu=MU, dims=2)
    normal = data.draw(normal_force_histories(len(path), 1e5, 4e6))
    state = law.initial_state(1)
    for u, n in zip(path, normal):
        response = law.respond(state, u[None, :], np.array([n]), 0.01)
        force = response.force[0]
        assert np.linalg.norm(force) <= MU * n * (1 + 1e-12)
        slip_increment = response.state["slip"][0] - state["slip"][0]
        # The increment is a difference of slips, exact only to the round-off of u: judge it
        # where it stands clear of that.
        if np.linalg.norm(slip_increment) > 1e-9 * max(np.max(np.abs(path)), U_YIELD):
            # Associated rule: the slip grows along the friction force, on the circle.
            cross = force[0] * slip_increment[1] - force[1] * slip_increment[0]
            assert abs(cross) <= 1e-6 * np.linalg.norm(force) * np.linalg.norm(slip_increment)
            assert force @ slip_increment > 0
            assert np.linalg.norm(force) == pytest.approx(MU * n, rel=1e-12)
        state = response.state


@given(path=displacement_paths(2, U_YIELD), fraction=st.floats(0.0, 0.999))
def test_stick_response_is_exactly_k_u(path, fraction):
    """Below the friction circle from the virgin state the bearing is a linear spring, to the bit."""
    peak = np.max(np.linalg.norm(path, axis=1))
    path = path * (fraction * U_YIELD / peak) if peak > 0 else path
    law = RegularizedCoulomb(k=K, mu=MU, dims=2)
    np.testing.assert_array_equal(drive(law, path, N), K * path)


def test_zero_normal_force_means_no_friction_capacity():
    law = RegularizedCoulomb(k=K, mu=MU, dims=2)
    u = np.array([[1e-3, -2e-3], [5e-3, 1e-3]])
    forces, tangents, state = run_history(law, u, 0.0)
    assert np.all(forces == 0) and np.all(tangents == 0)
    np.testing.assert_array_equal(state["slip"][0], u[-1])


def test_uplift_is_treated_as_no_contact():
    law = RegularizedCoulomb(k=K, mu=MU)
    np.testing.assert_array_equal(drive(law, [1e-3, 2e-3], normal_force=[-1e5, -1e5]), [0.0, 0.0])


def test_a_drop_in_normal_force_returns_the_force_to_the_smaller_circle():
    law = RegularizedCoulomb(k=K, mu=MU)
    forces = drive(law, [0.1 * U_YIELD, 0.1 * U_YIELD], normal_force=[N, 0.01 * N])
    assert forces[0] == pytest.approx(0.1 * MU * N)
    assert forces[1] == pytest.approx(0.01 * MU * N)


def test_2d_motion_along_one_axis_equals_the_1d_law():
    path = U_YIELD * np.array([0.5, 2.0, 3.0, 1.0, -2.5, -4.0, 0.0])
    one = drive(RegularizedCoulomb(k=K, mu=MU), path, N)
    two = drive(RegularizedCoulomb(k=K, mu=MU, dims=2), np.stack([path, np.zeros_like(path)], axis=1), N)
    np.testing.assert_allclose(two[:, 0], one, rtol=1e-14)
    assert np.all(two[:, 1] == 0)


def test_slip_tangent_is_the_tangential_projector_scaled_by_the_return():
    law = RegularizedCoulomb(k=K, mu=MU, dims=2)
    u = np.array([[3 * U_YIELD, 4 * U_YIELD]])  # trial force 5 mu N along (0.6, 0.8)
    response = law.respond(law.initial_state(1), u, np.array([N]), 0.01)
    direction = np.array([0.6, 0.8])
    np.testing.assert_allclose(response.force[0], MU * N * direction)
    expected = K / 5 * (np.eye(2) - np.outer(direction, direction))
    np.testing.assert_allclose(response.tangent[0], expected, rtol=1e-12, atol=1e-6)


@pytest.mark.parametrize(
    "params, message",
    [
        ({"k": 0.0, "mu": 0.04}, r"'k' = 0.0 is outside the allowed range k > 0"),
        ({"k": 4e8, "mu": 1.0}, r"'mu' = 1.0 is outside the allowed range 0 <= mu < 1"),
        ({"k": 4e8, "mu": -0.01}, r"0 <= mu < 1"),
        ({"k": float("nan"), "mu": 0.04}, r"'k' = nan is outside"),
        ({"k": float("inf"), "mu": 0.04}, r"'k' = inf is outside"),
        # k is a per-bearing parameter: one real number, or a 1-D array of them
        ({"k": "400e6", "mu": 0.04}, r"'k' must be a real number or a 1-D array of real numbers \(one per bearing\) "
                                     r"\(k > 0\), got str"),
        ({"k": True, "mu": 0.04}, r"'k' must be a real number"),
        ({"k": 4e8}, r"missing parameter\(s\) 'mu' \(0 <= mu < 1\)"),
        ({"k": 4e8, "mu": 0.04, "muu": 0.1}, r"unknown parameter\(s\) 'muu'; parameters of regularized-coulomb: k, mu, dims"),
        ({"k": 4e8, "mu": 0.04, "dims": 3}, r"'dims' must be 1 or 2"),
    ],
)
def test_bad_parameters_name_the_parameter_and_the_range(params, message):
    with pytest.raises(ParameterError, match=message):
        create_law("regularized-coulomb", **params)


def test_integer_and_numpy_parameters_are_accepted_as_floats():
    law = create_law("regularized-coulomb", k=np.int64(400_000_000), mu=np.float32(0.04))
    assert isinstance(law.k, float) and law.k == 4e8


def test_slip_is_the_plastic_part_of_the_displacement():
    law = RegularizedCoulomb(k=K, mu=MU)
    _, _, state = run_history(law, [[[3 * U_YIELD]]], N)
    np.testing.assert_allclose(law.slip(state), [[2 * U_YIELD]])
