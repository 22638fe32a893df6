"""The conformance suite: properties every bearing law must have, checked with hypothesis.

A law author runs it in one line from pytest::

    from bearingfw.testing import check_law

    def test_my_law_conforms():
        check_law(MyLaw(k=4e8))

or, to get one test per property, ``@parametrize_with_checks([MyLaw(k=4e8)])`` on a test
``def test_conformance(law, check): check(law)``.

Each property raises :class:`ConformanceError` (an ``AssertionError``) whose message starts
with the law's name and the property's name, and hypothesis prints the smallest failing input.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Iterable

import attrs
import numpy as np
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from bearingfw.protocol import PROTOCOL_MEMBERS, BearingLaw, LawResponse
from bearingfw.testing.drive import run_history
from bearingfw.testing.strategies import closed_cycles, displacement_paths, normal_force_histories


class ConformanceError(AssertionError):
    """A law broke one property of the conformance suite."""

    def __init__(self, law_name: str, prop: str, detail: str):
        super().__init__(f"law {law_name!r} breaks property '{prop}': {detail}")
        self.law_name = law_name
        self.prop = prop


@attrs.frozen
class Context:
    """The law under test and the scales its random inputs are drawn at."""

    law: BearingLaw
    displacement_scale: float
    normal_force_range: tuple[float, float]
    elastic_stiffness: float
    dt: float
    max_examples: int
    shrink: bool = True

    @property
    def force_scale(self) -> float:
        return max(self.elastic_stiffness * self.displacement_scale, 1e-300)

    def fail(self, prop: str, detail: str):
        raise ConformanceError(self.law.name, prop, detail)

    def paths(self, n: int | None = None):
        return displacement_paths(self.law.dims, self.displacement_scale, n=n)

    def forces(self, steps: int, n: int | None = None):
        return normal_force_histories(steps, *self.normal_force_range, n=n)

    def paths_with_forces(self, n: int | None = None):
        """A displacement path and a normal-force history of the same length."""
        return self.paths(n).flatmap(lambda path: st.tuples(st.just(path), self.forces(len(path), n)))

    def hypothesis(self, strategy: st.SearchStrategy):
        """Decorate a one-argument property: run it at once over examples drawn from ``strategy``."""

        def decorate(body: Callable):
            runner = settings(
                max_examples=self.max_examples,
                deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
                # Shrinking finds the smallest failing input but can take a minute for a law
                # that fails late; callers that only need pass/fail switch it off.
                phases=[Phase.explicit, Phase.reuse, Phase.generate] + ([Phase.shrink] if self.shrink else []),
            )(given(strategy)(body))
            runner()
            return runner

        return decorate


def make_context(
    law: BearingLaw,
    displacement_scale: float | None = None,
    normal_force_range: tuple[float, float] = (1e5, 4e6),
    dt: float = 0.01,
    max_examples: int = 30,
    shrink: bool = True,
) -> Context:
    """Find the law's scales: the initial stiffness and, if it has one, the force bound.

    Without an explicit ``displacement_scale`` the inputs are drawn around the displacement at
    which the force reaches its bound (friction: ``mu N / k``), or 1 mm.
    """
    low, high = normal_force_range
    if not 0 <= low <= high:
        raise ValueError(f"normal_force_range must satisfy 0 <= low <= high, got {normal_force_range}")
    stiffness = 0.0
    if not law.rigid:
        mid = np.array([0.5 * (low + high)])
        response = law.respond(law.initial_state(1), np.zeros((1, law.dims)), mid, dt)
        stiffness = float(np.max(np.abs(response.tangent)))
        bound = float(law.force_bound(mid)[0]) if hasattr(law, "force_bound") else 0.0
        if displacement_scale is None and stiffness > 0 and bound > 0:
            displacement_scale = bound / stiffness
    return Context(law, displacement_scale or 1e-3, (low, high), stiffness, dt, max_examples, shrink)


def _same(a, b) -> bool:
    """Deep equality of states: dicts, sequences, numpy arrays (NaNs equal), attrs objects."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.shape == b.shape and a.dtype == b.dtype and bool(np.array_equal(a, b, equal_nan=a.dtype.kind == "f"))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if attrs.has(type(a)) and type(a) is type(b):
        return all(_same(getattr(a, f.name), getattr(b, f.name)) for f in attrs.fields(type(a)))
    return bool(a == b)


# --- the properties -------------------------------------------------------------------------


def check_protocol(ctx: Context) -> None:
    """The law has every protocol member with a valid value."""
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


def check_response_shapes(ctx: Context) -> None:
    """respond returns a LawResponse with force (n, dims) and tangent (n, dims, dims), finite."""
    law, dims = ctx.law, ctx.law.dims

    @ctx.hypothesis(st.integers(1, 4).flatmap(lambda n: st.tuples(ctx.paths(n), st.just(n))))
    def prop(example):
        path, n = example
        state = law.initial_state(n)
        for u, normal in zip(path, np.full((len(path), n), ctx.normal_force_range[1])):
            response = law.respond(state, u, normal, ctx.dt)
            if not isinstance(response, LawResponse):
                ctx.fail("response shapes", f"respond returned {type(response).__name__}, not LawResponse")
            force, tangent = np.asarray(response.force), np.asarray(response.tangent)
            if force.shape != (n, dims) or tangent.shape != (n, dims, dims):
                ctx.fail(
                    "response shapes",
                    f"for n={n}: force {force.shape} (expected {(n, dims)}), tangent {tangent.shape} "
                    f"(expected {(n, dims, dims)})",
                )
            if not (np.all(np.isfinite(force)) and np.all(np.isfinite(tangent))):
                ctx.fail("response shapes", f"non-finite force or tangent at u={u.tolist()}")
            state = response.state


def check_zero_at_rest(ctx: Context) -> None:
    """Zero displacement from the initial state gives zero force (and zero slip, if reported)."""
    law = ctx.law

    @ctx.hypothesis(st.integers(1, 4).flatmap(lambda n: ctx.forces(1, n)))
    def prop(normal):
        n = normal.shape[1]
        force = law.respond(law.initial_state(n), np.zeros((n, law.dims)), normal[0], ctx.dt).force
        if np.any(np.abs(force) > 1e-12 * ctx.force_scale):
            ctx.fail("zero force at rest", f"force {np.asarray(force).tolist()} at zero displacement")
        if hasattr(law, "slip"):
            slip = np.asarray(law.slip(law.initial_state(n)))
            if slip.shape != (n, law.dims) or np.any(slip != 0):
                ctx.fail("zero force at rest", f"slip(initial_state({n})) is {slip.tolist()}, not zeros of shape {(n, law.dims)}")


def check_purity(ctx: Context) -> None:
    """respond never mutates the state it is given, and the same call gives the same answer."""
    law = ctx.law

    @ctx.hypothesis(ctx.paths())
    def prop(path):
        state = law.initial_state(1)
        normal = np.array([ctx.normal_force_range[1]])
        for u in path:
            before = copy.deepcopy(state)
            first = law.respond(state, u[None, :], normal, ctx.dt)
            if not _same(before, state):
                ctx.fail("purity", f"respond mutated its input state at u={u.tolist()}")
            second = law.respond(state, u[None, :], normal, ctx.dt)
            if not (_same(first.force, second.force) and _same(first.tangent, second.tangent) and _same(first.state, second.state)):
                ctx.fail("purity", f"two identical calls gave different results at u={u.tolist()}")
            state = first.state


def check_vectorised(ctx: Context) -> None:
    """n connectors answered together equal each connector answered alone."""
    law = ctx.law
    n = 3
    @ctx.hypothesis(ctx.paths_with_forces(n))
    def prop(example):
        path, normal = example
        together, _, _ = run_history(law, path, normal, ctx.dt, n=n)
        for i in range(n):
            alone, _, _ = run_history(law, path[:, i : i + 1], normal[:, i : i + 1], ctx.dt, n=1)
            if not np.allclose(alone[:, 0], together[:, i], rtol=1e-10, atol=1e-12 * ctx.force_scale):
                ctx.fail("vectorised", f"connector {i} of {n} differs from the same connector alone")


def check_tangent(ctx: Context) -> None:
    """The tangent equals the finite-difference derivative of the force (central, or one-sided at a kink)."""
    law, dims = ctx.law, ctx.law.dims
    @ctx.hypothesis(ctx.paths_with_forces())
    def prop(example):
        path, normal = example
        state = law.initial_state(1)
        for u, force_n in zip(path[:-1], normal[:-1]):
            state = law.respond(state, u[None, :], np.array([force_n]), ctx.dt).state
        u, n_last = path[-1][None, :], np.array([normal[-1]])
        tangent = np.asarray(law.respond(state, u, n_last, ctx.dt).tangent)[0]
        h = 1e-6 * max(ctx.displacement_scale, float(np.max(np.abs(u))))

        def force_at(du):
            return np.asarray(law.respond(state, u + du, n_last, ctx.dt).force)[0]

        f0 = force_at(np.zeros((1, dims)))
        scale = max(ctx.elastic_stiffness, float(np.max(np.abs(tangent))), 1e-300)
        for j in range(dims):
            step = np.zeros((1, dims))
            step[0, j] = h
            plus, minus = force_at(step), force_at(-step)
            # Second-order one-sided differences: at a kink (stick/slip) the tangent is one of
            # the one-sided derivatives, and first-order ones err by h times the curvature.
            candidates = {
                "central": (plus - minus) / (2 * h),
                "forward": (4 * plus - 3 * f0 - force_at(2 * step)) / (2 * h),
                "backward": (3 * f0 - 4 * minus + force_at(-2 * step)) / (2 * h),
            }
            errors = {kind: float(np.max(np.abs(fd - tangent[:, j]))) for kind, fd in candidates.items()}
            if min(errors.values()) > 1e-5 * max(scale, float(np.max(np.abs(candidates["central"])))):
                ctx.fail(
                    "tangent",
                    f"column {j} of the tangent at u={u[0].tolist()}, N={n_last[0]:g} is {tangent[:, j].tolist()} "
                    f"but finite differences give {candidates['central'].tolist()}",
                )


def check_dissipation(ctx: Context) -> None:
    """The work done on the law over a closed displacement cycle is not negative."""
    law = ctx.law
    normal = 0.5 * sum(ctx.normal_force_range)

    @ctx.hypothesis(closed_cycles(law.dims, ctx.displacement_scale))
    def prop(cycle):
        forces, _, _ = run_history(law, cycle, normal, ctx.dt)
        u = np.concatenate([np.zeros((1, law.dims)), cycle])
        f = np.concatenate([np.zeros((1, law.dims)), forces[:, 0]])
        # Trapezoidal work of the discrete response; exact for the elastic part.
        increments = np.einsum("ij,ij->i", 0.5 * (f[1:] + f[:-1]), np.diff(u, axis=0))
        work = float(increments.sum())
        tolerance = 1e-9 * float(np.abs(increments).sum()) + 1e-12 * ctx.force_scale * ctx.displacement_scale
        if work < -tolerance:
            ctx.fail("dissipation", f"the work over a closed cycle is {work:.6g} < 0 (the law creates energy)")


def check_odd(ctx: Context) -> None:
    """A symmetric law answers the mirrored path with the mirrored force."""
    law = ctx.law
    @ctx.hypothesis(ctx.paths_with_forces())
    def prop(example):
        path, normal = example
        forward, _, _ = run_history(law, path, normal, ctx.dt)
        mirrored, _, _ = run_history(law, -path, normal, ctx.dt)
        if not np.allclose(mirrored, -forward, rtol=1e-9, atol=1e-12 * ctx.force_scale):
            ctx.fail("odd symmetry", "the force for -u is not -F(u); declare symmetric = False if that is intended")


def check_force_bound(ctx: Context) -> None:
    """The force never exceeds the bound the law declares with force_bound(normal_force)."""
    law = ctx.law
    @ctx.hypothesis(ctx.paths_with_forces())
    def prop(example):
        path, normal = example
        forces, _, _ = run_history(law, path, normal, ctx.dt)
        magnitude = np.linalg.norm(forces[:, 0], axis=1)
        bound = np.asarray(law.force_bound(normal), dtype=float)
        excess = magnitude - bound * (1 + 1e-12)
        worst = int(np.argmax(excess))
        if excess[worst] > 1e-12 * ctx.force_scale:
            ctx.fail(
                "force bound",
                f"|F| = {magnitude[worst]:.6g} exceeds the declared bound {bound[worst]:.6g} at step {worst} "
                f"(u={path[worst].tolist()}, N={normal[worst]:g})",
            )


def applicable_checks(law: BearingLaw) -> list[Callable[[Context], None]]:
    """The properties that apply to ``law``: a rigid law only has to satisfy the protocol."""
    if getattr(law, "rigid", False):
        return [check_protocol]
    checks = [check_protocol, check_response_shapes, check_zero_at_rest, check_purity, check_vectorised, check_tangent, check_dissipation]
    if getattr(law, "symmetric", True):
        checks.append(check_odd)
    if hasattr(law, "force_bound"):
        checks.append(check_force_bound)
    return checks


def check_law(law: BearingLaw, **options) -> None:
    """Run every applicable property on ``law``; raise :class:`ConformanceError` at the first failure.

    ``options`` go to :func:`make_context`: ``displacement_scale`` (m), ``normal_force_range``
    (N, default 1e5 to 4e6), ``dt`` (s), ``max_examples`` per property (default 30), ``shrink``
    (default True: report the smallest failing input hypothesis can find).
    """
    # The protocol comes first: finding the scales already calls respond().
    check_protocol(Context(law, 1e-3, (0.0, 0.0), 0.0, 0.01, 1))
    ctx = make_context(law, **options)
    for check in applicable_checks(law):
        check(ctx)


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
