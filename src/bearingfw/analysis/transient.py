"""Transient (time-history) analysis: HHT-alpha with Newton on the bearing laws.

Solves, on the free DOFs, the relative-formulation equation of motion of a bridge under the same
3-component support acceleration at every support (optional dynamic nodal loads)::

    M a + C v + f_int(q) = F_dead - M r a_g(t) + f(t),   f_int(q) = K q + B^T f_law(B q, N(V q))

from the gravity preload (:func:`~bearingfw.analysis.gravity`): ``q_0``, the committed law states
and their reference (the laws see ``B q - law_reference``: bearings set after the dead load start
at zero law displacement, in stick), ``v_0 = 0``. The dead load stays applied as the constant internal force of the preload
(``K q_0 + B^T f_0``, equal to the applied dead load within the static tolerance), so the preload
is an exact rest state; the unknowns are the dynamic part ``x = q - q_0``. ``a_0`` follows from
``M a_0 = F(0)`` (zero when the excitation starts at rest; massless DOFs follow the massive ones
quasi-statically). Bearing normal forces ``N = -kv V q`` follow the vertical response: every law
call reads the current ``N`` (and a law that declares ``uses_velocity`` its trial velocity,
:mod:`bearingfw.analysis.hht`). A bearing with ``uplift=True`` lifts off when its vertical spring
would pull: ``N = 0``, no vertical stiffness, no friction, until the gap closes again
(:mod:`bearingfw.model.connectors`); :attr:`TransientResult.uplift` counts the lift-offs, the time
lifted and the peak gap of each, over every integration step.

Time stepping (:mod:`bearingfw.analysis.hht`): HHT-alpha, ``gamma = 1/2 - alpha``,
``beta = (1 - alpha)^2 / 4``; Newton with the laws' consistent tangents, on the bearing
directions alone (fast path: the linear effective matrix is factorised once per step size and
condensed onto the ``m`` bearing directions) or on all DOFs (general path, for checking). A step
that does not converge is halved (``max_halvings`` times at most, reusing the factors of each
step size); the excitation is linear between its samples, so sub-steps and an integration step
that divides the record's ``dt`` see interpolated values. If it still fails,
:class:`TransientError` names the time, the connectors still moving and the residual, and holds
the result recorded up to the last converged instant. An exception from a law, a recorder or the
``progress`` callback is wrapped the same way (a :class:`TransientError` with the partial result,
the original as its ``__cause__``). Where a step needs no Python (:func:`bearingfw.analysis.hht.steps_plan`:
no laws, linear laws or compiled laws, under uniform support motion), runs of consecutive steps
are one compiled call each (:mod:`bearingfw.analysis.hht_steps`), with the same arithmetic; the
recorders and the progress callback still see every step, and a step such a run cannot finish is
solved (and halved, or reported) as above.

Damping: :class:`~bearingfw.analysis.damping.Rayleigh`, ``C = alpha M + beta K_free`` with
``K_free`` the linear structure (not the laws: see :mod:`bearingfw.analysis.damping` for why;
nor the compression-only springs of uplift bearings, which are laws of the kernel: a dashpot
across an open gap would pull the lifted girder back).

Energy: kinetic, strain, damping, bearing work and input work are accumulated every step
(:mod:`bearingfw.analysis.energy`); ``TransientResult.energy_error`` reports the imbalance, which
for ``alpha < 0`` includes HHT's numerical dissipation; ``TransientResult.balance_error`` leaves
that out (the column ``numerical``) and must be tiny for every ``alpha``.

Two "alpha"s: ``TransientSettings.alpha`` is HHT's (numerical dissipation, ``-1/3 .. 0``);
``Rayleigh.alpha`` is the mass-proportional damping coefficient (1/s). The paper names both so.

Default ``alpha = -0.05``: a little numerical dissipation removes the spurious high-frequency
response that stick/slip switches and the stiff vertical bearing springs excite, while the modes
of interest are barely touched: HHT's algorithmic damping ratio grows like ``(omega dt)^3`` (with
``alpha = -0.05``: 6e-6 at ``omega dt = 0.1``, i.e. 1.5 Hz at dt = 0.01 s; 6e-4 at 0.5; 4e-3 at
1.0) and the period elongation is about ``0.095 (omega dt)^2`` (0.083 for ``alpha = 0``). It is
also the value of Abaqus/Standard's HHT for transient-fidelity analyses, the code the paper used
(as we recall its documentation; not checked against it here). ``alpha = 0`` (average acceleration:
no numerical dissipation, an exact discrete energy balance) is one setting away.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable, Sequence

import attrs
import numpy as np
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

from bearingfw.analysis import hht
from bearingfw.analysis.damping import Rayleigh
from bearingfw.analysis.excitation import Excitation, build_excitation
from bearingfw.analysis.history import TransientResult, energy_table
from bearingfw.analysis.recorders import CHUNK, RESERVED_NAMES, Context, Samples, Snapshot
from bearingfw.analysis.static import StaticResult, factorize, gravity
from bearingfw.model import Model, ModelError, System, as_system
from bearingfw.parameters import ParameterError, choice, integer_parameter, parameter
from bearingfw.plugins import Registry

__all__ = ["TransientSettings", "TransientError", "solve_transient", "initial_acceleration", "build_problem", "PATHS"]

PATHS = ("fast", "general")


@attrs.frozen
class TransientSettings:
    """Integration and convergence settings of :func:`solve_transient`.

    ``alpha``: the HHT-alpha parameter (0: Newmark's average acceleration; more negative: more
    numerical dissipation of high frequencies); not Rayleigh's ``alpha`` (the mass-proportional
    damping coefficient of :class:`~bearingfw.analysis.Rayleigh`). ``dt_integration``: integration
    step, a divisor of the excitation's ``dt`` (default: ``dt``). ``tol_force``: force residual
    relative to the step's force scale (on the fast path its linearisation, blind to a sliding
    bearing's zero-tangent direction: there ``tol_displacement`` decides); ``tol_displacement``:
    Newton correction of the bearing displacements relative to their motion. ``max_iterations``
    Newton iterations (each with a backtracking line search) per step, then up to
    ``max_halvings`` halvings of the step.
    ``path``: ``"fast"`` (condensed onto the bearing directions) or ``"general"`` (full Newton).
    """

    alpha: float = parameter(low=-1.0 / 3.0, high=0.0, default=-0.05, doc="HHT-alpha (numerical dissipation), not Rayleigh's")
    dt_integration: float | None = parameter(optional=True, low=0.0, low_open=True, unit="s", doc="integration step")
    tol_force: float = parameter(low=0.0, low_open=True, high=1e-2, default=1e-8, doc="relative force residual")
    tol_displacement: float = parameter(
        low=0.0, low_open=True, high=1e-2, default=1e-10, doc="relative displacement correction"
    )
    max_iterations: int = integer_parameter(low=1, high=1000, default=25, doc="Newton iterations per step")
    max_halvings: int = integer_parameter(low=0, high=30, default=6, doc="step halvings before giving up")
    path: str = choice(PATHS, default="fast", doc="Newton on the bearing directions or on all DOFs")


@attrs.define(auto_exc=True, eq=False, str=False)
class TransientError(RuntimeError):
    """A step did not converge even after ``max_halvings`` halvings, or the run was stopped by an
    exception from a law, a recorder or the progress callback (then ``__cause__``).

    ``time``: where the failing sub-step ended; ``last_converged``: the last converged instant;
    ``connectors``: names of the connectors whose bearing displacements were still changing most
    (empty when an exception stopped the run); ``residual``: the force residual relative to the
    step's force scale (NaN when an exception stopped the run); ``result``: the
    :class:`TransientResult` recorded up to ``last_converged`` (None if even that failed).
    """

    message: str
    time: float
    last_converged: float
    connectors: tuple[str, ...]
    residual: float
    result: TransientResult | None = None

    def __str__(self) -> str:
        return self.message


def initial_acceleration(M, K, load: np.ndarray) -> np.ndarray:
    """``a_0`` with ``M a_0 = load`` on the DOFs with mass; massless DOFs follow quasi-statically.

    For a massless DOF set ``s`` the equilibrium rows carry no inertia, so their acceleration is
    the second time derivative of static condensation, ``a_s = -K_ss^{-1} K_sm a_m`` (with the
    linear structure's ``K``; only the first step's massless accelerations depend on it).
    """
    a = np.zeros(M.shape[0])
    if not np.any(load):
        return a
    massive = np.abs(M.diagonal()) > 0
    m, s = np.flatnonzero(massive), np.flatnonzero(~massive)
    Mc = M.tocsc()
    try:
        a[m] = factorize(Mc[m][:, m]).solve(load[m])
    except ModelError:  # a singular mass block (e.g. a mass-less mode in a consistent matrix)
        a[m] = spla.lsqr(Mc[m][:, m], load[m], atol=1e-14, btol=1e-14)[0]
    if s.size:
        Kc = K.tocsc()
        try:
            a[s] = -factorize(Kc[s][:, s]).solve(Kc[s][:, m] @ a[m])
        except ModelError:
            pass  # massless DOFs without stiffness of their own: leave their start acceleration at 0
    return a


def _system_and_preload(system_or_model, preload, registry) -> tuple[System, StaticResult]:
    if preload is None:
        system = as_system(system_or_model, registry)
        return system, gravity(system)
    if not isinstance(preload, StaticResult):
        raise ParameterError(f"solve_transient: 'preload' must be a StaticResult, got {type(preload).__name__}")
    system = preload.system
    if isinstance(system_or_model, System) and system_or_model is not system:
        raise ParameterError("solve_transient: 'preload' was computed on another System")
    if isinstance(system_or_model, Model) and system_or_model is not system.model:
        raise ParameterError("solve_transient: 'preload' was computed on another Model")
    if not isinstance(system_or_model, (System, Model)):
        raise ModelError(f"solve_transient needs a Model or a System, got {type(system_or_model).__name__}")
    return system, preload


def _substeps(settings: TransientSettings, dt: float) -> int:
    if settings.dt_integration is None:
        return 1
    ratio = dt / settings.dt_integration
    k = round(ratio)
    if k < 1 or abs(k - ratio) > 1e-9 * ratio:
        raise ParameterError(
            f"TransientSettings: parameter 'dt_integration' = {settings.dt_integration!r} must divide the "
            f"excitation time step dt = {dt!r} (dt / dt_integration = {ratio:.6g})"
        )
    return k


def build_problem(system: System, preload: StaticResult, damping: Rayleigh, settings: TransientSettings) -> hht.Problem:
    """The :class:`~bearingfw.analysis.hht.Problem` a run solves (free DOFs, from the preload)."""
    ops = system.connectors
    q0 = preload.q
    dead = system.reduce(preload.load)
    return hht.Problem(
        M=system.M_free,
        K=system.K_free,
        B=system.B_free,
        Bt=system.B_free.T.tocsr(),
        V=system.V_free,
        kv=ops.kv,
        a0=damping.alpha,
        a1=damping.beta,
        scheme=hht.Scheme(settings.alpha),
        ops=ops,
        # the laws see B q - law_reference (bearings set after the dead load: zero at the preload)
        d0=system.B_free @ q0 - preload.law_reference,
        f0=np.asarray(preload.law_forces, dtype=float),
        N0=ops.normal_forces(system.V_free @ q0),
        force_floor=1e-6 * float(np.max(np.abs(dead), initial=0.0)),
        tol_force=settings.tol_force,
        tol_displacement=settings.tol_displacement,
        max_iterations=settings.max_iterations,
        fast=settings.path == "fast",
    )


class _UpliftTally:
    """Lift-offs, time lifted and peak gap of the uplift connectors, from every committed (sub)step
    (:attr:`TransientResult.uplift`)."""

    def __init__(self, system: System, problem: hht.Problem):
        ops = system.connectors
        self.rows = ops.gap_rows
        self.names = [system.model.connectors[c].name for c in ops.gap_group.connectors] if self.rows.size else []
        self.lift_offs = np.zeros(self.rows.size, dtype=int)
        self.lifted_time = np.zeros(self.rows.size)
        self.peak_gap = np.maximum(problem.d0[self.rows], 0.0)

    def advance(self, d_before: np.ndarray, d_after: np.ndarray, h: float) -> None:
        a, b = d_before[self.rows], d_after[self.rows]  # total d_z: > 0 open
        opens, closes = (a <= 0.0) & (b > 0.0), (a > 0.0) & (b <= 0.0)
        self.lift_offs += opens
        # the part of the step with the gap open, the gap linear over the step
        with np.errstate(divide="ignore", invalid="ignore"):
            part = np.where(opens, b / (b - a), np.where(closes, a / (a - b), np.where(a > 0.0, 1.0, 0.0)))
        self.lifted_time += h * part
        self.peak_gap = np.maximum(self.peak_gap, b)

    def summary(self) -> dict[str, dict[str, float]]:
        return {
            name: {"lift_offs": int(n), "lifted_time": float(t), "peak_gap": float(g)}
            for name, n, t, g in zip(self.names, self.lift_offs, self.lifted_time, self.peak_gap, strict=True)
        }


class _Run:
    """The time loop: sub-stepping, recording, statistics."""

    def __init__(self, problem: hht.Problem, excitation: Excitation, probes, k: int, progress, system: System):
        self.p = problem
        self.exc = excitation
        self.system = system
        self.probes = probes
        self.h = excitation.dt / k
        self.n_steps = (excitation.steps - 1) * k
        self.progress = progress
        self.operators: dict[float, hht.Operator] = {}
        self.stats = {
            "steps": 0, "substeps": 0, "subdivisions": 0, "iterations": 0, "max_iterations": 0,
            "failed_iterations": 0, "backtracks": 0,
        }
        self.attempt = 0.0  # end of the sub-step being attempted (for the message of an exception)
        self.energy_rows: list[tuple[float, ...]] = []
        self.energy_times: list[float] = []
        self.times: list[float] = []
        self.last: hht.State | None = None
        self.uplift = _UpliftTally(system, problem) if problem.ops.gap_group is not None else None

    def operator(self, h: float) -> hht.Operator:
        if h not in self.operators:
            self.operators[h] = hht.build_operator(self.p, h)
        return self.operators[h]

    def record(self, s: hht.State, n: int | None) -> None:
        """Sample the recorders due at step ``n`` (``None``: the last converged instant of a failed
        run, for every recorder that has not sampled it yet)."""
        if n is not None or s.t > self.times[-1]:
            self.times.append(s.t)
            self.energy_times.append(s.t)
            self.energy_rows.append(s.energy.row())
        snap = None
        for probe in self.probes:
            if (n is None and probe.times[-1] < s.t) or (n is not None and n % probe.every == 0):
                if snap is None:
                    ag, vg = self.exc.ground(s.t)
                    snap = Snapshot(
                        s.t, s.x, s.v, s.a, s.f, s.law_states, ag, vg, self.exc.nodal(s.t), d=s.d, a_equilibrium=s.ae
                    )
                probe.sample(snap)

    def advance(self, s: hht.State, t0: float, h: float, depth: int) -> hht.State:
        t1 = t0 + h
        self.attempt = t1
        try:
            new, iterations, backtracks = hht.step(
                self.p, self.operator(h), s, t1, self.exc.load(t1), self.exc.bearing_offset(t1)
            )
        except hht.StepFailure as failure:
            self.stats["failed_iterations"] += failure.iterations
            if depth >= self.max_halvings:
                raise _Failed(failure, s, t1) from None
            self.stats["subdivisions"] += 1
            mid = self.advance(s, t0, h / 2, depth + 1)
            return self.advance(mid, t0 + h / 2, h / 2, depth + 1)
        self.committed(s, new, iterations, backtracks, h)
        return new

    def committed(self, s: hht.State, new: hht.State, iterations: int, backtracks: int, h: float) -> None:
        """Count a converged (sub)step from ``s`` to ``new``."""
        self.stats["substeps"] += 1
        self.stats["iterations"] += iterations
        self.stats["backtracks"] += backtracks
        self.stats["max_iterations"] = max(self.stats["max_iterations"], iterations)
        if self.uplift is not None:
            self.uplift.advance(s.d, new.d, h)
        self.last = new

    def run(self, state: hht.State, max_halvings: int) -> hht.State:
        self.max_halvings = max_halvings
        self.record(state, 0)
        total = self.n_steps
        h = self.h
        # runs of steps in one compiled call where a step needs no Python (hht.steps_plan); uniform
        # motion only (a step under differential motion has an offset)
        plan = hht.steps_plan(self.p, self.operator(h)) if self.exc.differential is None else None
        n = 0
        length = plan.block if plan is not None else 0  # steps asked of the next compiled call
        while n < total:
            if plan is not None:
                ask = min(length, total - n)
                if ask >= CHUNK:  # end where the recorders' chunks end: they take the run's arrays as they are
                    ask -= (n + ask + 1) % CHUNK
                times = [(n + j) * h + h for j in range(ask)]
                loads = self.exc.loads(times)
                self.attempt = times[0]
                try:
                    steps = hht.advance_steps(plan, state, times, loads)[0]
                except Exception:  # noqa: BLE001 - the Python step meets it again, at its own step, and reports it
                    steps = None
                done = 0 if steps is None else len(steps)
                if done:
                    state = self.take_steps(state, steps, n, total)
                    n += done
                if done == len(times):
                    length = min(plan.block, 2 * length)
                    continue
                # where a law keeps declining, a call per step costs little: ask for one step, then more
                length = length if done else 1
            # a step the compiled run could not finish (or every step without a plan): Python, with halvings
            state = self.advance(state, n * h, h, 0)
            n += 1
            self.after_step(state, n, total)
        return state

    def take_steps(self, s: hht.State, steps: hht.Steps, n: int, total: int) -> hht.State:
        """Commit, record and report the steps ``n + 1, n + 2, ...`` of a compiled run from ``s``, as
        :meth:`committed` and :meth:`after_step` do each step; return the last state.

        Probes with ``sample_many`` read the run's arrays side by side, once; the others, and the
        progress callback, see each step in turn. Where one of those raises at a step, the run ends
        there, as the step-by-step loop would: the steps after it are not taken."""
        singles = [p for p in self.probes if not _takes_samples(p)]
        samples = self._samples(steps) if self.probes else None
        done, failure = steps.done, None
        if singles or self.progress is not None:
            for j in range(done):
                k = n + 1 + j
                try:
                    due = [p for p in singles if k % p.every == 0]
                    if due:
                        snap = samples.snapshot(j)
                        for probe in due:
                            probe.sample(snap)
                    if self.progress is not None and (100 * k) // total > (100 * (k - 1)) // total:
                        self.stats["steps"] = k
                        self.progress(k / total)  # each whole percent once
                except Exception as exc:  # noqa: BLE001 - raised again below, once the steps up to it are kept
                    done, failure = j + 1, exc
                    break
        stats = self.stats
        stats["substeps"] += done
        stats["iterations"] += int(steps.iterations[:done].sum())
        stats["backtracks"] += int(steps.backtracks[:done].sum())
        stats["max_iterations"] = max(stats["max_iterations"], int(steps.iterations[:done].max()))
        stats["steps"] = n + done
        if self.uplift is not None:
            before = s.d
            for after in steps.d[:done]:
                self.uplift.advance(before, after, steps.plan.op.h)
                before = after
        self.attempt = float(steps.times[done - 1])
        self.last = steps.state(done - 1)
        times = steps.times[:done].tolist()
        self.times.extend(times)
        self.energy_times.extend(times)
        self.energy_rows.extend(steps.energy_rows()[:done])
        numbers = np.arange(n + 1, n + 1 + done)
        for probe in self.probes:  # every probe gets the run, even after one raised: no gaps in the others
            if probe not in singles:
                due = np.flatnonzero(numbers % probe.every == 0)
                if due.size:
                    try:
                        probe.sample_many(samples if due.size == steps.done else samples.take(due))
                    except Exception as exc:  # noqa: BLE001 - raised below, after the other probes
                        failure = failure or exc
        if failure is not None:
            raise failure
        return self.last

    def _samples(self, steps: hht.Steps) -> Samples:
        """The instants of a compiled run as the recorders read them."""
        ground = self.exc.grounds(steps.times)
        nodal = [self.exc.nodal(t) for t in steps.times.tolist()]
        return Samples(
            steps.law_states, t=steps.times, x=steps.x, v=steps.v, a=steps.a, f=steps.f,
            ground_acceleration=ground[0], ground_velocity=ground[1],
            nodal=None if nodal[0] is None else np.array(nodal), d=steps.d, a_equilibrium=steps.ae,
        )  # fmt: skip

    def after_step(self, state: hht.State, n: int, total: int) -> None:
        """Record step ``n`` (of ``total``) and report progress."""
        self.stats["steps"] = n
        self.record(state, n)
        if self.progress is not None and (100 * n) // total > (100 * (n - 1)) // total:
            self.progress(n / total)  # each whole percent once


def _takes_samples(probe) -> bool:
    """Whether ``probe`` takes a run of instants at once: it has ``sample_many``, and its ``sample`` is
    not newer than that (a ``sample`` set on the instance, e.g. a wrapper, or overridden in a subclass
    that inherits ``sample_many``, must see every instant)."""
    if "sample" in getattr(probe, "__dict__", {}):
        return False
    mro = type(probe).__mro__

    def owner(name):
        return next((k for k, cls in enumerate(mro) if name in vars(cls)), None)

    many, one = owner("sample_many"), owner("sample")
    return many is not None and (one is None or one >= many)


class _Failed(Exception):
    def __init__(self, failure: hht.StepFailure, state: hht.State, t1: float):
        super().__init__(failure.reason)
        self.failure, self.state, self.t1 = failure, state, t1


def _connector_names(system: System, rows: np.ndarray, limit: int = 5) -> tuple[str, ...]:
    """Connectors owning the governed rows with the largest scores (at least a tenth of the top),
    largest first, at most ``limit``."""
    ops = system.connectors
    score: dict[int, float] = {}
    for (c, _), value in zip(ops.governed, np.asarray(rows, dtype=float).reshape(-1), strict=False):
        value = np.inf if not np.isfinite(value) else abs(value)
        score[c] = max(score.get(c, 0.0), value)
    if not score:
        return ()
    top = max(score.values())
    chosen = sorted((c for c, v in score.items() if v >= 0.1 * top and v > 0), key=lambda c: -score[c])
    return tuple(system.model.connectors[c].name for c in chosen[:limit])


def solve_transient(
    system_or_model: Model | System,
    ground_acceleration,
    dt: float,
    *,
    settings: TransientSettings | None = None,
    damping: Rayleigh | None = None,
    recorders: Sequence = (),
    preload: StaticResult | None = None,
    nodal_loads=None,
    registry: Registry | None = None,
    progress: Callable[[float], None] | None = None,
) -> TransientResult:
    """Time-history response to the support acceleration ``ground_acceleration`` sampled every ``dt``.

    ``ground_acceleration``: array (steps, 3), m/s^2, global x, y, z, the same at every support
    (the experiment layer converts a record). ``preload``: the gravity preload to start from
    (default: :func:`~bearingfw.analysis.gravity` with g = 9.81). ``nodal_loads``: dynamic loads
    beyond the preload's: NodalLoad objects or a full vector (constant from t = 0), or an array
    (steps, n_dof) sampled like the ground motion. ``damping``: :class:`Rayleigh` (default none).
    ``recorders``: :mod:`bearingfw.analysis.recorders` objects. ``progress(fraction)`` is called
    about every 1 % of the steps.

    Raises :class:`TransientError` (with ``.result`` up to the failure) when a step does not
    converge, or when a law, a recorder or ``progress`` raises (the original is its ``__cause__``).
    """
    wall = _time.perf_counter()
    settings, damping = _checked_options(settings, damping)
    system, preload = _system_and_preload(system_or_model, preload, registry)
    excitation = build_excitation(system, ground_acceleration, dt, nodal_loads, preload=preload)
    k = _substeps(settings, excitation.dt)
    problem = build_problem(system, preload, damping, settings)
    probes = _bind_recorders(recorders, Context(system, preload, excitation, damping.alpha, damping.beta))
    state = _at_rest(problem, preload, excitation)
    run = _Run(problem, excitation, probes, k, progress, system)
    run.operator(run.h)  # the nominal step's factors: part of the setup
    report = _Report(run, probes, settings, damping, system, preload, wall)
    # BLAS on one thread: the loop's dense products are small, and threads woken for each one cost
    # more CPU than they save (the reference bridge's 'fixed' cell: 1.55 CPU s against 6.0 with two)
    with threadpool_limits(limits=1, user_api="blas"):
        try:
            run.run(state, settings.max_halvings)
        except _Failed as failed:
            raise _no_convergence(failed, run, state, report) from None
        except Exception as exc:  # a law, a recorder or progress: keep what was computed, chain the cause
            raise _stopped(exc, run, state, report) from exc
        return report.result(True, "")


def _checked_options(settings, damping) -> tuple[TransientSettings, Rayleigh]:
    settings = TransientSettings() if settings is None else settings
    if not isinstance(settings, TransientSettings):
        raise ParameterError(f"solve_transient: 'settings' must be TransientSettings, got {type(settings).__name__}")
    damping = Rayleigh() if damping is None else damping
    if not isinstance(damping, Rayleigh):
        raise ParameterError(f"solve_transient: 'damping' must be a Rayleigh object, got {type(damping).__name__}")
    return settings, damping


def _bind_recorders(recorders: Sequence, ctx: Context) -> list:
    """Check the recorders (objects with distinct valid names) and bind them to the run."""
    recorders = list(recorders)
    if any(not hasattr(r, "bind") for r in recorders):
        raise ParameterError(
            "solve_transient: 'recorders' must be recorder objects (ElementStress, ConnectorResponse, ...)"
        )
    labels = [getattr(r, "label", None) for r in recorders]
    bad = [lb for lb in labels if not isinstance(lb, str) or not lb or "." in lb or lb in RESERVED_NAMES]
    if bad:
        raise ParameterError(
            f"solve_transient: recorder names {bad} are not valid result keys (a non-empty string without '.' "
            f"and not one of {', '.join(RESERVED_NAMES)})"
        )
    if len(set(labels)) != len(labels):
        raise ParameterError(f"solve_transient: two recorders share a name: {labels}; give them distinct 'name's")
    return [r.bind(ctx) for r in recorders]


def _at_rest(problem: hht.Problem, preload: StaticResult, excitation: Excitation) -> hht.State:
    """The start: the preload at rest, with the acceleration of the excitation at t = 0."""
    load0 = excitation.load(0.0)
    return hht.initial_state(
        problem, tuple(preload.law_states), load0, initial_acceleration(problem.M, problem.K, load0)
    )


class _Report:
    """What a :class:`TransientResult` holds besides the recorders' arrays: the settings as run, the
    statistics, the preload's residual; builds the result when the run ends (or fails)."""

    def __init__(self, run: _Run, probes, settings: TransientSettings, damping: Rayleigh, system: System,
                 preload: StaticResult, wall: float):
        problem = run.p
        self.run, self.probes, self.settings, self.wall = run, probes, settings, wall
        self.described = {
            "alpha": settings.alpha,
            "gamma": problem.scheme.gamma,
            "beta": problem.scheme.beta,
            "dt": run.exc.dt,
            "dt_integration": run.h,
            "tol_force": settings.tol_force,
            "tol_displacement": settings.tol_displacement,
            "max_iterations": settings.max_iterations,
            "max_halvings": settings.max_halvings,
            "path": settings.path,
            "rayleigh": [damping.alpha, damping.beta],
        }
        dead = system.reduce(preload.load)
        residual = system.K_free @ preload.q + system.B_free.T @ problem.f0 - dead
        scale = float(np.max(np.abs(dead), initial=0.0))
        self.preload_residual = float(np.max(np.abs(residual), initial=0.0)) / scale if scale else 0.0
        self.setup = _time.perf_counter() - wall

    def result(self, completed: bool, message: str) -> TransientResult:
        run = self.run
        data, meta = {}, {}
        for probe in self.probes:
            arrays, description = probe.finish()
            data.update(arrays)
            meta[probe.label] = description
        stats = dict(run.stats)
        now = _time.perf_counter()
        stats.update(
            factorizations=len(run.operators),
            setup_time=self.setup,
            loop_time=now - self.wall - self.setup,
            wall_time=now - self.wall,
            preload_residual=self.preload_residual,
            alpha=self.settings.alpha,
        )
        res = TransientResult(
            time=np.array(run.times),
            data=data,
            energy=energy_table(run.energy_rows, run.energy_times),
            stats=stats,
            recorders=meta,
            settings=self.described,
            completed=completed,
            message=message,
            uplift=run.uplift.summary() if run.uplift is not None else {},
        )
        res.stats.update(
            energy_error=res.energy_error,
            balance_error=res.balance_error,
            numerical_dissipation=res.numerical_dissipation,
        )
        return res

    def partial(self, start: hht.State, message: str) -> TransientResult | None:
        """The result up to the last converged instant, or None if a recorder cannot finish."""
        last = self.run.last if self.run.last is not None else start
        try:
            self.run.record(last, None)  # the last converged instant (a sub-step, or a step a recorder skipped)
            return self.result(False, message)
        except Exception:  # noqa: BLE001 - a recorder that cannot finish (e.g. the one that raised): no partial result
            return None


def _no_convergence(failed: _Failed, run: _Run, start: hht.State, report: _Report) -> TransientError:
    last = run.last if run.last is not None else start
    names = _connector_names(run.system, failed.failure.rows)
    model = run.system.model
    laws = sorted({str(model.connector(name).law) for name in names if model.connector(name).law})
    halvings = report.settings.max_halvings
    how = (
        f"with the step halved {halvings} times, to {failed.t1 - failed.state.t:.3g} s"
        if halvings
        else f"at the full step {failed.t1 - failed.state.t:.3g} s; step halving is off (max_halvings = 0)"
    )
    message = (
        f"solve_transient: no convergence at t = {failed.t1:.6g} s ({failed.failure.reason} {how}); "
        f"connectors still moving: {', '.join(names) or 'none'}"
        f"{' (law ' + ', '.join(repr(law) for law in laws) + ')' if laws else ''}; relative force residual "
        f"{failed.failure.residual:.3g}; results kept up to t = {last.t:.6g} s"
    )
    return TransientError(message, failed.t1, last.t, names, failed.failure.residual, report.partial(start, message))


def _stopped(exc: Exception, run: _Run, start: hht.State, report: _Report) -> TransientError:
    last = run.last if run.last is not None else start
    at = max(run.attempt, last.t)
    notes = "".join(f" ({note})" for note in getattr(exc, "__notes__", ()))  # e.g. the law that raised
    message = (
        f"solve_transient: stopped at t = {at:.6g} s by {type(exc).__name__}: {exc}{notes}; "
        f"results kept up to t = {last.t:.6g} s"
    )
    return TransientError(message, at, last.t, (), float("nan"), report.partial(start, message))
