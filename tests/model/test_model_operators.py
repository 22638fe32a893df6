"""The connector operators D, B, V and the grouping of connectors by law."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bearingfw.model import Connector, Model, ModelError, Node, axes_from_rotation, build_system, connector_frame

unit = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.2)
up = unit.map(lambda v: (v[0], v[1], abs(v[2]) + 0.1))  # a connector's z axis points up


def bearings(specs):
    """Pairs of coincident nodes P{k} (support side) / S{k} (girder side), one connector each."""
    nodes, cons = [], []
    for k, spec in enumerate(specs):
        nodes += [Node(f"P{k}", 3.0 * k, 0, 0), Node(f"S{k}", 3.0 * k, 0, 0)]
        cons.append(Connector(f"c{k}", f"P{k}", f"S{k}", **spec))
    return Model(nodes, connectors=cons)


@settings(max_examples=40, deadline=None)
@given(
    x_axis=unit, z_axis=up, guided=st.sampled_from(["x", "y"]), u=arrays(np.float64, 24, elements=st.floats(-1, 1))
)
def test_operators_give_relative_displacements_in_the_local_frame(x_axis, z_axis, guided, u):
    if abs(np.dot(x_axis, z_axis)) > 0.95 * np.linalg.norm(x_axis) * np.linalg.norm(z_axis):
        return
    spring = dict(law="linear-spring", law_params={"k": 1e8}, vertical_stiffness=2e9, x_axis=x_axis, z_axis=z_axis)
    model = bearings([dict(kind="planar", **spring), dict(kind="axial", guided=guided, **spring)])
    ops = build_system(model).connectors
    R = connector_frame(x_axis, z_axis)
    d = [R @ (u[6 * (2 * k + 1) : 6 * (2 * k + 1) + 3] - u[12 * k : 12 * k + 3]) for k in range(2)]
    np.testing.assert_allclose(ops.D @ u, np.concatenate(d), atol=1e-12)
    planar, axial = ops.split(ops.B @ u)
    np.testing.assert_allclose(planar[0], d[0][:2], atol=1e-12)
    np.testing.assert_allclose(axial[0], d[1][[0 if guided == "x" else 1]], atol=1e-12)
    np.testing.assert_allclose(ops.V @ u, [d[0][2], d[1][2]], atol=1e-12)
    np.testing.assert_allclose(ops.normal_forces(ops.V @ u), [-2e9 * d[0][2], -2e9 * d[1][2]], rtol=1e-12, atol=1e-3)


def test_frame_from_a_rotation_matrix():
    c = np.cos(0.3)
    s = np.sin(0.3)
    R = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # a bearing skewed by 0.3 rad
    con = Connector("skew", "P0", "S0", "planar", law="frictionless", vertical_stiffness=1e9, **axes_from_rotation(R))
    np.testing.assert_allclose(con.rotation, R, atol=1e-15)
    with pytest.raises(ModelError, match="proper 3x3 rotation"):
        axes_from_rotation(np.diag([1.0, 1.0, -1.0]))


def test_connectors_of_a_per_bearing_law_share_one_law_object_per_dims():
    """linear-spring declares per_bearing: one object per dims, k an array where it differs
    (tests/model/test_model_grouping.py: laws without per_bearing keep one object per parameter set)."""
    s = dict(vertical_stiffness=1e9)
    model = bearings(
        [
            dict(kind="planar", law="linear-spring", law_params={"k": 1e8}, **s),
            dict(kind="join"),
            dict(kind="planar", law="linear-spring", law_params={"k": 2e8}, **s),
            dict(kind="planar", law="linear-spring", law_params={"k": 1e8}, **s),
            dict(kind="axial", law="linear-spring", law_params={"k": 1e8}, **s),
            dict(kind="planar", law="fixed", **s),
        ]
    )
    ops = build_system(model).connectors
    groups = [(g.law.name, np.asarray(g.law.k).tolist(), g.dims, g.connectors.tolist()) for g in ops.groups]
    assert groups == [("linear-spring", [1e8, 2e8, 1e8], 2, [0, 2, 3]), ("linear-spring", 1e8, 1, [4])]
    assert isinstance(ops.groups[1].law.k, float)  # equal over the group: a scalar, as before
    assert [(g.rows.start, g.rows.stop) for g in ops.groups] == [(0, 6), (6, 7)]
    # springs: every non-JOIN connector; N of a group's connectors comes from its spring rows
    assert ops.spring_connectors.tolist() == [0, 2, 3, 4, 5]
    assert ops.groups[0].springs.tolist() == [0, 1, 2]
    # the fixed law ties connector 5's horizontal directions, the JOIN all three of connector 1
    assert sorted(ops.ties) == [(1, 0), (1, 1), (1, 2), (4, 1), (5, 0), (5, 1)]


def test_law_forces_and_tangents_assemble_through_B():
    """Energy check: u^T B^T K_t B u = sum k |d_governed|^2 and B^T f is the gradient."""
    s = dict(vertical_stiffness=1e9, law="linear-spring")
    model = bearings(
        [
            dict(kind="planar", law_params={"k": 1e8}, x_axis=(1, 1, 0), **s),
            dict(kind="axial", guided="y", law_params={"k": 3e8}, **s),
        ]
    )
    system = build_system(model)
    ops = system.connectors
    rng = np.random.default_rng(0)
    u = rng.normal(size=system.n_dof)
    d = ops.B @ u
    responses = ops.respond(ops.initial_states(), d, ops.normal_forces(ops.V @ u), 0.01)
    Kt = ops.tangent(responses)
    expected = 1e8 * np.sum(d[:2] ** 2) + 3e8 * d[2] ** 2
    assert u @ (ops.B.T @ Kt @ ops.B) @ u == pytest.approx(expected, rel=1e-12)
    np.testing.assert_allclose(ops.B.T @ ops.forces(responses), ops.B.T @ Kt @ ops.B @ u, rtol=1e-12)


def test_assembled_tangent_is_the_derivative_of_the_assembled_force():
    """With two planar friction bearings slipping (a full 2x2 tangent), B^T K_t B = d(B^T f)/du."""
    law = dict(law="regularized-coulomb", law_params={"k": 1e8, "mu": 0.05}, vertical_stiffness=1e9)
    model = bearings([dict(kind="planar", x_axis=(1, 0.4, 0), **law), dict(kind="planar", **law)])
    ops = build_system(model).connectors
    rng = np.random.default_rng(1)
    u = rng.normal(scale=5e-2, size=24)  # ~5 cm: far beyond the stick limit mu N / k = 1.5 mm
    N = np.array([2e6, 3e6])
    states = ops.initial_states()

    def force(v):
        return ops.B.T @ ops.forces(ops.respond(states, ops.B @ v, N, 0.01))

    responses = ops.respond(states, ops.B @ u, N, 0.01)
    (forces,) = ops.split(ops.forces(responses))
    np.testing.assert_allclose(np.linalg.norm(forces, axis=1), 0.05 * N, rtol=1e-12)  # both slipping
    K = (ops.B.T @ ops.tangent(responses) @ ops.B).toarray()
    for _ in range(5):
        e = rng.normal(size=24)
        h = 1e-7
        fd = (force(u + h * e) - force(u - h * e)) / (2 * h)
        np.testing.assert_allclose(K @ e, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())
    assert abs(K - K.T).max() < 1e-9 * abs(K).max()


def test_uplift_reaches_the_law_as_zero_normal_force():
    """A friction bearing lifted off (N < 0) has no capacity: the protocol's N is >= 0."""
    law = dict(law="regularized-coulomb", law_params={"k": 1e8, "mu": 0.05}, vertical_stiffness=1e9)
    ops = build_system(bearings([dict(kind="planar", **law)])).connectors
    u = np.zeros(12)
    u[6:8] = [1e-3, 0.0]  # girder side moves 1 mm along x
    u[8] = 1e-4  # and lifts: N = -1e9 * 1e-4 < 0
    N = ops.normal_forces(ops.V @ u)
    assert N[0] == pytest.approx(-1e5)
    (response,) = ops.respond(ops.initial_states(), ops.B @ u, N, 0.01)
    np.testing.assert_allclose(response.force, 0.0)
