"""The friction-pendulum laws: closed forms, derivatives, limits, parameters, preset, a free vibration."""

import math

import attrs
import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import bearingfw
from bearingfw import ParameterError, create_law
from bearingfw.testing import check_law
from bearingfw.testing.strategies import laws as law_strategy
from bearingfw_pendulum import FrictionPendulum, VelocityFrictionPendulum
from bearingfw_pendulum.plugin import PRESET_RADIUS, pendulum_preset_law

K, R, MU = 2.0e8, 2.0, 0.05
N0 = 2.0e6
K0 = K - N0 / R  # the friction part's stiffness at N0
SLIDE = MU * N0 / K0  # displacement at which sliding starts from rest


def pendulum(dims=1, **overrides):
    return FrictionPendulum(**{"k": K, "R": R, "mu": MU, **overrides}, dims=dims)


def vel_pendulum(dims=1, **overrides):
    return VelocityFrictionPendulum(**{"k": K, "R": R, "f_min": 0.03, "f_max": 0.08, "a": 20.0, **overrides}, dims=dims)


def step(law, state, u, normal, velocity=None):
    u = np.atleast_2d(np.asarray(u, dtype=float))
    normal = np.atleast_1d(np.asarray(normal, dtype=float))
    if velocity is None:
        return law.respond(state, u, normal, 0.01)
    return law.respond(state, u, normal, 0.01, velocity=np.atleast_2d(np.asarray(velocity, dtype=float)))


def drive(law, u, normal, velocity=None):
    state = law.initial_state(1)
    out = []
    for i in range(len(u)):
        r = step(law, state, u[i], normal[i], None if velocity is None else velocity[i])
        out.append(r.force[0])
        state = r.state
    return np.array(out), state


# --- closed forms -------------------------------------------------------------------------------


def test_monotonic_push_is_bilinear():
    """k up to the slide at mu N / (k - N/R), then mu N + N u / R."""
    law = pendulum()
    u = np.linspace(0.05, 40.0, 60) * SLIDE
    force, state = drive(law, u, np.full(60, N0))
    expected = np.where(u <= SLIDE, K * u, MU * N0 + N0 * u / R)
    np.testing.assert_allclose(force[:, 0], expected, rtol=1e-12)
    assert state["slip"][0, 0] == pytest.approx(u[-1] - MU * N0 / K0, rel=1e-12)


def test_unloading_is_stiff_and_reverse_sliding_starts_two_mu_n_lower():
    law = pendulum()
    top = 0.05
    state = step(law, law.initial_state(1), [top], N0).state
    peak = MU * N0 + N0 * top / R
    # back along k until the friction part reaches -mu N: 2 mu N / k0 below the top
    back = top - 1.5 * MU * N0 / K0
    r = step(law, state, [back], N0)
    assert r.force[0, 0] == pytest.approx(peak - K * (top - back), rel=1e-12)
    assert r.tangent[0, 0, 0] == K
    further = top - 3.0 * MU * N0 / K0
    r = step(law, state, [further], N0)
    assert r.force[0, 0] == pytest.approx(-MU * N0 + N0 * further / R, rel=1e-12)
    assert r.tangent[0, 0, 0] == pytest.approx(N0 / R)


def test_energy_dissipated_per_cycle_is_4_mu_n_times_the_slide():
    """The closed loop between +-U has area 4 mu N (U - mu N / k0) (bilinear, characteristic strength mu N)."""
    law = pendulum()
    amplitude = 0.08
    half = np.linspace(amplitude, -amplitude, 400)
    cycle = np.concatenate([np.linspace(0, amplitude, 200), half, half[::-1], half])
    force, _ = drive(law, cycle, np.full(len(cycle), N0))
    # the last full loop: from +U down to -U and back up to +U
    start = 200 + 400 - 1
    loop_u, loop_f = cycle[start:], force[start:, 0]
    area = -np.trapezoid(loop_f, loop_u)
    assert abs(area) == pytest.approx(4 * MU * N0 * (amplitude - MU * N0 / K0), rel=1e-3)


def test_2d_slides_radially_with_the_restoring_force_added():
    law = pendulum(dims=2)
    u = np.array([0.03, -0.04])
    r = step(law, law.initial_state(1), u, N0)
    direction = u / np.linalg.norm(u)
    np.testing.assert_allclose(r.force[0], MU * N0 * direction + N0 * u / R, rtol=1e-13)
    np.testing.assert_allclose(r.state["slip"][0], u - MU * N0 * direction / K0, rtol=1e-13)
    sliding = K0 * MU * N0 / (K0 * np.linalg.norm(u)) * (np.eye(2) - np.outer(direction, direction))
    expected = sliding + N0 / R * np.eye(2)
    np.testing.assert_allclose(r.tangent[0], expected, rtol=1e-12)


def test_2d_is_rotation_invariant():
    law = vel_pendulum(dims=2)
    rng = np.random.default_rng(3)
    u = np.cumsum(rng.normal(scale=3e-3, size=(50, 2)), axis=0)
    v = rng.normal(scale=0.1, size=(50, 2))
    normal = N0 * (1 + 0.3 * rng.random(50))
    angle = 1.1
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    force, _ = drive(law, u, normal, v)
    turned, _ = drive(law, u @ rot.T, normal, v @ rot.T)
    np.testing.assert_allclose(turned, force @ rot.T, rtol=0, atol=1e-9 * np.abs(force).max())


def test_stick_force_follows_the_normal_force_through_the_slip_only():
    """In stick F = k (u - u_p) + N u_p / R: a change of N at fixed u moves F by dN u_p / R."""
    law = pendulum()
    state = step(law, law.initial_state(1), [0.05], N0).state
    slip = state["slip"][0, 0]
    u = 0.05 - 0.5 * MU * N0 / K0  # back into stick
    a = step(law, state, [u], N0)
    b = step(law, state, [u], 1.1 * N0)
    assert b.force[0, 0] - a.force[0, 0] == pytest.approx(0.1 * N0 * slip / R, rel=1e-9)
    assert a.dforce_dnormal[0, 0] == pytest.approx(slip / R, rel=1e-12)


def test_no_contact_means_no_force_and_the_slip_follows():
    law = vel_pendulum(dims=2)
    state = step(law, law.initial_state(1), [0.03, 0.01], N0, [0.2, 0.0]).state
    for normal in (0.0, -5e5):
        r = step(law, state, [0.04, 0.02], normal, [0.2, 0.1])
        assert np.all(r.force == 0) and np.all(r.tangent == 0)
        assert np.all(r.dforce_dnormal == 0) and np.all(r.dforce_dvelocity == 0)
        np.testing.assert_array_equal(r.state["slip"][0], [0.04, 0.02])


def test_normal_force_beyond_k_r_is_a_clear_error():
    law = pendulum(k=1e6, R=1.0)
    with pytest.raises(ParameterError, match=r"connector 0 carries N = 2e\+06 N.*'k' = 1e\+06"):
        step(law, law.initial_state(1), [0.01], N0)


def test_velocity_none_is_rest_and_respond_is_pure():
    law = vel_pendulum(dims=2)
    state = step(law, law.initial_state(1), [0.02, 0.01], N0, [0.3, 0.0]).state
    before = state["slip"].copy()
    a = law.respond(state, np.array([[0.03, 0.0]]), np.array([N0]), 0.01)
    b = law.respond(state, np.array([[0.03, 0.0]]), np.array([N0]), 0.01, velocity=np.zeros((1, 2)))
    np.testing.assert_array_equal(a.force, b.force)
    np.testing.assert_array_equal(state["slip"], before)


# --- derivatives ----------------------------------------------------------------------------------


def central(f, h):
    return (f(h) - f(-h)) / (2 * h)


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize("sliding", [True, False])
def test_derivatives_match_finite_differences(dims, sliding):
    law = vel_pendulum(dims=dims)
    rng = np.random.default_rng(17)
    for _ in range(15):
        slip = rng.normal(scale=0.02, size=(1, dims))
        state = {"slip": slip}
        direction = rng.normal(size=dims)
        direction /= np.linalg.norm(direction)
        normal = N0 * (0.5 + rng.random())
        reach = 0.03 * normal / (K - normal / R)  # stick range at rest
        u = slip[0] + direction * reach * ((3.0 + 5 * rng.random()) if sliding else 0.5 * rng.random())
        v = rng.normal(scale=0.05, size=dims) * (1.0 if sliding else 0.0)
        r = step(law, state, u, normal, v)
        for j in range(dims):
            e = np.eye(dims)[j]
            du = central(lambda x: step(law, state, u + x * e, normal, v).force[0], 1e-9)
            dv = central(lambda x: step(law, state, u, normal, v + x * e).force[0], 1e-7)
            np.testing.assert_allclose(r.tangent[0, :, j], du, rtol=1e-5, atol=1e-6 * K)
            if sliding:
                np.testing.assert_allclose(r.dforce_dvelocity[0, :, j], dv, rtol=1e-5, atol=1e-6 * N0)
            else:
                assert np.all(r.dforce_dvelocity == 0)
        dn = central(lambda x: step(law, state, u, normal + x, v).force[0], 1.0)
        np.testing.assert_allclose(r.dforce_dnormal[0], dn, rtol=1e-6, atol=1e-12)


# --- limits, arrays, parameters ---------------------------------------------------------------------


@pytest.mark.parametrize("dims", [1, 2])
def test_rate_independent_limit_is_the_constant_friction_pendulum_bit_for_bit(dims):
    frozen, constant = vel_pendulum(dims=dims).rate_independent_limit()
    assert frozen.a == 0.0 and constant == FrictionPendulum(k=K, R=R, mu=0.03, dims=dims)
    assert not getattr(constant, "uses_velocity", False) and not getattr(constant, "rate_dependent", False)
    rng = np.random.default_rng(4)
    u = np.cumsum(rng.normal(scale=4e-3, size=(80, 3, dims)), axis=0)
    v = rng.normal(scale=0.3, size=(80, 3, dims))
    normal = N0 * rng.uniform(-0.2, 1.5, size=(80, 3))
    sf, sc = frozen.initial_state(3), constant.initial_state(3)
    for i in range(80):
        a = frozen.respond(sf, u[i], normal[i], 0.01, velocity=v[i])
        b = constant.respond(sc, u[i], normal[i], 0.01)
        np.testing.assert_array_equal(a.force, b.force)
        np.testing.assert_array_equal(a.tangent, b.tangent)
        np.testing.assert_array_equal(a.dforce_dnormal, b.dforce_dnormal)
        sf, sc = a.state, b.state


def test_equal_coefficients_give_the_constant_pendulum_at_any_velocity():
    law = vel_pendulum(dims=2, f_min=0.05, f_max=0.05)
    rng = np.random.default_rng(9)
    u = np.cumsum(rng.normal(scale=4e-3, size=(60, 2)), axis=0)
    normal = np.full(60, N0)
    a, _ = drive(law, u, normal, rng.normal(scale=0.3, size=(60, 2)))
    b, _ = drive(pendulum(dims=2, mu=0.05), u, normal)
    np.testing.assert_array_equal(a, b)


def test_per_bearing_arrays_equal_separate_laws():
    params = [
        {"k": 2e8, "R": 1.5, "f_min": 0.02, "f_max": 0.06, "a": 10.0},
        {"k": 5e8, "R": 3.0, "f_min": 0.04, "f_max": 0.04, "a": 30.0},
        {"k": 1e8, "R": 2.2, "f_min": 0.01, "f_max": 0.09, "a": 0.0},
    ]
    grouped = VelocityFrictionPendulum(**{key: [p[key] for p in params] for key in params[0]}, dims=2)
    rng = np.random.default_rng(2)
    u = np.cumsum(rng.normal(scale=3e-3, size=(50, 3, 2)), axis=0)
    v = rng.normal(scale=0.1, size=(50, 3, 2))
    normal = N0 * rng.uniform(0.2, 1.5, size=(50, 3))
    state = grouped.initial_state(3)
    together = []
    for i in range(50):
        r = grouped.respond(state, u[i], normal[i], 0.01, velocity=v[i])
        together.append(r.force)
        state = r.state
    together = np.array(together)
    for j, p in enumerate(params):
        alone, _ = drive(VelocityFrictionPendulum(**p, dims=2), u[:, j], normal[:, j], v[:, j])
        np.testing.assert_allclose(together[:, j], alone, rtol=1e-14, atol=1e-9)


@pytest.mark.parametrize(
    ("make", "overrides", "message"),
    [
        (pendulum, {"R": 0.0}, "'R' = 0.0 is outside the allowed range R > 0"),
        (pendulum, {"mu": 1.0}, "'mu' = 1.0 is outside the allowed range 0.001 <= mu < 1"),
        (pendulum, {"k": -1.0}, "'k' = -1.0 is outside the allowed range k > 0"),
        (pendulum, {"R": [2.0, -1.0]}, r"'R'\[1\] = -1.0 is outside"),
        (vel_pendulum, {"f_min": 0.1, "f_max": 0.05}, "'f_min'.*'f_max'.*f_min <= f_max"),
        (vel_pendulum, {"a": -2.0}, "'a' = -2.0 is outside the allowed range a >= 0"),
        (vel_pendulum, {"R": "large"}, "'R' must be a real number or a 1-D array"),
    ],
)
def test_bad_parameters_are_named(make, overrides, message):
    with pytest.raises(ParameterError, match=message):
        make(**overrides)


def test_registered_with_units():
    registry = bearingfw.get_registry()
    assert registry.law_class("friction-pendulum") is FrictionPendulum
    assert registry.law_class("friction-pendulum-vel") is VelocityFrictionPendulum
    assert create_law("friction-pendulum", k=K, R=R, mu=MU, dims=2).dims == 2
    units = {f.name: f.metadata.get("unit") for f in attrs.fields(VelocityFrictionPendulum)}
    assert units["R"] == "m" and units["k"] == "N/m" and units["a"] == "s/m"


# --- the conformance kit ------------------------------------------------------------------------------


@pytest.mark.parametrize("make", [pendulum, vel_pendulum])
@pytest.mark.parametrize("dims", [1, 2])
def test_conforms(make, dims):
    check_law(make(dims=dims), max_examples=8)


@settings(
    max_examples=2,
    deadline=None,
    phases=[Phase.explicit, Phase.generate],  # no shrinking: each example runs the whole kit
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.nested_given],
)
@given(data=st.data())
def test_conforms_on_random_admissible_parameters(data):
    cls = data.draw(st.sampled_from([FrictionPendulum, VelocityFrictionPendulum]))
    check_law(data.draw(law_strategy(cls, dims=st.sampled_from([1, 2]))), max_examples=4, shrink=False)


# --- the preset ---------------------------------------------------------------------------------------------


def test_preset():
    name, params = pendulum_preset_law(bearingfw.PresetBearing("1A", ks=4e8, friction=0.04))
    law = create_law(name, **params, dims=2)
    assert 2 * math.pi * math.sqrt(law.R / 9.81) == pytest.approx(3.0)
    assert (law.k, law.mu) == (4e8, 0.04) and law.R == PRESET_RADIUS
    assert not bearingfw.get_registry().preset("pendulum").needs_dead_load


# --- inside a transient analysis ------------------------------------------------------------------------


def test_free_vibration_has_the_pendulum_period_and_a_linear_decay_of_2_mu_r_per_half_cycle():
    """A block on a friction pendulum, set swinging by a ground pulse, then free: it swings at
    omega = sqrt(g / R) about offsets +-mu R, so each half cycle the amplitude falls by 2 mu R
    (Coulomb damping; the stick compliance mu N / k0 = 0.5 mm changes it by < 1 %)."""
    from bearingfw.analysis import NodalResponse, TransientSettings, solve_transient
    from bearingfw.model import Connector, Model, NodalMass, Node, Support

    mass, g, radius, mu = 2.0e5, 9.81, 2.0, 0.02
    model = Model(
        [Node("g", 0, 0, 0), Node("m", 0, 0, 0)],
        connectors=[Connector("fp", "g", "m", "axial", law="friction-pendulum",
                              law_params={"k": 2e8, "R": radius, "mu": mu}, vertical_stiffness=1e10)],  # fmt: skip
        supports=[Support("g")],
        masses=[NodalMass("m", mass)],
    )
    dt = 0.01
    steps = 1200
    ag = np.zeros((steps, 3))
    ag[1:101, 0] = 2.0  # a 1 s pulse: the block swings out about 0.6 m
    result = solve_transient(model, ag, dt, settings=TransientSettings(alpha=0.0),
                             recorders=[NodalResponse(["m"], "displacement", name="x")])  # fmt: skip
    x = result.data["x"][:, 0, 0]
    free = x[150:]
    # the extrema of the free swing (sign changes of the increments)
    turning = np.flatnonzero(np.sign(np.diff(free[1:])) != np.sign(np.diff(free[:-1]))) + 1
    peaks = free[turning]
    assert len(peaks) >= 6, peaks
    decay = np.abs(peaks[:-1]) - np.abs(peaks[1:])
    np.testing.assert_allclose(decay[:4], 2 * mu * radius, rtol=0.02)
    # each turning point is known to a sample: average over four half cycles
    half_period = (turning[4] - turning[0]) * dt / 4
    assert half_period == pytest.approx(math.pi * math.sqrt(radius / g), rel=0.01)
