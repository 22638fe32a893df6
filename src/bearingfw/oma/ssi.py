"""Covariance-driven stochastic subspace identification (SSI-COV) of ambient accelerations.

The model. Sampled every ``dt``, a linear structure driven by broadband (white) excitation is
the stochastic state-space model ``x_{k+1} = A x_k + w_k``, ``y_k = C x_k + v_k`` (``y``: the
``l`` channels). Its output correlations against ``r`` reference channels,
``R_j = E[y_{k+j} y_ref,k^T]`` (``l x r``), factor for ``j >= 1`` as ``R_j = C A^(j-1) G`` with
``G = E[x_{k+1} y_ref,k^T]``. Stacked into the block Toeplitz matrix of ``i`` block rows::

    T = [[R_i      R_(i-1) ... R_1 ],
         [R_(i+1)  R_i     ... R_2 ],
         ...
         [R_(2i-1)         ... R_i ]]  =  O Z,   O = [C; C A; ...; C A^(i-1)]

it is the observability matrix ``O`` times a (reversed) controllability matrix ``Z``: its rank
is the number of states ``n`` (two per mode). With estimated correlations ``T`` has full rank,
but its leading singular values belong to the structure and the rest to noise. For each model
order ``n`` the first ``n`` singular triplets of ``T = U S V^T`` give ``O = U_n S_n^(1/2)``; the
first block row of ``O`` is ``C``, and ``A`` follows from the shift structure of ``O`` (its
rows without the last block, times ``A``, are its rows without the first block), solved in the
least-squares sense. The eigenvalues ``mu`` of ``A`` are the discrete poles: the continuous
pole ``lambda = ln(mu) / dt`` gives the natural frequency ``|lambda| / 2 pi`` and the damping
ratio ``-Re(lambda) / |lambda|``, exactly for a viscously damped mode; the eigenvectors ``psi``
give the (complex) mode shapes ``C psi`` at the channels.

One SVD serves every order: the orders 2, 4, ..., ``max_order`` reuse it, which is what a
stabilisation diagram (:mod:`bearingfw.oma.stabilisation`) compares. So does the shift
equation: with ``O_n = U_n S_n^(1/2)`` its least-squares solution is
``A_n = S_n^(-1/2) (U_up^T U_up)_n^(-1) (U_up^T U_down)_n S_n^(1/2)`` (``U_up``, ``U_down``: ``U``
without its last, first block row; ``(.)_n`` the leading ``n x n`` block), so two ``k x k``
products of the largest order serve all orders.

Choosing ``block_rows``: ``T`` must be able to hold the order, ``i r >= max_order``, the shift
equation must be determined, ``(i - 1) l >= max_order`` (``l`` outputs), and the correlation
lags it spans (``2 i dt``) should cover about a period of the lowest mode of interest, so that
slow modes are well separated from noise.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
import scipy.linalg as sla

from bearingfw.parameters import ParameterError, integer_parameter

__all__ = [
    "Poles",
    "SSISettings",
    "block_toeplitz",
    "complex_mac",
    "correlations",
    "leading_singular",
    "modal_phase_collinearity",
    "real_shape",
    "ssi_cov",
]


#: The paper's model order (section 3.1: "order - 30").
PAPER_ORDER = 30
#: The default largest order: twice the paper's. A record sees every mode of its band, not only
#: those of interest, and each takes two states (noise takes more): the simulated ambient test
#: of the reference bridge (28 deck channels, 0-20 Hz) still adds a stable mode at order 22 of
#: 30, and with traffic-like loads on the deck its first vertical mode became stable only at
#: order 30. :func:`bearingfw.oma.identify` warns when the top orders still add modes.
DEFAULT_ORDER = 60
#: Block rows by default: 40 span 80 samples of lag, about a period of the lowest mode for a
#: sampling rate of 40-100 times its frequency.
DEFAULT_BLOCK_ROWS = 40


@attrs.frozen
class SSISettings:
    """SSI-COV settings: the largest model order (states; orders ``2, 4, ..., max_order``), block rows.

    ``block_rows`` defaults to :data:`DEFAULT_BLOCK_ROWS` (at most a twentieth of the record),
    or more if the order needs them (:meth:`rows_for`).
    """

    max_order: int = integer_parameter(
        low=2, high=1000, default=DEFAULT_ORDER, doc="largest model order (states; the paper's: 30)"
    )
    block_rows: int | None = attrs.field(default=None)

    def __attrs_post_init__(self):
        if self.max_order % 2:
            raise ParameterError(
                f"SSISettings: parameter 'max_order' must be even (two states per mode), got {self.max_order}"
            )
        if self.block_rows is not None and (
            isinstance(self.block_rows, bool)
            or not isinstance(self.block_rows, int)
            or not 1 <= self.block_rows <= 10000
        ):
            raise ParameterError(
                f"SSISettings: parameter 'block_rows' must be an integer with 1 <= block_rows <= 10000 or None, "
                f"got {self.block_rows!r}"
            )

    @property
    def orders(self) -> np.ndarray:
        return np.arange(2, self.max_order + 1, 2)

    def rows_for(self, n_outputs: int, n_references: int, n_samples: int) -> int:
        """The block rows ``i`` for ``n_outputs`` channels, ``n_references`` references and ``n_samples`` samples.

        ``T`` must hold the largest order, ``i r >= max_order``; the shift equation must be
        determined, ``(i - 1) l >= max_order``; and the correlations up to lag ``2 i - 1`` must
        come from at least twice as many samples, ``4 i <= n_samples``.
        """
        needed = max(math.ceil(self.max_order / n_references), math.ceil(self.max_order / n_outputs) + 1)
        most = n_samples // 4
        if self.block_rows is not None:
            i = self.block_rows
        else:
            i = max(needed, min(DEFAULT_BLOCK_ROWS, n_samples // 20))
        if not needed <= i <= most:
            allowed = f"{needed} <= block_rows <= {most}" if needed <= most else "none: the record is too short"
            raise ParameterError(
                f"SSISettings: block_rows = {i} with {n_outputs} channel(s), {n_references} reference(s) and "
                f"{n_samples} samples for max_order = {self.max_order}: T holds order block_rows x references, "
                f"the shift equation needs (block_rows - 1) x channels >= max_order, and the lags need "
                f"4 x block_rows <= samples; allowed: {allowed} (or lower max_order)"
            )
        return i


@attrs.frozen(eq=False)
class Poles:
    """The poles of every model order, flat: one entry per (order, pole), lowest order first.

    ``shapes`` are complex, one row per pole, at the channels. Only poles with a positive
    imaginary part are kept (one of each conjugate pair; real poles are not vibration modes).
    ``singular_values`` are those of the block Toeplitz matrix (their drop shows the order).
    """

    order: np.ndarray
    frequency: np.ndarray
    damping: np.ndarray
    shapes: np.ndarray
    orders: np.ndarray
    singular_values: np.ndarray
    dt: float
    block_rows: int

    @property
    def size(self) -> int:
        return int(self.frequency.size)

    @property
    def mpc(self) -> np.ndarray:
        return modal_phase_collinearity(self.shapes)


def correlations(y: np.ndarray, lags: int, references=None) -> np.ndarray:
    """Unbiased output correlations ``R_j = sum_k y_(k+j) y_ref,k^T / (N - j)``, ``j = 0 .. lags-1``: (lags, l, r).

    ``y`` is (samples, channels), its mean removed first; ``references`` are column indices (default all).
    """
    y = np.asarray(y, dtype=float)
    y = y - y.mean(axis=0)
    ref = y if references is None else y[:, np.asarray(references, dtype=int)]
    n = y.shape[0]
    return np.stack([y[j:].T @ ref[: n - j] / (n - j) for j in range(lags)])


def block_toeplitz(R: np.ndarray, block_rows: int) -> np.ndarray:
    """``T`` of the module docstring from correlations ``R`` (lags >= 2 i, l, r): block (p, q) is ``R_(i+p-q)``."""
    i = block_rows
    _, outputs, refs = R.shape
    p, q = np.meshgrid(np.arange(i), np.arange(i), indexing="ij")
    blocks = R[i + p - q]  # (i, i, outputs, refs)
    return blocks.transpose(0, 2, 1, 3).reshape(i * outputs, i * refs)


def complex_mac(a: np.ndarray, b: np.ndarray, rowwise: bool = False) -> np.ndarray:
    """MAC of complex shapes, one per row: ``|a^H b|^2 / ((a^H a)(b^H b))``.

    The table of every row of ``a`` against every row of ``b``, (len(a), len(b)); with
    ``rowwise``, row ``k`` of ``a`` against row ``k`` of ``b`` only, (len(a),).
    """
    a = np.atleast_2d(a)
    b = np.atleast_2d(b)
    na, nb = np.sum(np.abs(a) ** 2, axis=1), np.sum(np.abs(b) ** 2, axis=1)
    if rowwise:
        return np.abs(np.sum(a.conj() * b, axis=1)) ** 2 / (na * nb)
    return np.abs(a.conj() @ b.T) ** 2 / np.outer(na, nb)


def modal_phase_collinearity(shapes: np.ndarray) -> np.ndarray:
    """MPC of complex shapes (rows): ``|phi^T phi|^2 / (phi^H phi)^2``, 1 when all components share a phase."""
    shapes = np.atleast_2d(shapes)
    return np.abs(np.sum(shapes * shapes, axis=1)) ** 2 / np.sum(np.abs(shapes) ** 2, axis=1) ** 2


def real_shape(shapes: np.ndarray) -> np.ndarray:
    """Real shapes from complex ones (rows): turned to the phase that makes them most real, largest component +1.

    The turn ``exp(-i theta)`` with ``theta = arg(sum phi_k^2) / 2`` maximises ``sum Re(...)^2``:
    the principal direction of the components in the complex plane.
    """
    shapes = np.atleast_2d(shapes)
    theta = np.angle(np.sum(shapes * shapes, axis=1)) / 2
    real = np.real(shapes * np.exp(-1j * theta)[:, None])
    biggest = real[np.arange(real.shape[0]), np.argmax(np.abs(real), axis=1)]
    return real / np.where(biggest == 0, 1.0, biggest)[:, None]


#: The Gram route's singular values are accurate to about ``eps (s_1 / s_k)^2`` relative; below
#: this ratio ``s_k / s_1`` :func:`leading_singular` falls back to a full SVD.
GRAM_LIMIT = 1e-5


def leading_singular(T: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``k`` leading left singular vectors and values of ``T``.

    They come from the leading eigenpairs of the smaller Gram matrix (``T T^T``, or ``T^T T``
    with ``U = T V / s``): a matrix product and a partial symmetric eigensolution, a fraction of
    the time of a full SVD of a large Toeplitz matrix (the bridge's 1120 x 1120: about 0.2 s
    against 0.9 s on one core, and the gap widens when other processes compete for the cores).
    Squaring ``T`` costs accuracy where ``s_k`` is small against ``s_1``: the relative error of
    ``s_k`` is about ``eps (s_1 / s_k)^2`` and of its vector about as large. Estimated
    correlations carry statistical errors of order ``1 / sqrt(samples)``, which put the noise
    floor of ``T``'s singular values far above that; if ``s_k / s_1`` still falls below
    :data:`GRAM_LIMIT` (an almost noise-free record), the full SVD is used instead.
    """
    rows, cols = T.shape
    k = min(k, rows, cols)
    gram = T @ T.T if rows <= cols else T.T @ T
    values, vectors = sla.eigh(gram, subset_by_index=[gram.shape[0] - k, gram.shape[0] - 1], driver="evr")
    values, vectors = values[::-1], vectors[:, ::-1]
    s = np.sqrt(np.clip(values, 0.0, None))
    if s[0] == 0 or s[-1] < GRAM_LIMIT * s[0]:
        U, s, _ = np.linalg.svd(T, full_matrices=False)
        return U[:, :k], s[:k]
    if rows <= cols:
        return vectors, s
    return (T @ vectors) / s, s


def shift_operators(U: np.ndarray, s: np.ndarray, outputs: int, orders) -> list[np.ndarray]:
    """The state matrix ``A_n`` of each order ``n`` from the shift structure of ``O_n = U_n S_n^(1/2)``.

    The least-squares solution of ``O_up A = O_down`` (module docstring) from the leading
    blocks of two small Gram matrices of the largest order.
    """
    up, down = U[:-outputs], U[outputs:]
    gram, cross = up.T @ up, up.T @ down
    root = np.sqrt(s)
    out = []
    for n in orders:
        whitened = np.linalg.solve(gram[:n, :n], cross[:n, :n])
        out.append(whitened * root[None, :n] / root[:n, None])
    return out


def ssi_cov(y: np.ndarray, dt: float, settings: SSISettings = SSISettings(), references=None) -> Poles:
    """Poles of every model order from accelerations ``y`` (samples, channels) sampled every ``dt`` s."""
    y = np.asarray(y, dtype=float)
    if y.ndim != 2:
        raise ParameterError(f"ssi_cov: y must be (samples, channels), got shape {y.shape}")
    if not (math.isfinite(dt) and dt > 0):
        raise ParameterError(f"ssi_cov: dt = {dt!r} must be > 0 s")
    n_samples, outputs = y.shape
    r = outputs if references is None else len(references)
    i = settings.rows_for(outputs, r, n_samples)
    T = block_toeplitz(correlations(y, 2 * i, references), i)
    U, s = leading_singular(T, settings.max_order)
    if s.size < settings.max_order or s[settings.max_order - 1] <= 0:
        raise ParameterError(
            f"ssi_cov: the correlations have rank {int(np.count_nonzero(s))} < max_order = {settings.max_order} "
            "(constant or duplicated channels?); lower max_order"
        )
    found = {"order": [], "frequency": [], "damping": [], "shapes": []}
    for n, A in zip(settings.orders, shift_operators(U, s, outputs, settings.orders), strict=True):
        mu, psi = np.linalg.eig(A)
        keep = mu.imag > 0
        lam = np.log(mu[keep]) / dt
        found["order"].append(np.full(lam.size, n))
        found["frequency"].append(np.abs(lam) / (2 * np.pi))
        found["damping"].append(-lam.real / np.abs(lam))
        # C psi with C = O_n[:l] = U_n[:l] S_n^(1/2) and the eigenvectors of A_n
        found["shapes"].append(((U[:outputs, :n] * np.sqrt(s[:n])) @ psi[:, keep]).T)
    return Poles(
        order=np.concatenate(found["order"]),
        frequency=np.concatenate(found["frequency"]),
        damping=np.concatenate(found["damping"]),
        shapes=np.concatenate(found["shapes"], axis=0),
        orders=settings.orders,
        singular_values=s,
        dt=float(dt),
        block_rows=i,
    )
