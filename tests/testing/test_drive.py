import numpy as np
import pytest

from bearingfw import create_law
from bearingfw.testing import drive


def test_drive_keeps_the_shape_of_u_and_commits_every_step():
    law = create_law("regularized-coulomb", k=1.0, mu=0.5)
    # Yield force 0.5 with N = 1: load to 2, unload to 0 leaves -0.5 (plastic set of 1.5).
    forces = drive(law, [1.0, 2.0, 0.0])
    np.testing.assert_allclose(forces, [0.5, 0.5, -0.5])
    two = drive(create_law("linear-spring", k=2.0, dims=2), np.ones((4, 2)))
    assert two.shape == (4, 2)


def test_drive_takes_one_normal_force_per_step():
    law = create_law("regularized-coulomb", k=1.0, mu=0.5)
    np.testing.assert_allclose(drive(law, [3.0, 6.0, 12.0], normal_force=[1.0, 2.0, 4.0]), [0.5, 1.0, 2.0])


def test_drive_rejects_a_rigid_law_and_bad_shapes():
    with pytest.raises(TypeError, match="'fixed' is rigid"):
        drive(create_law("fixed"), [0.0, 1.0])
    with pytest.raises(ValueError, match=r"a 2-D law 'linear-spring' takes \(steps, 2\)"):
        drive(create_law("linear-spring", k=1.0, dims=2), [0.0, 1.0])
    with pytest.raises(ValueError, match="normal_force has shape"):
        drive(create_law("linear-spring", k=1.0), [0.0, 1.0], normal_force=[1.0, 2.0, 3.0])
