"""The paper's SDOF estimate of the stick stiffness K_s (section 3.3, figure 15, eqs. 7-11).

Two frames oscillating transversally on two columns of bending stiffness ``K_c`` each
(``K_c = 3 E I / h^3``, a cantilever under a pinned bearing): with frictionless sliding on one
bearing only one column works (eq. 7), with a stick spring ``K_s`` in series the other joins::

    f_a = sqrt(K_c / m) / (2 pi)                                        (7)
    K   = K_c + K_c K_s / (K_c + K_s) = K_c (K_c + 2 K_s) / (K_c + K_s)   (8)
    f_b = sqrt(K / m) / (2 pi)                                          (9)
    alpha = f_b / f_a = sqrt((K_c + 2 K_s) / (K_c + K_s))               (10)
    K_s = K_c (alpha^2 - 1) / (2 - alpha^2)                             (11)

``alpha`` lies in ``[1, sqrt(2))``: a spring cannot more than double the stiffness.
"""

from __future__ import annotations

import math

from bearingfw.parameters import ParameterError

__all__ = ["frequency_ratio", "ks_eq11"]


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise ParameterError(f"ks_eq11: {name} = {value!r} must be > 0")
    return value


def frequency_ratio(k_c: float, k_s: float) -> float:
    """Eq. (10): ``f_b / f_a`` of the frame with a stick spring ``k_s`` on the second column."""
    k_c, k_s = _positive("k_c", k_c), float(k_s)
    if not (math.isfinite(k_s) and k_s >= 0):
        raise ParameterError(f"frequency_ratio: k_s = {k_s!r} must be >= 0")
    return math.sqrt((k_c + 2 * k_s) / (k_c + k_s))


def ks_eq11(k_c: float, f_a: float, f_b: float) -> float:
    """Eq. (11): the stick stiffness (N/m) that lifts the transverse frequency from ``f_a`` to ``f_b``.

    The paper's K_c = 147 MN/m, f_a = 1.87 Hz (untuned model), f_b = 2.48 Hz (measured) give
    K_s = 462 MN/m. ``f_b / f_a`` must lie in ``[1, sqrt(2))``.
    """
    k_c, f_a, f_b = _positive("k_c", k_c), _positive("f_a", f_a), _positive("f_b", f_b)
    alpha2 = (f_b / f_a) ** 2
    if not 1.0 <= alpha2 < 2.0:
        raise ParameterError(
            f"ks_eq11: f_b / f_a = {f_b / f_a:.4g} must lie in [1, sqrt(2)) = [1, 1.414): a stick spring in series "
            "with the second column at most doubles the frame's stiffness"
        )
    return k_c * (alpha2 - 1.0) / (2.0 - alpha2)
