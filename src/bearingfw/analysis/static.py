"""Static analysis: point loads and the gravity preload that dynamics starts from.

Equilibrium on the free DOFs ``q`` (``u = T q``)::

    R(q) = K_free q + B_free^T f_law(B u - d_ref, N(u)) - T^T f = 0

``N = -kv V u`` is the compressive normal force of each spring-supported connector and
``d_ref`` (:attr:`StaticResult.law_reference`) the governed relative displacement at which the
laws' displacement is zero. How the bearings take part is the option ``bearings``:

- ``"active"`` (default of :func:`solve_static`): the laws act from their virgin state at the
  undeformed geometry (``d_ref = 0``). Newton with a consistent Jacobian, one load step (a linear
  law converges in one iteration): the laws' tangents and, for laws with dF/dN, the part of ``N``
  following the vertical springs (``-B^T E diag(kv) V``, as in the transient Jacobian); a
  correction that does not cut the residual is halved (a line search: across stick-slip switches
  full corrections can cycle). The first iteration, at ``q = 0`` where the laws' force is zero,
  takes their tangent at ``N`` of the load carried by the vertical springs: a friction law has
  no capacity, hence no stiffness, without contact, and starting from the load carried with every
  friction bearing free lands far from the equilibrium. Under gravity a friction bearing whose
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
from bearingfw.protocol import LawResponse

__all__ = [
    "StaticResult",
    "ConvergenceError",
    "StiffnessRangeError",
    "check_law_tangents",
    "initial_stiffness_error",
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
    "OUT_OF_RANGE",
    "ACCURATE_CONTRAST",
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
#: Halvings of a Newton correction of the active static solve at most (:func:`_backtrack`).
_BACKTRACKS = 10
#: Armijo's sufficient decrease: a correction of length ``lam`` must cut the residual norm by ``_ARMIJO lam``.
_ARMIJO = 1e-4
#: A tangent block of a law counts as having lost its stiffness below this fraction of its initial one.
_LOST = 1e-9
#: A law tangent beyond this multiple of the structure's stiffest diagonal term is out of range
#: whatever the factors say: beside it the structure's own stiffness is below round-off (1 / eps).
OUT_OF_RANGE = 1.0 / float(np.finfo(float).eps)
#: The largest stiffness a bearing's error message allows, as a multiple of the structure's stiffest
#: term: beyond it the round-off of the stiff term (eps times the contrast) reaches the static solve's
#: tolerance (1e-10) and Newton no longer converges, although the factors may still be found.
ACCURATE_CONTRAST = 1e5


class ConvergenceError(RuntimeError):
    """Newton did not reach equilibrium (or the bearings' tangent lost the stiffness it needed)."""


class StiffnessRangeError(ModelError):
    """A bearing stiffness that the stiffness matrix cannot take: a law's tangent that is not finite,
    or a law's tangent or a connector's ``vertical_stiffness`` so much stiffer than the structure that
    the factors lose the structure in round-off (the matrix then looks singular, but the structure is
    no mechanism). Bad input: a bearing that stiff is a fixed connection.

    ``law`` (None for a vertical spring) and ``connector``: the names of the law and of the bearing;
    ``value``: the stiffness; ``limit``: the largest stiffness (N/m) this structure resolves beside
    it, None when unknown.
    """

    def __init__(self, message: str, law: str | None = None, connector: str | None = None,
                 value: float | None = None, limit: float | None = None):
        super().__init__(message)
        self.law, self.connector, self.value, self.limit = law, connector, value, limit


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


def _structure_stiffness(system: System) -> float:
    """The stiffest diagonal term of the structure without the laws (``K_free``)."""
    return float(abs(system.K_free.diagonal()).max(initial=0.0))


def _block_sizes(g, tangent) -> np.ndarray | None:
    """Per connector of group ``g``: the largest absolute term of its tangent block (NaN if any term
    is NaN), or None for a tangent of the wrong shape (reported elsewhere, naming the law)."""
    t = np.asarray(tangent, dtype=float)
    if t.shape != (g.n, g.dims, g.dims):
        return None
    return np.abs(t).reshape(g.n, -1).max(axis=1, initial=0.0)


def _assembled(system: System, blocks) -> sp.csr_matrix:
    """``K_free + B_free^T K_t B_free`` (symmetrised) from per-group tangent blocks."""
    ops = system.connectors
    Kt = ops.tangent([LawResponse(None, t, None) for t in blocks])
    Kt = (Kt + Kt.T) / 2
    return (system.K_free + system.B_free.T @ Kt @ system.B_free).tocsr()


def _capped(tangent, cap: float) -> np.ndarray:
    """Tangent blocks with the eigenvalues of their symmetric part clipped to ``+-cap`` (the stiff
    directions capped, the others kept: a block stiff along x but free along y stays free along y)."""
    t = np.asarray(tangent, dtype=float)
    values, vectors = np.linalg.eigh((t + np.swapaxes(t, 1, 2)) / 2)
    values = np.clip(values, -cap, cap)
    return np.einsum("nij,nj,nkj->nik", vectors, values, vectors)


def _stiffness_error(system: System, blocks, failure: str | None = None) -> StiffnessRangeError | None:
    """The error for the laws' tangent ``blocks`` (one per group) if one is out of range, else None.

    Out of range: a term that is not finite; one beyond :data:`OUT_OF_RANGE` times the structure's
    stiffest term; or, when the factors failed (``failure``: why), one stiffer than the structure's
    stiffest term such that, with every law capped at that term, the structure stands (so it was
    the stiff law, not a mechanism). The limit stated is where the factors' smallest pivot would fall
    below :data:`PIVOT_RATIO` of a law that stiff (the capped matrix's smallest pivot over it), or
    :data:`ACCURATE_CONTRAST` times the structure's stiffest term if that is lower.
    """
    ops = system.connectors
    stiffest = _structure_stiffness(system)
    worst = None  # (size, law name, connector name)
    sizes_per_group = []
    for g, t in zip(ops.groups, blocks, strict=True):
        sizes = _block_sizes(g, t)
        if sizes is None:
            return None
        bad = ~np.isfinite(sizes)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            terms = np.asarray(t, dtype=float).reshape(g.n, -1)[k]
            value = float(terms[~np.isfinite(terms)][0])
            name = system.model.connectors[int(g.connectors[k])].name
            return StiffnessRangeError(
                f"law {g.law.name!r} of the bearing {name!r} returned a tangent stiffness {value} (not finite): the "
                "stiffness matrix cannot be assembled; a law's tangent must be a finite number of N/m",
                law=g.law.name, connector=name, value=value,
            )
        if sizes.size and (worst is None or sizes.max() > worst[0]):
            k = int(np.argmax(sizes))
            worst = (float(sizes[k]), g.law.name, system.model.connectors[int(g.connectors[k])].name)
        sizes_per_group.append(sizes)
    if worst is None or stiffest <= 0 or worst[0] <= stiffest:
        return None  # no law is stiffer than the structure: a failure is the structure's (a mechanism)
    absurd = worst[0] > OUT_OF_RANGE * stiffest
    if not absurd and failure is None:
        return None

    def ratio_capped(cap: float) -> float:
        """The factors' smallest pivot over the largest with every law tangent capped at ``cap``."""
        capped = [_capped(t, cap) if z.size and z.max() > cap else t for t, z in zip(blocks, sizes_per_group, strict=True)]
        try:
            pivots = np.abs(spla.splu(_assembled(system, capped).tocsc()).U.diagonal())
        except RuntimeError:
            return 0.0
        return float(pivots.min()) / float(pivots.max()) if pivots.max() > 0 else 0.0

    # With the laws capped at the structure's stiffest term, does the structure stand? Then the stiff
    # law, not a mechanism, made the factors fail. Far beyond the structure's stiffness the smallest
    # pivot stays and the largest grows with the law's: the ratio falls as 1 / k, which gives the
    # largest stiffness whose ratio stays above PIVOT_RATIO.
    at_structure = ratio_capped(stiffest)
    if at_structure < PIVOT_RATIO:
        if not absurd:
            return None  # a mechanism even with the laws capped: say mechanism
        limit = None
    else:
        probe = min(worst[0], 1e4 * stiffest)
        at_probe = ratio_capped(probe)
        limit = probe * at_probe / PIVOT_RATIO if at_probe >= PIVOT_RATIO else stiffest * at_structure / PIVOT_RATIO
        limit = min(limit, ACCURATE_CONTRAST * stiffest)
    size, law, name = worst
    allowed = (f"at most about {limit:.2g} N/m for this structure" if limit is not None
               else f"at most {OUT_OF_RANGE:.1e} times the structure's stiffest term ({stiffest:.3g})")
    return StiffnessRangeError(
        f"law {law!r} of the bearing {name!r} has a tangent stiffness {size:.3g} N/m, {size / stiffest:.2g} times the "
        f"stiffest term of the structure ({stiffest:.3g}): the stiffness matrix cannot resolve the structure beside "
        f"it{f' ({failure})' if failure else ''}; this is not a mechanism. Allowed: a finite stiffness {allowed}; "
        "a connection stiffer than that is a fixed one (a rigid law or a tie)",
        law=law, connector=name, value=size, limit=limit,
    )


def _pivot_ratio(K) -> float:
    """The smallest LU pivot of ``K`` over the largest (0 when SuperLU finds it singular)."""
    try:
        pivots = np.abs(spla.splu(K.tocsc()).U.diagonal())
    except RuntimeError:
        return 0.0
    return float(pivots.min()) / float(pivots.max()) if pivots.size and pivots.max() > 0 else 0.0


def _spring_stiffness_error(K, system: System, failure: str, stabilizer=None) -> StiffnessRangeError | None:
    """After the factors of ``K`` (on the free DOFs of ``system``, holding its vertical springs) failed:
    the error naming a connector whose ``vertical_stiffness`` is why, or None (then: a mechanism).

    As for the laws (:func:`_stiffness_error`): with every spring capped at the stiffest term of the
    rest of ``K``, does the structure stand? ``stabilizer``: the ``B_free^T B_free`` that the solve
    added times :data:`STABILIZER` and the largest diagonal term (so, here, of the capped matrix)."""
    ops = system.connectors
    if K.shape != system.K_free.shape or not ops.spring_connectors.size:
        return None
    linear = ~ops.uplift
    if not linear.any():
        return None
    kv = ops.kv[linear]
    V = system.V_free[np.flatnonzero(linear)]
    rest = (K - V.T @ sp.diags(kv) @ V).tocsr()
    stiffest = float(abs(rest.diagonal()).max(initial=0.0))
    k = int(np.argmax(kv))
    if not (stiffest > 0 and kv[k] > stiffest):
        return None

    def capped(cap: float) -> float:
        trial = rest + V.T @ sp.diags(np.minimum(kv, cap)) @ V
        if stabilizer is not None:
            trial = trial + STABILIZER * float(abs(trial.diagonal()).max(initial=0.0)) * stabilizer
        return _pivot_ratio(trial)

    at_structure = capped(stiffest)
    if at_structure < PIVOT_RATIO:
        return None
    probe = min(float(kv[k]), 1e4 * stiffest)
    at_probe = capped(probe)
    limit = probe * at_probe / PIVOT_RATIO if at_probe >= PIVOT_RATIO else stiffest * at_structure / PIVOT_RATIO
    limit = min(limit, ACCURATE_CONTRAST * stiffest)
    name = system.model.connectors[int(ops.spring_connectors[np.flatnonzero(linear)[k]])].name
    return StiffnessRangeError(
        f"connector {name!r}: field 'vertical_stiffness' = {kv[k]:.3g} N/m is {kv[k] / stiffest:.2g} times the stiffest "
        f"term of the rest of the structure ({stiffest:.3g}): the stiffness matrix cannot resolve the structure beside it "
        f"({failure}); this is not a mechanism. Allowed: 0 < vertical_stiffness <= about {limit:.2g} N/m for this "
        "structure (a connection stiffer than that is a fixed one)",
        connector=name, value=float(kv[k]), limit=limit,
    )


def check_law_tangents(system: System, blocks) -> None:
    """Raise :class:`StiffnessRangeError` naming the law, the bearing and the value if a law tangent
    (``blocks``: one ``(n, dims, dims)`` array per group of ``system.connectors``) is not finite or
    beyond :data:`OUT_OF_RANGE` times the structure's stiffest term. One pass over the blocks."""
    stiffest = _structure_stiffness(system)
    bound = OUT_OF_RANGE * stiffest if stiffest > 0 else np.inf
    for g, t in zip(system.connectors.groups, blocks, strict=True):
        sizes = _block_sizes(g, t)
        if sizes is not None and not np.all(sizes <= bound):  # NaN fails too
            error = _stiffness_error(system, blocks)
            if error is not None:
                raise error
            return


def initial_stiffness_error(
    system: System, normal_forces: np.ndarray | None = None, dt: float = 1.0, failure: str | None = None
) -> StiffnessRangeError | None:
    """After a solve with the laws' initial tangents failed (``failure``: why): the
    :class:`StiffnessRangeError` naming the law and bearing to blame, or None if no law's stiffness
    explains it (then it is the structure's: a mechanism)."""
    if not system.connectors.groups:
        return None
    return _stiffness_error(system, initial_tangent_blocks(system, normal_forces, dt), failure=failure)


def _factorize_with_laws(K, system: System, blocks, **options):
    """:func:`factorize` of a matrix holding the laws' tangent ``blocks`` and the vertical springs: when
    it fails, a law's or a spring's stiffness is named if that, not a mechanism, is why."""
    try:
        return factorize(K, system=system, **options)
    except ModelError as exc:
        reason = str(exc).partition("(")[2].partition(")")[0] or "singular factors"
        error = _stiffness_error(system, blocks, failure=reason) or _spring_stiffness_error(K, system, reason)
        if error is not None:
            raise error from exc
        raise


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

    Raises :class:`StiffnessRangeError` for a law tangent that is not finite or absurdly stiff
    (:func:`check_law_tangents`).
    """
    ops = system.connectors
    if not ops.groups:
        return system.K_free
    blocks = initial_tangent_blocks(system, normal_forces, dt)
    check_law_tangents(system, blocks)
    return _assembled(system, blocks)


def initial_tangent_blocks(system: System, normal_forces: np.ndarray | None, dt: float) -> list[np.ndarray]:
    """The laws' initial tangents per group (:func:`initial_tangent`)."""
    ops = system.connectors
    N = np.zeros(ops.n_connectors) if normal_forces is None else np.asarray(normal_forces, dtype=float)
    zero = np.zeros(ops.n_governed)
    responses = ops.respond(ops.initial_states(), zero, N[ops.spring_connectors], dt)
    return ops.tangent_blocks(responses)


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
        """(n_connectors, 3) from the vertical spring forces ``kv V u``, the law forces and the multipliers;
        with instants as rows of each (``(k, ...)``), ``(k, n_connectors, 3)``."""
        law_forces = np.asarray(law_forces)
        forces = np.zeros(law_forces.shape[:-1] + (3 * self.n_connectors,))
        forces[..., self.spring_slots] = spring_forces
        forces[..., self.law_slots] = law_forces
        forces[..., self.tie_slots] = -np.asarray(multipliers)[..., self.tie_rows]  # lam: the tie's force on node j along e_k
        return forces.reshape(law_forces.shape[:-1] + (-1, 3))

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
    """Raise the mechanism error if the structure with the laws' initial tangents is singular (or
    :class:`StiffnessRangeError` if a law's stiffness is why)."""
    if system.connectors.groups:
        blocks = initial_tangent_blocks(system, _per_connector(system, N_springs), dt)
        check_law_tangents(system, blocks)
        _factorize_with_laws(_assembled(system, blocks), system, blocks)


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

    The first iteration is at the undeformed geometry, where the laws' displacement and so their
    force is zero; only their tangent depends on ``N`` there. It is taken with the normal forces of
    the load carried by the vertical springs (the governed directions free;
    :func:`_carried_normal_forces`): a friction law then has its stick stiffness, as the bearing
    has under the dead load, not the zero tangent of no contact (``N = 0`` at ``q = 0``), which
    would start Newton from the load carried with every friction bearing free, far from the
    equilibrium, from where the stick-slip switches can cycle. Only if that solve is singular
    does the first iteration take ``N = 0``.
    """
    N_start = _carried_normal_forces(system, f) if system.connectors.groups else None
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


@attrs.frozen(eq=False)
class _ActiveTrial:
    """An iterate of :func:`_newton_active` and what the laws say there."""

    q: np.ndarray
    u: np.ndarray
    N: np.ndarray  # per spring row
    follows: bool  # N is N(q) (False: the first iterate's N_start), so dF/dN belongs in the Jacobian
    responses: list
    f_law: np.ndarray
    residual: np.ndarray

    @property
    def size(self) -> float:
        return float(np.max(np.abs(self.residual), initial=0.0))

    @property
    def merit(self) -> float:
        merit = float(np.linalg.norm(self.residual))
        return merit if np.isfinite(merit) else np.inf


def _newton_active(system: System, f: np.ndarray, dt: float, tol: float, max_iter: int, N_start):
    """:func:`_active`'s Newton; ``N_start``: the normal forces of the first iteration (None: from ``q = 0``).

    The Jacobian is consistent: the laws' tangents and, for laws with dF/dN, the part of
    ``N = -kv V q`` (``-B^T E diag(kv) V``, as in the transient Jacobian). A correction that does
    not cut the residual norm by Armijo's factor is halved (at most :data:`_BACKTRACKS` times, then
    the best trial is taken): across a stick-slip switch the full correction can overshoot, and
    Newton would otherwise cycle between slip patterns. A correction that does converges takes the
    full step, so a smooth problem follows plain Newton exactly.
    """
    ops = system.connectors
    T = system.T
    f_free = T.T @ f
    states0 = ops.initial_states()

    def evaluate(q: np.ndarray, N=None) -> _ActiveTrial:
        u = T @ q
        follows = N is None
        if follows:
            N = ops.normal_forces(ops.V @ u)
        responses = ops.respond(states0, ops.B @ u, N, dt)
        f_law = ops.forces(responses)
        residual = system.K_free @ q + system.B_free.T @ f_law - f_free
        return _ActiveTrial(q, u, N, follows, responses, f_law, residual)

    def converged(trial: _ActiveTrial) -> bool:
        return trial.size <= tol * max(_force_scale(f, trial.f_law), 1e-300)

    trial = evaluate(np.zeros(system.n_free), N_start)
    for iteration in range(max_iter + 1):
        if converged(trial):
            return trial.u, trial.f_law, tuple(r.state for r in trial.responses), iteration
        if iteration == max_iter:
            scale = max(_force_scale(f, trial.f_law), 1e-300)
            raise ConvergenceError(
                f"solve_static: no equilibrium after {max_iter} Newton iterations "
                f"(residual {trial.size:.3g} vs force scale {scale:.3g})"
            )
        responses = trial.responses
        blocks = ops.tangent_blocks(responses)
        check_law_tangents(system, blocks)
        Kt = system.K_free + system.B_free.T @ ops.tangent(responses) @ system.B_free
        if ops.any_coupling and trial.follows:
            Kt = Kt + system.B_free.T @ (_normal_coupling(ops, responses, trial.N) @ system.V_free)
        try:
            lu = _factorize_with_laws(Kt, system, blocks)
        except ModelError as exc:
            if iteration == 0 or isinstance(exc, StiffnessRangeError):  # a mechanism of the structure, or a law
                raise
            slipping = _lost_stiffness(system, responses, trial.N, dt)
            raise ConvergenceError(
                "solve_static (bearings='active'): the bearings "
                f"{', '.join(map(repr, slipping)) or '(unidentified)'} slip under this load and their tangent "
                "lost the stiffness that held the structure (e.g. a girder held horizontally by friction "
                "bearings only): the equilibrium does not fix the sliding position. This is not a mechanism "
                "of the structure (it stands with the bearings' initial stiffness). For a dead load use "
                f"bearings='set-after-dead-load' (the bearings installed in the dead-load position). [{exc}]"
            ) from exc
        trial = _backtrack(evaluate, converged, trial, -lu.solve(trial.residual))


def _backtrack(evaluate, converged, current: _ActiveTrial, dq: np.ndarray) -> _ActiveTrial:
    """The iterate ``current.q + lam dq`` with the largest ``lam = 1, 1/2, ...`` that converges or cuts
    the residual norm by Armijo's factor; the smallest residual of those tried if none does."""
    best, lam = None, 1.0
    for _ in range(_BACKTRACKS + 1):
        trial = evaluate(current.q + lam * dq)
        if converged(trial) or trial.merit <= (1.0 - _ARMIJO * lam) * current.merit:
            return trial
        if best is None or trial.merit < best.merit:
            best = trial
        lam *= 0.5
    return best


def _normal_coupling(ops, responses, N_springs: np.ndarray) -> sp.csr_matrix:
    """``d f_law / d (V u)`` of the laws with dF/dN: ``-E diag(kv)``, ``E`` their ``dF/dN`` (rows of
    ``B`` by spring rows), as in the transient Jacobian; zero where ``N <= 0`` (the clamp)."""
    rows, springs, values = ops.normal_derivatives(responses, N_springs)
    return sp.csr_matrix((-values * ops.kv[springs], (rows, springs)), shape=(ops.n_governed, ops.kv.size))


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
    governed = system.B_free.T @ system.B_free
    try:
        lu = factorize(K + kappa * governed, system=system)
    except StiffnessRangeError:
        raise
    except ModelError as exc:  # a vertical spring too stiff for the factors (its kappa too)? else a mechanism
        reason = str(exc).partition("(")[2].partition(")")[0] or "singular factors"
        stiff = _spring_stiffness_error(K, system, reason, stabilizer=governed)
        if stiff is not None:
            raise stiff from exc
        raise
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
