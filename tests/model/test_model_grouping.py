"""Law groups (per-bearing laws in one object), the uplift connectors' gap rows, the operators'
velocity and dF/dN helpers."""

from __future__ import annotations

import contextlib
import importlib.metadata as metadata
import sys
import types
from typing import ClassVar

import attrs
import numpy as np
import pytest

import bearingfw
from bearingfw.model import Connector, Model, ModelError, Node, build_system
from bearingfw.model.connectors import CompressionOnlyGap
from bearingfw.parameters import check_per_bearing, choice
from bearingfw.plugins import load_registry


@attrs.frozen
class PlainSpring:
    """F = k u, without per_bearing: one object per parameter set."""

    name: ClassVar[str] = "test-plain-spring"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return None

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        tangent = self.k * np.broadcast_to(np.eye(self.dims), (len(u), self.dims, self.dims))
        return bearingfw.LawResponse(self.k * u, tangent, state)


@attrs.frozen
class ShapedSpring:
    """A per-bearing spring with a non-numeric parameter: F = k u (``shape`` only splits groups)."""

    name: ClassVar[str] = "test-shaped-spring"
    rigid: ClassVar[bool] = False
    per_bearing: ClassVar[bool] = True
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m", per_bearing=True)
    c: float = bearingfw.parameter(low=0.0, default=0.0, unit="N s/m", per_bearing=True)
    shape: str = choice(("round", "square"), default="round")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        check_per_bearing(self, n)
        return None

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        check_per_bearing(self, u.shape[0])
        k = np.asarray(self.k, dtype=float)
        tangent = k.reshape(-1, 1, 1) * np.broadcast_to(np.eye(self.dims), (len(u), self.dims, self.dims))
        return bearingfw.LawResponse(k[..., None] * u, tangent, state)


@contextlib.contextmanager
def registry_with(*laws):
    module_name = "bearingfw_grouping_test_plugin"
    module = types.ModuleType(module_name)

    @bearingfw.hookimpl
    def bearingfw_register_laws():
        return list(laws)

    module.bearingfw_register_laws = bearingfw_register_laws
    sys.modules[module_name] = module
    eps = [*metadata.entry_points(group="bearingfw"), metadata.EntryPoint("grouping-test", module_name, "bearingfw")]
    try:
        yield load_registry(eps)
    finally:
        sys.modules.pop(module_name, None)


@pytest.fixture(scope="module")
def laws():
    with registry_with(PlainSpring, ShapedSpring) as registry:
        yield registry


def bearings(specs):
    nodes, cons = [], []
    for k, spec in enumerate(specs):
        nodes += [Node(f"P{k}", 3.0 * k, 0, 0), Node(f"S{k}", 3.0 * k, 0, 0)]
        cons.append(Connector(f"c{k}", f"P{k}", f"S{k}", **spec))
    return Model(nodes, connectors=cons)


def law(name, **params):
    return dict(law=name, law_params=params, vertical_stiffness=1e9)


def test_a_law_without_per_bearing_gets_one_object_per_parameter_set(laws):
    model = bearings(
        [
            dict(kind="planar", **law("test-plain-spring", k=1e8)),
            dict(kind="join"),
            dict(kind="planar", **law("test-plain-spring", k=2e8)),
            dict(kind="planar", **law("test-plain-spring", k=1e8)),
            dict(kind="axial", **law("test-plain-spring", k=1e8)),
        ]
    )
    ops = build_system(model, laws).connectors
    groups = [(g.law.k, g.dims, g.connectors.tolist()) for g in ops.groups]
    assert groups == [(1e8, 2, [0, 3]), (2e8, 2, [2]), (1e8, 1, [4])]
    assert [(g.rows.start, g.rows.stop) for g in ops.groups] == [(0, 4), (4, 6), (6, 7)]
    assert ops.groups[0].springs.tolist() == [0, 2]


def test_a_per_bearing_law_gets_one_object_per_dims_and_non_numeric_parameters(laws):
    model = bearings(
        [
            dict(kind="planar", **law("test-shaped-spring", k=1e8, c=5.0)),
            dict(kind="planar", **law("test-plain-spring", k=1e8)),
            dict(kind="planar", **law("test-shaped-spring", k=3e8, c=5.0)),
            dict(kind="axial", **law("test-shaped-spring", k=1e8)),
            dict(kind="planar", **law("test-shaped-spring", k=2e8, c=5, shape="square")),
            dict(kind="planar", **law("test-shaped-spring", k=2e8, c=5.0)),
        ]
    )
    ops = build_system(model, laws).connectors
    shaped = [g for g in ops.groups if g.law.name == "test-shaped-spring"]
    assert [(g.dims, g.law.shape, g.connectors.tolist()) for g in shaped] == [
        (2, "round", [0, 2, 5]), (2, "square", [4]), (1, "round", [3])
    ]
    first = shaped[0].law
    # differing values: a read-only float array in connector order; equal ones stay a float
    assert isinstance(first.k, np.ndarray) and first.k.tolist() == [1e8, 3e8, 2e8] and not first.k.flags.writeable
    assert isinstance(first.c, float) and first.c == 5.0
    assert isinstance(shaped[1].law.k, float)
    # rows of B: group after group, connector-major
    assert [(g.rows.start, g.rows.stop) for g in ops.groups] == [(0, 6), (6, 8), (8, 10), (10, 11)]
    # one call answers for all the group's connectors, as separate objects would
    u = np.random.default_rng(2).normal(size=(3, 2))
    grouped = first.respond(None, u, np.ones(3), 0.01).force
    single = [ShapedSpring(k=k, c=5.0, dims=2).respond(None, u[i : i + 1], np.ones(1), 0.01).force[0]
              for i, k in enumerate([1e8, 3e8, 2e8])]
    np.testing.assert_array_equal(grouped, single)


def test_per_bearing_parameters_are_checked_per_connector(laws):
    bad = bearings([dict(kind="planar", **law("test-shaped-spring", k=1e8)),
                    dict(kind="planar", **law("test-shaped-spring", k=-1.0))])
    with pytest.raises(ModelError, match=r"connector 'c1': field 'law_params': .*'k' = -1.0 .*k > 0"):
        build_system(bad, laws)
    many = bearings([dict(kind="planar", **law("test-shaped-spring", k=(1e8, 2e8)))])
    with pytest.raises(ModelError, match=r"connector 'c0': .*'k' of law 'test-shaped-spring' must be one number per"):
        build_system(many, laws)


# --- uplift --------------------------------------------------------------------------------------
def test_uplift_is_for_planar_and_axial_connectors_only():
    with pytest.raises(ModelError, match=r"connector 'j': field 'uplift' applies to PLANAR and AXIAL .* JOIN"):
        Connector("j", "a", "b", "join", uplift=True)
    with pytest.raises(ModelError, match=r"connector 'p': field 'uplift' must be True or False, got 'yes'"):
        Connector("p", "a", "b", "planar", law="frictionless", vertical_stiffness=1e9, uplift="yes")
    assert Connector("p", "a", "b", "axial", law="frictionless", vertical_stiffness=1e9, uplift=True).uplift is True


def test_uplift_springs_leave_K_and_become_gap_rows_of_B():
    """An uplift connector's vertical spring is out of K and its e_z row is the last rows of B,
    governed by the gap law; K plus the gap's closed stiffness is the K of uplift=False."""
    specs = [
        dict(kind="planar", **law("linear-spring", k=1e8)),
        dict(kind="axial", **law("linear-spring", k=1e8)),
        dict(kind="join"),
        dict(kind="planar", **law("frictionless")),
    ]
    plain = build_system(bearings(specs))
    lifting = build_system(bearings([{**s, "uplift": True} if s["kind"] != "join" and k != 1 else s
                                     for k, s in enumerate(specs)]))
    ops = lifting.connectors
    assert ops.uplift.tolist() == [True, False, True]  # per spring row (connectors 0, 1, 3)
    gap = ops.gap_group
    assert gap.gap and gap.connectors.tolist() == [0, 3] and gap.springs.tolist() == [0, 2]
    assert ops.gap_rows.tolist() == [5, 6] and ops.governed[5:] == ((0, 2), (3, 2))
    np.testing.assert_array_equal(ops.B[:5].toarray(), plain.connectors.B.toarray())
    np.testing.assert_array_equal(ops.B[5:].toarray(), ops.V[[0, 2]].toarray())
    B_gap = ops.B[5:]
    closed = lifting.K + B_gap.T @ B_gap * 1e9
    assert abs(closed - plain.K).max() <= 1e-6 * abs(plain.K).max()
    # without uplift nothing changes: no gap group
    assert plain.connectors.gap_group is None and plain.connectors.gap_rows.size == 0


def test_the_gap_law_is_compression_only_on_the_total_vertical_displacement():
    gap = CompressionOnlyGap(np.array([1e9, 2e9, 3e9]))
    r = gap.respond(None, np.array([[-1e-3], [0.0], [2e-3]]), np.zeros(3), 0.01)
    np.testing.assert_array_equal(r.force[:, 0], [-1e6, 0.0, 0.0])  # compression: F = kv d_z < 0, N = -F > 0
    np.testing.assert_array_equal(r.tangent[:, 0, 0], [1e9, 2e9, 0.0])  # closed at d_z = 0


# --- operators: the velocity term of the tangent, dF/dN ---------------------------------------------
def test_tangent_blocks_add_the_velocity_term_and_normal_derivatives_vanish_without_contact():
    model = bearings([dict(kind="planar", **law("regularized-coulomb", k=1e8, mu=0.1)),
                      dict(kind="axial", **law("regularized-coulomb", k=1e8, mu=0.1))])
    ops = build_system(model).connectors
    assert [g.coupling for g in ops.groups] == [True, True] and ops.any_coupling and not ops.any_velocity
    d = np.array([1e-2, 2e-2, -3e-2])  # far beyond stick: both slide
    N = np.array([1e6, -1e5])  # the second lifted (N < 0: no contact)
    responses = ops.respond(ops.initial_states(), d, N, 0.01)
    rows, springs, values = ops.normal_derivatives(responses, N)
    assert rows.tolist() == [0, 1, 2] and springs.tolist() == [0, 0, 1]
    np.testing.assert_allclose(values[:2], 0.1 * d[:2] / np.linalg.norm(d[:2]), rtol=1e-12)
    assert values[2] == 0.0  # lifted: the clamp max(N, 0) holds N at zero
    # no law uses the velocity: the rate changes nothing
    for a, b in zip(ops.tangent_blocks(responses, 50.0), ops.tangent_blocks(responses), strict=True):
        np.testing.assert_array_equal(a, b)
