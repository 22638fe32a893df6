"""Master-slave constraints: every equation holds for every column of T, rigid bodies pass."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bearingfw.model import Connector, FrameElement, Material, Model, Node, RigidLink, Section, Support, build_system

STEEL = Material("steel", 210e9, density=7850.0)
SEC = Section("s", A=0.01, Iy=1e-4, Iz=2e-4, J=5e-5)
coordinate = st.floats(-5.0, 5.0, allow_nan=False)
point = st.tuples(coordinate, coordinate, coordinate)
unit = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.2)


def rigid_body_vectors(system):
    return np.column_stack([system.rigid_body(d, about=(0.3, -0.2, 0.1)) for d in ("x", "y", "z", "rx", "ry", "rz")])


def equation_residual(system):
    """max |C T| scaled by the coefficients: 0 when T satisfies every independent equation."""
    CT = system.constraints.C @ system.T
    return abs(CT).max() if CT.nnz else 0.0


@settings(max_examples=40, deadline=None)
@given(
    girder=point, offset=point, far=point, x_axis=unit, z_axis=unit, kind=st.sampled_from(["join", "axial", "planar"])
)
def test_rigid_links_and_ties_hold_for_every_column_of_T(girder, offset, far, x_axis, z_axis, kind):
    girder, far = np.array(girder), np.array(far)
    soffit = girder + np.array(offset)
    if np.linalg.norm(far - girder) < 0.1 or np.linalg.norm(far - soffit) < 0.1:
        far = far + 11.0
    if abs(np.dot(x_axis, z_axis)) > 0.95 * np.linalg.norm(x_axis) * np.linalg.norm(z_axis):
        x_axis = (
            np.cross(z_axis, (1.0, 2.0, 3.0)) if np.linalg.norm(np.cross(z_axis, (1.0, 2.0, 3.0))) > 0.1 else (0, 0, 1)
        )
    nodes = [Node("g", *girder), Node("s", *soffit), Node("p", *soffit), Node("f", *far), Node("h", *(far + 1.0))]
    sliding = {} if kind == "join" else dict(law="linear-spring", law_params={"k": 1e8}, vertical_stiffness=1e9)
    model = Model(
        nodes,
        elements=[FrameElement("pier", "f", "p", SEC, STEEL), FrameElement("girder", "g", "h", SEC, STEEL)],
        connectors=[Connector("c", "p", "s", kind, x_axis=x_axis, z_axis=z_axis, **sliding)],
        rigid_links=[RigidLink("offset", "g", "s")],
    )
    system = build_system(model)
    assert equation_residual(system) < 1e-9  # coefficients are O(1): offsets below 1e-10 m count as zero
    # free-floating structure: every rigid-body motion satisfies the constraints exactly
    R = rigid_body_vectors(system)
    q, *_ = np.linalg.lstsq(system.T.toarray(), R, rcond=None)
    np.testing.assert_allclose(system.T @ q, R, atol=1e-10)
    # the connector's relative displacement of a rigid-body motion is zero (it has no length)
    np.testing.assert_allclose(system.connectors.D @ R, 0.0, atol=1e-12)
    n_eq = len(system.constraints.equations)
    assert system.n_free == system.n_dof - n_eq - system.constraints.inactive.size
    assert np.linalg.matrix_rank(system.T.toarray()) == system.n_free


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
    assert equation_residual(system) < 1e-12


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
