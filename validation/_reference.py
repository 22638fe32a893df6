"""Independent references for the law comparisons, random paths and difference measures.

Nothing here calls bearingfw or OpenSees: these are the third opinions used to decide which side
of a gap is right.

- :func:`epp_reference`: the elastic-perfectly-plastic spring, written as the textbook 1-D
  return map (exact for a piecewise-linear path: the EPP response is rate independent and its
  one-step return is exact in 1-D).
- :func:`friction_reference`: the 2-D radial return of isotropic Coulomb friction with stick
  stiffness ``k``, one backward-Euler step per increment, written as a plain scalar loop.
- :func:`bouc_wen_reference`: the Bouc-Wen ODE integrated along every straight increment with an
  adaptive 8th-order Runge-Kutta method (scipy's DOP853, rtol 1e-10), for the two biaxial forms
  that exist in the wild: Park-Wen-Ang (bearingfw) and the isotropic form with ``|z . du|``
  (OpenSees's elastomericBearingBoucWen). Both reduce to the same 1-D law.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

__all__ = [
    "random_path",
    "proportional_path",
    "subdivide",
    "relative_difference",
    "epp_reference",
    "friction_reference",
    "bouc_wen_reference",
]


# --------------------------------------------------------------------------------------------
# Paths


def random_path(rng: np.random.Generator, amplitude: float, steps: int, dims: int = 1, knots: int = 8) -> np.ndarray:
    """A seeded random displacement path, (steps,) for dims = 1 else (steps, dims).

    Piecewise linear through ``knots`` random points (uniform in [-1, 1] per component) at random
    times, starting from rest at time 0, sampled at ``steps`` equal time steps after 0 and scaled
    so that its largest magnitude is ``amplitude``. Components are independent, so a 2-D path is
    non-proportional (the direction of motion turns). Samples between two knots lie on a
    straight segment, so the path is exactly the polyline through its samples.
    """
    times = np.concatenate([[0.0], np.sort(rng.uniform(0.02, 0.98, knots - 1)), [1.0]])
    values = np.vstack([np.zeros((1, dims)), rng.uniform(-1.0, 1.0, (knots, dims))])
    t = np.arange(1, steps + 1) / steps
    u = np.column_stack([np.interp(t, times, values[:, j]) for j in range(dims)])
    u *= amplitude / np.linalg.norm(u, axis=1).max()
    return u[:, 0] if dims == 1 else u


def proportional_path(rng: np.random.Generator, amplitude: float, steps: int, angle_deg: float) -> np.ndarray:
    """A 1-D random path along the fixed horizontal direction ``angle_deg`` from x, (steps, 2)."""
    s = random_path(rng, amplitude, steps)
    a = np.radians(angle_deg)
    return np.outer(s, [np.cos(a), np.sin(a)])


def subdivide(u, longest: float) -> np.ndarray:
    """The same polyline (from rest) with every increment cut into equal parts no longer than ``longest``."""
    u = np.asarray(u, dtype=float)
    points = np.concatenate([np.zeros((1,) + u.shape[1:]), u])
    steps = np.diff(points, axis=0)
    lengths = np.abs(steps) if u.ndim == 1 else np.linalg.norm(steps, axis=1)
    parts = np.maximum(1, np.ceil(lengths / longest).astype(int))
    pieces = [points[i] + np.multiply.outer(np.arange(1, m + 1) / m, steps[i]) for i, m in enumerate(parts)]
    return np.concatenate(pieces)


def relative_difference(a, b, scale=None) -> tuple[float, float]:
    """``(max, rms)`` of ``|a - b|`` over the history, divided by the peak of ``|b|`` (or ``scale``).

    Rows are vectors in 2-D (the Euclidean norm per step).
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.ndim == 1:
        a, b = a[:, None], b[:, None]
    diff = np.linalg.norm(a - b, axis=1)
    peak = np.linalg.norm(b, axis=1).max() if scale is None else scale
    if peak == 0.0:
        return (0.0, 0.0) if diff.max() == 0.0 else (np.inf, np.inf)
    return float(diff.max() / peak), float(np.sqrt(np.mean(diff**2)) / peak)


# --------------------------------------------------------------------------------------------
# References


def epp_reference(k: float, yield_force: float, u) -> np.ndarray:
    """Force history of an elastic-perfectly-plastic spring (stiffness k, yield force F_y)."""
    plastic = 0.0
    out = np.empty(len(u))
    for i, ui in enumerate(u):
        f = k * (ui - plastic)
        if f > yield_force:
            plastic = ui - yield_force / k
            f = yield_force
        elif f < -yield_force:
            plastic = ui + yield_force / k
            f = -yield_force
        out[i] = f
    return out


def friction_reference(k: float, mu: float, u, normal_force) -> np.ndarray:
    """Isotropic 2-D Coulomb friction with stick stiffness k: one radial return per increment."""
    u = np.asarray(u, dtype=float)
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), u.shape[:1])
    slip_x = slip_y = 0.0
    out = np.empty_like(u)
    for i, ((ux, uy), n) in enumerate(zip(u, normal)):
        fx, fy = k * (ux - slip_x), k * (uy - slip_y)
        size = np.hypot(fx, fy)
        capacity = mu * max(n, 0.0)
        if size > capacity:
            fx, fy = fx * capacity / size, fy * capacity / size
            slip_x, slip_y = ux - fx / k, uy - fy / k
        out[i] = fx, fy
    return out


def bouc_wen_reference(
    u, uy: float, A: float, beta: float, gamma: float, n: float, form: str = "park-wen"
) -> np.ndarray:
    """The hysteretic variable ``z`` (dimensionless, ``|z| <~ 1``) along ``u``, (steps, dims).

    ``uy dz = A du - |z|^(n-2) q z`` along each straight increment ``du``, with
    ``q = beta (|du_x z_x| + |du_y z_y|) + gamma z . du`` (form "park-wen") or
    ``q = beta |z . du| + gamma z . du`` (form "isotropic"); in 1-D both are
    ``beta |du| |z|^(n-1) z + gamma du |z|^n``.
    """
    if form not in ("park-wen", "isotropic"):
        raise ValueError(form)
    u = np.asarray(u, dtype=float)
    if u.ndim == 1:
        u = u[:, None]
    z = np.zeros(u.shape[1])
    previous = np.zeros(u.shape[1])
    out = np.empty_like(u)
    for i, ui in enumerate(u):
        du = ui - previous
        if np.any(du != 0.0):

            def rate(_, z, du=du):
                r = np.sqrt(z @ z)
                if r == 0.0:
                    return A * du / uy
                dot = z @ du
                q = beta * (np.abs(du * z).sum() if form == "park-wen" else abs(dot)) + gamma * dot
                return (A * du - r ** (n - 2.0) * q * z) / uy

            z = solve_ivp(rate, (0.0, 1.0), z, method="DOP853", rtol=1e-10, atol=1e-12).y[:, -1]
        previous = ui
        out[i] = z
    return out
