"""Driving a law through a displacement history, outside any FE model."""

from __future__ import annotations

import numpy as np

from bearingfw.protocol import BearingLaw, law_flag


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


def path_velocities(u, dt: float) -> np.ndarray:
    """Backward-difference velocities ``(u_k - u_{k-1}) / dt`` of a path from rest (``u_{-1} = 0``), same shape as ``u``."""
    u = np.asarray(u, dtype=float)
    return np.diff(u, axis=0, prepend=np.zeros_like(u[:1])) / dt


def _velocities(law: BearingLaw, velocity, u3: np.ndarray, dt: float):
    """The velocity history (steps, n, dims) for a law that uses it, else None."""
    if not law_flag(law, "uses_velocity"):
        if velocity is not None:
            raise ValueError(f"law {law.name!r} does not declare uses_velocity: it takes no velocity")
        return None
    if velocity is None:
        return path_velocities(u3, dt)
    v = np.asarray(velocity, dtype=float)
    if v.size != u3.size:
        raise ValueError(f"velocity has shape {v.shape}; expected the shape of u, {u3.shape}")
    return v.reshape(u3.shape)


def respond(law: BearingLaw, state, u, normal_force, dt: float, velocity=None):
    """``law.respond``, with ``velocity=`` passed only to a law that declares ``uses_velocity``
    (zeros if not given), as the kernel does."""
    if law_flag(law, "uses_velocity"):
        if velocity is None:
            velocity = np.zeros(np.shape(u))
        return law.respond(state, u, normal_force, dt, velocity=velocity)
    return law.respond(state, u, normal_force, dt)


def run_history(law: BearingLaw, u, normal_force=1.0, dt: float = 0.01, n: int = 1, velocity=None):
    """Run ``law`` from its initial state, committing every step.

    ``u`` is (steps, n, dims) (or the single-connector shapes of :func:`drive`). A law that
    declares ``uses_velocity`` gets ``velocity`` (the shape of ``u``), by default the backward
    differences of ``u`` over ``dt`` (:func:`path_velocities`). Returns the force history
    (steps, n, dims), the tangent history (steps, n, dims, dims) and the final state.
    """
    if law.rigid:
        raise TypeError(f"law {law.name!r} is rigid: it has no force-displacement response to drive")
    u3, normal = _histories(law, u, normal_force, n)
    v3 = _velocities(law, velocity, u3, dt)
    steps, n, dims = u3.shape
    forces = np.empty((steps, n, dims))
    tangents = np.empty((steps, n, dims, dims))
    state = law.initial_state(n)
    for i in range(steps):
        response = respond(law, state, u3[i], normal[i], dt, None if v3 is None else v3[i])
        forces[i] = response.force
        tangents[i] = response.tangent
        state = response.state
    return forces, tangents, state


def drive(law: BearingLaw, u, normal_force=1.0, dt: float = 0.01, velocity=None) -> np.ndarray:
    """The force history of one connector driven through the displacement history ``u``.

    ``u`` has shape (steps,) for a 1-D law or (steps, dims); ``normal_force`` is a scalar or one
    value per step. Each step is committed before the next. A law that declares
    ``uses_velocity`` gets ``velocity`` (the shape of ``u``; default: the backward differences of
    ``u`` over ``dt``). The result has ``u``'s shape. A rigid law has no force-displacement
    response and raises ``TypeError``.
    """
    shape = np.shape(u)
    forces, _, _ = run_history(law, u, normal_force, dt, velocity=velocity)
    return forces.reshape(shape)
