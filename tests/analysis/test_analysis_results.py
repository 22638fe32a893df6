"""Section forces and stresses against statics and hand calculations."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import RECT, STEEL, cantilever_model

from bearingfw.analysis import (
    element_stresses,
    gravity,
    principal_stress,
    section_forces,
    section_stresses,
    solve_static,
)
from bearingfw.model import Model, NodalLoad, Node, Section, StressPoint, Support, TrussElement

L = 8.0


def test_cantilever_tip_load_section_forces():
    """Statics of the part beyond a cut: N = Fx, V = F, T = Mx, My = -Fz a, Mz = Fy a (a = arm)."""
    Fx, Fy, Fz, Mx = 1e4, 2e4, -3e4, 5e3
    model = cantilever_model(n=8, L=L)
    res = solve_static(model, [NodalLoad("N8", fx=Fx, fy=Fy, fz=Fz, mx=Mx)])
    forces = section_forces(res.system, res.u)
    for k in range(8):
        for end, x in ((0, L * k / 8), (1, L * (k + 1) / 8)):
            a = L - x
            expected = [Fx, Fy, Fz, Mx, -Fz * a, Fy * a]
            np.testing.assert_allclose(forces[f"E{k}"][end], expected, rtol=1e-9, atol=1e-6)
    assert forces.component("E0", "My", end=0) == pytest.approx(-Fz * L, rel=1e-9)  # P L at the root


def test_self_weight_section_forces_include_the_element_load():
    model = cantilever_model(n=8, L=L)
    res = gravity(model, g=9.81)
    w = STEEL.density * RECT.A * 9.81
    forces = section_forces(res.system, res.u, g=res.g)
    assert forces.component("E0", "My", 0) == pytest.approx(w * L**2 / 2, rel=1e-9)  # hogging at the root
    assert forces.component("E0", "Vz", 0) == pytest.approx(-w * L, rel=1e-9)
    assert forces.component("E3", "My", 1) == pytest.approx(w * (L / 2) ** 2 / 2, rel=1e-9)
    assert abs(forces.component("E7", "My", 1)) < 1e-6 * w * L**2
    # consistent (work-equivalent) gravity loads make the nodal deflection exact: w L^4 / (8 E I)
    assert res.displacement("N8", "uz") == pytest.approx(-w * L**4 / (8 * STEEL.E * RECT.Iy), rel=1e-9)


def test_self_weight_of_a_clamped_clamped_beam_gives_the_fixed_end_moments():
    """Both ends clamped: end moments w L^2 / 12 (hogging), midspan w L^2 / 24, deflection w L^4 / (384 E I)."""
    base = cantilever_model(n=8, L=L)
    model = Model(base.nodes, base.elements, supports=[Support("N0"), Support("N8")])
    res = gravity(model, g=9.81)
    w = STEEL.density * RECT.A * 9.81
    forces = section_forces(res.system, res.u, g=res.g)
    assert forces.component("E0", "My", 0) == pytest.approx(w * L**2 / 12, rel=1e-9)
    assert forces.component("E7", "My", 1) == pytest.approx(w * L**2 / 12, rel=1e-9)
    assert forces.component("E3", "My", 1) == pytest.approx(-w * L**2 / 24, rel=1e-9)
    assert res.displacement("N4", "uz") == pytest.approx(-w * L**4 / (384 * STEEL.E * RECT.Iy), rel=1e-9)


def test_max_principal_stress_at_a_recovery_point_by_hand():
    d = 0.4
    section = Section.circle("tube", d)
    model = cantilever_model(n=4, L=L, section=section)
    Fx, Fy, Fz, Mx = 2e5, 3e4, -5e4, 4e4
    res = solve_static(model, [NodalLoad("N4", fx=Fx, fy=Fy, fz=Fz, mx=Mx)])
    root = section_forces(res.system, res.u, ["E0"])["E0"][0]
    stresses = section_stresses(root, section)
    top = stresses.points.index("top")  # y = 0, z = d / 2
    A, I2, J, r = np.pi * d**2 / 4, np.pi * d**4 / 64, np.pi * d**4 / 32, d / 2
    sigma = Fx / A + (-Fz * L) * r / I2  # N/A + My z / Iy
    # the top lies on the centroidal chord for Vy (Q / (I b) = 4 / (3 A)) and on the extreme
    # fibre for Vz (no shear); torsion T r / J points along -y there
    tau_xy = 4 * Fy / (3 * A) - Mx * r / J
    tau = abs(tau_xy)
    s1 = sigma / 2 + np.sqrt(sigma**2 / 4 + tau**2)
    assert stresses.sigma[top] == pytest.approx(sigma, rel=1e-9)
    assert stresses.tau[top] == pytest.approx(tau, rel=1e-9)
    assert stresses.sigma1[top] == pytest.approx(s1, rel=1e-9)
    # the left point (y = -r) carries the lateral bending: sigma = N/A - Mz y / Iz
    left = stresses.points.index("left")
    assert stresses.sigma[left] == pytest.approx(Fx / A + Fy * L * r / I2, rel=1e-9)
    assert np.all(stresses.sigma1 >= stresses.sigma - 1e-6)
    via_model = element_stresses(res.system, res.u, ["E0"])["E0"]
    np.testing.assert_allclose(via_model.sigma1[0], stresses.sigma1)


def test_torsion_factor_overrides_tr_over_j():
    section = Section(
        "box",
        A=0.1,
        Iy=0.02,
        Iz=0.03,
        J=0.04,
        points=(StressPoint("web", 0.5, 0.0, torsion_factor=12.5), StressPoint("centre", 0.0, 0.0, 12.5)),
    )
    s = section_stresses(np.array([0.0, 0.0, 0.0, 1e3, 0.0, 0.0]), section)
    np.testing.assert_allclose(s.tau, [12.5e3, 12.5e3])
    np.testing.assert_allclose(s.sigma1, [12.5e3, 12.5e3])


def test_principal_stress_of_pure_shear_and_uniaxial():
    assert principal_stress(0.0, 3.0) == pytest.approx(3.0)
    assert principal_stress(-4.0, 0.0) == pytest.approx(0.0)
    assert principal_stress(5.0, 0.0) == pytest.approx(5.0)
    assert principal_stress(0.0, 0.0) == 0.0


def test_principal_stress_keeps_its_precision_under_large_compression():
    """sigma = -1e8 Pa with tau = 1 Pa: sigma_1 = tau^2 / |sigma| (1 + O(tau^2 / sigma^2)) = 1e-8 Pa."""
    np.testing.assert_allclose(principal_stress(-1e8, 1.0), 1e-8, rtol=1e-12)
    np.testing.assert_allclose(principal_stress([-1e8, 1e8], [1.0, 1.0]), [1e-8, 1e8 + 1e-8], rtol=1e-12)


# Torsion of a rectangle long x short (Timoshenko & Goodier, table of sec. 109):
# tau_max = T / (alpha long short^2) at the middle of the long sides; alpha = 0.208 (square),
# 0.246 (2:1); at the middle of the short sides 0.795 tau_max for 2:1 (equal for a square);
# zero at the corners.
@pytest.mark.parametrize(
    "b, h, alpha, short_ratio",
    [(1.0, 1.0, 0.208, 1.0), (1.0, 2.0, 0.246, 0.795), (2.0, 1.0, 0.246, 0.795)],
)
def test_rectangle_torsion_stresses_at_the_default_points_by_hand(b, h, alpha, short_ratio):
    section = Section.rectangle("r", b, h)
    T = 1e3
    s = section_stresses(np.array([0.0, 0.0, 0.0, T, 0.0, 0.0]), section)
    tau = dict(zip(s.points, s.tau, strict=True))
    long, short = max(b, h), min(b, h)
    tau_max = T / (alpha * long * short**2)
    on_long = ("left", "right") if h >= b else ("top", "bottom")
    on_short = ("top", "bottom") if h >= b else ("left", "right")
    for p in on_long:
        assert tau[p] == pytest.approx(tau_max, rel=2e-3)
    for p in on_short:
        assert tau[p] == pytest.approx(short_ratio * tau_max, rel=2e-3)
    for p in ("top-left", "top-right", "bottom-left", "bottom-right"):
        assert tau[p] == 0.0


@pytest.mark.parametrize("b, h", [(1.0, 1.0), (1.0, 2.0)])
def test_rectangle_shear_stresses_at_the_default_points_by_hand(b, h):
    """Q / (I b): 1.5 V / A on the centroidal chord, zero at the extreme fibres."""
    section = Section.rectangle("r", b, h)
    A, V = b * h, 6e4

    def tau(forces):
        s = section_stresses(np.array(forces, dtype=float), section)
        return dict(zip(s.points, s.tau, strict=True))

    vy, vz = tau([0, V, 0, 0, 0, 0]), tau([0, 0, V, 0, 0, 0])
    for p in ("left", "right"):
        assert vz[p] == pytest.approx(1.5 * V / A, rel=1e-12) and vy[p] == 0.0
    for p in ("top", "bottom"):
        assert vy[p] == pytest.approx(1.5 * V / A, rel=1e-12) and vz[p] == 0.0
    for p in ("top-left", "top-right", "bottom-left", "bottom-right"):
        assert vy[p] == 0.0 and vz[p] == 0.0


def test_points_without_factors_keep_the_average_shear_and_t_r_over_j():
    section = Section("s", A=0.2, Iy=0.01, Iz=0.02, J=0.03, Avy=0.1, Avz=0.15, points=(StressPoint("p", 0.3, 0.4),))
    s = section_stresses(np.array([0.0, 2e3, 0.0, 6e2, 0.0, 0.0]), section)
    r = 0.5
    tau_T = 6e2 * r / 0.03
    np.testing.assert_allclose(s.tau, [np.hypot(2e3 / 0.1 - tau_T * 0.4 / r, tau_T * 0.3 / r)], rtol=1e-12)


def test_truss_axial_force():
    A, P = 2e-3, 7e4
    model = Model(
        [Node("a", 0, 0, 0), Node("b", 3.0, 0.0, 4.0)],
        [TrussElement("bar", "a", "b", A, STEEL)],
        supports=[Support("a", ("ux", "uy", "uz")), Support("b", ("uy", "ux"))],
    )
    res = solve_static(model, [NodalLoad("b", fz=P)])
    # the support at b takes the horizontal part; the bar carries P / sin(angle) = P * 5 / 4
    np.testing.assert_allclose(section_forces(res.system, res.u)["bar"][:, 0], [1.25 * P, 1.25 * P], rtol=1e-9)
