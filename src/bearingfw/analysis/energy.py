"""Energy balance of a transient run (relative formulation, measured from the preload state).

With ``x = q - q_0`` the dynamic displacement from the preload, the equation of motion is
``M a + C v + K x + B^T (f - f_0) = F(t)`` (``F`` the ground-motion inertia load ``-M r a_g``
plus any dynamic nodal loads), and its power balance integrates to::

    E_kin + E_strain + E_damp + W_bearings = W_input

    E_kin      = 1/2 v^T M v                  kinetic (relative velocity)
    E_strain   = 1/2 x^T K x                  linear structure: members and vertical bearing springs
                                              (those without uplift)
    E_damp     = int v^T C v dt               Rayleigh damping
    W_bearings = int (f - f_0) . dd           work of the bearing laws: their dissipation plus any
                                              energy stored in them (stick springs, linear springs);
                                              also of a law's viscous force (a velocity law) and of
                                              uplift bearings' compression-only vertical springs
                                              (elastic: while closed, 1/2 kv (d_z - d_z0)^2; while
                                              open, the work of the dead load it no longer carries)
    W_input    = int v^T F dt                 work of the excitation

The integrals are accumulated per step with the trapezoidal rule on the displacement increment,
``dW = dx^T (F_n + F_{n+1}) / 2``; ``imbalance = W_input - (E_kin + E_strain + E_damp + W_bearings)``.

What the imbalance holds. With ``G = C v + K x + B^T (f - f_0) - F`` and ``rho = M a + G`` (the
out-of-balance force at an instant), the definitions above give exactly, per step::

    d imbalance = [dx^T M (a_n + a_{n+1}) / 2 - (E_kin,{n+1} - E_kin,n)] - dx^T (rho_n + rho_{n+1}) / 2

- HHT ``alpha = 0`` (Newmark's average acceleration): ``dx = h (v_n + v_{n+1}) / 2`` and
  ``v_{n+1} - v_n = h (a_n + a_{n+1}) / 2``, so the bracket vanishes, and the scheme enforces
  ``rho = 0``: the balance is exact up to round-off and the Newton tolerance. Any larger
  imbalance is an error.
- HHT ``alpha < 0``: the scheme enforces ``M a_{n+1} + (1 + alpha) G_{n+1} - alpha G_n = 0``,
  i.e. ``rho_{n+1} = -alpha (G_{n+1} - G_n)`` (``rho_0 = 0``: the start is taken as balanced), and
  ``gamma != 1/2`` makes the bracket nonzero. Those two terms, evaluated with the scheme's
  ``rho``, are its **numerical dissipation** (column ``numerical``): energy the integrator removes
  by design, mostly from high frequencies. It is positive over a run (HHT is dissipative), and
  grows with ``-alpha`` and with ``omega h``.

So the table reports the imbalance (``imbalance``, :func:`energy_error`: what the run lost or
gained against the physical terms) and its split: ``numerical`` (the scheme's share) and the
rest, ``imbalance - numerical`` (:func:`balance_error`), the work of what Newton left unsolved
plus round-off, which must be tiny for every ``alpha``.
"""

from __future__ import annotations

import attrs
import numpy as np

__all__ = ["Energy", "ENERGY_COLUMNS", "accumulate", "energy_error", "balance_error", "numerical_dissipation"]

#: Columns of the energy table of a :class:`~bearingfw.analysis.TransientResult`.
ENERGY_COLUMNS = ("kinetic", "strain", "damping", "bearings", "input", "imbalance", "numerical")


@attrs.frozen
class Energy:
    """Energy terms (J) at one instant; ``imbalance = input - (kinetic + strain + damping + bearings)``;
    ``numerical``: the HHT scheme's numerical dissipation up to this instant (module docstring)."""

    kinetic: float = 0.0
    strain: float = 0.0
    damping: float = 0.0
    bearings: float = 0.0
    input: float = 0.0
    numerical: float = 0.0

    @property
    def imbalance(self) -> float:
        return self.input - (self.kinetic + self.strain + self.damping + self.bearings)

    def row(self) -> tuple[float, ...]:
        return (self.kinetic, self.strain, self.damping, self.bearings, self.input, self.imbalance, self.numerical)


def accumulate(energy: Energy, terms) -> Energy:
    """The energy after a step from its terms ``(kinetic, strain, W_damping, W_bearings, W_input,
    W_inertia, W_rho)``: the kinetic and strain energies at the step's end, then the works of the
    step's damping, bearing, load, inertia (``M a``) and out-of-balance (``rho``) forces
    (:func:`bearingfw.analysis.hht_kernels.commit` computes them, from the arrays of a step)."""
    kinetic, strain, damping, bearings, work_input, inertia, rho = terms
    return Energy(
        kinetic=kinetic,
        strain=strain,
        damping=energy.damping + damping,
        bearings=energy.bearings + bearings,
        input=energy.input + work_input,
        numerical=energy.numerical + (inertia - (kinetic - energy.kinetic) - rho),
    )


def _relative(values: np.ndarray, table: dict[str, np.ndarray], reduce) -> float:
    """``reduce(values) / max |W_input|`` (0 when nothing was put in and nothing is left)."""
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        return 0.0
    top = float(np.max(np.abs(np.asarray(table["input"], dtype=float))))
    value = float(reduce(values))
    return value / top if top > 0 else (0.0 if value == 0 else float("inf"))


def energy_error(table: dict[str, np.ndarray]) -> float:
    """``max |imbalance| / max |W_input|`` over a run (0 when no work was put in).

    For HHT ``alpha < 0`` this includes the scheme's numerical dissipation (:func:`balance_error`
    leaves it out)."""
    return _relative(np.abs(table["imbalance"]), table, np.max)


def balance_error(table: dict[str, np.ndarray]) -> float:
    """``max |imbalance - numerical| / max |W_input|``: the energy error that is not the scheme's
    numerical dissipation (NaN for a table without the ``numerical`` column)."""
    if "numerical" not in table:
        return float("nan")
    imbalance = np.asarray(table["imbalance"], dtype=float) - np.asarray(table["numerical"], dtype=float)
    return _relative(np.abs(imbalance), table, np.max)


def numerical_dissipation(table: dict[str, np.ndarray]) -> float:
    """The scheme's numerical dissipation at the end of the run over ``max |W_input|`` (NaN without
    the ``numerical`` column)."""
    if "numerical" not in table:
        return float("nan")
    return _relative(table["numerical"], table, lambda v: v[-1])
