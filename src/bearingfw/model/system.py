"""The assembled system: what every analysis (static, modal, transient) works on.

:func:`build_system` turns a :class:`~bearingfw.model.Model` into full-DOF matrices, the
connector operators and the constraint transformation, and keeps the reduced ("free")
quantities that the solvers use:

- ``K`` (full): members plus the connectors' vertical springs; the laws are *not* in it.
- ``M`` (full): members and nodal masses.
- ``T`` (full x free): ``u = T q`` (supports, rigid links, tied connector directions).
- ``K_free = T^T K T``, ``M_free = T^T M T``, ``B_free = B T``, ``V_free = V T``.

A nonlinear step then needs only: internal force ``K_free q + B_free^T f(B_free q)`` and
tangent ``K_free + B_free^T K_t B_free``, where ``f`` and ``K_t`` come from the laws, grouped
as in ``connectors.groups``. Because ``K_free`` is constant, a transient solver can factorise
the linear part once and iterate on the (few) governed connector directions only.
"""

from __future__ import annotations

from collections.abc import Iterable

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.model._fields import ModelError
from bearingfw.model.assembly import (
    FrameArrays,
    TrussArrays,
    frame_arrays,
    gravity_load,
    mass_matrix,
    stiffness_matrix,
    truss_arrays,
)
from bearingfw.model.connectors import ConnectorOperators, build_connector_operators
from bearingfw.model.constraints import Constraints, build_constraints, rigid_link_equations, support_equations
from bearingfw.model.dofs import NDOF_NODE, DofMap, component_index
from bearingfw.model.model import Model
from bearingfw.model.nodes import NodalLoad
from bearingfw.plugins import Registry

__all__ = ["System", "build_system", "as_system", "DIRECTIONS"]

#: Ground-motion / participation directions: translations along and rotations about global axes.
DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")


@attrs.frozen(eq=False)
class System:
    """Assembled matrices and operators of a model (see the module docstring)."""

    model: Model
    dofmap: DofMap
    K: sp.csr_matrix
    M: sp.csr_matrix
    constraints: Constraints
    connectors: ConnectorOperators
    frames: FrameArrays
    trusses: TrussArrays
    K_free: sp.csr_matrix
    M_free: sp.csr_matrix
    B_free: sp.csr_matrix
    V_free: sp.csr_matrix

    @property
    def T(self) -> sp.csr_matrix:
        return self.constraints.T

    @property
    def n_dof(self) -> int:
        return self.dofmap.n_dof

    @property
    def n_free(self) -> int:
        return self.constraints.n_free

    @property
    def free_dofs(self) -> np.ndarray:
        """Full DOF index of each free DOF (``T`` has an identity row there, so ``q = u[free_dofs]``)."""
        return self.constraints.masters

    def expand(self, q: np.ndarray) -> np.ndarray:
        """Full DOF vector(s) from free ones: ``u = T q`` (q may be (n_free,) or (n_free, k))."""
        return self.T @ q

    def reduce(self, f: np.ndarray) -> np.ndarray:
        """Free-DOF load from a full load vector: ``T^T f``."""
        return self.T.T @ f

    def gravity_load(self, g: float = 9.81) -> np.ndarray:
        """Full load vector of all weights (members, added mass, nodal masses) under ``g``."""
        return gravity_load(self.model, self.dofmap, self.frames, self.trusses, g)

    def load_vector(self, loads: Iterable[NodalLoad] | np.ndarray = ()) -> np.ndarray:
        """Full load vector from point loads (or a full vector, checked and copied)."""
        if isinstance(loads, np.ndarray):
            if loads.shape != (self.n_dof,):
                raise ModelError(f"load vector must have shape ({self.n_dof},), got {loads.shape}")
            return loads.astype(float, copy=True)
        f = np.zeros(self.n_dof)
        for load in loads:
            if not isinstance(load, NodalLoad):
                raise ModelError(f"loads must be NodalLoad objects, got {load!r}")
            f[self.dofmap.node_dofs(load.node)] += load.values
        return f

    def rigid_body(self, direction: str, about: Iterable[float] = (0.0, 0.0, 0.0)) -> np.ndarray:
        """Full DOF vector of a unit rigid-body motion of every node.

        ``"x"|"y"|"z"``: unit translation; ``"rx"|"ry"|"rz"``: unit rotation about the global
        axis through ``about`` (translations ``theta x (X - about)``, rotations ``theta``).
        ``M @ rigid_body(d)`` per unit ground acceleration is the inertia load of uniform
        support excitation in direction ``d``.
        """
        k = DIRECTIONS.index(direction) if direction in DIRECTIONS else component_index(direction)
        r = np.zeros((self.dofmap.n_nodes, NDOF_NODE))
        if k < 3:
            r[:, k] = 1.0
        else:
            axis = np.zeros(3)
            axis[k - 3] = 1.0
            r[:, :3] = np.cross(axis, self.model.coordinates - np.asarray(about, dtype=float))
            r[:, k] = 1.0
        return r.reshape(-1)


def build_system(model: Model, registry: Registry | None = None) -> System:
    """Assemble ``model``. Laws are looked up in ``registry`` (default: the installed plugins)."""
    if not isinstance(model, Model):
        raise ModelError(f"build_system needs a Model, got {type(model).__name__}")
    dofmap = model.dofmap
    frames = frame_arrays(model, dofmap)
    trusses = truss_arrays(model, dofmap)
    connectors = build_connector_operators(model, dofmap, registry)
    K = (stiffness_matrix(dofmap.n_dof, frames, trusses) + connectors.spring_stiffness()).tocsr()
    M = mass_matrix(model, dofmap, frames, trusses)
    touched = (
        (abs(K.diagonal()) > 0) | (abs(M.diagonal()) > 0) | (np.asarray(abs(connectors.D).sum(axis=0)).ravel() > 0)
    )
    equations = support_equations(model, dofmap) + rigid_link_equations(model, dofmap) + connectors.tie_equations()
    constraints = build_constraints(dofmap.n_dof, equations, touched)
    T = constraints.T
    return System(
        model=model,
        dofmap=dofmap,
        K=K,
        M=M,
        constraints=constraints,
        connectors=connectors,
        frames=frames,
        trusses=trusses,
        K_free=(T.T @ K @ T).tocsr(),
        M_free=(T.T @ M @ T).tocsr(),
        B_free=(connectors.B @ T).tocsr(),
        V_free=(connectors.V @ T).tocsr(),
    )


def as_system(model_or_system: Model | System, registry: Registry | None = None) -> System:
    """Accept either a model (assembled here) or an already assembled system."""
    if isinstance(model_or_system, System):
        return model_or_system
    return build_system(model_or_system, registry)
