"""Modal analysis: the paper's step-1 linearisation, participation, automatic labels and MAC.

Linearisation: each connector enters with its law's *initial* tangent,
``respond(initial_state(n), zeros, N, dt).tangent`` with ``N`` from the gravity preload (by
default with the bearings set after the dead load, where the laws' displacement is zero); so a
frictionless law leaves the direction free, a linear spring adds ``k``, regularized Coulomb its
stick stiffness ``k``, and a rigid law is already a tie in ``T``. A bearing with ``uplift=True``
enters closed, with its vertical stiffness ``kv`` (linearised about the preload, which keeps it
closed), and a law that uses the velocity with its ``tangent`` at zero velocity. The eigenproblem
``K_t phi = omega^2 M phi`` on the free DOFs is solved for the lowest modes by shift-invert
Lanczos (``eigsh`` with a shift ``sigma < 0`` below every eigenvalue, so that zero-frequency
mechanisms are found too and ``M`` may be singular, e.g. lumped mass without rotary inertia),
or densely for small systems as ``M phi = nu (K - sigma M) phi``, ``lambda = sigma + 1/nu``.

Shapes are mass-normalised (``phi^T M phi = 1``), expanded to full DOFs (``T phi``) and signed
so that their largest component is positive.

Participation (uniform support excitation in direction ``d``, rigid-body vector ``r_d``):
``Gamma = phi^T M r_d`` and effective modal mass ``Gamma^2``; summed over all modes it gives the
*movable mass* ``r_d^T M T (T^T M T)^+ T^T M r_d`` (pseudo-inverse: DOFs without mass carry
none), the mass that can move: less than the total ``r_d^T M r_d`` by what the supports hold
(with a lumped mass exactly the mass on supported DOFs). Effective mass ratios are taken
against it (:attr:`ModalResult.mass_ratios`), so that all modes give 1.

Errors: :func:`eigen` raises :class:`~bearingfw.model.ModelError` (a ``ValueError``) for a bad
request (shift, method, more modes than DOFs with mass) and for a matrix it cannot factorise.

Labels, from the modal kinetic energy ``p = phi * (M phi)`` (elementwise, sums to 1):

- longitudinal = energy in ``ux``; lateral = ``uy`` + ``rz``;
- vertical = ``uz`` (its part symmetric about the deck axis) + ``ry``;
- torsional = ``rx`` + the part of ``uz`` antisymmetric about the deck axis.

The deck axis is the line ``y = axis_y`` (default: the mass centre's y). The antisymmetric part
of the vertical motion at a node is ``(w - w') / 2`` with ``w'`` the vertical displacement of its
mirror node (same x, z, mirrored y; a node without a mirror counts as symmetric), so the twin
girders of a deck moving in opposition read as torsion. The label is the largest share.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Sequence

import attrs
import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from bearingfw.analysis.static import (
    BEARINGS,
    ConvergenceError,
    StiffnessRangeError,
    StaticResult,
    gravity,
    initial_stiffness_error,
    initial_tangent,
)
from bearingfw.model import COMPONENTS, DIRECTIONS, ModelError, System, as_system
from bearingfw.model.dofs import NDOF_NODE
from bearingfw.plugins import Registry

__all__ = [
    "ModalResult",
    "solve_modal",
    "eigen",
    "TooManyModes",
    "initial_tangent",
    "participation",
    "movable_mass",
    "energy_shares",
    "label_modes",
    "mac",
    "automac",
    "LABELS",
    "DEFAULT_SHIFT",
]

LABELS = ("vertical", "lateral", "longitudinal", "torsional")
#: Default eigenvalue shift (rad/s)^2: below zero, so that K - sigma M is positive definite.
DEFAULT_SHIFT = -1.0
#: Systems up to this many free DOFs are solved densely by ``method="auto"``.
DENSE_LIMIT = 100
#: ``nu = 1 / (lambda - shift)`` below this fraction of the largest means an infinite eigenvalue (a
#: direction without mass). LAPACK resolves a zero ``nu`` to round-off; ARPACK's Ritz values of a
#: zero ``nu`` stay at ~1e-11 of the largest, so the sparse test is looser (still ~3e4 times the
#: lowest frequency, far beyond any mode a sparse solve is asked for).
_INFINITE = {"dense": 1e-12, "sparse": 1e-9}


class TooManyModes(ModelError):
    """More modes were asked for than the model has DOFs with mass (``available``)."""

    def __init__(self, message: str, available: int):
        super().__init__(message)
        self.available = available


def eigen(K, M, n_modes: int, *, shift: float = DEFAULT_SHIFT, method: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``n_modes`` eigenpairs of ``K phi = lambda M phi``: (lambda ascending, M-normalised phi).

    Raises :class:`~bearingfw.model.ModelError` (a ``ValueError``) for a bad request and when
    ``K - shift M`` cannot be factorised.
    """
    n = K.shape[0]
    if shift >= 0:
        raise ModelError(f"eigen: shift must be negative, got {shift!r}")
    if method not in ("auto", "dense", "sparse"):
        raise ModelError(f"eigen: method must be 'auto', 'dense' or 'sparse', got {method!r}")
    massive = int(np.count_nonzero(np.abs(M.diagonal()) > 0))
    if not 1 <= n_modes <= massive:
        raise TooManyModes(f"asked for {n_modes} modes; the model has {massive} DOFs with mass (at most that many modes)",
                           massive)
    dense = method == "dense" or (method == "auto" and (n <= DENSE_LIMIT or n_modes >= n - 1))
    if dense:
        Kd, Md = (np.asarray(A.todense()) if sp.issparse(A) else np.asarray(A) for A in (K, M))
        try:
            nu, vec = sla.eigh(Md, Kd - shift * Md)
        except np.linalg.LinAlgError as exc:
            raise ModelError(f"K - shift*M is not positive definite ({exc}): a mechanism without mass?") from exc
        order = np.argsort(nu)[::-1][:n_modes]
        nu, vec = nu[order], vec[:, order]
        infinite = _INFINITE["dense"]
    else:
        v0 = np.ones(n)  # deterministic start vector
        try:
            lam, vec = spla.eigsh(K.tocsc(), k=n_modes, M=M.tocsc(), sigma=shift, which="LM", v0=v0)
        except RuntimeError as exc:
            raise ModelError(f"shift-invert factorisation failed ({exc}): a mechanism without mass?") from exc
        nu = 1.0 / (lam - shift)  # a spurious Ritz value may come out below the shift: nu < 0
        order = np.argsort(nu)[::-1]
        nu, vec = nu[order], vec[:, order]
        infinite = _INFINITE["sparse"]
    # An infinite eigenvalue (a direction without mass) has nu = 0.
    finite = nu > infinite * nu[0]
    if not np.all(finite):
        raise ModelError(f"asked for {n_modes} modes; the model has only {int(np.sum(finite))} with mass")
    lam = shift + 1.0 / nu
    vec = vec / np.sqrt(np.einsum("ij,ij->j", vec, M @ vec))
    biggest = np.argmax(np.abs(vec), axis=0)
    vec = vec * np.sign(vec[biggest, np.arange(vec.shape[1])])
    return lam, vec


def participation(system: System, shapes: np.ndarray, directions: Sequence[str] = DIRECTIONS, about=(0.0, 0.0, 0.0)):
    """Participation factors, effective masses (per mode) and total masses ``r^T M r`` per direction."""
    gamma, meff, total = {}, {}, {}
    for d in directions:
        Mr = system.M @ system.rigid_body(d, about)
        gamma[d] = shapes.T @ Mr
        meff[d] = gamma[d] ** 2
        total[d] = float(system.rigid_body(d, about) @ Mr)
    return gamma, meff, total


def movable_mass(system: System, directions: Sequence[str] = DIRECTIONS, about=(0.0, 0.0, 0.0)) -> dict[str, float]:
    """``b^T M_free^+ b`` with ``b = T^T M r`` per direction: the sum of the effective masses of all modes.

    ``b = T^T M^(1/2) (M^(1/2) r)`` lies in the range of ``T^T M^(1/2)``, which is the range of
    ``M_free = T^T M T``: the pseudo-inverse is well defined even where ``M_free`` is singular (lumped mass without
    rotary inertia, an offset mass): it is applied by a slightly regularised factorisation,
    ``x <- x + (M_free + eps I)^{-1} (b - M_free x)``, which converges on the range of ``M_free``
    (by ``eps / (eps + m)`` per step) and adds nothing along its null space (``b`` has no part
    there).
    """
    M_free = system.M_free.tocsc()
    b = np.column_stack([system.reduce(system.M @ system.rigid_body(d, about)) for d in directions])
    scale = float(abs(M_free.diagonal()).max(initial=0.0))
    if scale == 0.0:
        return dict.fromkeys(directions, 0.0)
    lu = spla.splu((M_free + 1e-10 * scale * sp.eye(M_free.shape[0])).tocsc())
    x = np.zeros_like(b)
    total = np.zeros(len(directions))
    for _ in range(50):
        x = x + lu.solve(b - M_free @ x)
        previous, total = total, np.einsum("ij,ij->j", b, x)
        if np.all(np.abs(total - previous) <= 1e-14 * np.abs(total)):
            break
    return {d: float(t) for d, t in zip(directions, total, strict=True)}


def _mirror_partners(coords: np.ndarray, axis_y: float) -> np.ndarray:
    mirrored = coords.copy()
    mirrored[:, 1] = 2 * axis_y - coords[:, 1]
    size = float(np.linalg.norm(coords.max(axis=0) - coords.min(axis=0)))
    tol = 1e-6 * size + 1e-9
    from scipy.spatial import cKDTree  # here: scipy.spatial's import costs 0.2 s in every process that never pairs nodes

    dist, idx = cKDTree(coords).query(mirrored, distance_upper_bound=tol)
    own = np.arange(len(coords))
    return np.where(np.isfinite(dist), idx, own)


def energy_shares(system: System, shapes: np.ndarray, axis_y: float | None = None) -> dict[str, np.ndarray]:
    """Kinetic-energy shares per label (module docstring), each (n_modes,), summing to 1."""
    Mphi = system.M @ shapes
    p = shapes * Mphi
    comp = {c: p[k::NDOF_NODE].sum(axis=0) for k, c in enumerate(COMPONENTS)}
    uy, uz = COMPONENTS.index("uy"), COMPONENTS.index("uz")
    coords = system.model.coordinates
    if axis_y is None:
        w = (system.M @ system.rigid_body("y"))[uy::NDOF_NODE]
        axis_y = float(w @ coords[:, 1] / w.sum()) if w.sum() > 0 else float(coords[:, 1].mean())
    partner = _mirror_partners(coords, axis_y)
    wz, Mwz = shapes[uz::NDOF_NODE], Mphi[uz::NDOF_NODE]
    anti = ((wz - wz[partner]) / 2 * Mwz).sum(axis=0)
    shares = {
        "vertical": comp["uz"] - anti + comp["ry"],
        "lateral": comp["uy"] + comp["rz"],
        "longitudinal": comp["ux"],
        "torsional": comp["rx"] + anti,
    }
    total = sum(shares.values())
    total = np.where(np.abs(total) > 0, total, 1.0)
    return {k: v / total for k, v in shares.items()}


def label_modes(shares: dict[str, np.ndarray]) -> tuple[str, ...]:
    table = np.array([shares[k] for k in LABELS])
    return tuple(LABELS[k] for k in np.argmax(table, axis=0))


def mac(phi_a: np.ndarray, phi_b: np.ndarray, dofs: Sequence[int] | np.ndarray | None = None) -> np.ndarray:
    """Modal assurance criterion (the paper's eq. 12), ``(n_a, n_b)``.

    ``MAC_ij = (a_i . b_j)^2 / ((a_i . a_i) (b_j . b_j))`` over the rows ``dofs`` (default: all)
    of the shape matrices (one mode per column; a 1-D array is one mode). It is invariant to the
    scale and sign of either shape.
    """
    a = np.asarray(phi_a, dtype=float)
    b = np.asarray(phi_b, dtype=float)
    a = a[:, None] if a.ndim == 1 else a
    b = b[:, None] if b.ndim == 1 else b
    if dofs is not None:
        a, b = a[np.asarray(dofs)], b[np.asarray(dofs)]
    if a.shape[0] != b.shape[0]:
        raise ValueError(f"mac: shapes have {a.shape[0]} and {b.shape[0]} rows")
    na, nb = np.einsum("ij,ij->j", a, a), np.einsum("ij,ij->j", b, b)
    if np.any(na == 0) or np.any(nb == 0):
        raise ValueError("mac: a mode shape is zero at the chosen DOFs")
    return (a.T @ b) ** 2 / np.outer(na, nb)


def automac(phi: np.ndarray, dofs: Sequence[int] | np.ndarray | None = None) -> np.ndarray:
    """MAC of a mode set against itself (1 on the diagonal)."""
    return mac(phi, phi, dofs)


@attrs.frozen(eq=False)
class ModalResult:
    """Modes of the linearised model, lowest first.

    ``shapes`` (n_dof, n_modes) in full DOFs, mass-normalised. ``participation``,
    ``effective_mass`` map a direction (``x, y, z, rx, ry, rz``) to per-mode arrays;
    ``total_mass`` to ``r^T M r`` (all the mass, supported DOFs included); ``movable_mass`` to
    the mass that can move, the sum of the effective masses of all modes (module docstring).
    ``shares`` maps each label to per-mode energy shares. ``normal_forces`` are the connectors'
    ``N`` the laws were linearised at; ``about`` the reference point of rotational participation.
    """

    system: System
    eigenvalues: np.ndarray
    shapes: np.ndarray
    participation: dict[str, np.ndarray]
    effective_mass: dict[str, np.ndarray]
    total_mass: dict[str, float]
    shares: dict[str, np.ndarray]
    labels: tuple[str, ...]
    normal_forces: np.ndarray
    about: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @functools.cached_property
    def movable_mass(self) -> dict[str, float]:
        """:func:`movable_mass` per direction (computed on first use: it factorises ``M_free``)."""
        return movable_mass(self.system, tuple(self.effective_mass), self.about)

    @property
    def mass_ratios(self) -> dict[str, np.ndarray]:
        """Effective mass over movable mass per direction and mode (all modes sum to 1)."""
        movable = self.movable_mass
        return {d: m / movable[d] if movable[d] > 0 else np.zeros_like(m) for d, m in self.effective_mass.items()}

    @property
    def n_modes(self) -> int:
        return int(self.eigenvalues.size)

    @property
    def shapes_free(self) -> np.ndarray:
        """The shapes on the free DOFs ``q`` (``shapes = T shapes_free``)."""
        return self.shapes[self.system.free_dofs]

    @property
    def omega(self) -> np.ndarray:
        """Circular frequencies (rad/s); a slightly negative eigenvalue (mechanism) gives 0."""
        return np.sqrt(np.maximum(self.eigenvalues, 0.0))

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies (Hz)."""
        return self.omega / (2 * np.pi)

    @property
    def numbered_labels(self) -> tuple[str, ...]:
        """``"vertical 1", "lateral 1", "vertical 2", ...``"""
        seen: dict[str, int] = {}
        out = []
        for lab in self.labels:
            seen[lab] = seen.get(lab, 0) + 1
            out.append(f"{lab} {seen[lab]}")
        return tuple(out)

    def find(self, label: str, k: int = 1) -> int:
        """Index of the ``k``-th mode labelled ``label``."""
        hits = [m for m, lab in enumerate(self.labels) if lab == label]
        if len(hits) < k:
            raise KeyError(f"only {len(hits)} {label!r} mode(s) among the {self.n_modes} computed")
        return hits[k - 1]

    def dominant(self, direction: str) -> int:
        """Index of the mode with the largest effective mass in ``direction``."""
        return int(np.argmax(self.effective_mass[direction]))


def solve_modal(
    model_or_system,
    n_modes: int = 10,
    *,
    preload: StaticResult | None = None,
    registry: Registry | None = None,
    g: float = 9.81,
    dt: float = 1.0,
    shift: float = DEFAULT_SHIFT,
    method: str = "auto",
    about=(0.0, 0.0, 0.0),
    axis_y: float | None = None,
    bearings: str = "set-after-dead-load",
) -> ModalResult:
    """The lowest ``n_modes`` modes with every connector at its law's initial tangent.

    The laws' normal forces come from ``preload`` (default: :func:`gravity` with ``g`` and
    ``bearings``, run only when some law is present). If that automatic preload fails, a
    mechanism in statics (:class:`~bearingfw.model.ModelError`, e.g. frictionless bearings
    without other horizontal restraint, which the modes show as zero frequencies) or no
    convergence (:class:`ConvergenceError`), the analysis goes on with a warning and the laws
    get ``N = 0`` for their initial tangent (which for the built-in laws does not depend on
    ``N``); pass a ``preload`` to control it. ``about`` is the reference point of rotational
    participation, ``axis_y`` the deck axis used for the torsion label.

    A law tangent that is not finite, or so stiff that the matrices lose the structure beside it,
    raises :class:`~bearingfw.analysis.static.StiffnessRangeError` naming the law and the bearing.
    """
    system = as_system(model_or_system, registry)
    if bearings not in BEARINGS:  # checked here: a failing automatic preload only warns
        raise ModelError(f"solve_modal: parameter 'bearings' must be one of {', '.join(map(repr, BEARINGS))}")
    ops = system.connectors
    N = np.zeros(ops.n_connectors)
    if preload is not None:
        N = preload.normal_forces
    elif ops.groups:
        try:
            N = gravity(system, g=g, dt=dt, bearings=bearings).normal_forces
        except StiffnessRangeError:  # bad input, not a preload to do without
            raise
        except (ModelError, ConvergenceError) as exc:
            warnings.warn(
                f"modal: gravity preload failed ({type(exc).__name__}: {exc}); laws get N = 0 for their initial "
                "tangent",
                stacklevel=2,
            )
    Kt = initial_tangent(system, N, dt)
    try:
        lam, phi = eigen(Kt, system.M_free, n_modes, shift=shift, method=method)
    except ModelError as exc:  # a law so stiff that the eigensolver lost the structure: say so
        error = initial_stiffness_error(system, N, dt, failure=f"eigen: {exc}")
        if error is not None:
            raise error from exc
        raise
    shapes = np.asarray(system.expand(phi))
    gamma, meff, total = participation(system, shapes, DIRECTIONS, about)
    shares = energy_shares(system, shapes, axis_y)
    return ModalResult(
        system=system,
        eigenvalues=lam,
        shapes=shapes,
        participation=gamma,
        effective_mass=meff,
        total_mass=total,
        shares=shares,
        labels=label_modes(shares),
        normal_forces=np.asarray(N, dtype=float),
        about=tuple(float(a) for a in about),
    )
