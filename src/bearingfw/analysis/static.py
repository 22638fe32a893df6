"""Static analysis: point loads and the gravity preload that dynamics starts from.

Equilibrium on the free DOFs ``q`` (``u = T q``)::

    R(q) = K_free q + B_free^T f_law(B u - d_ref, N(u)) - T^T f = 0

``N = -kv V u`` is the compressive normal force of each spring-supported connector and
``d_ref`` (:attr:`StaticResult.law_reference`) the governed relative displacement at which the
laws' displacement is zero. How the bearings take part is the option ``bearings``:

- ``"active"`` (default of :func:`solve_static`): the laws act from their virgin state at the
  undeformed geometry (``d_ref = 0``). Newton with the laws' consistent tangents, one load step
  (a linear law converges in one iteration); within an iteration ``N`` is taken from the current
  iterate (its derivative is not part of the tangent), except that a first iteration at which
  the laws' tangents at ``N = 0`` leave the structure a mechanism (friction without contact has
  no stick stiffness) is taken with ``N`` of the load carried by the vertical springs. Under gravity a friction bearing whose
  girder end moves (rotation times the soffit offset, shortening) may slip already.
- ``"set-after-dead-load"`` (default of :func:`gravity`): the bearings are installed in the
  dead-load position, as usual in practice (preset so that the dead-load movements are
  accommodated). The load is carried with the law-governed directions free (zero force):
  ``K_free q = T^T f``; ``N`` comes from the vertical springs; the laws keep their virgin states
  (zero slip, zero force) and ``d_ref = B u``, so that their displacement is zero there. (Laws
  are taken to exert no force at zero displacement from their initial state, as every built-in
  law does.)

Uplift bearings (``Connector(uplift=True)``): their compression-only vertical springs are a law
of the kernel (:class:`~bearingfw.model.connectors.CompressionOnlyGap`) on the total ``d_z``,
never set after the dead load (``d_ref = 0`` there). ``"active"`` lets them open like any law;
``"set-after-dead-load"`` carries the load with them closed (their stiffness ``kv`` in the solve)
and raises a :class:`~bearingfw.model.ModelError` naming the bearings that this load pulls
(tension that they cannot carry).

In ``"set-after-dead-load"``, motions that only the bearings restrain (a girder resting on
sliding bearings alone, its rigid horizontal translation) are left undetermined by the
equilibrium: the load does no work on them. They are fixed numerically: the solve uses
``K_s = K_free + kappa B_free^T B_free`` with a tiny ``kappa`` (``STABILIZER`` times the largest
diagonal term of ``K_free``) and refines ``q <- q + K_s^{-1} (T^T f - K_free q)`` until the
residual is round-off: each step reduces the error of every loaded deformation by
``kappa / (kappa + k)`` (``k`` the structure's stiffness in it), so two or three steps do, and the
undetermined motions get only round-off over ``kappa``. A load *along* such a motion (gravity on
a tilted sliding plane, a horizontal load on a girder that only its bearings hold) cannot be
carried by free bearings: that is an error (use ``"active"``). The structure must also not be a
mechanism with the laws at their initial tangent (e.g. frictionless bearings and nothing else
holding the deck horizontally): that is checked, and reported as a mechanism, in both modes.

Convergence: the residual must be within ``tol`` of the force scale, the total of the absolute
applied forces (supported DOFs included: it bounds every reaction) and law forces. It is not
judged against ``|K| |q|``, which a mechanism's huge ``q`` would inflate until garbage passed.

Mechanisms: :func:`factorize` rejects a matrix whose LU factors have a pivot below
``PIVOT_RATIO`` of the largest (round-off can leave a singular matrix with tiny instead of zero
pivots), and names the DOFs that move most in the free motion.

After convergence the full residual ``r = K u + B^T f_law - f`` is the set of constraint
forces; its Lagrange multipliers give the support reactions and the forces of tied connector
directions (:mod:`bearingfw.model.constraints`). The gravity preload is this analysis with the
weight of every member, added mass and nodal mass as the load; its law states and
``law_reference`` are what a transient analysis starts from (the laws then see
``B u - law_reference``: :attr:`StaticResult.law_displacements`).
"""

from __future__ import annotations

from collections.abc import Iterable

import attrs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from bearingfw.model import ModelError, NodalLoad, System, as_system
from bearingfw.model.connectors import normal_force
from bearingfw.model.nodes import COMPONENTS
from bearingfw.plugins import Registry

__all__ = [
    "StaticResult",
    "ConvergenceError",
    "solve_static",
    "gravity",
    "factorize",
    "initial_tangent",
    "recover_connector_forces",
    "ForceRecovery",
    "BEARINGS",
    "PIVOT_RATIO",
    "SYMMETRIC_ORDERING",
    "STABILIZER",
]

#: How bearings take part in a static analysis (module docstring).
BEARINGS = ("set-after-dead-load", "active")
#: LU pivots below this fraction of the largest one mean a (near-)singular matrix: a mechanism.
#: Real stiffness contrasts of a bridge model stay above ~1e-6; a mechanism leaves ~1e-16.
PIVOT_RATIO = 1e-12
#: SuperLU's column ordering for symmetric matrices (minimum degree on ``A^T + A``): on bridge
#: models about a quarter fewer fill-ins than the default COLAMD, and back-substitutions about
#: 30 % faster (:func:`factorize`).
SYMMETRIC_ORDERING = "MMD_AT_PLUS_A"
#: Stabilising stiffness of the governed directions in the "set-after-dead-load" solve, as a
#: fraction of the largest diagonal term of K_free (well above PIVOT_RATIO, far below any member).
STABILIZER = 1e-8
#: The round-off of a residual ``f - K q``, relative to the size ``|K| |q|`` of the terms it sums.
_ROUNDOFF = 1024 * np.finfo(float).eps
#: A tangent block of a law counts as having lost its stiffness below this fraction of its initial one.
_LOST = 1e-9


class ConvergenceError(RuntimeError):
    """Newton did not reach equilibrium (or the bearings' tangent lost the stiffness it needed)."""


def _free_motion(K, lu=None, count: int = 8) -> np.ndarray:
    """Indices of the DOFs of ``K`` that move most in its (near-)null space, largest first.

    One solve with the (regularised, if ``lu`` is None) factors: ``K^-1 b`` is dominated by
    the directions of the smallest pivots, i.e. the free motion.
    """
    n = K.shape[0]
    b = np.random.default_rng(0).standard_normal(n)
    try:
        if lu is None:
            shift = 1e-10 * max(float(abs(K.diagonal()).max(initial=0.0)), 1.0)
            lu = spla.splu((K + shift * sp.eye(n)).tocsc())
        z = np.abs(lu.solve(b))
    except (RuntimeError, ValueError):
        return np.zeros(0, dtype=int)
    if not np.all(np.isfinite(z)) or not z.max(initial=0.0) > 0:
        return np.zeros(0, dtype=int)
    order = np.argsort(-z, kind="stable")
    return order[z[order] >= 0.1 * z[order[0]]][:count]


def _describe_free(system: System | None, free: np.ndarray) -> str:
    if system is not None and free.size and system.n_free > int(free.max()):
        return ", ".join(system.dofmap.describe(int(d)) for d in system.free_dofs[free])
    return ", ".join(f"free DOF {int(d)}" for d in free)


def factorize(
    K, *, system: System | None = None, pivot_ratio: float = PIVOT_RATIO, ordering: str = "COLAMD"
):
    """LU factors of a free-DOF matrix; a clear :class:`ModelError` when the structure is a mechanism.

    Singular means an exactly zero pivot or one below ``pivot_ratio`` of the largest (round-off
    turns the zero pivots of a singular matrix into tiny ones). The message names the DOFs that
    move most in the free motion, as node.component when ``system`` (whose free DOFs ``K``
    acts on) is given. ``ordering`` is SuperLU's column ordering (``permc_spec``): its default
    COLAMD suits any matrix; :data:`SYMMETRIC_ORDERING` leaves fewer fill-ins for a symmetric
    one (the effective matrices of :mod:`~bearingfw.analysis.hht`), so that each
    back-substitution is cheaper. The ordering changes the factors' round-off, not what is singular.
    """
    K = K.tocsc()
    try:
        lu = spla.splu(K, permc_spec=ordering)
    except RuntimeError as exc:
        reason, lu = str(exc), None
    else:
        pivots = np.abs(lu.U.diagonal())
        largest = float(pivots.max(initial=0.0))
        ratio = float(pivots.min(initial=largest)) / largest if largest > 0 else 0.0
        if ratio >= pivot_ratio:
            return lu
        reason = f"smallest LU pivot {ratio:.1e} of the largest"
    moving = _describe_free(system, _free_motion(K, lu))
    raise ModelError(
        f"the stiffness matrix is singular ({reason}): the model is a mechanism; the free motion moves "
        f"most {moving or 'unknown DOFs'}; check supports, connectors (a frictionless direction needs "
        "another restraint) and rigid links"
    )


def initial_tangent(system: System, normal_forces: np.ndarray | None = None, dt: float = 1.0):
    """``K_free + B_free^T K_t B_free`` with every law's initial tangent (symmetrised).

    ``K_t`` is ``respond(initial_state(n), 0, N, dt).tangent``: the laws in their virgin state at
    zero law displacement (for bearings set after the dead load: at the dead-load position), at
    zero velocity; the uplift bearings' gap law closed (its ``kv``).
    ``normal_forces`` per connector (default zero) are passed to the laws.
    """
    ops = system.connectors
    if not ops.groups:
        return system.K_free
    N = np.zeros(ops.n_connectors) if normal_forces is None else np.asarray(normal_forces, dtype=float)
    zero = np.zeros(ops.n_governed)
    responses = ops.respond(ops.initial_states(), zero, N[ops.spring_connectors], dt)
    Kt = ops.tangent(responses)
    Kt = (Kt + Kt.T) / 2
    return (system.K_free + system.B_free.T @ Kt @ system.B_free).tocsr()


@attrs.frozen(eq=False)
class StaticResult:
    """Equilibrium state of a static analysis.

    ``support_reactions`` (n_supports, 6): forces and moments the supports apply to the
    structure, global axes, zero for free components. ``connector_forces`` (n_connectors, 3):
    local ``x, y, z`` forces resisting the relative displacement (a spring gives ``+k d``);
    ``normal_forces`` (n_connectors,): compressive normal force ``N = -F_z`` (>0 in
    compression). ``law_states``: the committed states, one per law group. ``law_reference``
    (aligned with the rows of ``B``): the governed relative displacement at which the laws'
    displacement is zero, ``B u`` of the dead load for ``bearings="set-after-dead-load"``, zeros
    for ``"active"``; the laws see ``B u - law_reference`` (:attr:`law_displacements`).
    ``bearings`` records the option the result was computed with.
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
    law_reference: np.ndarray | None = None
    bearings: str = "active"

    def __attrs_post_init__(self):
        if self.law_reference is None:
            object.__setattr__(self, "law_reference", np.zeros(self.system.connectors.n_governed))

    @property
    def q(self) -> np.ndarray:
        """Free DOFs (``u = T q``)."""
        return self.u[self.system.free_dofs]

    @property
    def normal_forces(self) -> np.ndarray:
        return normal_force(self.connector_forces[:, 2])

    @property
    def law_displacements(self) -> np.ndarray:
        """The displacement the laws see, ``B u - law_reference`` (flat, rows of ``B``)."""
        return self.system.connectors.B @ self.u - self.law_reference

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


@attrs.frozen(eq=False)
class ForceRecovery:
    """Where every connector force and support reaction comes from, as index arrays: built once per
    system so that recovering them is a few vectorised assignments (a recorder does it every step).

    Flat slots index ``(n_connectors, 3)`` connector forces and ``(n_supports, 6)`` reactions;
    ``*_rows`` are the rows of ``B`` (law forces) or the constraint equations (multipliers) that
    fill them. Law directions first, then the ties, which override (module docstring of
    :func:`recover_connector_forces`).
    """

    n_connectors: int
    n_supports: int
    spring_slots: np.ndarray
    law_slots: np.ndarray
    tie_slots: np.ndarray
    tie_rows: np.ndarray
    support_slots: np.ndarray
    support_rows: np.ndarray

    @classmethod
    def of(cls, system: System) -> ForceRecovery:
        ops = system.connectors
        equations = system.constraints.equations

        def slots(pairs, width):
            return np.array([width * a + b for a, b in pairs], dtype=int)

        ties = [(k, eq) for k, eq in enumerate(equations) if eq.source == "connector"]
        supports = [(k, eq) for k, eq in enumerate(equations) if eq.source == "support"]
        return cls(
            n_connectors=ops.n_connectors,
            n_supports=len(system.model.supports),
            spring_slots=3 * np.asarray(ops.spring_connectors, dtype=int) + 2,
            law_slots=slots(ops.governed, 3),
            tie_slots=slots([(eq.index, eq.component) for _, eq in ties], 3),
            tie_rows=np.array([k for k, _ in ties], dtype=int),
            support_slots=slots([(eq.index, eq.component) for _, eq in supports], 6),
            support_rows=np.array([k for k, _ in supports], dtype=int),
        )

    def connector_forces(self, spring_forces: np.ndarray, law_forces: np.ndarray, multipliers: np.ndarray) -> np.ndarray:
        """(n_connectors, 3) from the vertical spring forces ``kv V u``, the law forces and the multipliers."""
        forces = np.zeros(3 * self.n_connectors)
        forces[self.spring_slots] = spring_forces
        forces[self.law_slots] = law_forces
        forces[self.tie_slots] = -np.asarray(multipliers)[self.tie_rows]  # lam: the tie's force on node j along e_k
        return forces.reshape(-1, 3)

    def support_reactions(self, multipliers: np.ndarray) -> np.ndarray:
        reactions = np.zeros(6 * self.n_supports)
        reactions[self.support_slots] = np.asarray(multipliers)[self.support_rows]
        return reactions.reshape(-1, 6)


def recover_connector_forces(
    system: System, u: np.ndarray, law_forces: np.ndarray, multipliers: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Connector forces (n, 3, local, resisting convention) and support reactions (n_supports, 6).

    Law directions from the law forces (flat, rows of ``B``), vertical springs from ``kv d_z``,
    tied directions and supports from the constraint multipliers (a tie's multiplier replaces
    anything else in its direction). Repeated use on one system: :class:`ForceRecovery`.
    """
    ops = system.connectors
    recovery = ForceRecovery.of(system)
    springs = ops.kv * (ops.V @ u) if ops.spring_connectors.size else np.zeros(0)
    return (
        recovery.connector_forces(springs, np.asarray(law_forces, dtype=float), multipliers),
        recovery.support_reactions(multipliers),
    )


def _per_connector(system: System, N_springs: np.ndarray) -> np.ndarray:
    N = np.zeros(system.connectors.n_connectors)
    N[system.connectors.spring_connectors] = N_springs
    return N


def _force_scale(f: np.ndarray, f_law: np.ndarray) -> float:
    """Total of the absolute applied and law forces: the size every equilibrium residual is judged by."""
    return float(np.sum(np.abs(f)) + np.sum(np.abs(f_law)))


def _check_mechanism_with_laws(system: System, N_springs: np.ndarray, dt: float) -> None:
    """Raise the mechanism error if the structure with the laws' initial tangents is singular."""
    if system.connectors.groups:
        factorize(initial_tangent(system, _per_connector(system, N_springs), dt), system=system)


def _lost_stiffness(system: System, responses, N_springs: np.ndarray, dt: float) -> list[str]:
    """Connectors whose law tangent has (nearly) lost a direction's stiffness against its virgin one."""
    ops = system.connectors
    virgin = ops.respond(ops.initial_states(), np.zeros(ops.n_governed), N_springs, dt)
    names = []
    for g, now, then in zip(ops.groups, responses, virgin, strict=True):
        lowest = np.linalg.svd(np.asarray(now.tangent, dtype=float), compute_uv=False)[:, -1]
        highest = np.linalg.svd(np.asarray(then.tangent, dtype=float), compute_uv=False)[:, 0]
        lost = (lowest <= _LOST * highest) & (highest > 0)
        names += [system.model.connectors[c].name for c in g.connectors[lost]]
    return names


def _active(system: System, f: np.ndarray, dt: float, tol: float, max_iter: int):
    """Newton with the laws acting from their virgin state (``bearings="active"``).

    The first iteration is at the undeformed geometry, where every ``N`` is zero. If the laws'
    tangents leave the structure a mechanism there (a friction law has no stick stiffness without
    contact), it is taken again with the normal forces of the load carried by the vertical springs
    (the governed directions free; :func:`_carried_normal_forces`), and Newton goes on from there.
    """
    try:
        return _newton_active(system, f, dt, tol, max_iter, None)
    except ModelError:
        N_start = _carried_normal_forces(system, f)
        if N_start is None:
            raise
        return _newton_active(system, f, dt, tol, max_iter, N_start)


def _carried_normal_forces(system: System, f: np.ndarray) -> np.ndarray | None:
    """The springs' normal forces when the load is carried with the governed directions free (one
    solve of the stabilised ``K_free``, uplift springs closed), or None if even that is singular."""
    ops = system.connectors
    K = system.K_free
    if ops.gap_rows.size:
        B_gap = system.B_free[ops.gap_rows]
        K = K + B_gap.T @ sp.diags(ops.gap_group.law.kv) @ B_gap
    kappa = STABILIZER * max(float(abs(K.diagonal()).max(initial=0.0)), 1e-300)
    try:
        q = factorize(K + kappa * (system.B_free.T @ system.B_free), system=system).solve(system.T.T @ f)
    except ModelError:
        return None
    return ops.normal_forces(system.V_free @ q)


def _newton_active(system: System, f: np.ndarray, dt: float, tol: float, max_iter: int, N_start):
    """:func:`_active`'s Newton; ``N_start``: the normal forces of the first iteration (None: from ``q = 0``)."""
    ops = system.connectors
    T = system.T
    f_free = T.T @ f
    states0 = ops.initial_states()
    q = np.zeros(system.n_free)
    for iteration in range(max_iter + 1):
        u = T @ q
        N = ops.normal_forces(ops.V @ u) if iteration or N_start is None else N_start
        responses = ops.respond(states0, ops.B @ u, N, dt)
        f_law = ops.forces(responses)
        residual = system.K_free @ q + system.B_free.T @ f_law - f_free
        scale = max(_force_scale(f, f_law), 1e-300)
        if np.max(np.abs(residual), initial=0.0) <= tol * scale:
            return u, f_law, tuple(r.state for r in responses), iteration
        if iteration == max_iter:
            raise ConvergenceError(
                f"solve_static: no equilibrium after {max_iter} Newton iterations "
                f"(residual {np.max(np.abs(residual)):.3g} vs force scale {scale:.3g})"
            )
        Kt = system.K_free + system.B_free.T @ ops.tangent(responses) @ system.B_free
        try:
            lu = factorize(Kt, system=system)
        except ModelError as exc:
            if iteration == 0:  # the laws' initial tangents: a mechanism of the structure
                raise
            slipping = _lost_stiffness(system, responses, N, dt)
            raise ConvergenceError(
                "solve_static (bearings='active'): the bearings "
                f"{', '.join(map(repr, slipping)) or '(unidentified)'} slip under this load and their tangent "
                "lost the stiffness that held the structure (e.g. a girder held horizontally by friction "
                "bearings only): the equilibrium does not fix the sliding position. This is not a mechanism "
                "of the structure (it stands with the bearings' initial stiffness). For a dead load use "
                f"bearings='set-after-dead-load' (the bearings installed in the dead-load position). [{exc}]"
            ) from exc
        q = q - lu.solve(residual)


def _set_after_dead_load(system: System, f: np.ndarray, dt: float, tol: float, max_iter: int):
    """The load carried with the governed directions free (``bearings="set-after-dead-load"``)."""
    ops = system.connectors
    T = system.T
    f_free = T.T @ f
    K = system.K_free
    gap_rows = ops.gap_rows
    if gap_rows.size:  # uplift bearings carry the load closed: their springs' stiffness kv
        B_gap = system.B_free[gap_rows]
        K = (K + B_gap.T @ sp.diags(ops.gap_group.law.kv) @ B_gap).tocsr()
    # A tiny stiffness in the governed directions fixes the motions only the bearings restrain;
    # the refinement below removes its force from everything the load deforms.
    kappa = STABILIZER * max(float(abs(K.diagonal()).max(initial=0.0)), 1e-300)
    lu = factorize(K + kappa * (system.B_free.T @ system.B_free), system=system)
    q = np.zeros(system.n_free)
    scale = max(_force_scale(f, np.zeros(0)), 1e-300)
    previous = np.inf
    magnitude = abs(K)
    for iteration in range(max_iter + 1):
        residual = f_free - K @ q
        size = float(np.max(np.abs(residual), initial=0.0))
        # Converged: within tol of the load, or at the round-off of K q itself (a fine mesh's stiff
        # members make |K| |q| large enough that tol * scale lies below what K q can resolve).
        if size <= max(tol * scale, _ROUNDOFF * float(np.max(magnitude @ np.abs(q), initial=0.0))):
            break
        if iteration == max_iter or size > 0.5 * previous:
            # Not converging: the load has a part the free bearing directions cannot carry. Unless
            # even the laws cannot hold it (a mechanism, reported as such), say so.
            _check_mechanism_with_laws(system, ops.normal_forces(ops.V @ (T @ q)), dt)
            moving = _describe_free(system, np.argsort(-np.abs(q))[:8])
            raise ModelError(
                "gravity/solve_static (bearings='set-after-dead-load'): the load pushes along motions that only "
                f"the bearings restrain (moving most {moving}), e.g. gravity along a tilted sliding plane or a "
                "horizontal load on a girder that only its bearings hold; bearings set after the dead load "
                "carry no force in their governed directions. Use bearings='active' for such a load "
                f"(residual {size:.3g} vs force scale {scale:.3g})"
            )
        previous = size
        q = q + lu.solve(residual)
    u = T @ q
    N = ops.normal_forces(ops.V @ u)
    _check_mechanism_with_laws(system, N, dt)
    f_law = np.zeros(ops.n_governed)
    reference = ops.B @ u
    if gap_rows.size:
        f_law[gap_rows] = _closed_gap_forces(system, reference[gap_rows])
        reference[gap_rows] = 0.0  # the gap law sees the total d_z
    return u, f_law, ops.initial_states(), reference, iteration


def _closed_gap_forces(system: System, d_gap: np.ndarray) -> np.ndarray:
    """The forces ``kv d_z`` of the uplift bearings' springs, closed; an error if the load pulls any."""
    ops = system.connectors
    group = ops.gap_group
    pulled = d_gap > 0.0
    if np.any(pulled):
        names = [system.model.connectors[c].name for c in group.connectors[pulled]]
        tension = group.law.kv[pulled] * d_gap[pulled]
        raise ModelError(
            "gravity/solve_static (bearings='set-after-dead-load'): the load pulls the uplift bearing(s) "
            f"{', '.join(map(repr, names))} (tension {', '.join(f'{t:.3g}' for t in tension)} N), which cannot "
            "carry tension; make them uplift=False, or use bearings='active' to let them lift off"
        )
    return group.law.kv * d_gap


def solve_static(
    model_or_system,
    loads: Iterable[NodalLoad] | np.ndarray = (),
    *,
    g: float = 0.0,
    registry: Registry | None = None,
    dt: float = 1.0,
    tol: float = 1e-10,
    max_iter: int = 50,
    bearings: str = "active",
) -> StaticResult:
    """Static equilibrium under point loads (or a full load vector) plus gravity ``g`` (m/s^2).

    ``bearings``: ``"active"`` (default; the laws act from their virgin state) or
    ``"set-after-dead-load"`` (the load is carried with the law-governed directions free and the
    laws are set, virgin, at the resulting position): see the module docstring. ``dt`` is
    passed to the laws' ``respond`` (a static analysis is one step); ``tol`` bounds the
    residual relative to the total of the absolute applied and law forces.

    Raises :class:`ModelError` for a mechanism (naming the DOFs of the free motion) and
    :class:`ConvergenceError` when Newton does not converge or ``"active"`` bearings slip into
    a position the equilibrium does not fix.
    """
    system = as_system(model_or_system, registry)
    if not (np.isfinite(g) and g >= 0.0):
        raise ModelError(f"solve_static: parameter 'g' = {g!r} must be >= 0")
    if bearings not in BEARINGS:
        allowed = ", ".join(map(repr, BEARINGS))
        raise ModelError(f"solve_static: parameter 'bearings' must be one of {allowed}, got {bearings!r}")
    f = system.load_vector(loads)
    if g:
        f = f + system.gravity_load(g)
    inactive = system.constraints.inactive
    if inactive.size and np.any(f[inactive] != 0.0):
        bad = inactive[f[inactive] != 0.0][0]
        raise ModelError(f"a load acts on DOF {system.dofmap.describe(int(bad))}, which nothing resists")
    ops = system.connectors
    if bearings == "active":
        u, f_law, states, iterations = _active(system, f, dt, tol, max_iter)
        reference = np.zeros(ops.n_governed)
    else:
        u, f_law, states, reference, iterations = _set_after_dead_load(system, f, dt, tol, max_iter)
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
        law_states=tuple(states),
        law_forces=f_law,
        iterations=iterations,
        law_reference=reference,
        bearings=bearings,
    )


def gravity(
    model_or_system,
    *,
    g: float = 9.81,
    loads: Iterable[NodalLoad] | np.ndarray = (),
    bearings: str = "set-after-dead-load",
    **options,
) -> StaticResult:
    """The gravity preload: self-weight, superimposed dead load (added and nodal masses), ``g`` down.

    Returns the displacements, support reactions, bearing normal forces, the law states and
    ``law_reference`` from which a transient analysis continues. ``bearings``:

    - ``"set-after-dead-load"`` (default): the bearings are installed in the dead-load position
      (preset so that the dead-load movements are accommodated): the dead load (and ``loads``)
      is carried with the law-governed directions free, the laws get ``N`` from the vertical
      springs, keep their virgin states (zero slip, zero force), and ``law_reference = B u``.
      A friction bearing thus starts the dynamics in stick, not on its slip circle. A
      structure that is a mechanism with the laws' initial tangents (frictionless bearings and
      nothing else holding the deck) is still reported as a mechanism.
    - ``"active"``: the laws act from the undeformed geometry (friction bearings may slip under
      the self-weight; a girder on friction bearings alone whose bearings both slip has no
      determined position, reported as such).

    Other options as for :func:`solve_static`.
    """
    return solve_static(model_or_system, loads, g=g, bearings=bearings, **options)
