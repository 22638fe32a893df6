"""Linear elastic isotropic materials."""

from __future__ import annotations

import attrs

from bearingfw.model._fields import ModelError, name_field
from bearingfw.parameters import parameter

__all__ = ["Material"]


@attrs.frozen
class Material:
    """Young's modulus ``E``, Poisson's ratio ``nu`` (or an explicit shear modulus ``G``), density.

    The shear modulus used is ``G`` if given, else ``E / (2 (1 + nu))``. ``density`` may be zero
    for a massless member (the SDOF idealisations of the paper use massless columns).
    """

    name: str = name_field()
    E: float = parameter(low=0.0, low_open=True, unit="Pa", doc="Young's modulus")
    density: float = parameter(low=0.0, default=0.0, unit="kg/m^3", doc="mass density")
    nu: float = parameter(low=-1.0, high=0.5, low_open=True, default=0.2, doc="Poisson's ratio")
    G: float | None = parameter(optional=True, low=0.0, low_open=True, unit="Pa", doc="shear modulus (overrides nu)")

    @property
    def shear_modulus(self) -> float:
        """``G`` if given, else ``E / (2 (1 + nu))``."""
        return self.G if self.G is not None else self.E / (2.0 * (1.0 + self.nu))

    @staticmethod
    def composite_modulus(E_c: float, A_c: float, E_s: float, A_s: float) -> float:
        """The paper's eq. (1): ``E_cs = (E_c A_c + E_s A_s) / (A_c + A_s)`` (prestressed girders)."""
        if min(E_c, A_c, E_s, A_s) < 0 or A_c + A_s <= 0:
            raise ModelError("composite_modulus: moduli and areas must be >= 0 with a positive total area")
        return (E_c * A_c + E_s * A_s) / (A_c + A_s)
