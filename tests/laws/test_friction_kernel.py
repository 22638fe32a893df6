"""The compiled friction return map gives the bits of the numpy formulas it replaced (issue 16)."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw.laws import friction_return_map


def numpy_return_map(k, u, slip, capacity):
    """The return map as numpy evaluated it before it was compiled (coulomb.py, 2026-11-25)."""
    trial = k * (u - slip)
    trial_norm = np.abs(trial[:, 0]) if u.shape[1] == 1 else np.sqrt(np.einsum("ij,ij->i", trial, trial))
    sliding = (trial_norm > capacity) | (capacity <= 0.0)
    safe_norm = np.where(sliding & (trial_norm > 0.0), trial_norm, 1.0)
    scale = np.where(sliding, capacity / safe_norm, 1.0)
    force = trial * scale[:, None]
    new_slip = np.where(sliding[:, None], u - force / k, slip)
    direction = trial / safe_norm[:, None]
    projector = np.eye(u.shape[1]) - sliding[:, None, None] * (direction[:, :, None] * direction[:, None, :])
    tangent = np.asarray(k, dtype=float)[..., None] * scale[:, None, None] * projector
    return force, new_slip, direction, sliding, tangent


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize("k_kind", ["scalar", "one", "column"])
def test_the_compiled_map_is_the_numpy_map_to_the_bit(dims, k_kind):
    rng = np.random.default_rng(dims)
    n = 9
    for _ in range(200):
        k = {"scalar": 4e8, "one": np.array([3e8]), "column": rng.uniform(1e7, 1e9, (n, 1))}[k_kind]
        slip = rng.normal(0, 1e-3, (n, dims)) * (rng.random((n, 1)) < 0.5)
        u = rng.normal(0, 2e-3, (n, dims)) * (rng.random((n, 1)) < 0.8)
        u[0] = slip[0]  # a zero trial force
        capacity = rng.choice([-1.0, 0.0, 5e4, 1e5, 3e5], n)
        got = friction_return_map(k, u, slip, capacity)
        for name, a, b in zip(got._fields, got, numpy_return_map(k, u, slip, capacity), strict=True):
            assert a.shape == b.shape and np.array_equal(a, b), name


def test_a_read_only_or_strided_input_is_accepted():
    u = np.zeros((6, 2))[::2]  # strided
    slip = np.ones((3, 2)) * 1e-3
    slip.setflags(write=False)
    k = np.full((3, 1), 1e8)
    k.setflags(write=False)
    got = friction_return_map(k, u, slip, np.full(3, 5e4))
    want = numpy_return_map(k, u, slip, np.full(3, 5e4))
    assert all(np.array_equal(a, b) for a, b in zip(got, want, strict=True))


@pytest.mark.parametrize("capacity", [5e4, np.float64(5e4), np.array([5e4]), np.full(4, 5e4)])
@pytest.mark.parametrize("slip_shape", ["full", "one row", "scalar"])
def test_capacity_and_slip_broadcast_as_the_numpy_map_did(capacity, slip_shape):
    """A plugin may use the map with one yield force for all its connectors, or one slip row: the
    compiled loop must not read past a length-1 array (it read memory beyond it)."""
    rng = np.random.default_rng(3)
    u = rng.normal(0, 2e-3, (4, 2))
    slip = {"full": np.full((4, 2), 1e-4), "one row": np.full((1, 2), 1e-4), "scalar": 1e-4}[slip_shape]
    got = friction_return_map(4e8, u, slip, capacity)
    want = numpy_return_map(4e8, u, slip, capacity)
    for name, a, b in zip(got._fields, got, want, strict=True):
        assert a.shape == b.shape and np.array_equal(a, b), name
    with pytest.raises(ValueError):
        friction_return_map(4e8, u, np.zeros((3, 2)), capacity)  # a slip of other connectors
