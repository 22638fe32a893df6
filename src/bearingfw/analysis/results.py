"""Element results: section forces at member ends and stresses at recovery points.

Section forces (local axes of the element, :mod:`bearingfw.model.elements`) are the stress
resultants on a cut, acting on the part with smaller local x from the part with larger x::

    N = int sigma dA          (tension positive)
    Vy = int tau_xy dA,  Vz = int tau_xz dA
    T = int (y tau_xz - z tau_xy) dA
    My = int z sigma dA,  Mz = -int y sigma dA

so a positive ``My`` stretches the fibres at ``z > 0`` and a positive ``Mz`` those at ``y < 0``.
From the element end forces ``F = k_local u_local - f_local`` (``f_local`` the element's
share of the gravity load, so that a member carrying its own weight is right) the section at
end i is ``-F[0:6]`` and at end j ``+F[6:12]``. Member inertia within the element is not
included (only end values are recovered).

Stresses at a recovery point ``(y, z)`` of the section (:class:`~bearingfw.model.StressPoint`)::

    sigma = N / A + My z / Iy - Mz y / Iz
    tau_xy = s_y Vy - tau_T * z / r,   tau_xz = s_z Vz + tau_T * y / r,   tau = |(tau_xy, tau_xz)|
    sigma_1 = sigma / 2 + sqrt((sigma / 2)^2 + tau^2)      (maximum principal stress)

with the point's factors where given: ``tau_T = torsion_factor * T`` (else ``T r / J``, exact for
circles only), ``s_y = shear_factor_y`` and ``s_z = shear_factor_z`` (else the average ``1 / Avy``,
``1 / Avz``, or ``1 / A`` without shear areas). ``r`` is the distance from the centroid; the
torsional shear acts perpendicular to the radius; at the centroid a given ``torsion_factor``
adds ``|tau_T|`` to ``tau``. The default points of ``Section.rectangle`` and ``Section.circle``
carry their factors (e.g. zero shear at a rectangle's corners).
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np

from bearingfw.model import FrameElement, ModelError, Section, System

__all__ = [
    "SECTION_COMPONENTS",
    "SectionForces",
    "Stresses",
    "section_forces",
    "section_stresses",
    "element_stresses",
    "principal_stress",
]

SECTION_COMPONENTS = ("N", "Vy", "Vz", "T", "My", "Mz")


@attrs.frozen(eq=False)
class SectionForces:
    """``values[e, end, c]``: element ``names[e]``, end 0 (i) or 1 (j), component ``SECTION_COMPONENTS[c]``."""

    names: tuple[str, ...]
    values: np.ndarray

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.values[self.names.index(name)]
        except ValueError:
            raise KeyError(f"no section forces for element {name!r}") from None

    def component(self, name: str, component: str, end: int = 0) -> float:
        return float(self[name][end, SECTION_COMPONENTS.index(component)])


def section_forces(
    system: System, u: np.ndarray, elements: Sequence[str] | None = None, *, g: float = 0.0
) -> SectionForces:
    """Section forces at both ends of the named elements (default: all) for full displacements ``u``.

    ``g`` is the gravity the displacements were computed with (the member's own weight is then
    subtracted as an element load). Truss bars have ``N`` only.
    """
    model = system.model
    names = tuple(e.name for e in model.elements) if elements is None else tuple(elements)
    positions = np.array([model.element_index(n) for n in names], dtype=int)
    out = np.zeros((len(names), 2, 6))
    frames, trusses = system.frames, system.trusses
    frame_row = {int(k): r for r, k in enumerate(frames.index)}
    truss_row = {int(k): r for r, k in enumerate(trusses.index)}
    fr = np.array([frame_row[p] for p in positions if p in frame_row], dtype=int)
    at_f = np.array([k for k, p in enumerate(positions) if p in frame_row], dtype=int)
    if fr.size:
        lam = frames.transform()[fr]
        u_local = np.einsum("nij,nj->ni", lam, u[frames.dofs[fr]])
        F = np.einsum("nij,nj->ni", frames.k_local[fr], u_local) - g * frames.weight_local[fr]
        out[at_f, 0] = -F[:, :6]
        out[at_f, 1] = F[:, 6:]
    tr = np.array([truss_row[p] for p in positions if p in truss_row], dtype=int)
    at_t = np.array([k for k, p in enumerate(positions) if p in truss_row], dtype=int)
    if tr.size:
        ut = u[trusses.dofs[tr]]
        elongation = np.einsum("ni,ni->n", trusses.e[tr], ut[:, 3:] - ut[:, :3])
        N = trusses.EA[tr] / trusses.L[tr] * elongation
        out[at_t, :, 0] = N[:, None]
    return SectionForces(names, out)


@attrs.frozen(eq=False)
class Stresses:
    """Stresses at a section's recovery points: arrays of shape ``forces.shape[:-1] + (n_points,)``."""

    points: tuple[str, ...]
    sigma: np.ndarray
    tau: np.ndarray
    sigma1: np.ndarray


def principal_stress(sigma, tau):
    """Maximum principal stress of a plane state with normal ``sigma`` and shear ``tau``.

    ``sigma / 2 + sqrt((sigma / 2)^2 + tau^2)``; for ``sigma < 0`` the equal form
    ``tau^2 / (sqrt((sigma / 2)^2 + tau^2) - sigma / 2)``, which does not cancel (a large
    compression with a little shear gives a small positive stress, not round-off).
    """
    half = np.asarray(sigma, dtype=float) / 2
    tau = np.asarray(tau, dtype=float)
    radius = np.hypot(half, tau)
    below = radius - half  # > 0 where half < 0 (both terms add), so the division is safe there
    safe = np.where(half < 0, below, 1.0)
    return np.where(half < 0, tau**2 / safe, half + radius)


def _point_factor(points, field: str, default: np.ndarray) -> np.ndarray:
    """A per-point factor of the section's recovery points, ``default`` where a point gives none."""
    given = np.array([np.nan if getattr(p, field) is None else getattr(p, field) for p in points])
    return np.where(np.isnan(given), default, given)


def section_stresses(forces: np.ndarray, section: Section) -> Stresses:
    """Stresses from section forces ``(..., 6)`` (``SECTION_COMPONENTS`` order) at ``section.points``."""
    if not section.points:
        raise ModelError(f"section {section.name!r} has no recovery points")
    f = np.asarray(forces, dtype=float)
    if f.shape[-1:] != (6,):
        raise ValueError(f"section_stresses: forces must have shape (..., 6), got {f.shape}")
    points = section.points
    y = np.array([p.y for p in points], dtype=float)
    z = np.array([p.z for p in points], dtype=float)
    r = np.hypot(y, z)
    torsion = _point_factor(points, "torsion_factor", r / section.J)
    s_y = _point_factor(points, "shear_factor_y", 1.0 / (section.Avy if section.Avy is not None else section.A))
    s_z = _point_factor(points, "shear_factor_z", 1.0 / (section.Avz if section.Avz is not None else section.A))
    # per point: tau_T = torsion T; tau_xy = s_y Vy - tau_T z / r, tau_xz = s_z Vz + tau_T y / r (at r = 0,
    # |tau_T| adds to the shear instead); sigma = N / A + My z / Iy - Mz y / Iz; sigma1 by principal_stress
    flat = np.ascontiguousarray(f.reshape(-1, 6))
    sigma, tau, sigma1 = (np.empty((flat.shape[0], len(points))) for _ in range(3))
    _stress_kernel().point_stresses(flat, y, z, r, torsion, s_y, s_z, float(section.A), float(section.Iy),
                                    float(section.Iz), sigma, tau, sigma1)  # fmt: skip
    shape = f.shape[:-1] + (len(points),)
    return Stresses(tuple(p.name for p in points), sigma.reshape(shape), tau.reshape(shape), sigma1.reshape(shape))


def _stress_kernel():
    """:mod:`bearingfw.analysis.stress_kernel`, imported at the first use (it imports numba)."""
    from bearingfw.analysis import stress_kernel

    return stress_kernel


def element_stresses(
    system: System, u: np.ndarray, elements: Sequence[str] | None = None, *, g: float = 0.0
) -> dict[str, Stresses]:
    """Stresses at both ends of named frame elements (default: all frames with recovery points)."""
    model = system.model
    if elements is None:
        elements = [e.name for e in model.elements if isinstance(e, FrameElement) and e.section.points]
    forces = section_forces(system, u, elements, g=g)
    out = {}
    for name in elements:
        e = model.element(name)
        if not isinstance(e, FrameElement):
            raise ModelError(f"element {name!r} is not a frame element; use section_forces for its axial force")
        out[name] = section_stresses(forces[name], e.section)
    return out
