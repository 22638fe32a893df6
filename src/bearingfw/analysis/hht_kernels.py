"""The vector arithmetic of one HHT step, compiled with numba (issue 16).

:func:`bearingfw.analysis.hht.step` is a back-substitution, the bearing laws, and some thirty
operations on vectors of the free DOFs: Newmark's predictors, the right-hand side, the new
velocity and acceleration, the products ``M [x, v, a]`` and ``K [x, v, a]``, the damping and
out-of-balance forces and the energy terms. As numpy calls each of those costs a microsecond or
more of dispatch, which at a few thousand DOFs is more than its arithmetic; together they cost
about what the back-substitution does. Here they are two loops over the DOFs:

* :func:`predict`: ``xt``, ``vt`` and ``r`` (before the solve);
* :func:`commit`: everything after it, with the one sparse product of a step (``[M; K] x``) and
  ``B^T phi`` as plain CSR loops.

The formulas are those of :mod:`bearingfw.analysis.hht` (its docstring), element by element in
the same order, so ``x``, ``v`` and ``a`` are those the numpy code gave to round-off (a dot
product summed in another order). The bearing work is ``dx . B^T (phi_n + phi_{n+1}) / 2``,
which equals ``(B dx) . (phi_n + phi_{n+1}) / 2`` without the product with ``B``.

Each kernel has one explicit signature (C-contiguous float64 arrays; CSR index arrays as uint32:
an unsigned index needs no test for a negative one, which halves a sparse product's time), so one
machine-code version is compiled and cached on disk (:func:`bearingfw.jit.kernel`);
:mod:`bearingfw.analysis.hht` imports this module at the first step, not at its own import
(numba's import costs a few tenths of a second).
"""

from __future__ import annotations

import math

import numpy as np

from numba import njit

from bearingfw.jit import kernel

_V = "float64[::1]"
_M2 = "float64[:, ::1]"
_M3 = "float64[:, :, ::1]"
_I = "uint32[::1]"

#: ``(xva, products, T, weights, load1, load0, Bt_phi, c, alpha, out)``
_PREDICT = f"void({_M2}, {_M3}, {_M2}, {_V}, {_V}, {_V}, {_V}, float64, float64, {_M2})"


@kernel(_PREDICT)
def predict(xva, products, T, weights, load1, load0, Bt_phi, c, alpha, out):
    """Newmark's predictors ``[xt; vt] = T [x; v; a]`` and the right-hand side
    ``r = weights . [M x, M v, M a, K x, K v, K a] + c F_{n+1} - alpha F_n + alpha B^T phi_n``
    (:func:`bearingfw.analysis.hht.effective_rhs`), into the rows of ``out`` (3, n): ``r, xt, vt``.

    The kernels write into arrays the caller gives: a returned array costs about a microsecond
    to hand back to Python, more than a row of this loop."""
    n = xva.shape[1]
    r, xt, vt = out[0], out[1], out[2]
    for i in range(n):
        x, v, a = xva[0, i], xva[1, i], xva[2, i]
        xt[i] = T[0, 0] * x + T[0, 1] * v + T[0, 2] * a
        vt[i] = T[1, 0] * x + T[1, 1] * v + T[1, 2] * a
        value = (
            weights[0] * products[0, 0, i]
            + weights[1] * products[0, 1, i]
            + weights[2] * products[0, 2, i]
            + weights[3] * products[1, 0, i]
            + weights[4] * products[1, 1, i]
            + weights[5] * products[1, 2, i]
        )
        value = value + c * load1[i]
        if alpha != 0.0:
            value = value - alpha * load0[i] + alpha * Bt_phi[i]
        r[i] = value


#: rows of :func:`commit`'s ``out``: ``x, v, a``, ``M [x, v, a]``, ``K [x, v, a]``, ``B^T phi``,
#: the damping force, ``G``, ``rho``, ``ae``
ROWS = 14

_COMMIT = (
    "void("
    f"{_V}, {_V}, {_V}, {_M2}, {_M3}, {_M2}, {_I}, {_I}, {_V}, "  # x, xt, vt, xva_n, products_n, T, [M; K] CSR
    f"{_I}, {_I}, {_V}, {_V}, boolean, "  # B^T CSR, phi, has_bearings
    f"{_V}, {_V}, {_V}, {_V}, {_V}, {_V}, {_V}, "  # load_n, load1, Cv_n, Ma_n, Bt_phi_n, G_n, rho_n
    f"{_V}, float64, float64, float64, float64, float64, "  # ae_n, beta h^2, gamma h, a0, a1, alpha
    f"{_M2}, {_V})"  # out (ROWS, n), energy terms (7)
)


@kernel(_COMMIT)
def commit(
    x, xt, vt, xva_n, products_n, T, mk_indptr, mk_indices, mk_data,
    bt_indptr, bt_indices, bt_data, phi, has_bearings,
    load_n, load1, Cv_n, Ma_n, Bt_phi_n, G_n, rho_n,
    ae_n, beta_h2, gamma_h, a0, a1, alpha, out, energy,
):  # fmt: skip
    """Everything a step computes once its displacements ``x`` are known (see the module docstring).

    Writes the rows of ``out`` (:data:`ROWS`): ``x, v, a``, ``M x, M v, M a, K x, K v, K a``,
    ``B^T phi`` (``Bt_phi_n`` again without bearings), the damping force ``C v``, ``G``, ``rho``,
    ``ae``; and into ``energy`` the terms :func:`bearingfw.analysis.energy.accumulate` takes: the kinetic
    and strain energies at the new instant, then the step's works by the trapezoidal rule of the
    damping, bearing, input, inertia (``M a``) and out-of-balance (``rho``) forces."""
    n = x.shape[0]
    xva = out[0:3]
    products = out[3:9].reshape((2, 3, n))
    Bt_phi, damping, G, rho, ae = out[9], out[10], out[11], out[12], out[13]
    kinetic = strain = work_damping = work_bearings = work_input = work_inertia = work_rho = 0.0
    for i in range(n):
        # Newmark's updates, as hht.step wrote them in numpy
        a = (x[i] - xt[i]) / beta_h2
        v = vt[i] + a * gamma_h
        xva[0, i] = x[i]
        xva[1, i] = v
        xva[2, i] = a
        # [M; K] x, row i of M then row i of K
        mx = 0.0
        for k in range(mk_indptr[i], mk_indptr[i + 1]):
            mx += mk_data[k] * x[mk_indices[k]]
        kx = 0.0
        for k in range(mk_indptr[n + i], mk_indptr[n + i + 1]):
            kx += mk_data[k] * x[mk_indices[k]]
        # the products of v and a follow from x's as the kinematics do (hht.step)
        m_xt = T[0, 0] * products_n[0, 0, i] + T[0, 1] * products_n[0, 1, i] + T[0, 2] * products_n[0, 2, i]
        m_vt = T[1, 0] * products_n[0, 0, i] + T[1, 1] * products_n[0, 1, i] + T[1, 2] * products_n[0, 2, i]
        k_xt = T[0, 0] * products_n[1, 0, i] + T[0, 1] * products_n[1, 1, i] + T[0, 2] * products_n[1, 2, i]
        k_vt = T[1, 0] * products_n[1, 0, i] + T[1, 1] * products_n[1, 1, i] + T[1, 2] * products_n[1, 2, i]
        ma = (mx - m_xt) / beta_h2
        ka = (kx - k_xt) / beta_h2
        mv = m_vt + ma * gamma_h
        kv = k_vt + ka * gamma_h
        products[0, 0, i], products[0, 1, i], products[0, 2, i] = mx, mv, ma
        products[1, 0, i], products[1, 1, i], products[1, 2, i] = kx, kv, ka
        if has_bearings:
            bp = 0.0
            for k in range(bt_indptr[i], bt_indptr[i + 1]):
                bp += bt_data[k] * phi[bt_indices[k]]
        else:
            bp = Bt_phi_n[i]
        Bt_phi[i] = bp
        cv = a0 * mv + a1 * kv
        damping[i] = cv
        g = cv + kx + bp - load1[i]
        G[i] = g
        r = -alpha * (g - G_n[i])
        rho[i] = r
        ae[i] = (a + alpha * ae_n[i]) / (1.0 + alpha) if alpha != 0.0 else a
        # the energy terms (energy.accumulate): values at the new instant, works by trapezoids
        dx = x[i] - xva_n[0, i]
        kinetic += v * mv
        strain += x[i] * kx
        work_damping += dx * (Cv_n[i] + cv)
        work_bearings += dx * (Bt_phi_n[i] + bp)
        work_input += dx * (load_n[i] + load1[i])
        work_inertia += dx * (Ma_n[i] + ma)
        work_rho += dx * (rho_n[i] + r)
    energy[0] = 0.5 * kinetic
    energy[1] = 0.5 * strain
    energy[2] = 0.5 * work_damping
    energy[3] = 0.5 * work_bearings
    energy[4] = 0.5 * work_input
    energy[5] = 0.5 * work_inertia
    energy[6] = 0.5 * work_rho


_BACK = f"void({_I}, {_I}, {_V}, {_I}, {_I}, {_V}, {_I}, {_I}, {_V}, {_V})"


@kernel(_BACK)
def back_substitute(l_indptr, l_indices, l_data, u_indptr, u_indices, u_data, perm_r, perm_c, b, out):
    """``A^-1 b`` into ``out`` from SuperLU's factors ``P_r A P_c = L U`` (scipy's ``splu``: ``L``
    unit lower and ``U`` upper triangular, as CSC with sorted rows, so a column of ``L`` starts
    with its unit diagonal and one of ``U`` ends with its pivot).

    ``L U z = P_r b``, then ``x = P_c z``: a forward and a backward substitution by columns, each
    column's entries once. SuperLU's own ``solve`` walks its supernodes through several library
    layers and costs about three times this at a thousand DOFs (issue 16)."""
    n = b.shape[0]
    z = np.empty(n)
    for i in range(n):
        z[perm_r[i]] = b[i]
    for j in range(n):
        zj = z[j]
        if zj != 0.0:
            for k in range(l_indptr[j] + 1, l_indptr[j + 1]):
                z[l_indices[k]] -= l_data[k] * zj
    for j in range(n - 1, -1, -1):
        last = u_indptr[j + 1] - 1
        zj = z[j] / u_data[last]
        z[j] = zj
        if zj != 0.0:
            for k in range(u_indptr[j], last):
                z[u_indices[k]] -= u_data[k] * zj
    for i in range(n):
        out[i] = z[perm_c[i]]


# ---- the laws' block-diagonal tangent K_t ------------------------------------------------------
# K_t is stored flat: connector k's (dims x dims) block, row by row, from offsets[k], acting on the
# rows starts[k] .. starts[k] + dims[k] - 1 of the governed directions (hht.Problem.layout).

_L = "int64[::1]"


@njit(cache=True)
def tangent_times_into(tangent, starts, dims, offsets, vector, out):
    """``out = K_t @ vector`` (also for the compiled Newton iteration, :mod:`~bearingfw.analysis.hht_newton`)."""
    for k in range(starts.shape[0]):
        s, n, o = starts[k], dims[k], offsets[k]
        for a in range(n):
            total = 0.0
            for b in range(n):
                total += tangent[o + a * n + b] * vector[s + b]
            out[s + a] = total


@kernel(f"{_V}({_V}, {_L}, {_L}, {_L}, {_V})")
def tangent_times(tangent, starts, dims, offsets, vector):
    """``K_t @ vector``."""
    out = np.empty(vector.shape[0])
    tangent_times_into(tangent, starts, dims, offsets, vector, out)
    return out


@kernel(f"{_M2}({_M2}, {_V}, {_L}, {_L}, {_L}, boolean)")
def times_tangent(matrix, tangent, starts, dims, offsets, identity):
    """``matrix @ K_t`` (``matrix``: rows x m), plus the identity in its leading square when
    ``identity`` (the condensed Jacobian ``I + c S K_t``)."""
    rows = matrix.shape[0]
    out = np.empty((rows, matrix.shape[1]))
    for k in range(starts.shape[0]):
        s, n, o = starts[k], dims[k], offsets[k]
        for r in range(rows):
            for b in range(n):
                total = 0.0
                for a in range(n):
                    total += matrix[r, s + a] * tangent[o + a * n + b]
                out[r, s + b] = total
    if identity:
        for i in range(min(rows, matrix.shape[1])):
            out[i, i] += 1.0
    return out


# ---- a Newton iterate of the condensed bearing system (hht._solve_fast) -----------------------

_ABSORB = (
    f"Tuple(({_V}, {_V}, {_V}, {_V}, float64, boolean))("
    f"{_M2}, int64, {_V}, {_V}, {_V}, {_V}, {_V}, {_V}, {_L}, {_V}, {_V})"
)


@njit(cache=True)
def absorb_into(cSN, m, f, f0, d, d_lin, N_lin, tangent, coupled, kv_coupled, N, phi, g, N_new, gap):
    """:func:`absorb` into the arrays given; returns ``(merit, finite)`` (also for the compiled
    Newton iteration, :mod:`~bearingfw.analysis.hht_newton`)."""
    rows = cSN.shape[0]
    for j in range(m):
        phi[j] = f[j] - f0[j]
    finite = True
    merit = 0.0
    for r in range(rows):
        total = 0.0
        for j in range(m):
            total += cSN[r, j] * phi[j]
        if not math.isfinite(total):
            finite = False
        if r < m:
            value = (d[r] - d_lin[r]) + total
            g[r] = value
            merit += value * value
        else:
            N_new[r - m] = N_lin[r - m] + total
    for j in range(tangent.shape[0]):
        if not math.isfinite(tangent[j]):
            finite = False
    for i in range(coupled.shape[0]):
        value = (N[coupled[i]] - N_new[coupled[i]]) / kv_coupled[i]
        gap[i] = value
        merit += value * value
    return merit, finite


@kernel(_ABSORB)
def absorb(cSN, m, f, f0, d, d_lin, N_lin, tangent, coupled, kv_coupled, N):
    """What the law forces ``f`` and tangent (flat) at the iterate ``(d, N)`` give: ``phi = f - f_0``,
    ``g = d - d_lin + c S phi``, ``N_new = N_lin + c kv (V W) phi`` (one product with ``cSN``), on
    the ``coupled`` springs ``(N - N_new) / kv``, the squared residual norm ``|g|^2 (+ |gap|^2)``, and
    whether the forces (through ``c S phi``) and the tangent are finite."""
    phi, g, N_new, gap = np.empty(m), np.empty(m), np.empty(cSN.shape[0] - m), np.empty(coupled.shape[0])
    merit, finite = absorb_into(cSN, m, f, f0, d, d_lin, N_lin, tangent, coupled, kv_coupled, N, phi, g, N_new, gap)
    return phi, g, N_new, gap, merit, finite


@kernel(f"boolean({_V}, {_V}, {_V}, {_V}, float64, float64)")
def displacement_converged(delta, d, d_n, d0, tol, round_d):
    """Newton's displacement test: ``max |delta| <= tol max(|d - d_n|, |d - d_0|) + round_d`` (false
    when any of them is not a number, as numpy's comparison of a NaN maximum is)."""
    largest = 0.0
    moved = 0.0
    for i in range(delta.shape[0]):
        step, since_n, since_0 = abs(delta[i]), abs(d[i] - d_n[i]), abs(d[i] - d0[i])
        if math.isnan(step) or math.isnan(since_n) or math.isnan(since_0):
            return False
        largest = max(largest, step)
        moved = max(moved, since_n, since_0)
    return largest <= tol * moved + round_d
