"""Static analysis: point loads and the gravity preload that dynamics starts from.

Equilibrium on the free DOFs ``q`` (``u = T q``)::

    R(q) = K_free q + B_free^T f_law(B u, N(u)) - T^T f = 0

solved by Newton with the laws' consistent tangents (one load step from the laws' virgin
state, so a linear law converges in one iteration). ``N = -kv V u`` is the compressive normal
force of each spring-supported connector; within an iteration it is taken from the current
iterate (its derivative is not part of the tangent).

After convergence the full residual ``r = K u + B^T f_law - f`` is the set of constraint
forces; its Lagrange multipliers give the support reactions and the forces of tied connector
directions (:mod:`bearingfw.model.constraints`). The gravity preload is this analysis with the
weight of every member, added mass and nodal mass as the load; its law states are the
committed states a transient analysis starts from.
"""

from __future__ import annotations

from collections.abc import Iterable

import attrs
import numpy as np
import scipy.sparse.linalg as spla

from bearingfw.model import ModelError, NodalLoad, System, as_system
from bearingfw.model.nodes import COMPONENTS
from bearingfw.plugins import Registry

__all__ = ["StaticResult", "ConvergenceError", "solve_static", "gravity", "factorize", "recover_connector_forces"]


class ConvergenceError(RuntimeError):
    """Newton did not reach equilibrium."""


def factorize(K):
    """LU factors of a free-DOF matrix with a clear message when the structure is a mechanism."""
    try:
        return spla.splu(K.tocsc())
    except RuntimeError as exc:
        raise ModelError(
            f"the stiffness matrix is singular ({exc}): the model is a mechanism; check supports, "
            "connectors (a frictionless direction needs another restraint) and rigid links"
        ) from exc


@attrs.frozen(eq=False)
class StaticResult:
    """Equilibrium state of a static analysis.

    ``support_reactions`` (n_supports, 6): forces and moments the supports apply to the
    structure, global axes, zero for free components. ``connector_forces`` (n_connectors, 3):
    local ``x, y, z`` forces resisting the relative displacement (a spring gives ``+k d``);
    ``normal_forces`` (n_connectors,): compressive normal force ``N = -F_z`` (>0 in
    compression). ``law_states``: the committed states, one per law group.
    """

    system: System
    u: np.ndarray
    load: np.ndarray
    g: float
    multipliers: np.ndarray
    support_reactions: np.ndarray
    connector_forces: np.ndarray
    law_states: tuple
    law_forces: np.ndarray
    iterations: int

    @property
    def q(self) -> np.ndarray:
        """Free DOFs (``u = T q``)."""
        return self.u[self.system.free_dofs]

    @property
    def normal_forces(self) -> np.ndarray:
        return -self.connector_forces[:, 2]

    def displacement(self, node: str, component: str = "uz") -> float:
        return float(self.u[self.system.dofmap.dof(node, component)])

    def connector_force(self, name: str) -> np.ndarray:
        return self.connector_forces[self.system.model.connector_index(name)]

    def normal_force(self, name: str) -> float:
        return float(self.normal_forces[self.system.model.connector_index(name)])

    def support_reaction(self, node: str) -> dict[str, float]:
        for k, s in enumerate(self.system.model.supports):
            if s.node == node:
                return dict(zip(COMPONENTS, self.support_reactions[k].tolist(), strict=True))
        raise ModelError(f"no support at node {node!r}")

    def reaction_resultant(self, about=(0.0, 0.0, 0.0)) -> np.ndarray:
        """Sum of support reactions: force (3) and moment about ``about`` (3)."""
        model = self.system.model
        total = np.zeros(6)
        for k, s in enumerate(model.supports):
            f, m = self.support_reactions[k, :3], self.support_reactions[k, 3:]
            arm = model.coordinates[model.node_index(s.node)] - np.asarray(about, dtype=float)
            total[:3] += f
            total[3:] += m + np.cross(arm, f)
        return total


def recover_connector_forces(
    system: System, u: np.ndarray, law_forces: np.ndarray, multipliers: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Connector forces (n, 3, local, resisting convention) and support reactions (n_supports, 6).

    Law directions from the law forces (flat, rows of ``B``), vertical springs from ``kv d_z``,
    tied directions and supports from the constraint multipliers.
    """
    ops = system.connectors
    model = system.model
    forces = np.zeros((ops.n_connectors, 3))
    if ops.spring_connectors.size:
        forces[ops.spring_connectors, 2] = ops.kv * (ops.V @ u)
    for (c, k), f in zip(ops.governed, law_forces, strict=True):
        forces[c, k] = f
    reactions = np.zeros((len(model.supports), 6))
    for eq, lam in zip(system.constraints.equations, multipliers, strict=True):
        if eq.source == "support":
            reactions[eq.index, eq.component] = lam
        elif eq.source == "connector":
            forces[eq.index, eq.component] = -lam  # lam is the tie's force on node j along e_k
    return forces, reactions


def solve_static(
    model_or_system,
    loads: Iterable[NodalLoad] | np.ndarray = (),
    *,
    g: float = 0.0,
    registry: Registry | None = None,
    dt: float = 1.0,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> StaticResult:
    """Static equilibrium under point loads (or a full load vector) plus gravity ``g`` (m/s^2).

    ``dt`` is passed to the laws' ``respond`` (a static analysis is one step); ``tol`` bounds
    the residual relative to the largest sum of absolute terms in any equation
    (``|K| |q| + |B^T| |f_law| + |f|``).
    """
    system = as_system(model_or_system, registry)
    if not (np.isfinite(g) and g >= 0.0):
        raise ModelError(f"solve_static: parameter 'g' = {g!r} must be >= 0")
    f = system.load_vector(loads)
    if g:
        f = f + system.gravity_load(g)
    inactive = system.constraints.inactive
    if inactive.size and np.any(f[inactive] != 0.0):
        bad = inactive[f[inactive] != 0.0][0]
        raise ModelError(f"a load acts on DOF {system.dofmap.describe(int(bad))}, which nothing resists")
    ops = system.connectors
    T = system.T
    f_free = T.T @ f
    # The residual is judged against the size of the terms summed into it (|K| |q| + ...), so
    # that round-off in a stiff model does not read as non-convergence.
    abs_K, abs_Bt = abs(system.K_free), abs(system.B_free.T)
    states0 = ops.initial_states()
    q = np.zeros(system.n_free)
    for iteration in range(max_iter + 1):
        u = T @ q
        responses = ops.respond(states0, ops.B @ u, ops.normal_forces(ops.V @ u), dt)
        f_law = ops.forces(responses)
        residual = system.K_free @ q + system.B_free.T @ f_law - f_free
        terms = abs_K @ np.abs(q) + abs_Bt @ np.abs(f_law) + np.abs(f_free)
        scale = max(float(np.max(terms, initial=0.0)), 1e-300)
        if np.max(np.abs(residual), initial=0.0) <= tol * scale:
            break
        if iteration == max_iter:
            raise ConvergenceError(
                f"solve_static: no equilibrium after {max_iter} Newton iterations "
                f"(residual {np.max(np.abs(residual)):.3g} N vs force scale {scale:.3g} N)"
            )
        Kt = system.K_free + system.B_free.T @ ops.tangent(responses) @ system.B_free
        q = q - factorize(Kt).solve(residual)
    r_full = system.K @ u + ops.B.T @ f_law - f
    lam = system.constraints.multipliers(r_full)
    forces, reactions = recover_connector_forces(system, u, f_law, lam)
    return StaticResult(
        system=system,
        u=u,
        load=f,
        g=float(g),
        multipliers=lam,
        support_reactions=reactions,
        connector_forces=forces,
        law_states=tuple(r.state for r in responses),
        law_forces=f_law,
        iterations=iteration,
    )


def gravity(
    model_or_system, *, g: float = 9.81, loads: Iterable[NodalLoad] | np.ndarray = (), **options
) -> StaticResult:
    """The gravity preload: self-weight, superimposed dead load (added and nodal masses), ``g`` down.

    Returns the displacements, support reactions, bearing normal forces and the committed law
    states from which a transient analysis continues. Options as for :func:`solve_static`.
    """
    return solve_static(model_or_system, loads, g=g, **options)
