"""The dynamic loads of a transient run: uniform support acceleration and optional nodal loads.

Relative formulation: every support moves with the same ground acceleration ``a_g(t)`` (global
``x, y, z``), and the response is measured relative to the ground. The inertia load on the free
DOFs is ``-T^T M r a_g`` with ``r = [r_x r_y r_z]`` the unit rigid-body translations
(:meth:`~bearingfw.model.System.rigid_body`): the mass that sits on supported DOFs only loads the
supports. Nodal loads (full DOF vectors, beyond the dead load already in the preload) add
``T^T f(t)``.

Samples are given every ``dt``; between samples the excitation is linear in time (so an
integration step that divides ``dt``, or a subdivided step, sees the straight line between the
record's points). The ground velocity, needed for absolute velocities, is the exact integral of
that piecewise-linear acceleration from rest.
"""

from __future__ import annotations

from collections.abc import Iterable

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.model import NodalLoad, System
from bearingfw.parameters import ParameterError

__all__ = ["Excitation", "build_excitation"]


@attrs.frozen(eq=False)
class Excitation:
    """Ground motion and nodal loads sampled every ``dt``, linear in between."""

    dt: float
    acceleration: np.ndarray  # (steps, 3), m/s^2
    velocity: np.ndarray  # (steps, 3), m/s
    P: np.ndarray  # (n_free, 3): T^T M r
    R: np.ndarray  # (n_dof, 3): rigid-body translations
    T: sp.csr_matrix
    nodal_full: np.ndarray | None  # (n_dof,) constant or (steps, n_dof), full DOFs

    @property
    def steps(self) -> int:
        return self.acceleration.shape[0]

    @property
    def duration(self) -> float:
        return (self.steps - 1) * self.dt

    def _where(self, t: float) -> tuple[int, float]:
        tau = min(max(t / self.dt, 0.0), self.steps - 1.0)
        i = min(int(tau), self.steps - 2) if self.steps > 1 else 0
        return i, tau - i

    def _sample(self, table: np.ndarray, t: float) -> np.ndarray:
        if self.steps == 1:
            return table[0]
        i, w = self._where(t)
        return table[i] if w == 0.0 else (1.0 - w) * table[i] + w * table[i + 1]

    def ground(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Ground acceleration and velocity (3,) at time ``t``."""
        if self.steps == 1:
            return self.acceleration[0], self.velocity[0]
        i, w = self._where(t)
        a0, a1 = self.acceleration[i], self.acceleration[i + 1]
        acc = (1.0 - w) * a0 + w * a1
        vel = self.velocity[i] + self.dt * (w * a0 + 0.5 * w * w * (a1 - a0))
        return acc, vel

    def nodal(self, t: float) -> np.ndarray | None:
        """Full nodal load vector at ``t`` (None without nodal loads)."""
        if self.nodal_full is None:
            return None
        if self.nodal_full.ndim == 1:
            return self.nodal_full
        return self._sample(self.nodal_full, t)

    def bearing_offset(self, t: float) -> tuple[np.ndarray, np.ndarray] | None:
        """What differential support motion adds, at ``t``, to the kernel's ``[B; V] x`` (the law
        displacements, then the vertical springs' shortening) and the rate of its ``B`` rows, or None.

        Uniform motion moves every support alike: it deforms no bearing, so this is None and a step
        is exactly what it always was (:func:`bearingfw.analysis.hht.step`). It must be zero at
        ``t = 0`` (the run starts from the preload at rest)."""
        return None

    def load(self, t: float) -> np.ndarray:
        """The dynamic load on the free DOFs at ``t``: ``-T^T M r a_g(t) + T^T f(t)``."""
        F = -(self.P @ self._sample(self.acceleration, t))
        nodal = self.nodal(t)
        if nodal is not None:
            F = F + self.T.T @ nodal
        return F


def _nodal_array(system: System, nodal_loads, steps: int) -> np.ndarray | None:
    if nodal_loads is None:
        return None
    if isinstance(nodal_loads, np.ndarray):
        arr = np.asarray(nodal_loads, dtype=float)
        if arr.shape not in ((system.n_dof,), (steps, system.n_dof)):
            raise ParameterError(
                f"solve_transient: 'nodal_loads' must have shape ({system.n_dof},) (constant) or "
                f"({steps}, {system.n_dof}) (one full load vector per excitation sample), got {arr.shape}"
            )
        arr = arr.copy()
    elif isinstance(nodal_loads, Iterable):
        loads = list(nodal_loads)
        if not all(isinstance(ld, NodalLoad) for ld in loads):
            raise ParameterError("solve_transient: 'nodal_loads' must be NodalLoad objects or an array")
        arr = system.load_vector(loads)
    else:
        raise ParameterError(f"solve_transient: 'nodal_loads' must be NodalLoad objects or an array, got {nodal_loads!r}")
    if not np.all(np.isfinite(arr)):
        raise ParameterError("solve_transient: 'nodal_loads' holds non-finite values")
    inactive = system.constraints.inactive
    if inactive.size and np.any(arr[..., inactive] != 0.0):
        bad = inactive[np.any((arr[..., inactive] != 0.0).reshape(-1, inactive.size), axis=0)][0]
        raise ParameterError(
            f"solve_transient: a nodal load acts on DOF {system.dofmap.describe(int(bad))}, which nothing resists"
        )
    return arr


def build_excitation(system: System, ground_acceleration, dt: float, nodal_loads=None) -> Excitation:
    """Check the inputs of :func:`~bearingfw.analysis.solve_transient` and build the excitation.

    ``ground_acceleration``: (steps, 3) in m/s^2 (global x, y, z), ``dt`` its sampling step (s).
    ``nodal_loads``: None, NodalLoad objects or a full vector (constant from ``t = 0``), or an array
    (steps, n_dof) sampled like the ground motion.
    """
    if not (isinstance(dt, (int, float, np.floating)) and not isinstance(dt, bool) and np.isfinite(dt) and dt > 0):
        raise ParameterError(f"solve_transient: 'dt' = {dt!r} must be a time step > 0 s")
    ag = np.asarray(ground_acceleration, dtype=float)
    if ag.ndim != 2 or ag.shape[1] != 3 or ag.shape[0] < 2:
        raise ParameterError(
            f"solve_transient: 'ground_acceleration' must have shape (steps, 3) with steps >= 2 "
            f"(x, y, z in m/s^2), got {ag.shape}"
        )
    if not np.all(np.isfinite(ag)):
        raise ParameterError("solve_transient: 'ground_acceleration' holds non-finite values")
    ag = ag.copy()
    velocity = np.zeros_like(ag)
    velocity[1:] = np.cumsum(0.5 * float(dt) * (ag[1:] + ag[:-1]), axis=0)
    R = np.column_stack([system.rigid_body(d) for d in ("x", "y", "z")])
    P = np.asarray(system.reduce(system.M @ R))
    return Excitation(float(dt), ag, velocity, P, R, system.T, _nodal_array(system, nodal_loads, ag.shape[0]))
