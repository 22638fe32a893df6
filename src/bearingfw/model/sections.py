"""Cross-sections of frame members and their stress-recovery points.

Section axes are the element's local ``y`` and ``z`` (see :mod:`bearingfw.model.elements`),
through the centroid and along the principal axes. ``Iy`` is the second moment about local y
(bending in the local x-z plane), ``Iz`` about local z (bending in the x-y plane), ``J`` the
St-Venant torsion constant. ``Avy``/``Avz`` are the shear areas for shear force along y/z
(used by the Timoshenko element and by the average shear stress ``V / Av``).
"""

from __future__ import annotations

import math

import attrs

from bearingfw.model._fields import ModelError, name_field
from bearingfw.parameters import parameter

__all__ = ["Section", "StressPoint"]


@attrs.frozen
class StressPoint:
    """A point ``(y, z)`` of the section (local axes, m) at which stresses are recovered.

    ``torsion_factor`` (1/m^3), if given, is the torsional shear stress per unit torque at this
    point, ``tau_T = torsion_factor * T`` (e.g. ``1 / (2 A_m t)`` for a thin-walled box, Bredt).
    Without it ``tau_T = T r / J`` with ``r`` the distance from the centroid, exact for circular
    and annular sections. Either way the torsional shear acts perpendicular to the radius.
    """

    name: str = name_field()
    y: float = parameter(unit="m", doc="local y coordinate")
    z: float = parameter(unit="m", doc="local z coordinate")
    torsion_factor: float | None = parameter(optional=True, low=0.0, unit="1/m^3", doc="tau_T / T at this point")


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
        at the four corners and the mid-sides.
        """
        if not (b > 0 and h > 0):
            raise ModelError(f"Section {name!r}: rectangle sides b = {b!r} and h = {h!r} must be > 0")
        a, c = max(b, h), min(b, h)
        J = a * c**3 * (1.0 / 3.0 - 0.21 * (c / a) * (1.0 - (c / a) ** 4 / 12.0))
        points = kwargs.pop("points", None)
        if points is None:
            points = tuple(
                StressPoint(n, y, z)
                for n, y, z in (
                    ("top-left", -b / 2, h / 2),
                    ("top-right", b / 2, h / 2),
                    ("bottom-left", -b / 2, -h / 2),
                    ("bottom-right", b / 2, -h / 2),
                    ("top", 0.0, h / 2),
                    ("bottom", 0.0, -h / 2),
                    ("left", -b / 2, 0.0),
                    ("right", b / 2, 0.0),
                )
            )
        A = b * h
        kwargs.setdefault("Avy", 5 * A / 6)
        kwargs.setdefault("Avz", 5 * A / 6)
        return cls(name, A=A, Iy=b * h**3 / 12, Iz=h * b**3 / 12, J=J, points=points, **kwargs)

    @classmethod
    def circle(cls, name: str, d: float, **kwargs) -> Section:
        """A solid circle of diameter ``d``: J = Ip, shear areas 0.9 A, points on the axes."""
        if not d > 0:
            raise ModelError(f"Section {name!r}: diameter d = {d!r} must be > 0")
        A = math.pi * d**2 / 4
        second_moment = math.pi * d**4 / 64
        r = d / 2
        points = kwargs.pop(
            "points",
            (
                StressPoint("top", 0.0, r),
                StressPoint("bottom", 0.0, -r),
                StressPoint("left", -r, 0.0),
                StressPoint("right", r, 0.0),
            ),
        )
        kwargs.setdefault("Avy", 0.9 * A)
        kwargs.setdefault("Avz", 0.9 * A)
        return cls(name, A=A, Iy=second_moment, Iz=second_moment, J=2 * second_moment, points=points, **kwargs)
