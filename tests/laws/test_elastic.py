"""Frictionless, fixed and linear-spring laws."""

import numpy as np
import pytest
from hypothesis import given

from bearingfw import ParameterError, create_law
from bearingfw.testing import displacement_paths, drive


@given(path=displacement_paths(2, 1e-2))
def test_frictionless_never_resists(path):
    law = create_law("frictionless", dims=2)
    np.testing.assert_array_equal(drive(law, path, 1e6), np.zeros_like(path))


@given(path=displacement_paths(2, 1e-2))
def test_linear_spring_is_k_u(path):
    law = create_law("linear-spring", k=4e8, dims=2)
    np.testing.assert_array_equal(drive(law, path), 4e8 * path)
    tangent = law.respond(law.initial_state(3), np.ones((3, 2)), np.ones(3), 0.01).tangent
    np.testing.assert_array_equal(tangent, np.broadcast_to(4e8 * np.eye(2), (3, 2, 2)))


def test_fixed_is_rigid_and_cannot_be_driven():
    law = create_law("fixed", dims=2)
    assert law.rigid is True
    with pytest.raises(TypeError, match="rigid"):
        drive(law, np.zeros((3, 2)))
    with pytest.raises(TypeError, match="ties its directions"):
        law.respond(law.initial_state(1), np.zeros((1, 2)), np.ones(1), 0.01)


def test_linear_spring_rejects_a_non_positive_stiffness():
    with pytest.raises(ParameterError, match=r"'k' = -1.0 is outside the allowed range k > 0"):
        create_law("linear-spring", k=-1)
