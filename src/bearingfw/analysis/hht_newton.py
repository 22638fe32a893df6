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
``2/3 m^3``, instead of ``2/3 (m + n_c)^3`` (scipy's LAPACK ``dgetrf`` and ``dgetrs``, called
through their addresses). The predictor solves the same system with the last step's tangents; it
reuses the last correction's LU factors when they were formed from those (returned, and handed
back at the next step).

The laws are C-callable functions of one signature (:func:`bearingfw.jit.law_signature`), passed
by their addresses (:func:`_call_law`): this module is compiled once for every law and cached. A law
function that declines (anything but :data:`bearingfw.jit.ANSWERED`, also what an exception
escaping it returns), a non-finite iterate, a singular correction or no convergence returns a
status instead: the step is then solved again by the Python iteration,
which reports the failure as it always has.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

from bearingfw.analysis.hht_kernels import absorb_into, displacement_converged, tangent_times_into
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


def _address_call(context, builder, sig, args):
    """Code for calling the C function at the address ``args[0]`` with the other arguments, each
    array as its data pointer: how the compiled laws and LAPACK's routines take them."""
    values = [
        context.make_array(ty)(context, builder, value).data if isinstance(ty, types.Array) else value
        for ty, value in zip(sig.args[1:], args[1:])
    ]
    void = sig.return_type == types.void
    returns = ir.VoidType() if void else context.get_value_type(sig.return_type)
    function = ir.FunctionType(returns, [value.type for value in values])
    result = builder.call(builder.inttoptr(args[0], function.as_pointer()), values)
    return context.get_dummy_value() if void else result


@intrinsic
def _call_law(typingctx, address, parameters, state, u, normal_force, n, dims, dt, force, tangent, dfdn, new_state):
    """Call the compiled law at ``address`` (:func:`bearingfw.jit.law_signature`) with the data of
    these arrays. The address is a run-time value, so what calls this is cached on disk like any
    kernel (numba caches no function that takes other compiled functions as arguments)."""
    signature = types.int64(address, parameters, state, u, normal_force, n, dims, dt, force, tangent, dfdn, new_state)
    return signature, _address_call


@intrinsic
def _getrf(typingctx, address, m, n, a, lda, ipiv, info):
    """LAPACK's ``dgetrf`` at ``address`` (scipy's, :func:`lapack`): LU factors with partial pivoting."""
    return types.void(address, m, n, a, lda, ipiv, info), _address_call


@intrinsic
def _getrs(typingctx, address, trans, n, nrhs, a, lda, ipiv, b, ldb, info):
    """LAPACK's ``dgetrs`` at ``address``: a solve with ``dgetrf``'s factors."""
    return types.void(address, trans, n, nrhs, a, lda, ipiv, b, ldb, info), _address_call


def lapack() -> np.ndarray:
    """The addresses of scipy's ``dgetrf`` and ``dgetrs`` (passed to :func:`solve_condensed`, not
    compiled in: an address differs from process to process, the cached machine code does not)."""
    from numba.extending import get_cython_function_address

    return np.array([get_cython_function_address("scipy.linalg.cython_lapack", name) for name in ("dgetrf", "dgetrs")],
                    dtype=np.int64)  # fmt: skip


#: ``dgetrs``'s ``trans``: LAPACK reads the row-major ``J`` as its transpose, so it factorises
#: ``J^T`` and solves with that transposed, i.e. with ``J``
_TRANSPOSED = np.array([ord("T")], dtype=np.uint8)


@njit(cache=True)
def _factor(addresses, J, piv, ints):
    """``J``'s LU factors in place (of ``J^T`` as LAPACK reads it); False if ``J`` is singular."""
    ints[0], ints[1] = J.shape[0], 0
    _getrf(addresses[0], ints[0:1], ints[0:1], J, ints[0:1], piv, ints[1:2])
    return ints[1] == 0


@njit(cache=True)
def _solve(addresses, J, piv, y, ints, trans):
    """``y = J^-1 y`` with :func:`_factor`'s factors of ``J``."""
    ints[0], ints[1], ints[2] = J.shape[0], 0, 1
    _getrs(addresses[1], trans, ints[0:1], ints[2:3], J, ints[0:1], piv, y, ints[0:1], ints[1:2])
    return ints[1] == 0


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
def _evaluate(slot, laws, groups, parameters, springs, states_n, h, trials, flags, contact, cSN, d_lin, N_lin, f0,
              coupled, kv_coupled, ecol, ekv, round_d):  # fmt: skip
    """An iterate: the laws at ``(D[slot], NN[slot])`` and what they give (``hht_kernels.absorb``):
    ``phi``, ``g``, ``N_new``, the coupled springs' gap, ``E_k`` per row, the residual norm and
    whether it is at round-off and finite. False when a law declined."""
    D, NN, F, PHI, TAN, DFDN, EV, G, NNEW, GAP, ST, MERIT = trials
    TINY, FINITE = flags
    m = D.shape[1]
    nc = coupled.shape[0]
    d, N = D[slot], NN[slot]
    if not _call_laws(laws, groups, parameters, springs, states_n, d, N, h, F[slot], TAN[slot], DFDN[slot], ST[slot], contact):
        return False
    f, phi, g, N_new, gap, ev, tan = F[slot], PHI[slot], G[slot], NNEW[slot], GAP[slot], EV[slot], TAN[slot]
    merit, finite = absorb_into(cSN, m, f, f0, d, d_lin, N_lin, tan, coupled, kv_coupled, N, phi, g, N_new, gap)
    if nc:
        dfdn = DFDN[slot]
        for i in range(m):
            col = ecol[i]
            value = 0.0
            if col >= 0 and N[coupled[col]] > 0.0:
                value = dfdn[i] * ekv[i]
                if not math.isfinite(value):
                    finite = False
            ev[i] = value
    merit = math.sqrt(merit)
    MERIT[slot] = merit
    TINY[slot] = merit <= round_d
    FINITE[slot] = finite
    return True


@njit(cache=True)
def solve_condensed(
    laws, groups, parameters, springs, starts, dims, offsets, ecol, ekv, coupled, kv_coupled,
    bv_indptr, bv_indices, bv_data, d0, N0, kv, f0,
    cSN, cW, cVW,
    x_lin, offset, f_n, d_n, N_n, tangent_n, ev_n, states_n, lu_n, piv_n, reuse, addresses, trans,
    h, c, force_scale, tol_force, tol_displacement, d0_size, max_iterations, backtracks_max, armijo, round_,
):  # fmt: skip
    """One step's bearing displacements by Newton on the condensed system (module docstring).

    Returns ``(status, iterations, halvings, x, f, d, N, phi, tangent, ev, states, lu, piv)``: the
    new displacements, law forces, bearing displacements, normal forces, ``phi = f - f_0``, the
    flat tangent, ``E_k`` per row (``ev``), the packed law states and the LU factors of the last
    correction's matrix (for the next step's predictor). ``tangent_n`` empty: no tangents yet (the
    first step); ``reuse``: ``lu_n``, ``piv_n`` are the factors of the predictor's matrix;
    ``addresses``: LAPACK's (:func:`lapack`), ``trans``: :data:`_TRANSPOSED`."""
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
    G = np.empty((3, m))
    NNEW = np.empty((3, nv))
    GAP = np.empty((3, nc))
    ST = np.empty((3, size_s))
    MERIT = np.empty(3)
    TINY = np.zeros(3, dtype=np.bool_)
    FINITE = np.zeros(3, dtype=np.bool_)
    contact = np.empty(springs.shape[0])

    J = np.empty((m, m))
    piv = np.empty(m, dtype=np.int32)
    ints = np.empty(3, dtype=np.int32)  # LAPACK's integer arguments
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
        tangent_times_into(tangent_n, starts, dims, offsets, d_n, work)
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
        tangent_times_into(tangent_n, starts, dims, offsets, d_p, y)
        if has_e_n:
            for i in range(m):
                if ev_n[i] != 0.0:
                    y[i] += ev_n[i] * rhs_nu[ecol[i]]
        if reuse:  # the last correction's matrix: its factors
            ok = _solve(addresses, lu_n, piv_n, y, ints, trans)
        else:
            _reduced_matrix(tangent_n, starts, dims, offsets, cSN[:m], ev_n, ecol, cVW, J)
            ok = _factor(addresses, J, piv, ints) and _solve(addresses, J, piv, y, ints, trans)
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

    trials = (D, NN, F, PHI, TAN, DFDN, EV, G, NNEW, GAP, ST, MERIT)
    flags = (TINY, FINITE)
    common = (laws, groups, parameters, springs, states_n, h, trials, flags, contact, cSN, d_lin, N_lin, f0,
              coupled, kv_coupled, ecol, ekv, round_d)  # fmt: skip
    if not _evaluate(cur, *common):
        return DECLINED, 0, 0, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
    halvings = 0
    for it in range(1, max_iterations + 1):
        if not FINITE[cur]:
            return NOT_FINITE, it, halvings, x_lin, f_n, d_n, N_n, f_n, tangent_n, ev_n, states_n, J, piv
        d, N, f, g, tan, ev, gap = D[cur], NN[cur], F[cur], G[cur], TAN[cur], EV[cur], GAP[cur]
        # the correction: y from the reduced system, its right-hand side the linearised residual
        tangent_times_into(tan, starts, dims, offsets, g, y)
        for i in range(m):
            if ev[i] != 0.0:
                y[i] += ev[i] * gap[ecol[i]]
        linear_residual = _inf(y)
        _reduced_matrix(tan, starts, dims, offsets, cSN[:m], ev, ecol, cVW, J)
        if not (_factor(addresses, J, piv, ints) and _solve(addresses, J, piv, y, ints, trans)):
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
        if displacement_converged(delta, d, d_n, d0, tol_displacement, round_d):
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
            if not _evaluate(trial, *common):
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
