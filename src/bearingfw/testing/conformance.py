"""The conformance kit: properties every bearing law must have, checked with hypothesis.

A law author runs it in one line from pytest::

    from bearingfw.testing import check_law

    def test_my_law_conforms():
        check_law(MyLaw(k=4e8))

or, to get one test per property, ``@parametrize_with_checks([MyLaw(k=4e8)])`` on a test
``def test_conformance(law, check): check(law)``. Each property raises :class:`ConformanceError`
(an ``AssertionError``) whose message starts with the law's name and the property's name;
hypothesis prints the smallest failing input. An exception raised by the law itself is reported
the same way, under the property that was running.

The properties (a property applies when the law declares what it is about, see
:mod:`bearingfw.protocol` for the flags):

========================== ====================================================================
protocol                   the members exist with valid values; optional flags are bools
response shapes            ``force`` (n, dims) and ``tangent`` (n, dims, dims) are float ndarrays,
                           finite; ``dforce_dnormal`` / ``dforce_dvelocity`` when declared; a
                           ``uses_velocity`` law also answers ``velocity=None``
zero force at rest         no force (and no slip) at zero displacement from the initial state
purity                     ``respond`` mutates neither its inputs nor the law, keeps no reference
                           to the caller's arrays, and repeats itself
vectorised                 n connectors together equal each connector alone
tangent                    the tangent is the derivative of the force (see "Kinks" below)
dissipation                the initial tangent is positive semi-definite, and the work over a
                           closed displacement cycle is not negative
odd symmetry               ``symmetric`` laws (the default) answer ``-u`` with ``-F``
force bound                ``|F| <= force_bound(N)`` for laws that declare ``force_bound``
trial independence         the kernel calls ``respond`` in every Newton iteration from the same
                           committed state, and again with a halved ``dt``: such trial calls do
                           not change the answer (no hidden memory, e.g. a velocity taken from
                           the last trial instead of the committed state)
committed state            rate-independent laws: ``respond`` at the committed displacement gives
                           the committed force back (a slip stored with the wrong sign does not)
per-bearing                ``per_bearing`` laws: one law holding per-connector parameter arrays
                           (drawn by :func:`~bearingfw.testing.strategies.per_bearing_laws`)
                           equals separate laws; an array of the wrong length is refused
normal derivative          ``normal_coupling`` laws: ``dforce_dnormal`` is d F / d N
velocity derivative        ``uses_velocity`` laws: ``dforce_dvelocity`` (None counts as zero) is
                           d F / d v
velocity from the kernel   ``uses_velocity`` laws take their rate from ``velocity``: at a fixed
                           velocity the response does not change with ``dt``
rotation invariance        2-D laws, unless they say ``isotropic = False``: rotating (or
                           mirroring) the path, and the velocities, rotates the forces; uncoupled
                           per-axis limits fail it
no contact                 ``friction`` laws: zero force and tangent (and dF/dv, and dF/dN in
                           tension) whenever ``N <= 0``, including ``N < 0`` passed directly
history                    ``friction`` laws: after sliding out along a ray and back to the
                           origin the force is not the origin's (a law that forgets its slip)
normality                  ``friction`` laws with a ``force_bound``: the slip (``slip(state)``, or
                           the displacement less the elastic part) grows along the force
                           (maximum dissipation; a non-associated slip direction fails)
rate independence          laws that are not ``rate_dependent``: the same forces whatever ``dt``
                           (halved steps, the static preload's ``dt = 1``)
compiled                   laws that offer ``compiled(n)``: the compiled function answers as
                           ``respond`` (force, tangent, dF/dN, next state) along drawn histories
linear                     ``linear`` laws: along any path, at any normal force and ``dt``, the
                           tangent is the first call's, the force is ``F(0) + K u``, and the state
                           comes back unchanged (the kernel folds ``K`` into its matrix)
rate-independent limit     laws with ``rate_independent_limit()``: the copy with its rate
                           dependence switched off, driven with arbitrary velocities and time
                           steps, gives the forces of the equivalent rate-independent law
========================== ====================================================================

Inputs. Displacement paths are random walks of up to ``max_steps`` steps whose amplitudes range
from 0.1 to 20 times ``displacement_scale`` (by default the displacement at which the force
reaches its bound, ``mu N / k`` for friction, else 1 mm); hypothesis also draws exact zeros, so
paths revisit the committed point and move along one axis, where laws have kinks. Normal forces
are drawn in ``normal_force_range`` and, where a property says so, also exactly 0 and (for
``friction`` laws only) negative. A ``uses_velocity`` law gets velocities from
:func:`~bearingfw.testing.strategies.velocity_histories` (any velocity with any path: the
kernel's velocity comes from the integrator) except where a property needs them consistent with
the path (dissipation, history: backward differences over ``dt``).

Comparisons between two computations that should agree (vectorised, odd symmetry, rotation, per
bearing, rate independence) compare forces, which are continuous, never tangents: where a trial
sits exactly on a stick/slip boundary round-off may pick either side's tangent.

Kinks. A tangent is judged column by column against finite differences of the force at the
same committed state. With ``h`` = 1e-6, 1e-7 and 1e-8 times ``max(displacement_scale, |u|)``
(in turn; the first that agrees ends the search) a column is accepted if it matches, within
1e-5 of the stiffness scale, the central difference, the forward or the backward second-order
one-sided difference, or any convex combination of the two one-sided differences. So: a kink
exactly at the trial point (the committed point of a hysteretic law, ``|v|`` at ``v = 0``,
``N = 0``) accepts either one-sided derivative or anything between them (the mean, e.g.
``sign(0) = 0``: Clarke's generalised derivative); a kink near the trial point lies on one side
only of the smallest stencils, whose other side then decides; a smooth point is judged by
central differences, with the smaller steps as a fallback for strongly curved responses. The
same rule judges ``dforce_dnormal`` (steps relative to ``max(N_high, |N|)``) and
``dforce_dvelocity`` (relative to ``max(velocity_scale, |v|)``). A correct law therefore passes
whatever the examples are; a wrong tangent is wrong on a whole side and fails.

Determinism, CI and longer runs. ``check_law`` runs ``max_examples`` examples per property
(default 30) and, by default, ``derandomize=True`` without the example database: the same
examples on every run, so a verdict never changes between runs of the same code. 30 examples
take a few seconds per law and ``dims`` for a closed-form law (regularized-coulomb, 18
properties: 2 to 3 s on an idle core); that is what a plugin's CI should run. For a law that is expensive per call, lower
``max_examples`` (5 to 10) and ``max_steps``, or choose a ``displacement_scale`` that keeps the
increments moderate. To search harder, e.g. nightly or before a release::

    check_law(law, max_examples=1000, derandomize=False)   # new random examples every run
    check_law(law, max_examples=300, seed=7)              # another reproducible set

(``derandomize=False`` keeps hypothesis' example database, which replays earlier failures;
``shrink=False`` skips shrinking when only the verdict matters.)
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Iterable

import attrs
import numpy as np
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import seed as hypothesis_seed
from hypothesis.errors import Flaky
from hypothesis import strategies as st

from bearingfw.parameters import ParameterError
from bearingfw.protocol import OPTIONAL_FLAGS, PROTOCOL_MEMBERS, BearingLaw, LawResponse, law_flag
from bearingfw.testing.drive import path_velocities
from bearingfw.testing.strategies import (
    closed_cycles,
    contact_force_histories,
    displacement_paths,
    histories,
    normal_force_histories,
    per_bearing_fields,
    per_bearing_laws,
    velocity_histories,
)

#: Relative tolerance of a derivative against finite differences (of the stiffness scale).
DERIVATIVE_TOLERANCE = 1e-5
#: Finite-difference steps, relative to max(scale, |x|): tried in turn (module docstring, "Kinks").
DERIVATIVE_STEPS = (1e-6, 1e-7, 1e-8)


class ConformanceError(AssertionError):
    """A law broke one property of the conformance kit."""

    def __init__(self, law_name: str, prop: str, detail: str):
        super().__init__(f"law {law_name!r} breaks property '{prop}': {detail}")
        self.law_name = law_name
        self.prop = prop


@attrs.frozen
class Context:
    """The law under test, the scales its random inputs are drawn at, and how hypothesis runs."""

    law: BearingLaw
    displacement_scale: float
    normal_force_range: tuple[float, float]
    elastic_stiffness: float
    dt: float
    max_examples: int
    shrink: bool = True
    velocity_scale: float = 0.1
    max_steps: int = 30
    derandomize: bool = True
    seed: int | None = None
    #: The largest |d force / d velocity| at rest (uses_velocity laws), N s/m.
    viscous_stiffness: float = 0.0

    @property
    def force_scale(self) -> float:
        return max(self.elastic_stiffness * self.displacement_scale, self.viscous_stiffness * self.velocity_scale, 1e-300)

    @property
    def uses_velocity(self) -> bool:
        return law_flag(self.law, "uses_velocity")

    @property
    def tension(self) -> bool:
        """Whether properties may pass ``N < 0`` directly: only to laws that declare ``friction``."""
        return law_flag(self.law, "friction")

    def roundoff(self, u) -> float:
        """A force tolerance for two computations that differ by round-off of displacements up to ``|u|``."""
        reach = max(self.displacement_scale, float(np.max(np.abs(u), initial=0.0)))
        return 1e-12 * max(self.elastic_stiffness * reach, self.force_scale)

    def fail(self, prop: str, detail: str):
        raise ConformanceError(self.law.name, prop, detail)

    def paths(self, n: int = 1, max_steps: int | None = None):
        """Displacement paths (steps, n, dims)."""
        return displacement_paths(self.law.dims, self.displacement_scale, n=n, max_steps=max_steps or self.max_steps)

    def forces(self, steps: int, n: int = 1, contact: bool = False):
        """Normal forces (steps, n); ``contact=True`` also draws 0 and, for friction laws, tension."""
        low, high = self.normal_force_range
        if contact:
            return contact_force_histories(steps, low, high, n=n, tension=self.tension)
        return normal_force_histories(steps, low, high, n=n)

    def velocities(self, steps: int, n: int = 1):
        """Velocities (steps, n, dims) for a ``uses_velocity`` law, else None."""
        if not self.uses_velocity:
            return st.none()
        return velocity_histories(steps, self.law.dims, self.velocity_scale, n=n)

    def histories(self, n: int = 1, contact: bool = False, max_steps: int | None = None):
        """``(path, normal, velocity)``: (steps, n, dims), (steps, n), (steps, n, dims) or None
        (:func:`~bearingfw.testing.strategies.histories`); ``contact=True`` also draws ``N = 0`` and,
        for friction laws, ``N < 0``."""
        low, high = self.normal_force_range
        return histories(
            self.law.dims, self.displacement_scale, n, max_steps or self.max_steps, low, high, contact, self.tension,
            self.velocity_scale if self.uses_velocity else None,
        )

    def hypothesis(self, strategy: st.SearchStrategy):
        """Decorate a one-argument property: run it at once over examples drawn from ``strategy``."""

        def decorate(body: Callable):
            fixed = self.derandomize and self.seed is None
            options = {
                "max_examples": self.max_examples,
                "deadline": None,
                "suppress_health_check": list(HealthCheck),
                # Shrinking finds the smallest failing input but can take a minute for a law
                # that fails late; callers that only need pass/fail switch it off.
                "phases": [Phase.explicit, Phase.reuse, Phase.generate] + ([Phase.shrink] if self.shrink else []),
                "derandomize": fixed,
                "print_blob": True,
            }
            if fixed:
                options["database"] = None  # the same examples every run, whatever ran before
            runner = settings(**options)(given(strategy)(body))
            if self.seed is not None:
                runner = hypothesis_seed(self.seed)(runner)
            try:
                runner()
            except Flaky as error:
                # Hypothesis replays a failing example before reporting it; a law that answers the
                # same inputs differently (memory in the law object, say) makes that replay fail.
                found = _conformance_errors(error)
                first = f"; the first failure was: {found[0]}" if found else ""
                raise ConformanceError(
                    self.law.name, "purity", f"the same calls gave different answers when repeated (state kept outside "
                    f"the arguments, e.g. in the law object?){first}"
                ) from error
            return runner

        return decorate


def _conformance_errors(error: BaseException) -> list[ConformanceError]:
    """The ConformanceErrors inside ``error`` (an exception group, or chained)."""
    if isinstance(error, ConformanceError):
        return [error]
    found = []
    for inner in getattr(error, "exceptions", ()):
        found += _conformance_errors(inner)
    return found


def make_context(
    law: BearingLaw,
    displacement_scale: float | None = None,
    normal_force_range: tuple[float, float] = (1e5, 4e6),
    dt: float = 0.01,
    max_examples: int = 30,
    shrink: bool = True,
    velocity_scale: float = 0.1,
    max_steps: int = 30,
    derandomize: bool = True,
    seed: int | None = None,
) -> Context:
    """Find the law's scales: the initial stiffness and, if it has one, the force bound.

    Without an explicit ``displacement_scale`` the inputs are drawn around the displacement at
    which the force reaches its bound (friction: ``mu N / k``); for a law without a bound, around
    the displacement at which it yields (:func:`yield_displacement`), or 1 mm if it does not.
    """
    low, high = normal_force_range
    if not 0 <= low <= high:
        raise ValueError(f"normal_force_range must satisfy 0 <= low <= high, got {normal_force_range}")
    if not (dt > 0 and velocity_scale > 0 and max_examples >= 1 and max_steps >= 2):
        raise ValueError("dt and velocity_scale must be > 0, max_examples >= 1 and max_steps >= 2")
    stiffness = viscous = 0.0
    if not law.rigid:
        mid = np.array([0.5 * (low + high)])
        response = _call(law, "scales", law.initial_state(1), np.zeros((1, law.dims)), mid, dt)
        stiffness = float(np.max(np.abs(response.tangent)))
        if response.dforce_dvelocity is not None:
            viscous = float(np.max(np.abs(response.dforce_dvelocity)))
        bound = float(law.force_bound(mid)[0]) if hasattr(law, "force_bound") else 0.0
        if displacement_scale is None and stiffness > 0 and bound > 0:
            displacement_scale = bound / stiffness
        elif displacement_scale is None and stiffness > 0:
            displacement_scale = yield_displacement(law, mid, dt, stiffness)
    return Context(
        law, displacement_scale or 1e-3, (low, high), stiffness, dt, max_examples, shrink, velocity_scale, max_steps,
        derandomize, seed, viscous,
    )


def yield_displacement(law, normal_force, dt: float, stiffness: float) -> float | None:
    """Where a law yields: the displacement along the first axis from rest at which its secant
    stiffness falls to half the initial ``stiffness`` (found by one call per trial displacement,
    decades from 1 um to 10 cm, then bisection to a factor of 1.2), or None if it does not within
    10 cm (an elastic law). A scale for laws without a force bound (Bouc-Wen, elastomeric, pendulum)."""
    direction = np.zeros((1, law.dims))
    direction[0, 0] = 1.0

    def softened(d: float) -> bool:
        response = _call(law, "scales", law.initial_state(1), d * direction, normal_force, dt)
        return abs(float(np.asarray(response.force, dtype=float)[0, 0])) < 0.5 * stiffness * d

    low = None
    for exponent in range(-6, 0):
        if softened(10.0**exponent):
            high = 10.0**exponent
            break
        low = 10.0**exponent
    else:
        return None
    if low is None:
        return high
    for _ in range(4):  # to within a factor of 10^(1/16): plenty for a scale
        middle = math.sqrt(low * high)
        low, high = (low, middle) if softened(middle) else (middle, high)
    return high


# --- calling and driving the law -------------------------------------------------------------


def _call(law, prop: str, state, u, normal, dt, velocity=None, *, explicit_none: bool = False) -> LawResponse:
    """``law.respond`` on copies of the inputs, as the kernel calls it; an exception becomes a failure.

    A ``uses_velocity`` law gets ``velocity`` (zeros if None, unless ``explicit_none``).
    """
    u = np.array(u, dtype=float)
    normal = np.array(normal, dtype=float)
    try:
        if law_flag(law, "uses_velocity"):
            v = None if explicit_none else (np.zeros_like(u) if velocity is None else np.array(velocity, dtype=float))
            return law.respond(state, u, normal, dt, velocity=v)
        return law.respond(state, u, normal, dt)
    except ConformanceError:
        raise
    except Exception as error:  # the law's own failure, reported under the property that found it
        where = f"u={u.tolist()}, N={normal.tolist()}, dt={dt!r}"
        if law_flag(law, "uses_velocity"):
            where += f", velocity={None if velocity is None else np.asarray(velocity).tolist()}"
        raise ConformanceError(law.name, prop, f"respond raised {type(error).__name__}: {error} ({where})") from error


def _force(ctx: Context, prop: str, response, n: int) -> np.ndarray:
    force = np.asarray(getattr(response, "force", None), dtype=object)
    if force.shape != (n, ctx.law.dims):
        ctx.fail(prop, f"respond returned a force of shape {force.shape}, expected {(n, ctx.law.dims)}")
    return force.astype(float)


def _drive(ctx: Context, prop: str, law, path, normal, velocity=None, dt: float | None = None, state=None):
    """Drive ``law`` along ``path`` (steps, n, dims), committing every step.

    Returns ``(forces (steps, n, dims), responses, states)``; ``states[k]`` is the committed state
    *before* step ``k`` (``states[0]`` the initial state, ``states[steps]`` the final one).
    """
    dt = ctx.dt if dt is None else dt
    steps, n, _ = path.shape
    state = law.initial_state(n) if state is None else state
    forces, responses, states = np.empty(path.shape), [], [state]
    for k in range(steps):
        response = _call(law, prop, state, path[k], normal[k], dt, None if velocity is None else velocity[k])
        forces[k] = _force(ctx, prop, response, n)
        responses.append(response)
        state = response.state
        states.append(state)
    return forces, responses, states


def _same(a, b) -> bool:
    """Deep equality of states: dicts, sequences, numpy arrays (NaNs equal), attrs objects."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.shape == b.shape and a.dtype == b.dtype and bool(np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if attrs.has(type(a)) and type(a) is type(b):
        return all(_same(getattr(a, f.name), getattr(b, f.name)) for f in attrs.fields(type(a)))
    try:
        return bool(a == b)
    except Exception:  # an object without a usable equality: compare what it holds
        return _same(vars(a), vars(b)) if hasattr(a, "__dict__") and hasattr(b, "__dict__") else a is b


def _law_snapshot(law):
    """What a law object holds (fields, attributes), deep-copied, to see whether respond changes it."""
    held = {}
    if attrs.has(type(law)):
        held.update({field.name: getattr(law, field.name) for field in attrs.fields(type(law))})
    if hasattr(law, "__dict__"):
        held.update(vars(law))
    try:
        return copy.deepcopy(held)
    except Exception:  # something that cannot be copied is left out of the comparison
        return {}


def _close(a, b, rtol: float, atol: float) -> bool:
    return bool(np.allclose(a, b, rtol=rtol, atol=atol, equal_nan=False))


def _rotation(angle: float, mirror: bool) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    rotation = np.array([[c, -s], [s, c]])
    return rotation @ np.diag([1.0, -1.0]) if mirror else rotation


def _derivative_check(evaluate, x0: np.ndarray, claimed: np.ndarray, scale_x: float, stiffness: float):
    """Judge ``claimed`` (out, len(x0)) against finite differences of ``evaluate(x) -> (out,)`` at ``x0``.

    Returns None if every column passes (module docstring, "Kinks"), else ``(column, central
    difference at the first step)``.
    """
    x0 = np.asarray(x0, dtype=float)
    f0 = evaluate(x0)
    base = max(scale_x, float(np.max(np.abs(x0), initial=0.0)))
    for j in range(x0.size):
        column = claimed[:, j]
        first_central = None
        for relative in DERIVATIVE_STEPS:
            h = relative * base
            step = np.zeros_like(x0)
            step.flat[j] = h
            plus, minus = evaluate(x0 + step), evaluate(x0 - step)
            central = (plus - minus) / (2 * h)
            first_central = central if first_central is None else first_central
            scale = max(stiffness, float(np.max(np.abs(column))), float(np.max(np.abs(central))))
            tolerance = DERIVATIVE_TOLERANCE * scale
            if np.max(np.abs(central - column)) <= tolerance:
                break
            forward = (4 * plus - 3 * f0 - evaluate(x0 + 2 * step)) / (2 * h)
            backward = (3 * f0 - 4 * minus + evaluate(x0 - 2 * step)) / (2 * h)
            gap = forward - backward
            size = float(np.dot(gap, gap))
            weight = float(np.clip(np.dot(column - backward, gap) / size, 0.0, 1.0)) if size > 0 else 0.0
            between = backward + weight * gap  # the nearest convex combination of the one-sided derivatives
            if min(np.max(np.abs(candidate - column)) for candidate in (forward, backward, between)) <= tolerance:
                break
        else:
            return j, first_central
    return None


# --- the properties -------------------------------------------------------------------------


def check_protocol(ctx: Context) -> None:
    """The law has every protocol member with a valid value; optional flags are bools."""
    law = ctx.law
    missing = [m for m in PROTOCOL_MEMBERS if not hasattr(law, m)]
    if missing:
        ctx.fail("protocol", f"missing member(s) {', '.join(missing)}")
    if not isinstance(law.name, str) or not law.name:
        ctx.fail("protocol", f"name must be a non-empty string, got {law.name!r}")
    if isinstance(law.dims, bool) or law.dims not in (1, 2):
        ctx.fail("protocol", f"dims must be 1 or 2, got {law.dims!r}")
    if not isinstance(law.rigid, bool):
        ctx.fail("protocol", f"rigid must be a bool, got {law.rigid!r}")
    for flag in (*OPTIONAL_FLAGS, "symmetric", "isotropic"):
        value = getattr(law, flag, False)
        if not isinstance(value, (bool, np.bool_)):
            ctx.fail("protocol", f"the optional flag {flag!r} must be a bool, got {value!r}")
    if hasattr(law, "rate_independent_limit") and not law_flag(law, "rate_dependent"):
        ctx.fail("protocol", "rate_independent_limit() is for rate-dependent laws: declare rate_dependent = True")


def check_response_shapes(ctx: Context) -> None:
    """respond returns a LawResponse of float ndarrays, force (n, dims) and tangent (n, dims, dims), finite,
    with dforce_dnormal (n, dims) if it declares normal_coupling and dforce_dvelocity (n, dims, dims) if
    given; a uses_velocity law also answers velocity=None."""
    law, dims, prop = ctx.law, ctx.law.dims, "response shapes"

    def check(response, n, where):
        if not isinstance(response, LawResponse):
            ctx.fail(prop, f"respond returned {type(response).__name__}, not LawResponse ({where})")
        expected = {"force": (n, dims), "tangent": (n, dims, dims)}
        if law_flag(law, "normal_coupling") or response.dforce_dnormal is not None:
            expected["dforce_dnormal"] = (n, dims)
        if response.dforce_dvelocity is not None:
            expected["dforce_dvelocity"] = (n, dims, dims)
        for field, shape in expected.items():
            value = getattr(response, field)
            if not isinstance(value, np.ndarray):
                what = "None: a law that declares normal_coupling returns it" if value is None else type(value).__name__
                ctx.fail(prop, f"{field} is {what}, not a numpy array ({where})")
            if value.shape != shape or value.dtype.kind != "f":
                ctx.fail(prop, f"for n={n}: {field} has shape {value.shape} and dtype {value.dtype}, "
                               f"expected {shape} floats ({where})")  # fmt: skip
            if not np.all(np.isfinite(value)):
                ctx.fail(prop, f"{field} is not finite: {value.tolist()} ({where})")

    @ctx.hypothesis(st.integers(1, 4).flatmap(lambda n: ctx.histories(n, contact=True)))
    def prop_(example):
        path, normal, velocity = example
        n = path.shape[1]
        state = law.initial_state(n)
        for k in range(len(path)):
            where = f"u={path[k].tolist()}, N={normal[k].tolist()}"
            response = _call(law, prop, state, path[k], normal[k], ctx.dt, None if velocity is None else velocity[k])
            check(response, n, where)
            if ctx.uses_velocity:
                check(_call(law, prop, state, path[k], normal[k], ctx.dt, explicit_none=True), n, where + ", velocity=None")
            state = response.state


def check_zero_at_rest(ctx: Context) -> None:
    """Zero displacement (and, for a velocity law, zero velocity) from the initial state gives zero
    force (and zero slip, if reported)."""
    law, prop = ctx.law, "zero force at rest"

    @ctx.hypothesis(st.integers(1, 4).flatmap(lambda n: ctx.forces(1, n, contact=True)))
    def prop_(normal):
        n = normal.shape[1]
        response = _call(law, prop, law.initial_state(n), np.zeros((n, law.dims)), normal[0], ctx.dt)
        force = _force(ctx, prop, response, n)
        if np.any(np.abs(force) > 1e-12 * ctx.force_scale):
            ctx.fail(prop, f"force {force.tolist()} at zero displacement (N={normal[0].tolist()})")
        if hasattr(law, "slip"):
            slip = np.asarray(law.slip(law.initial_state(n)))
            if slip.shape != (n, law.dims) or np.any(slip != 0):
                ctx.fail(prop, f"slip(initial_state({n})) is {slip.tolist()}, not zeros of shape {(n, law.dims)}")


def check_purity(ctx: Context) -> None:
    """respond mutates neither its inputs (state, u, N, velocity) nor the law, keeps no reference to the
    caller's arrays in the state it returns, and the same call gives the same answer."""
    law, prop = ctx.law, "purity"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        path, normal, velocity = example
        state = law.initial_state(1)
        for k in range(len(path)):
            where = f"at u={path[k].tolist()}, N={normal[k].tolist()}"
            u_in, n_in = path[k].copy(), normal[k].copy()
            v_in = None if velocity is None else velocity[k].copy()
            before, held = copy.deepcopy(state), _law_snapshot(law)
            try:
                if ctx.uses_velocity:
                    first = law.respond(state, u_in, n_in, ctx.dt, velocity=v_in)
                else:
                    first = law.respond(state, u_in, n_in, ctx.dt)
            except Exception as error:
                ctx.fail(prop, f"respond raised {type(error).__name__}: {error} ({where})")
            if not _same(before, state):
                ctx.fail(prop, f"respond mutated the state it was given {where}")
            if not (np.array_equal(u_in, path[k]) and np.array_equal(n_in, normal[k])
                    and (v_in is None or np.array_equal(v_in, velocity[k]))):  # fmt: skip
                ctx.fail(prop, f"respond modified its input arrays (u, normal_force or velocity) {where}")
            if not _same(held, _law_snapshot(law)):
                ctx.fail(prop, f"respond changed the law object itself {where}: a law keeps its state outside")
            kept = copy.deepcopy(first.state)
            # The kernel reuses its arrays: the state must not be a view of what the caller passed.
            u_in += 1.0
            n_in += 1.0
            if v_in is not None:
                v_in += 1.0
            if not _same(kept, first.state):
                ctx.fail(prop, f"the returned state shares memory with the caller's u, normal_force or velocity {where}")
            second = _call(law, prop, state, path[k], normal[k], ctx.dt, None if velocity is None else velocity[k])
            same_force = _same(np.asarray(first.force), np.asarray(second.force))
            same_tangent = _same(np.asarray(first.tangent), np.asarray(second.tangent))
            if not (same_force and same_tangent and _same(kept, second.state)):
                ctx.fail(prop, f"two identical calls gave different results {where}")
            state = first.state


def check_vectorised(ctx: Context) -> None:
    """n connectors answered together equal each connector answered alone."""
    law, prop, n = ctx.law, "vectorised", 3

    @ctx.hypothesis(ctx.histories(n, contact=True))
    def prop_(example):
        path, normal, velocity = example
        together, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        for i in range(n):
            alone, _, _ = _drive(ctx, prop, law, path[:, i : i + 1], normal[:, i : i + 1],
                                 None if velocity is None else velocity[:, i : i + 1])  # fmt: skip
            if not _close(alone[:, 0], together[:, i], 1e-10, ctx.roundoff(path)):
                step = int(np.argmax(np.abs(alone[:, 0] - together[:, i]).max(axis=1)))
                ctx.fail(prop, f"connector {i} of {n} differs from the same connector alone at step {step}: "
                               f"{together[step, i].tolist()} against {alone[step, 0].tolist()}")  # fmt: skip


def _last_point(ctx: Context, prop: str, example):
    """The committed state before the last step of a history, and that step's inputs."""
    path, normal, velocity = example
    _, _, states = _drive(ctx, prop, ctx.law, path[:-1], normal[:-1], None if velocity is None else velocity[:-1])
    v = None if velocity is None else velocity[-1]
    return states[-1], path[-1], normal[-1], v


def check_tangent(ctx: Context) -> None:
    """The tangent is the derivative of the force in u (at fixed N and velocity): module docstring, "Kinks"."""
    law, dims, prop = ctx.law, ctx.law.dims, "tangent"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        state, u, normal, v = _last_point(ctx, prop, example)
        tangent = np.asarray(_call(law, prop, state, u, normal, ctx.dt, v).tangent, dtype=float)[0]

        def force(x):
            return _force(ctx, prop, _call(law, prop, state, x.reshape(1, dims), normal, ctx.dt, v), 1)[0]

        scale = max(ctx.elastic_stiffness, float(np.max(np.abs(tangent))), 1e-300)
        wrong = _derivative_check(force, u[0], tangent, ctx.displacement_scale, scale)
        if wrong is not None:
            j, central = wrong
            ctx.fail(prop, f"column {j} of the tangent at u={u[0].tolist()}, N={normal[0]:g} is {tangent[:, j].tolist()} "
                           f"but finite differences give {central.tolist()}")  # fmt: skip


def check_normal_derivative(ctx: Context) -> None:
    """A law that declares normal_coupling returns dforce_dnormal = d force / d N (at fixed u and velocity)."""
    law, dims, prop = ctx.law, ctx.law.dims, "normal derivative"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        state, u, normal, v = _last_point(ctx, prop, example)
        claimed = _call(law, prop, state, u, normal, ctx.dt, v).dforce_dnormal
        if claimed is None:
            ctx.fail(prop, "dforce_dnormal is None, but the law declares normal_coupling")
        claimed = np.asarray(claimed, dtype=float).reshape(dims, 1)

        def force(x):
            return _force(ctx, prop, _call(law, prop, state, u, x, ctx.dt, v), 1)[0]

        scale = max(ctx.force_scale / max(ctx.normal_force_range[1], 1e-300), float(np.max(np.abs(claimed))))
        wrong = _derivative_check(force, normal, claimed, ctx.normal_force_range[1], scale)
        if wrong is not None:
            ctx.fail(prop, f"dforce_dnormal at u={u[0].tolist()}, N={normal[0]:g} is {claimed[:, 0].tolist()} "
                           f"but finite differences in N give {wrong[1].tolist()}")  # fmt: skip


def check_velocity_derivative(ctx: Context) -> None:
    """A uses_velocity law returns dforce_dvelocity = d force / d velocity (None counts as zero)."""
    law, dims, prop = ctx.law, ctx.law.dims, "velocity derivative"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        state, u, normal, v = _last_point(ctx, prop, example)
        claimed = _call(law, prop, state, u, normal, ctx.dt, v).dforce_dvelocity
        claimed = np.zeros((dims, dims)) if claimed is None else np.asarray(claimed, dtype=float)[0]

        def force(x):
            return _force(ctx, prop, _call(law, prop, state, u, normal, ctx.dt, x.reshape(1, dims)), 1)[0]

        scale = max(ctx.force_scale / ctx.velocity_scale, float(np.max(np.abs(claimed))))
        wrong = _derivative_check(force, v[0], claimed, ctx.velocity_scale, scale)
        if wrong is not None:
            j, central = wrong
            ctx.fail(prop, f"column {j} of dforce_dvelocity at u={u[0].tolist()}, v={v[0].tolist()} is "
                           f"{claimed[:, j].tolist()} (None counts as zero) but finite differences give "
                           f"{central.tolist()}")  # fmt: skip


def check_velocity_from_kernel(ctx: Context) -> None:
    """A uses_velocity law takes its rate from the velocity it is given: at a fixed velocity, dt changes nothing."""
    law, prop = ctx.law, "velocity from the kernel"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        path, normal, velocity = example
        forces, _, states = _drive(ctx, prop, law, path, normal, velocity)
        for k in range(len(path)):
            for dt in (0.5 * ctx.dt, 3.0 * ctx.dt):
                other = _force(ctx, prop, _call(law, prop, states[k], path[k], normal[k], dt, velocity[k]), 1)
                if not _close(other, forces[k], 1e-12, ctx.roundoff(path)):
                    ctx.fail(prop, f"at step {k} the force is {forces[k].tolist()} with dt={ctx.dt:g} but {other.tolist()} "
                                   f"with dt={dt:g} at the same velocity: a law that declares uses_velocity takes its rate "
                                   f"from the velocity the kernel gives it")  # fmt: skip


def check_trial_independence(ctx: Context) -> None:
    """Trial calls from the committed state (other displacements, normal forces, velocities, halved dt),
    as Newton iterations and step halving make them, do not change the answer of the next call."""
    law, dims, prop = ctx.law, ctx.law.dims, "trial independence"
    decoy = st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(0.0, 2.0), st.sampled_from([1.0, 0.5, 0.25]))
    example = st.tuples(ctx.histories(1, contact=True), st.lists(st.integers(0, 3), min_size=1, max_size=8),
                        st.lists(decoy, min_size=1, max_size=6))  # fmt: skip

    @ctx.hypothesis(example)
    def prop_(drawn):
        (path, normal, velocity), counts, decoys = drawn
        with_trials = np.empty(path.shape)
        state, used = law.initial_state(1), 0
        for k in range(len(path)):
            v = None if velocity is None else velocity[k]
            for _ in range(counts[k % len(counts)]):
                du_x, du_y, n_factor, dt_factor = decoys[used % len(decoys)]
                used += 1
                trial_u = path[k] + ctx.displacement_scale * np.array([du_x, du_y][:dims])
                trial_v = None if v is None else v * (1.0 - du_x) + ctx.velocity_scale * du_y
                _call(law, prop, state, trial_u, normal[k] * n_factor, ctx.dt * dt_factor, trial_v)
            response = _call(law, prop, state, path[k], normal[k], ctx.dt, v)
            with_trials[k] = _force(ctx, prop, response, 1)
            state = response.state
        clean, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        if not _close(with_trials, clean, 1e-12, ctx.roundoff(path)):
            k = int(np.argmax(np.abs(with_trials - clean).reshape(len(path), -1).max(axis=1)))
            ctx.fail(prop, f"at step {k} (u={path[k].tolist()}) the force is {with_trials[k].tolist()} after other trial "
                           f"calls from the committed state but {clean[k].tolist()} without them: the response must depend "
                           f"only on the committed state and this call's arguments")  # fmt: skip


def check_committed_state(ctx: Context) -> None:
    """A rate-independent law called at its committed displacement (same N) gives the committed force back."""
    law, prop = ctx.law, "committed state"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        path, normal, velocity = example
        forces, _, states = _drive(ctx, prop, law, path, normal, velocity)
        for k in range(len(path)):
            again = _force(ctx, prop, _call(law, prop, states[k + 1], path[k], normal[k], ctx.dt,
                                            None if velocity is None else velocity[k]), 1)  # fmt: skip
            if not _close(again, forces[k], 1e-9, ctx.roundoff(path)):
                ctx.fail(prop, f"committed at u={path[k].tolist()} with force {forces[k].tolist()}, but respond from "
                               f"that committed state at the same u gives {again.tolist()} (is the state updated "
                               f"consistently?)")  # fmt: skip


def check_per_bearing(ctx: Context) -> None:
    """A per_bearing law holding per-connector parameter arrays equals separate laws with the scalar values,
    and refuses a call for a number of connectors that is not the arrays' length."""
    law, prop, n = ctx.law, "per-bearing", 3
    if not per_bearing_fields(law):
        ctx.fail(prop, "the law declares per_bearing but has no field made with bearingfw.parameter(..., per_bearing=True)")

    @ctx.hypothesis(st.tuples(per_bearing_laws(law, n, built=False), ctx.histories(n, contact=True)))
    def prop_(example):
        (combined, singles), (path, normal, velocity) = example
        try:
            array_law = type(law)(**combined)
        except Exception as error:
            ctx.fail(prop, f"{type(law).__name__}(**{combined!r}) raised {type(error).__name__}: {error}, but each "
                           f"connector's values are admissible on their own")  # fmt: skip
        laws = [type(law)(**params) for params in singles]
        together, _, _ = _drive(ctx, prop, array_law, path, normal, velocity)
        for i, single in enumerate(laws):
            alone, _, _ = _drive(ctx, prop, single, path[:, i : i + 1], normal[:, i : i + 1],
                                 None if velocity is None else velocity[:, i : i + 1])  # fmt: skip
            if not _close(alone[:, 0], together[:, i], 1e-10, 1e-10 * _scale_of(single, ctx, path)):
                step = int(np.argmax(np.abs(alone[:, 0] - together[:, i]).max(axis=1)))
                ctx.fail(prop, f"connector {i} of {array_law!r} differs from {single!r} alone at step {step}: "
                               f"{together[step, i].tolist()} against {alone[step, 0].tolist()}")  # fmt: skip
        if any(isinstance(getattr(array_law, name), np.ndarray) for name in per_bearing_fields(law)):
            try:
                state = array_law.initial_state(n + 1)
                array_law.respond(state, np.zeros((n + 1, law.dims)), np.full(n + 1, normal[0, 0]), ctx.dt,
                                  **({"velocity": np.zeros((n + 1, law.dims))} if ctx.uses_velocity else {}))  # fmt: skip
            except ParameterError:
                return
            except Exception as error:
                ctx.fail(prop, f"a call for {n + 1} connectors with {n} per-bearing values raised "
                               f"{type(error).__name__}: {error}; use bearingfw.parameters.check_per_bearing(law, n) "
                               f"for a clear ParameterError")  # fmt: skip
            ctx.fail(prop, f"{array_law!r} answered a call for {n + 1} connectors although it holds {n} per-bearing "
                           f"values: check with bearingfw.parameters.check_per_bearing(law, n)")  # fmt: skip


def _scale_of(law, ctx: Context, path) -> float:
    """The force scale of one drawn law (its initial stiffness times the reach of the path)."""
    mid = np.array([0.5 * sum(ctx.normal_force_range)])
    response = _call(law, "per-bearing", law.initial_state(1), np.zeros((1, law.dims)), mid, ctx.dt)
    stiffness = float(np.max(np.abs(response.tangent)))
    return max(stiffness * max(ctx.displacement_scale, float(np.max(np.abs(path)))), ctx.force_scale, 1e-300)


def check_dissipation(ctx: Context) -> None:
    """A law does not create energy: its initial tangent is positive semi-definite (the work from rest is
    not negative) and the work done on it over a closed displacement cycle is not negative."""
    law, prop = ctx.law, "dissipation"
    normal = 0.5 * sum(ctx.normal_force_range)
    initial = np.asarray(_call(law, prop, law.initial_state(1), np.zeros((1, law.dims)), [normal], ctx.dt).tangent)[0]
    lowest = float(np.linalg.eigvalsh(0.5 * (initial + initial.T))[0])
    if lowest < -1e-9 * max(float(np.max(np.abs(initial))), 1e-300):
        ctx.fail(prop, f"the initial tangent {initial.tolist()} is not positive semi-definite: a displacement from rest "
                       f"releases energy (the force must resist the displacement: a spring returns +k u)")  # fmt: skip

    @ctx.hypothesis(closed_cycles(law.dims, ctx.displacement_scale, max_steps=max(2, ctx.max_steps // 2)))
    def prop_(cycle):
        path = cycle[:, None, :]
        velocity = path_velocities(path, ctx.dt) if ctx.uses_velocity else None
        forces, _, _ = _drive(ctx, prop, law, path, np.full((len(cycle), 1), normal), velocity)
        u = np.concatenate([np.zeros((1, law.dims)), cycle])
        f = np.concatenate([np.zeros((1, law.dims)), forces[:, 0]])
        # Trapezoidal work of the discrete response; exact for the elastic part.
        increments = np.einsum("ij,ij->i", 0.5 * (f[1:] + f[:-1]), np.diff(u, axis=0))
        work = float(increments.sum())
        tolerance = 1e-9 * float(np.abs(increments).sum()) + 1e-12 * ctx.force_scale * ctx.displacement_scale
        if work < -tolerance:
            ctx.fail(prop, f"the work over a closed cycle is {work:.6g} < 0 (the law creates energy)")


def check_odd(ctx: Context) -> None:
    """A symmetric law answers the mirrored path (and velocities) with the mirrored force."""
    law, prop = ctx.law, "odd symmetry"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        path, normal, velocity = example
        forward, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        mirrored, _, _ = _drive(ctx, prop, law, -path, normal, None if velocity is None else -velocity)
        if not _close(mirrored, -forward, 1e-9, ctx.roundoff(path)):
            ctx.fail(prop, "the force for -u is not -F(u); declare symmetric = False if that is intended")


def check_rotation(ctx: Context) -> None:
    """A 2-D law (unless isotropic = False) is isotropic: a rotated or mirrored path gives the rotated forces."""
    law, prop = ctx.law, "rotation invariance"

    @ctx.hypothesis(st.tuples(ctx.histories(1, contact=True), st.floats(0.0, 2 * math.pi), st.booleans()))
    def prop_(example):
        (path, normal, velocity), angle, mirror = example
        q = _rotation(angle, mirror)
        forces, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        turned, _, _ = _drive(ctx, prop, law, path @ q.T, normal, None if velocity is None else velocity @ q.T)
        if not _close(turned, forces @ q.T, 1e-9, 1e3 * ctx.roundoff(path)):
            k = int(np.argmax(np.abs(turned - forces @ q.T).reshape(len(path), -1).max(axis=1)))
            ctx.fail(prop, f"the path {'mirrored and ' if mirror else ''}turned by {math.degrees(angle):.6g} degrees gives "
                           f"{turned[k, 0].tolist()} at step {k}, not the turned force {(forces[k, 0] @ q.T).tolist()}: "
                           f"the 2-D law depends on the axes (declare isotropic = False if it is meant to)")  # fmt: skip


def check_force_bound(ctx: Context) -> None:
    """The force never exceeds the bound the law declares with force_bound(normal_force)."""
    law, prop = ctx.law, "force bound"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        path, normal, velocity = example
        forces, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        magnitude = np.linalg.norm(forces[:, 0], axis=1)
        bound = np.asarray(law.force_bound(normal[:, 0]), dtype=float)
        excess = magnitude - bound * (1 + 1e-12)
        worst = int(np.argmax(excess))
        if excess[worst] > 1e-12 * ctx.force_scale:
            ctx.fail(prop, f"|F| = {magnitude[worst]:.6g} exceeds the declared bound {bound[worst]:.6g} at step {worst} "
                           f"(u={path[worst, 0].tolist()}, N={normal[worst, 0]:g})")  # fmt: skip


def check_no_contact(ctx: Context) -> None:
    """A friction law carries no force whenever N <= 0: zero force and tangent (and dF/dv; dF/dN when N < 0),
    whatever its state and displacement, N < 0 passed directly included."""
    law, dims, prop = ctx.law, ctx.law.dims, "no contact"
    low, high = ctx.normal_force_range
    lost = st.one_of(st.just(0.0), st.floats(-high, -1e-3 * max(low, 1.0)))

    @ctx.hypothesis(st.tuples(ctx.histories(1, contact=True), lost))
    def prop_(example):
        (path, normal, velocity), extra = example
        _, responses, states = _drive(ctx, prop, law, path, normal, velocity)
        # Also from the final state, at the last displacement and at a far one, with no contact.
        checks = [(r, normal[k, 0], path[k]) for k, r in enumerate(responses)]
        for u in (path[-1], path[-1] + 5 * ctx.displacement_scale):
            response = _call(law, prop, states[-1], u, [extra], ctx.dt, None if velocity is None else velocity[-1])
            checks.append((response, extra, u))
        tolerance = 1e-12 * ctx.force_scale
        for response, n_k, u in checks:
            if n_k > 0:
                continue
            force = _force(ctx, prop, response, 1)
            parts = {"force": force, "tangent": np.asarray(response.tangent, dtype=float) * ctx.displacement_scale}
            if response.dforce_dvelocity is not None:
                parts["dforce_dvelocity"] = np.asarray(response.dforce_dvelocity, dtype=float) * ctx.velocity_scale
            if n_k < 0 and response.dforce_dnormal is not None:
                parts["dforce_dnormal"] = np.asarray(response.dforce_dnormal, dtype=float) * high
            for name, value in parts.items():
                if np.any(np.abs(value) > tolerance):
                    returned = np.asarray(getattr(response, name), dtype=float).tolist()
                    ctx.fail(prop, f"{name} is {returned} at N={n_k:g} (u={np.asarray(u).tolist()}): a friction law has "
                                   f"no contact, so no force, when N <= 0")  # fmt: skip


def check_history(ctx: Context) -> None:
    """A friction law remembers its slip: after sliding out along a ray and back to the origin, the force
    there is not the origin's (zero)."""
    law, dims, prop = ctx.law, ctx.law.dims, "history"
    if ctx.elastic_stiffness <= 0:
        return

    @ctx.hypothesis(st.tuples(st.floats(0.0, 2 * math.pi), st.floats(3.0, 20.0), st.integers(3, 12),
                              st.floats(*ctx.normal_force_range)))  # fmt: skip
    def prop_(example):
        angle, reach, steps, normal = example
        if normal <= 0:
            return
        if dims == 2:
            e = np.array([math.cos(angle), math.sin(angle)])
        else:
            e = np.array([1.0 if angle < math.pi else -1.0])
        amplitude = reach * ctx.displacement_scale
        out = np.linspace(0.0, amplitude, steps + 1)[1:]
        distances = np.concatenate([out, out[-2::-1], [0.0]])
        path = (distances[:, None] * e)[:, None, :]
        velocity = path_velocities(path, ctx.dt) if ctx.uses_velocity else None
        forces, _, _ = _drive(ctx, prop, law, path, np.full((len(path), 1), normal), velocity)
        at_end, at_origin = float(np.linalg.norm(forces[steps - 1, 0])), float(np.linalg.norm(forces[-1, 0]))
        slid = 0.0 < at_end < 0.5 * ctx.elastic_stiffness * amplitude
        if slid and at_origin <= 1e-3 * at_end:
            ctx.fail(prop, f"slid out to u={path[steps - 1, 0].tolist()} (|F| = {at_end:.6g}, far below the elastic "
                           f"{ctx.elastic_stiffness * amplitude:.6g}) and back to the origin, where the force is "
                           f"{forces[-1, 0].tolist()}: the law forgot its slip")  # fmt: skip


def check_normality(ctx: Context) -> None:
    """A friction law with a force bound slides along its force (associated rule, maximum dissipation): from
    a committed state, a small step that makes it slide grows the slip along the force."""
    law, dims, prop = ctx.law, ctx.law.dims, "normality"
    delta = 1e-4 * ctx.displacement_scale
    turns = (math.radians(60.0), math.radians(-60.0)) if dims == 2 else (0.0,)

    @ctx.hypothesis(ctx.histories(1))
    def prop_(example):
        path, normal, velocity = example
        forces, _, states = _drive(ctx, prop, law, path, normal, velocity)
        for k in range(len(path)):
            size = float(np.linalg.norm(forces[k, 0]))
            if size == 0.0:
                continue
            along = forces[k, 0] / size
            v = None if velocity is None else velocity[k]
            for turn in turns:
                d = _rotation(turn, False)[:dims, :dims] @ along if dims == 2 else along
                u = path[k] + delta * d
                response = _call(law, prop, states[k + 1], u, normal[k], ctx.dt, v)
                force = _force(ctx, prop, response, 1)[0]
                slip = _slip_increment(ctx, law, states[k + 1], response, delta * d, force - forces[k, 0], normal[k])
                if slip is None:
                    return
                length = float(np.linalg.norm(slip))
                if length <= 1e-3 * delta or not np.any(force):
                    continue
                cosine = float(np.dot(slip, force)) / (length * float(np.linalg.norm(force)))
                if cosine < 1.0 - 5e-5:
                    ctx.fail(prop, f"from the state committed at u={path[k, 0].tolist()} (force {forces[k, 0].tolist()}) "
                                   f"a step {(delta * d).tolist()} slips by {slip.tolist()}, at "
                                   f"{math.degrees(math.acos(max(-1.0, min(1.0, cosine)))):.3g} degrees to the force "
                                   f"{force.tolist()}: friction slides along its force (associated rule)")  # fmt: skip


def _slip_increment(ctx: Context, law, committed, response, du, dforce, normal):
    """The slip of one small step: from ``slip(state)`` if the law reports it, else the displacement less
    the elastic part ``K_e^-1 dF`` (K_e the initial tangent); None if neither is available."""
    if hasattr(law, "slip"):
        return np.asarray(law.slip(response.state), dtype=float)[0] - np.asarray(law.slip(committed), dtype=float)[0]
    initial = np.asarray(_call(law, "normality", law.initial_state(1), np.zeros((1, law.dims)), normal, ctx.dt).tangent)[0]
    if np.linalg.cond(initial) > 1e8:
        return None
    return du - np.linalg.solve(initial, dforce)


def check_rate_independence(ctx: Context) -> None:
    """A law that is not rate_dependent gives the same forces along a path whatever dt."""
    law, prop = ctx.law, "rate independence"

    @ctx.hypothesis(ctx.histories(1, contact=True))
    def prop_(example):
        path, normal, velocity = example
        reference, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        for dt in (0.5 * ctx.dt, 1.0, 7.3 * ctx.dt):
            other, _, _ = _drive(ctx, prop, law, path, normal, velocity, dt=dt)
            if not _close(other, reference, 1e-9, ctx.roundoff(path)):
                k = int(np.argmax(np.abs(other - reference).reshape(len(path), -1).max(axis=1)))
                ctx.fail(prop, f"at step {k} the force is {reference[k, 0].tolist()} with dt={ctx.dt:g} but "
                               f"{other[k, 0].tolist()} with dt={dt:g}: declare rate_dependent = True if the law "
                               f"depends on the time step")  # fmt: skip


def check_rate_independent_limit(ctx: Context) -> None:
    """rate_independent_limit() gives (the law with its rate dependence switched off, an equivalent
    rate-independent law); the first, with arbitrary velocities and time steps, responds as the second."""
    law, prop = ctx.law, "rate-independent limit"
    try:
        switched_off, equivalent = law.rate_independent_limit()
    except Exception as error:
        ctx.fail(prop, f"rate_independent_limit() raised {type(error).__name__}: {error}")
    for which, other in (("the law switched off", switched_off), ("the equivalent law", equivalent)):
        if getattr(other, "dims", None) != law.dims or getattr(other, "rigid", True):
            ctx.fail(prop, f"{which} {other!r} must be a non-rigid law with dims = {law.dims}")
    if law_flag(equivalent, "rate_dependent"):
        ctx.fail(prop, f"the equivalent law {equivalent!r} must not be rate dependent")

    @ctx.hypothesis(st.tuples(ctx.histories(1, contact=True), st.sampled_from([1.0, 0.5, 0.125, 7.0])))
    def prop_(example):
        (path, normal, velocity), factor = example
        limit, _, _ = _drive(ctx, prop, switched_off, path, normal, velocity, dt=ctx.dt * factor)
        v_equivalent = path_velocities(path, ctx.dt) if law_flag(equivalent, "uses_velocity") else None
        expected, _, _ = _drive(ctx, prop, equivalent, path, normal, v_equivalent)
        if not _close(limit, expected, 1e-9, ctx.roundoff(path)):
            k = int(np.argmax(np.abs(limit - expected).reshape(len(path), -1).max(axis=1)))
            ctx.fail(prop, f"at step {k} {switched_off!r} gives {limit[k, 0].tolist()} but {equivalent!r} gives "
                           f"{expected[k, 0].tolist()}")  # fmt: skip


def check_linear(ctx: Context) -> None:
    """A ``linear`` law is affine in ``u`` with one constant tangent and a state that never changes."""
    law, prop = ctx.law, "linear"
    state0 = law.initial_state(1)
    zero = _call(law, prop, state0, np.zeros((1, law.dims)), np.full(1, ctx.normal_force_range[1]), ctx.dt)
    K = np.asarray(zero.tangent, dtype=float)
    F0 = _force(ctx, prop, zero, 1)

    @ctx.hypothesis(st.tuples(ctx.histories(1, contact=True), st.sampled_from([1.0, 0.5, 7.0])))
    def prop_(example):
        (path, normal, velocity), factor = example
        state = state0
        for k, u in enumerate(path):
            response = _call(law, prop, state, u, normal[k], ctx.dt * factor, velocity=None if velocity is None else velocity[k])
            tangent = np.asarray(response.tangent, dtype=float)
            if not _close(tangent, K, 1e-12, 1e-12 * float(np.abs(K).max(initial=0.0))):
                ctx.fail(prop, f"at step {k} the tangent is {tangent.tolist()}, not the constant {K.tolist()} a linear "
                               "law must have (drop linear = True)")  # fmt: skip
            expected = F0 + np.einsum("nij,nj->ni", K, u)
            force = _force(ctx, prop, response, 1)
            if not _close(force, expected, 1e-9, ctx.roundoff(path)):
                ctx.fail(prop, f"at step {k} u = {u.tolist()} gives {force.tolist()}, not F(0) + K u = {expected.tolist()}")
            if not _same(response.state, state0):
                ctx.fail(prop, f"at step {k} the state changed to {response.state!r}; a linear law has a constant state")
            state = response.state


def applicable_checks(law: BearingLaw) -> list[Callable[[Context], None]]:
    """The properties that apply to ``law`` (by the flags it declares); a rigid law only has the protocol."""
    if getattr(law, "rigid", False):
        return [check_protocol]
    checks = [check_protocol, check_response_shapes, check_zero_at_rest, check_purity, check_vectorised, check_tangent,
              check_dissipation]  # fmt: skip
    if getattr(law, "symmetric", True):
        checks.append(check_odd)
    if hasattr(law, "force_bound"):
        checks.append(check_force_bound)
    checks.append(check_trial_independence)
    if not law_flag(law, "rate_dependent"):
        checks += [check_committed_state, check_rate_independence]
    if law_flag(law, "per_bearing"):
        checks.append(check_per_bearing)
    if law_flag(law, "normal_coupling"):
        checks.append(check_normal_derivative)
    if law_flag(law, "uses_velocity"):
        checks += [check_velocity_derivative, check_velocity_from_kernel]
    if getattr(law, "dims", 1) == 2 and getattr(law, "isotropic", True):
        checks.append(check_rotation)
    if law_flag(law, "friction"):
        checks += [check_no_contact, check_history]
        if hasattr(law, "force_bound"):
            checks.append(check_normality)
    if hasattr(law, "rate_independent_limit"):
        checks.append(check_rate_independent_limit)
    if law_flag(law, "linear"):
        checks.append(check_linear)
    if callable(getattr(law, "compiled", None)) and not law_flag(law, "uses_velocity"):
        checks.append(check_compiled)
    return checks


def call_compiled(compiled, state, u, normal_force, dt: float) -> LawResponse:
    """Call a law's compiled function (:class:`bearingfw.protocol.CompiledLaw`) as the time step's
    compiled Newton iteration does, from Python: ``state`` is the law's own (packed here), ``u``
    ``(n, dims)``, ``normal_force`` ``(n,)`` (clamped at zero, as the kernel does). Returns the
    answer as a :class:`LawResponse` with the unpacked state, or None when the function declined."""
    import ctypes

    from bearingfw.jit import ANSWERED

    u = np.array(u, dtype=float, order="C")
    n, dims = u.shape
    contact = np.ascontiguousarray(np.maximum(np.asarray(normal_force, dtype=float), 0.0))
    parameters = np.ascontiguousarray(compiled.parameters, dtype=float)
    packed = np.array(compiled.pack(state), dtype=float).reshape(-1)
    force, tangent, dfdn = np.zeros((n, dims)), np.zeros((n, dims, dims)), np.zeros((n, dims))
    new_state = np.zeros(packed.size)
    pointer = (lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))
    status = compiled.function.ctypes(
        pointer(parameters), pointer(packed), pointer(u), pointer(contact), n, dims, float(dt),
        pointer(force), pointer(tangent), pointer(dfdn), pointer(new_state),
    )  # fmt: skip
    if status != ANSWERED:
        return None
    return LawResponse(force, tangent, compiled.unpack(new_state), dforce_dnormal=dfdn)


def check_compiled(ctx: Context) -> None:
    """The compiled function of a law that offers one answers as ``respond``: the same force, tangent,
    ``dforce_dnormal`` (zero for a law without it) and next state, step after step of drawn
    histories (two connectors; to round-off). A function that declines is allowed (the kernel then
    calls ``respond``)."""
    law, prop = ctx.law, "compiled"

    @ctx.hypothesis(ctx.histories(2, contact=True))
    def prop_(example):
        path, normal, _velocity = example
        steps, n, dims = path.shape
        try:
            compiled = law.compiled(n)
        except Exception as error:
            ctx.fail(prop, f"compiled({n}) raised {type(error).__name__}: {error}")
        if compiled is None:
            return
        state = law.initial_state(n)
        coupled = law_flag(law, "normal_coupling")
        for k in range(steps):
            expected = _call(law, prop, state, path[k], normal[k], ctx.dt)
            try:
                got = call_compiled(compiled, state, path[k], normal[k], ctx.dt)
            except Exception as error:
                ctx.fail(prop, f"calling the compiled function raised {type(error).__name__}: {error}")
            if got is None:
                return
            tolerance = ctx.roundoff(path)
            dfdn = np.zeros((n, dims)) if not coupled or expected.dforce_dnormal is None else expected.dforce_dnormal
            for name, a, b, scale in (
                ("force", got.force, expected.force, tolerance),
                ("tangent", got.tangent, expected.tangent, 0.0),
                ("dforce_dnormal", got.dforce_dnormal, dfdn, 0.0),
                ("next state", compiled.pack(got.state), compiled.pack(expected.state), 0.0),
            ):
                b = np.asarray(b, dtype=float).reshape(np.shape(a))
                if not _close(np.asarray(a), b, 1e-12, scale + 1e-12 * float(np.max(np.abs(b), initial=0.0))):
                    ctx.fail(prop, f"step {k} (u={path[k].tolist()}, N={normal[k].tolist()}): the compiled function "
                                   f"gives {name} {np.asarray(a).tolist()}, respond gives {b.tolist()}")  # fmt: skip
            state = expected.state


def _split(law) -> list:
    """A law holding per-bearing arrays as one law per connector (scalar values); else ``[law]``."""
    arrays = {name: getattr(law, name) for name in per_bearing_fields(law) if isinstance(getattr(law, name), np.ndarray)}
    if not arrays:
        return [law]
    count = len(next(iter(arrays.values())))
    return [attrs.evolve(law, **{name: float(value[i]) for name, value in arrays.items()}) for i in range(count)]


def check_array_law(law: BearingLaw, **options) -> None:
    """A law holding per-bearing arrays answers each connector as the law with that connector's values."""
    singles = _split(law)
    ctx = make_context(singles[0], **options)
    n, prop = len(singles), "per-bearing"

    @ctx.hypothesis(ctx.histories(n, contact=True))
    def prop_(example):
        path, normal, velocity = example
        together, _, _ = _drive(ctx, prop, law, path, normal, velocity)
        for i, single in enumerate(singles):
            alone, _, _ = _drive(ctx, prop, single, path[:, i : i + 1], normal[:, i : i + 1],
                                 None if velocity is None else velocity[:, i : i + 1])  # fmt: skip
            if not _close(alone[:, 0], together[:, i], 1e-10, 1e-10 * _scale_of(single, ctx, path)):
                ctx.fail(prop, f"connector {i} differs from {single!r} alone")


def check_law(law: BearingLaw, **options) -> None:
    """Run every applicable property on ``law``; raise :class:`ConformanceError` at the first failure.

    ``options`` go to :func:`make_context`: ``displacement_scale`` (m), ``normal_force_range``
    (N, default 1e5 to 4e6), ``dt`` (s, default 0.01), ``velocity_scale`` (m/s, default 0.1),
    ``max_examples`` per property (default 30), ``max_steps`` per path (default 30; hypothesis
    draws at most about 8 kB per example, which bounds it to about 100), ``shrink``
    (default True: report the smallest failing input hypothesis can find), ``derandomize``
    (default True: the same examples every run) and ``seed`` (another reproducible set). See
    the module docstring for what to run in CI and how to run longer.

    A law holding per-bearing parameter arrays is checked as one law per connector, and as a
    whole against them.
    """
    # The protocol comes first: finding the scales already calls respond().
    check_protocol(Context(law, 1e-3, (0.0, 0.0), 0.0, 0.01, 1))
    singles = _split(law)
    for single in singles:
        ctx = make_context(single, **options)
        for check in applicable_checks(single):
            check(ctx)
    if len(singles) > 1 or singles[0] is not law:
        check_array_law(law, **options)


def parametrize_with_checks(laws: Iterable[BearingLaw], **options):
    """A ``pytest.mark.parametrize`` over (law, check) pairs, one test per law and property.

    Use it on ``def test_conformance(law, check): check(law)``.
    """
    import pytest  # only needed by callers that use pytest

    cases = []
    for law in laws:
        for check in applicable_checks(law):
            run = _bind(check, options)
            cases.append(pytest.param(law, run, id=f"{law.name}-dims{law.dims}-{check.__name__.removeprefix('check_')}"))
    return pytest.mark.parametrize(("law", "check"), cases)


def _bind(check: Callable[[Context], None], options: dict) -> Callable[[BearingLaw], None]:
    def run(law: BearingLaw) -> None:
        check(make_context(law, **options))

    run.__name__ = check.__name__
    return run
