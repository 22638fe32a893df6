"""Static analysis against closed-form and hand (unit-load method) solutions."""

from __future__ import annotations

import numpy as np
import pytest
from attrs import evolve as attrs_evolve
from kernel_models import (
    CONCRETE,
    GIRDER,
    RECT,
    SDOF_KC,
    SDOF_M,
    STEEL,
    cantilever_model,
    deck_model,
    sdof_frame_model,
)

from bearingfw.analysis import ConvergenceError, factorize, gravity, recover_connector_forces, solve_static
from bearingfw.analysis.static import SYMMETRIC_ORDERING
from bearingfw.model import (
    Connector,
    FrameElement,
    Model,
    ModelError,
    NodalLoad,
    Node,
    RigidLink,
    Section,
    Support,
    TrussElement,
    build_system,
)

EXACT = 1e-9  # Euler-Bernoulli/Timoshenko elements are exact for nodal loads: only round-off remains


def rel(a, b):
    return abs(a - b) / abs(b)


def test_cantilever_tip_load_both_planes_and_torsion():
    L, P, Tq = 10.0, 2.0e3, 5.0e3
    model = cantilever_model(n=20, L=L)
    res = solve_static(model, [NodalLoad("N20", fy=P, fz=-P, mx=Tq)])
    G = STEEL.shear_modulus
    assert rel(res.displacement("N20", "uz"), -P * L**3 / (3 * STEEL.E * RECT.Iy)) < EXACT
    assert rel(res.displacement("N20", "uy"), P * L**3 / (3 * STEEL.E * RECT.Iz)) < EXACT
    assert rel(res.displacement("N20", "rx"), Tq * L / (G * RECT.J)) < EXACT
    # theta_y = -w' (right-handed about y), theta_z = v'
    assert rel(res.displacement("N20", "ry"), P * L**2 / (2 * STEEL.E * RECT.Iy)) < EXACT
    assert rel(res.displacement("N20", "rz"), P * L**2 / (2 * STEEL.E * RECT.Iz)) < EXACT
    r = res.support_reaction("N0")
    assert r["uz"] == pytest.approx(P, rel=EXACT) and r["uy"] == pytest.approx(-P, rel=EXACT)
    assert r["ry"] == pytest.approx(-P * L, rel=EXACT) and r["rx"] == pytest.approx(-Tq, rel=EXACT)


def test_timoshenko_adds_shear_flexibility_exactly():
    L, P = 1.0, 1.0e5  # a stocky member: shear deformation is ~ 20% of the deflection
    model = cantilever_model(n=5, L=L, shear_deformation=True)
    res = solve_static(model, [NodalLoad("N5", fz=-P, fy=P)])
    G = STEEL.shear_modulus
    bending_z, shear_z = P * L**3 / (3 * STEEL.E * RECT.Iy), P * L / (G * RECT.Avz)
    assert shear_z / bending_z > 0.1
    assert rel(res.displacement("N5", "uz"), -(bending_z + shear_z)) < EXACT
    assert rel(res.displacement("N5", "uy"), P * L**3 / (3 * STEEL.E * RECT.Iz) + P * L / (G * RECT.Avy)) < EXACT


def test_truss_bar_axial():
    L, A, P = 7.0, 3e-3, 4e4
    nodes = [Node("a", 0, 0, 0), Node("b", L, 0, 0)]
    model = Model(
        nodes,
        [TrussElement("bar", "a", "b", A, STEEL)],
        supports=[Support("a", ("ux", "uy", "uz")), Support("b", ("uy", "uz"))],
    )
    res = solve_static(model, [NodalLoad("b", fx=P)])
    assert rel(res.displacement("b", "ux"), P * L / (STEEL.E * A)) < EXACT
    # the bar's node rotations are untouched DOFs: dropped, not a singular matrix
    assert res.system.constraints.inactive.size == 6


def test_space_truss_tripod_against_unit_load_method():
    """A statically determinate tripod; bar forces from statics, displacements by virtual work."""
    h, a = 4.0, 3.0
    areas = (2e-3, 3e-3, 5e-3)
    bases = [(a * np.cos(t), a * np.sin(t), 0.0) for t in np.deg2rad([90.0, 210.0, 330.0])]
    bases[1] = (bases[1][0] - 0.7, bases[1][1], 0.4)  # break the symmetry
    nodes = [Node("top", 0.3, -0.2, h)] + [Node(f"b{k}", *xyz) for k, xyz in enumerate(bases)]
    bars = [TrussElement(f"bar{k}", f"b{k}", "top", areas[k], STEEL) for k in range(3)]
    model = Model(nodes, bars, supports=[Support(f"b{k}", ("ux", "uy", "uz")) for k in range(3)])
    P = np.array([3e4, -2e4, -8e4])
    res = solve_static(model, [NodalLoad("top", *P)])
    top = np.array(nodes[0].xyz)
    e = np.array([top - np.array(b) for b in bases])
    lengths = np.linalg.norm(e, axis=1)
    e /= lengths[:, None]
    # apex equilibrium: P - sum N_k e_k = 0 (tension N_k pulls the apex towards base k)
    forces = np.linalg.solve(e.T, P)
    flexibility = lengths / (STEEL.E * np.array(areas))
    for d in range(3):
        unit = np.linalg.solve(e.T, np.eye(3)[d])
        expected = float(np.sum(forces * unit * flexibility))
        assert rel(res.displacement("top", ("ux", "uy", "uz")[d]), expected) < 1e-6
    assert np.allclose(res.reaction_resultant()[:3], -P, rtol=0, atol=1e-9 * np.abs(P).max())


def test_portal_frame_against_unit_load_method():
    """Pinned base A, roller B (vertical reaction only), horizontal load H at the top of column A.

    Statics: R_B = H h / b, column AC in tension H h / b, column BD in compression, beam moment
    from H h at C to 0 at D, beam axial force 0. Unit-load method (bending and axial energy):
    u_C = H (h^3 / (3 E Ic) + h^2 b / (3 E Ib) + 2 h^3 / (b^2 E Ac)).
    """
    h, b, H = 4.0, 6.0, 5e4
    column = Section("column", A=0.02, Iy=2e-4, Iz=1e-4, J=5e-5)
    beam = Section("beam", A=0.03, Iy=5e-4, Iz=2e-4, J=8e-5)
    n = 3
    nodes, elements = [], []
    for name, (x0, z0), (x1, z1), sec in (
        ("AC", (0, 0), (0, h), column),
        ("CD", (0, h), (b, h), beam),
        ("DB", (b, h), (b, 0), column),
    ):
        for k in range(n + 1):
            nodes.append(Node(f"{name}{k}", x0 + (x1 - x0) * k / n, 0.0, z0 + (z1 - z0) * k / n))
        elements += [FrameElement(f"{name}e{k}", f"{name}{k}", f"{name}{k + 1}", sec, STEEL) for k in range(n)]
    # corners: the member ends are distinct nodes at the same point, joined rigidly (rigid links)
    links = [RigidLink("C", f"AC{n}", "CD0"), RigidLink("D", f"CD{n}", "DB0")]
    supports = [Support("AC0", ("ux", "uy", "uz", "rx", "rz")), Support(f"DB{n}", ("uy", "uz", "rx", "rz"))]
    model = Model(nodes, elements, rigid_links=links, supports=supports)
    res = solve_static(model, [NodalLoad(f"AC{n}", fx=H)])
    E = STEEL.E
    u_C = H * (h**3 / (3 * E * column.Iy) + h**2 * b / (3 * E * beam.Iy) + 2 * h**3 / (b**2 * E * column.A))
    assert rel(res.displacement(f"AC{n}", "ux"), u_C) < 1e-6
    assert rel(res.displacement(f"CD{n}", "ux"), u_C) < 1e-6  # beam axial force is zero
    assert rel(res.displacement(f"CD{n}", "uz"), -(H * h / b) * h / (E * column.A)) < 1e-6
    assert rel(res.displacement(f"AC{n}", "uz"), (H * h / b) * h / (E * column.A)) < 1e-6
    assert rel(res.support_reaction(f"DB{n}")["uz"], H * h / b) < 1e-9


def test_rigid_offset_transfers_the_moment():
    """A horizontal load P at an offset e below the tip acts on the tip as P plus M_y = -e P."""
    L, e, P = 6.0, 0.8, 3e4
    base = cantilever_model(n=6, L=L)
    model = Model(
        [*base.nodes, Node("off", L, 0.0, -e)],
        base.elements,
        rigid_links=[RigidLink("offset", "N6", "off")],
        supports=base.supports,
    )
    res = solve_static(model, [NodalLoad("off", fx=P)])
    E, Iy, A = STEEL.E, RECT.Iy, RECT.A
    M = -e * P
    assert rel(res.displacement("N6", "ux"), P * L / (E * A)) < EXACT
    assert rel(res.displacement("N6", "ry"), M * L / (E * Iy)) < EXACT
    assert rel(res.displacement("N6", "uz"), -M * L**2 / (2 * E * Iy)) < EXACT
    # the offset node moves rigidly with the tip: u_off = u_tip + theta x r
    assert rel(res.displacement("off", "ux"), P * L / (E * A) + e**2 * P * L / (E * Iy)) < EXACT
    assert rel(res.support_reaction("N0")["ry"], e * P) < EXACT
    assert res.system.n_free == 6 * 6  # the offset node costs no DOFs


def test_sdof_frame_static_stiffness_is_eq_8():
    """A lateral load H on the deck: u = H / K with K = K_c + K_c K_s / (K_c + K_s)."""
    Ks, H = 4.0e8, 1.0e6
    res = solve_static(sdof_frame_model("linear-spring", {"k": Ks}), [NodalLoad("DL", fy=H)])
    K = SDOF_KC + SDOF_KC * Ks / (SDOF_KC + Ks)
    assert rel(res.displacement("DL", "uy"), H / K) < EXACT
    spring = res.connector_force("sliding")
    assert rel(spring[1], H * (K - SDOF_KC) / K) < EXACT  # the share of the right column
    assert rel(res.connector_force("pinned")[1], H * SDOF_KC / K) < EXACT  # tie force from multipliers


def test_friction_limits_the_static_bearing_force():
    """Regularized Coulomb under gravity and a lateral load beyond mu N: the bearing slides at mu N."""
    Ks, mu = 4.0e8, 0.05
    model = sdof_frame_model("regularized-coulomb", {"k": Ks, "mu": mu})
    H = 0.5 * SDOF_M * 9.81  # far beyond the friction capacity of the right bearing
    res = gravity(model, loads=[NodalLoad("DL", fy=H)], bearings="active")
    N = res.normal_force("sliding")
    assert N > 0
    assert rel(abs(res.connector_force("sliding")[1]), mu * N) < 1e-9
    (state,) = res.law_states
    assert abs(state["slip"][0, 1]) > 0  # the committed state records the slip
    assert res.iterations > 1
    # the pinned column takes the rest
    assert rel(res.connector_force("pinned")[1] + res.connector_force("sliding")[1], H) < 1e-9


@pytest.mark.parametrize("bearings", ["set-after-dead-load", "active"])
@pytest.mark.parametrize(
    "law, params",
    [
        ("frictionless", {}),
        ("linear-spring", {"k": 4e8}),
        ("regularized-coulomb", {"k": 4e8, "mu": 0.04}),
        ("fixed", {}),
    ],
)
def test_gravity_reactions_sum_to_the_weight(law, params, bearings):
    model = deck_model(law, params)
    g = 9.81
    res = gravity(model, g=g, bearings=bearings)
    mass = sum(
        (e.material.density * e.section.A + e.added_mass)
        * np.linalg.norm(model.coordinates[model.node_index(e.j)] - model.coordinates[model.node_index(e.i)])
        for e in model.elements
    )
    superstructure = sum(
        (e.material.density * e.section.A + e.added_mass)
        * np.linalg.norm(model.coordinates[model.node_index(e.j)] - model.coordinates[model.node_index(e.i)])
        for e in model.elements
        if not e.name.startswith("pier")
    )
    nodal = sum(m.mass for m in model.masses)
    weight, deck_weight = g * (mass + nodal), g * (superstructure + nodal)
    total = res.reaction_resultant()
    assert rel(total[2], weight) < 1e-9
    assert np.all(np.abs(total[:2]) < 1e-9 * weight)
    assert rel(res.normal_forces.sum(), deck_weight) < 1e-9
    assert np.all(res.normal_forces > 0)
    # every connector's vertical force balances its girder's share: horizontal forces sum to zero
    R = np.array([c.rotation for c in model.connectors])
    horizontal = np.einsum("nij,ni->j", R, res.connector_forces)[:2]
    assert np.all(np.abs(horizontal) < 1e-9 * weight)


def test_gravity_is_linear_in_g_for_linear_laws():
    a = gravity(deck_model("linear-spring", {"k": 4e8}), g=9.81)
    b = gravity(a.system, g=2 * 9.81)
    assert np.allclose(b.u, 2 * a.u, rtol=1e-9, atol=1e-15)
    assert np.allclose(b.normal_forces, 2 * a.normal_forces, rtol=1e-9)


def test_zero_load_gives_the_virgin_state_in_either_bearing_mode():
    system = build_system(deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}))
    for res in (solve_static(system), gravity(system, g=0.0)):
        assert res.iterations == 0 and not np.any(res.u)
        assert not np.any(res.support_reactions) and not np.any(res.connector_forces)
        assert not np.any(res.law_reference) and not np.any(res.law_forces)
        for state in res.law_states:
            assert not np.any(state["slip"])


# --- mechanisms ---------------------------------------------------------------------------------
def bent_beam_pinned_at_one_node():
    """A bent member held by one pin: free to rotate rigidly about it (round-off leaves tiny pivots)."""
    nodes = [Node(f"N{k}", 1.3 * k, 0.7 * k, 0.37 * k * k) for k in range(5)]
    elements = [FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", RECT, STEEL) for k in range(4)]
    return Model(nodes, elements, supports=[Support("N0", ("ux", "uy", "uz"))])


def test_a_near_singular_mechanism_is_reported_not_solved():
    """Before: 'converged' to |u| ~ 2e9 m, because the residual was judged against |K| |q|."""
    model = bent_beam_pinned_at_one_node()
    with pytest.raises(ModelError, match=r"singular \(smallest LU pivot .* mechanism; the free motion moves most N4\."):
        solve_static(model, [NodalLoad("N4", fz=-1e3)])
    system = build_system(model)
    with pytest.raises(ModelError, match="mechanism"):
        factorize(system.K_free)
    # the same structure pinned at a second node stands
    held = Model(model.nodes, model.elements, supports=[Support("N0"), Support("N4", ("ux", "uy", "uz"))])
    assert np.abs(solve_static(held, [NodalLoad("N2", fz=-1e3)]).u).max() < 1e-3


def simply_supported_girder(law, params, with_fork=True):
    """One girder on two PLANAR bearings at the soffit (rigid offsets), a torsional fork at one end.

    Under self-weight the end rotations move the soffits apart by the offset times the rotation:
    about 1.2 mm each way, far beyond the stick limit of friction (mu N / k ~ 0.05 mm).
    """
    n, span = 8, 20.0
    nodes = [Node(f"G{k}", span * k / n, 0.0, 0.0) for k in range(n + 1)]
    elements = [FrameElement(f"E{k}", f"G{k}", f"G{k + 1}", GIRDER, CONCRETE, added_mass=1500.0) for k in range(n)]
    links, connectors, supports = [], [], []
    for k in (0, n):
        nodes += [Node(f"S{k}", span * k / n, 0.0, -0.8), Node(f"P{k}", span * k / n, 0.0, -0.8)]
        links.append(RigidLink(f"L{k}", f"G{k}", f"S{k}"))
        supports.append(Support(f"P{k}"))
        connectors.append(
            Connector(f"C{k}", f"P{k}", f"S{k}", "planar", law=law, law_params=params, vertical_stiffness=5e9)
        )
    if with_fork:
        supports.append(Support("G0", ("rx",)))
    return Model(nodes, elements, connectors, links, supports)


FRICTION = ("regularized-coulomb", {"k": 4e8, "mu": 0.04})


def test_bearings_set_after_the_dead_load_start_virgin_at_the_dead_load_position():
    model = simply_supported_girder(*FRICTION)
    res = gravity(model)
    assert res.bearings == "set-after-dead-load"
    weight = -res.load[2::6].sum()  # the load acts down (-z)
    # the laws carry nothing, keep their virgin states and see zero displacement
    assert not np.any(res.law_forces) and not np.any(res.connector_forces[:, :2])
    assert not np.any(res.law_states[0]["slip"])
    np.testing.assert_allclose(res.law_displacements, 0.0, atol=1e-18)
    # law_reference is the dead-load movement: the soffits (0.8 m below the axis) move apart by
    # the end rotation times the offset, u_x = (theta x r)_x = -0.8 theta_y
    ops = res.system.connectors
    np.testing.assert_allclose(res.law_reference, ops.B @ res.u, rtol=0, atol=1e-18)
    theta = res.displacement("G0", "ry")
    np.testing.assert_allclose(res.law_reference.reshape(2, 2)[:, 0], [-0.8 * theta, 0.8 * theta], rtol=1e-9)
    assert abs(theta) * 0.8 > 10 * 0.04 * res.normal_forces[0] / 4e8  # far beyond the stick limit
    np.testing.assert_allclose(res.normal_forces, [weight / 2] * 2, rtol=1e-9)
    # a law evaluated relative to the reference: stick, zero force, the initial tangent
    (response,) = ops.respond(res.law_states, ops.B @ res.u, ops.normal_forces(ops.V @ res.u), 1.0, res.law_reference)
    np.testing.assert_allclose(response.force, 0.0, atol=1e-9)
    np.testing.assert_allclose(response.tangent, np.broadcast_to(4e8 * np.eye(2), (2, 2, 2)))


def test_active_friction_bearings_that_slip_under_dead_load_get_their_own_message():
    """Both bearings slide apart: nothing fixes the girder's longitudinal position. Not a mechanism."""
    model = simply_supported_girder(*FRICTION)
    with pytest.raises(ConvergenceError, match=r"the bearings 'C0', 'C8' slip .* not a mechanism"):
        gravity(model, bearings="active")
    # with springs instead the same structure stands, its bearings pulled apart by the dead load
    res = gravity(simply_supported_girder("linear-spring", {"k": 4e8}), bearings="active")
    weight = -res.load[2::6].sum()
    np.testing.assert_allclose(res.law_forces.reshape(2, 2)[:, 0].sum(), 0.0, atol=1e-9 * weight)
    assert np.abs(res.law_forces).max() > 1e5


def test_frictionless_bearings_without_other_restraint_are_a_mechanism_in_both_modes():
    model = simply_supported_girder("frictionless", {})
    for mode in ("set-after-dead-load", "active"):
        with pytest.raises(ModelError, match=r"mechanism; the free motion moves most G\d\.u[xy]"):
            gravity(model, bearings=mode)


def test_a_load_along_a_direction_only_the_bearings_hold_needs_active_bearings():
    model = simply_supported_girder("linear-spring", {"k": 4e8})
    with pytest.raises(ModelError, match="pushes along motions that only the bearings restrain"):
        gravity(model, loads=[NodalLoad("G4", fx=1e3)])
    res = gravity(model, loads=[NodalLoad("G4", fx=1e3)], bearings="active")
    assert res.law_forces.reshape(2, 2)[:, 0].sum() == pytest.approx(1e3, rel=1e-9)


def test_set_after_dead_load_matches_active_for_linear_springs_but_with_zero_bearing_force():
    """Same vertical equilibrium (N), but active springs take the end movements, set ones do not."""
    model = deck_model("linear-spring", {"k": 4e8})
    active = gravity(model, bearings="active")
    set_ = gravity(active.system)
    np.testing.assert_allclose(set_.normal_forces.sum(), active.normal_forces.sum(), rtol=1e-12)
    assert np.abs(active.law_forces).max() > 1e3 and not np.any(set_.law_forces)
    np.testing.assert_allclose(active.law_reference, 0.0)
    np.testing.assert_allclose(active.law_displacements, active.system.connectors.B @ active.u)


def test_unknown_bearing_mode_is_named():
    with pytest.raises(ModelError, match=r"parameter 'bearings' must be one of 'set-after-dead-load', 'active'"):
        gravity(cantilever_model(n=2), bearings="frozen")


# --- connector frames and the sign of N ---------------------------------------------------------
def test_join_and_spring_normal_forces_are_compressive_and_balance_the_deck():
    res = gravity(sdof_frame_model("linear-spring", {"k": 4e8}))
    N = {c.name: res.normal_force(c.name) for c in res.system.model.connectors}
    assert N["pinned"] > 0 and N["sliding"] > 0  # JOIN from the tie multiplier, PLANAR from the spring
    assert N["pinned"] + N["sliding"] == pytest.approx(SDOF_M * 9.81, rel=1e-9)


@pytest.mark.parametrize("angle", [0.3, 2.0])
def test_normal_force_does_not_depend_on_the_connector_frame_about_the_vertical(angle):
    base = sdof_frame_model("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    x_axis = (np.cos(angle), np.sin(angle), 0.0)
    turned = Model(
        base.nodes,
        base.elements,
        [attrs_evolve(c, x_axis=x_axis) for c in base.connectors],
        base.rigid_links,
        base.supports,
        base.masses,
    )
    np.testing.assert_allclose(gravity(turned).normal_forces, gravity(base).normal_forces, rtol=1e-9)


def test_a_tilted_bearing_frame_reads_n_along_its_own_z():
    """A PLANAR bearing whose z axis leans by a: N = (vertical reaction) cos a, horizontal part sin a."""
    a = 0.1
    base = sdof_frame_model("linear-spring", {"k": 4e8})
    tilted = [
        attrs_evolve(c, x_axis=(1.0, 0.0, 0.0), z_axis=(0.0, np.sin(a), np.cos(a))) if c.name == "sliding" else c
        for c in base.connectors
    ]
    model = Model(base.nodes, base.elements, tilted, base.rigid_links, base.supports, base.masses)
    res = gravity(model)
    con = model.connector("sliding")
    on_deck = -(con.rotation.T @ res.connector_force("sliding"))  # global force on the girder side
    assert res.normal_force("sliding") > 0
    assert res.normal_force("sliding") == pytest.approx(on_deck[2] * np.cos(a) + on_deck[1] * np.sin(a), rel=1e-9)
    total = sum(-(c.rotation.T @ res.connector_force(c.name)) for c in model.connectors)
    np.testing.assert_allclose(total, [0.0, 0.0, SDOF_M * 9.81], atol=1e-9 * SDOF_M * 9.81)


def test_factorize_orderings_solve_alike_and_both_detect_a_mechanism():
    system = build_system(cantilever_model(n=12))
    b = np.random.default_rng(3).normal(size=system.n_free)
    x = factorize(system.K_free).solve(b)
    y = factorize(system.K_free, ordering=SYMMETRIC_ORDERING).solve(b)
    np.testing.assert_allclose(y, x, rtol=1e-9, atol=1e-12 * np.abs(x).max())
    mechanism = build_system(bent_beam_pinned_at_one_node()).K_free
    for ordering in ("COLAMD", SYMMETRIC_ORDERING):
        with pytest.raises(ModelError, match="mechanism"):
            factorize(mechanism, ordering=ordering)


def test_vectorised_force_recovery_equals_the_equation_by_equation_assignment():
    """recover_connector_forces builds index arrays (ForceRecovery); check them against a plain loop."""
    preload = gravity(deck_model("linear-spring", {"k": 4e8}))
    system = preload.system
    ops = system.connectors
    rng = np.random.default_rng(5)
    u = rng.normal(size=system.n_dof)
    law = rng.normal(size=ops.n_governed)
    lam = rng.normal(size=len(system.constraints.equations))
    forces, reactions = recover_connector_forces(system, u, law, lam)
    expected = np.zeros((ops.n_connectors, 3))
    expected[ops.spring_connectors, 2] = ops.kv * (ops.V @ u)
    for (c, k), f in zip(ops.governed, law, strict=True):
        expected[c, k] = f
    expected_reactions = np.zeros((len(system.model.supports), 6))
    for eq, value in zip(system.constraints.equations, lam, strict=True):
        if eq.source == "connector":
            expected[eq.index, eq.component] = -value
        elif eq.source == "support":
            expected_reactions[eq.index, eq.component] = value
    assert any(eq.source == "connector" for eq in system.constraints.equations)
    np.testing.assert_array_equal(forces, expected)
    np.testing.assert_array_equal(reactions, expected_reactions)
