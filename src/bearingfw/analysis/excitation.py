"""The dynamic loads of a transient run: support motion (uniform or per support group) and nodal loads.

Uniform motion (an array ``(steps, 3)``). Relative formulation: every support moves with the same
ground acceleration ``a_g(t)`` (global ``x, y, z``), and the response is measured relative to the
ground. The inertia load on the free DOFs is ``-T^T M r a_g`` with ``r = [r_x r_y r_z]`` the unit
rigid-body translations (:meth:`~bearingfw.model.System.rigid_body`): the mass that sits on
supported DOFs only loads the supports. Nodal loads (full DOF vectors, beyond the dead load already
in the preload) add ``T^T f(t)``.

Per-support motion (:class:`SupportMotion`: groups of supported nodes, each with its own
three-component acceleration). The full DOF vector is ``u = T q + S u_s(t)``: ``S`` puts each
group's three translations on its restrained translation DOFs (and on whatever rigid links and
tied connector directions make follow them: ``S`` is a particular solution of the constraint
equations ``C u = c(u_s)``, support rotations stay at zero). The free DOFs are split as
``q = q_0 + x + R u_s`` with the pseudo-static influence matrix ``R = -K_0^-1 T^T K_0,full S``,
``K_0`` the linear structure plus every law's initial tangent (:func:`~bearingfw.analysis.static.initial_tangent`;
for a deck on sliding bearings that is the stick stiffness, so ``K_0`` is regular where ``K_free``
alone is not). ``Psi = T R + S`` (full DOFs x 3 per group) is the quasi-static displacement of the
whole bridge under unit support displacements. The kernel then integrates the same equation in
``x`` as for uniform motion, with

    load(t)   = -(T^T M Psi) u_s''(t) - (T^T K Psi) u_s(t)  (+ T^T f(t))
    e(t)      = [B; V] Psi u_s(t)     added to ``[B; V] x`` (law displacements, vertical springs)
    e_rate(t) = B Psi u_s'(t)         added to the laws' velocity

(:meth:`Excitation.bearing_offset`, consumed by :func:`bearingfw.analysis.hht.step`). Every internal
force is evaluated at the total displacement, so the result does not depend on ``K_0``: ``R`` only
decides which part of the motion is "dynamic" (``x``, on which the inertia acts through ``M x''``)
and therefore which velocity the Rayleigh damping acts on: **damping acts on ``x'``**, the motion
relative to the quasi-static one (the usual engineering choice; OpenSees's ``MultipleSupport``
instead damps the absolute velocity with the mass-proportional term). Uniform motion is then
exactly today's run: ``Psi`` is the rigid-body matrix ``r``, the stiffness term and ``e`` vanish.

To keep that exact in floating point, the motion is split into a reference group's motion (the
first group unless ``reference`` names one), handled exactly as uniform motion with ``r``, and
each other group's difference from it, ``delta_k = u_k - u_ref``, which alone goes through
``Psi`` (by linearity the same equations). Identical groups give ``delta = 0``: no ``e`` and the
load ``-T^T M r a_ref``, bit for bit the uniform run.

Ground displacements. A group's difference from the reference is integrated from its
accelerations exactly for accelerations linear between samples (velocity by the trapezoid,
displacement ``u_{n+1} = u_n + h v_n + h^2 (2 a_n + a_{n+1}) / 6``); with ``baseline =
"polynomial"`` (default) a least-squares polynomial ``sum_{j=2..p} c_j t^j`` (no constant or linear
term, so the start stays at rest; ``p = baseline_degree``, default 3) is fitted to that displacement
and its second derivative removed from the difference's acceleration, which is then integrated
again: the correction acts only on the differential motion, the only part whose displacement
loads the bridge. ``displacement`` given per group (a record file that has them) is used as given
(linear between samples, velocity from its central differences), the accelerations only for the
inertia.

Samples are given every ``dt``; between samples the excitation is linear in time (so an
integration step that divides ``dt``, or a subdivided step, sees the straight line between the
record's points). The ground velocity, needed for absolute velocities, is the exact integral of
that piecewise-linear acceleration from rest.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.analysis.static import factorize, initial_tangent, initial_tangent_blocks
from bearingfw.model import NodalLoad, System
from bearingfw.parameters import ParameterError, choice, integer_parameter
from bearingfw.protocol import LawResponse

__all__ = [
    "Excitation",
    "Differential",
    "SupportMotion",
    "support_group_problem",
    "build_excitation",
    "integrate_motion",
    "pseudo_static_influence",
    "support_groups",
    "supported_nodes",
]

_AXES = ("x", "y", "z")


# ---- per-support motion ------------------------------------------------------------------------------
def _groups(value):
    if not isinstance(value, Mapping):
        return value
    out = {}
    for k, nodes in value.items():
        out[k] = (nodes,) if isinstance(nodes, str) else tuple(nodes) if isinstance(nodes, Iterable) else nodes
    return out


def _arrays(value):
    if value is None or not isinstance(value, Mapping):
        return value
    out = {}
    for k, v in value.items():
        try:
            out[k] = np.array(v, dtype=float)
        except (TypeError, ValueError):
            out[k] = v
    return out


def _check_groups(instance, attribute, value):
    if not isinstance(value, dict) or not value:
        raise ParameterError("SupportMotion: field 'groups' must be a non-empty mapping {group name: [node names]}")
    seen: dict[str, str] = {}
    for name, nodes in value.items():
        if not isinstance(name, str) or not name:
            raise ParameterError(f"SupportMotion: field 'groups' has a group name {name!r}; give non-empty strings")
        if not isinstance(nodes, tuple) or not nodes or not all(isinstance(n, str) and n for n in nodes):
            raise ParameterError(f"SupportMotion: field 'groups' entry {name!r} must be a non-empty list of node names")
        for n in nodes:
            if n in seen:
                raise ParameterError(f"SupportMotion: field 'groups' puts node {n!r} in both {seen[n]!r} and {name!r}")
            seen[n] = name


@attrs.frozen(eq=False)
class SupportMotion:
    """Ground motion per group of supported nodes (module docstring).

    ``groups``: ``{group: [node names]}``; every supported node of the model in exactly one group
    (:func:`support_groups` makes them from the positions). ``acceleration``: ``{group: (steps, 3)}``
    in m/s^2, global x, y, z, sampled every ``dt`` of the run, all groups alike long.
    ``displacement``: optional ``{group: (steps, 3)}`` in m (every group, starting at 0) where the
    record files have them; otherwise they are integrated with ``baseline`` correction of each
    group's difference from ``reference`` (default: the first group).
    """

    groups: dict = attrs.field(converter=_groups, validator=_check_groups)
    acceleration: dict = attrs.field(converter=_arrays)
    displacement: dict | None = attrs.field(default=None, converter=_arrays)
    reference: str | None = attrs.field(default=None)
    baseline: str = choice(("polynomial", "none"), default="polynomial", doc="baseline correction of the differences")
    baseline_degree: int = integer_parameter(low=2, high=8, default=3, doc="highest power of the baseline polynomial")

    def __attrs_post_init__(self):
        names = list(self.groups)
        for field in ("acceleration", "displacement"):
            table = getattr(self, field)
            if table is None and field == "displacement":
                continue
            if not isinstance(table, dict) or set(table) != set(names):
                got = sorted(table) if isinstance(table, dict) else type(table).__name__
                raise ParameterError(
                    f"SupportMotion: field {field!r} must give one (steps, 3) array for each group {names}, got {got}"
                )
        steps = None
        for field in ("acceleration", "displacement"):
            table = getattr(self, field)
            for name in names if table is not None else ():
                arr = table[name]
                if not isinstance(arr, np.ndarray) or arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] < 2:
                    shape = getattr(arr, "shape", type(arr).__name__)
                    raise ParameterError(
                        f"SupportMotion: field {field!r} of group {name!r} must have shape (steps, 3) with steps >= 2 "
                        f"(global x, y, z), got {shape}"
                    )
                if not np.all(np.isfinite(arr)):
                    raise ParameterError(f"SupportMotion: field {field!r} of group {name!r} holds non-finite values")
                if steps is None:
                    steps = arr.shape[0]
                elif arr.shape[0] != steps:
                    raise ParameterError(
                        f"SupportMotion: field {field!r} of group {name!r} has {arr.shape[0]} samples, the first group "
                        f"{steps}; every group's motion must be sampled alike"
                    )
                if field == "displacement" and np.any(arr[0] != 0.0):
                    raise ParameterError(
                        f"SupportMotion: field 'displacement' of group {name!r} must start at 0 (the run starts at rest "
                        f"from the preload), got {arr[0].tolist()}"
                    )
        if self.reference is not None and self.reference not in self.groups:
            raise ParameterError(f"SupportMotion: field 'reference' = {self.reference!r} must be one of the groups {names}")

    @property
    def steps(self) -> int:
        return next(iter(self.acceleration.values())).shape[0]

    @property
    def reference_group(self) -> str:
        return self.reference if self.reference is not None else next(iter(self.groups))

    @property
    def uniform(self) -> bool:
        """True when every group moves exactly as the reference (then the run is the uniform one)."""
        return not self.differences(1.0)[0]

    def differences(self, dt: float) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
        """``(groups, u, v, a)``: the groups that differ from the reference and their differences
        ``delta`` (steps, 3 per group), after the baseline correction (module docstring)."""
        ref = self.reference_group
        names, us, vs, accs = [], [], [], []
        for name in self.groups:
            if name == ref:
                continue
            da = self.acceleration[name] - self.acceleration[ref]
            du = None if self.displacement is None else self.displacement[name] - self.displacement[ref]
            if not np.any(da) and (du is None or not np.any(du)):
                continue
            if du is None:
                if self.baseline == "polynomial":
                    da = _baseline_corrected(da, dt, self.baseline_degree)
                du, dv = integrate_motion(da, dt)
            else:
                dv = np.gradient(du, dt, axis=0)
                dv[0] = 0.0
            names.append(name)
            us.append(du)
            vs.append(dv)
            accs.append(da)
        if not names:
            empty = np.zeros((self.steps, 0))
            return [], empty, empty, empty
        return names, np.hstack(us), np.hstack(vs), np.hstack(accs)

    def kinematics(self, dt: float) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """``{group: (u, v, a)}`` (steps, 3) each: every group's motion as the analysis applies it (the
        reference's integrated from rest, the others the reference's plus their corrected difference)."""
        ref = self.reference_group
        a_ref = self.acceleration[ref]
        if self.displacement is not None:
            u_ref = self.displacement[ref]
            v_ref = np.gradient(u_ref, dt, axis=0)
            v_ref[0] = 0.0
        else:
            u_ref, v_ref = integrate_motion(a_ref, dt)
        names, du, dv, da = self.differences(dt)
        out = {}
        for name in self.groups:
            out[name] = (u_ref, v_ref, a_ref)
        for k, name in enumerate(names):
            cols = slice(3 * k, 3 * k + 3)
            out[name] = (u_ref + du[:, cols], v_ref + dv[:, cols], a_ref + da[:, cols])
        return out


def integrate_motion(acceleration: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Displacement and velocity from rest of an acceleration linear between samples (exact)."""
    a = np.asarray(acceleration, dtype=float)
    v = np.zeros_like(a)
    u = np.zeros_like(a)
    v[1:] = np.cumsum(0.5 * dt * (a[1:] + a[:-1]), axis=0)
    u[1:] = np.cumsum(dt * v[:-1] + dt * dt * (2.0 * a[:-1] + a[1:]) / 6.0, axis=0)
    return u, v


def _baseline_corrected(acceleration: np.ndarray, dt: float, degree: int) -> np.ndarray:
    """``acceleration`` minus the second derivative of the polynomial ``sum_{j=2..degree} c_j t^j`` fitted
    (least squares) to its displacement from rest."""
    n = acceleration.shape[0]
    t = np.arange(n) * dt
    u, _ = integrate_motion(acceleration, dt)
    scale = t[-1] if t[-1] > 0 else 1.0
    s = t / scale  # powers of t / T: a well-conditioned fit
    powers = np.arange(2, degree + 1)
    basis = s[:, None] ** powers[None, :]
    coeffs, *_ = np.linalg.lstsq(basis, u, rcond=None)
    second = (powers * (powers - 1))[None, :] * s[:, None] ** (powers - 2)[None, :] / scale**2
    return acceleration - second @ coeffs


def supported_nodes(system: System) -> list[str]:
    """Names of the nodes that carry a support, in the model's order."""
    return [s.node for s in system.model.supports]


def support_groups(system_or_model, axis: str = "x", tolerance: float = 1.0, prefix: str = "support") -> dict[str, tuple[str, ...]]:
    """Supported nodes grouped by their position along global ``axis``: nodes within ``tolerance`` (m)
    of the previous one form a group (an abutment, a pier line, an arch springing line). Groups are
    named ``<prefix>1``, ``<prefix>2``, ... in increasing position."""
    if axis not in _AXES:
        raise ParameterError(f"support_groups: 'axis' must be one of x, y, z, got {axis!r}")
    if not (isinstance(tolerance, (int, float)) and np.isfinite(tolerance) and tolerance >= 0):
        raise ParameterError(f"support_groups: 'tolerance' must be a length >= 0 m, got {tolerance!r}")
    model = getattr(system_or_model, "model", system_or_model)
    names = [s.node for s in model.supports]
    if not names:
        raise ParameterError("support_groups: the model has no supports")
    coords = model.coordinates
    pos = np.array([coords[model.node_index(n), _AXES.index(axis)] for n in names])
    order = np.argsort(pos, kind="stable")
    groups: list[list[str]] = []
    last = None
    for i in order:
        if last is None or pos[i] - last > tolerance:
            groups.append([])
        groups[-1].append(names[i])
        last = pos[i]
    return {f"{prefix}{k + 1}": tuple(g) for k, g in enumerate(groups)}


def _unit_support_displacements(system: System, groups: list[tuple[str, ...]]) -> np.ndarray:
    """``S`` (n_dof, 3 per group): a particular solution of the constraint equations for a unit
    translation of each group (its nodes' restrained translations move, rotations stay)."""
    model = system.model
    cons = system.constraints
    group_of = {n: g for g, nodes in enumerate(groups) for n in nodes}
    k = 3 * len(groups)

    def rhs(equations) -> np.ndarray:
        c = np.zeros((len(equations), k))
        for i, eq in enumerate(equations):
            if eq.source == "support" and eq.component < 3:
                g = group_of.get(model.supports[eq.index].node)  # None: a group that does not move here
                if g is not None:
                    c[i, 3 * g + eq.component] = 1.0
        return c

    S = np.zeros((system.n_dof, k))
    if cons.equations:
        S = np.asarray(cons.C.T @ np.atleast_2d(cons.solve_gram(rhs(cons.equations))).reshape(len(cons.equations), k))
    # an equation eliminated as redundant (a tie or link between supported nodes) must hold too
    for eq, want in zip(cons.redundant, rhs(cons.redundant), strict=True):
        got = eq.coefficients @ S[eq.dofs]
        if np.max(np.abs(got - want), initial=0.0) > 1e-9 * max(1.0, float(np.max(np.abs(eq.coefficients)))):
            owner = {"support": model.supports, "link": model.rigid_links, "connector": model.connectors}[eq.source]
            raise ParameterError(
                f"SupportMotion: {getattr(owner[eq.index], 'name', eq.source)!r} joins supported nodes of different "
                f"groups rigidly; put them in one group"
            )
    return S


def pseudo_static_influence(
    system: System, groups: list[tuple[str, ...]], normal_forces: np.ndarray | None = None
) -> np.ndarray:
    """``Psi = T R + S`` (n_dof, 3 per group): the quasi-static displacement of every DOF under a unit
    translation of each group, with the laws at their initial tangent (module docstring)."""
    S = _unit_support_displacements(system, groups)
    ops = system.connectors
    blocks = initial_tangent_blocks(system, normal_forces, 1.0) if ops.groups else []
    K0 = initial_tangent(system, normal_forces)  # K_free + B_free^T Kt B_free, with the tangent checks
    # T^T K0_full S = T^T K S + B_free^T Kt (B S): S also moves the supported ends of the bearings
    KS = system.T.T @ (system.K @ S)
    if ops.groups:
        Kt = ops.tangent([LawResponse(None, t, None) for t in blocks])
        KS = KS + system.B_free.T @ (((Kt + Kt.T) / 2) @ (ops.B @ S))
    try:
        lu = factorize(K0, system=system)
    except Exception as exc:  # noqa: BLE001 - a ModelError or LawStiffnessError: say what it was for
        raise ParameterError(
            f"SupportMotion: the pseudo-static influence needs the structure with its bearings at their initial "
            f"tangent to stand: {exc}"
        ) from exc
    R = -lu.solve(np.asarray(KS))
    return np.asarray(system.T @ R) + S


# ---- the excitation -------------------------------------------------------------------------------------
@attrs.frozen(eq=False)
class Differential:
    """The differential support motion of a run: the groups that differ from the reference, their
    differences (steps, 3 per group), and what ``Psi`` maps them to (module docstring)."""

    groups: tuple[str, ...]
    u: np.ndarray  # (steps, k)
    v: np.ndarray
    a: np.ndarray
    given: bool  # displacements given (linear between samples), else integrated (cubic between samples)
    psi: np.ndarray  # (n_dof, k)
    inertia: np.ndarray  # (n_free, k): T^T M Psi
    stiffness: np.ndarray  # (n_free, k): T^T K Psi
    BV: np.ndarray  # (m + n_springs, k): [B; V] Psi
    m: int


@attrs.frozen(eq=False)
class Excitation:
    """Ground motion and nodal loads sampled every ``dt``, linear in between.

    ``acceleration``: the reference group's (uniform motion: every support's); ``differential``:
    the other groups' differences, None for uniform motion (module docstring)."""

    dt: float
    acceleration: np.ndarray  # (steps, 3), m/s^2
    velocity: np.ndarray  # (steps, 3), m/s
    P: np.ndarray  # (n_free, 3): T^T M R
    R: np.ndarray  # (n_dof, 3): rigid-body translations
    T: sp.csr_matrix
    nodal_full: np.ndarray | None  # (n_dof,) constant or (steps, n_dof), full DOFs
    differential: Differential | None = None
    support: SupportMotion | None = None

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
        """Ground acceleration and velocity (3,) at time ``t`` (of the reference group)."""
        if self.steps == 1:
            return self.acceleration[0], self.velocity[0]
        i, w = self._where(t)
        if w == 0.0:  # at a sample (every step when the record's dt is the step): the formulas below at w = 0
            return self.acceleration[i], self.velocity[i]
        a0, a1 = self.acceleration[i], self.acceleration[i + 1]
        acc = (1.0 - w) * a0 + w * a1
        vel = self.velocity[i] + self.dt * (w * a0 + 0.5 * w * w * (a1 - a0))
        return acc, vel

    def grounds(self, times) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`ground` at each of ``times``, one row each, the same values, as array operations."""
        times = np.asarray(times, dtype=float)
        if self.steps == 1:
            return np.tile(self.acceleration[0], (times.size, 1)), np.tile(self.velocity[0], (times.size, 1))
        i, w = self._wheres(times)
        a0, a1 = self.acceleration[i], self.acceleration[i + 1]
        at_sample = w == 0.0
        acc = np.where(at_sample, a0, (1.0 - w) * a0 + w * a1)
        vel = np.where(at_sample, self.velocity[i], self.velocity[i] + self.dt * (w * a0 + 0.5 * w * w * (a1 - a0)))
        return acc, vel

    def _wheres(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`_where` of each of ``times`` (more than one sample): indices, and weights as a column."""
        tau = np.minimum(np.maximum(times / self.dt, 0.0), self.steps - 1.0)
        i = np.minimum(tau.astype(np.int64), self.steps - 2)
        return i, (tau - i)[:, None]

    def support_differences(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """The differential support displacement, velocity and acceleration (3 per differing group) at
        ``t``, None for uniform motion. Integrated differences are exact for the piecewise-linear
        acceleration; given displacements are linear between samples."""
        dif = self.differential
        if dif is None:
            return None
        i, w = self._where(t)
        a0, a1 = dif.a[i], dif.a[i + 1]
        acc = (1.0 - w) * a0 + w * a1
        if dif.given:
            return (1.0 - w) * dif.u[i] + w * dif.u[i + 1], (1.0 - w) * dif.v[i] + w * dif.v[i + 1], acc
        h = self.dt
        tau = w * h
        vel = dif.v[i] + tau * a0 + (a1 - a0) * tau * w / 2.0
        disp = dif.u[i] + dif.v[i] * tau + a0 * tau * tau / 2.0 + (a1 - a0) * tau * tau * w / 6.0
        return disp, vel, acc

    def pseudo_static(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """``Psi delta`` and its rates (full DOFs) at ``t``: the quasi-static displacement, velocity and
        acceleration of the bridge under the differential support motion (None for uniform motion)."""
        diff = self.support_differences(t)
        if diff is None:
            return None
        psi = self.differential.psi
        return psi @ diff[0], psi @ diff[1], psi @ diff[2]

    def nodal(self, t: float) -> np.ndarray | None:
        """Full nodal load vector at ``t`` (None without nodal loads)."""
        if self.nodal_full is None:
            return None
        if self.nodal_full.ndim == 1:
            return self.nodal_full
        return self._sample(self.nodal_full, t)

    def loads(self, times) -> np.ndarray:
        """:meth:`load` at each of ``times`` (s), one row each, the same values; for uniform motion
        without time-varying nodal loads as array operations (the time loop takes a run of steps'
        loads at once, :mod:`bearingfw.analysis.hht_steps`)."""
        times = np.asarray(times, dtype=float)
        varying = self.nodal_full is not None and self.nodal_full.ndim > 1
        if self.differential is not None or varying or self.steps == 1:
            return np.array([self.load(t) for t in times.tolist()]).reshape(times.size, self.P.shape[0])
        i, w = self._wheres(times)  # _sample, element by element as it computes one instant
        table = self.acceleration
        a = np.where(w == 0.0, table[i], (1.0 - w) * table[i] + w * table[i + 1])
        F = self._inertia(a)
        return F if self.nodal_full is None else F + self.T.T @ self.nodal_full

    def bearing_offset(self, t: float) -> tuple[np.ndarray, np.ndarray] | None:
        """What differential support motion adds, at ``t``, to the kernel's ``[B; V] x`` (the law
        displacements, then the vertical springs' shortening) and the rate of its ``B`` rows, or None.

        Uniform motion moves every support alike: it deforms no bearing, so this is None and a step
        is exactly what it always was (:func:`bearingfw.analysis.hht.step`). It is zero at ``t = 0``
        (the run starts from the preload at rest): ``e = [B; V] Psi delta(t)``, ``e_rate = B Psi delta'(t)``."""
        diff = self.support_differences(t)
        if diff is None:
            return None
        dif = self.differential
        return dif.BV @ diff[0], dif.BV[: dif.m] @ diff[1]

    def _inertia(self, a: np.ndarray) -> np.ndarray:
        """``-P a`` for a ground acceleration ``a`` (3,), or for rows of them (k, 3): the three
        products summed in this order, so that a row of many is bit for bit that of one instant
        (a BLAS product may sum them otherwise for one vector than for a matrix)."""
        P = self.P
        return -(P[:, 0] * a[..., 0:1] + P[:, 1] * a[..., 1:2] + P[:, 2] * a[..., 2:3])

    def load(self, t: float) -> np.ndarray:
        """The dynamic load on the free DOFs at ``t``: ``-T^T M r a_g(t) + T^T f(t)``, and under
        differential motion ``- T^T M Psi delta''(t) - T^T K Psi delta(t)``."""
        F = self._inertia(self._sample(self.acceleration, t))
        diff = self.support_differences(t)
        if diff is not None:
            F = F - self.differential.inertia @ diff[2] - self.differential.stiffness @ diff[0]
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


def support_group_problem(system: System, groups: Mapping[str, Sequence[str]]) -> str | None:
    """What is wrong with support ``groups`` (group -> node names) on ``system``: a node unknown or
    without a support, or a supported node in no group; None if every supported node is in exactly
    one group and nothing else in any (the groups' own duplicates are refused where they are made)."""
    supported = supported_nodes(system)
    grouped = {n for nodes in groups.values() for n in nodes}
    known = set(system.model.node_names)
    unknown = sorted(n for n in grouped if n not in known)
    if unknown:
        return f"support groups name unknown nodes {unknown}"
    unsupported = sorted(n for n in grouped if n not in set(supported))
    if unsupported:
        return f"support groups name nodes without a support {unsupported}; the supported nodes are {supported}"
    missing = [n for n in supported if n not in grouped]
    if missing:
        return (f"support groups leave supported nodes {missing} in no group; every supported node needs a group "
                "(bearingfw.analysis.excitation.support_groups makes them)")
    return None


def _check_support_groups(system: System, motion: SupportMotion) -> None:
    """Every supported node in exactly one group, and nothing else in any."""
    problem = support_group_problem(system, motion.groups)
    if problem is not None:
        raise ParameterError(f"solve_transient: 'ground_acceleration' {problem}")


def _differential(system: System, motion: SupportMotion, dt: float, normal_forces) -> Differential | None:
    names, du, dv, da = motion.differences(dt)
    if not names:
        return None
    psi = pseudo_static_influence(system, [motion.groups[n] for n in names], normal_forces)
    ops = system.connectors
    T = system.T
    BV = np.vstack([np.asarray(ops.B @ psi).reshape(-1, psi.shape[1]), np.asarray(ops.V @ psi).reshape(-1, psi.shape[1])])
    return Differential(
        groups=tuple(names), u=du, v=dv, a=da, given=motion.displacement is not None, psi=psi,
        inertia=np.asarray(T.T @ (system.M @ psi)), stiffness=np.asarray(T.T @ (system.K @ psi)),
        BV=BV, m=ops.B.shape[0],
    )


def _uniform_array(ground_acceleration) -> np.ndarray:
    ag = np.asarray(ground_acceleration, dtype=float)
    if ag.ndim != 2 or ag.shape[1] != 3 or ag.shape[0] < 2:
        raise ParameterError(
            f"solve_transient: 'ground_acceleration' must have shape (steps, 3) with steps >= 2 "
            f"(x, y, z in m/s^2), or be a SupportMotion, got {ag.shape}"
        )
    if not np.all(np.isfinite(ag)):
        raise ParameterError("solve_transient: 'ground_acceleration' holds non-finite values")
    return ag.copy()


def build_excitation(system: System, ground_acceleration, dt: float, nodal_loads=None, preload=None) -> Excitation:
    """Check the inputs of :func:`~bearingfw.analysis.solve_transient` and build the excitation.

    ``ground_acceleration``: (steps, 3) in m/s^2 (global x, y, z), the same at every support; or a
    :class:`SupportMotion` (per support group); or an object with a method
    ``support_motion(system, dt) -> SupportMotion`` (motion generated from the supports' positions,
    e.g. by :mod:`bearingfw.experiment.records`). ``dt`` its sampling step (s).
    ``nodal_loads``: None, NodalLoad objects or a full vector (constant from ``t = 0``), or an array
    (steps, n_dof) sampled like the ground motion. ``preload``: the gravity preload whose normal forces
    the laws' initial tangents in ``K_0`` use (default: ``N = 0``; the built-in laws' initial tangent
    does not depend on ``N``).
    """
    if not (isinstance(dt, (int, float, np.floating)) and not isinstance(dt, bool) and np.isfinite(dt) and dt > 0):
        raise ParameterError(f"solve_transient: 'dt' = {dt!r} must be a time step > 0 s")
    motion = None
    deferred = getattr(ground_acceleration, "support_motion", None)
    if callable(deferred):
        motion = deferred(system, float(dt))
    elif isinstance(ground_acceleration, SupportMotion):
        motion = ground_acceleration
    if motion is not None:
        if not isinstance(motion, SupportMotion):
            raise ParameterError(f"solve_transient: 'ground_acceleration'.support_motion gave {type(motion).__name__}, "
                                 "not a SupportMotion")
        _check_support_groups(system, motion)
        ag = np.array(motion.acceleration[motion.reference_group], dtype=float)
        normal_forces = None if preload is None else preload.normal_forces
        differential = _differential(system, motion, float(dt), normal_forces)
    else:
        ag = _uniform_array(ground_acceleration)
        differential = None
    velocity = np.zeros_like(ag)
    velocity[1:] = np.cumsum(0.5 * float(dt) * (ag[1:] + ag[:-1]), axis=0)
    R = np.column_stack([system.rigid_body(d) for d in ("x", "y", "z")])
    P = np.asarray(system.reduce(system.M @ R))
    return Excitation(
        float(dt), ag, velocity, P, R, system.T, _nodal_array(system, nodal_loads, ag.shape[0]), differential, motion
    )
