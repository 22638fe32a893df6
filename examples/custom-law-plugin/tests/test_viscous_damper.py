import numpy as np
import pytest

import bearingfw
from bearingfw.testing import check_law, drive


@pytest.mark.parametrize("dims", [1, 2])
def test_the_damper_conforms(dims):
    check_law(bearingfw.create_law("viscous-damper", c=2e6, dims=dims))


def test_the_force_is_c_times_the_step_velocity():
    law = bearingfw.create_law("viscous-damper", c=2e6)
    np.testing.assert_allclose(drive(law, [0.001, 0.003, 0.003], dt=0.01), [2e6 * 0.1, 2e6 * 0.2, 0.0])
