"""Driving a law through a displacement history, outside any FE model."""

from __future__ import annotations

import numpy as np

from bearingfw.protocol import BearingLaw


def _histories(law: BearingLaw, u, normal_force, n: int):
    """Reshape ``u`` to (steps, n, dims) and ``normal_force`` to (steps, n)."""
    u = np.asarray(u, dtype=float)
    dims = law.dims
    if n == 1 and u.ndim == 1 and dims == 1:
        u3 = u[:, None, None]
    elif n == 1 and u.ndim == 2 and u.shape[1] == dims:
        u3 = u[:, None, :]
    elif u.ndim == 3 and u.shape[1:] == (n, dims):
        u3 = u
    else:
        expected = "(steps,) or (steps, 1)" if dims == 1 else f"(steps, {dims})"
        raise ValueError(f"u has shape {u.shape}; a {dims}-D law {law.name!r} takes {expected}")
    steps = u3.shape[0]
    force = np.asarray(normal_force, dtype=float)
    if force.ndim == 0:
        force = np.full((steps, n), float(force))
    elif force.shape == (steps,):
        force = np.repeat(force[:, None], n, axis=1)
    elif force.shape != (steps, n):
        raise ValueError(f"normal_force has shape {force.shape}; expected a scalar or one value per step ({steps},)")
    return u3, force


def run_history(law: BearingLaw, u, normal_force=1.0, dt: float = 0.01, n: int = 1):
    """Run ``law`` from its initial state, committing every step.

    ``u`` is (steps, n, dims) (or the single-connector shapes of :func:`drive`). Returns the
    force history (steps, n, dims), the tangent history (steps, n, dims, dims) and the final
    state.
    """
    if law.rigid:
        raise TypeError(f"law {law.name!r} is rigid: it has no force-displacement response to drive")
    u3, normal = _histories(law, u, normal_force, n)
    steps, n, dims = u3.shape
    forces = np.empty((steps, n, dims))
    tangents = np.empty((steps, n, dims, dims))
    state = law.initial_state(n)
    for i in range(steps):
        response = law.respond(state, u3[i], normal[i], dt)
        forces[i] = response.force
        tangents[i] = response.tangent
        state = response.state
    return forces, tangents, state


def drive(law: BearingLaw, u, normal_force=1.0, dt: float = 0.01) -> np.ndarray:
    """The force history of one connector driven through the displacement history ``u``.

    ``u`` has shape (steps,) for a 1-D law or (steps, dims); ``normal_force`` is a scalar or one
    value per step. Each step is committed before the next. The result has ``u``'s shape.
    A rigid law has no force-displacement response and raises ``TypeError``.
    """
    shape = np.shape(u)
    forces, _, _ = run_history(law, u, normal_force, dt)
    return forces.reshape(shape)
