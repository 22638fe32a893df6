"""Master-slave constraints: every equation holds for every column of T, rigid bodies pass."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bearingfw.model import Connector, FrameElement, Material, Model, Node, RigidLink, Section, Support, build_system
from bearingfw.model.constraints import ARM_ZERO

STEEL = Material("steel", 210e9, density=7850.0)
SEC = Section("s", A=0.01, Iy=1e-4, Iz=2e-4, J=5e-5)
coordinate = st.floats(-5.0, 5.0, allow_nan=False)
point = st.tuples(coordinate, coordinate, coordinate)
unit = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.2)
up = unit.map(lambda v: (v[0], v[1], abs(v[2]) + 0.1))  # a connector's z axis points up


def rigid_body_vectors(system):
    return np.column_stack([system.rigid_body(d, about=(0.3, -0.2, 0.1)) for d in ("x", "y", "z", "rx", "ry", "rz")])


def equation_residual(system, equations=None):
    """``max |C T|`` over translation and over rotation columns of ``T`` (0 when ``T`` satisfies
    the equations: the independent ones by default).

    Coefficients are O(1) on translations; on rotations they are lever arms (m). A row left with
    nothing but arms below ``ARM_ZERO`` counts as redundant: a redundant equation may miss by that
    much on rotation columns (independent ones hold exactly).
    """
    equations = system.constraints.equations if equations is None else equations
    if not equations:
        return 0.0, 0.0
    C = np.zeros((len(equations), system.n_dof))
    for k, eq in enumerate(equations):
        np.add.at(C[k], eq.dofs, eq.coefficients)
    CT = np.abs(C @ system.T)
    rotation = system.free_dofs % 6 >= 3
    return CT[:, ~rotation].max(initial=0.0), CT[:, rotation].max(initial=0.0)


def assert_equations_hold(system, equations=None):
    translation, rotation = equation_residual(system, equations)
    assert translation < 1e-9 and rotation < ARM_ZERO + 1e-9


@settings(max_examples=40, deadline=None)
@given(
    girder=point,
    offset=point,
    far=point,
    x_axis=unit,
    z_axis=up,
    kind=st.sampled_from(["join", "axial", "planar"]),
    supported=st.booleans(),
)
def test_rigid_links_and_ties_hold_for_every_column_of_T(girder, offset, far, x_axis, z_axis, kind, supported):
    girder, far = np.array(girder), np.array(far)
    soffit = girder + np.array(offset)
    if np.linalg.norm(far - girder) < 0.1 or np.linalg.norm(far - soffit) < 0.1:
        far = far + 11.0
    if abs(np.dot(x_axis, z_axis)) > 0.95 * np.linalg.norm(x_axis) * np.linalg.norm(z_axis):
        x_axis = (
            np.cross(z_axis, (1.0, 2.0, 3.0)) if np.linalg.norm(np.cross(z_axis, (1.0, 2.0, 3.0))) > 0.1 else (1, 0, 0)
        )
    nodes = [Node("g", *girder), Node("s", *soffit), Node("p", *soffit), Node("f", *far), Node("h", *(far + 1.0))]
    sliding = {} if kind == "join" else dict(law="linear-spring", law_params={"k": 1e8}, vertical_stiffness=1e9)
    model = Model(
        nodes,
        elements=[FrameElement("pier", "f", "p", SEC, STEEL), FrameElement("girder", "g", "h", SEC, STEEL)],
        connectors=[Connector("c", "p", "s", kind, x_axis=x_axis, z_axis=z_axis, **sliding)],
        rigid_links=[RigidLink("offset", "g", "s")],
        # both ends of the connector held: its tied directions become redundant equations
        supports=[Support("g"), Support("p")] if supported else [],
    )
    system = build_system(model)
    assert max(equation_residual(system)) < 1e-9  # coefficients O(1): offsets below 1e-10 m count as zero
    # the redundant equations (skipped by the elimination) hold as well
    assert bool(system.constraints.redundant) == (supported and kind != "planar")
    assert_equations_hold(system, system.constraints.redundant)
    n_eq = len(system.constraints.equations)
    assert system.n_free == system.n_dof - n_eq - system.constraints.inactive.size
    assert np.linalg.matrix_rank(system.T.toarray()) == system.n_free
    if supported:
        return
    # free-floating structure: every rigid-body motion satisfies the constraints exactly
    R = rigid_body_vectors(system)
    q, *_ = np.linalg.lstsq(system.T.toarray(), R, rcond=None)
    np.testing.assert_allclose(system.T @ q, R, atol=1e-10)
    # the connector's relative displacement of a rigid-body motion is zero (it has no length)
    np.testing.assert_allclose(system.connectors.D @ R, 0.0, atol=1e-12)


def test_a_tie_between_supported_nodes_is_redundant_and_reactions_still_balance():
    nodes = [Node("a", 0, 0, 0), Node("b", 0, 0, 0), Node("c", 4, 0, 0)]
    model = Model(
        nodes,
        elements=[FrameElement("e", "b", "c", SEC, STEEL)],
        connectors=[Connector("j", "a", "b", "join")],
        supports=[Support("a"), Support("b", ("ux", "uy", "uz", "rx", "ry", "rz"))],
    )
    system = build_system(model)
    assert {eq.source for eq in system.constraints.redundant} == {"connector"}
    assert len(system.constraints.redundant) == 3
    assert_equations_hold(system, system.constraints.redundant)


def test_chained_rigid_links_follow_the_first_master():
    nodes = [Node("a", 0, 0, 0), Node("b", 1, 0, 0), Node("c", 1, 2, -1), Node("d", 5, 0, 0)]
    model = Model(
        nodes,
        elements=[FrameElement("e", "a", "d", SEC, STEEL)],
        rigid_links=[RigidLink("ab", "a", "b"), RigidLink("bc", "b", "c")],
    )
    system = build_system(model)
    dof = system.dofmap
    # rotate node a by theta about z: c moves by theta x (X_c - X_a)
    q = np.zeros(system.n_free)
    masters = list(system.constraints.masters)
    q[masters.index(dof.dof("a", "rz"))] = 1e-3
    u = system.expand(q)
    np.testing.assert_allclose(u[dof.node_dofs("c")[:3]], np.cross([0, 0, 1e-3], [1, 2, -1]), atol=1e-15)
    np.testing.assert_allclose(u[dof.dof("c", "rz")], 1e-3)


def test_cyclic_rigid_links_are_redundant_not_singular():
    nodes = [Node("a", 0, 0, 0), Node("b", 1, 0, 0), Node("d", 5, 0, 0)]
    model = Model(
        nodes,
        elements=[FrameElement("e", "a", "d", SEC, STEEL)],
        rigid_links=[RigidLink("ab", "a", "b"), RigidLink("ba", "b", "a")],
        supports=[Support("d")],
    )
    system = build_system(model)
    assert len(system.constraints.redundant) == 6
    assert max(equation_residual(system)) < 1e-12
    assert max(equation_residual(system, system.constraints.redundant)) < 1e-12


@pytest.mark.parametrize("gap", [0.0, 1e-7, 5e-7])
def test_a_tie_between_nodes_linked_to_one_master_is_redundant_at_a_round_off_gap(gap):
    """Two soffit nodes rigidly linked to the same master and joined: the JOIN adds nothing.

    Their arms differ by the gap, well inside the connector length tolerance: the tie's reduced
    rows hold only sub-micrometre lever arms on the master's rotations, which must count as zero
    (else the JOIN would clamp the master's rotations).
    """
    nodes = [Node("m", 0, 0, 0), Node("a", 0, 0, -1), Node("b", 0, 0, -1 + gap), Node("d", 5, 0, 0)]
    model = Model(
        nodes,
        [FrameElement("e", "m", "d", SEC, STEEL)],
        [Connector("c", "a", "b", "join")],
        [RigidLink("la", "m", "a"), RigidLink("lb", "m", "b")],
        [Support("d")],
    )
    system = build_system(model)
    assert [eq.source for eq in system.constraints.redundant] == ["connector"] * 3
    assert system.n_free == 6  # the master's six DOFs, none clamped
    assert_equations_hold(system, system.constraints.redundant)


def test_untouched_dofs_are_inactive():
    nodes = [Node("a", 0, 0, 0), Node("b", 1, 0, 0), Node("lonely", 9, 9, 9)]
    model = Model(nodes, elements=[FrameElement("e", "a", "b", SEC, STEEL)], supports=[Support("a")])
    system = build_system(model)
    assert sorted(system.constraints.inactive) == list(system.dofmap.node_dofs("lonely"))
    assert system.n_free == 6


@pytest.mark.parametrize("kind, tied", [("join", {0, 1, 2}), ("axial", {1}), ("planar", set())])
def test_connector_kinds_tie_their_directions(kind, tied):
    nodes = [Node("p", 0, 0, 0), Node("s", 0, 0, 0), Node("f", 0, 0, -3), Node("g", 4, 0, 0)]
    sliding = {} if kind == "join" else dict(law="frictionless", vertical_stiffness=1e9)
    model = Model(
        nodes,
        [FrameElement("pier", "f", "p", SEC, STEEL), FrameElement("deck", "s", "g", SEC, STEEL)],
        [Connector("c", "p", "s", kind, **sliding)],
        supports=[Support("f")],
    )
    system = build_system(model)
    assert {k for _, k in system.connectors.ties} == tied
    assert {k for _, k in system.connectors.governed} == {0, 1, 2} - tied - {2}
