"""Energy balance of a transient run (relative formulation, measured from the preload state).

With ``x = q - q_0`` the dynamic displacement from the preload, the equation of motion is
``M a + C v + K x + B^T (f - f_0) = F(t)`` (``F`` the ground-motion inertia load ``-M r a_g``
plus any dynamic nodal loads), and its power balance integrates to::

    E_kin + E_strain + E_damp + W_bearings = W_input

    E_kin      = 1/2 v^T M v                  kinetic (relative velocity)
    E_strain   = 1/2 x^T K x                  linear structure: members and vertical bearing springs
    E_damp     = int v^T C v dt               Rayleigh damping
    W_bearings = int (f - f_0) . dd           work of the bearing laws: their dissipation plus any
                                              energy stored in them (stick springs, linear springs)
    W_input    = int v^T F dt                 work of the excitation

The integrals are accumulated per step with the trapezoidal rule on the displacement increment,
``dW = dx^T (F_n + F_{n+1}) / 2``. For Newmark's average acceleration (HHT ``alpha = 0``)
``dx = dt (v_n + v_{n+1}) / 2`` and ``v_{n+1} - v_n = dt (a_n + a_{n+1}) / 2`` exactly, so the
discrete balance holds to round-off and the Newton tolerance: any larger imbalance is an error.
With ``alpha < 0`` the scheme dissipates energy in the higher modes by design; the imbalance
then measures that numerical dissipation.
"""

from __future__ import annotations

import attrs
import numpy as np

__all__ = ["Energy", "ENERGY_COLUMNS", "advance_energy", "energy_error"]

#: Columns of the energy table of a :class:`~bearingfw.analysis.TransientResult`.
ENERGY_COLUMNS = ("kinetic", "strain", "damping", "bearings", "input", "imbalance")


@attrs.frozen
class Energy:
    """Energy terms (J) at one instant; ``imbalance = input - (kinetic + strain + damping + bearings)``."""

    kinetic: float = 0.0
    strain: float = 0.0
    damping: float = 0.0
    bearings: float = 0.0
    input: float = 0.0

    @property
    def imbalance(self) -> float:
        return self.input - (self.kinetic + self.strain + self.damping + self.bearings)

    def row(self) -> tuple[float, ...]:
        return (self.kinetic, self.strain, self.damping, self.bearings, self.input, self.imbalance)


def _trapezoid(increment: np.ndarray, force0: np.ndarray, force1: np.ndarray) -> float:
    return 0.5 * float(increment @ (force0 + force1))


def advance_energy(
    energy: Energy,
    *,
    dx: np.ndarray,
    v1: np.ndarray,
    Mv1: np.ndarray,
    x1: np.ndarray,
    Kx1: np.ndarray,
    damping0: np.ndarray,
    damping1: np.ndarray,
    dd: np.ndarray,
    bearing0: np.ndarray,
    bearing1: np.ndarray,
    load0: np.ndarray,
    load1: np.ndarray,
) -> Energy:
    """The terms after one step: state functions at the new point, works by the trapezoidal rule.

    ``damping*`` are the damping forces ``C v``, ``bearing*`` the law forces minus their preload
    values (connector space, ``dd`` the increment of ``B x``), ``load*`` the dynamic loads.
    """
    return Energy(
        kinetic=0.5 * float(v1 @ Mv1),
        strain=0.5 * float(x1 @ Kx1),
        damping=energy.damping + _trapezoid(dx, damping0, damping1),
        bearings=energy.bearings + _trapezoid(dd, bearing0, bearing1),
        input=energy.input + _trapezoid(dx, load0, load1),
    )


def energy_error(table: dict[str, np.ndarray]) -> float:
    """``max |imbalance| / max |W_input|`` over a run (0 when no work was put in)."""
    imbalance = np.abs(np.asarray(table["imbalance"], dtype=float))
    work = np.abs(np.asarray(table["input"], dtype=float))
    if imbalance.size == 0:
        return 0.0
    top = float(work.max())
    return float(imbalance.max()) / top if top > 0 else (0.0 if float(imbalance.max()) == 0 else float("inf"))
