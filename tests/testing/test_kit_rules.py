"""The rules of the conformance kit: how derivatives at kinks are judged, determinism, scales,
the strategies it draws from, and how a law's own exceptions are reported."""

import numpy as np
import pytest
from broken_laws import COULOMB, VELOCITY, Coulomb, Damper, VelocityFriction
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bearingfw import LawResponse, create_law
from bearingfw.testing import (
    ConformanceError,
    check_law,
    contact_force_histories,
    drive,
    histories,
    path_velocities,
    per_bearing_laws,
)
from bearingfw.testing.conformance import _derivative_check, make_context, yield_displacement
from bearingfw.testing.strategies import unit_arrays

once = settings(max_examples=40, derandomize=True, database=None, deadline=None, suppress_health_check=list(HealthCheck))


# --- derivatives at kinks -----------------------------------------------------------------------


def absolute(x):
    return np.abs(x)


@pytest.mark.parametrize("claimed", [1.0, -1.0, 0.0, 0.3], ids=["forward", "backward", "mean", "between"])
def test_at_a_kink_either_one_sided_derivative_or_anything_between_passes(claimed):
    assert _derivative_check(absolute, np.array([0.0]), np.array([[claimed]]), 1.0, 1.0) is None


@pytest.mark.parametrize("claimed", [1.5, -1.2, 2.0])
def test_at_a_kink_a_slope_outside_the_one_sided_ones_fails(claimed):
    assert _derivative_check(absolute, np.array([0.0]), np.array([[claimed]]), 1.0, 1.0) is not None


@pytest.mark.parametrize("offset", [1e-12, 3e-9, 5e-7, 1.5e-6])
def test_a_kink_next_to_the_point_is_judged_from_the_other_side(offset):
    """|x - offset| at x = 0: slope -1 there, while the stencils of some step sizes straddle the kink.
    A kink closer than the shortest step (1e-8 of the scale) counts as one at the point: there
    the other side's slope passes too; farther away it fails."""
    shifted = lambda x: np.abs(x - offset)  # noqa: E731
    assert _derivative_check(shifted, np.array([0.0]), np.array([[-1.0]]), 1.0, 1.0) is None
    wrong_side = _derivative_check(shifted, np.array([0.0]), np.array([[1.0]]), 1.0, 1.0)
    if offset < 1e-11 or offset > 1e-7:
        assert (wrong_side is None) == (offset < 1e-11)


def test_a_strongly_curved_side_is_judged_with_shorter_steps():
    """exp(x / 1e-4) at x = 0.02 with steps relative to |x|: the first step (2e-8) errs by 1e-5
    relative even with second-order differences; the shorter ones do not (the bouc-wen draw of issue 14)."""
    curved = lambda x: 1e-4 * np.exp((x - 0.02) / 1e-4) * (x <= 0.02) + (x - 0.02 + 1e-4) * (x > 0.02)  # noqa: E731
    assert _derivative_check(curved, np.array([0.02]), np.array([[1.0]]), 1e-3, 1.0) is None


def test_a_wrong_smooth_derivative_fails_and_reports_the_central_difference():
    cubic = lambda x: x**3  # noqa: E731
    wrong = _derivative_check(cubic, np.array([2.0]), np.array([[11.0]]), 1.0, 12.0)
    assert wrong is not None and wrong[0] == 0 and wrong[1][0] == pytest.approx(12.0, rel=1e-8)


# --- determinism ----------------------------------------------------------------------------------


def test_a_verdict_is_the_same_on_every_run():
    """Derandomized by default: the same examples, so the same failing input and message."""
    from broken_laws import ElasticTangentInSlip

    messages = set()
    for _ in range(2):
        with pytest.raises(ConformanceError) as caught:
            check_law(ElasticTangentInSlip(dims=2, **COULOMB), max_examples=10, shrink=False)
        messages.add(str(caught.value).split("Failing test case")[0])
    assert len(messages) == 1


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize(
    "law",
    [Coulomb(dims=2, **COULOMB), VelocityFriction(dims=2, **VELOCITY)],
    ids=["stick-slip kink", "kink of |v| at v = 0"],
)
def test_correct_laws_with_kinks_pass_on_other_example_sets_too(law, seed):
    """A correct law passes whatever the examples: other seeds give other (reproducible) sets."""
    check_law(law, max_examples=10, seed=seed)


# --- scales ---------------------------------------------------------------------------------------


class ElastoPlastic:
    """1-D elastic-perfectly-plastic spring without a declared force bound (yield force 2e3 N)."""

    name, dims, rigid, k, yield_force = "epp", 1, False, 1e6, 2e3

    def initial_state(self, n):
        return {"slip": np.zeros((n, 1))}

    def respond(self, state, u, normal_force, dt):
        trial = self.k * (u - state["slip"])
        force = np.clip(trial, -self.yield_force, self.yield_force)
        tangent = (self.k * (np.abs(trial) < self.yield_force))[:, :, None]
        return LawResponse(force, tangent, {"slip": u - force / self.k})


def test_a_law_without_a_bound_is_driven_around_its_yield_displacement():
    law = ElastoPlastic()
    # The secant stiffness is half the initial one at twice the yield displacement 2 mm.
    assert yield_displacement(law, np.array([1e6]), 0.01, law.k) == pytest.approx(4e-3, rel=0.2)
    assert make_context(law).displacement_scale == pytest.approx(4e-3, rel=0.2)
    assert yield_displacement(create_law("linear-spring", k=4e8), np.array([1e6]), 0.01, 4e8) is None
    assert make_context(create_law("linear-spring", k=4e8)).displacement_scale == 1e-3
    check_law(law, max_examples=10)


# --- strategies -----------------------------------------------------------------------------------


@once
@given(unit_arrays((400,)))
def test_unit_arrays_lie_in_the_unit_interval_with_exact_zeros_and_edges(values):
    assert values.shape == (400,) and np.all(np.abs(values) <= 1.0)


@settings(max_examples=5, derandomize=True, database=None, deadline=None, suppress_health_check=list(HealthCheck))
@given(unit_arrays((2000,)))
def test_unit_arrays_draw_zeros_and_edges_often(values):
    """1/8 exact zeros (trials at the committed point, motion along an axis), 1/16 edges, from the
    control byte of each number (hypothesis' random bytes; a shrunk or "simplest" draw is all zeros)."""
    if np.all(values == 0.0):
        return
    assert 0.08 < np.mean(values == 0.0) < 0.2 and 0.03 < np.mean(np.abs(values) == 1.0) < 0.1


@once
@given(st.data())
def test_histories_have_consistent_shapes_and_ranges(data):
    n, dims = data.draw(st.integers(1, 4)), data.draw(st.sampled_from([1, 2]))
    path, normal, velocity = data.draw(histories(dims, 1e-3, n, 12, 1e5, 4e6, contact=True, tension=False, velocity_scale=0.1))
    steps = len(path)
    assert 2 <= steps <= 12 and path.shape == (steps, n, dims) and normal.shape == (steps, n)
    assert velocity.shape == (steps, n, dims) and np.all(np.abs(velocity) <= 1.0)
    assert np.all((normal == 0) | ((normal >= 1e5) & (normal <= 4e6)))
    assert np.max(np.abs(path)) <= 20e-3 * steps * (1 + 1e-12)


@once
@given(contact_force_histories(50, 1e5, 4e6, tension=True))
def test_contact_force_histories_lose_contact_and_pull_only_when_asked(normal):
    assert np.all((normal <= 0) | ((normal >= 1e5) & (normal <= 4e6))) and np.all(normal >= -4e6)


@once
@given(st.data())
def test_per_bearing_laws_draw_values_around_the_law_and_within_range(data):
    law = Coulomb(k=4e8, mu=0.04, dims=2)
    array_law, singles = data.draw(per_bearing_laws(law, 3))
    assert array_law.dims == 2 and [s.dims for s in singles] == [2, 2, 2]
    for i, single in enumerate(singles):
        for name in ("k", "mu"):
            value = getattr(array_law, name)
            assert (value if np.ndim(value) == 0 else value[i]) == getattr(single, name)
        assert 4e8 / 2.01 <= single.k <= 4e8 * 2.01 and 0.0 <= single.mu <= 0.04 + 0.25


def test_drive_gives_a_velocity_law_the_backward_differences_unless_told():
    law = VelocityFriction(dims=1, k=1e6, f_min=0.01, f_max=0.05, a=100.0)
    path = np.array([1e-3, 2e-3, 4e-3])
    np.testing.assert_allclose(path_velocities(path, 0.01), [0.1, 0.1, 0.2])
    fast = drive(law, path, normal_force=1e4, dt=0.01)
    at_rest = drive(law, path, normal_force=1e4, dt=0.01, velocity=np.zeros(3))
    mu = 0.05 - 0.04 * np.exp(-100.0 * np.array([0.1, 0.1, 0.2]))
    np.testing.assert_allclose(fast, mu * 1e4)  # sliding from the first step (k u > mu N)
    np.testing.assert_allclose(at_rest, 0.01 * 1e4)
    with pytest.raises(ValueError, match="does not declare uses_velocity"):
        drive(create_law("linear-spring", k=1.0), [1.0], velocity=[1.0])


# --- reporting ------------------------------------------------------------------------------------


class Raises(Damper):
    def respond(self, state, u, normal_force, dt):
        if np.any(np.abs(u) > 1e-3):
            raise ZeroDivisionError("boom")
        return super().respond(state, u, normal_force, dt)


def test_an_exception_from_the_law_is_a_failure_of_the_property_that_met_it():
    with pytest.raises(ConformanceError, match=r"breaks property '[a-z ]+': respond raised ZeroDivisionError: boom \(u="):
        check_law(Raises(c=1e6), max_examples=20, shrink=False)


def test_check_law_splits_a_law_holding_per_bearing_arrays():
    law = Coulomb(k=np.array([4e8, 1e8]), mu=np.array([0.04, 0.1]), dims=1)
    check_law(law, max_examples=5)
