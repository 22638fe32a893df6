"""One Hilber-Hughes-Taylor step with Newton-Raphson on the bearing laws.

Equation of motion on the free DOFs, measured from the preload (``x = q - q_0``, see
:mod:`bearingfw.analysis.transient`)::

    M a + C v + K x + B^T phi(d, N) = F(t),    d = d_0 + B x,  N = N_0 - kv (V x),  phi = f - f_0

``f`` the law forces, ``f_0`` their preload values, ``d`` the displacement the laws see (``d_0``:
the preload's ``B q_0 - law_reference``, zero for bearings set after the dead load). HHT-alpha (``-1/3 <= alpha <= 0``) with
``gamma = 1/2 - alpha``, ``beta = (1 - alpha)^2 / 4``, ``c = 1 + alpha`` enforces::

    M a_{n+1} + c G_{n+1} - alpha G_n = 0,    G = C v + K x + B^T phi - F

with Newmark's updates ``x_{n+1} = xt + beta h^2 a_{n+1}``, ``v_{n+1} = vt + gamma h a_{n+1}``
(``xt = x_n + h v_n + (1/2 - beta) h^2 a_n``, ``vt = v_n + (1 - gamma) h a_n``). Eliminating
``a_{n+1}`` and ``v_{n+1}`` leaves, for ``x = x_{n+1}``::

    A x + c B^T phi(B x) = r,    A = M / (beta h^2) + c gamma / (beta h) C + c K
    r = M (xt / (beta h^2) + c a0 w + alpha a0 v_n) + K (c a1 w + alpha a1 v_n + alpha x_n)
        + alpha B^T phi_n + c F_{n+1} - alpha F_n,        w = gamma / (beta h) xt - vt

(``C = a0 M + a1 K``). ``A`` is constant for a step size ``h``: it is factorised once per ``h``.

Fast path (static condensation onto the ``m`` governed bearing directions): with
``W = A^{-1} B^T`` (n x m), ``S = B W`` (m x m) and ``x_lin = A^{-1} r`` (one back-substitution),
``x = x_lin - c W phi``, so the bearing displacements solve the small system::

    g(d) = d - d_lin + c S phi(d) = 0,    d_lin = d_0 + B x_lin,     J = I + c S K_t

by Newton (``K_t`` the laws' block-diagonal consistent tangent). The normal forces follow
``N = N_lin + c kv (V W) phi``, evaluated for the next iterate with ``phi`` linearised there
(``phi - K_t delta``); the laws give no ``dphi/dN``, so their dependence on ``N`` lags one
iteration and the change of ``N`` is part of the convergence test. After convergence ``x = x_lin - c W phi`` (one dense
n x m product). General path (for checking): Newton on ``x`` with the full tangent
``A + c B^T K_t B``, refactorised every iteration. Both solve the same equations.

Convergence (every iteration, both paths): the force residual (general: ``|A x + c B^T phi - r|``;
fast: its linearisation ``c |K_t g|``) within ``tol_force`` of the step's force scale (the largest
of the dynamic load, the law forces and a floor of 1e-6 of the dead load), the Newton correction of
the bearing displacements within ``tol_displacement`` of their motion (since the preload and in
this step), and (fast path) the change of ``N`` within ``tol_force`` of ``max |N|``. Each test
allows a few hundred ulps of round-off of the quantities it compares.
"""

from __future__ import annotations

from collections.abc import Callable

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.analysis.energy import Energy, advance_energy
from bearingfw.analysis.static import factorize
from bearingfw.model import ConnectorOperators, ModelError

__all__ = ["Scheme", "Products", "Problem", "Operator", "State", "StepFailure", "build_operator", "step"]

#: Round-off allowance of the convergence tests, in units of the compared quantities' size.
_ROUND = 256 * np.finfo(float).eps


@attrs.frozen
class Scheme:
    """HHT-alpha parameters (``alpha = 0``: Newmark's average acceleration)."""

    alpha: float

    @property
    def gamma(self) -> float:
        return 0.5 - self.alpha

    @property
    def beta(self) -> float:
        return (1.0 - self.alpha) ** 2 / 4.0


#: Below this many free DOFs the per-step products use dense copies: scipy's per-call overhead
#: (~10 us) would otherwise dominate a small model's step.
DENSE_BELOW = 200


@attrs.frozen(eq=False)
class Products:
    """``M``, ``K``, ``B``, ``B^T``, ``V`` for the per-step products (dense copies for small models)."""

    M: object
    K: object
    B: object
    Bt: object
    V: object

    @classmethod
    def of(cls, M, K, B, Bt, V) -> Products:
        mats = (M, K, B, Bt, V)
        if M.shape[0] < DENSE_BELOW:
            mats = tuple(np.asarray(A.toarray()) for A in mats)
        return cls(*mats)


@attrs.frozen(eq=False)
class Problem:
    """The matrices and preload quantities one step needs (free DOFs; see the module docstring)."""

    M: sp.csr_matrix
    K: sp.csr_matrix
    B: sp.csr_matrix
    Bt: sp.csr_matrix
    V: sp.csr_matrix
    kv: np.ndarray
    a0: float  # Rayleigh mass coefficient
    a1: float  # Rayleigh stiffness coefficient
    scheme: Scheme
    ops: ConnectorOperators
    d0: np.ndarray  # preload law displacements (what the laws see: B q_0 - law_reference)
    f0: np.ndarray  # preload law forces
    N0: np.ndarray  # preload normal forces per spring row
    force_floor: float
    tol_force: float
    tol_displacement: float
    max_iterations: int
    fast: bool
    mul: Products = attrs.field(init=False)

    def __attrs_post_init__(self):
        object.__setattr__(self, "mul", Products.of(self.M, self.K, self.B, self.Bt, self.V))

    @property
    def m(self) -> int:
        return self.B.shape[0]

    def normal_forces(self, x: np.ndarray) -> np.ndarray:
        return self.N0 - self.kv * (self.mul.V @ x)

    def damping_force(self, Mv: np.ndarray, Kv: np.ndarray) -> np.ndarray:
        return self.a0 * Mv + self.a1 * Kv


@attrs.frozen(eq=False)
class Operator:
    """What depends on the step size ``h`` only: the factors of ``A`` and, on the fast path, the
    condensation scaled by ``c = 1 + alpha``: ``cW = c A^{-1} B^T``, ``cS = B cW``, ``cNW = c kv (V W)``
    (the change of ``N`` per unit law force)."""

    h: float
    A: sp.csc_matrix
    solve: Callable[[np.ndarray], np.ndarray]
    cW: np.ndarray | None
    cS: np.ndarray | None
    cNW: np.ndarray | None


def build_operator(p: Problem, h: float) -> Operator:
    """Factorise ``A`` for step ``h`` (and, on the fast path, condense it onto the bearings)."""
    s = p.scheme
    c = 1.0 + s.alpha
    cm = 1.0 / (s.beta * h * h)
    cd = c * s.gamma / (s.beta * h)
    A = ((cm + cd * p.a0) * p.M + (c + cd * p.a1) * p.K).tocsc()
    lu = factorize(A)
    cW = cS = cNW = None
    if p.fast and p.m:
        cW = c * lu.solve(p.Bt.toarray())
        cS = np.asarray(p.mul.B @ cW)
        cNW = p.kv[:, None] * np.asarray(p.mul.V @ cW)
    return Operator(h, A, lu.solve, cW, cS, cNW)


@attrs.frozen(eq=False)
class State:
    """A committed instant: kinematics (from the preload), bearing quantities, the load and energy."""

    t: float
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    f: np.ndarray  # law forces (total)
    d: np.ndarray  # bearing displacements the laws were called with (total)
    N: np.ndarray  # normal forces per spring row (total)
    law_states: tuple
    load: np.ndarray  # dynamic load F(t)
    Mv: np.ndarray
    Kv: np.ndarray
    energy: Energy


class StepFailure(Exception):
    """Newton did not converge in one (sub)step."""

    def __init__(self, reason: str, residual: float, rows: np.ndarray, iterations: int):
        super().__init__(reason)
        self.reason = reason
        self.residual = residual
        self.rows = rows  # per governed row: how much it was still moving (for naming connectors)
        self.iterations = iterations


def effective_rhs(p: Problem, s: State, h: float, load1: np.ndarray):
    """``r`` of the module docstring and the predictors ``xt``, ``vt``."""
    al, ga, be = p.scheme.alpha, p.scheme.gamma, p.scheme.beta
    c = 1.0 + al
    xt = s.x + h * s.v + (h * h * (0.5 - be)) * s.a
    vt = s.v + (h * (1.0 - ga)) * s.a
    w = (ga / (be * h)) * xt - vt
    rm = xt / (be * h * h)
    if p.a0:
        rm = rm + (c * p.a0) * w + (al * p.a0) * s.v
    r = p.mul.M @ rm + c * load1
    if p.a1 or al:
        r = r + p.mul.K @ ((c * p.a1) * w + (al * p.a1) * s.v + al * s.x)
    if al:
        r = r - al * s.load
        if p.m:
            r = r + al * (p.mul.Bt @ (s.f - p.f0))
    return r, xt, vt


def _finite(*arrays) -> bool:
    return all(np.isfinite(a).all() for a in arrays)


def _inf(a: np.ndarray) -> float:
    return float(np.abs(a).max()) if a.size else 0.0


def _blocks(p: Problem, responses) -> list[tuple[slice, np.ndarray]]:
    """The laws' tangents per group, ``(rows of B, (n, dims, dims))``: ``K_t`` is block diagonal."""
    return [(g.rows, np.asarray(r.tangent, dtype=float)) for g, r in zip(p.ops.groups, responses, strict=True)]


def _tangent_times(blocks, vector: np.ndarray) -> np.ndarray:
    """``K_t @ vector`` block by block."""
    out = np.empty_like(vector)
    for rows, t in blocks:
        out[rows] = np.einsum("nij,nj->ni", t, vector[rows].reshape(t.shape[0], -1)).reshape(-1)
    return out


def _times_tangent(matrix: np.ndarray, blocks) -> np.ndarray:
    """``matrix @ K_t`` block by block (``m x m`` dense times block diagonal)."""
    out = np.empty_like(matrix)
    rows_m = matrix.shape[0]
    for rows, t in blocks:
        n, d = t.shape[0], t.shape[1]
        # batched (n) products of (rows_m x d) by (d x d): far faster than the equivalent einsum
        out[:, rows] = np.matmul(matrix[:, rows].reshape(rows_m, n, d).transpose(1, 0, 2), t).transpose(1, 0, 2).reshape(
            rows_m, n * d
        )
    return out


def _solve_fast(p: Problem, op: Operator, s: State, r: np.ndarray, h: float, force_scale: float):
    x_lin = op.solve(r)
    if not p.m:
        return x_lin, s.f, s.d, p.normal_forces(x_lin), s.law_states, 0
    d_lin = p.d0 + p.mul.B @ x_lin
    N_lin = p.normal_forces(x_lin)
    # Predictor: the law forces of the last step held.
    phi = s.f - p.f0
    d = d_lin - op.cS @ phi
    N = N_lin + op.cNW @ phi
    c = 1.0 + p.scheme.alpha
    eye = np.eye(p.m)
    delta = np.zeros(p.m)
    f_err = np.inf
    size = max(_inf(d_lin), _inf(p.d0))
    for it in range(1, p.max_iterations + 1):
        responses = p.ops.respond(s.law_states, d, N, h)
        f = p.ops.forces(responses)
        blocks = _blocks(p, responses)
        phi = f - p.f0
        g = d - d_lin + op.cS @ phi
        N_new = N_lin + op.cNW @ phi
        if not _finite(f, g, N_new, *(t for _, t in blocks)):
            raise StepFailure("a law returned a non-finite force or tangent", np.inf, ~np.isfinite(f), it)
        try:
            delta = np.linalg.solve(eye + _times_tangent(op.cS, blocks), g)
        except np.linalg.LinAlgError:
            raise StepFailure("singular condensed Jacobian", np.inf, np.abs(g), it) from None
        # Force residual: the linearisation c K_t g of c B^T (phi(B x) - phi(d)).
        stiff = max((_inf(t) for _, t in blocks), default=0.0)
        f_err = c * _inf(_tangent_times(blocks, g))
        f_ok = f_err <= p.tol_force * max(force_scale, _inf(f)) + _ROUND * c * stiff * size
        d_ok = _inf(delta) <= p.tol_displacement * max(_inf(d - s.d), _inf(d - p.d0)) + _ROUND * size
        n_ok = _inf(N_new - N) <= p.tol_force * max(_inf(N), _inf(N_new)) + _ROUND * _inf(N_lin)
        if f_ok and d_ok and n_ok:
            return x_lin - op.cW @ phi, f, d, N, tuple(rr.state for rr in responses), it
        d = d - delta
        # N for the next iterate from the law forces linearised there (exact for linear laws, so
        # they converge in two evaluations); the laws' own dependence on N lags one iteration.
        N = N_lin + op.cNW @ (phi - _tangent_times(blocks, delta))
    raise StepFailure("no convergence", f_err / max(force_scale, 1e-300), np.abs(delta), p.max_iterations)


def _solve_general(p: Problem, op: Operator, s: State, r: np.ndarray, h: float, force_scale: float):
    c = 1.0 + p.scheme.alpha
    if not p.m:
        x = op.solve(r)
        return x, s.f, s.d, p.normal_forces(x), s.law_states, 0
    x = op.solve(r - c * (p.mul.Bt @ (s.f - p.f0)))  # predictor: the law forces of the last step held
    delta = np.zeros(p.m)
    f_err = np.inf
    for it in range(1, p.max_iterations + 1):
        d = p.d0 + p.mul.B @ x
        N = p.normal_forces(x)
        responses = p.ops.respond(s.law_states, d, N, h)
        f = p.ops.forces(responses)
        Kt = p.ops.tangent(responses)
        if not _finite(f, Kt.data):
            raise StepFailure("a law returned a non-finite force or tangent", np.inf, ~np.isfinite(f), it)
        Bt_phi = p.mul.Bt @ (f - p.f0)
        R = op.A @ x + c * Bt_phi - r
        try:
            dx = -factorize(op.A + c * (p.Bt @ Kt @ p.B)).solve(R)
        except (ModelError, RuntimeError):  # a singular tangent
            raise StepFailure("singular tangent matrix", np.inf, np.ones(p.m), it) from None
        delta = p.mul.B @ dx
        f_err = _inf(R)
        f_ok = f_err <= p.tol_force * max(force_scale, _inf(f)) + _ROUND * max(_inf(r), c * _inf(Bt_phi))
        d_ok = _inf(delta) <= p.tol_displacement * max(_inf(d - s.d), _inf(d - p.d0)) + _ROUND * _inf(d)
        if f_ok and d_ok:
            return x, f, d, N, tuple(rr.state for rr in responses), it
        x = x + dx
    raise StepFailure("no convergence", f_err / max(force_scale, 1e-300), np.abs(delta), p.max_iterations)


def step(p: Problem, op: Operator, s: State, t1: float, load1: np.ndarray) -> tuple[State, int]:
    """Advance ``s`` by ``op.h`` to time ``t1`` and dynamic load ``load1``: the new state and the Newton iterations.

    Raises :class:`StepFailure` when Newton does not converge.
    """
    h = op.h
    sch = p.scheme
    r, xt, vt = effective_rhs(p, s, h, load1)
    force_scale = max(_inf(load1), _inf(s.f), p.force_floor)
    solver = _solve_fast if p.fast else _solve_general
    x, f, d, N, law_states, iterations = solver(p, op, s, r, h, force_scale)
    if not _finite(x):
        raise StepFailure("non-finite displacements", np.inf, np.ones(p.m), iterations)
    a = (x - xt) / (sch.beta * h * h)
    v = vt + (sch.gamma * h) * a
    Mv = p.mul.M @ v
    Kv = p.mul.K @ v if p.a1 else s.Kv
    energy = advance_energy(
        s.energy,
        dx=x - s.x,
        v1=v,
        Mv1=Mv,
        x1=x,
        Kx1=p.mul.K @ x,
        damping0=p.damping_force(s.Mv, s.Kv),
        damping1=p.damping_force(Mv, Kv),
        dd=p.mul.B @ (x - s.x),
        bearing0=s.f - p.f0,
        bearing1=f - p.f0,
        load0=s.load,
        load1=load1,
    )
    return State(t1, x, v, a, f, d, N, law_states, load1, Mv, Kv, energy), iterations
