import numpy as np
import pytest

import bearingfw
from bearingfw.testing import check_law


@pytest.mark.parametrize("dims", [1, 2])
def test_the_damper_conforms(dims):
    check_law(bearingfw.create_law("viscous-damper", c=2e6, dims=dims))


def test_the_force_is_c_times_the_velocity_the_kernel_gives():
    law = bearingfw.create_law("viscous-damper", c=2e6, dims=2)
    velocity = np.array([[0.1, -0.2], [0.0, 0.3]])
    response = law.respond(law.initial_state(2), np.full((2, 2), 0.05), np.zeros(2), 0.01, velocity=velocity)
    np.testing.assert_array_equal(response.force, 2e6 * velocity)
    # no stiffness at fixed velocity; d force / d velocity = c I, which the kernel scales by dv/du
    np.testing.assert_array_equal(response.tangent, np.zeros((2, 2, 2)))
    np.testing.assert_array_equal(response.dforce_dvelocity, np.broadcast_to(2e6 * np.eye(2), (2, 2, 2)))


def test_without_a_velocity_the_damper_is_at_rest():
    law = bearingfw.create_law("viscous-damper", c=2e6)
    response = law.respond(law.initial_state(1), np.array([[0.01]]), np.zeros(1), 0.01)
    np.testing.assert_array_equal(response.force, [[0.0]])


def test_one_law_object_serves_dampers_of_different_coefficients():
    law = bearingfw.create_law("viscous-damper", c=[1e6, 3e6])
    response = law.respond(law.initial_state(2), np.zeros((2, 1)), np.zeros(2), 0.01, velocity=np.array([[0.2], [0.2]]))
    np.testing.assert_array_equal(response.force, [[2e5], [6e5]])
    with pytest.raises(bearingfw.ParameterError, match="'c' holds 2 per-bearing values but the law was called for 3"):
        law.respond({}, np.zeros((3, 1)), np.zeros(3), 0.01)


def test_a_bad_coefficient_names_the_parameter_and_its_range():
    with pytest.raises(bearingfw.ParameterError, match=r"'c' = -1.0 is outside the allowed range c > 0"):
        bearingfw.create_law("viscous-damper", c=-1.0)
