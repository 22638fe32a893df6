"""Viscous damping of the transient analysis: Rayleigh's mass- and stiffness-proportional model.

``C = alpha M + beta K`` on the free DOFs. (Rayleigh's ``alpha`` and ``beta``, as the paper names
them, are unrelated to the HHT-alpha integration parameter ``TransientSettings.alpha`` and to
Newmark's ``beta``; the time stepper calls the Rayleigh pair ``a0``, ``a1``.) The modal damping ratio at circular frequency
``omega`` is ``zeta = alpha / (2 omega) + beta omega / 2``; two (frequency, ratio) pairs fix the
two coefficients (:func:`rayleigh_from_ratios`), e.g. the paper's 2.1 % at 1.50 Hz and 2.7 % at
3.36 Hz give ``alpha = 0.21 1/s`` and ``beta = 0.00208 s``. A measured free decay gives the ratio
through the logarithmic decrement (:func:`damping_ratio_from_log_decrement`).

Which stiffness: ``K`` is ``System.K_free``, the *linear* structure (members and the bearings'
vertical springs), never the bearing laws' tangent or initial stiffness. Two reasons:

- a constant ``C`` keeps the effective matrix of the HHT step constant, so the transient solver
  factorises it once per step size and condenses the nonlinearity exactly onto the bearing
  directions;
- stiffness-proportional damping on a friction or sliding bearing's stick (initial) stiffness
  produces a damping force ``beta k_stick v`` that is not capped by ``mu N``: a sliding bearing
  with its large slip velocity would transmit spurious forces far above the friction limit, and a
  tangent-proportional ``C`` would jump at every stick/slip transition. Charney (2008), "Unintended
  consequences of modeling damping in structures", J. Struct. Eng. 134(4), and Hall (2006),
  "Problems encountered from the use (or misuse) of Rayleigh damping", Earthquake Engng Struct.
  Dyn. 35, discuss these spurious forces. Energy the bearings dissipate comes from their laws.

So a mode whose stiffness comes mainly from the bearing laws (a deck sliding on springs) gets
only the mass-proportional part of the damping. The same holds for the vertical springs of
bearings with ``uplift=True``: compression-only, they are a law of the kernel and not in ``K``
(a dashpot ``beta kv`` across an open gap would hold the lifted girder down).
"""

from __future__ import annotations

import math

import attrs

from bearingfw.parameters import ParameterError, parameter

__all__ = ["Rayleigh", "rayleigh_from_ratios", "damping_ratio_from_log_decrement"]


def damping_ratio_from_log_decrement(delta: float) -> float:
    """Damping ratio from the logarithmic decrement ``delta = ln(x_k / x_{k+1})`` of a free decay.

    ``zeta = delta / sqrt(4 pi^2 + delta^2)`` (exact for a viscously damped SDOF): 0.13 gives
    2.1 % and 0.17 gives 2.7 % (the paper's measured decrements).
    """
    delta = float(delta)
    if not (math.isfinite(delta) and delta >= 0.0):
        raise ParameterError(f"damping_ratio_from_log_decrement: delta = {delta!r} must be >= 0")
    return delta / math.sqrt(4.0 * math.pi**2 + delta**2)


def rayleigh_from_ratios(f1: float, zeta1: float, f2: float, zeta2: float) -> tuple[float, float]:
    """Rayleigh coefficients ``(alpha, beta)`` giving ratio ``zeta1`` at ``f1`` Hz and ``zeta2`` at ``f2`` Hz.

    Solves ``zeta_i = alpha / (2 w_i) + beta w_i / 2`` with ``w_i = 2 pi f_i``::

        alpha = 2 w1 w2 (zeta1 w2 - zeta2 w1) / (w2^2 - w1^2),  beta = 2 (zeta2 w2 - zeta1 w1) / (w2^2 - w1^2)

    A negative coefficient (ratios that fall too fast or rise too fast with frequency) is
    rejected: it would make some modes negatively damped.
    """
    for name, value, low in (("f1", f1, 0.0), ("f2", f2, 0.0)):
        if not (math.isfinite(value) and value > low):
            raise ParameterError(f"rayleigh_from_ratios: {name} = {value!r} must be > 0 Hz")
    for name, value in (("zeta1", zeta1), ("zeta2", zeta2)):
        if not (math.isfinite(value) and 0.0 <= value < 1.0):
            raise ParameterError(f"rayleigh_from_ratios: {name} = {value!r} must be in 0 <= {name} < 1")
    if f1 == f2:
        raise ParameterError(f"rayleigh_from_ratios: f1 and f2 must differ (both {f1!r} Hz)")
    w1, w2 = 2.0 * math.pi * f1, 2.0 * math.pi * f2
    den = w2**2 - w1**2
    alpha = 2.0 * w1 * w2 * (zeta1 * w2 - zeta2 * w1) / den
    beta = 2.0 * (zeta2 * w2 - zeta1 * w1) / den
    if alpha < 0.0 or beta < 0.0:
        raise ParameterError(
            f"rayleigh_from_ratios: ratios {zeta1:g} at {f1:g} Hz and {zeta2:g} at {f2:g} Hz give a negative "
            f"coefficient (alpha = {alpha:.4g} 1/s, beta = {beta:.4g} s)"
        )
    return alpha, beta


@attrs.frozen
class Rayleigh:
    """Rayleigh damping ``C = alpha M + beta K_free`` (see the module docstring for which ``K``).

    ``alpha`` (1/s) multiplies the mass, ``beta`` (s) the stiffness: the paper's names, not the
    HHT-alpha of :class:`~bearingfw.analysis.TransientSettings` nor Newmark's beta.
    """

    alpha: float = parameter(low=0.0, default=0.0, unit="1/s", doc="Rayleigh mass-proportional coefficient (not HHT's alpha)")
    beta: float = parameter(
        low=0.0, default=0.0, unit="s", doc="Rayleigh stiffness-proportional coefficient, linear structure (not Newmark's beta)"
    )

    @classmethod
    def from_ratios(cls, f1: float, zeta1: float, f2: float, zeta2: float) -> Rayleigh:
        """Coefficients from two (frequency in Hz, damping ratio) pairs (:func:`rayleigh_from_ratios`)."""
        return cls(*rayleigh_from_ratios(f1, zeta1, f2, zeta2))

    def ratio(self, frequency: float) -> float:
        """Damping ratio of a mode at ``frequency`` Hz whose stiffness is all in ``K_free``."""
        w = 2.0 * math.pi * frequency
        return self.alpha / (2.0 * w) + self.beta * w / 2.0
