"""Cross-sections of the reference bridge: the girder line, a T of its web and half the slab.

Section axes follow :mod:`bearingfw.model.sections`: for a horizontal member local z is up, so
``Iy`` governs vertical bending and ``Iz`` bending in the deck's plane.

T-section: flange ``b_f x t_f`` on a web ``b_w x (h - t_f)``; centroid ``c`` above the soffit::

    A = b_f t_f + b_w (h - t_f)
    c = (b_f t_f (h - t_f / 2) + b_w (h - t_f)^2 / 2) / A
    Iy = sum(b d^3 / 12 + b d (z_i - c)^2)        Iz = t_f b_f^3 / 12 + (h - t_f) b_w^3 / 12

and the St-Venant constant of its two rectangles (the kernel's rectangle formula).

The deck's cross-section is kept rigid by rigid links between the girder lines
(:mod:`bearingfw.bridges.reference`), so the slab and crossbars need no members of their own.
"""

from __future__ import annotations

import attrs

from bearingfw.bridges.parameters import BridgeParameters
from bearingfw.model import Section, StressPoint

__all__ = ["TeeGeometry", "arch_section", "box", "girder_geometry", "girder_section", "tee"]


@attrs.frozen
class TeeGeometry:
    """A T-section: flange on top of a web, ``depth`` from the flange top to the soffit (m)."""

    flange_width: float
    flange_thickness: float
    web_width: float
    depth: float

    @property
    def parts(self) -> tuple[tuple[float, float, float], ...]:
        """(width, height, centroid height above the soffit) of the flange and of the web."""
        tf, h = self.flange_thickness, self.depth
        return ((self.flange_width, tf, h - tf / 2), (self.web_width, h - tf, (h - tf) / 2))

    @property
    def area(self) -> float:
        return sum(b * d for b, d, _ in self.parts)

    @property
    def centroid(self) -> float:
        """Height of the centroid above the soffit."""
        return sum(b * d * z for b, d, z in self.parts) / self.area

    @property
    def Iy(self) -> float:
        c = self.centroid
        return sum(b * d**3 / 12 + b * d * (z - c) ** 2 for b, d, z in self.parts)

    @property
    def Iz(self) -> float:
        return sum(d * b**3 / 12 for b, d, _ in self.parts)

    @property
    def J(self) -> float:
        return sum(Section.rectangle("part", b, d).J for b, d, _ in self.parts)


def tee(name: str, geometry: TeeGeometry, *, J: float | None = None, Iz: float | None = None) -> Section:
    """A T-section with recovery points at the soffit (centre, corners) and the slab top (centre, edges).

    ``J`` and ``Iz`` replace the T's own constants (effective values of the deck). Stresses at
    the points: no transverse shear across the free top and bottom faces, none at the corners
    and slab edges; torsional shear ``T t / J`` with ``t`` the wall (web or slab) at the point,
    the open thin-walled section's value for the section's ``J``.
    """
    c, h = geometry.centroid, geometry.depth
    J = geometry.J if J is None else J
    bw, bf = geometry.web_width / 2, geometry.flange_width / 2
    web, slab = geometry.web_width / J, geometry.flange_thickness / J

    def point(label, y, z, factor, shear_y=None):
        return StressPoint(label, y, z, torsion_factor=factor, shear_factor_y=shear_y, shear_factor_z=0.0)

    points = (
        point("bottom", 0.0, -c, web),
        point("bottom-left", -bw, -c, web, 0.0),
        point("bottom-right", bw, -c, web, 0.0),
        point("top", 0.0, h - c, slab),
        point("top-left", -bf, h - c, slab, 0.0),
        point("top-right", bf, h - c, slab, 0.0),
    )
    return Section(name, A=geometry.area, Iy=geometry.Iy, Iz=geometry.Iz if Iz is None else Iz, J=J, points=points)


def girder_geometry(p: BridgeParameters) -> TeeGeometry:
    return TeeGeometry(p.deck_width / 2, p.slab_thickness, p.girder_width, p.girder_depth)


def girder_section(p: BridgeParameters) -> Section:
    """One girder line: its web and half the slab, torsion constant ``girder_torsion``."""
    return tee("girder", girder_geometry(p), J=p.girder_torsion)


def box(name: str, b: float, d: float, t: float) -> Section:
    """A hollow rectangle ``b`` (local y) by ``d`` (local z) with walls ``t`` (solid when ``2 t >= min(b, d)``).

    ``A = b d - b_i d_i``, ``Iy = (b d^3 - b_i d_i^3) / 12``, ``Iz = (d b^3 - d_i b_i^3) / 12`` with the
    void ``b_i = b - 2 t``, ``d_i = d - 2 t``; torsion by Bredt for a thin-walled cell,
    ``J = 4 A_m^2 t / s_m`` with ``A_m = (b - t)(d - t)`` and ``s_m = 2 (b - t) + 2 (d - t)``.
    Recovery points at the corners and mid-sides.
    """
    if 2 * t >= min(b, d):
        return Section.rectangle(name, b, d)
    bi, di = b - 2 * t, d - 2 * t
    am, sm = (b - t) * (d - t), 2 * (b - t) + 2 * (d - t)
    solid = Section.rectangle(name, b, d)
    points = tuple(StressPoint(pt.name, pt.y, pt.z, torsion_factor=1 / (2 * am * t)) for pt in solid.points)
    return Section(
        name, A=b * d - bi * di, Iy=(b * d**3 - bi * di**3) / 12, Iz=(d * b**3 - di * bi**3) / 12,
        J=4 * am**2 * t / sm, points=points,
    )


def arch_section(p: BridgeParameters) -> Section:
    """The arch rib: a box ``arch_width`` x ``arch_depth`` with walls ``arch_wall``."""
    return box("arch", p.arch_width, p.arch_depth, p.arch_wall)
