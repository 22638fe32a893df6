"""Cross-sections of frame members and their stress-recovery points.

Section axes are the element's local ``y`` and ``z`` (see :mod:`bearingfw.model.elements`),
through the centroid and along the principal axes. ``Iy`` is the second moment about local y
(bending in the local x-z plane), ``Iz`` about local z (bending in the x-y plane), ``J`` the
St-Venant torsion constant. ``Avy``/``Avz`` are the shear areas for shear force along y/z
(used by the Timoshenko element, and by the stress recovery where a point gives no shear
factor).

Stresses at a recovery point (:mod:`bearingfw.analysis.results`) use per-point factors where the
section knows them: the torsional shear per unit torque and the transverse shear per unit shear
force. :meth:`Section.rectangle` and :meth:`Section.circle` set them for their default points.
"""

from __future__ import annotations

import math

import attrs
import numpy as np

from bearingfw.model._fields import ModelError, name_field
from bearingfw.parameters import parameter

__all__ = ["Section", "StressPoint", "rectangle_torsion"]


@attrs.frozen
class StressPoint:
    """A point ``(y, z)`` of the section (local axes, m) at which stresses are recovered.

    ``torsion_factor`` (1/m^3), if given, is the torsional shear stress per unit torque at this
    point, ``tau_T = torsion_factor * T`` (e.g. ``1 / (2 A_m t)`` for a thin-walled box, Bredt).
    Without it ``tau_T = T r / J`` with ``r`` the distance from the centroid, exact for circular
    and annular sections only. Either way the torsional shear acts perpendicular to the radius.

    ``shear_factor_y`` / ``shear_factor_z`` (1/m^2), if given, are the transverse shear stress
    per unit shear force, ``tau_xy = shear_factor_y * Vy`` and ``tau_xz = shear_factor_z * Vz``
    (e.g. ``Q / (I b)``: the first moment of the area beyond the point's chord over the second
    moment and the chord width; zero at an extreme fibre, where the surface is free). Without
    them the average ``V / Av`` is used.
    """

    name: str = name_field()
    y: float = parameter(unit="m", doc="local y coordinate")
    z: float = parameter(unit="m", doc="local z coordinate")
    torsion_factor: float | None = parameter(optional=True, low=0.0, unit="1/m^3", doc="tau_T / T at this point")
    shear_factor_y: float | None = parameter(optional=True, low=0.0, unit="1/m^2", doc="tau_xy / Vy at this point")
    shear_factor_z: float | None = parameter(optional=True, low=0.0, unit="1/m^2", doc="tau_xz / Vz at this point")


#: Catalan's constant, sum over odd n of (-1)^((n-1)/2) / n^2 (torsion of a rectangle).
_CATALAN = 0.915965594177219015
#: Odd n of the rectangle's torsion series; the terms left decay like exp(-n pi b / t) or 1/n^5.
_ODD = np.arange(1, 400, 2, dtype=float)


def rectangle_torsion(long: float, short: float) -> tuple[float, float, float]:
    """St-Venant torsion of a solid rectangle ``long >= short``: ``(k1, c_long, c_short)``.

    From Prandtl's stress function as a Fourier series (Timoshenko & Goodier, sec. 109), with
    ``beta = long / short``, sums over odd ``n`` and ``theta`` the twist per length:

    - ``J = k1 long short^3``, ``k1 = (1 - (192 / pi^5) / beta * sum tanh(n pi beta / 2) / n^5) / 3``;
    - mid long side (the largest stress): ``tau = c_long G theta short``,
      ``c_long = 1 - (8 / pi^2) sum 1 / (n^2 cosh(n pi beta / 2))``;
    - mid short side: ``tau = c_short G theta short``,
      ``c_short = (8 / pi^2) sum (-1)^((n-1)/2) tanh(n pi beta / 2) / n^2``
      (summed as Catalan's constant minus the fast-decaying ``1 - tanh`` part);
    - corners: zero.

    So per unit torque ``tau / T = c / (k1 long short^2)``; the tabulated ``alpha = k1 / c_long``
    (``tau_max = T / (alpha long short^2)``) is 0.208 for a square and 0.246 for 2:1.
    """
    beta = long / short
    x = _ODD * np.pi * beta / 2
    decay = np.exp(-2 * x)  # 1 / cosh(x) = 2 e^-x / (1 + e^-2x), 1 - tanh(x) = 2 e^-2x / (1 + e^-2x)
    sech = 2 * np.exp(-x) / (1 + decay)
    one_minus_tanh = 2 * decay / (1 + decay)
    alternating = np.where(_ODD % 4 == 1, 1.0, -1.0)
    k1 = (1 - 192 / np.pi**5 / beta * np.sum((1 - one_minus_tanh) / _ODD**5)) / 3
    c_long = 1 - 8 / np.pi**2 * np.sum(sech / _ODD**2)
    c_short = 8 / np.pi**2 * (_CATALAN - np.sum(alternating * one_minus_tanh / _ODD**2))
    return float(k1), float(c_long), float(c_short)


def _points(value):
    try:
        return tuple(value)
    except TypeError:
        return value


@attrs.frozen
class Section:
    """Section properties of a frame member (principal axes)."""

    name: str = name_field()
    A: float = parameter(low=0.0, low_open=True, unit="m^2", doc="area")
    Iy: float = parameter(low=0.0, low_open=True, unit="m^4", doc="second moment about local y")
    Iz: float = parameter(low=0.0, low_open=True, unit="m^4", doc="second moment about local z")
    J: float = parameter(low=0.0, low_open=True, unit="m^4", doc="St-Venant torsion constant")
    Avy: float | None = parameter(optional=True, low=0.0, low_open=True, unit="m^2", doc="shear area along local y")
    Avz: float | None = parameter(optional=True, low=0.0, low_open=True, unit="m^2", doc="shear area along local z")
    points: tuple[StressPoint, ...] = attrs.field(default=(), converter=_points)

    @points.validator
    def _check_points(self, attribute, value):
        if not isinstance(value, tuple) or not all(isinstance(p, StressPoint) for p in value):
            raise ModelError(f"Section {self.name!r}: field 'points' must be StressPoint objects")
        names = [p.name for p in value]
        if len(set(names)) != len(names):
            raise ModelError(f"Section {self.name!r}: field 'points' has duplicate point names {names}")

    @property
    def Ip(self) -> float:
        """Polar second moment of area ``Iy + Iz`` (rotary inertia of the section per unit mass)."""
        return self.Iy + self.Iz

    @classmethod
    def rectangle(cls, name: str, b: float, h: float, **kwargs) -> Section:
        """A solid ``b`` (along local y) by ``h`` (along local z) rectangle.

        ``J = a c^3 (1/3 - 0.21 (c/a) (1 - (c/a)^4 / 12))`` with ``a >= c`` the long and short
        sides (Roark; within 0.2 % of the exact series); shear areas ``5/6 A``; recovery points
        at the four corners and the mid-sides, with

        - torsion factors from the exact series (:func:`rectangle_torsion`): the largest at the
          middle of the long sides, a smaller one at the middle of the short sides, zero at the
          corners (the shear stress would have to be tangent to both free faces there);
        - shear factors ``Q / (I b)``: ``1.5 / A`` across the chord through the centroid (mid
          sides parallel to the force: ``tau_xz`` at left/right, ``tau_xy`` at top/bottom), zero
          at the extreme fibres (corners; ``tau_xz`` at top/bottom, ``tau_xy`` at left/right).
        """
        if not (b > 0 and h > 0):
            raise ModelError(f"Section {name!r}: rectangle sides b = {b!r} and h = {h!r} must be > 0")
        a, c = max(b, h), min(b, h)
        J = a * c**3 * (1.0 / 3.0 - 0.21 * (c / a) * (1.0 - (c / a) ** 4 / 12.0))
        A = b * h
        points = kwargs.pop("points", None)
        if points is None:
            k1, c_long, c_short = rectangle_torsion(a, c)
            per_torque = 1.0 / (k1 * a * c**2)
            # top/bottom lie on the sides of length b, left/right on those of length h
            t_tb = per_torque * (c_long if b >= h else c_short)
            t_lr = per_torque * (c_long if h > b else c_short)
            centre = 1.5 / A  # Q / (I b) on the centroidal chord of a rectangle
            points = (
                *(
                    StressPoint(n, y, z, torsion_factor=0.0, shear_factor_y=0.0, shear_factor_z=0.0)
                    for n, y, z in (
                        ("top-left", -b / 2, h / 2),
                        ("top-right", b / 2, h / 2),
                        ("bottom-left", -b / 2, -h / 2),
                        ("bottom-right", b / 2, -h / 2),
                    )
                ),
                StressPoint("top", 0.0, h / 2, torsion_factor=t_tb, shear_factor_y=centre, shear_factor_z=0.0),
                StressPoint("bottom", 0.0, -h / 2, torsion_factor=t_tb, shear_factor_y=centre, shear_factor_z=0.0),
                StressPoint("left", -b / 2, 0.0, torsion_factor=t_lr, shear_factor_y=0.0, shear_factor_z=centre),
                StressPoint("right", b / 2, 0.0, torsion_factor=t_lr, shear_factor_y=0.0, shear_factor_z=centre),
            )
        kwargs.setdefault("Avy", 5 * A / 6)
        kwargs.setdefault("Avz", 5 * A / 6)
        return cls(name, A=A, Iy=b * h**3 / 12, Iz=h * b**3 / 12, J=J, points=points, **kwargs)

    @classmethod
    def circle(cls, name: str, d: float, **kwargs) -> Section:
        """A solid circle of diameter ``d``: J = Ip, shear areas 0.9 A, points on the axes.

        Torsion ``T r / J`` is exact. Shear factors ``Q / (I b) = 4 / (3 A)`` across the
        centroidal chord (``tau_xy`` at top/bottom, ``tau_xz`` at left/right; the elementary
        value, within 4 % of the elastic one), zero at the extreme fibres.
        """
        if not d > 0:
            raise ModelError(f"Section {name!r}: diameter d = {d!r} must be > 0")
        A = math.pi * d**2 / 4
        second_moment = math.pi * d**4 / 64
        r = d / 2
        centre = 4.0 / (3.0 * A)
        points = kwargs.pop(
            "points",
            (
                StressPoint("top", 0.0, r, shear_factor_y=centre, shear_factor_z=0.0),
                StressPoint("bottom", 0.0, -r, shear_factor_y=centre, shear_factor_z=0.0),
                StressPoint("left", -r, 0.0, shear_factor_y=0.0, shear_factor_z=centre),
                StressPoint("right", r, 0.0, shear_factor_y=0.0, shear_factor_z=centre),
            ),
        )
        kwargs.setdefault("Avy", 0.9 * A)
        kwargs.setdefault("Avz", 0.9 * A)
        return cls(name, A=A, Iy=second_moment, Iz=second_moment, J=2 * second_moment, points=points, **kwargs)
