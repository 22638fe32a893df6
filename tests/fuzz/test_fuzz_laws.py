"""Fuzzing ``respond()`` of every registered law: random shapes, NaN and infinite displacements and normal
forces, uplift, huge values, states from earlier calls.

For each call, one of: a :class:`ParameterError` naming the law and the argument at fault; or a
response of the right shapes whose force is finite for finite moderate input and, where an input
was NaN or infinite, is not silently a finite resisting force (refused or propagated). Never
another exception, a hang, or a change to the committed state passed in.
"""

from __future__ import annotations

import copy
import math

import attrs
import numpy as np
import pytest
from fuzz_support import PROFILES, fuzz_settings, time_limit
from hypothesis import given, note
from hypothesis import strategies as st

from bearingfw.parameters import ParameterError
from bearingfw.plugins import get_registry
from bearingfw.protocol import law_flag

BUILTIN = ("frictionless", "linear-spring", "regularized-coulomb")
REGISTRY = get_registry()
LAWS = sorted(name for name, entry in REGISTRY.laws.items() if not getattr(entry.value, "rigid", False))


def typical_parameters(cls) -> dict:
    """Each parameter's typical value, else its default, else a value inside its bounds."""
    chosen = {}
    for field in attrs.fields(cls):
        if field.name == "dims":
            continue
        meta = field.metadata
        if meta.get("typical") is not None:
            chosen[field.name] = meta["typical"]
        elif field.default is not attrs.NOTHING:
            continue
        else:
            low, high, _, _ = meta.get("bounds", (None, None, False, False))
            chosen[field.name] = (low + high) / 2 if low is not None and high is not None else (
                (low or 0.0) + 1.0 if high is None else high - 1.0)
    return chosen


def make_law(name: str, dims: int):
    cls = REGISTRY.laws[name].value
    return cls(**typical_parameters(cls), dims=dims)


moderate = st.floats(-0.2, 0.2, allow_nan=False)
odd = st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, 1e-320, -0.0, 1e6])
normal_values = st.one_of(st.floats(0.0, 2e6, allow_nan=False), st.floats(-1e6, 0.0), st.just(0.0))
odd_normals = st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300])


@st.composite
def calls(draw, name: str):
    dims = draw(st.sampled_from([1, 2]))
    law = make_law(name, dims)
    n = draw(st.integers(1, 4))
    oddity = draw(st.sampled_from(["none", "none", "none", "u shape", "N shape", "v shape", "u values",
                                   "N values", "huge u"]))
    u = np.array(draw(st.lists(moderate, min_size=n * dims, max_size=n * dims))).reshape(n, dims)
    normal = np.array(draw(st.lists(normal_values, min_size=n, max_size=n)))
    velocity = np.array(draw(st.lists(st.floats(-1.0, 1.0), min_size=n * dims, max_size=n * dims))).reshape(n, dims)
    if oddity == "u shape":
        u = draw(st.sampled_from([u.reshape(-1), u.reshape(n, dims, 1), np.zeros((n, dims + 1)), np.zeros(()),
                                  np.zeros((n + 1, 3 - dims))]))
    elif oddity == "N shape":
        normal = draw(st.sampled_from([np.float64(1e5), np.ones((n, 1)), np.ones(n + 1), np.ones(max(n - 1, 0))]))
    elif oddity == "v shape":
        velocity = draw(st.sampled_from([velocity.reshape(-1), np.zeros((n + 1, dims)), np.zeros((n, 3 - dims))]))
    elif oddity == "u values":
        u = u.copy()
        u.reshape(-1)[draw(st.integers(0, n * dims - 1))] = draw(st.sampled_from([math.nan, math.inf, -math.inf]))
    elif oddity == "N values":
        normal = normal.copy()
        normal[draw(st.integers(0, n - 1))] = draw(odd_normals)
    elif oddity == "huge u":
        u = u.copy()
        u.reshape(-1)[draw(st.integers(0, n * dims - 1))] = draw(odd)
    history = draw(st.lists(st.tuples(moderate, st.floats(0.0, 2e6)), max_size=3))
    return law, n, u, normal, velocity, oddity, history


def respond(law, state, u, normal, velocity, dt=0.01):
    if law_flag(law, "uses_velocity"):
        return law.respond(state, u, normal, dt, velocity=velocity)
    return law.respond(state, u, normal, dt)


ARGUMENT = {"u shape": "'u'", "N shape": "'normal_force'", "v shape": "'velocity'", "N values": "'normal_force'"}


def check_call(law, n, u, normal, velocity, oddity, history):
    note(f"{law!r}, {oddity}: u {u!r}, N {normal!r}")
    state = law.initial_state(n)
    for step, N in history:  # a committed state with some history behind it
        state = respond(law, state, np.full((n, law.dims), step), np.full(n, N), np.zeros((n, law.dims))).state
    before = copy.deepcopy(state)
    try:
        with time_limit(5.0, f"{law.name}.respond"), np.errstate(all="ignore"):  # propagation is expected
            response = respond(law, state, u, normal, velocity)
    except ParameterError as refusal:
        message = str(refusal)
        assert law.name in message or type(law).__name__ in message, f"the refusal does not name the law: {message}"
        if oddity in ARGUMENT:
            assert ARGUMENT[oddity] in message, f"the refusal does not name the argument: {message}"
        assert oddity != "none" or "normal" in message, f"moderate input refused: {message}"
        return
    assert oddity not in ("u shape", "N shape", "v shape") or (oddity == "v shape" and not law_flag(law, "uses_velocity")), (
        f"a wrong shape was answered: force {np.shape(response.force)}"
    )
    _assert_same(before, state)
    force, tangent = np.asarray(response.force), np.asarray(response.tangent)
    assert force.shape == (n, law.dims) and tangent.shape == (n, law.dims, law.dims)
    if oddity in ("none", "v shape"):
        assert np.isfinite(force).all() and np.isfinite(tangent).all(), f"moderate input, force {force}"
    elif oddity == "u values":
        bad = ~np.isfinite(u).all(axis=1)
        assert not (np.isfinite(force[bad]).all() and np.any(force[bad] != 0)), (
            f"a NaN or infinite displacement gave the finite force {force[bad]}")
    elif oddity == "N values":
        bad = ~np.isfinite(normal)  # (1e300 is drawn too: finite, if absurd, and may be answered)
        if bad.any() and (law_flag(law, "friction") or law_flag(law, "normal_coupling")):
            assert not np.isfinite(force[bad]).all(), f"a NaN or infinite normal force gave the force {force[bad]}"


def _assert_same(before, after):
    if isinstance(before, dict):
        assert before.keys() == after.keys()
        for key in before:
            _assert_same(before[key], after[key])
    elif isinstance(before, np.ndarray):
        assert np.array_equal(before, after, equal_nan=True), "respond() changed the committed state"


def _law_cases():
    """Every registered law, in each profile (the plugins' laws included: no known findings remain)."""
    return [
        pytest.param(name, profile.values[0], marks=list(profile.marks), id=f"{name}-{profile.id}")
        for name in LAWS
        for profile in PROFILES
    ]


#: Examples per profile run, as a multiple of the profile's: fewer for a law whose calls are costly (Bouc-Wen
#: integrates its hysteretic variable in up to 1000 substeps of a Newton solve per call), in both profiles:
#: the default run stays within seconds.
SCALE = {"bouc-wen": 1}


@pytest.mark.parametrize("name, profile", _law_cases())
def test_respond_refuses_or_answers_soundly(name, profile):
    @fuzz_settings(profile, scale=SCALE.get(name, 3))
    @given(calls(name))
    def check(call):
        check_call(*call)

    check()


PLUGIN_LAWS = ("bouc-wen", "elastomeric-plasticity", "friction-pendulum", "friction-pendulum-vel", "ptfe-friction")


def test_the_builtin_and_plugin_laws_are_all_fuzzed():
    assert set(BUILTIN) <= set(LAWS) and set(PLUGIN_LAWS) <= set(LAWS)


@pytest.mark.parametrize("law, u, normal, argument, expected, given", [
    ("linear-spring", np.zeros(3), np.ones(3), "'u'", "(n, 1)", "(3,)"),  # gave a (3, 3) force before
    ("regularized-coulomb", np.zeros(3), np.ones(3), "'u'", "(n, 1)", "(3,)"),
    ("regularized-coulomb", np.zeros((3, 1)), np.ones(2), "'normal_force'", "(3,)", "(2,)"),
    ("frictionless", np.zeros((2, 2)), np.ones(2), "'u'", "(n, 1)", "(2, 2)"),
])
def test_wrong_shapes_are_named(law, u, normal, argument, expected, given):
    built = make_law(law, 1)
    with pytest.raises(ParameterError) as refused:
        built.respond(built.initial_state(len(u)), u, normal, 0.01)
    message = str(refused.value)
    assert f"law {law!r}: respond() argument {argument} must have shape {expected}" in message
    assert message.endswith(f"got shape {given}")


def test_a_nan_normal_force_is_not_stick():
    """Before: NaN compared as 'no sliding', so a regularized-Coulomb bearing stuck with the stick force."""
    law = make_law("regularized-coulomb", 1)
    with pytest.raises(ParameterError, match=r"law 'regularized-coulomb': .*'normal_force' is nan at connector 1"):
        law.respond(law.initial_state(2), np.full((2, 1), 0.01), np.array([1e6, np.nan]), 0.01)


@pytest.mark.parametrize("law, u, normal, velocity, argument, given", [
    # answered with a (3, 3) force before
    ("elastomeric-plasticity", np.zeros(3), np.ones(3), None, "'u'", "(3,)"),
    ("bouc-wen", np.zeros((2, 2)), np.ones(2), None, "'u'", "(2, 2)"),  # a bare numpy error before
    ("friction-pendulum", np.zeros((1, 1, 1)), np.ones(1), None, "'u'", "(1, 1, 1)"),  # answered before
    ("ptfe-friction", np.zeros((2, 1)), np.ones(2), np.zeros((3, 1)), "'velocity'", "(3, 1)"),  # einsum error
    ("friction-pendulum-vel", np.zeros((2, 1)), np.ones(2), np.zeros(2), "'velocity'", "(2,)"),
    ("ptfe-friction", np.zeros((2, 1)), np.ones(3), np.zeros((2, 1)), "'normal_force'", "(3,)"),
])
def test_plugin_laws_name_a_wrong_shape(law, u, normal, velocity, argument, given):
    built = make_law(law, 1)
    with pytest.raises(ParameterError) as refused:
        respond(built, built.initial_state(2), u, normal, velocity)
    message = str(refused.value)
    assert message.startswith(f"law {law!r}: respond() argument {argument} must have") and f"got shape {given}" in message


@pytest.mark.parametrize("law", ["friction-pendulum", "friction-pendulum-vel", "ptfe-friction"])
def test_plugin_friction_laws_refuse_a_nan_normal_force(law):
    """Before: friction-pendulum treated NaN as no contact and answered the finite force 0."""
    built = make_law(law, 1)
    with pytest.raises(ParameterError, match=rf"law {law!r}: .*'normal_force' is nan at connector 1"):
        respond(built, built.initial_state(2), np.full((2, 1), 0.01), np.array([1e5, np.nan]), np.zeros((2, 1)))


def test_bouc_wen_propagates_a_nan_displacement_to_its_connector_only():
    """Before: ValueError 'cannot convert float NaN to integer'. Now the NaN connector's force is NaN and
    the other connector answers as it would alone."""
    law = make_law("bouc-wen", 1)
    u = np.array([[0.004], [np.nan]])
    response = law.respond(law.initial_state(2), u, np.ones(2), 0.01)
    alone = law.respond(law.initial_state(1), u[:1], np.ones(1), 0.01)
    assert np.isnan(response.force[1]).all() and np.isnan(response.tangent[1]).all()
    assert response.force[0] == pytest.approx(alone.force[0], rel=1e-12) and np.isfinite(response.force[0]).all()
