"""Element matrices: symmetry, rigid-body modes, mass; invariance of a model under rotation."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from bearingfw.analysis import solve_static
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


@settings(max_examples=30, deadline=None)
@given(q=quaternion, shift=point)
def test_a_rotated_and_moved_cantilever_gives_the_rotated_answer(q, shift):
    """Rigidly moving the model (and its loads, orientation vectors) moves the displacements with it."""
    Q = Rotation.from_quat(q).as_matrix()
    n, L = 6, 5.0

    def build(transform, orient):
        nodes = [Node(f"N{k}", *transform(np.array([L * k / n, 0.0, 0.0]))) for k in range(n + 1)]
        elements = [
            FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", SEC, STEEL, orientation=orient, shear_deformation=True)
            for k in range(n)
        ]
        return Model(nodes, elements, supports=[Support("N0")])

    force, moment = np.array([1e3, -2e3, 3e3]), np.array([4e2, -1e2, 2e2])
    ref = solve_static(build(lambda x: x, (0.0, 0.0, 1.0)), [NodalLoad(f"N{n}", *force, *moment)])
    moved = solve_static(
        build(lambda x: Q @ x + np.array(shift), tuple(Q @ [0.0, 0.0, 1.0])),
        [NodalLoad(f"N{n}", *(Q @ force), *(Q @ moment))],
    )
    u_ref = ref.u.reshape(-1, 6)
    u_mov = moved.u.reshape(-1, 6)
    scale = abs(u_ref).max()
    np.testing.assert_allclose(u_mov[:, :3], u_ref[:, :3] @ Q.T, atol=1e-9 * scale)
    np.testing.assert_allclose(u_mov[:, 3:], u_ref[:, 3:] @ Q.T, atol=1e-9 * scale)


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
