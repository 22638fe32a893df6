"""The per-connector arithmetic of :meth:`BoucWen.respond`, compiled with numba (issue 16).

:mod:`bearingfw_boucwen.law` imports this module on the first call of ``respond`` (not when the
plugin is merely registered: numba's import costs a few tenths of a second), through
:func:`bearingfw_boucwen.law._kernels`. The formulas are those of the law's module docstring; each
connector is one iteration of a plain loop, so a connector's answer does not depend on the
others it is called with (the kit's "vectorised" property, to the bit).

Numpy's per-operation overhead (about a microsecond on arrays of a few connectors) made the
former vectorised law cost 50-500 us per call of 11 connectors; a loop costs about what the
arithmetic does. The two entry points, :func:`respond_1d` and :func:`respond_2d`, have one
explicit signature each (C-contiguous float64 arrays; ``BoucWen.respond`` makes its inputs so),
so one machine-code version of each is compiled, when this module is imported, and cached on
disk (``cache=True``, next to this file in ``__pycache__``); the helpers are compiled for the
types they are called with from there.

The parameter table (built once per law and connector count by ``law._Prepared``): one row per
connector, the columns named by the ``COL_*`` constants.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from bearingfw.jit import ANSWERED, DECLINED, law_kernel
from numba import carray, njit

# The columns of the parameter table, one row per connector.
COL_A, COL_BETA, COL_GAMMA, COL_UY, COL_N = 0, 1, 2, 3, 4
COL_STILL = 5  # n = 2: increments shorter than this leave z as it is (BoucWen.STILL uy)
COL_S, COL_KAPPA, COL_LINEAR = 6, 7, 8  # n = 2 unloading: sqrt(b/A), sqrt(A b), b = beta - gamma <= 0 (1.0/0.0)
COL_Z_MAX = 9  # (A / (beta + gamma))^(1/n) (for n = 2 by a square root, as the closed form takes it)
COL_RATE = 10  # n = 2 loading rate sqrt(A (beta + gamma))
COL_SUBSTEP = 11  # n != 2: the longest substep (BoucWen.substep)
COL_HYSTERETIC = 12  # (1 - alpha) k uy: force per unit z
COL_ALPHA_K = 13  # alpha k: the linear spring
COL_MAX_SUBSTEPS, COL_MAX_ITERATIONS = 14, 15  # BoucWen.MAX_SUBSTEPS, BoucWen.MAX_NEWTON_ITERATIONS
COLUMNS = 16

_TINY = 1e-300
_STEP = 1e-20  # the complex step's size (divided by t^2 for t > 1)
_PI2_4 = math.pi**2 / 4
#: tanh(r)/r = sum_k a_k r^(2k), a_k = 2^(2k+2) (2^(2k+2) - 1) B_(2k+2) / (2k+2)!, B the Bernoulli numbers
_S7, _S6, _S5, _S4 = -929569 / 638512875, 21844 / 6081075, -1382 / 155925, 62 / 2835
_S3, _S2, _S1, _S0 = -17 / 315, 2 / 15, -1 / 3, 1.0

_ARRAY2 = "float64[:, ::1]"
_ARRAY3 = "float64[:, :, ::1]"
_SIGNATURE = f"Tuple(({_ARRAY2}, {_ARRAY3}, {_ARRAY2}))({_ARRAY2}, {_ARRAY2}, {_ARRAY2}, {_ARRAY2})"


@njit(cache=True)
def _sign(x):
    """``np.sign`` of a float (0 for 0)."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0 * x  # 0 (or NaN for NaN, as numpy)


@njit(cache=True)
def _direction(d, z):
    """The sign of an increment's component: that of ``d``, or where ``d = 0`` the unloading side ``-sgn(z)``."""
    return _sign(d) if d != 0.0 else _sign(-z)


# --- n = 2: the closed form ------------------------------------------------------------------


@njit(cache=True)
def _exact_1d(row, z0, d):
    """One connector, 1-D, n = 2: ``(z1, dz/du)``.

    ``zeta = sgn(du) z`` only grows. Unloading (``zeta < 0``), ``uy zeta' = A + b zeta^2``
    (``b = beta - gamma``): ``zeta = tan(atan(s zeta0) + kappa t)/s`` up to 0 (``zeta0 + A t`` if
    ``b = 0``); then loading, ``zeta = z_max tanh(atanh(zeta0/z_max) + rate t)`` by the addition
    theorem; ``t = |du|/uy``. The tangent of an exact integration is the right-hand side at the
    end point, ``F(z1)/uy``. An increment shorter than STILL uy keeps ``z0``, with the limit tangent.
    """
    A, beta, gamma, uy = row[COL_A], row[COL_BETA], row[COL_GAMMA], row[COL_UY]
    direction = _direction(d, z0)
    length = abs(d)
    if not length > row[COL_STILL]:
        # dPhi/ddelta / uy at z0: the limit of the moving case
        slope = (beta * abs(z0) * direction + gamma * z0) / -uy
        return z0, z0 * slope + A / uy
    zeta = direction * z0
    t = length / uy
    if zeta < 0.0:  # unloading: up to zeta = 0, then loading
        if row[COL_LINEAR] != 0.0:
            left = zeta + A * t
            zeta, t = min(left, 0.0), max(left, 0.0) / A
        else:
            s, kappa = row[COL_S], row[COL_KAPPA]
            angle = math.atan(s * zeta) + kappa * t
            zeta, t = math.tan(min(angle, 0.0)) / s, max(angle, 0.0) / kappa
    z_max = row[COL_Z_MAX]
    rise = math.tanh(row[COL_RATE] * t)
    zeta = (zeta + z_max * rise) / (1.0 + rise * zeta / z_max)
    abs_zeta = abs(zeta)
    return direction * zeta, (A - abs_zeta * (beta * zeta + gamma * abs_zeta)) / uy


@njit(cache=True)
def _tanhc(y):
    """``tanh(sqrt(y))/sqrt(y)`` (``tan(sqrt(-y))/sqrt(-y)`` for ``y < 0``) of a complex ``y``.

    Even in ``sqrt(y)``, so analytic in ``y`` whichever root is taken. Below ``|y| = 1e-2`` its
    power series (the rest is below 1e-19): there the quotient's imaginary part would carry an
    absolute error of round-off size, far larger than the complex step where ``Re y`` is about 0
    (``c = 0``); the series, a polynomial, keeps it exact.
    """
    if abs(y) < 1e-2:
        series = _S7 * y
        series += _S6
        series = series * y + _S5
        series = series * y + _S4
        series = series * y + _S3
        series = series * y + _S2
        series = series * y + _S1
        series = series * y + _S0
        return series
    r = cmath.sqrt(y)
    return cmath.tanh(r) / r


@njit(cache=True)
def _atanhc(y):
    """``atanh(sqrt(y))/sqrt(y)`` for real ``y < 1`` (``atan`` for ``y < 0``), through the complex root."""
    r = cmath.sqrt(complex(y + _TINY, 0.0))
    return (cmath.atanh(r) / r).real


@njit(cache=True)
def _coefficients(zx, zy, ex, ey, sx, sy, A, bpg, gmb):
    """``w``, ``q = w . z`` and ``c = A w . e`` of a segment from ``z``.

    ``w_i = (beta sgn(z_i) s_i + gamma) e_i`` (``|e_i| = s_i e_i``, ``s`` the increment's signs),
    ``sgn(z_i)`` that of ``z_i``, or where ``z_i = 0`` the sign ``z_i`` takes at once, that of the
    motion: ``sgn(z_i) s_i = sgn(z_i s_i + tiny)``; ``beta sgn + gamma`` is ``bpg = beta + gamma``
    or ``gmb = gamma - beta``.
    """
    wx = (bpg if zx.real * sx > -_TINY else gmb) * ex
    wy = (bpg if zy.real * sy > -_TINY else gmb) * ey
    return wx, wy, wx * zx + wy * zy, A * (wx * ex + wy * ey)


@njit(cache=True)
def _segment(zx, zy, ex, ey, q, c, t, two_A):
    """The closed form over ``t`` (in units of uy) from ``z``: ``(z1x, z1y, crossed)``.

    ``crossed``: a component of ``z`` would change sign along the segment (then ``z1`` is not the
    end state). Without a crossing ``f`` is increasing on the segment, so a component keeps its
    sign if it has it at the end, where ``1 + 2 q v + c v^2 > 0`` and ``v`` is on its first branch.
    """
    y = c * (t * t / 4.0)
    v = 0.5 * t * _tanhc(y)
    qv, cv2 = q * v, c * v * v
    denominator = 1.0 + 2.0 * qv + cv2
    along, keep = two_A * (v + qv * v), 1.0 - cv2
    z1x, z1y = (zx * keep + along * ex) / denominator, (zy * keep + along * ey) / denominator
    # a component changed sign, 1 + 2 q v + c v^2 < 0, or a c < 0 segment's angle is past pi
    crossed = (
        min(zx.real * z1x.real, min(denominator.real, y.real + _PI2_4)) < 0.0
        or min(zy.real * z1y.real, min(denominator.real, y.real + _PI2_4)) < 0.0
    )
    return z1x, z1y, crossed


@njit(cache=True)
def _first_crossing(zx, zy, ex, ey, q, c, t, A):
    """Which component of real ``z`` reaches 0 first along the segment, and where (in units of uy).

    Component ``i`` (``z_i e_i < 0``) reaches 0 at the smallest positive root of
    ``(2 q + c T) v^2 + 2 v - T = 0``, ``T = -z_i/(A e_i)``: ``v = 1 / (s + sqrt(s^2 + 2 q s + c))``,
    ``s = 1/T``; then ``t = 2 v atanhc(c v^2)``. ``(-1, t)`` if none does before ``t``.
    """
    first, t_first = -1, math.inf
    for i in range(2):
        z, e = (zx, ex) if i == 0 else (zy, ey)
        t_cross = math.inf
        if z * e < 0.0:
            s = -A * e / z
            discriminant = s * s + 2.0 * q * s + c
            v = 1.0 / (s + math.sqrt(max(discriminant, 0.0)))
            y = c * v * v
            if discriminant >= 0.0 and y < 1.0:
                t_cross = 2.0 * v * _atanhc(y)
        if not t_cross >= 0.0:
            t_cross = math.inf
        if t_cross < t_first:
            first, t_first = i, t_cross
    if not math.isfinite(t_first):
        first = -1
    return first, min(t_first, t)


@njit(cache=True)
def _exact_2d(row, z0x, z0y, dx, dy, tangent):
    """One connector, 2-D, n = 2: ``(z1x, z1y)``, ``dz/du`` into ``tangent`` (2, 2).

    Segments of fixed signs of ``z`` in closed form. ``dz/du = dz/dL e^T + dz/de p p^T / L``:
    along ``e``, ``F(z1)/uy``; across, the imaginary part of the closed form evaluated with
    ``e + i h p``, divided by ``h`` (a complex step, exact to round-off; ``h t^2`` kept small so
    that every imaginary part stays a perturbation). An event's position does not enter it.
    """
    A, beta, gamma, uy = row[COL_A], row[COL_BETA], row[COL_GAMMA], row[COL_UY]
    sx, sy = _direction(dx, z0x), _direction(dy, z0y)
    length = math.hypot(dx, dy)
    A_uy = A / uy
    if not length > row[COL_STILL]:
        slope_x = (beta * abs(z0x) * sx + gamma * z0x) / -uy
        slope_y = (beta * abs(z0y) * sy + gamma * z0y) / -uy
        tangent[0, 0], tangent[0, 1] = z0x * slope_x + A_uy, z0x * slope_y
        tangent[1, 0], tangent[1, 1] = z0y * slope_x, z0y * slope_y + A_uy
        return z0x, z0y
    bpg, gmb, two_A = beta + gamma, gamma - beta, 2.0 * A
    ex, ey = dx / length, dy / length
    px, py = -ey, ex  # e turned by +90 degrees
    t = length / uy
    h = _STEP / max(1.0, t * t)  # Im(c t^2) stays at most about _STEP, whatever t
    ecx, ecy = complex(ex, h * px), complex(ey, h * py)
    zax, zay = complex(z0x, 0.0), complex(z0y, 0.0)
    wx, wy, q, c = _coefficients(zax, zay, ecx, ecy, sx, sy, A, bpg, gmb)
    # Segments of fixed signs: evaluate to the end; if a component of z would change sign (rare),
    # advance to where the first one reaches 0 and go on from there with its new sign; each
    # component crosses at most once, so two events at most. One call site of the closed form
    # (the compiled code inlines it: one copy keeps the compilation short).
    t_left, t_eval, advancing, events = t, t, False, 0
    zx, zy = zax, zay
    first = -1
    for _ in range(5):
        zx, zy, crossed = _segment(zax, zay, ecx, ecy, q, c, t_eval, two_A)
        if advancing:
            zax, zay = zx, zy
            if first == 0:
                zax = complex(0.0, zax.imag)  # exactly on the switching line
            elif first == 1:
                zay = complex(0.0, zay.imag)
            t_left = t_left - t_eval
            wx, wy, q, c = _coefficients(zax, zay, ecx, ecy, sx, sy, A, bpg, gmb)
            advancing, t_eval, events = False, t_left, events + 1
        elif crossed and events < 2:
            first, t_eval = _first_crossing(zax.real, zay.real, ex, ey, q.real, c.real, t_left, A)
            advancing = True
        else:
            break
    z1x, z1y = zx.real, zy.real
    # F(z1)/uy = (A e - (w . z1) z1)/uy along e, with the last segment's signs; across, dz/de p / L
    wz = wx.real * z1x + wy.real * z1y
    ax, ay = A_uy * ex - wz * (z1x / uy), A_uy * ey - wz * (z1y / uy)
    cx, cy = zx.imag / (h * length), zy.imag / (h * length)
    tangent[0, 0], tangent[0, 1] = ax * ex + cx * px, ax * ey + cx * py
    tangent[1, 0], tangent[1, 1] = ay * ex + cy * px, ay * ey + cy * py
    return z1x, z1y


# --- any other n: backward-Euler substeps ----------------------------------------------------


@njit(cache=True)
def _backward_euler_1d(row, z0, delta):
    """Newton on ``R(z) = z - z0 - Phi(z, delta)/uy = 0``, 1-D: ``(z, dR/dz)`` (NaN if it does not converge).

    Iterates are kept in ``|z| <= z_max``, where the root is; converged when the residual is at
    round-off level, so the returned ``dR/dz`` is exact at the returned ``z``.
    """
    A, beta, gamma, uy, n, z_max = row[COL_A], row[COL_BETA], row[COL_GAMMA], row[COL_UY], row[COL_N], row[COL_Z_MAX]
    tolerance = 1e-13 * (z_max + A * abs(delta) / uy)
    z = z0
    for _ in range(int(row[COL_MAX_ITERATIONS])):
        c = abs(z) ** (n - 1.0) * (beta * abs(delta) + gamma * delta * _sign(z))
        residual = z - z0 - (A * delta - c * z) / uy
        newton = 1.0 - c * (n / -uy)
        if abs(residual) <= tolerance:
            return z, newton
        z = min(max(z - residual / newton, -z_max), z_max)
    return math.nan, math.nan


@njit(cache=True)
def _substep_1d(row, z, dz, delta, d_delta, direction):
    """One substep of ``delta``: ``z`` and ``dz/du``, by ``(dR/dz) dz1 = dz0 + dPhi/ddelta / uy ddelta``."""
    A, beta, gamma, uy, n = row[COL_A], row[COL_BETA], row[COL_GAMMA], row[COL_UY], row[COL_N]
    z, newton = _backward_euler_1d(row, z, delta)
    abs_z = abs(z)
    slope = (A - abs_z ** (n - 1.0) * (beta * z * direction + gamma * abs_z)) / uy
    return z, (dz + slope * d_delta) / newton


@njit(cache=True)
def _substepped_1d(row, z, d):
    """One connector, 1-D, any n: ``(z1, dz/du)`` by backward-Euler substeps.

    Full substeps of length ``s`` along ``e``, then the remainder (``d`` itself, with derivative 1,
    when the increment is shorter than one substep).
    """
    direction = _direction(d, z)
    h, length, max_substeps = row[COL_SUBSTEP], abs(d), row[COL_MAX_SUBSTEPS]
    full, full_step, d_full, remainder, d_remainder = 0.0, 0.0, 0.0, d, 1.0
    if not length < h:
        e = d / length
        s = max(h, length / max_substeps)
        full = math.floor(length / s)
        slope = 0.0 if h >= length / max_substeps else 1.0 / max_substeps
        eet = e * e
        d_full = slope * eet + (s / max(length, s)) * (1.0 - eet)
        full_step = s * e
        remainder, d_remainder = d - full * full_step, 1.0 - full * d_full
    count = int(full)
    dz = 0.0
    for j in range(count + 1):
        delta, d_delta = (full_step, d_full) if j < count else (remainder, d_remainder)
        z, dz = _substep_1d(row, z, dz, delta, d_delta, direction)
    return z, dz


@njit(cache=True)
def _backward_euler_2d(row, z0x, z0y, dx, dy):
    """Newton on ``z - z0 - Phi(z, delta)/uy = 0``, 2-D: ``(zx, zy, dR/dz as m00, m01, m10, m11)``.

    ``Phi = A delta - r^(n-1) q_hat z`` with ``q_hat`` the Park-Wen term at the unit vector
    ``z/r`` (finite at ``z = 0`` for ``n >= 1``); ``d(r^(n-2) q z)/dz = r^(n-1) (q_hat I +
    z_hat ((n-2) q_hat z_hat + dq/dz)^T)``. Iterates pulled back radially into the ball.
    """
    A, beta, gamma, uy, n, z_max = row[COL_A], row[COL_BETA], row[COL_GAMMA], row[COL_UY], row[COL_N], row[COL_Z_MAX]
    tol_x, tol_y = 1e-13 * (z_max + A * abs(dx) / uy), 1e-13 * (z_max + A * abs(dy) / uy)
    adx, ady = abs(dx), abs(dy)
    zx, zy = z0x, z0y
    for _ in range(int(row[COL_MAX_ITERATIONS])):
        r = math.hypot(zx, zy)
        safe = r if r > 0.0 else 1.0
        hx, hy = zx / safe, zy / safe  # the unit vector (0 at z = 0)
        r_n1 = r ** (n - 1.0)
        q_hat = (beta * adx * abs(hx) + gamma * hx * dx) + (beta * ady * abs(hy) + gamma * hy * dy)
        c = r_n1 * q_hat
        res_x = zx - z0x - (A * dx - c * zx) / uy
        res_y = zy - z0y - (A * dy - c * zy) / uy
        gx = (n - 2.0) * q_hat * hx + (beta * adx * _sign(zx) + gamma * dx)
        gy = (n - 2.0) * q_hat * hy + (beta * ady * _sign(zy) + gamma * dy)
        ax, ay = r_n1 * hx, r_n1 * hy
        m00, m01 = 1.0 - (c + ax * gx) / -uy, -((ax * gy) / -uy)
        m10, m11 = -((ay * gx) / -uy), 1.0 - (c + ay * gy) / -uy
        if abs(res_x) <= tol_x and abs(res_y) <= tol_y:
            return zx, zy, m00, m01, m10, m11
        det = m00 * m11 - m01 * m10
        zx, zy = zx - (m11 * res_x + -m01 * res_y) / det, zy - (-m10 * res_x + m00 * res_y) / det
        norm = math.hypot(zx, zy)
        if norm > z_max:  # back into the ball, radially
            zx, zy = zx * (z_max / norm), zy * (z_max / norm)
    return math.nan, math.nan, math.nan, math.nan, math.nan, math.nan


@njit(cache=True)
def _substepped_2d(row, z0x, z0y, dx, dy, tangent):
    """One connector, 2-D, any n: ``(z1x, z1y)``, ``dz/du`` into ``tangent``, by backward-Euler substeps.

    Full substeps of length ``s`` along ``e``, then the remainder (``d`` itself, with derivative I,
    when the increment is shorter than one substep). Each: a backward-Euler step, then
    ``dz/du <- M^-1 (dz/du + d(Phi/uy)/d delta  d delta/d du)``, ``M = dR/dz``.
    """
    A, beta, gamma, uy, n = row[COL_A], row[COL_BETA], row[COL_GAMMA], row[COL_UY], row[COL_N]
    sx, sy = _direction(dx, z0x), _direction(dy, z0y)
    h, length, max_substeps = row[COL_SUBSTEP], math.hypot(dx, dy), row[COL_MAX_SUBSTEPS]
    full, fx, fy, f00, f01, f10, f11 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    rx, ry, r00, r01, r10, r11 = dx, dy, 1.0, 0.0, 0.0, 1.0
    if not length < h:
        ex, ey = dx / length, dy / length
        s = max(h, length / max_substeps)
        full = math.floor(length / s)
        slope = 0.0 if h >= length / max_substeps else 1.0 / max_substeps
        ratio = s / max(length, s)
        # d(s e)/d du = s'(L) e e^T + s (I - e e^T)/L
        exx, exy, eyy = ex * ex, ex * ey, ey * ey
        f00, f01 = slope * exx + ratio * (1.0 - exx), slope * exy + ratio * -exy
        f10, f11 = slope * exy + ratio * -exy, slope * eyy + ratio * (1.0 - eyy)
        fx, fy = s * ex, s * ey
        rx, ry = dx - full * fx, dy - full * fy
        r00, r01, r10, r11 = 1.0 - full * f00, -(full * f01), -(full * f10), 1.0 - full * f11
    count = int(full)
    zx, zy, t00, t01, t10, t11 = z0x, z0y, 0.0, 0.0, 0.0, 0.0
    for j in range(count + 1):
        if j < count:
            delta_x, delta_y, d00, d01, d10, d11 = fx, fy, f00, f01, f10, f11
        else:
            delta_x, delta_y, d00, d01, d10, d11 = rx, ry, r00, r01, r10, r11
        zx, zy, m00, m01, m10, m11 = _backward_euler_2d(row, zx, zy, delta_x, delta_y)
        # d(Phi/uy)/d delta = (A I - r^(n-1) z_hat (beta |z| direction + gamma z)^T) / uy
        r = math.hypot(zx, zy)
        safe = r if r > 0.0 else 1.0
        r_n1 = r ** (n - 1.0)
        ax, ay = r_n1 * (zx / safe), r_n1 * (zy / safe)
        bx, by = beta * abs(zx) * sx + gamma * zx, beta * abs(zy) * sy + gamma * zy
        g00, g01, g10, g11 = (A - ax * bx) / uy, -(ax * by) / uy, -(ay * bx) / uy, (A - ay * by) / uy
        det = m00 * m11 - m01 * m10
        # solve(M, dz + g @ d_delta), column by column
        a0, a1 = t00 + (g00 * d00 + g01 * d10), t10 + (g10 * d00 + g11 * d10)
        t00, t10 = (m11 * a0 + -m01 * a1) / det, (-m10 * a0 + m00 * a1) / det
        b0, b1 = t01 + (g00 * d01 + g01 * d11), t11 + (g10 * d01 + g11 * d11)
        t01, t11 = (m11 * b0 + -m01 * b1) / det, (-m10 * b0 + m00 * b1) / det
    tangent[0, 0], tangent[0, 1], tangent[1, 0], tangent[1, 1] = t00, t01, t10, t11
    return zx, zy


@njit(cache=True)
def _connector_1d(row, z0, u0, u):
    """One connector, 1-D: ``(force, tangent, z)``."""
    d = u - u0
    if row[COL_N] == 2.0:
        z1, dz = _exact_1d(row, z0, d)
    else:
        z1, dz = _substepped_1d(row, z0, d)
    hysteretic, alpha_k = row[COL_HYSTERETIC], row[COL_ALPHA_K]
    if alpha_k == 0.0:
        return hysteretic * z1, hysteretic * dz, z1
    return alpha_k * u + hysteretic * z1, alpha_k + hysteretic * dz, z1


@njit(cache=True)
def _connector_2d(row, z0, u0, u, force, tangent, z):
    """One connector, 2-D: its force (2), tangent (2, 2) and z (2) into the arrays given."""
    dx, dy = u[0] - u0[0], u[1] - u0[1]
    if row[COL_N] == 2.0:
        z1x, z1y = _exact_2d(row, z0[0], z0[1], dx, dy, tangent)
    else:
        z1x, z1y = _substepped_2d(row, z0[0], z0[1], dx, dy, tangent)
    hysteretic, alpha_k = row[COL_HYSTERETIC], row[COL_ALPHA_K]
    z[0], z[1] = z1x, z1y
    for a in range(2):
        for b in range(2):
            tangent[a, b] = hysteretic * tangent[a, b] + (alpha_k if a == b and alpha_k != 0.0 else 0.0)
    if alpha_k == 0.0:
        force[0], force[1] = hysteretic * z1x, hysteretic * z1y
    else:
        force[0], force[1] = alpha_k * u[0] + hysteretic * z1x, alpha_k * u[1] + hysteretic * z1y


# --- the calls -----------------------------------------------------------------------------


@njit(_SIGNATURE, cache=True)
def respond_1d(table, z0, u0, u):
    """1-D ``(force, tangent, z)`` of every connector: ``table`` (m, COLUMNS), the others (m, 1)."""
    m = u.shape[0]
    force, tangent, z = np.empty((m, 1)), np.empty((m, 1, 1)), np.empty((m, 1))
    for i in range(m):
        force[i, 0], tangent[i, 0, 0], z[i, 0] = _connector_1d(table[i], z0[i, 0], u0[i, 0], u[i, 0])
    return force, tangent, z


@njit(_SIGNATURE, cache=True)
def respond_2d(table, z0, u0, u):
    """2-D ``(force, tangent, z)`` of every connector: ``table`` (m, COLUMNS), the others (m, 2)."""
    m = u.shape[0]
    force, tangent, z = np.empty((m, 2)), np.empty((m, 2, 2)), np.empty((m, 2))
    for i in range(m):
        _connector_2d(table[i], z0[i], u0[i], u[i], force[i], tangent[i], z[i])
    return force, tangent, z


@law_kernel
def compiled_law(parameters, state, u, normal_force, n, dims, dt, force, tangent, dforce_dnormal, new_state):
    """The law as a compiled function (:func:`bearingfw.jit.law_kernel`, ``BoucWen.compiled``):
    ``parameters`` the table's rows then the largest displacement answered; the state per
    connector ``z`` then ``u`` (``dims`` each). Declines a displacement that is not a number or
    beyond that bound: ``respond`` answers it."""
    table = carray(parameters, (n * COLUMNS + 1,))
    bound = table[n * COLUMNS]
    size = n * dims
    u_, old, new = carray(u, (size,)), carray(state, (2 * size,)), carray(new_state, (2 * size,))
    f, t, e = carray(force, (size,)), carray(tangent, (size * dims,)), carray(dforce_dnormal, (size,))
    for i in range(size):
        if not -bound <= u_[i] <= bound:
            return DECLINED
    for c in range(n):
        row = table[c * COLUMNS : (c + 1) * COLUMNS]
        a, b = c * dims, (c + 1) * dims
        z0, u0 = old[2 * a : 2 * a + dims], old[2 * a + dims : 2 * b]
        if dims == 1:
            f[a], t[a], new[2 * a] = _connector_1d(row, z0[0], u0[0], u_[a])
        else:
            _connector_2d(row, z0, u0, u_[a:b], f[a:b], t[a * dims : b * dims].reshape((2, 2)), new[2 * a : 2 * a + 2])
        for j in range(dims):
            new[2 * a + dims + j] = u_[a + j]
            e[a + j] = 0.0
    return ANSWERED
