"""The compiled recovery of section stresses (:mod:`bearingfw.analysis.stress_kernel`) against the
formulas of :func:`bearingfw.analysis.results.section_stresses` as array expressions: the same bits,
for points off and at the centroid, with and without their own torsion and shear factors, under
compression and tension, for any leading shape of the forces."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw.analysis.results import principal_stress, section_stresses
from bearingfw.model import Section
from bearingfw.model.sections import StressPoint

SECTION = Section(
    "box", A=0.31, Iy=0.052, Iz=0.081, J=0.07, Avy=0.12, Avz=0.16,
    points=(
        StressPoint("top", 0.0, 0.6, torsion_factor=2.5, shear_factor_y=0.0),
        StressPoint("corner", -0.9, -0.4),
        StressPoint("centre", 0.0, 0.0),
        StressPoint("web", 0.45, 0.0, shear_factor_z=7.5),
        StressPoint("axis", 0.0, 0.0, torsion_factor=4.0),
    ),
)  # fmt: skip


def _expressions(forces: np.ndarray, section: Section):
    """The stresses as whole-array operations (how section_stresses computed them before the kernel)."""
    f = np.asarray(forces, dtype=float)[..., None, :]
    N, Vy, Vz, T, My, Mz = (f[..., k] for k in range(6))
    pts = section.points
    y, z = np.array([p.y for p in pts]), np.array([p.z for p in pts])
    r = np.hypot(y, z)

    def factor(field, default):
        given = np.array([np.nan if getattr(p, field) is None else getattr(p, field) for p in pts])
        return np.where(np.isnan(given), default, given)

    tau_T = factor("torsion_factor", r / section.J) * T
    s_y, s_z = factor("shear_factor_y", 1.0 / section.Avy), factor("shear_factor_z", 1.0 / section.Avz)
    safe_r = np.where(r > 0, r, 1.0)
    tau_xy = s_y * Vy - np.where(r > 0, tau_T * z / safe_r, 0.0)
    tau_xz = s_z * Vz + np.where(r > 0, tau_T * y / safe_r, 0.0)
    tau = np.hypot(tau_xy, tau_xz) + np.where(r > 0, 0.0, np.abs(tau_T))
    sigma = N / section.A + My * z / section.Iy - Mz * y / section.Iz
    return sigma, tau, principal_stress(sigma, tau)


@pytest.mark.parametrize("shape", [(6,), (7, 6), (40, 2, 6), (3, 5, 2, 6)])
def test_the_compiled_stresses_are_the_formulas_bit_for_bit(shape):
    rng = np.random.default_rng(sum(shape))
    forces = rng.normal(size=shape) * np.array([4e6, 3e5, 2e5, 1e5, 8e6, 5e6])
    got = section_stresses(forces, SECTION)
    want = _expressions(forces, SECTION)
    assert got.points == ("top", "corner", "centre", "web", "axis")
    for value, expected in zip((got.sigma, got.tau, got.sigma1), want, strict=True):
        assert value.shape == shape[:-1] + (5,)
        assert np.array_equal(value, expected)
    assert (got.sigma < 0).any() and (got.sigma > 0).any()  # both branches of sigma1 ran
    assert np.all(got.sigma1 >= 0)


def test_non_finite_forces_give_what_the_formulas_give():
    forces = np.array([[np.nan, 1e5, 0, 0, 0, 0], [0, 0, 0, np.inf, 0, 0], [-1e300, 1e-300, 0, 0, 0, 0]])
    got = section_stresses(forces, SECTION)
    for value, expected in zip((got.sigma, got.tau, got.sigma1), _expressions(forces, SECTION), strict=True):
        assert np.array_equal(value, expected, equal_nan=True)


def test_forces_without_six_components_are_refused():
    with pytest.raises(ValueError, match=r"forces must have shape \(\.\.\., 6\)"):
        section_stresses(np.zeros((4, 5)), SECTION)
