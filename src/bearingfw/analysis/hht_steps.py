"""Many HHT steps in one compiled call (issue 16).

A step of :func:`bearingfw.analysis.hht.step` is four compiled calls (the right-hand side, the
back-substitution, the Newton iteration, everything after it) joined by Python: the state
object, the energy, the bookkeeping of the time loop. At a thousand DOFs that Python costs about
what the arithmetic does. :func:`advance` makes the same calls, in the same order, for a run of
consecutive steps of one size, and keeps every step's arrays for the recorders.

It runs when a step needs nothing Python does (:func:`bearingfw.analysis.hht.steps_plan`; the
time loop calls it through :func:`bearingfw.analysis.hht.advance_steps`): the fast path, uniform
support motion, no law using the velocity, and the laws either absent, linear (folded into the
factorised matrix) or compiled (:class:`~bearingfw.analysis.hht.CompiledLaws`). It stops at the
first step it cannot finish (a law declines, a non-finite iterate, no convergence): that step is
then solved by :func:`~bearingfw.analysis.hht.step`, which reports failures and halves the step
as it always has (as it does any step of a run that raised).

Modes: :data:`NO_LAWS` (no bearing directions), :data:`FOLDED` (linear laws in ``A``: the law
displacements and forces follow from ``x``), :data:`NEWTON` (the compiled Newton iteration,
:func:`~bearingfw.analysis.hht_newton.solve_condensed`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from bearingfw.analysis.hht_kernels import back_substitute, commit, predict
from bearingfw.analysis.hht_newton import CONVERGED, _inf, solve_condensed

NO_LAWS, FOLDED, NEWTON = 0, 1, 2


@njit(cache=True)
def _largest(a, b, c):
    """Python's ``max(a, b, c)`` (the first of equal or unordered values kept)."""
    out = a
    if b > out:
        out = b
    if c > out:
        out = c
    return out


@njit(cache=True)
def advance(
    mode, factors, T, weights, mk, bt, beta_h2, gamma_h, a0, a1, alpha, force_floor, linear,
    laws, groups, parameters, springs, starts, dims, offsets, ecol, ekv, coupled, kv_coupled,
    bv_indptr, bv_indices, bv_data, d0, N0, kv, f0, cSN, cW, cVW,
    addresses, trans, tol_force, tol_displacement, d0_size, max_iterations, backtracks_max, armijo, round_,
    h, start, load_n, energy_n, f_n, d_n, N_n, tangent_n, ev_n, states_n, lu_n, piv_n, reuse,
    loads, OUT, F, D, NN, S, ENERGY, ITERATIONS, BACKTRACKS,
):  # fmt: skip
    """Advance from the committed instant ``start`` (the rows of :func:`~bearingfw.analysis.hht_kernels.commit`'s
    ``out``, with ``load_n``, ``energy_n`` = (kinetic, strain, damping, bearings, input, numerical),
    and the law quantities ``f_n``, ``d_n``, ``N_n``, the Newton iteration's carried arrays) by one step
    per row of ``loads`` (the dynamic load at each step's end).

    Step ``j`` writes ``OUT[j]`` (commit's rows), its law forces, displacements, normal forces and
    packed states into ``F[j]``, ``D[j]``, ``NN[j]``, ``S[j]``, its energy row (``Energy.row``'s seven
    columns) into ``ENERGY[j]`` and its Newton iterations and halvings. Returns the number of steps
    done (fewer than asked when one could not be finished) and, after the last of them, what the
    next step's predictor takes: the tangent, ``E_k`` per row, the LU factors and pivots and
    ``phi``."""
    n = start.shape[1]
    c = 1.0 + alpha
    rts = np.empty((3, n))
    x_lin = np.empty(n)
    terms = np.empty(7)
    previous = start
    phi = np.zeros(f0.shape[0])
    for j in range(loads.shape[0]):
        load1 = loads[j]
        products_n = previous[3:9].reshape((2, 3, n))
        predict(previous[0:3], products_n, T, weights, load1, load_n, previous[9], c, alpha, rts)
        back_substitute(factors[0], factors[1], factors[2], factors[3], factors[4], factors[5], factors[6], factors[7],
                        rts[0], x_lin)  # fmt: skip
        iterations = halvings = 0
        if mode == NEWTON:
            force_scale = _largest(_inf(load1), _inf(f_n), force_floor)
            status, iterations, halvings, x, f, d, N, phi, tangent, ev, states, lu, piv = solve_condensed(
                laws, groups, parameters, springs, starts, dims, offsets, ecol, ekv, coupled, kv_coupled,
                bv_indptr, bv_indices, bv_data, d0, N0, kv, f0, cSN, cW, cVW,
                x_lin, np.zeros(0), f_n, d_n, N_n, tangent_n, ev_n, states_n, lu_n, piv_n, reuse, addresses, trans,
                h, c, force_scale, tol_force, tol_displacement, d0_size,
                max_iterations, backtracks_max, armijo, round_,
            )  # fmt: skip
            if status != CONVERGED:
                return j, tangent_n, ev_n, lu_n, piv_n, phi
            tangent_n, ev_n, states_n, lu_n, piv_n, reuse = tangent, ev, states, lu, piv, True
        else:
            x = x_lin  # commit copies it; the buffer is next written at the next step
            m = d0.shape[0]
            f, d, N = F[j], D[j], NN[j]  # every row written below (none without laws: m = 0)
            for r in range(m + N0.shape[0]):
                total = 0.0
                for q in range(bv_indptr[r], bv_indptr[r + 1]):
                    total += bv_data[q] * x[bv_indices[q]]
                if r < m:
                    d[r] = d0[r] + total
                else:
                    N[r - m] = N0[r - m] - kv[r - m] * total
            if mode == FOLDED:
                for i in range(m):
                    total = 0.0
                    for k in range(m):
                        total += linear[i, k] * (d[k] - d0[k])
                    phi[i] = total
                    f[i] = f0[i] + total
        for i in range(n):
            if not math.isfinite(x[i]):
                return j, tangent_n, ev_n, lu_n, piv_n, phi
        out = OUT[j]
        commit(
            x, rts[1], rts[2], previous[0:3], products_n, T, mk[0], mk[1], mk[2], bt[0], bt[1], bt[2],
            f0 if mode == NO_LAWS else phi, mode != NO_LAWS,
            load_n, load1, previous[10], previous[5], previous[9], previous[11], previous[12], previous[13],
            beta_h2, gamma_h, a0, a1, alpha, out, terms,
        )  # fmt: skip
        # energy.accumulate, then Energy.row
        kinetic, strain = terms[0], terms[1]
        damping = energy_n[2] + terms[2]
        bearings = energy_n[3] + terms[3]
        work_input = energy_n[4] + terms[4]
        numerical = energy_n[5] + (terms[5] - (kinetic - energy_n[0]) - terms[6])
        energy_n = np.array([kinetic, strain, damping, bearings, work_input, numerical])
        row = ENERGY[j]
        row[0], row[1], row[2], row[3], row[4] = kinetic, strain, damping, bearings, work_input
        row[5] = work_input - (kinetic + strain + damping + bearings)
        row[6] = numerical
        if mode == NEWTON:
            F[j] = f
            D[j] = d
            NN[j] = N
            S[j] = states_n
        ITERATIONS[j] = iterations
        BACKTRACKS[j] = halvings
        f_n, d_n, N_n = F[j], D[j], NN[j]
        load_n = load1
        previous = out
    return loads.shape[0], tangent_n, ev_n, lu_n, piv_n, phi
