"""One Hilber-Hughes-Taylor step with Newton-Raphson on the bearing laws.

Equation of motion on the free DOFs, measured from the preload (``x = q - q_0``, see
:mod:`bearingfw.analysis.transient`)::

    M a + C v + K x + B^T phi(d, N) = F(t),    d = d_0 + B x,  N = N_0 - kv (V x),  phi = f - f_0

``f`` the law forces, ``f_0`` their preload values, ``d`` the displacement the laws see (``d_0``:
the preload's ``B q_0 - law_reference``, zero for bearings set after the dead load). HHT-alpha
(``-1/3 <= alpha <= 0``; this ``alpha`` is the scheme's, not Rayleigh's mass coefficient ``a0``)
with ``gamma = 1/2 - alpha``, ``beta = (1 - alpha)^2 / 4``, ``c = 1 + alpha`` enforces::

    M a_{n+1} + c G_{n+1} - alpha G_n = 0,    G = C v + K x + B^T phi - F

with Newmark's updates ``x_{n+1} = xt + beta h^2 a_{n+1}``, ``v_{n+1} = vt + gamma h a_{n+1}``
(``xt = x_n + h v_n + (1/2 - beta) h^2 a_n``, ``vt = v_n + (1 - gamma) h a_n``). Eliminating
``a_{n+1}`` and ``v_{n+1}`` leaves, for ``x = x_{n+1}``::

    A x + c B^T phi(B x) = r,    A = M / (beta h^2) + c gamma / (beta h) C + c K
    r = M (xt / (beta h^2) + c a0 w + alpha a0 v_n) + K (c a1 w + alpha a1 v_n + alpha x_n)
        + alpha B^T phi_n + c F_{n+1} - alpha F_n,        w = gamma / (beta h) xt - vt

(``C = a0 M + a1 K``, Rayleigh). ``A`` is constant for a step size ``h``: it is factorised once per
``h`` (:func:`factor`).

Products: ``r`` needs ``M`` and ``K`` times combinations of ``x_n``, ``v_n``, ``a_n``, and the energy
balance and damping force need ``M v``, ``M a``, ``K x``, ``K v`` at the new instant. A state keeps
``M [x, v, a]`` and ``K [x, v, a]`` (:attr:`State.products`); a step makes one sparse product,
``[M; K] x_{n+1}``, and gets the others from Newmark's updates applied to the products
(``M a_{n+1} = (M x_{n+1} - M xt) / (beta h^2)``, ``M v_{n+1} = M vt + gamma h M a_{n+1}``), the
same operations the scheme applies to ``x``, ``v``, ``a`` (so their round-off is of the same kind).

Compiled (:mod:`bearingfw.analysis.hht_kernels`): the right-hand side with the predictors, and
everything after the solve (the new state, that one sparse product, ``B^T phi``, the damping and
out-of-balance forces and the energy terms) are one loop each over the DOFs; the step's
back-substitution is a compiled substitution on SuperLU's factors (:class:`Factors`); the fast
path's block products with ``K_t`` and an iterate's residual are compiled loops too. The other
sparse products (``[B; V] x`` and the like) call scipy's CSR kernel directly (:class:`_Sparse`:
the same sums, without the dispatch that costs more than the product at a few hundred rows).
When every law of a run offers a compiled function (``compiled(n)``, :mod:`bearingfw.protocol`)
and none uses the velocity, the fast path's whole Newton iteration below is one compiled call
(:mod:`bearingfw.analysis.hht_newton`, :class:`CompiledLaws`); a step it cannot finish is solved
again by the Python iteration here, which reports failures. The time loop runs consecutive steps
of one size in one compiled call where a step needs nothing Python does (no laws, linear laws,
or compiled laws, under uniform support motion: :func:`steps_plan`, :func:`advance_steps`,
:mod:`bearingfw.analysis.hht_steps`); a step that call cannot finish comes back to :func:`step`.

Fast path (static condensation onto the ``m`` governed bearing directions): with
``W = A^{-1} B^T`` (n x m), ``S = B W`` (m x m) and ``x_lin = A^{-1} r`` (one back-substitution),
``x = x_lin - c W phi``, so the bearing displacements solve the small system::

    g(d) = d - d_lin + c S phi(d) = 0,    d_lin = d_0 + B x_lin,     J = I + c S K_t

by Newton (``K_t`` the laws' block-diagonal consistent tangent). The first iterate linearises the
law forces about the last step's converged point with its tangent,
``(I + c S K_t,n) d = d_lin - c S (phi_n - K_t,n d_n)``: exact for linear laws and sticking
bearings, which then converge at their first law call (one call per step instead of two); with
dF/dN it also linearises in the coupled normal forces (:func:`_predict`), exact for a 1-D friction
bearing that keeps sliding under a changing normal force. Its matrix is the Jacobian of the last
step's last Newton correction, whose LU factors the state keeps (:attr:`State.jacobian`): the
predictor costs one dense forward and back substitution. The
normal forces follow
``N = N_lin + c kv (V W) phi``, evaluated for the next iterate with ``phi`` linearised there
(``phi - K_t delta``); a law that gives no ``dphi/dN`` sees its ``N`` lag one iteration, and the
change of ``N`` is part of the convergence test. After convergence ``x = x_lin - c W phi`` (one
dense n x m product). ``B`` and ``V`` act as one stacked operator (``[B; V] x``,
``[S; kv V W]``): one product gives both. General path (for checking): Newton on ``x`` with the
full tangent ``A + c B^T K_t B``, refactorised every iteration. Both solve the same equations.

Linear laws (every law of the run declares ``linear``, :mod:`bearingfw.protocol`): ``phi(d) =
K_l (d - d_0)`` with one constant tangent, so their stiffness goes into the factorised matrix,
``(A + c B^T K_l B) x = r - c B^T K_l e`` (``e`` the support motion's offset of the law
displacements, zero for uniform motion), and a step is that one back-substitution: no law call,
no Newton iteration (:func:`linear_tangent`). A run with any other law keeps the condensation.

Velocity (laws with ``uses_velocity``, :mod:`bearingfw.protocol`): they get the trial velocity of
their directions at the trial point, ``B v_{n+1} = B vt + gamma / (beta h) (B x - B xt)`` with
``B x = d - d_0`` (the preload's ``d_0`` is no motion), on both paths; so
``dv/dd = gamma / (beta h)`` and ``K_t`` above is each law's ``tangent + gamma / (beta h)
dforce_dvelocity``. A linear viscous law is then exactly HHT's damping force ``C v``.

Normal-force coupling (laws with ``normal_coupling``: ``E = dphi/dN``, zero where ``N <= 0``,
the kernel's clamp): on the fast path the normal forces of the coupled springs are Newton
unknowns beside ``d``, scaled as vertical displacements ``nu = N / kv``. With ``x = x_lin - c W phi``
the two equations and their exact Jacobian are::

    g(d, nu) = d - d_lin + c S phi(d, kv nu) = 0
    h(d, nu) = nu - nu_lin - c (V W) phi(d, kv nu) = 0       (nu_lin = N_lin / kv)

    J = [ I + c S K_t      c S E_k     ]        E_k = E diag(kv)   (m x n_c)
        [ -c (V W) K_t     I - c (V W) E_k ]

(``V W`` the coupled springs' rows, ``Operator.cVW``), one dense solve of size ``m + n_c``. The
other springs' ``N`` still follow the law forces linearised at the next iterate (above); the line
search and the residual norm use ``(g, h)``, and the force residual's linearisation becomes
``c (K_t g + E_k h)``. General path: ``N = N_0 - kv V x`` adds ``-c B^T E diag(kv) V`` to the
tangent. Without a coupled law both paths are exactly those above.

Uplift (``Connector(uplift=True)``): the compression-only vertical springs are rows of ``B`` ruled
by the kernel's gap law (:class:`~bearingfw.model.connectors.CompressionOnlyGap`), not part of
``K``, so the condensation treats them like any bearing direction; their ``N`` comes from ``V``
as before and is zero whenever the gap is open.

Line search (both paths): a friction bearing's tangent jumps between the stick stiffness and zero
(sliding), so a full Newton correction computed in one regime overshoots into the other and the
iterates can alternate between two states forever. Each correction is therefore backtracked
(halved, at most ``BACKTRACKS`` times) until the residual norm falls by Armijo's factor
``1 - 1e-4 lambda`` (fast: ``|g|``; general: ``|A x + c B^T phi - r|``); a full step that
already decreases it, or lands at round-off level, is taken as is, so smooth problems keep
Newton's quadratic convergence at no extra cost. If no trial decreases it, the best one is taken
(and step halving in the time loop is the remedy of last resort).

Convergence (every iteration, both paths): the Newton correction of the bearing displacements
within ``tol_displacement`` of their motion (since the preload and in this step); the force
residual within ``tol_force`` of the step's force scale (the largest of the dynamic load, the law
forces and a floor of 1e-6 of the dead load), general: ``|A x + c B^T phi - r|``, fast: its
linearisation ``c |K_t g|``; and (fast path) the change of ``N`` within ``tol_force`` of
``max |N|``. The linearised force test is blind to directions with a zero tangent (a sliding
bearing): there the displacement test is the one that decides. Each test allows a few hundred
ulps of round-off of the quantities it compares. A failed fast-path step reports the true force
residual of its last iterate, ``c |B^T (phi(d - g) - phi(d))|`` (that of ``x = x_lin - c W phi(d)``,
one extra law call).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence

import attrs
import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dgesv as _gesv
from scipy.linalg.lapack import dgetrs as _getrs

try:  # scipy's sparse kernels (private; the products fall back to the public operator without them)
    from scipy.sparse import _sparsetools
except ImportError:  # pragma: no cover - a scipy that moved them
    _sparsetools = None

from bearingfw.analysis.energy import Energy, accumulate
from bearingfw.analysis.static import SYMMETRIC_ORDERING, factorize
from bearingfw.jit import kernel_array
from bearingfw.model import ConnectorOperators, ModelError
from bearingfw.protocol import CompiledLaw, law_flag

__all__ = [
    "Scheme",
    "Products",
    "Problem",
    "Operator",
    "State",
    "initial_state",
    "StepFailure",
    "effective_matrix",
    "factor",
    "Factors",
    "build_operator",
    "step",
    "BACKTRACKS",
]

_sum = np.add.reduce
_max = np.maximum.reduce
#: Round-off allowance of the convergence tests, in units of the compared quantities' size.
_ROUND = 256 * np.finfo(float).eps
#: Halvings of a Newton correction the line search tries before taking its best trial.
BACKTRACKS = 10
#: Armijo's sufficient decrease: a trial of length ``lam`` must cut the residual norm by ``_ARMIJO lam``.
_ARMIJO = 1e-4


@attrs.frozen
class Scheme:
    """HHT-alpha parameters (``alpha = 0``: Newmark's average acceleration; not Rayleigh's alpha)."""

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


class _Sparse:
    """A sparse matrix whose product with a vector calls scipy's own kernel directly.

    ``A @ x`` for a CSR/CSC ``A`` and a vector ``x`` is scipy's ``csr_matvec`` (``csc_matvec``) into a
    zeroed result; the dispatch around it costs several times the product at the sizes of a step
    (a few hundred rows). This makes the same call on the same arrays (the same sums in the same
    order); anything but a float vector goes to the matrix itself."""

    __slots__ = ("matrix", "shape", "_kernel", "_args")

    def __init__(self, matrix):
        self.matrix = matrix
        self.shape = matrix.shape
        self._kernel = getattr(_sparsetools, f"{matrix.format}_matvec", None) if _sparsetools is not None else None
        self._args = (matrix.shape[0], matrix.shape[1], matrix.indptr, matrix.indices, matrix.data)
        if matrix.dtype != np.float64:
            self._kernel = None

    def __matmul__(self, x):
        if self._kernel is None or type(x) is not np.ndarray or x.shape != (self.shape[1],) or x.dtype != np.float64:
            return self.matrix @ x
        out = np.zeros(self.shape[0])
        self._kernel(*self._args, x, out)
        return out

    def toarray(self) -> np.ndarray:
        return self.matrix.toarray()


@attrs.frozen(eq=False)
class Products:
    """``M``, ``K``, ``B``, ``B^T``, ``V`` and the stacked ``[B; V]`` for the per-step products
    (dense copies for small models; else :class:`_Sparse`, the same sparse products at less cost
    per call)."""

    M: object
    K: object
    B: object
    Bt: object
    V: object
    BV: object
    #: ``[M; K]``: the one sparse product of a step, ``M x`` and ``K x`` of the new displacements
    MK: object

    @classmethod
    def of(cls, M, K, B, Bt, V) -> Products:
        mats = (M, K, B, Bt, V, sp.vstack([B, V]).tocsr(), sp.vstack([M, K]).tocsr())
        if M.shape[0] < DENSE_BELOW:
            mats = tuple(np.asarray(A.toarray()) for A in mats)
        else:
            mats = tuple(_Sparse(A) for A in mats)
        return cls(*mats)


def _csr32(A) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``A``'s CSR arrays ``(indptr, indices, data)`` as the compiled step takes them: uint32 indices,
    float64 values (:mod:`bearingfw.analysis.hht_kernels`)."""
    A = sp.csr_matrix(A, dtype=np.float64)
    A.sum_duplicates()
    return A.indptr.astype(np.uint32), A.indices.astype(np.uint32), np.ascontiguousarray(A.data)


def _layout(ops: ConnectorOperators) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per connector of every law group (in the groups' order): its first row of ``B``, its number
    of directions ``dims`` and the offset of its ``dims x dims`` block in the flat tangent."""
    starts = [g.rows.start + g.dims * np.arange(g.n) for g in ops.groups]
    dims = [np.full(g.n, g.dims) for g in ops.groups]
    sizes = np.concatenate(dims) ** 2 if dims else np.zeros(0, dtype=np.int64)
    offsets = np.concatenate(([0], np.cumsum(sizes)[:-1])) if sizes.size else sizes
    flat = (lambda parts: np.ascontiguousarray(np.concatenate(parts) if parts else np.zeros(0), dtype=np.int64))
    return flat(starts), flat(dims), np.ascontiguousarray(offsets, dtype=np.int64)


#: False: the fast path's Newton iteration always runs in Python (for comparisons; tests)
COMPILED_NEWTON = True


def _compiled_law(g) -> CompiledLaw | None:
    """The compiled function a law group's law offers (``compiled(n)``), checked; None if it offers
    none. One that cannot be used (``compiled`` raises, or gives no C-callable function, or a state
    that does not pack to ``state_size`` floats a connector) is left aside with a warning: the
    run's steps are then solved through ``respond``, as without it."""
    make = getattr(g.law, "compiled", None)
    if not callable(make):
        return None
    try:
        law = make(g.n)
        if law is None:
            return None
        int(law.function.address)
        np.asarray(law.parameters, dtype=float)
        packed = kernel_array(law.pack(g.law.initial_state(g.n))).reshape(-1)
        if packed.size != g.n * int(law.state_size):
            raise ValueError(f"pack() gives {packed.size} floats for {g.n} connector(s) of state_size {law.state_size}")
    except Exception as exc:  # an optional fast path: a defect in it must not stop the run
        name = getattr(g.law, "name", type(g.law).__name__)
        warnings.warn(
            f"law {name!r}: its compiled function cannot be used ({type(exc).__name__}: {exc}); the steps are "
            "solved through respond()", RuntimeWarning, stacklevel=2,
        )  # fmt: skip
        return None
    return law


@attrs.frozen(eq=False)
class CompiledLaws:
    """What :func:`~bearingfw.analysis.hht_newton.solve_condensed` needs to call the laws of a
    run as compiled functions (:class:`bearingfw.protocol.CompiledLaw`), and to pack and unpack
    their states; built when every law group offers one, the fast path runs, and no law uses the
    velocity (:meth:`of`)."""

    laws: np.ndarray  # the addresses of the C-callable functions, one per group
    functions: tuple  # those functions (held here: their addresses stay valid while they live)
    #: per group: first row of ``B``, connectors, dims, offset in the flat tangent, first connector
    #: (in layout order), offset of its parameters and of its packed state
    groups: np.ndarray
    parameters: np.ndarray
    springs: np.ndarray  # per connector: its spring row (its N)
    #: per row of ``B``: the column of its spring among ``Problem.coupled`` (-1: no dF/dN) and its kv
    ecol: np.ndarray
    ekv: np.ndarray
    bv: tuple  # [B; V] as CSR arrays (:func:`_csr32`)
    packs: tuple
    unpacks: tuple
    state_bounds: tuple  # per group: (start, stop) of its state in the packed array
    lapack: np.ndarray  # the addresses of LAPACK's dgetrf and dgetrs (hht_newton.lapack)

    @classmethod
    def of(cls, p: Problem) -> CompiledLaws | None:
        ops = p.ops
        if not (p.fast and p.m) or ops.any_velocity:
            return None
        made = []
        for g in ops.groups:
            made.append(_compiled_law(g))
            if made[-1] is None:
                return None
        _starts, _dims, offsets = p.layout
        rows, params, springs, bounds = [], [], [], []
        first = poff = soff = 0
        for g, law in zip(ops.groups, made):
            size = g.n * law.state_size
            rows.append((g.rows.start, g.n, g.dims, offsets[first] if g.n else 0, first, poff, soff))
            params.append(np.asarray(law.parameters, dtype=float).reshape(-1))
            springs.append(np.broadcast_to(np.asarray(g.springs, dtype=np.int64).reshape(-1), (g.n,)))
            bounds.append((soff, soff + size))
            first, poff, soff = first + g.n, poff + params[-1].size, soff + size
        ecol = np.full(p.m, -1, dtype=np.int64)
        ecol[ops.coupling_rows] = np.searchsorted(p.coupled, ops.coupling_springs)
        ekv = np.zeros(p.m)
        ekv[ops.coupling_rows] = p.kv[ops.coupling_springs]
        flat = (lambda parts, dtype: np.ascontiguousarray(np.concatenate(parts) if parts else np.zeros(0), dtype=dtype))
        return cls(
            laws=np.array([law.function.address for law in made], dtype=np.int64),
            functions=tuple(law.function for law in made),
            groups=np.array(rows, dtype=np.int64).reshape(-1, 7),
            parameters=flat(params, np.float64),
            springs=flat(springs, np.int64),
            ecol=ecol,
            ekv=ekv,
            bv=_csr32(sp.vstack([p.B, p.V])),
            packs=tuple(law.pack for law in made),
            unpacks=tuple(law.unpack for law in made),
            state_bounds=tuple(bounds),
            lapack=_newton().lapack(),
        )

    def pack(self, states: tuple) -> np.ndarray:
        parts = [kernel_array(pack(state)).reshape(-1) for pack, state in zip(self.packs, states, strict=True)]
        for part, (a, b), function in zip(parts, self.state_bounds, self.functions, strict=True):
            if part.size != b - a:  # the compiled function would read and write past its state
                raise ModelError(
                    f"a compiled law ({getattr(function, '__name__', function)!r}): pack() gave {part.size} floats "
                    f"for a state of {b - a} (state_size times the connectors)"
                )
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    def unpack(self, packed: np.ndarray) -> tuple:
        return tuple(unpack(packed[a:b]) for unpack, (a, b) in zip(self.unpacks, self.state_bounds, strict=True))


@attrs.frozen(eq=False)
class Problem:
    """The matrices and preload quantities one step needs (free DOFs; see the module docstring)."""

    M: sp.csr_matrix
    K: sp.csr_matrix
    B: sp.csr_matrix
    Bt: sp.csr_matrix
    V: sp.csr_matrix
    kv: np.ndarray
    a0: float  # Rayleigh mass coefficient (Rayleigh's "alpha", 1/s)
    a1: float  # Rayleigh stiffness coefficient (Rayleigh's "beta", s)
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
    #: the CSR arrays of ``[M; K]`` and of ``B^T`` for the compiled step (:func:`_csr32`, :func:`step`)
    csr: tuple[tuple, tuple] = attrs.field(init=False, repr=False)
    #: where each connector's tangent block sits: ``(starts, dims, offsets)``, its first governed row,
    #: its size and its place in the flat tangent (:func:`_tangent`, :mod:`~bearingfw.analysis.hht_kernels`)
    layout: tuple[np.ndarray, np.ndarray, np.ndarray] = attrs.field(init=False, repr=False)
    d0_size: float = attrs.field(init=False)  # max |d_0|, part of the round-off allowances
    #: spring rows whose N the laws' dF/dN couples into Newton (sorted), their kv, and where each
    #: of ``ops.coupling_rows`` puts its dF/dN in ``E`` (flat index) and with which kv (:func:`_coupling`)
    coupled: np.ndarray = attrs.field(init=False)
    kv_coupled: np.ndarray = attrs.field(init=False)
    coupling_slots: np.ndarray = attrs.field(init=False)
    coupling_kv: np.ndarray = attrs.field(init=False)
    #: ``coupled`` as a slice where the rows are consecutive (a view instead of a copy), else itself
    coupled_at: slice | np.ndarray = attrs.field(init=False, repr=False)
    #: what depends on the step size only, per step size (:func:`effective_rhs`'s weights)
    per_step_size: dict = attrs.field(init=False, factory=dict, repr=False)
    #: the laws as compiled functions when every law of the run offers one (:class:`CompiledLaws`),
    #: else None: the fast path's Newton iteration then runs compiled (:mod:`~bearingfw.analysis.hht_newton`)
    compiled: CompiledLaws | None = attrs.field(init=False, repr=False)

    def __attrs_post_init__(self):
        # the compiled step takes these as writable, contiguous float64 arrays: a preload with active
        # bearings hands over the law's own (possibly frozen or strided) force array as f0
        for name in ("kv", "d0", "f0", "N0"):
            object.__setattr__(self, name, kernel_array(getattr(self, name)))
        object.__setattr__(self, "mul", Products.of(self.M, self.K, self.B, self.Bt, self.V))
        object.__setattr__(self, "csr", (_csr32(sp.vstack([self.M, self.K])), _csr32(self.Bt)))
        object.__setattr__(self, "layout", _layout(self.ops))
        object.__setattr__(self, "d0_size", _inf(self.d0))
        springs = self.ops.coupling_springs
        coupled = np.unique(springs)
        index = np.full(self.kv.size, -1, dtype=int)
        index[coupled] = np.arange(coupled.size)
        object.__setattr__(self, "coupled", coupled)
        consecutive = coupled.size and coupled[-1] - coupled[0] + 1 == coupled.size
        object.__setattr__(self, "coupled_at", slice(int(coupled[0]), int(coupled[-1]) + 1) if consecutive else coupled)
        object.__setattr__(self, "kv_coupled", self.kv[coupled])
        object.__setattr__(self, "coupling_slots", self.ops.coupling_rows * coupled.size + index[springs])
        object.__setattr__(self, "coupling_kv", self.kv[springs])
        object.__setattr__(self, "compiled", CompiledLaws.of(self) if COMPILED_NEWTON else None)

    @property
    def m(self) -> int:
        return self.B.shape[0]

    def normal_forces(self, x: np.ndarray) -> np.ndarray:
        return self.N0 - self.kv * (self.mul.V @ x)

    def bearings(self, x: np.ndarray, offset: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(d, N)`` at ``x``: the law displacements and normal forces, from one ``[B; V]`` product.

        ``offset``: what differential support motion adds to ``[B; V] x`` at this instant (rows of
        ``B`` then of ``V``; :meth:`~bearingfw.analysis.excitation.Excitation.bearing_offset`)."""
        dv = self.mul.BV @ x
        if offset is not None:
            dv = dv + offset
        return self.d0 + dv[: self.m], self.N0 - self.kv * dv[self.m :]

    def damping_force(self, Mv: np.ndarray, Kv: np.ndarray) -> np.ndarray:
        return self.a0 * Mv + self.a1 * Kv


def effective_matrix(M, K, a0: float, a1: float, scheme: Scheme, h: float) -> sp.csc_matrix:
    """``A = M / (beta h^2) + c gamma / (beta h) C + c K`` with ``C = a0 M + a1 K`` (module docstring)."""
    c = 1.0 + scheme.alpha
    cm = 1.0 / (scheme.beta * h * h)
    cd = c * scheme.gamma / (scheme.beta * h)
    return ((cm + cd * a0) * M + (c + cd * a1) * K).tocsc()


def factor(A) -> Factors:
    """LU factors of an effective matrix: :func:`~bearingfw.analysis.factorize` with the symmetric
    ordering (``A`` is symmetric: cheaper back-substitutions, the dominant cost of a fast-path
    step); a (nearly) singular ``A`` raises its mechanism error naming the DOFs that move."""
    return Factors(factorize(A, ordering=SYMMETRIC_ORDERING))


class Factors:
    """SuperLU's factors of ``A`` whose :meth:`solve` of one right-hand side is the compiled
    :func:`~bearingfw.analysis.hht_kernels.back_substitute` on those same factors (the step's one
    back-substitution; about a third of SuperLU's own solve at a thousand DOFs). Several
    right-hand sides at once (the condensation ``A^-1 B^T``) go to SuperLU."""

    #: Largest factors (nonzeros of L and U) copied for the compiled back-substitution: the copy
    #: costs 12 bytes a nonzero (about 240 MB here); beyond it the step solves with SuperLU.
    MAX_COPIED = 20_000_000

    def __init__(self, lu):
        self.lu = lu
        self._kernel = None
        self._compiled = 0 < lu.nnz <= self.MAX_COPIED
        if not self._compiled:
            return
        L, U = lu.L.tocsc(), lu.U.tocsc()
        L.sort_indices()
        U.sort_indices()
        u32 = np.uint32
        self._arrays = (
            L.indptr.astype(u32), L.indices.astype(u32), np.ascontiguousarray(L.data, dtype=float),
            U.indptr.astype(u32), U.indices.astype(u32), np.ascontiguousarray(U.data, dtype=float),
            lu.perm_r.astype(u32), lu.perm_c.astype(u32),
        )  # fmt: skip
        # the kernel reads each column's diagonal where sorted CSC puts it; else SuperLU solves
        n = L.shape[0]
        diagonal = np.arange(n)
        self._compiled = bool(n) and (
            np.array_equal(L.indices[L.indptr[:-1]], diagonal) and np.array_equal(U.indices[U.indptr[1:] - 1], diagonal)
        )

    @property
    def shape(self) -> tuple[int, int]:
        return self.lu.shape

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``A^-1 b`` (``b`` a vector, or a matrix of right-hand sides as columns)."""
        if (
            not self._compiled or type(b) is not np.ndarray or b.ndim != 1 or b.shape[0] != self.shape[0]
            or b.dtype != np.float64 or not b.flags.c_contiguous or not b.flags.writeable
        ):  # fmt: skip
            return self.lu.solve(b)  # SuperLU: also says what is wrong with a vector of another size
        if self._kernel is None:
            self._kernel = _kernels().back_substitute
        out = np.empty(b.shape[0])
        self._kernel(*self._arrays, b, out)
        return out


@attrs.frozen(eq=False)
class Operator:
    """What depends on the step size ``h`` only: the factors of ``A`` (``A`` itself on the general
    path only, which needs it for its residual) and, on the fast path, the condensation scaled by
    ``c = 1 + alpha``: ``cW = c A^{-1} B^T``, and stacked ``cSN = [B cW; kv (V cW)]``, whose rows are
    ``cS`` (m) and ``cNW`` (the change of ``N`` per unit law force)."""

    h: float
    A: sp.csc_matrix | None
    solve: Callable[[np.ndarray], np.ndarray]
    cW: np.ndarray | None
    cSN: np.ndarray | None
    m: int = 0
    #: the rows of ``cNW`` of the coupled springs over their ``kv`` (``c V W``: their vertical
    #: displacement per unit law force), for the Jacobian with dF/dN (module docstring)
    cVW: np.ndarray | None = None
    #: the linear laws' tangent ``K_l`` folded into ``A`` (:func:`linear_tangent`); None: Newton on the laws
    linear: np.ndarray | None = None
    #: ``[c S; -c V W]``: both block rows of the Jacobian with dF/dN, one product each (module docstring)
    cSV: np.ndarray | None = attrs.field(init=False, repr=False)

    def __attrs_post_init__(self):
        object.__setattr__(self, "cSV", None if self.cVW is None else np.vstack((self.cS, -self.cVW)))

    @property
    def cS(self) -> np.ndarray | None:
        return None if self.cSN is None else self.cSN[: self.m]

    @property
    def cNW(self) -> np.ndarray | None:
        return None if self.cSN is None else self.cSN[self.m :]


def linear_tangent(p: Problem, h: float) -> np.ndarray | None:
    """The laws' constant tangent ``K_l`` (m x m) when every law of the run declares ``linear``
    (:mod:`bearingfw.protocol`) and the fast path runs; None otherwise.

    Such laws answer ``phi(d) = K_l (d - d_0)`` whatever their state, normal force and step, so
    ``A x + c B^T phi(B x + e) = r`` is the linear system ``(A + c B^T K_l B) x = r - c B^T K_l e``
    (``e``: the support motion's offset): the tangent goes into the factorised matrix and a step is
    one back-substitution, with no law call and no Newton iteration."""
    ops = p.ops
    if not (p.fast and p.m) or ops.any_velocity or p.coupled.size:
        return None
    if not all(law_flag(g.law, "linear") for g in ops.groups):
        return None
    return np.asarray(ops.tangent(ops.respond(ops.initial_states(), p.d0, p.N0, h)).toarray())


def build_operator(p: Problem, h: float) -> Operator:
    """Factorise ``A`` for step ``h`` (and, on the fast path, condense it onto the bearings, or fold
    linear laws into it: :func:`linear_tangent`)."""
    c = 1.0 + p.scheme.alpha
    A = effective_matrix(p.M, p.K, p.a0, p.a1, p.scheme, h)
    linear = linear_tangent(p, h)
    if linear is not None:
        A = (A + c * (p.Bt @ sp.csr_matrix(linear) @ p.B)).tocsc()
    lu = factor(A)
    cW = cSN = cVW = None
    if p.fast and p.m and linear is None:
        cW = np.ascontiguousarray(c * lu.solve(p.Bt.toarray()))
        cSN = np.asarray(p.mul.BV @ cW)
        if p.coupled.size:
            cVW = cSN[p.m + p.coupled].copy()
        cSN[p.m :] *= p.kv[:, None]
    return Operator(h, None if p.fast else A, lu.solve, cW, cSN, p.m, cVW, linear)


@attrs.frozen(eq=False)
class State:
    """A committed instant: kinematics (from the preload), bearing quantities, the load and energy.

    ``ae``: the acceleration whose inertia HHT's alpha-weighted equilibrium balances at this
    instant, ``ae_{n+1} = (a_{n+1} + alpha ae_n) / (1 + alpha)`` (``= a`` for ``alpha = 0``): with it
    ``M ae + G = 0`` holds exactly, so constraint forces recovered from it are those of the
    equations the scheme solved. ``G`` (``C v + K x + B^T phi - F``) and ``rho`` (the scheme's
    out-of-balance force ``M a + G = -alpha (G_n - G_{n-1})``) feed the energy balance's
    numerical-dissipation term (:mod:`bearingfw.analysis.energy`).
    """

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
    Cv: np.ndarray  # damping force
    Ma: np.ndarray
    Bt_phi: np.ndarray  # B^T (f - f_0)
    G: np.ndarray
    rho: np.ndarray
    ae: np.ndarray
    #: the laws' tangent ``K_t`` at ``d``, flat (fast path, :func:`_tangent`; None at the start and on
    #: the general path): the next step's predictor linearises the law forces with it
    tangents: np.ndarray | None = None
    #: ``[[M x, M v, M a], [K x, K v, K a]]`` (2, 3, n): the next step's right-hand side and this
    #: step's energy and damping terms are combinations of them (:func:`effective_rhs`)
    products: np.ndarray | None = None
    #: with dF/dN (fast path): ``E`` at ``d`` (:func:`_coupling`; None: zero), for the predictor
    coupling: np.ndarray | None = None
    #: ``x``, ``v``, ``a`` as the rows of one (3, n) array (they are its views; None: separate arrays)
    xva: np.ndarray | None = None
    #: fast path: ``(operator, tangents, coupling, lu, piv)``, the LU factors of the condensed Jacobian
    #: that the step's last Newton correction factorised, with the operator and the tangents and
    #: coupling it was formed from; the next step's predictor solves with that matrix
    #: (:func:`_predict`). None: not available. The compiled iteration keeps its own here,
    #: ``("reduced", operator, tangents, coupling, E per row, packed states, states, lu, piv)``: the
    #: factors of its reduced system (:mod:`~bearingfw.analysis.hht_newton`), which the Python
    #: predictor never takes for its own (the first entry is not an operator).
    jacobian: tuple | None = None


def initial_state(p: Problem, law_states: tuple, load0: np.ndarray, a0: np.ndarray) -> State:
    """The preload at rest (``x = v = 0``) with start acceleration ``a0`` under the dynamic load ``load0``."""
    n = p.M.shape[0]
    zero = np.zeros(n)
    products = np.zeros((2, 3, n))
    products[:, 2] = (p.mul.MK @ a0).reshape(2, n)
    return State(
        t=0.0, x=zero, v=zero, a=a0, f=p.f0, d=p.d0, N=p.N0, law_states=law_states, load=load0,
        Mv=zero, Kv=zero, energy=Energy(), Cv=zero, Ma=products[0, 2], Bt_phi=zero, G=-load0,
        rho=zero,  # the scheme takes the start as balanced: any misfit of a0 counts as error
        ae=a0, products=products,
    )


class StepFailure(Exception):
    """Newton did not converge in one (sub)step."""

    def __init__(self, reason: str, residual: float, rows: np.ndarray, iterations: int):
        super().__init__(reason)
        self.reason = reason
        self.residual = residual
        self.rows = rows  # per governed row: how much it was still moving (for naming connectors)
        self.iterations = iterations


def _predictors(scheme: Scheme, h: float) -> np.ndarray:
    """``[xt; vt] = T [x; v; a]`` (2 x 3): Newmark's predictors from the last instant."""
    return np.array([[1.0, h, h * h * (0.5 - scheme.beta)], [0.0, 1.0, h * (1.0 - scheme.gamma)]])


def _rhs_weights(p: Problem, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Newmark's predictors ``T`` (:func:`_predictors`) and the weights of ``M [x, v, a]`` and
    ``K [x, v, a]`` in ``r`` (:func:`effective_rhs`), (2, 3) each; computed once per step size."""
    cached = p.per_step_size.get(h)
    if cached is not None:
        return cached
    al, ga, be = p.scheme.alpha, p.scheme.gamma, p.scheme.beta
    c = 1.0 + al
    T = _predictors(p.scheme, h)
    # rm = xt / (be h^2) + c a0 w + al a0 v,   rk = c a1 w + al a1 v + al x,   w = ga / (be h) xt - vt
    m_xt, m_vt = 1.0 / (be * h * h) + c * p.a0 * ga / (be * h), -c * p.a0
    k_xt, k_vt = c * p.a1 * ga / (be * h), -c * p.a1
    weights = np.array(
        [
            [m_xt * T[0, 0], m_xt * T[0, 1] + m_vt + al * p.a0, m_xt * T[0, 2] + m_vt * T[1, 2]],
            [k_xt * T[0, 0] + al, k_xt * T[0, 1] + k_vt + al * p.a1, k_xt * T[0, 2] + k_vt * T[1, 2]],
        ]
    ).reshape(6)
    p.per_step_size[h] = T, weights
    return T, weights


def effective_rhs(p: Problem, s: State, h: float, load1: np.ndarray):
    """``r`` of the module docstring and the predictors ``xt``, ``vt``.

    ``M rm`` and ``K (...)`` are combinations of the products ``M [x, v, a]`` and ``K [x, v, a]``
    the last step kept (:attr:`State.products`): no sparse product here; one compiled loop
    (:func:`bearingfw.analysis.hht_kernels.predict`)."""
    T, weights = _rhs_weights(p, h)
    xva = np.stack((s.x, s.v, s.a)) if s.xva is None else s.xva
    al = p.scheme.alpha
    out = np.empty((3, xva.shape[1]))
    _kernels().predict(xva, s.products, T, weights, load1, s.load, s.Bt_phi, 1.0 + al, al, out)
    return out


def _kernels():
    """:mod:`bearingfw.analysis.hht_kernels`, imported at the first step (numba's import is not free)."""
    global _KERNELS
    if _KERNELS is None:
        from bearingfw.analysis import hht_kernels as _KERNELS
    return _KERNELS


_KERNELS = None


#: below this many entries a sum of Python floats (``tolist``) is cheaper than numpy's reduction
_SMALL = 256


def _finite(*arrays) -> bool:
    # one sum per array: a NaN or an infinity makes it non-finite (a sum that merely overflows is
    # then looked at element by element)
    for a in arrays:
        total = sum(a.ravel().tolist()) if a.size <= _SMALL else _sum(a, axis=None)
        if not math.isfinite(total) and not np.isfinite(a).all():
            return False
    return True


def _inf(a: np.ndarray) -> float:
    return float(_max(np.abs(a), axis=None)) if a.size else 0.0


def _tangent(p: Problem, responses, rate: float) -> np.ndarray:
    """The laws' tangent ``K_t`` (block diagonal) as one flat array, block after block
    (:attr:`Problem.layout`).

    For a law that uses the velocity, ``rate = dv/du = gamma / (beta h)`` times its
    ``dforce_dvelocity`` is added (the velocity moves with the displacement)."""
    if p.ops.any_velocity:
        blocks = p.ops.tangent_blocks(responses, rate)
    else:
        blocks = [np.asarray(r.tangent, dtype=float) for r in responses]
    if len(blocks) == 1:
        return blocks[0].reshape(-1)  # C order: a view, or the copy a non-contiguous block needs
    return np.concatenate([t.reshape(-1) for t in blocks])


def _coupling(p: Problem, responses, N: np.ndarray) -> np.ndarray | None:
    """``E = (d phi / d N) diag(kv)`` on the coupled springs, (m, n_c): the change of the law forces
    per unit vertical displacement ``nu = N / kv`` of those springs (zero where ``N <= 0``); None
    when it is zero (every coupled bearing sticking, or without contact)."""
    values = p.ops.normal_derivatives(responses, N)[2]
    if not np.count_nonzero(values):
        return None
    E = np.zeros(p.m * p.coupled.size)
    E[p.coupling_slots] = values * p.coupling_kv
    return E.reshape(p.m, p.coupled.size)


@attrs.frozen(eq=False)
class Motion:
    """What a step needs to give the laws their trial velocity: ``rate = gamma / (beta h)`` and,
    when a law uses the velocity, ``B v = B vt + rate (B x - B xt)`` with ``B x = d - d_0 - e``.

    ``offset``: ``e``, what differential support motion adds to ``[B; V] x`` at the step's end (None:
    uniform motion), and ``offset_rate`` its rate on the rows of ``B``, added to the laws' velocity."""

    rate: float
    Bvt: np.ndarray | None = None
    Bxt: np.ndarray | None = None
    offset: np.ndarray | None = None
    offset_rate: np.ndarray | None = None

    def velocity(self, p: Problem, d: np.ndarray) -> np.ndarray | None:
        if self.Bvt is None:
            return None
        if self.offset is None:
            return self.Bvt + self.rate * ((d - p.d0) - self.Bxt)
        return self.Bvt + self.rate * ((d - p.d0 - self.offset[: p.m]) - self.Bxt) + self.offset_rate


def _tangent_times(p: Problem, tangent: np.ndarray, vector: np.ndarray) -> np.ndarray:
    """``K_t @ vector`` (``tangent`` flat: :func:`_tangent`)."""
    return _kernels().tangent_times(tangent, *p.layout, vector)


def _times_tangent(p: Problem, matrix: np.ndarray, tangent: np.ndarray, identity: bool = False) -> np.ndarray:
    """``matrix @ K_t`` (``m`` columns; plus the identity when ``identity``: ``I + c S K_t``)."""
    return _kernels().times_tangent(matrix, tangent, *p.layout, identity)


def _line_search(trial_at: Callable[[float], object], current) -> tuple[object, int]:
    """Backtrack along a Newton correction: ``trial_at(lam)`` evaluates the iterate moved by ``lam``
    times the full correction from ``current``; returns the accepted trial and the halvings made.

    A trial is accepted when its residual norm ``.merit`` falls by Armijo's factor, or when it is
    at round-off level (``.tiny``); a non-finite trial is returned at once (the caller reports it).
    If none of the ``BACKTRACKS + 1`` trials is accepted, the one with the smallest residual is.
    """
    best, lam = None, 1.0
    for k in range(BACKTRACKS + 1):
        trial = trial_at(lam)
        if not trial.finite or trial.tiny or trial.merit <= (1.0 - _ARMIJO * lam) * current.merit:
            return trial, k
        if best is None or trial.merit < best.merit:
            best = trial
        lam *= 0.5
    return best, BACKTRACKS


@attrs.define(eq=False)
class _FastTrial:
    """An iterate of the fast path and what the laws say there."""

    d: np.ndarray
    N: np.ndarray
    responses: list
    f: np.ndarray
    phi: np.ndarray
    tangent: np.ndarray  # K_t, flat (_tangent)
    g: np.ndarray  # d - d_lin + c S phi
    N_new: np.ndarray  # N_lin + c kv (V W) phi: the normal forces these law forces imply
    merit: float  # |g| (with dF/dN: |(g, h)|)
    tiny: bool  # |g| at round-off level
    finite: bool  # the law forces (they reach every entry of c S phi) and tangents
    E: np.ndarray | None = None  # with dF/dN: _coupling at this iterate (None: zero)
    h: np.ndarray | None = None  # with dF/dN: (N - N_new) / kv on the coupled springs


def _stiffness(tangent: np.ndarray) -> float:
    return _inf(tangent)


_NONE = np.zeros(0, dtype=np.int64)


#: what a solver returns instead of ``(tangents, coupling, jacobian, phi)`` (:func:`step`) when it has none
_NOT_LINEARISED = (None, None, None, None)


def _solve_dense(J: np.ndarray, g: np.ndarray) -> np.ndarray | None:
    """``J^-1 g`` (LAPACK ``gesv`` directly: numpy's wrapper costs several times the solve at this
    size), or None when ``J`` is singular."""
    _, _, x, info = _gesv(J, g)
    return x if info == 0 else None


def _factor_solve(J: np.ndarray, g: np.ndarray):
    """:func:`_solve_dense` that also returns the LU factors ``(lu, piv)`` (None when singular)."""
    lu, piv, x, info = _gesv(J, g)
    return (x, (lu, piv)) if info == 0 else (None, None)


def _solve_factored(factors, g: np.ndarray) -> np.ndarray | None:
    """``J^-1 g`` with ``J``'s LU factors from :func:`_factor_solve` (``gesv`` is ``getrf`` then
    ``getrs``: the same solution as factorising again)."""
    x, info = _getrs(factors[0], factors[1], g)
    return x if info == 0 else None


def _factors_for(s: State, op: Operator):
    """The LU factors of :attr:`State.jacobian` if they are those of the predictor's matrix (formed
    with ``op`` from the state's own tangents and coupling), else None."""
    jacobian = s.jacobian
    if jacobian is None or jacobian[0] is not op or jacobian[1] is not s.tangents or jacobian[2] is not s.coupling:
        return None
    return jacobian[3:]


def _predict(p: Problem, op: Operator, s: State, d_lin: np.ndarray, N_lin: np.ndarray):
    """The first iterate ``(d, N)`` of a fast-path step.

    With the last step's tangents, the law forces linearised about its converged point,
    ``phi ~ phi_n + K_t (d - d_n)``, put in ``g(d) = 0``: ``(I + c S K_t) d = d_lin - c S (phi_n - K_t d_n)``.
    That is exact for a linear law (or a bearing still sticking), which then converges at its first
    evaluation. With dF/dN (``E`` nonzero at the last point: a coupled bearing sliding) the
    linearisation includes ``E (nu - nu_n)`` and the coupled springs' ``nu = N / kv`` are unknowns
    beside ``d`` (the Jacobian of the module docstring at the last point): a bearing that keeps
    sliding under a changing normal force is then exact in 1-D too. Without tangents (the first
    step), or if that system is singular, the last law forces held: ``d = d_lin - c S phi_n``.

    That matrix is the Jacobian of the last step's last Newton correction (the same tangents, the
    same operator): its LU factors are reused when the state has them (:attr:`State.jacobian`).
    """
    m = p.m
    phi = s.f - p.f0
    if s.tangents is not None:
        held = phi - _tangent_times(p, s.tangents, s.d)
        factors = _factors_for(s, op)
        if s.coupling is not None:
            nu_n = s.N[p.coupled_at] / p.kv_coupled
            held = held - s.coupling @ nu_n
            # [d_lin - c S held; nu_lin + c V W held] (cSV's lower block is -c V W)
            rhs = op.cSV @ held
            rhs[:m] = d_lin - rhs[:m]
            rhs[m:] = N_lin[p.coupled_at] / p.kv_coupled - rhs[m:]
            if factors is not None:
                z = _solve_factored(factors, rhs)
            else:
                J = np.concatenate((_times_tangent(p, op.cSV, s.tangents), op.cSV @ s.coupling), axis=1)
                J.reshape(-1)[:: J.shape[0] + 1] += 1.0
                z = _solve_dense(J, rhs)
            if z is not None and _finite(z):
                d, nu = z[:m], z[m:]
                if p.coupled.size == p.kv.size:  # every spring coupled: N is nu's throughout
                    return d, p.kv_coupled * nu
                N = N_lin + op.cNW @ (held + _tangent_times(p, s.tangents, d) + s.coupling @ nu)
                N[p.coupled_at] = p.kv_coupled * nu
                return d, N
        else:
            rhs = d_lin - op.cS @ held
            if factors is not None:
                d = _solve_factored(factors, rhs)
            else:
                d = _solve_dense(_times_tangent(p, op.cS, s.tangents, identity=True), rhs)
            if d is not None and _finite(d):
                return d, N_lin + op.cNW @ (held + _tangent_times(p, s.tangents, d))
    sn = op.cSN @ phi
    return d_lin - sn[:m], N_lin + sn[m:]


def _coupled_correction(p: Problem, op: Operator, trial: _FastTrial):
    """Newton's correction ``(delta, delta_nu)`` of the bearing displacements and of the coupled
    springs' ``nu = N / kv`` (module docstring: the Jacobian with dF/dN), ``K_t delta`` when it was
    formed on the way (else None), and the LU factors of the Jacobian; ``delta`` None if singular.

    ``J = I + [[c S K_t, c S E_k], [-c V W K_t, -c V W E_k]]``; with ``E_k = 0`` (no coupled
    bearing sliding) its first block row alone gives ``delta``, and ``delta_nu = h + c V W K_t delta``.
    """
    m = p.m
    if trial.E is None:
        delta, factors = _factor_solve(_times_tangent(p, op.cS, trial.tangent, identity=True), trial.g)
        if delta is None:
            return None, None, None, None
        change = _tangent_times(p, trial.tangent, delta)
        return delta, trial.h + op.cVW @ change, change, factors
    J = np.concatenate((_times_tangent(p, op.cSV, trial.tangent), op.cSV @ trial.E), axis=1)
    J.reshape(-1)[:: J.shape[0] + 1] += 1.0  # the diagonal, in place
    x, factors = _factor_solve(J, np.concatenate((trial.g, trial.h)))
    return (None, None, None, None) if x is None else (x[:m], x[m:], None, factors)


def _solve_fast(p: Problem, op: Operator, s: State, r: np.ndarray, h: float, force_scale: float, motion: Motion):
    if p.compiled is not None and op.linear is None:
        solved = _solve_compiled(p, op, s, r, h, force_scale, motion)
        if solved is not None:
            return solved
    return _solve_fast_python(p, op, s, r, h, force_scale, motion)


#: the first entry of :attr:`State.jacobian` when the compiled iteration made it (its factors are
#: those of the reduced system, :mod:`~bearingfw.analysis.hht_newton`)
_REDUCED = "reduced"


def _solve_compiled(p: Problem, op: Operator, s: State, r: np.ndarray, h: float, force_scale: float, motion: Motion):
    """:func:`_solve_fast_python` as one compiled call (:mod:`~bearingfw.analysis.hht_newton`); None
    when it did not converge (or a law declined): the Python iteration then solves the step again
    and reports what went wrong."""
    plan = p.compiled
    newton = _newton()
    carried = _carried(p, op, s)
    c = 1.0 + p.scheme.alpha
    offset = motion.offset if motion.offset is not None else _EMPTY
    operands = _newton_operands(p, op)
    status, iterations, halvings, x, f, d, N, phi, tangent, ev, states_packed, lu, piv = newton.solve_condensed(
        *operands[:21],
        op.solve(r), kernel_array(offset), kernel_array(s.f), kernel_array(s.d), kernel_array(s.N), *carried,
        *operands[21:23], h, c, force_scale, *operands[23:],
    )  # fmt: skip
    if status != newton.CONVERGED:
        return None
    states = plan.unpack(states_packed)
    return x, f, d, N, states, iterations, halvings, _compiled_linearised(p, op, tangent, ev, states_packed, states, lu, piv, phi)


def _newton_operands(p: Problem, op: Operator) -> tuple:
    """:func:`~bearingfw.analysis.hht_newton.solve_condensed`'s operands that depend on the problem
    and the step size only: the 21 before ``x_lin``, LAPACK's addresses and ``trans``, and the 6
    tolerances and limits after ``force_scale``."""
    plan, m = p.compiled, p.m
    cVW = op.cVW if op.cVW is not None else np.zeros((0, m))
    return (
        plan.laws, plan.groups, plan.parameters, plan.springs, *p.layout, plan.ecol, plan.ekv, p.coupled,
        p.kv_coupled, *plan.bv, p.d0, p.N0, p.kv, p.f0, op.cSN, op.cW, cVW,
        plan.lapack, _newton()._TRANSPOSED,
        p.tol_force, p.tol_displacement, p.d0_size, p.max_iterations, BACKTRACKS, _ARMIJO, _ROUND,
    )  # fmt: skip


def _carried(p: Problem, op: Operator, s: State) -> tuple:
    """What the compiled iteration takes from the last step: its tangents, ``E_k`` per row, packed
    law states, and the LU factors of the predictor's matrix with whether they are that matrix's
    (``(tangents, ev, packed, lu, piv, reuse)``)."""
    plan, m = p.compiled, p.m
    # the last step's: (_REDUCED, operator, tangents, E, E per row, packed states, states, LU, pivots)
    jacobian = s.jacobian if s.jacobian is not None and s.jacobian[0] is _REDUCED else None
    if jacobian is not None and jacobian[6] is s.law_states:
        packed = jacobian[5]  # the states this iteration unpacked last step
    else:
        packed = plan.pack(s.law_states)
    ours = jacobian is not None and jacobian[2] is s.tangents and jacobian[3] is s.coupling
    if ours and jacobian[1] is op:  # the predictor's matrix is the last correction's: its factors
        ev_n, lu_n, piv_n, reuse = jacobian[4], jacobian[7], jacobian[8], True
    else:
        ev_n, lu_n, piv_n, reuse = np.zeros(m), _EMPTY2, _NO_PIVOTS, False
        if ours:
            ev_n = jacobian[4]
        elif s.coupling is not None:  # E as the Python iteration keeps it, (m, n_c): E_k per row
            rows = np.flatnonzero(plan.ecol >= 0)
            ev_n[rows] = s.coupling[rows, plan.ecol[rows]]
    # (a read-only or strided array would make numba compile another version of the iteration)
    tangents = kernel_array(s.tangents) if s.tangents is not None else _EMPTY
    return tangents, ev_n, packed, lu_n, piv_n, reuse


def _compiled_linearised(p: Problem, op: Operator, tangent, ev, packed, states, lu, piv, phi) -> tuple:
    """The compiled iteration's ``(tangents, E, jacobian, phi)`` for the state (:attr:`State.jacobian`)."""
    E = None
    if ev.any():  # E as the Python iteration keeps it (a later step may run there)
        rows = np.flatnonzero(ev)
        E = np.zeros((p.m, p.coupled.size))
        E[rows, p.compiled.ecol[rows]] = ev[rows]
    return tangent, E, (_REDUCED, op, tangent, E, ev, packed, states, lu, piv), phi


def _newton():
    """:mod:`bearingfw.analysis.hht_newton`, imported at the first compiled step."""
    global _NEWTON
    if _NEWTON is None:
        from bearingfw.analysis import hht_newton as _NEWTON
    return _NEWTON


_NEWTON = None
_EMPTY = np.zeros(0)
_EMPTY2 = np.zeros((0, 0))
_NO_PIVOTS = np.zeros(0, dtype=np.int32)


def _solve_fast_python(p: Problem, op: Operator, s: State, r: np.ndarray, h: float, force_scale: float, motion: Motion):
    if op.linear is not None:  # linear laws, folded into A: x in one back-substitution (linear_tangent)
        e = motion.offset
        x = op.solve(r if e is None else r - (1.0 + p.scheme.alpha) * (p.mul.Bt @ (op.linear @ e[: p.m])))
        d, N = p.bearings(x, e)
        phi = op.linear @ (d - p.d0)
        return x, p.f0 + phi, d, N, s.law_states, 0, 0, (None, None, None, phi)
    x_lin = op.solve(r)
    if not p.m:
        return x_lin, s.f, s.d, p.bearings(x_lin, motion.offset)[1], s.law_states, 0, 0, _NOT_LINEARISED
    d_lin, N_lin = p.bearings(x_lin, motion.offset)
    c = 1.0 + p.scheme.alpha
    size = max(_inf(d_lin), p.d0_size)
    round_d = _ROUND * size
    n_round = _ROUND * _inf(N_lin)
    m = p.m
    coupled = p.coupled_at
    n_coupled = p.coupled.size
    kv_coupled = p.kv_coupled
    rate = motion.rate
    respond, forces, law_states, f0, cSN = p.ops.respond, p.ops.forces, s.law_states, p.f0, op.cSN
    velocity = None if motion.Bvt is None else motion.velocity
    kernels = _kernels()
    absorb, displacement_converged = kernels.absorb, kernels.displacement_converged
    coupled_rows = p.coupled.astype(np.int64) if n_coupled else _NONE

    # one law group without velocity (the usual case): its force and tangent as they come
    single = len(p.ops.groups) == 1 and not p.ops.any_velocity

    def evaluate(d: np.ndarray, N: np.ndarray) -> _FastTrial:
        responses = respond(law_states, d, N, h, velocity=None if velocity is None else velocity(p, d))
        if single:  # ConnectorOperators.forces and _tangent for one group
            f = kernel_array(np.asarray(responses[0].force, dtype=float).reshape(-1))
            tangent = kernel_array(np.asarray(responses[0].tangent, dtype=float).reshape(-1))
        else:
            f = kernel_array(forces(responses))
            tangent = kernel_array(_tangent(p, responses, rate))
        # phi, g = d - d_lin + c S phi, N_new and the coupled springs' gap, from one product with cSN
        phi, g, N_new, gap, merit, finite = absorb(cSN, m, f, f0, d, d_lin, N_lin, tangent, coupled_rows, kv_coupled, N)
        merit = math.sqrt(merit)
        if not n_coupled:
            return _FastTrial(d, N, responses, f, phi, tangent, g, N_new, merit, merit <= round_d, finite)
        E = _coupling(p, responses, N)
        finite = finite and (E is None or _finite(E))
        return _FastTrial(d, N, responses, f, phi, tangent, g, N_new, merit, merit <= round_d, finite, E, gap)

    trial = evaluate(*_predict(p, op, s, d_lin, N_lin))
    delta = np.zeros(m)
    backtracks = 0
    for it in range(1, p.max_iterations + 1):
        if not trial.finite:
            raise StepFailure("a law returned a non-finite force or tangent", np.inf, ~np.isfinite(trial.f), it)
        tangent = trial.tangent
        if n_coupled:
            delta, delta_nu, change, factors = _coupled_correction(p, op, trial)
        else:
            delta, factors = _factor_solve(_times_tangent(p, op.cS, tangent, identity=True), trial.g)
        if delta is None:
            raise StepFailure("singular condensed Jacobian", np.inf, np.abs(trial.g), it)
        d = trial.d
        # the tests, cheapest and most often failing first (each only when the one before passed)
        if displacement_converged(delta, d, s.d, p.d0, p.tol_displacement, round_d):
            N, f = trial.N, trial.f
            # force residual: the linearisation c (K_t g + E h) of c B^T (phi(B x, N(x)) - phi(d, N))
            linear_residual = _tangent_times(p, tangent, trial.g)
            if trial.E is not None:
                linear_residual = linear_residual + trial.E @ trial.h
            if (
                _inf(trial.N_new - N) <= p.tol_force * max(_inf(N), _inf(trial.N_new)) + n_round
                and c * _inf(linear_residual)
                <= p.tol_force * max(force_scale, _inf(f)) + _ROUND * c * _stiffness(tangent) * size
            ):
                states = tuple(rr.state for rr in trial.responses)
                linearised = (tangent, trial.E, (op, tangent, trial.E, *factors), trial.phi)
                return x_lin - op.cW @ trial.phi, f, d, N, states, it, backtracks, linearised
        base = trial
        if n_coupled and n_coupled == p.kv.size:
            # every spring coupled: N is a Newton unknown throughout
            dN_coupled = kv_coupled * delta_nu

            def trial_at(lam: float, base=base, delta=delta, dN_coupled=dN_coupled) -> _FastTrial:
                if lam == 1.0:  # the full step (the usual one): lam times anything is itself
                    return evaluate(base.d - delta, base.N - dN_coupled)
                return evaluate(base.d - lam * delta, base.N - lam * dN_coupled)
        elif n_coupled:
            # N of the coupled springs is a Newton unknown; the others' N follows the law forces
            # linearised at the next iterate, as below
            if change is None:
                change = _tangent_times(p, tangent, delta)
            dN = op.cNW @ (change if trial.E is None else change + trial.E @ delta_nu)
            dN_coupled = kv_coupled * delta_nu

            def trial_at(lam: float, base=base, delta=delta, dN=dN, dN_coupled=dN_coupled) -> _FastTrial:
                if lam == 1.0:  # the full step (the usual one): lam times anything is itself
                    N_next = base.N_new - dN
                    N_next[coupled] = base.N[coupled] - dN_coupled
                    return evaluate(base.d - delta, N_next)
                N_next = base.N_new - lam * dN
                N_next[coupled] = base.N[coupled] - lam * dN_coupled
                return evaluate(base.d - lam * delta, N_next)
        else:
            # N for the next iterate from the law forces linearised there (exact for linear laws, so
            # they converge in two evaluations); the laws' own dependence on N lags one iteration.
            dN = op.cNW @ _tangent_times(p, tangent, delta)

            def trial_at(lam: float, base=base, delta=delta, dN=dN) -> _FastTrial:
                if lam == 1.0:
                    return evaluate(base.d - delta, base.N_new - dN)
                return evaluate(base.d - lam * delta, base.N_new - lam * dN)

        trial, k = _line_search(trial_at, base)
        backtracks += k
    if not trial.finite:
        raise StepFailure("a law returned a non-finite force or tangent", np.inf, ~np.isfinite(trial.f), p.max_iterations)
    residual = _fast_residual(p, s, h, trial, motion)
    raise StepFailure("no convergence", residual / force_scale, np.abs(delta), p.max_iterations)


def _fast_residual(p: Problem, s: State, h: float, trial: _FastTrial, motion: Motion) -> float:
    """The true force residual of the fast path's iterate (one extra law call; for reporting).

    ``x = x_lin - c W phi(d)`` has law displacements ``d - g`` and normal forces ``N_new``; its
    residual ``A x + c B^T phi(B x) - r`` is ``c B^T (phi(d - g) - phi(d))``.
    """
    d = trial.d - trial.g
    responses = p.ops.respond(s.law_states, d, trial.N_new, h, velocity=motion.velocity(p, d))
    phi = p.ops.forces(responses) - p.f0
    residual = (1.0 + p.scheme.alpha) * _inf(p.mul.Bt @ (phi - trial.phi))
    return residual if np.isfinite(residual) else np.inf


@attrs.define(eq=False)
class _GeneralTrial:
    x: np.ndarray
    d: np.ndarray
    N: np.ndarray
    responses: list
    f: np.ndarray
    Bt_phi: np.ndarray
    R: np.ndarray  # A x + c B^T phi - r
    merit: float
    tiny: bool
    finite: bool


def _general_jacobian(p: Problem, op: Operator, trial: _GeneralTrial, rate: float):
    """``A + c B^T d phi/dx``: the laws' tangents (with ``rate`` times dF/dv) and, for laws with
    dF/dN, ``N = N_0 - kv V x``'s part, ``-B^T E diag(kv) V``."""
    c = 1.0 + p.scheme.alpha
    Kt = p.ops.tangent(trial.responses, rate) if p.ops.any_velocity else p.ops.tangent(trial.responses)
    stiffness = p.Bt @ Kt @ p.B
    if p.coupled.size:
        rows, springs, values = p.ops.normal_derivatives(trial.responses, trial.N)
        En = sp.csr_matrix((-values * p.kv[springs], (rows, springs)), shape=(p.m, p.kv.size))
        stiffness = stiffness + p.Bt @ (En @ p.V)
    return op.A + c * stiffness


def _solve_general(
    p: Problem, op: Operator, s: State, r: np.ndarray, h: float, force_scale: float, motion: Motion
):
    c = 1.0 + p.scheme.alpha
    if not p.m:
        x = op.solve(r)
        return x, s.f, s.d, p.bearings(x, motion.offset)[1], s.law_states, 0, 0, _NOT_LINEARISED

    def evaluate(x: np.ndarray) -> _GeneralTrial:
        d, N = p.bearings(x, motion.offset)
        responses = p.ops.respond(s.law_states, d, N, h, velocity=motion.velocity(p, d))
        f = p.ops.forces(responses)
        Bt_phi = p.mul.Bt @ (f - p.f0)
        R = op.A @ x + c * Bt_phi - r
        tiny = _inf(R) <= _ROUND * max(_inf(r), c * _inf(Bt_phi))
        finite = _finite(f, R, *(np.asarray(rr.tangent) for rr in responses))
        return _GeneralTrial(x, d, N, responses, f, Bt_phi, R, float(np.linalg.norm(R)), tiny, finite)

    trial = evaluate(op.solve(r - c * s.Bt_phi))  # predictor: the law forces of the last step held
    delta = np.zeros(p.m)
    backtracks = 0
    for it in range(1, p.max_iterations + 1):
        if not trial.finite:
            raise StepFailure("a law returned a non-finite force or tangent", np.inf, ~np.isfinite(trial.f), it)
        try:
            # a new tangent each iteration, solved once: SuperLU's own solve (no compiled copy of its factors)
            dx = -factorize(_general_jacobian(p, op, trial, motion.rate), ordering=SYMMETRIC_ORDERING).solve(trial.R)
        except (ModelError, RuntimeError):  # a singular tangent: name the bearings most out of balance
            raise StepFailure("singular tangent matrix", np.inf, np.abs(p.mul.B @ trial.R), it) from None
        delta = p.mul.B @ dx
        d, f = trial.d, trial.f
        converged = (
            _inf(delta) <= p.tol_displacement * max(_inf(d - s.d), _inf(d - p.d0)) + _ROUND * _inf(d)
            and _inf(trial.R) <= p.tol_force * max(force_scale, _inf(f)) + _ROUND * max(_inf(r), c * _inf(trial.Bt_phi))
        )
        if converged:
            return trial.x, f, d, trial.N, tuple(rr.state for rr in trial.responses), it, backtracks, _NOT_LINEARISED
        base = trial
        trial, k = _line_search(lambda lam, base=base, dx=dx: evaluate(base.x + lam * dx), base)
        backtracks += k
    if not trial.finite:
        raise StepFailure("a law returned a non-finite force or tangent", np.inf, ~np.isfinite(trial.f), p.max_iterations)
    raise StepFailure("no convergence", _inf(trial.R) / force_scale, np.abs(delta), p.max_iterations)


def step(
    p: Problem, op: Operator, s: State, t1: float, load1: np.ndarray, offset1: tuple | None = None
) -> tuple[State, int, int]:
    """Advance ``s`` by ``op.h`` to time ``t1`` and dynamic load ``load1``.

    ``offset1``: under differential support motion, ``(e, e_rate)`` at ``t1``: what the support
    displacements add to ``[B; V] x`` (the law displacements, then the vertical springs) and its
    rate on the rows of ``B`` (:meth:`~bearingfw.analysis.excitation.Excitation.bearing_offset`);
    None for uniform motion, which leaves the step exactly as it was.

    Returns the new state, the Newton iterations and the line-search halvings. Raises
    :class:`StepFailure` when Newton does not converge.
    """
    h = op.h
    sch = p.scheme
    al = sch.alpha
    r, xt, vt = effective_rhs(p, s, h, load1)
    force_scale = max(_inf(load1), _inf(s.f), p.force_floor)
    rate = sch.gamma / (sch.beta * h)
    e, e_rate = (None, None) if offset1 is None else offset1
    if p.ops.any_velocity and p.m:
        motion = Motion(rate, p.mul.B @ vt, p.mul.B @ xt, e, e_rate)
    else:
        motion = Motion(rate, offset=e)
    solver = _solve_fast if p.fast else _solve_general
    x, f, d, N, law_states, iterations, backtracks, (tangents, coupling, jacobian, phi) = solver(
        p, op, s, r, h, force_scale, motion
    )
    if not _finite(x):
        raise StepFailure("non-finite displacements", np.inf, np.ones(p.m), iterations)
    T, _ = _rhs_weights(p, h)
    if p.m:
        phi = f - p.f0 if phi is None else phi
    mk, bt = p.csr
    kernels = _kernels()
    out, terms = np.empty((kernels.ROWS, x.size)), np.empty(7)
    kernels.commit(
        x, xt, vt, s.xva if s.xva is not None else np.stack((s.x, s.v, s.a)), s.products, T,
        *mk, *bt, p.f0 if phi is None else phi, bool(p.m),
        s.load, load1, s.Cv, s.Ma, s.Bt_phi, s.G, s.rho, s.ae, sch.beta * h * h, sch.gamma * h, p.a0, p.a1, al,
        out, terms,
    )  # fmt: skip
    xva, products = out[0:3], out[3:9].reshape(2, 3, -1)
    x, v, a = xva
    Mv, Ma, Kv = products[0, 1], products[0, 2], products[1, 1]
    Bt_phi, damping1, G, rho, ae = out[9:]
    energy = accumulate(s.energy, terms.tolist())
    state = State(
        t1, x, v, a, f, d, N, law_states, load1, Mv, Kv, energy, damping1, Ma, Bt_phi, G, rho, ae, tangents, products,
        coupling, xva, jacobian,
    )
    return state, iterations, backtracks


# ---- many steps in one compiled call (hht_steps) ----------------------------------------------

#: False: every step goes through :func:`step` (for comparisons; tests)
COMPILED_STEPS = True

#: about how many bytes a run of compiled steps keeps for its states (:attr:`StepsPlan.block`)
STEPS_BYTES = 8_000_000


@attrs.frozen(eq=False)
class StepsPlan:
    """What :func:`advance_steps` hands the compiled steps (:mod:`~bearingfw.analysis.hht_steps`) for
    one step size, made by :func:`steps_plan`."""

    p: Problem
    op: Operator
    mode: int
    operands: tuple  # hht_steps.advance's arguments before ``h``
    block: int  # steps per call: their states take about STEPS_BYTES


def steps_plan(p: Problem, op: Operator) -> StepsPlan | None:
    """The compiled steps of size ``op.h`` (:mod:`~bearingfw.analysis.hht_steps`), or None when a
    step needs Python: the general path, a law using the velocity, laws neither linear (folded) nor
    all compiled, or factors too large to copy (:class:`Factors`). Only for uniform support motion:
    a step under differential motion has an offset, which the caller must not give here."""
    factors = getattr(op.solve, "__self__", None)
    if not (COMPILED_STEPS and p.fast) or p.ops.any_velocity or not isinstance(factors, Factors):
        return None
    if not factors._compiled:  # (this module's own class)
        return None
    steps = _steps()
    if op.linear is not None:
        mode = steps.FOLDED
    elif not p.m:
        mode = steps.NO_LAWS
    elif p.compiled is not None:
        mode = steps.NEWTON
    else:
        return None
    if mode == steps.NEWTON:
        newton = _newton_operands(p, op)
    else:  # the same types, empty where the iteration is not run (one compiled version of advance)
        i64 = np.int64
        none = np.zeros(0, dtype=i64)
        newton = (
            none, np.zeros((0, 7), dtype=i64), _EMPTY, none, *p.layout, np.full(p.m, -1, dtype=i64), np.zeros(p.m),
            p.coupled, p.kv_coupled, *_csr32(sp.vstack([p.B, p.V])), p.d0, p.N0, p.kv, p.f0, _EMPTY2, _EMPTY2, _EMPTY2,
            np.zeros(2, dtype=i64), _newton()._TRANSPOSED,
            p.tol_force, p.tol_displacement, p.d0_size, p.max_iterations, BACKTRACKS, _ARMIJO, _ROUND,
        )  # fmt: skip
    h, sch = op.h, p.scheme
    T, weights = _rhs_weights(p, h)
    mk, bt = p.csr
    linear = np.ascontiguousarray(op.linear, dtype=float) if op.linear is not None else _EMPTY2
    operands = (
        mode, factors._arrays, T, weights, mk, bt, sch.beta * h * h, sch.gamma * h, p.a0, p.a1, sch.alpha,
        p.force_floor, linear, *newton,
    )  # fmt: skip
    n = p.M.shape[0]
    block = max(1, STEPS_BYTES // (8 * _kernels().ROWS * max(n, 1)))
    return StepsPlan(p, op, mode, operands, block)


class LawStates(Sequence):
    """The law states after each step of a compiled run, unpacked when read (``unpack`` of the packed
    rows; None: the laws are not iterated, every step has the ``start`` states). It keeps the
    packed states only, not the run's other arrays: a recorder that keeps every k-th step holds it
    until its chunk is full, k runs later."""

    def __init__(self, unpack: Callable | None, packed: np.ndarray, start: tuple):
        self.unpack, self.packed, self.start = unpack, packed, start

    def __len__(self) -> int:
        return self.packed.shape[0]

    def __getitem__(self, j: int) -> tuple:
        j = range(len(self))[j]  # an IndexError past the end
        return self.start if self.unpack is None else self.unpack(self.packed[j])


@attrs.frozen(eq=False)
class Steps(Sequence):
    """What a run of compiled steps reached (:func:`advance_steps`), one row per finished step: the
    arrays :func:`step` would have put into each :class:`State`, side by side. As a sequence, the
    steps' states (each made when read, :meth:`state`); the recorders read the arrays directly."""

    plan: StepsPlan
    times: np.ndarray  # (k,) the steps' ends
    loads: np.ndarray  # (k, n) the dynamic loads
    out: np.ndarray  # (k, ROWS, n): x, v, a, the products (6 rows), B^T phi, C v, G, rho, ae
    f: np.ndarray  # (k, m) law forces
    d: np.ndarray  # (k, m) law displacements
    N: np.ndarray  # (k, springs) normal forces
    packed: np.ndarray  # (k, ...) the compiled laws' packed states (NEWTON)
    energy: np.ndarray  # (k, 7) kinetic, strain, damping, bearings, input, (unused), numerical
    iterations: np.ndarray  # (k,) Newton iterations
    backtracks: np.ndarray  # (k,) line-search halvings
    start_law_states: tuple  # the law states where the laws are not iterated (folded, none)
    last: tuple  # (tangent, ev, lu, piv, phi) of the last step's iteration (NEWTON)

    @property
    def done(self) -> int:
        return self.times.size

    def __len__(self) -> int:
        return self.done

    def __getitem__(self, j):
        if isinstance(j, slice):
            return [self.state(k) for k in range(self.done)[j]]
        return self.state(range(self.done)[j])

    @property
    def x(self) -> np.ndarray:
        return self.out[:, 0]

    @property
    def v(self) -> np.ndarray:
        return self.out[:, 1]

    @property
    def a(self) -> np.ndarray:
        return self.out[:, 2]

    @property
    def ae(self) -> np.ndarray:
        return self.out[:, 13]

    @property
    def law_states(self) -> LawStates:
        """The law states after each step, unpacked when read."""
        unpack = self.plan.p.compiled.unpack if self.plan.mode == _steps().NEWTON else None
        return LawStates(unpack, self.packed, self.start_law_states)

    def energy_rows(self) -> list[tuple[float, ...]]:
        """:meth:`Energy.row` of every step."""
        e = self.energy
        imbalance = e[:, 4] - (e[:, 0] + e[:, 1] + e[:, 2] + e[:, 3])  # Energy.imbalance, in its order
        return list(zip(*(e[:, c].tolist() for c in range(5)), imbalance.tolist(), e[:, 6].tolist(), strict=True))

    def state(self, j: int) -> State:
        """Step ``j``'s :class:`State`, with its own arrays (a recorder that keeps every k-th state must
        not keep the whole run of steps alive); the last step's carries its iteration's factors for
        the next step's predictor."""
        p, n = self.plan.p, self.out.shape[2]
        out = self.out[j].copy()
        xva = out[0:3]
        products = out[3:9].reshape(2, 3, n)
        law_states = self.law_states[j]
        row = self.energy[j]
        energy = Energy(row[0], row[1], row[2], row[3], row[4], row[6])
        linearised = (None, None, None)
        if j == self.done - 1 and self.plan.mode == _steps().NEWTON:  # the next step's predictor takes these
            tangent, ev, lu, piv, phi = self.last
            linearised = _compiled_linearised(p, self.plan.op, tangent, ev, self.packed[j], law_states, lu, piv, phi)
        return State(
            float(self.times[j]), xva[0], xva[1], xva[2], self.f[j].copy(), self.d[j].copy(), self.N[j].copy(),
            law_states, self.loads[j].copy(), products[0, 1], products[1, 1], energy, out[10], products[0, 2], out[9],
            out[11], out[12], out[13], linearised[0], products, linearised[1], xva, linearised[2],
        )  # fmt: skip


def advance_steps(plan: StepsPlan, s: State, times, loads: np.ndarray) -> tuple[Steps, np.ndarray, np.ndarray]:
    """Steps of size ``plan.op.h`` from ``s`` to each of ``times`` (consecutive), under the dynamic
    loads ``loads`` (one row per step), in one compiled call: exactly the arithmetic of :func:`step`.

    Returns the steps reached (the states, :class:`Steps`), with the Newton iterations and halvings
    of each. Fewer steps than times: the next step could not be finished there (a law declined, a
    non-finite iterate, no convergence); :func:`step` must solve it (and report why, or halve it)."""
    p, op, steps = plan.p, plan.op, _steps()
    n, m, k = s.x.size, p.m, len(times)
    xva = s.xva if s.xva is not None else np.stack((s.x, s.v, s.a))
    start = np.concatenate((xva, s.products.reshape(6, n), np.stack((s.Bt_phi, s.Cv, s.G, s.rho, s.ae))))
    if plan.mode == steps.NEWTON:
        carried = _carried(p, op, s)
    else:
        carried = (_EMPTY, np.zeros(m), _EMPTY, _EMPTY2, _NO_PIVOTS, False)
    e = s.energy
    energy_n = np.array([e.kinetic, e.strain, e.damping, e.bearings, e.input, e.numerical])
    OUT = np.empty((k, _kernels().ROWS, n))
    F, D, NN = np.empty((k, m)), np.empty((k, m)), np.empty((k, p.kv.size))
    S = np.empty((k, carried[2].size))
    ENERGY = np.empty((k, 7))
    iterations, backtracks = np.zeros(k, dtype=np.int64), np.zeros(k, dtype=np.int64)
    done, tangent, ev, lu, piv, phi = steps.advance(
        *plan.operands, op.h, start, kernel_array(s.load), energy_n, kernel_array(s.f), kernel_array(s.d),
        kernel_array(s.N), *carried, kernel_array(loads), OUT, F, D, NN, S, ENERGY, iterations, backtracks,
    )  # fmt: skip
    steps = Steps(
        plan, np.asarray(times, dtype=float)[:done], loads[:done], OUT[:done], F[:done], D[:done], NN[:done],
        S[:done], ENERGY[:done], iterations[:done], backtracks[:done], s.law_states, (tangent, ev, lu, piv, phi),
    )  # fmt: skip
    return steps, steps.iterations, steps.backtracks


def _steps():
    """:mod:`bearingfw.analysis.hht_steps`, imported at the first run of compiled steps."""
    global _STEPS
    if _STEPS is None:
        from bearingfw.analysis import hht_steps as _STEPS
    return _STEPS


_STEPS = None
