"""The lead-rubber law: hand-computed loops, the circular surface, the return map, the tangent,
per-bearing parameters, the preset, and the law inside a transient analysis."""

import attrs
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import bearingfw
from bearingfw import ParameterError
from bearingfw.testing import check_law, drive, run_history
from bearingfw_elastomeric import ElastomericPlasticity, lead_rubber_parameters
from bearingfw_elastomeric.plugin import preset_law

examples = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# A lead-rubber bearing of a highway bridge (the validation's set): K_u = 10 MN/m, Q_d = 100 kN,
# K_d = 1 MN/m; u_y = qd / ((1 - alpha) k) = 11.1 mm, F_y = 111.1 kN.
K, QD, ALPHA = 1.0e7, 1.0e5, 0.1
UY = QD / ((1 - ALPHA) * K)


def lrb(dims=1, **params):
    return ElastomericPlasticity(**{"k": K, "qd": QD, "alpha": ALPHA, **params}, dims=dims)


@st.composite
def laws(draw, dims=1):
    return ElastomericPlasticity(
        k=draw(st.floats(1e5, 1e9)), qd=draw(st.floats(1e3, 1e7)), alpha=draw(st.floats(0.0, 0.95)), dims=dims
    )


@st.composite
def paths(draw, law, max_steps=8, n=None):
    """Displacements (steps, dims) or (steps, n, dims) from rest, increments up to 3 yield displacements."""
    steps = draw(st.integers(1, max_steps))
    shape = (steps, law.dims) if n is None else (steps, n, law.dims)
    count = int(np.prod(shape))
    increments = draw(st.lists(st.floats(-3.0, 3.0), min_size=count, max_size=count))
    return float(np.max(law.yield_displacement)) * np.cumsum(np.reshape(increments, shape), axis=0)


def rotation(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


# --- registration, parameters ---------------------------------------------------------------


def test_registered_through_its_entry_point_with_its_preset():
    registry = bearingfw.get_registry()
    entry = registry.laws["elastomeric-plasticity"]
    assert entry.value is ElastomericPlasticity
    assert entry.origin.distribution == "bearingfw-elastomeric"
    preset = registry.preset("lead-rubber")
    assert preset.needs_dead_load
    assert preset.law is preset_law
    law = bearingfw.create_law("elastomeric-plasticity", k=K, qd=QD, alpha=ALPHA, dims=2)
    assert law == lrb(2)


def test_declares_per_bearing_and_nothing_rate_or_contact_related():
    from bearingfw.protocol import law_flag

    law = lrb()
    assert law_flag(law, "per_bearing")
    for flag in ("uses_velocity", "normal_coupling", "friction", "rate_dependent"):
        assert not law_flag(law, flag), flag


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"k": 0.0}, "'k' = 0.0 is outside the allowed range k > 0"),
        ({"qd": 0.0}, "'qd' = 0.0 is outside the allowed range qd > 0"),
        ({"qd": -5.0}, "'qd' = -5.0 is outside the allowed range qd > 0"),
        ({"alpha": 1.0}, "'alpha' = 1.0 is outside the allowed range 0 <= alpha < 1"),
        ({"alpha": -0.1}, "'alpha' = -0.1 is outside the allowed range 0 <= alpha < 1"),
        ({"k": float("nan")}, "'k' = nan is outside the allowed range k > 0"),
        ({"qd": "100 kN"}, "'qd' must be a real number or a 1-D array"),
        ({"alpha": [0.1, 1.2]}, "'alpha'[1] = 1.2 is outside the allowed range 0 <= alpha < 1"),
        ({"dims": 3}, "'dims' must be 1 or 2"),
    ],
)
def test_bad_parameters_are_named_with_their_range(params, message):
    with pytest.raises(ParameterError, match="elastomeric-plasticity") as error:
        lrb(**params) if "dims" not in params else ElastomericPlasticity(k=K, qd=QD, alpha=ALPHA, dims=params["dims"])
    assert message in str(error.value)


def test_a_per_bearing_array_of_the_wrong_length_is_named():
    law = lrb(k=[1e7, 2e7, 3e7])
    with pytest.raises(ParameterError, match="'k' holds 3 per-bearing values but the law was called for 2"):
        law.initial_state(2)
    with pytest.raises(ParameterError, match="'k' holds 3 per-bearing values"):
        law.respond(law.initial_state(3), np.zeros((2, 1)), np.ones(2), 0.01)


# --- 1-D: the bilinear loop by hand -----------------------------------------------------------


def test_monotonic_loading_is_bilinear_with_the_hand_computed_values():
    law = lrb()
    u = np.array([0.5 * UY, UY, 0.02, 0.05])
    force = drive(law, u)
    # elastic k u up to u_y (F_y = 111.1 kN), then qd + alpha k u
    np.testing.assert_allclose(force, [0.5 * K * UY, QD / (1 - ALPHA), QD + 0.1 * K * 0.02, 150e3], rtol=1e-13)
    assert law.yield_force == pytest.approx(QD / 0.9) and law.yield_displacement == pytest.approx(UY)
    assert law.post_yield_stiffness == pytest.approx(1e6)


def test_unloading_is_elastic_over_twice_the_yield_force_then_yields_in_reverse():
    law = lrb()
    # to 50 mm (150 kN), back to 30 mm: the lead core unloads from +qd to -80 kN, F = 150 - 200 kN
    # = -50 kN; back to 0: reverse yield, F = -qd; and the hand values of the tangents.
    forces, tangents, state = run_history(law, [0.05, 0.03, 0.0])
    np.testing.assert_allclose(forces[:, 0, 0], [150e3, -50e3, -100e3], rtol=1e-13)
    np.testing.assert_allclose(tangents[:, 0, 0, 0], [1e6, 1e7, 1e6], rtol=1e-13)
    # reverse yield starts at F_max - 2 F_y: 2 u_y below the turning point
    turn = drive(law, [0.05, 0.05 - 2 * UY + 1e-9, 0.05 - 2 * UY - 1e-4])
    assert turn[1] == pytest.approx(150e3 - 2 * QD / (1 - ALPHA), rel=1e-6)
    assert turn[2] == pytest.approx(150e3 - 2 * QD / (1 - ALPHA) - 1e6 * 1e-4, rel=1e-9)
    # after reverse yield at u = 0 (q = -qd) the lead core's plastic displacement is u_y, and the
    # bearing comes to rest at zero force at (1 - alpha) u_y = qd / k = 10 mm
    assert state["plastic"][0, 0] == pytest.approx(UY, rel=1e-13)
    assert law.slip(state)[0, 0] == pytest.approx(QD / K, rel=1e-13)
    np.testing.assert_allclose(law.slip(state), (1 - ALPHA) * state["plastic"])


def test_slip_is_where_the_force_vanishes_on_elastic_unloading():
    law = lrb(dims=2)
    forces, _, state = run_history(law, np.array([[0.04, 0.01], [0.01, 0.05]]))
    slip = law.slip(state)
    at_rest = law.respond(state, slip, np.ones(1), 0.01)
    np.testing.assert_allclose(at_rest.force, 0.0, atol=1e-9 * QD)
    np.testing.assert_allclose(at_rest.state["plastic"], state["plastic"])  # reached elastically
    assert np.all(law.slip(law.initial_state(3)) == 0.0)


@pytest.mark.parametrize("amplitude", [2.0, 5.0, 20.0])
def test_energy_of_a_full_cycle_is_4_qd_times_amplitude_minus_yield(amplitude):
    """The textbook loop area of a lead-rubber bearing, EDC = 4 Q_d (D - D_y)."""
    law = lrb()
    d = amplitude * UY
    t = np.linspace(0.0, 1.0, 4001)
    # start on the loop: one cycle to settle, the second measured
    u = d * np.sin(2 * np.pi * 2 * t)
    force = drive(law, u)
    half = len(t) // 2
    work = np.sum(0.5 * (force[half + 1 :] + force[half:-1]) * np.diff(u[half:]))
    assert work == pytest.approx(4 * QD * (d - UY), rel=2e-3)


def test_an_increment_gives_the_same_state_in_one_step_or_many_in_1d():
    """Backward Euler is exact in 1-D: the return does not depend on how the increment is cut."""
    law = lrb()
    rng = np.random.default_rng(3)
    knots = np.concatenate([[0.0], rng.uniform(-6, 6, 6) * UY])
    fine = np.concatenate([np.linspace(a, b, 37)[1:] for a, b in zip(knots[:-1], knots[1:])])
    np.testing.assert_allclose(drive(law, knots[1:]), drive(law, fine)[35::36], rtol=1e-12, atol=1e-9)


# --- 2-D: circular surface, coupling, isotropy ----------------------------------------------


@examples
@given(st.data())
def test_the_hysteretic_force_stays_in_the_circle_and_sits_on_it_after_yield(data):
    law = data.draw(laws(dims=2))
    path = data.draw(paths(law))
    state = law.initial_state(1)
    for u in path:
        response = law.respond(state, u[None, :], np.ones(1), 0.01)
        q = response.force[0] - law.alpha * law.k * u
        step = response.state["plastic"][0] - state["plastic"][0]
        assert np.linalg.norm(q) <= law.qd * (1 + 1e-12)
        # (a repeated point on the surface may "yield" by round-off: not a plastic step to judge)
        if np.linalg.norm(step) > 1e-9 * law.yield_displacement:
            assert np.linalg.norm(q) == pytest.approx(law.qd, rel=1e-12)
            # associated flow: the plastic increment is parallel to q and points the same way
            assert abs(step[0] * q[1] - step[1] * q[0]) <= 1e-9 * np.linalg.norm(step) * law.qd
            assert step @ q > 0
        state = response.state


def test_yield_is_coupled_a_diagonal_push_yields_at_the_circle_not_per_axis():
    law = lrb(dims=2)
    e = np.array([1.0, 1.0]) / np.sqrt(2)
    pushed = np.array([0.99 * UY * e, 1.01 * UY * e])
    before, after = law.respond(law.initial_state(2), pushed, np.ones(2), 0.01).state["plastic"]
    assert np.all(before == 0) and np.linalg.norm(after) == pytest.approx(0.01 * UY, rel=1e-9)
    # per-axis limits would wait until each component reached u_y (|u| = 1.41 u_y)


@examples
@given(st.data(), st.floats(0.0, 2 * np.pi))
def test_isotropy_the_rotated_path_gives_the_rotated_force(data, angle):
    law = data.draw(laws(dims=2))
    path = data.draw(paths(law))
    R = rotation(angle)
    force = drive(law, path)
    turned = drive(law, path @ R.T)
    np.testing.assert_allclose(turned, force @ R.T, rtol=1e-9, atol=1e-9 * law.qd)


@examples
@given(st.data(), st.floats(0.0, 2 * np.pi))
def test_2d_motion_along_a_line_is_the_1d_law(data, angle):
    one = data.draw(laws(dims=1))
    two = attrs.evolve(one, dims=2)
    s = data.draw(paths(one))[:, 0]
    e = np.array([np.cos(angle), np.sin(angle)])
    np.testing.assert_allclose(drive(two, np.outer(s, e)), np.outer(drive(one, s), e), rtol=1e-10, atol=1e-10 * one.qd)


def test_a_turn_after_yield_follows_the_radial_return_by_hand():
    """Yield along x to 3 u_y, then move u_y along y: the trial force (qd, k0 u_y) = qd (1, 1) is
    returned to qd (1, 1)/sqrt 2; the tangent across the trial direction is k0 qd/|q*| + alpha k."""
    law = lrb(dims=2)
    k0 = (1 - ALPHA) * K
    response = law.respond(law.respond(law.initial_state(1), np.array([[3 * UY, 0.0]]), np.ones(1), 0.01).state,
                           np.array([[3 * UY, UY]]), np.ones(1), 0.01)  # fmt: skip
    q = QD * np.array([1.0, 1.0]) / np.sqrt(2)
    np.testing.assert_allclose(response.force[0], q + ALPHA * K * np.array([3 * UY, UY]), rtol=1e-13)
    n = np.array([1.0, 1.0]) / np.sqrt(2)
    expected = ALPHA * K * np.eye(2) + k0 * (QD / (np.sqrt(2) * QD)) * (np.eye(2) - np.outer(n, n))
    np.testing.assert_allclose(response.tangent[0], expected, rtol=1e-13)


# --- tangent, purity, vectorisation, per-bearing values ---------------------------------------


def _fd_columns(law, state, u, h):
    """Central finite differences of the force, column by column."""
    cols = []
    for j in range(law.dims):
        step = np.zeros_like(u)
        step[0, j] = h
        plus = law.respond(state, u + step, np.ones(1), 0.01).force[0]
        minus = law.respond(state, u - step, np.ones(1), 0.01).force[0]
        cols.append((plus - minus) / (2 * h))
    return np.array(cols).T


@examples
@given(st.data(), st.sampled_from([1, 2]))
def test_tangent_is_the_derivative_of_the_force(data, dims):
    law = data.draw(laws(dims=dims))
    path = data.draw(paths(law))
    _, _, state = run_history(law, path[:-1]) if len(path) > 1 else (None, None, law.initial_state(1))
    u = path[-1][None, :]
    h = 1e-7 * float(law.yield_displacement)
    trial = (1 - law.alpha) * law.k * (u - state["plastic"])
    margin = abs(np.linalg.norm(trial) - law.qd) / ((1 - law.alpha) * law.k)
    if margin < 1e3 * h:
        return  # within the differencing step of the kink: one-sided, checked below
    tangent = law.respond(state, u, np.ones(1), 0.01).tangent[0]
    np.testing.assert_allclose(tangent, _fd_columns(law, state, u, h), rtol=1e-5, atol=1e-6 * law.k)


def test_at_the_committed_point_on_the_surface_the_tangent_is_the_unloading_one():
    law = lrb(dims=2)
    state = law.respond(law.initial_state(1), np.array([[0.05, 0.02]]), np.ones(1), 0.01).state
    again = law.respond(state, np.array([[0.05, 0.02]]), np.ones(1), 0.01)
    np.testing.assert_allclose(again.tangent[0], K * np.eye(2), rtol=1e-12)
    np.testing.assert_allclose(again.state["plastic"], state["plastic"], rtol=1e-12)


@examples
@given(st.data(), st.sampled_from([1, 2]))
def test_respond_is_pure_and_normal_force_time_step_and_velocity_play_no_part(data, dims):
    law = data.draw(laws(dims=dims))
    path = data.draw(paths(law, n=2))
    state = law.initial_state(2)
    for u in path:
        frozen = {key: value.copy() for key, value in state.items()}
        reference = law.respond(state, u, np.array([1e6, 2e6]), 0.01)
        other = law.respond(state, u, np.array([-3e5, 0.0]), 0.37, velocity=np.full((2, dims), 4.0))
        for key in state:
            np.testing.assert_array_equal(state[key], frozen[key])
        np.testing.assert_array_equal(reference.force, other.force)
        np.testing.assert_array_equal(reference.tangent, other.tangent)
        np.testing.assert_array_equal(reference.state["plastic"], other.state["plastic"])
        assert reference.state["plastic"] is not u
        state = reference.state


@examples
@given(st.data(), st.sampled_from([1, 2]))
def test_per_bearing_arrays_equal_separate_law_objects(data, dims):
    members = [data.draw(laws(dims=dims)) for _ in range(3)]
    grouped = ElastomericPlasticity(
        k=[m.k for m in members], qd=[m.qd for m in members], alpha=[m.alpha for m in members], dims=dims
    )
    path = data.draw(paths(members[0], n=3))
    together, tangents, state = run_history(grouped, path, n=3)
    for i, member in enumerate(members):
        alone, alone_tangents, alone_state = run_history(member, path[:, i], n=1)
        np.testing.assert_allclose(together[:, i], alone[:, 0], rtol=1e-12, atol=1e-12 * member.qd)
        np.testing.assert_allclose(tangents[:, i], alone_tangents[:, 0], rtol=1e-12, atol=1e-12 * member.k)
        np.testing.assert_allclose(grouped.slip(state)[i], member.slip(alone_state)[0], rtol=1e-12, atol=1e-18)


def test_per_bearing_values_are_read_only_arrays_and_scalars_stay_floats():
    law = lrb(k=np.array([1e7, 2e7]), qd=5, alpha=0)
    assert isinstance(law.qd, float) and isinstance(law.alpha, float)
    assert law.k.dtype == float and not law.k.flags.writeable
    np.testing.assert_allclose(law.yield_displacement, [5 / 1e7, 5 / 2e7])


@pytest.mark.parametrize("dims", [1, 2])
def test_passes_the_bearingfw_conformance_suite(dims):
    check_law(lrb(dims), max_examples=15)
    # and at an elastic-perfectly-plastic extreme, on a scale where it yields at once
    check_law(lrb(dims, alpha=0.0, qd=1e3), max_examples=8)


@settings(max_examples=3, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.sampled_from([1, 2]).flatmap(lambda dims: bearingfw.testing.laws(ElastomericPlasticity, dims=dims)))
def test_passes_the_conformance_suite_at_parameters_the_kit_draws(law):
    check_law(law, max_examples=5, shrink=False)


# --- the design helper and the preset ---------------------------------------------------------


def test_lead_rubber_parameters_by_hand():
    # W = 2 MN: K_d = 2e6 (2 pi / 2.5)^2 / 9.81 = 1.2878 MN/m, K_u = 12.878 MN/m, qd = 100 kN
    p = lead_rubber_parameters(2e6)
    assert p["k"] == pytest.approx(10 * 2e6 * (2 * np.pi / 2.5) ** 2 / 9.81, rel=1e-14)
    assert p["k"] == pytest.approx(12.878e6, rel=1e-4)
    assert p == {"k": p["k"], "qd": 1e5, "alpha": 0.1}
    law = ElastomericPlasticity(**p)
    # the isolated period of the weight on K_d is the one asked for
    assert 2 * np.pi * np.sqrt(2e6 / 9.81 / law.post_yield_stiffness) == pytest.approx(2.5, rel=1e-12)
    q = lead_rubber_parameters(1e6, period=3.0, strength_ratio=0.08, stiffness_ratio=8)
    assert q["alpha"] == 0.125 and q["qd"] == pytest.approx(8e4)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"weight": 0.0}, "'weight' = 0.0 is outside the allowed range weight > 0 N"),
        ({"weight": 1e6, "period": -1.0}, "'period' = -1.0"),
        ({"weight": 1e6, "strength_ratio": 1.0}, "0 < strength_ratio < 1"),
        ({"weight": 1e6, "stiffness_ratio": 1.0}, "stiffness_ratio > 1"),
        ({"weight": "heavy"}, "'weight' = 'heavy'"),
    ],
)
def test_lead_rubber_parameters_reject_bad_input(kwargs, message):
    with pytest.raises(ParameterError, match="lead_rubber_parameters") as error:
        lead_rubber_parameters(**kwargs)
    assert message in str(error.value)


def test_the_preset_designs_each_bearing_for_its_dead_load():
    name, params = preset_law(bearingfw.PresetBearing("3B", ks=4e8, friction=0.04, dead_load=2e6))
    assert name == "elastomeric-plasticity"
    assert params == lead_rubber_parameters(2e6, period=2.5, strength_ratio=0.05, stiffness_ratio=10.0)
    ElastomericPlasticity(**params, dims=2)  # admissible
    with pytest.raises(ParameterError, match="bearing '1A' carries N = None"):
        preset_law(bearingfw.PresetBearing("1A", ks=4e8, friction=0.04))


# --- inside a transient analysis ---------------------------------------------------------------


def _isolated_mass(kind="planar"):
    from bearingfw.model import Connector, Model, NodalMass, Node, Support

    extra = {"guided": "x"} if kind == "axial" else {}
    return Model(
        [Node("ground", 0.0, 0.0, 0.0), Node("deck", 0.0, 0.0, 0.0)],
        connectors=[Connector("lrb", "ground", "deck", kind, law="elastomeric-plasticity",
                              law_params={"k": K, "qd": QD, "alpha": ALPHA}, vertical_stiffness=1e10, **extra)],
        supports=[Support("ground"), Support("deck", ("rx", "ry", "rz"))],
        masses=[NodalMass("deck", 2e6 / 9.81)],
    )  # fmt: skip


@pytest.mark.parametrize("kind", ["planar", "axial"])
def test_in_a_transient_analysis_the_bearing_force_is_the_law_along_its_path_and_balances_the_mass(kind):
    from bearingfw.analysis import ConnectorResponse, NodalResponse, TransientSettings, solve_transient

    model = _isolated_mass(kind)
    dt = 0.01
    t = np.arange(301) * dt
    ag = np.column_stack([3.0 * np.sin(2 * np.pi * 1.0 * t), 2.0 * np.sin(2 * np.pi * 0.7 * t + 1.0), 0 * t])
    result = solve_transient(model, ag, dt, settings=TransientSettings(alpha=0.0, dt_integration=dt),
                             recorders=[ConnectorResponse(["lrb"], name="b"),
                                        NodalResponse(["deck"], "acceleration", name="acc")])  # fmt: skip
    dims = 2 if kind == "planar" else 1
    u = result.data["b.law_displacement"][1:, 0, :dims]
    force = result.data["b.force"][1:, 0, :dims]
    assert np.max(np.linalg.norm(u, axis=1)) > 3 * UY  # the bearing yields, repeatedly
    law = lrb(dims)
    np.testing.assert_allclose(force, drive(law, u), rtol=1e-9, atol=1e-9 * QD)
    # Newmark (alpha = 0) satisfies m (a + a_g) + F = 0 at every step, in the law's directions
    mass = 2e6 / 9.81
    acc = result.data["acc"][1:, 0, :dims]
    np.testing.assert_allclose(mass * (acc + ag[1:, :dims]) + force, 0.0, atol=1e-6 * QD)


def test_the_preset_runs_the_reference_bridge_and_each_bearing_follows_its_own_law():
    from bearingfw.analysis import ConnectorResponse, solve_transient
    from bearingfw.bridges import reference_bridge

    model = reference_bridge("lead-rubber")
    dt = 0.01
    t = np.arange(151) * dt
    ramp = np.minimum(1.0, t / 0.5)
    ag = np.column_stack([4.0 * ramp * np.sin(2 * np.pi * 1.2 * t), 3.0 * ramp * np.sin(2 * np.pi * 0.9 * t), 0 * t])
    result = solve_transient(model, ag, dt, recorders=[ConnectorResponse(name="b")])
    lrbs = [(i, c) for i, c in enumerate(model.connectors) if c.law == "elastomeric-plasticity"]
    assert len(lrbs) == 11  # every bearing but the fixed 4A
    assert len({dict(c.law_params)["qd"] for _, c in lrbs}) > 5  # designed per bearing
    yielded = 0
    for i, c in lrbs:
        directions = list(c.law_directions)
        law = ElastomericPlasticity(**dict(c.law_params), dims=len(directions))
        u = result.data["b.law_displacement"][1:, i, directions]
        force = result.data["b.force"][1:, i, directions]
        np.testing.assert_allclose(force, drive(law, u), rtol=1e-9, atol=1e-9 * law.qd)
        yielded += np.max(np.linalg.norm(u, axis=1)) > law.yield_displacement
    assert yielded >= 6
