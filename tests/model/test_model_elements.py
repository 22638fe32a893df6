"""Element matrices: symmetry, rigid-body modes, mass; invariance of a model under rotation."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from bearingfw.analysis import solve_modal, solve_static
from bearingfw.model.assembly import NEAR_VERTICAL, frame_axes
from bearingfw.model import (
    FrameElement,
    Material,
    Model,
    ModelError,
    NodalLoad,
    Node,
    Section,
    Support,
    TrussElement,
    build_system,
)

STEEL = Material("steel", 210e9, density=7850.0, nu=0.3)
SEC = Section("s", A=0.02, Iy=3e-4, Iz=1e-4, J=2e-4, Avy=0.015, Avz=0.016)
point = st.tuples(*[st.floats(-10, 10, allow_nan=False)] * 3)
quaternion = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: np.linalg.norm(q) > 0.1)


def element_matrices(xi, xj, orientation=None, **options):
    model = Model(
        [Node("i", *xi), Node("j", *xj)], [FrameElement("e", "i", "j", SEC, STEEL, orientation=orientation, **options)]
    )
    system = build_system(model)
    return system, system.K.toarray(), system.M.toarray()


@settings(max_examples=60, deadline=None)
@given(xi=point, xj=point, timoshenko=st.booleans(), mass=st.sampled_from(["consistent", "lumped"]))
def test_frame_element_is_symmetric_with_exactly_six_rigid_body_modes(xi, xj, timoshenko, mass):
    L = np.linalg.norm(np.subtract(xj, xi))
    if L < 0.5:
        return
    system, K, M = element_matrices(xi, xj, shear_deformation=timoshenko, mass=mass)
    np.testing.assert_allclose(K, K.T, rtol=0, atol=1e-9 * abs(K).max())
    np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-12 * abs(M).max())
    R = np.column_stack([system.rigid_body(d, about=xi) for d in ("x", "y", "z", "rx", "ry", "rz")])
    assert abs(K @ R).max() < 1e-9 * abs(K).max() * max(L, 1.0)
    eig = np.linalg.eigvalsh(K)
    assert np.sum(np.abs(eig) < 1e-9 * eig.max()) == 6 and eig.min() > -1e-9 * eig.max()
    for d in ("x", "y", "z"):
        r = system.rigid_body(d)
        assert r @ M @ r == pytest.approx(STEEL.density * SEC.A * L, rel=1e-12)


def test_truss_mass_and_stiffness():
    model = Model([Node("i", 0, 0, 0), Node("j", 3, 4, 0)], [TrussElement("t", "i", "j", 1e-3, STEEL, added_mass=2.0)])
    system = build_system(model)
    r = system.rigid_body("y")
    assert r @ system.M @ r == pytest.approx((STEEL.density * 1e-3 + 2.0) * 5.0)
    assert abs(system.K @ r).max() < 1e-6
    assert np.linalg.matrix_rank(system.K.toarray()) == 1


def cantilever_response(transform, orient, load_rotation):
    """Tip displacements of a clamped member along ``transform`` of the x axis under a rotated tip load."""
    n, L = 6, 5.0
    nodes = [Node(f"N{k}", *transform(np.array([L * k / n, 0.0, 0.0]))) for k in range(n + 1)]
    elements = [
        FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", SEC, STEEL, orientation=orient, shear_deformation=True)
        for k in range(n)
    ]
    force, moment = np.array([1e3, -2e3, 3e3]), np.array([4e2, -1e2, 2e2])
    res = solve_static(
        Model(nodes, elements, supports=[Support("N0")]),
        [NodalLoad(f"N{n}", *(load_rotation @ force), *(load_rotation @ moment))],
    )
    return res.u.reshape(-1, 6)


def assert_rotated(u_mov, u_ref, Q):
    scale = abs(u_ref).max()
    np.testing.assert_allclose(u_mov[:, :3], u_ref[:, :3] @ Q.T, atol=1e-9 * scale)
    np.testing.assert_allclose(u_mov[:, 3:], u_ref[:, 3:] @ Q.T, atol=1e-9 * scale)


@settings(max_examples=30, deadline=None)
@given(q=quaternion, shift=point)
def test_a_rotated_and_moved_cantilever_gives_the_rotated_answer(q, shift):
    """Rigidly moving the model (and its loads, orientation vectors) moves the displacements with it."""
    Q = Rotation.from_quat(q).as_matrix()
    ref = cantilever_response(lambda x: x, (0.0, 0.0, 1.0), np.eye(3))
    moved = cantilever_response(lambda x: Q @ x + np.array(shift), tuple(Q @ [0.0, 0.0, 1.0]), Q)
    assert_rotated(moved, ref, Q)


@settings(max_examples=30, deadline=None)
@given(angle=st.floats(-np.pi, np.pi), shift=point, slope=st.floats(-1.2, 1.2))
def test_default_orientation_turns_with_the_model_about_the_vertical(angle, shift, slope):
    """Default axes (v = Z) are invariant under a rotation about Z: a sloping member turned about
    the vertical, without an orientation vector, gives the turned answer."""
    Q = Rotation.from_euler("z", angle).as_matrix()
    S = Rotation.from_euler("y", -slope).as_matrix()  # the member rises at the given slope
    ref = cantilever_response(lambda x: S @ x, None, S)
    moved = cantilever_response(lambda x: Q @ S @ x + np.array(shift), None, Q @ S)
    assert_rotated(moved, ref, Q)


@pytest.mark.parametrize("lean", [(1e-4, 0.0), (0.0, 1e-4), (-3e-4, 2e-4)])
def test_default_orientation_of_a_pier_does_not_jump_with_a_tiny_lean(lean):
    """A vertical cantilever and the same leaning by ~1e-4 rad answer alike (to the lean)."""
    up = Rotation.from_euler("y", -np.pi / 2).as_matrix()  # x axis -> +Z
    ref = cantilever_response(lambda x: up @ x, None, up)
    tilt = Rotation.from_rotvec([-lean[1], lean[0], 0.0]).as_matrix()
    moved = cantilever_response(lambda x: tilt @ up @ x, None, tilt @ up)
    scale = abs(ref).max()
    np.testing.assert_allclose(moved, ref, atol=10 * max(map(abs, lean)) * scale)


def default_axes(*axes):
    """Local axes (rows x, y, z) of members from the origin along each of ``axes`` (default orientation)."""
    xj = np.array(axes, dtype=float)
    return frame_axes(np.zeros_like(xj), xj, np.full(xj.shape, np.nan))


def test_default_axes_of_horizontal_members():
    along_x, along_y, skew = default_axes((5, 0, 0), (0, 5, 0), (3, 4, 0))
    np.testing.assert_allclose(along_x, np.eye(3), atol=1e-15)  # y = Y, z = Z
    np.testing.assert_allclose(along_y, [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-15)  # y = -X
    np.testing.assert_allclose(skew[2], [0, 0, 1], atol=1e-15)  # z vertical up for any horizontal member


def test_default_axes_of_vertical_members():
    up, down = default_axes((0, 0, 6), (0, 0, -6))
    np.testing.assert_allclose(up, [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-15)  # y = Y, z = -X
    np.testing.assert_allclose(down, [[0, 0, -1], [0, -1, 0], [-1, 0, 0]], atol=1e-15)  # y = -Y, z = -X


@pytest.mark.parametrize("tilt", [1e-8, 1e-6, 1e-4, 0.9 * NEAR_VERTICAL])
@pytest.mark.parametrize("direction", [(1, 0), (0, 1), (-1, 0), (0, -1), (0.6, -0.8)])
def test_default_axes_of_a_slightly_tilted_member_stay_within_the_tilt_of_the_vertical_ones(tilt, direction):
    """Before: tilted by more than 1e-6 in y, local y jumped by 90 degrees (v = Z was used)."""
    (vertical,) = default_axes((0, 0, 6))
    (tilted,) = default_axes((6 * tilt * direction[0], 6 * tilt * direction[1], 6))
    assert np.abs(tilted - vertical).max() <= 1.01 * tilt


def test_beyond_near_vertical_the_horizontal_rule_applies():
    (member,) = default_axes((0, 6 * 2 * NEAR_VERTICAL, 6))  # leaning towards +Y
    np.testing.assert_allclose(member[1], [-1, 0, 0], atol=1e-6)  # y = Z x x / |.| = -X


def test_a_pier_leaning_slightly_either_way_has_the_vertical_piers_modes():
    """A 1 x 2 pier: its two bending modes differ; a tiny lean must not swap them."""
    section = Section.rectangle("pier", 1.0, 2.0)

    def pier(dx, dy, n=6):
        nodes = [Node(f"N{k}", dx * k / n, dy * k / n, 6.0 * k / n) for k in range(n + 1)]
        elements = [FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", section, STEEL) for k in range(n)]
        return Model(nodes, elements, supports=[Support("N0")])

    def modes(model):
        res = solve_modal(model, 2)
        return res.frequencies, [abs(res.participation["x"][m]) > abs(res.participation["y"][m]) for m in range(2)]

    f0, along_x0 = modes(pier(0.0, 0.0))
    for dx, dy in ((1e-3, 0.0), (0.0, 1e-3)):
        f, along_x = modes(pier(dx, dy))
        np.testing.assert_allclose(f, f0, rtol=1e-6)
        assert along_x == along_x0


def test_rectangle_and_circle_sections():
    square = Section.rectangle("sq", 1.0, 1.0)
    assert square.J == pytest.approx(0.1406, rel=2e-3)  # exact St-Venant value 0.1406 a^4
    wide = Section.rectangle("wide", 2.0, 1.0)
    assert wide.J == pytest.approx(0.2287 * 2.0, rel=2e-3)  # exact 0.229 a b^3 for a = 2b
    assert wide.Iy == pytest.approx(2.0 / 12) and wide.Iz == pytest.approx(8.0 / 12)
    assert {p.name for p in wide.points} >= {"top-left", "bottom-right", "top"}
    disc = Section.circle("d", 0.5)
    assert disc.J == pytest.approx(np.pi * 0.5**4 / 32) and disc.Avy == pytest.approx(0.9 * disc.A)
    with pytest.raises(ModelError, match="must be > 0"):
        Section.rectangle("bad", -1.0, 1.0)
