"""The fast path's Newton iteration compiled, with the laws compiled too (issue 16).

:func:`bearingfw.analysis.hht._solve_fast` in Python makes some twenty calls per Newton
iteration (the laws, their checks, a dense solve, the line search, the norms), each a few
microseconds: at a few hundred DOFs that is most of a step. When every law of a run offers a
compiled function (:class:`bearingfw.protocol.CompiledLaw`) and none uses the velocity,
:func:`solve_condensed` does the whole iteration in one call: the bearing displacements and normal
forces of ``x_lin``, the predictor, Newton with its line search and its tests, and the new
displacements ``x = x_lin - c W phi``. It follows ``_solve_fast`` step by step (the same
iterates, the same tests, the same tolerances; see :mod:`bearingfw.analysis.hht`), with one
difference of arithmetic: Newton's correction is solved in the law forces' space.

The correction (with dF/dN; without it ``E_k = 0``)::

    [ I + c S K_t     c S E_k      ] [delta ]   [g]
    [ -c V W K_t      I - c V W E_k ] [dnu   ] = [h]

is, with ``y = K_t delta + E_k dnu`` (the change of the linearised law forces), ``delta = g - c S y``,
``dnu = h + c V W y`` and the m x m system::

    (I + K_t c S - E_k c V W) y = K_t g + E_k h

whose right-hand side is also the force residual's linearisation of the convergence test, and
whose ``y`` gives the next normal forces, ``N = N_new - c kv (V W) y``. ``E_k`` has one entry per
coupled row (the row's own spring), so forming the matrix costs ``m^2`` and the LU factorisation
``2/3 m^3``, instead of ``2/3 (m + n_c)^3`` (a plain loop up to :data:`SMALL` rows, LAPACK's
blocked solve above). The predictor solves the same system with the last step's tangents; it
reuses the last correction's factors (or matrix) when they were formed from those (returned, and
handed back at the next step).

The laws are C-callable functions of one signature (:func:`bearingfw.jit.law_signature`), passed
by their addresses (:func:`_call_law`): this module is compiled once for every law and cached. A law
function that declines (a nonzero return), a non-finite iterate, a singular correction or no
convergence returns a status instead: the step is then solved again by the Python iteration,
which reports the failure as it always has.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

from bearingfw.jit import ANSWERED

#: :func:`solve_condensed`'s status
CONVERGED, DECLINED, NOT_FINITE, SINGULAR, NOT_CONVERGED = 0, 1, 2, 3, 4


@njit(cache=True)
def _inf(a):
    """``max |a|``, NaN if any entry is NaN (as numpy's maximum reduction gives)."""
    largest = 0.0
    for i in range(a.shape[0]):
        value = abs(a[i])
        if value != value:
            return value
        if value > largest:
            largest = value
    return largest


@njit(cache=True)
def _finite(a):
    for i in range(a.shape[0]):
        if not math.isfinite(a[i]):
            return False
    return True


@njit(cache=True)
def _tangent_times(tangent, starts, dims, offsets, vector, out):
    """``out = K_t vector`` (``tangent`` flat, block by block)."""
    for c in range(starts.shape[0]):
        s, k, o = starts[c], dims[c], offsets[c]
        for a in range(k):
            total = 0.0
            for b in range(k):
                total += tangent[o + a * k + b] * vector[s + b]
            out[s + a] = total


@njit(cache=True)
def _reduced_matrix(tangent, starts, dims, offsets, cS, ev, ecol, cVW, J):
    """``J = I + K_t c S - E_k c V W`` (``E_k``: ``ev`` at ``(row, ecol[row])``)."""
    m = cS.shape[0]
    for c in range(starts.shape[0]):
        s, k, o = starts[c], dims[c], offsets[c]
        for a in range(k):
            i = s + a
            for j in range(m):
                J[i, j] = 0.0
            for b in range(k):
                t = tangent[o + a * k + b]
                if t != 0.0:
                    for j in range(m):
                        J[i, j] += t * cS[s + b, j]
    for i in range(m):
        J[i, i] += 1.0
        e = ev[i]
        if e != 0.0:
            col = ecol[i]
            for j in range(m):
                J[i, j] -= e * cVW[col, j]


@njit(cache=True)
def _lu(J, piv):
    """LU factors of ``J`` in place, with partial pivoting (LAPACK's ``getf2``); False if singular."""
    n = J.shape[0]
    for k in range(n):
        p, big = k, abs(J[k, k])
        for i in range(k + 1, n):
            if abs(J[i, k]) > big:
                p, big = i, abs(J[i, k])
        piv[k] = p
        if not big > 0.0:  # zero, or NaN
            return False
        if p != k:
            for j in range(n):
                J[k, j], J[p, j] = J[p, j], J[k, j]
        inverse = 1.0 / J[k, k]
        for i in range(k + 1, n):
            J[i, k] *= inverse
        for i in range(k + 1, n):
            factor = J[i, k]
            if factor != 0.0:
                for j in range(k + 1, n):
                    J[i, j] -= factor * J[k, j]
    return True


@njit(cache=True)
def _lu_solve(J, piv, b):
    """``b = J^-1 b`` in place with :func:`_lu`'s factors."""
    n = J.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(n):
        total = b[i]
        for j in range(i):
            total -= J[i, j] * b[j]
        b[i] = total
    for i in range(n - 1, -1, -1):
        total = b[i]
        for j in range(i + 1, n):
            total -= J[i, j] * b[j]
        b[i] = total / J[i, i]


@intrinsic
def _call_law(typingctx, address, parameters, state, u, normal_force, n, dims, dt, force, tangent, dfdn, new_state):
    """Call the compiled law at ``address`` (:func:`bearingfw.jit.law_signature`) with the data of
    these arrays. The address is a run-time value, so what calls this is cached on disk like any
    kernel (numba caches no function that takes other compiled functions as arguments)."""
    signature = types.int64(address, parameters, state, u, normal_force, n, dims, dt, force, tangent, dfdn, new_state)

    def codegen(context, builder, sig, args):
        double_p, i64 = ir.DoubleType().as_pointer(), ir.IntType(64)
        function = ir.FunctionType(i64, [double_p] * 4 + [i64, i64, ir.DoubleType()] + [double_p] * 4)
        pointer = builder.inttoptr(args[0], function.as_pointer())
        values = [
            context.make_array(ty)(context, builder, value).data if isinstance(ty, types.Array) else value
            for ty, value in zip(sig.args[1:], args[1:])
        ]
        return builder.call(pointer, values)

    return signature, codegen


#: Up to this size the reduced system is factorised by :func:`_lu` (and the factors kept for the
#: predictor); above it LAPACK's blocked solve (numpy's ``solve``) is faster than that plain loop.
SMALL = 48


@njit(cache=True)
def _solve(J, piv, y):
    """``y = J^-1 y``; False if ``J`` is singular (or not finite). Small: ``J`` becomes its LU factors
    (:func:`_lu`); large: ``J`` is kept and solved by LAPACK (the predictor solves with it again)."""
    if J.shape[0] <= SMALL:
        if not _lu(J, piv):
            return False
        _lu_solve(J, piv, y)
        return True
    try:
        y[:] = np.linalg.solve(J, y)
    except Exception:  # numpy's LinAlgError: singular, or not finite
        return False
    return True


@njit(cache=True)
def _solve_again(J, piv, y):
    """``y = J^-1 y`` with what :func:`_solve` left of ``J`` (its LU factors, or ``J`` itself)."""
    if J.shape[0] <= SMALL:
        _lu_solve(J, piv, y)
        return True
    try:
        y[:] = np.linalg.solve(J, y)
    except Exception:
        return False
    return True


@njit(cache=True)
def _call_laws(laws, groups, parameters, springs, states, d, N, h, f, tangent, dfdn, new_states, contact):
    """Every law group at ``(d, N)``: forces, tangents, dF/dN and trial states into the given rows;
    False when a law declines or a normal force is not finite."""
    for gi in range(laws.shape[0]):
        row, n, dims, toff, first, poff, soff = groups[gi]
        for i in range(n):
            value = N[springs[first + i]]
            if not math.isfinite(value):
                return False
            contact[first + i] = value if value > 0.0 else 0.0
        status = _call_law(
            laws[gi], parameters[poff:], states[soff:], d[row:], contact[first:], n, dims, h,
            f[row:], tangent[toff:], dfdn[row:], new_states[soff:],
        )  # fmt: skip
        if status != ANSWERED:  # declined, or an exception escaped it (which returns 0)
            return False
    return True


@njit(cache=True)
def solve_condensed(
    laws, groups, parameters, springs, starts, dims, offsets, ecol, ekv, coupled, kv_coupled,
    bv_indptr, bv_indices, bv_data, d0, N0, kv, f0,
    cSN, cW, cVW,
    x_lin, offset, f_n, d_n, N_n, tangent_n, ev_n, states_n, lu_n, piv_n, reuse,
    h, c, force_scale, tol_force, tol_displacement, d0_size, max_iterations, backtracks_max, armijo, round_,
):  # fmt: skip
    """One step's bearing displacements by Newton on the condensed system (module docstring).

    Returns ``(status, iterations, halvings, x, f, d, N, phi, tangent, ev, states, lu, piv)``: the
    new displacements, law forces, bearing displacements, normal forces, ``phi = f - f_0``, the
    flat tangent, ``E_k`` per row (``ev``), the packed law states and the LU factors of the last
    correction's matrix (for the next step's predictor). ``tangent_n`` empty: no tangents yet (the
    first step); ``reuse``: ``lu_n``, ``piv_n`` are the factors of the predictor's matrix."""
    m = cSN.shape[1]
    nv = cSN.shape[0] - m
    nc = coupled.shape[0]
    size_t = tangent_n.shape[0] if tangent_n.shape[0] else (offsets[-1] + dims[-1] * dims[-1] if starts.shape[0] else 0)
    size_s = states_n.shape[0]

    # ---- d_lin, N_lin: [B; V] x_lin (+ the support motion's offset)
    d_lin = np.empty(m)
    N_lin = np.empty(nv)
    for r in range(m + nv):
        total = 0.0
        for q in range(bv_indptr[r], bv_indptr[r + 1]):
            total += bv_data[q] * x_lin[bv_indices[q]]
        if offset.shape[0]:
            total = total + offset[r]
        if r < m:
            d_lin[r] = d0[r] + total
        else:
            N_lin[r - m] = N0[r - m] - kv[r - m] * total
    size = max(_inf(d_lin), d0_size)
    round_d = round_ * size
    n_round = round_ * _inf(N_lin)

    # ---- three trial slots (current, line-search trial, best so far)
    D = np.empty((3, m))
    NN = np.empty((3, nv))
    F = np.empty((3, m))
    PHI = np.empty((3, m))
    TAN = np.empty((3, size_t))
    DFDN = np.empty((3, m))
    EV = np.zeros((3, m))
    HAS_E = np.zeros(3, dtype=np.bool_)
    G = np.empty((3, m))
    NNEW = np.empty((3, nv))
    GAP = np.empty((3, nc))
    ST = np.empty((3, size_s))
    MERIT = np.empty(3)
    TINY = np.zeros(3, dtype=np.bool_)
    FINITE = np.zeros(3, dtype=np.bool_)
    contact = np.empty(springs.shape[0])

    J = np.empty((m, m))
    piv = np.empty(m, dtype=np.int64)
    y = np.empty(m)
    work = np.empty(m)
    delta = np.zeros(m)
    dnu = np.empty(nc)
    dN = np.empty(nv)

    # ---- the predictor (hht._predict): the law forces linearised about the last step's point
    cur = 0
    d_p, N_p = D[cur], NN[cur]
    predicted = False
    if tangent_n.shape[0]:
        held = np.empty(m)
        _tangent_times(tangent_n, starts, dims, offsets, d_n, work)
        has_e_n = False
        for i in range(m):
            held[i] = (f_n[i] - f0[i]) - work[i]
            if ev_n[i] != 0.0:
                has_e_n = True
        if has_e_n:  # held - E nu_n
            for i in range(m):
                if ev_n[i] != 0.0:
                    col = ecol[i]
                    held[i] -= ev_n[i] * (N_n[coupled[col]] / kv_coupled[col])
        rhs_nu = np.empty(nc)
        for i in range(m):
            total = 0.0
            for j in range(m):
                total += cSN[i, j] * held[j]
            d_p[i] = d_lin[i] - total
        if has_e_n:
            for i in range(nc):
                total = 0.0
                for j in range(m):
                    total += cVW[i, j] * held[j]
                rhs_nu[i] = N_lin[coupled[i]] / kv_coupled[i] + total
        # y = K_t d + E nu from (I + K_t cS - E_k cVW) y = K_t rhs_d + E_k rhs_nu
        _tangent_times(tangent_n, starts, dims, offsets, d_p, y)
        if has_e_n:
            for i in range(m):
                if ev_n[i] != 0.0:
                    y[i] += ev_n[i] * rhs_nu[ecol[i]]
        if reuse:  # the last correction's matrix: its factors (or itself) as _solve left them
            ok = _solve_again(lu_n, piv_n, y)
        else:
            _reduced_matrix(tangent_n, starts, dims, offsets, cSN[:m], ev_n, ecol, cVW, J)
            ok = _solve(J, piv, y)
        if ok:
            for i in range(m):
                total = 0.0
                for j in range(m):
                    total += cSN[i, j] * y[j]
                d_p[i] = d_p[i] - total
            nu = np.empty(nc)
            if has_e_n:
                for i in range(nc):
                    total = 0.0
                    for j in range(m):
                        total += cVW[i, j] * y[j]
                    nu[i] = rhs_nu[i] + total
            if _finite(d_p) and _finite(nu[: nc if has_e_n else 0]):
                for i in range(m):
                    work[i] = held[i] + y[i]
                for r in range(nv):
                    total = 0.0
                    for j in range(m):
                        total += cSN[m + r, j] * work[j]
                    N_p[r] = N_lin[r] + total
                if has_e_n:
                    for i in range(nc):
                        N_p[coupled[i]] = kv_coupled[i] * nu[i]
                predicted = True
    if not predicted:  # the last law forces held
        for r in range(m + nv):
            total = 0.0
            for j in range(m):
                total += cSN[r, j] * (f_n[j] - f0[j])
            if r < m:
                d_p[r] = d_lin[r] - total
            else:
                N_p[r - m] = N_lin[r - m] + total

    # ---- an iterate: the laws at (D[slot], NN[slot]) and what they give (hht_kernels.absorb)
    def evaluate(slot):
        d, N = D[slot], NN[slot]
        if not _call_laws(laws, groups, parameters, springs, states_n, d, N, h, F[slot], TAN[slot], DFDN[slot], ST[slot], contact):
            return False
        f, phi, g, N_new, gap, ev = F[slot], PHI[slot], G[slot], NNEW[slot], GAP[slot], EV[slot]
        for j in range(m):
            phi[j] = f[j] - f0[j]
        finite = True
        merit = 0.0
        for r in range(m + nv):
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
        tan = TAN[slot]
        for j in range(size_t):
            if not math.isfinite(tan[j]):
                finite = False
        has_e = False
        if nc:
            for i in range(nc):
                value = (N[coupled[i]] - N_new[coupled[i]]) / kv_coupled[i]
                gap[i] = value
                merit += value * value
            dfdn = DFDN[slot]
            for i in range(m):
                col = ecol[i]
                value = 0.0
                if col >= 0 and N[coupled[col]] > 0.0:
                    value = dfdn[i] * ekv[i]
                    if not math.isfinite(value):
                        finite = False
                ev[i] = value
                if value != 0.0:
                    has_e = True
        HAS_E[slot] = has_e
        merit = math.sqrt(merit)
        MERIT[slot] = merit
        TINY[slot] = merit <= round_d
        FINITE[slot] = finite
        return True

    if not evaluate(cur):
        return DECLINED, 0, 0, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
    halvings = 0
    for it in range(1, max_iterations + 1):
        if not FINITE[cur]:
            return NOT_FINITE, it, halvings, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
        d, N, f, g, tan, ev, gap = D[cur], NN[cur], F[cur], G[cur], TAN[cur], EV[cur], GAP[cur]
        # the correction: y from the reduced system, its right-hand side the linearised residual
        _tangent_times(tan, starts, dims, offsets, g, y)
        for i in range(m):
            if ev[i] != 0.0:
                y[i] += ev[i] * gap[ecol[i]]
        linear_residual = _inf(y)
        _reduced_matrix(tan, starts, dims, offsets, cSN[:m], ev, ecol, cVW, J)
        if not _solve(J, piv, y):
            return SINGULAR, it, halvings, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
        for i in range(m):
            total = 0.0
            for j in range(m):
                total += cSN[i, j] * y[j]
            delta[i] = g[i] - total
        for i in range(nc):
            total = 0.0
            for j in range(m):
                total += cVW[i, j] * y[j]
            dnu[i] = gap[i] + total
        # the tests (hht_kernels.displacement_converged, then the normal and force residuals)
        largest, moved, nan = 0.0, 0.0, False
        for i in range(m):
            a, b, e = abs(delta[i]), abs(d[i] - d_n[i]), abs(d[i] - d0[i])
            if a != a or b != b or e != e:
                nan = True
            largest = max(largest, a)
            moved = max(moved, b, e)
        if not nan and largest <= tol_displacement * moved + round_d:
            N_new = NNEW[cur]
            change = 0.0
            for r in range(nv):
                value = abs(N_new[r] - N[r])
                change = value if (value > change or value != value) else change
            if change <= tol_force * max(_inf(N), _inf(N_new)) + n_round and (
                c * linear_residual <= tol_force * max(force_scale, _inf(f)) + round_ * c * _inf(tan) * size
            ):
                phi = PHI[cur]
                x = np.empty(x_lin.shape[0])
                for i in range(x.shape[0]):
                    total = 0.0
                    for j in range(m):
                        total += cW[i, j] * phi[j]
                    x[i] = x_lin[i] - total
                return (
                    CONVERGED, it, halvings, x, F[cur].copy(), d.copy(), N.copy(), phi.copy(), tan.copy(),
                    ev.copy(), ST[cur].copy(), J, piv,
                )  # fmt: skip
        # the next normal forces: dN = c kv (V W) y, the coupled springs' from dnu
        for r in range(nv):
            total = 0.0
            for j in range(m):
                total += cSN[m + r, j] * y[j]
            dN[r] = total
        # line search (hht._line_search) in the two other slots
        base = cur
        trial = (cur + 1) % 3
        spare = (cur + 2) % 3
        best = -1
        lam = 1.0
        accepted = -1
        for k in range(backtracks_max + 1):
            dt_, Nt = D[trial], NN[trial]
            for i in range(m):
                dt_[i] = d[i] - lam * delta[i]
            for r in range(nv):
                Nt[r] = NNEW[base][r] - lam * dN[r]
            for i in range(nc):
                Nt[coupled[i]] = N[coupled[i]] - lam * (kv_coupled[i] * dnu[i])
            if not evaluate(trial):
                return DECLINED, it, halvings, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
            if not FINITE[trial] or TINY[trial] or MERIT[trial] <= (1.0 - armijo * lam) * MERIT[base]:
                accepted = trial
                halvings += k
                break
            if best < 0:
                best, trial = trial, spare
            elif MERIT[trial] < MERIT[best]:
                best, trial = trial, best
            lam *= 0.5
        if accepted < 0:
            accepted = best
            halvings += backtracks_max
        cur = accepted
    return NOT_CONVERGED, max_iterations, halvings, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
