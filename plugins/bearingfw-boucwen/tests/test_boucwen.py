"""The Bouc-Wen law: tangent, purity, bound, symmetry, dissipation, saturation, convergence, 2-D."""

import copy

import attrs
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import bearingfw
from bearingfw import ParameterError, create_law
from bearingfw.testing import check_law
from bearingfw_boucwen import BoucWen

# Each example drives the law through many substeps: no deadline, few but varied examples.
examples = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def laws(draw, dims=1, max_n=3.0, n=None):
    """A BoucWen law across the admissible parameters (gamma >= -0.6 beta keeps z_max moderate).

    ``n = 2`` (integrated in closed form) about half the time, else any exponent up to ``max_n``
    (backward-Euler substeps); ``n`` fixes it.
    """
    beta = draw(st.floats(0.1, 1.0))
    return BoucWen(
        k=draw(st.floats(1e6, 1e9)),
        alpha=draw(st.floats(0.0, 0.9)),
        uy=draw(st.floats(1e-4, 1e-2)),
        A=draw(st.floats(0.5, 2.0)),
        beta=beta,
        gamma=beta * draw(st.one_of(st.just(1.0), st.floats(-0.6, 1.0))),
        n=n if n is not None else draw(st.one_of(st.just(2.0), st.floats(1.0, max_n))),
        dims=dims,
    )


def yield_length(law):
    """z_max uy / A: the displacement that would saturate z at the initial slope A / uy."""
    return law.z_max * law.uy / law.A


@st.composite
def paths(draw, law, max_steps=5, max_increment=2.0):
    """Displacements (steps, dims) from rest; each component's increment up to ``max_increment``
    yield lengths, so that paths stay elastic, reach the knee, saturate and reverse."""
    steps = draw(st.integers(1, max_steps))
    count = steps * law.dims
    increments = draw(st.lists(st.floats(-max_increment, max_increment), min_size=count, max_size=count))
    return yield_length(law) * np.cumsum(np.reshape(increments, (steps, law.dims)), axis=0)


def run(law, path, state=None):
    """Force (steps, dims), tangent (steps, dims, dims) and the state after each step of one
    connector driven through ``path`` (steps, dims) from ``state`` (default: rest)."""
    state = law.initial_state(1) if state is None else state
    forces, tangents, states = [], [], []
    for u in path:
        response = law.respond(state, u[None, :], np.array([1e6]), 0.01)
        state = response.state
        forces.append(response.force[0])
        tangents.append(response.tangent[0])
        states.append(state)
    return np.array(forces), np.array(tangents), states


def initial_stiffness(law):
    return law.k * (law.alpha + (1 - law.alpha) * law.A)


# --- registration and parameters ------------------------------------------------------------


def test_registered_through_its_entry_point():
    entry = bearingfw.get_registry().laws["bouc-wen"]
    assert entry.value is BoucWen
    assert entry.origin.distribution == "bearingfw-boucwen"
    law = create_law("bouc-wen", k=4e8, alpha=0.02, uy=2e-4, dims=2)
    assert isinstance(law, BoucWen) and law.dims == 2 and law.rigid is False and law.symmetric is True
    assert (law.A, law.beta, law.gamma, law.n) == (1.0, 0.5, 0.5, 1.0)


@pytest.mark.parametrize(
    "params, message",
    [
        ({"k": 0.0}, r"'k' = 0.0 is outside the allowed range k > 0"),
        ({"alpha": 1.0}, r"'alpha' = 1.0 is outside the allowed range 0 <= alpha < 1"),
        ({"uy": -1e-3}, r"'uy' = -0.001 is outside the allowed range uy > 0"),
        ({"A": 0.0}, r"'A' = 0.0 is outside the allowed range A > 0"),
        ({"n": 0.5}, r"'n' = 0.5 is outside the allowed range n >= 1"),
        ({"beta": 0.0, "gamma": 0.0}, r"'beta' = 0.0 is outside the allowed range beta > 0"),
        ({"gamma": float("nan")}, r"'gamma' = nan is outside the allowed range gamma finite"),
        ({"beta": 0.2, "gamma": 0.5}, r"'beta' = 0.2 and 'gamma' = 0.5 must satisfy beta >= \|gamma\|"),
        ({"beta": 0.5, "gamma": -0.7}, r"'gamma' = -0.7 must satisfy beta \+ gamma > 0 .* and beta >= \|gamma\|"),
        ({"beta": 0.5, "gamma": -0.5}, r"'gamma' = -0.5 must satisfy beta \+ gamma > 0 \(else z [^)]*\); allowed"),
        ({"dims": 3}, r"'dims' must be 1 or 2"),
        ({"k": "stiff"}, r"'k' must be a real number"),
    ],
)
def test_parameter_errors_name_the_parameter_and_the_condition(params, message):
    with pytest.raises(ParameterError, match=message):
        create_law("bouc-wen", **{"k": 4e8, "alpha": 0.02, "uy": 2e-4, **params})


def test_a_missing_parameter_is_named():
    with pytest.raises(ParameterError, match=r"missing parameter\(s\) 'uy' \(uy > 0\)"):
        create_law("bouc-wen", k=4e8, alpha=0.02)


# --- the response ---------------------------------------------------------------------------


@pytest.mark.parametrize("dims", [1, 2])
def test_zero_displacement_from_rest_gives_zero_force_and_the_initial_stiffness(dims):
    law = BoucWen(k=4e8, alpha=0.1, uy=1e-3, A=1.5, beta=0.4, gamma=0.1, n=2.0, dims=dims)
    response = law.respond(law.initial_state(4), np.zeros((4, dims)), np.full(4, 1e6), 0.01)
    np.testing.assert_array_equal(response.force, np.zeros((4, dims)))
    expected = np.broadcast_to(initial_stiffness(law) * np.eye(dims), (4, dims, dims))
    np.testing.assert_allclose(response.tangent, expected, rtol=1e-14)


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_tangent_is_the_derivative_of_the_force(dims, data):
    """Against central differences, or one-sided ones at a kink (u at the committed point, a jump
    of the substep count), all Richardson-extrapolated: second order on each smooth piece."""
    law = data.draw(laws(dims))
    path = data.draw(paths(law, max_steps=3))
    state = run(law, path[:-1])[2][-1] if len(path) > 1 else law.initial_state(1)
    u = path[-1][None, :]
    tangent = law.respond(state, u, np.ones(1), 0.01).tangent[0]
    eps = 1e-6 * law.uy

    def force(offset):
        return law.respond(state, u + offset, np.ones(1), 0.01).force[0]

    f0 = force(0.0)
    for j in range(dims):
        step = np.eye(dims)[j] * eps
        plus, half_plus, minus, half_minus = force(step), force(step / 2), force(-step), force(-step / 2)
        central = (plus - minus) / (2 * eps)
        forward = 4 * (half_plus - f0) / eps - (plus - f0) / eps
        backward = 4 * (f0 - half_minus) / eps - (f0 - minus) / eps
        errors = [np.abs(fd - tangent[:, j]).max() for fd in (central, forward, backward)]
        scale = max(initial_stiffness(law), np.abs(tangent).max())
        assert min(errors) <= 1e-5 * scale, f"column {j}: tangent {tangent[:, j]}, central differences {central}"


@pytest.mark.parametrize("n", [1.5, 2.0])
@pytest.mark.parametrize("dims", [1, 2])
def test_at_the_committed_point_the_tangent_is_the_unloading_one(dims, n):
    """beta = gamma: unloading is elastic (slope A/uy in z), so the tangent there is the initial one."""
    law = BoucWen(k=4e8, alpha=0.05, uy=1e-3, n=n, dims=dims)
    path = law.uy * np.array([[3.0, -3.0], [2.6, -2.6]])[:, :dims]
    _, _, states = run(law, path)
    assert np.all(np.abs(states[-1]["z"]) > 0.1)  # loaded: the kink is real
    tangent = law.respond(states[-1], path[-1][None, :], np.ones(1), 0.01).tangent[0]
    np.testing.assert_allclose(tangent, initial_stiffness(law) * np.eye(dims), rtol=1e-12)


@pytest.mark.parametrize("dims", [1, 2])
def test_the_force_is_continuous_where_the_substep_count_changes(dims):
    """At |du| = m h one side takes m full substeps and a tiny remainder, the other m - 1 and a
    nearly full one: the forces must agree (equal substeps would jump by the change in error,
    about 1e-3 k uy here)."""
    law = BoucWen(k=1e6, alpha=0.0, uy=1e-3, dims=dims)
    direction = np.array([0.6, 0.8])[:dims] / np.linalg.norm(np.array([0.6, 0.8])[:dims])
    for m in (1, 3, 7):
        below, above = (
            law.respond(law.initial_state(1), (m * law.substep * f * direction)[None, :], np.ones(1), 0.01).force[0]
            for f in (1 - 1e-12, 1 + 1e-12)
        )
        assert np.abs(above - below).max() <= 1e-9 * law.k * law.uy


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_respond_is_pure(dims, data):
    law = data.draw(laws(dims))
    path = data.draw(paths(law))
    state = law.initial_state(1)
    for u in path:
        before = copy.deepcopy(state)
        trial = u[None, :].copy()
        response = law.respond(state, trial, np.ones(1), 0.01)
        for key in before:
            np.testing.assert_array_equal(state[key], before[key])
        # The new state shares no array with the old state or the caller's displacement.
        assert all(response.state[key] is not state[key] for key in state)
        kept = copy.deepcopy(response.state)
        trial += 1.0
        for key in kept:
            np.testing.assert_array_equal(response.state[key], kept[key])
        again = law.respond(state, u[None, :], np.ones(1), 0.01)
        np.testing.assert_array_equal(again.force, response.force)
        state = response.state


def test_normal_force_and_time_step_play_no_part():
    law = BoucWen(k=4e8, alpha=0.05, uy=1e-3, n=2.0, dims=2)
    state = law.respond(law.initial_state(3), np.full((3, 2), 2e-3), np.full(3, 1e6), 0.01).state
    u = np.array([[1e-3, -4e-3], [0.0, 5e-4], [3e-3, 3e-3]])
    reference = law.respond(state, u, np.full(3, 1e6), 0.01)
    for normal, dt in [(np.zeros(3), 0.01), (np.array([-1e5, 4e6, 0.0]), 0.01), (np.full(3, 1e6), 1e-5)]:
        other = law.respond(state, u, normal, dt)
        np.testing.assert_array_equal(other.force, reference.force)
        np.testing.assert_array_equal(other.tangent, reference.tangent)


# --- bound, symmetry, dissipation -----------------------------------------------------------


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_z_and_the_hysteretic_force_stay_within_the_bound(dims, data):
    """Large increments, hundreds of substeps (1-D: up to 12 yield lengths a step and n up to 6;
    2-D, dearer per substep: 4 and 3)."""
    law = data.draw(laws(dims, max_n=6.0 if dims == 1 else 3.0))
    path = data.draw(paths(law, max_steps=4, max_increment=12.0 if dims == 1 else 4.0))
    forces, _, states = run(law, path)
    z = np.array([s["z"][0] for s in states])
    assert np.all(np.linalg.norm(z, axis=1) <= law.z_max * (1 + 1e-12))
    hysteretic = np.linalg.norm(forces - law.alpha * law.k * path, axis=1)
    bound = (1 - law.alpha) * law.k * law.uy * law.z_max
    # alpha k u is subtracted back out of F: allow for its round-off.
    assert np.all(hysteretic <= bound * (1 + 1e-12) + 1e-14 * law.k * np.abs(path).max())


@pytest.mark.parametrize("n", [2.0, 2.5])
@pytest.mark.parametrize("dims", [1, 2])
def test_an_increment_beyond_max_substeps_stays_bounded_with_a_consistent_tangent(dims, n):
    """A wild trial displacement (3000 substep lengths): cut into MAX_SUBSTEPS equal substeps
    (n = 2.5), or integrated in closed form (n = 2), where nothing overflows."""
    law = BoucWen(k=4e8, alpha=0.05, uy=1e-3, n=n, beta=0.6, gamma=-0.2, dims=dims)
    direction = np.array([-0.8, 0.6])[:dims] / np.linalg.norm(np.array([-0.8, 0.6])[:dims])
    state = run(law, np.array([[4.0, 3.0]])[:, :dims] * law.uy)[2][-1]
    u = state["u"] + 3000 * law.substep * direction
    response = law.respond(state, u, np.ones(1), 0.01)
    assert np.linalg.norm(response.state["z"]) <= law.z_max * (1 + 1e-12)
    eps = 1e-6 * law.uy
    for j in range(dims):
        step = np.eye(dims)[j] * eps
        plus, minus = (law.respond(state, u + sign * step, np.ones(1), 0.01).force[0] for sign in (1, -1))
        np.testing.assert_allclose((plus - minus) / (2 * eps), response.tangent[0][:, j], rtol=1e-6, atol=1e-6 * law.k)


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_odd_symmetry(dims, data):
    law = data.draw(laws(dims))
    path = data.draw(paths(law))
    forward, forward_tangent, _ = run(law, path)
    mirrored, mirrored_tangent, _ = run(law, -path)
    np.testing.assert_allclose(mirrored, -forward, rtol=1e-12, atol=1e-12 * law.k * law.uy)
    np.testing.assert_allclose(mirrored_tangent, forward_tangent, rtol=1e-12, atol=1e-12 * law.k)


def stored_energy(law, z):
    """psi = (1 - alpha) k uy^2 |z|^2 / (2 A): the hysteretic spring's energy (its stiffness is (1 - alpha) k A)."""
    return (1 - law.alpha) * law.k * law.uy**2 * float(np.sum(z * z)) / (2 * law.A)


def hysteretic_work(law, u, forces):
    """Work of F - alpha k u along u (steps, dims), each step's end force times its increment: the
    rule under which backward Euler dissipates (forces[0] is not used)."""
    hysteretic = forces[1:] - law.alpha * law.k * u[1:]
    return float(np.einsum("ij,ij->", hysteretic, np.diff(u, axis=0)))


def dissipative_increment(law):
    """Increments for which the discrete dissipation is proven: any in 1-D (z moves monotonically
    along an increment); in 2-D at most one substep (backward Euler dissipates per substep)."""
    return 3.0 if law.dims == 1 else 0.99 * law.substep / yield_length(law) / np.sqrt(2)


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_dissipation_inequality_work_exceeds_the_change_of_stored_energy(dims, data):
    """From any committed state: W_hysteretic >= psi(z_end) - psi(z_start)."""
    law = data.draw(laws(dims))
    history = data.draw(paths(law, max_steps=3))
    start = run(law, history)[2][-1]
    onward = history[-1] + data.draw(paths(law, max_steps=8, max_increment=dissipative_increment(law)))
    forces, _, states = run(law, onward, start)
    u = np.concatenate([history[-1:], onward])
    work = hysteretic_work(law, u, np.concatenate([forces[:1], forces]))
    before, after = stored_energy(law, start["z"]), stored_energy(law, states[-1]["z"])
    # Round-off: of the work, and of the energies whose difference is taken.
    tolerance = 1e-10 * law.k * law.uy * np.abs(np.diff(u, axis=0)).sum() + 1e-12 * max(before, after)
    assert work >= after - before - tolerance


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_a_closed_cycle_from_rest_does_not_create_energy(dims, data):
    """Out from rest and back to exactly zero: the work done on the bearing is >= 0 (it is what
    was dissipated plus what z still stores). Elastic part by the trapezoidal rule (exact, zero on
    a closed cycle), hysteretic part by the end-force rule as above."""
    law = data.draw(laws(dims))
    out = data.draw(paths(law, max_steps=8, max_increment=dissipative_increment(law)))
    cycle = np.concatenate([np.zeros((1, dims)), out, out[-2::-1], np.zeros((1, dims))])
    forces, _, _ = run(law, cycle[1:])
    forces = np.concatenate([np.zeros((1, dims)), forces])
    elastic = law.alpha * law.k * float(np.einsum("ij,ij->", (cycle[1:] + cycle[:-1]) / 2, np.diff(cycle, axis=0)))
    work = elastic + hysteretic_work(law, cycle, forces)
    assert work >= -1e-10 * law.k * law.uy * np.abs(np.diff(cycle, axis=0)).sum()


# --- saturation and convergence -------------------------------------------------------------

SHAPES = [
    {},  # the defaults: A = 1, beta = gamma = 0.5, n = 1, so z_max = 1
    {"A": 1.3, "beta": 0.6, "gamma": 0.1, "n": 2.5},
    {"A": 1.0, "beta": 0.8, "gamma": -0.5, "n": 1.3},
]


@pytest.mark.parametrize("shape", SHAPES)
def test_with_alpha_zero_large_cycles_saturate_at_k_uy_z_max(shape):
    law = BoucWen(k=2e8, alpha=0.0, uy=5e-4, **shape)
    saturation = law.k * law.uy * (law.A / (law.beta + law.gamma)) ** (1 / law.n)
    # z approaches z_max within a few yield lengths; 40 of them leave an exp(-40)-small gap.
    amplitude = 40 * yield_length(law)
    legs = [np.linspace(a, b, 6)[1:] for a, b in [(0, amplitude), (amplitude, -amplitude), (-amplitude, amplitude)]]
    forces = run(law, np.concatenate(legs)[:, None])[0][:, 0]
    assert np.abs(forces).max() <= saturation * (1 + 1e-12)
    np.testing.assert_allclose(forces[[4, 9, 14]], [saturation, -saturation, saturation], rtol=1e-9)


def reference_z(law, z0, distance):
    """z along a monotonic increasing path from z0, dz/du of the 1-D law by an accurate Runge-Kutta."""

    def rate(_, z):
        return [(law.A - law.beta * abs(z[0]) ** (law.n - 1) * z[0] - law.gamma * abs(z[0]) ** law.n) / law.uy]

    solution = solve_ivp(
        rate, [0.0, distance], [z0], method="DOP853", rtol=1e-12, atol=1e-14 * law.z_max, dense_output=True
    )
    return lambda s: solution.sol(s)[0]


@pytest.mark.parametrize("shape", SHAPES)
def test_converges_to_the_exact_solution_as_the_step_shrinks(shape):
    """A monotonic path from the opposite saturation: reversal, knee, saturation again.

    Steps of h, h/2, h/4 (h the substep length): backward Euler is first order, so the
    largest error in z halves each time, and at h it is near the designed 0.6 % of z_max. One call
    spanning the whole path is cut into substeps, so it is as accurate as steps of h.
    """
    law = BoucWen(k=1e6, alpha=0.1, uy=1e-3, **shape)
    start = -20 * yield_length(law)
    state = law.respond(law.initial_state(1), np.array([[start]]), np.ones(1), 0.01).state
    distance = 8 * yield_length(law)
    exact = reference_z(law, float(state["z"][0, 0]), distance)
    errors = []
    for refinement in (1, 2, 4):
        s = np.linspace(0.0, distance, int(np.ceil(distance / law.substep * refinement)) + 1)[1:]
        forces = run(law, (start + s)[:, None], state)[0][:, 0]
        z = (forces - law.alpha * law.k * (start + s)) / ((1 - law.alpha) * law.k * law.uy)
        errors.append(np.abs(z - exact(s)).max() / law.z_max)
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 1.7) & (ratios < 2.3)), errors
    assert errors[0] < 0.01, errors
    one_call = law.respond(state, np.array([[start + distance]]), np.ones(1), 0.01).state["z"][0, 0]
    assert abs(one_call - exact(distance)) / law.z_max <= errors[0]


def park_wen_reference(law, z0, du):
    """z at the end of the straight increment ``du`` from ``z0`` (dims,), by an accurate Runge-Kutta."""
    length = float(np.linalg.norm(du))
    e = du / length

    def rate(_, z):
        r = np.linalg.norm(z)
        q = law.beta * np.sum(np.abs(e * z)) + law.gamma * (z @ e)
        return (law.A * e - r ** (law.n - 2.0) * q * z if r > 0 else law.A * e) / law.uy

    solution = solve_ivp(rate, [0.0, length], z0, method="DOP853", rtol=1e-12, atol=1e-14 * law.z_max)
    return solution.y[:, -1]


@pytest.mark.parametrize("dims", [1, 2])
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_n2_is_integrated_exactly(dims, data):
    """n = 2: z at the end of any increment (reversals, sign changes of z's components, up to 30
    yield lengths) is the exact solution of the law's equation, to 1e-9 of z_max."""
    law = data.draw(laws(dims, n=2.0))
    state = run(law, data.draw(paths(law, max_steps=3)))[2][-1]
    du = yield_length(law) * np.array(data.draw(st.lists(st.floats(-30.0, 30.0), min_size=dims, max_size=dims)))
    if np.linalg.norm(du) < 1e-9 * law.uy:  # (the reference's norm underflows for subnormal du)
        return
    z = law.respond(state, state["u"] + du[None, :], np.ones(1), 0.01).state["z"][0]
    expected = park_wen_reference(law, state["z"][0], du)
    assert np.abs(z - expected).max() <= 1e-9 * law.z_max, (state["z"][0], du / law.uy, z, expected)


def test_n2_through_two_sign_changes_is_exact_with_a_consistent_tangent():
    """2-D, both components of z opposite to the motion: two events (each component crosses zero
    once), then saturation. z against the reference, the tangent against central differences
    (the event positions move with u: the map is smooth, its tangent continuous, across them)."""
    law = BoucWen(k=1e6, alpha=0.1, uy=1e-3, A=1.2, beta=0.6, gamma=0.2, n=2.0, dims=2)
    state = run(law, law.uy * np.array([[1.0, 0.5], [2.0, 1.5]]))[2][-1]
    assert np.all(state["z"] > 0.3 * law.z_max)
    du = law.uy * np.array([-2.5, -4.0])
    response = law.respond(state, state["u"] + du[None, :], np.ones(1), 0.01)
    z = response.state["z"][0]
    assert np.all(z < 0)  # both components crossed
    np.testing.assert_allclose(z, park_wen_reference(law, state["z"][0], du), rtol=0, atol=1e-10 * law.z_max)
    eps = 1e-6 * law.uy
    for j in range(2):
        step = np.eye(2)[j] * eps
        plus, minus = (law.respond(state, state["u"] + du + sign * step, np.ones(1), 0.01).force[0] for sign in (1, -1))
        np.testing.assert_allclose((plus - minus) / (2 * eps), response.tangent[0][:, j], rtol=1e-6, atol=1e-7 * law.k)


@pytest.mark.parametrize(
    "z0, du",
    [([0.0, 0.76], [1.0, -1.0]), ([0.0, 0.76], [0.3, -0.3]), ([0.5, -0.5], [-1.0, -1.0]), ([0.0, 0.0], [2.0, 2.0])],
)
def test_n2_tangent_where_the_sign_dependent_term_cancels(z0, du):
    """beta = 1, gamma = 0 and motion at 45 degrees to the axes with z_x = 0 or |z_x| = |z_y|:
    c = A w . e = 0 exactly in a segment (found by hypothesis: the complex step then rests on
    tanhc's series near 0)."""
    law = BoucWen(k=1e6, alpha=0.0, uy=1e-3, A=1.0, beta=1.0, gamma=0.0, n=2.0, dims=2)
    state = {"z": np.array([z0]), "u": np.zeros((1, 2))}
    u = law.uy * np.array([du])
    for m in (1, 2):  # one connector (Python floats) and two (numpy)
        states = {"z": np.repeat(state["z"], m, axis=0), "u": np.zeros((m, 2))}
        tangent = law.respond(states, np.repeat(u, m, axis=0), np.ones(m), 0.01).tangent[0]
        eps = 1e-7 * law.uy
        for j in range(2):
            step = np.eye(2)[j] * eps
            plus, minus = (law.respond(state, u + sign * step, np.ones(1), 0.01).force[0] for sign in (1, -1))
            np.testing.assert_allclose(tangent[:, j], (plus - minus) / (2 * eps), rtol=1e-6, atol=1e-7 * law.k)


@pytest.mark.parametrize("dims", [1, 2])
def test_n2_with_beta_equal_to_gamma_unloads_elastically(dims):
    """beta = gamma and z opposite to the motion in every component: w = 0, so z moves as
    A du / uy exactly (c = 0, the closed form's degenerate case), with the initial stiffness."""
    law = BoucWen(k=4e8, alpha=0.0, uy=2e-4, n=2.0, dims=dims)
    state = run(law, law.uy * np.array([[2.0, 1.5]])[:, :dims])[2][-1]
    du = -0.3 * law.uy * np.array([1.0, 0.7])[:dims]
    response = law.respond(state, state["u"] + du[None, :], np.ones(1), 0.01)
    np.testing.assert_allclose(response.state["z"][0], state["z"][0] + du / law.uy, rtol=1e-14)
    np.testing.assert_allclose(response.tangent[0], law.k * np.eye(dims), rtol=1e-12, atol=1e-12 * law.k)


# --- 2-D against 1-D, vectorisation ---------------------------------------------------------


@examples
@given(data=st.data(), line=st.sampled_from(["x", "y", "oblique"]), angle=st.floats(0.0, 2 * np.pi))
def test_2d_motion_along_a_line_is_the_1d_law(data, line, angle):
    """Along an axis, and along any fixed line through the virgin state, z stays parallel to the
    motion and the Park-Wen form is the 1-D law: the same force along the line, the same
    stiffness e^T K e (the 2-D law is computed by separate, general code)."""
    law_1d = data.draw(laws(1))
    law_2d = attrs.evolve(law_1d, dims=2)
    s = data.draw(paths(law_1d))[:, 0]
    e = {"x": [1.0, 0.0], "y": [0.0, 1.0], "oblique": [np.cos(angle), np.sin(angle)]}[line]
    e = np.array(e)
    f1, k1, _ = run(law_1d, s[:, None])
    f2, k2, _ = run(law_2d, s[:, None] * e)
    scale = law_1d.k * max(law_1d.uy, np.abs(s).max())
    np.testing.assert_allclose(f2, f1 * e, rtol=1e-10, atol=1e-12 * scale)
    # An increment of exactly m substeps sits on a kink of the tangent (the substep count
    # changes there), where the two codes may round |du| to different sides: compare elsewhere.
    substeps = np.abs(np.diff(s, prepend=0.0)) / law_1d.substep
    smooth = np.abs(substeps - np.round(substeps)) > 1e-9 * np.maximum(substeps, 1.0)
    along = np.einsum("i,sij,j->s", e, k2, e)
    np.testing.assert_allclose(along[smooth], k1[smooth, 0, 0], rtol=1e-9, atol=1e-12 * law_1d.k)


@pytest.mark.parametrize("dims", [1, 2])
@examples
@given(data=st.data())
def test_n_connectors_together_equal_each_alone(dims, data):
    law = data.draw(laws(dims))
    n = 3
    columns = [data.draw(paths(law, max_steps=4)) for _ in range(n)]
    steps = min(len(c) for c in columns)
    u = np.stack([c[:steps] for c in columns], axis=1)  # (steps, n, dims)
    state, alone = law.initial_state(n), [law.initial_state(1) for _ in range(n)]
    for x in u:
        together = law.respond(state, x, np.full(n, 1e6), 0.01)
        for i in range(n):
            single = law.respond(alone[i], x[i : i + 1], np.full(1, 1e6), 0.01)
            np.testing.assert_allclose(together.force[i], single.force[0], rtol=1e-11, atol=1e-12 * law.k * law.uy)
            np.testing.assert_allclose(together.tangent[i], single.tangent[0], rtol=1e-9, atol=1e-10 * law.k)
            alone[i] = single.state
        state = together.state


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize("shape", [{"beta": 0.5, "gamma": 0.5}, {"A": 1.3, "beta": 0.7, "gamma": -0.4}])
def test_n2_one_connector_alone_is_the_vectorised_law(dims, shape):
    """n = 2 answers one connector in Python floats and several with numpy: the same closed form.
    400 random states across the ball and increments from 0.001 to 30 yield lengths (reversals,
    sign changes of z's components, zero components, increments below STILL uy)."""
    law = BoucWen(k=4e8, alpha=0.02, uy=2e-4, n=2.0, dims=dims, **shape)
    rng = np.random.default_rng(2024 + dims)
    m = 400
    z = rng.normal(size=(m, dims))
    z *= law.z_max * rng.uniform(0.0, 1.0, (m, 1)) / np.linalg.norm(z, axis=1, keepdims=True)
    z[:40, 0] = 0.0
    du = rng.normal(size=(m, dims)) * law.uy * 10.0 ** rng.uniform(-3.0, 1.5, (m, 1))
    du[40:80, -1] = 0.0
    du[80:90] = 0.0
    du[90:100] *= 1e-210  # below STILL uy
    state = {"z": z, "u": rng.normal(size=(m, dims)) * law.uy}
    together = law.respond(state, state["u"] + du, np.ones(m), 0.01)
    for i in range(m):
        alone = law.respond({"z": z[i : i + 1], "u": state["u"][i : i + 1]}, state["u"][i : i + 1] + du[i : i + 1],
                            np.ones(1), 0.01)  # fmt: skip
        np.testing.assert_allclose(alone.force[0], together.force[i], rtol=1e-12, atol=1e-12 * law.k * law.uy)
        np.testing.assert_allclose(alone.tangent[0], together.tangent[i], rtol=1e-9, atol=1e-10 * law.k)
        np.testing.assert_allclose(alone.state["z"][0], together.state["z"][i], rtol=0, atol=1e-13 * law.z_max)


# --- bearingfw's conformance suite ----------------------------------------------------------


SHAPES = {"n=1": {}, "n=2": {"n": 2.0}, "n=2 gamma<0": {"n": 2.0, "alpha": 0.0, "beta": 0.7, "gamma": -0.3}}


# 2-D with n = 1 substeps the biaxial law (about 16 s): it runs with -m slow; the default run has n = 1 in 1-D
# and the 2-D closed form
@pytest.mark.parametrize(("dims", "shape"), [
    pytest.param(dims, shape, id=f"{dims}-{name}", marks=[pytest.mark.slow] if (dims, name) == (2, "n=1") else [])
    for dims in (1, 2) for name, shape in SHAPES.items()
])
def test_passes_the_bearingfw_conformance_suite(dims, shape):
    """The defaults (beta = gamma; n = 1: substeps, n = 2: closed form) at the paper's bearing scale.
    The suite draws steps of up to 20 times displacement_scale, so uy / 4 still takes the paths far
    past yield (and keeps it short)."""
    law = BoucWen(**{"k": 4e8, "alpha": 0.05, "uy": 1e-3, **shape, "dims": dims})
    check_law(law, displacement_scale=law.uy / 4, max_examples=10, max_steps=12)


def test_slip_is_zero_in_the_elastic_range_and_grows_after_yield():
    law = BoucWen(k=1e6, alpha=0.0, uy=1e-3, n=8.0)  # a sharp knee: nearly elastic-plastic
    small = law.respond(law.initial_state(1), np.array([[1e-6]]), np.ones(1), 0.01).state
    assert abs(law.slip(small)[0, 0]) < 1e-3 * 1e-6
    large = law.respond(law.initial_state(1), np.array([[5e-3]]), np.ones(1), 0.01).state
    # Saturated (z = 1): the elastic part is uy, the rest is plastic.
    assert law.slip(large)[0, 0] == pytest.approx(5e-3 - 1e-3, rel=1e-3)


# --- regressions: the random draws of issue 14 that the conformance kit failed ------------------


def test_issue14_draw_n11_2d_a_connector_in_a_batch_equals_it_alone_bit_for_bit():
    """n = 11, uy = 0.21 mm, alpha = 0.34, A = 0.197, 2-D failed "vectorised": the batch's Newton
    iterations went on for connectors that had converged, so their round-off depended on the
    others. Each connector now keeps the iterate at which it converged: the same bits alone."""
    from bearingfw.testing.conformance import check_vectorised, make_context

    law = BoucWen(k=4e8, alpha=0.34, uy=0.21e-3, A=0.197, n=11.0, dims=2)
    rng = np.random.default_rng(14)
    m = 3
    state, alone = law.initial_state(m), [law.initial_state(1) for _ in range(m)]
    for step in range(6):
        # Increments from a hundredth of uy to 30 uy (the largest cut into MAX_SUBSTEPS substeps).
        u = state["u"] + rng.normal(size=(m, 2)) * law.uy * 10.0 ** rng.uniform(-2.0, 1.5, (m, 1))
        together = law.respond(state, u, np.full(m, 1e6), 0.01)
        for i in range(m):
            single = law.respond(alone[i], u[i : i + 1], np.full(1, 1e6), 0.01)
            np.testing.assert_array_equal(single.force[0], together.force[i])
            np.testing.assert_array_equal(single.tangent[0], together.tangent[i])
            alone[i] = single.state
        state = together.state
    check_vectorised(make_context(law, max_examples=3, max_steps=5, shrink=False))


def test_issue14_draw_n61_1d_tangent_at_a_repeated_point_passes_the_kit():
    """k = 2.44e8, alpha = 0.68, uy = 0.144 mm, A = 6.6, beta = 0.5, gamma = 0.145, n = 6.1 failed
    "tangent": at a trial equal to the committed point (u = 20 mm after saturating there) the law
    returns the unloading side's tangent, 965 MN/m, and the old kit's one-sided difference with
    h = 1e-6 |u| = 20 nm erred by 1.6e-5 on that strongly curved side (the loading side is
    alpha k = 166 MN/m; their mean, 565 MN/m, was the central difference it printed). The law was
    right; the kit now tries smaller steps before it judges (bearingfw.testing, "Kinks")."""
    from bearingfw.testing.conformance import _derivative_check, check_tangent, make_context

    law = BoucWen(k=2.44e8, alpha=0.68, uy=0.144e-3, A=6.6, beta=0.5, gamma=0.145, n=6.1, dims=1)
    normal = np.array([1e5])
    for u_end in (0.0178, 0.02):
        state = law.respond(law.initial_state(1), np.array([[u_end]]), normal, 0.01).state
        u = np.array([[u_end]])
        tangent = law.respond(state, u, normal, 0.01).tangent[0]
        unloading = (law.A + (law.beta - law.gamma) * law.z_max**law.n) / law.uy  # dz/du leaving saturation
        expected = law.k * (law.alpha + (1 - law.alpha) * law.uy * unloading)
        assert tangent[0, 0] == pytest.approx(expected, rel=1e-6)  # about 965 MN/m

        def force(x):
            return law.respond(state, x.reshape(1, 1), normal, 0.01).force[0]

        assert _derivative_check(force, u[0], tangent, 1e-3, law.k) is None
        backward = (force(u[0]) - force(u[0] - 1e-10)) / 1e-10
        assert backward[0] == pytest.approx(tangent[0, 0], rel=1e-4)
    check_tangent(make_context(law, max_examples=10, max_steps=10, shrink=False))


# --- per-bearing parameters -------------------------------------------------------------------


def test_declares_per_bearing_and_not_isotropic():
    assert BoucWen.per_bearing is True and BoucWen.isotropic is False
    assert all(attrs.fields_dict(BoucWen)[name].metadata["per_bearing"] for name in ("k", "alpha", "uy", "A", "beta", "gamma", "n"))


def test_the_park_wen_form_is_not_rotation_invariant():
    """Why isotropic = False: the same path turned by 30 degrees does not give the turned force."""
    law = BoucWen(k=1e6, alpha=0.0, uy=1e-3, n=2.0, dims=2)
    path = law.uy * np.array([[2.0, 0.0], [2.0, 2.0], [0.0, 2.5]])
    turn = np.array([[np.cos(0.5236), -np.sin(0.5236)], [np.sin(0.5236), np.cos(0.5236)]])
    forces, _, _ = run(law, path)
    turned, _, _ = run(law, path @ turn.T)
    assert np.abs(turned - forces @ turn.T).max() > 1e-3 * law.k * law.uy


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize("exponents", [(2.0, 2.0, 2.0), (2.0, 1.5, 3.0)], ids=["n=2", "mixed n"])
def test_per_bearing_arrays_equal_separate_laws(dims, exponents):
    """One law with a value per connector (uy as the reference bridge's preset gives it, and every
    other parameter too) answers each connector as a law with that connector's values alone."""
    values = {
        "k": [4e8, 2e8, 6e8], "alpha": [0.05, 0.0, 0.2], "uy": [2e-4, 1e-3, 5e-4], "A": [1.0, 1.3, 0.8],
        "beta": [0.5, 0.7, 0.4], "gamma": [0.5, -0.3, 0.1], "n": list(exponents),
    }  # fmt: skip
    together = BoucWen(**{name: np.array(v) for name, v in values.items()}, dims=dims)
    singles = [BoucWen(**{name: v[i] for name, v in values.items()}, dims=dims) for i in range(3)]
    rng = np.random.default_rng(7 + dims)
    state, alone = together.initial_state(3), [law.initial_state(1) for law in singles]
    for _ in range(8):
        u = state["u"] + rng.normal(size=(3, dims)) * 1e-3 * 10.0 ** rng.uniform(-2.0, 1.0, (3, 1))
        response = together.respond(state, u, np.full(3, 1e6), 0.01)
        for i, law in enumerate(singles):
            single = law.respond(alone[i], u[i : i + 1], np.full(1, 1e6), 0.01)
            np.testing.assert_allclose(response.force[i], single.force[0], rtol=1e-12, atol=1e-12 * law.k * law.uy)
            np.testing.assert_allclose(response.tangent[i], single.tangent[0], rtol=1e-9, atol=1e-10 * law.k)
            alone[i] = single.state
        state = response.state
    np.testing.assert_allclose(together.slip(state), np.concatenate([law.slip(s) for law, s in zip(singles, alone)]), rtol=1e-12)


def test_a_one_connector_array_is_the_scalar_law_bit_for_bit():
    scalar = BoucWen(k=4e8, alpha=0.05, uy=2e-4, n=2.0, dims=2)
    array = BoucWen(k=4e8, alpha=0.05, uy=np.array([2e-4]), n=2.0, dims=2)
    path = 1e-3 * np.array([[0.3, 0.1], [0.5, -0.4], [-0.2, 0.0]])
    for a, b in zip(run(scalar, path), run(array, path)):
        if isinstance(a, np.ndarray):
            np.testing.assert_array_equal(a, b)


def test_per_bearing_errors_name_the_parameter():
    law = BoucWen(k=4e8, alpha=0.05, uy=np.array([2e-4, 1e-3]), dims=1)
    with pytest.raises(ParameterError, match=r"parameter 'uy' holds 2 per-bearing values but the law was called for 3"):
        law.respond(law.initial_state(2) | {"z": np.zeros((3, 1)), "u": np.zeros((3, 1))}, np.zeros((3, 1)), np.ones(3), 0.01)
    with pytest.raises(ParameterError, match=r"'uy' holds 2 per-bearing values"):
        law.initial_state(3)
    with pytest.raises(ParameterError, match=r"one value per connector, all of the same length; got 'k' \(3\), 'uy' \(2\)"):
        BoucWen(k=np.array([4e8, 4e8, 1e8]), alpha=0.05, uy=np.array([2e-4, 1e-3]))
    with pytest.raises(ParameterError, match=r"'beta'\[1\] = 0.2 and 'gamma'\[1\] = 0.5 must satisfy beta >= \|gamma\|"):
        BoucWen(k=4e8, alpha=0.05, uy=1e-3, beta=np.array([0.5, 0.2]), gamma=0.5)
    with pytest.raises(ParameterError, match=r"'n'\[1\] = 0.5 is outside the allowed range n >= 1"):
        BoucWen(k=4e8, alpha=0.05, uy=1e-3, n=[2.0, 0.5])


@pytest.mark.parametrize("dims", [1, 2])
def test_per_bearing_laws_pass_the_kit(dims):
    """The kit's per-bearing property draws values around these per connector (n = 2 and not)."""
    from bearingfw.testing.conformance import check_per_bearing, make_context

    law = BoucWen(k=4e8, alpha=0.05, uy=1e-3, n=2.0, dims=dims)
    check_per_bearing(make_context(law, displacement_scale=law.uy / 4, max_examples=10, max_steps=8, shrink=False))


# --- the prepared parameters (issue 16: the per-call work done once per law and count) ----------


def _random_calls(law, m, rng, count=12):
    """``count`` trial calls ``(state, u)`` of ``m`` connectors: committed states from a random
    history, increments from 1e-3 to 30 uy, some components exactly still, reversals."""
    uy = np.max(law.uy)
    state, u, calls = law.initial_state(m), np.zeros((m, law.dims)), []
    for _ in range(count):
        u = u + rng.normal(size=(m, law.dims)) * uy * rng.uniform(0.3, 3.0, (m, 1))
        state = law.respond(state, u, np.ones(m), 0.01).state
        du = rng.normal(size=(m, law.dims)) * uy * 10.0 ** rng.uniform(-3.0, 1.5, (m, 1))
        du[0, -1] = 0.0  # a component that does not move (the reference bridge has such bearings)
        calls.append((state, u + du))
    return calls


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize(
    "shape",
    [{"beta": 0.5, "gamma": 0.5}, {"beta": 0.7, "gamma": 0.3}, {"A": 1.3, "beta": 0.6, "gamma": -0.2, "alpha": 0.1}],
    ids=["beta=gamma (the preset)", "beta>gamma", "A, gamma<0, alpha"],
)
def test_n2_per_bearing_uy_is_each_connectors_scalar_law_bit_for_bit(dims, shape):
    """The reference bridge's preset gives each bearing its own uy (all else shared). The
    per-bearing law evaluates its prepared columns with the operations of the scalar law: each
    connector's answer is, to the bit, that of a scalar law with its uy called for several
    connectors (the vectorised closed form; one connector alone takes the Python-float one)."""
    uy = np.array([6.2e-5, 2.2e-4, 1.5e-4, 9.2e-5, 2.1e-4])
    params = {"k": 4e8, "alpha": 0.0, "n": 2.0, **shape}
    law = BoucWen(uy=uy, dims=dims, **params)
    for state, u in _random_calls(law, len(uy), np.random.default_rng(16 + dims)):
        together = law.respond(state, u, np.ones(len(uy)), 0.01)
        for i, uy_i in enumerate(uy):
            scalar = BoucWen(uy=float(uy_i), dims=dims, **params)
            rows = [i, i]  # two copies: the vectorised path
            alone = scalar.respond({key: value[rows] for key, value in state.items()}, u[rows], np.ones(2), 0.01)
            np.testing.assert_array_equal(together.force[i], alone.force[0])
            np.testing.assert_array_equal(together.tangent[i], alone.tangent[0])
            np.testing.assert_array_equal(together.state["z"][i], alone.state["z"][0])


def test_a_call_with_another_connector_count_is_prepared_anew_and_checked():
    """The prepared parameters are per connector count: a scalar law answers 1, 3 and again 1
    connectors alike (the one-connector path stays the Python-float one), and a per-bearing law
    that answered its own count still refuses another."""
    law = BoucWen(k=4e8, alpha=0.05, uy=2e-4, n=2.0, dims=2)
    state = {"z": np.array([[0.3, -0.2]]), "u": np.zeros((1, 2))}
    u = np.array([[1e-4, 5e-5]])
    first = law.respond(state, u, np.ones(1), 0.01)
    tripled = {key: np.repeat(value, 3, axis=0) for key, value in state.items()}
    three = law.respond(tripled, np.repeat(u, 3, axis=0), np.ones(3), 0.01)
    again = law.respond(state, u, np.ones(1), 0.01)
    np.testing.assert_array_equal(first.force, again.force)
    np.testing.assert_array_equal(first.tangent, again.tangent)
    np.testing.assert_allclose(three.force, np.repeat(first.force, 3, axis=0), rtol=1e-13)
    array = BoucWen(k=4e8, alpha=0.05, uy=np.array([2e-4, 1e-3]), n=2.0, dims=1)
    array.respond(array.initial_state(2), np.full((2, 1), 1e-4), np.ones(2), 0.01)
    with pytest.raises(ParameterError, match=r"'uy' holds 2 per-bearing values but the law was called for 3"):
        array.respond({"z": np.zeros((3, 1)), "u": np.zeros((3, 1))}, np.zeros((3, 1)), np.ones(3), 0.01)


def test_prepared_parameters_are_forgotten_with_their_law():
    """They are kept beside the law (a frozen attrs object holds only its fields), by its id while
    it lives: a discarded law leaves nothing behind, and a new law at a reused id is prepared anew."""
    import gc

    from bearingfw_boucwen import law as module

    law = BoucWen(k=4e8, alpha=0.05, uy=np.array([2e-4, 1e-3]), n=2.0, dims=1)
    law.respond(law.initial_state(2), np.full((2, 1), 1e-4), np.ones(2), 0.01)
    key = id(law)
    assert key in module._PREPARED
    del law
    gc.collect()
    assert key not in module._PREPARED


@pytest.mark.parametrize("dims", [1, 2])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, 1e151])
@pytest.mark.parametrize("where", [0, 2, 4])
def test_a_non_finite_or_absurd_displacement_anywhere_is_answered_with_nan_for_its_connector(dims, bad, where):
    """Whatever its position among the connectors (NaN compares false, so a min/max scan could
    step over it), the connector gets NaN force, tangent and z; the others their usual answer."""
    law = BoucWen(k=4e8, alpha=0.05, uy=np.array([1e-4, 2e-4, 3e-4, 4e-4, 5e-4]), n=2.0, dims=dims)
    state, u = _random_calls(law, 5, np.random.default_rng(3), count=1)[0]
    sound = law.respond(state, u, np.ones(5), 0.01)
    u = u.copy()
    u[where, -1] = bad
    response = law.respond(state, u, np.ones(5), 0.01)
    others = [i for i in range(5) if i != where]
    assert np.isnan(response.force[where]).all() and np.isnan(response.tangent[where]).all()
    assert np.isnan(response.state["z"][where]).all()
    np.testing.assert_array_equal(response.force[others], sound.force[others])
    np.testing.assert_array_equal(response.tangent[others], sound.tangent[others])
