"""The ptfe-friction law: coefficient, stick/slip closed forms, derivatives, limits, parameters, preset."""

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
from bearingfw_ptfe import PTFEFriction
from bearingfw_ptfe.plugin import ptfe_preset_law

K = 2.0e8
N0 = 2.0e6
PRESSURE = {"area": 0.1, "delta_mu": 0.02, "alpha": 5e-8}  # alpha N0 / area = 1


def ptfe(dims=1, **overrides):
    params = {"k": K, "f_min": 0.03, "f_max": 0.09, "a": 20.0, **overrides}
    return PTFEFriction(**params, dims=dims)


def opensees_coefficient(mu_slow, mu_fast0, transition, speed, normal=0.0, area=1.0, delta_mu=0.0, alpha=0.0):
    """OpenSees's VelPressureDep::setTrial, transcribed independently (muFast from the pressure, then mu)."""
    fast = mu_fast0 - delta_mu * math.tanh(alpha * normal / area) if normal > 0 else mu_fast0
    return fast - (fast - mu_slow) * math.exp(-transition * abs(speed))


def step(law, state, u, normal, velocity):
    u = np.atleast_2d(np.asarray(u, dtype=float))
    velocity = np.atleast_2d(np.asarray(velocity, dtype=float))
    return law.respond(state, u, np.atleast_1d(np.asarray(normal, dtype=float)), 0.01, velocity=velocity)


# --- the coefficient -------------------------------------------------------------------------


@pytest.mark.parametrize("speed", [0.0, 1e-3, 0.05, 0.3, 2.0])
@pytest.mark.parametrize("normal", [0.0, 5e5, 2e6, 2e7])
def test_coefficient_is_opensees_vel_pressure_dep(speed, normal):
    law = ptfe(**PRESSURE)
    expected = opensees_coefficient(0.03, 0.09, 20.0, speed, normal, 0.1, 0.02, 5e-8)
    assert law.coefficient(np.array([speed]), np.array([normal]))[0] == pytest.approx(expected, rel=1e-13, abs=1e-16)


def test_coefficient_closed_form_points():
    law = ptfe()
    mu = law.coefficient(np.array([0.0, 1.0 / 20.0, 10.0]), np.full(3, N0))
    assert mu[0] == 0.03  # at rest: f_min exactly
    assert mu[1] == pytest.approx(0.09 - 0.06 / math.e, rel=1e-14)
    assert mu[2] == pytest.approx(0.09, rel=1e-12)
    pressured = ptfe(**PRESSURE).coefficient(np.array([10.0]), np.array([N0]))[0]
    assert pressured == pytest.approx(0.09 - 0.02 * math.tanh(1.0), rel=1e-12)  # f_max falls with the pressure


def test_coefficient_is_f_min_exactly_when_a_is_zero():
    law = ptfe(a=0.0, **PRESSURE)
    assert np.all(law.coefficient(np.array([0.0, 0.3, 50.0]), np.array([1e5, 2e6, 9e7])) == 0.03)


# --- closed forms ------------------------------------------------------------------------------


def test_stick_then_slip_at_mu_of_the_velocity_1d():
    """Monotonic push at a constant velocity: F = k u up to mu(v) N, then mu(v) N."""
    law = ptfe()
    v = 0.04
    mu = 0.09 - 0.06 * math.exp(-20.0 * v)
    yield_u = mu * N0 / K
    state = law.initial_state(1)
    for u in np.linspace(0.1, 3.0, 30) * yield_u:
        r = step(law, state, [u], N0, [v])
        expected = min(K * u, mu * N0)
        assert r.force[0, 0] == pytest.approx(expected, rel=1e-12)
        assert r.tangent[0, 0, 0] == (K if K * u < mu * N0 else 0.0)
        state = r.state
    assert state["slip"][0, 0] == pytest.approx(3.0 * yield_u - mu * N0 / K, rel=1e-12)


def test_velocity_reversal_changes_the_capacity_not_the_sign():
    """Sliding on while the velocity changes: |F| follows mu(|v|) N; the slip direction follows u, not v."""
    law = ptfe()
    state = step(law, law.initial_state(1), [0.01], N0, [0.5]).state
    for v in (0.5, 0.05, 0.0, -0.05):
        r = step(law, state, [0.01 + 1e-3], N0, [v])
        mu = 0.09 - 0.06 * math.exp(-20.0 * abs(v))
        assert r.force[0, 0] == pytest.approx(mu * N0, rel=1e-12)


def test_2d_slip_is_radial_with_the_speed_as_norm():
    law = ptfe(dims=2)
    velocity = np.array([0.03, -0.04])  # |v| = 0.05
    mu = 0.09 - 0.06 * math.exp(-20.0 * 0.05)
    u = np.array([0.004, 0.002])
    r = step(law, law.initial_state(1), u, N0, velocity)
    direction = u / np.linalg.norm(u)
    np.testing.assert_allclose(r.force[0], mu * N0 * direction, rtol=1e-13)
    np.testing.assert_allclose(r.state["slip"][0], u - mu * N0 * direction / K, rtol=1e-13)


def test_2d_is_rotation_invariant():
    law = ptfe(dims=2, **PRESSURE)
    rng = np.random.default_rng(3)
    u = np.cumsum(rng.normal(scale=4e-4, size=(40, 2)), axis=0)
    v = rng.normal(scale=0.05, size=(40, 2))
    normal = N0 * (1.0 + 0.3 * rng.random(40))
    angle = 0.7
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    state, turned = law.initial_state(1), law.initial_state(1)
    for i in range(40):
        r = step(law, state, u[i], normal[i], v[i])
        t = step(law, turned, rot @ u[i], normal[i], rot @ v[i])
        np.testing.assert_allclose(t.force[0], rot @ r.force[0], rtol=0, atol=1e-9 * N0)
        state, turned = r.state, t.state


def test_no_contact_means_no_force_and_the_slip_follows():
    law = ptfe(dims=2, **PRESSURE)
    state = step(law, law.initial_state(1), [0.003, 0.0], N0, [0.1, 0.0]).state
    for normal in (0.0, -1e5):
        r = step(law, state, [0.004, 0.001], normal, [0.1, 0.0])
        assert np.all(r.force == 0) and np.all(r.tangent == 0)
        assert np.all(r.dforce_dnormal == 0) and np.all(r.dforce_dvelocity == 0)
        np.testing.assert_array_equal(r.state["slip"][0], [0.004, 0.001])


def test_velocity_none_is_rest():
    law = ptfe(dims=2)
    state = law.initial_state(2)
    u = np.array([[0.003, 0.001], [-1e-4, 2e-4]])
    normal = np.array([N0, N0])
    a = law.respond(state, u, normal, 0.01)
    b = law.respond(state, u, normal, 0.01, velocity=np.zeros((2, 2)))
    np.testing.assert_array_equal(a.force, b.force)
    np.testing.assert_array_equal(a.state["slip"], b.state["slip"])


def test_respond_is_pure():
    law = ptfe(dims=2)
    state = step(law, law.initial_state(1), [0.003, 0.001], N0, [0.1, 0.0]).state
    before = state["slip"].copy()
    step(law, state, [0.005, 0.002], N0, [0.2, 0.1])
    np.testing.assert_array_equal(state["slip"], before)


# --- derivatives against finite differences ---------------------------------------------------


def central(f, x, h):
    return (f(x + h) - f(x - h)) / (2 * h)


@pytest.mark.parametrize("dims", [1, 2])
def test_derivatives_match_finite_differences_in_slip(dims):
    law = ptfe(dims=dims, **PRESSURE)
    rng = np.random.default_rng(11)
    for _ in range(20):
        slip = rng.normal(scale=1e-3, size=(1, dims))
        state = {"slip": slip}
        direction = rng.normal(size=dims)
        direction /= np.linalg.norm(direction)
        # a trial force well outside the circle: sliding, away from the stick/slip boundary
        u = slip[0] + direction * (3.0 + 5 * rng.random()) * 0.09 * N0 / K
        v = rng.normal(scale=0.05, size=dims)
        normal = N0 * (0.5 + rng.random())
        r = step(law, state, u, normal, v)
        h_u, h_v, h_n = 1e-9, 1e-7, 1.0
        for j in range(dims):
            e = np.eye(dims)[j]
            du = central(lambda x: step(law, state, u + x * e, normal, v).force[0], 0.0, h_u)
            dv = central(lambda x: step(law, state, u, normal, v + x * e).force[0], 0.0, h_v)
            np.testing.assert_allclose(r.tangent[0, :, j], du, rtol=1e-5, atol=1e-6 * K)
            np.testing.assert_allclose(r.dforce_dvelocity[0, :, j], dv, rtol=1e-5, atol=1e-6 * N0)
        dn = central(lambda x: step(law, state, u, normal + x, v).force[0], 0.0, h_n)
        np.testing.assert_allclose(r.dforce_dnormal[0], dn, rtol=1e-6, atol=1e-9)


def test_derivatives_in_stick():
    law = ptfe(dims=2, **PRESSURE)
    r = step(law, law.initial_state(1), [1e-4, -2e-4], N0, [0.3, 0.1])
    np.testing.assert_array_equal(r.tangent[0], K * np.eye(2))
    assert np.all(r.dforce_dvelocity == 0) and np.all(r.dforce_dnormal == 0)


def test_velocity_derivative_is_zero_at_rest():
    law = ptfe()
    r = step(law, law.initial_state(1), [0.01], N0, [0.0])
    assert r.dforce_dvelocity[0, 0, 0] == 0.0
    assert r.force[0, 0] == pytest.approx(0.03 * N0)


# --- the rate-independent limit -------------------------------------------------------------------


def drive_with_velocity(law, u, normal, velocity, n=1):
    state = law.initial_state(n)
    out = []
    for i in range(len(u)):
        kwargs = {"velocity": velocity[i]} if getattr(law, "uses_velocity", False) else {}
        r = law.respond(state, u[i], normal[i], 0.01, **kwargs)
        out.append(r.force)
        state = r.state
    return np.array(out)


@pytest.mark.parametrize("dims", [1, 2])
def test_rate_independent_limit_is_regularized_coulomb_bit_for_bit(dims):
    law = ptfe(dims=dims, **PRESSURE)
    frozen, coulomb = law.rate_independent_limit()
    assert frozen.a == 0.0 and coulomb.name == "regularized-coulomb"
    assert not getattr(coulomb, "uses_velocity", False) and not getattr(coulomb, "rate_dependent", False)
    rng = np.random.default_rng(5)
    steps, n = 80, 3
    u = np.cumsum(rng.normal(scale=3e-4, size=(steps, n, dims)), axis=0)
    velocity = rng.normal(scale=0.3, size=(steps, n, dims))
    normal = N0 * rng.uniform(-0.2, 1.5, size=(steps, n))  # includes lift-off
    np.testing.assert_array_equal(
        drive_with_velocity(frozen, u, normal, velocity, n), drive_with_velocity(coulomb, u, normal, velocity, n)
    )


def test_equal_coefficients_are_coulomb_at_f_max_at_any_velocity():
    law = ptfe(dims=2, f_min=0.06, f_max=0.06)
    coulomb = create_law("regularized-coulomb", k=K, mu=0.06, dims=2)
    rng = np.random.default_rng(8)
    u = np.cumsum(rng.normal(scale=3e-4, size=(60, 1, 2)), axis=0)
    velocity = rng.normal(scale=0.3, size=(60, 1, 2))
    normal = np.full((60, 1), N0)
    np.testing.assert_array_equal(
        drive_with_velocity(law, u, normal, velocity), drive_with_velocity(coulomb, u, normal, velocity)
    )


# --- per-bearing arrays, vectorisation ------------------------------------------------------------


def test_per_bearing_arrays_equal_separate_laws():
    params = [
        {"k": 2e8, "f_min": 0.02, "f_max": 0.06, "a": 10.0, "area": 0.1, "delta_mu": 0.01, "alpha": 4e-8},
        {"k": 5e8, "f_min": 0.03, "f_max": 0.03, "a": 30.0, "area": 0.2, "delta_mu": 0.0, "alpha": 0.0},
        {"k": 1e8, "f_min": 0.01, "f_max": 0.08, "a": 0.0, "area": 0.05, "delta_mu": 0.05, "alpha": 1e-8},
    ]
    grouped = PTFEFriction(**{key: [p[key] for p in params] for key in params[0]}, dims=2)
    rng = np.random.default_rng(2)
    u = np.cumsum(rng.normal(scale=3e-4, size=(50, 3, 2)), axis=0)
    velocity = rng.normal(scale=0.1, size=(50, 3, 2))
    normal = N0 * rng.uniform(0.2, 1.5, size=(50, 3))
    together = drive_with_velocity(grouped, u, normal, velocity, 3)
    for i, p in enumerate(params):
        alone = drive_with_velocity(PTFEFriction(**p, dims=2), u[:, i : i + 1], normal[:, i : i + 1],
                                    velocity[:, i : i + 1])  # fmt: skip
        np.testing.assert_allclose(together[:, i], alone[:, 0], rtol=1e-14, atol=1e-9)


def test_array_length_must_match_the_connectors():
    law = PTFEFriction(k=[2e8, 3e8], f_min=0.02, f_max=0.05, a=20.0)
    with pytest.raises(ParameterError, match="'k' holds 2 per-bearing values.*3 connector"):
        law.initial_state(3)


# --- parameters ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"f_min": 0.1, "f_max": 0.05}, "'f_min'.*'f_max'.*f_min <= f_max"),
        ({"f_max": 1.0}, "'f_max' = 1.0 is outside the allowed range 0.001 <= f_max < 1"),
        ({"a": -1.0}, "'a' = -1.0 is outside the allowed range a >= 0"),
        ({"k": 0.0}, "'k' = 0.0 is outside the allowed range k > 0"),
        ({"delta_mu": 0.07, "area": 0.1, "alpha": 1e-8}, "'delta_mu'.*delta_mu <= f_max - f_min"),
        ({"delta_mu": 0.01, "alpha": 1e-8}, "give 'area'"),
        ({"area": 0.0}, "'area' = 0.0 is outside the allowed range area > 0"),
        ({"f_min": [0.02, 0.2], "f_max": [0.05, 0.1]}, "f_min <= f_max"),
        ({"f_min": [0.02, -0.1]}, r"'f_min'\[1\] = -0.1 is outside"),
        ({"f_min": 0.0}, "'f_min' = 0.0 is outside the allowed range 0.001 <= f_min < 1"),
        ({"k": "stiff"}, "'k' must be a real number or a 1-D array"),
    ],
)
def test_bad_parameters_are_named(overrides, message):
    with pytest.raises(ParameterError, match=message):
        ptfe(**overrides)


def test_registered_with_ranges_and_units():
    registry = bearingfw.get_registry()
    assert registry.law_class("ptfe-friction") is PTFEFriction
    law = create_law("ptfe-friction", k=K, f_min=0.02, f_max=0.05, a=20.0, dims=2)
    assert law.dims == 2
    fields = {f.name: f.metadata for f in attrs.fields(PTFEFriction)}
    assert fields["a"]["unit"] == "s/m" and fields["area"]["unit"] == "m^2" and fields["alpha"]["unit"] == "1/Pa"


# --- the conformance kit ------------------------------------------------------------------------------


@pytest.mark.parametrize("dims", [1, 2])
def test_conforms(dims):
    check_law(ptfe(dims=dims, **PRESSURE), max_examples=8)


@settings(
    max_examples=2,
    deadline=None,
    phases=[Phase.explicit, Phase.generate],  # no shrinking: each example runs the whole kit
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.nested_given],
)
@given(law=law_strategy(PTFEFriction, dims=st.sampled_from([1, 2])))
def test_conforms_on_random_admissible_parameters(law):
    check_law(law, max_examples=4, shrink=False)


# --- the preset ------------------------------------------------------------------------------------------


def test_preset_gives_the_bearings_friction_at_speed_and_dead_load():
    bearing = bearingfw.PresetBearing("1A", ks=4e8, friction=0.04, dead_load=3.0e6)
    name, params = ptfe_preset_law(bearing)
    law = create_law(name, **params, dims=2)
    assert law.coefficient(np.array([5.0]), np.array([3.0e6]))[0] == pytest.approx(0.04, rel=1e-9)
    assert law.coefficient(np.array([0.0]), np.array([3.0e6]))[0] == pytest.approx(0.02)
    more, less = law.coefficient(np.array([5.0, 5.0]), np.array([6.0e6, 1.5e6]))
    assert more < 0.04 < less  # f_max falls with the pressure
    assert bearingfw.get_registry().preset("ptfe").needs_dead_load


def test_preset_needs_a_compressed_bearing():
    with pytest.raises(ParameterError, match="bearing '2B'.*N > 0"):
        ptfe_preset_law(bearingfw.PresetBearing("2B", ks=4e8, friction=0.04, dead_load=0.0))


# --- inside a transient analysis ------------------------------------------------------------------------


def test_block_under_constant_ground_acceleration_reaches_the_terminal_sliding_speed():
    """A block on a PTFE bearing, ground acceleration a0 with f_min g < a0 < f_max g: relative to the
    ground it slides at the speed where mu(v) g = a0, here mu(v) = 0.06 at v = ln 2 / a (closed form).

    The kernel must pass the law the velocity of the integrator: without it mu stays f_min and
    the block accelerates for ever.
    """
    from bearingfw.analysis import ConnectorResponse, NodalResponse, TransientSettings, solve_transient
    from bearingfw.model import Connector, Model, NodalMass, Node, Support

    mass, g, a = 1.0e5, 9.81, 20.0
    params = {"k": 2e8, "f_min": 0.03, "f_max": 0.09, "a": a}
    model = Model(
        [Node("g", 0, 0, 0), Node("m", 0, 0, 0)],
        connectors=[Connector("ptfe", "g", "m", "axial", law="ptfe-friction", law_params=params,
                              vertical_stiffness=1e10)],  # fmt: skip
        supports=[Support("g")],
        masses=[NodalMass("m", mass)],
    )
    dt, steps = 0.005, 600
    ag = np.zeros((steps, 3))
    ag[1:, 0] = 0.06 * g
    recorders = [NodalResponse(["m"], "velocity", name="v"), ConnectorResponse(["ptfe"], name="c")]
    result = solve_transient(model, ag, dt, settings=TransientSettings(alpha=0.0), recorders=recorders)
    velocity = result.data["v"][:, 0, 0]
    force = result.data["c.force"][:, 0, 0]
    normal = result.data["c.normal_force"][:, 0]
    terminal = math.log(2.0) / a
    late = slice(steps // 2, None)
    np.testing.assert_allclose(normal[late], mass * g, rtol=1e-6)
    np.testing.assert_allclose(-velocity[late], terminal, rtol=5e-3)  # the block lags behind the ground
    np.testing.assert_allclose(-force[late], 0.06 * mass * g, rtol=5e-3)
