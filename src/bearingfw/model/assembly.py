"""Element matrices in local axes, their transformation to global axes, and sparse assembly.

Everything here is a pure function over arrays, vectorised over the elements of one type.

Frame element (12 DOFs: node i then node j, each ``ux, uy, uz, rx, ry, rz`` in local axes):

- axial ``EA/L``, St-Venant torsion ``GJ/L``;
- bending in the local x-y plane (``v``, ``theta_z = v'``) with ``E Iz`` and in the x-z plane
  (``w``, ``theta_y = -w'``, hence the sign flips) with ``E Iy``;
- Timoshenko shear deformation through ``phi_y = 12 E Iz / (G Avy L^2)`` and
  ``phi_z = 12 E Iy / (G Avz L^2)`` (zero for Euler-Bernoulli). For tip-loaded members both
  stiffnesses are exact (the cubic solves the beam equation without span load).
- consistent mass: cubic Hermitian translational mass ``m L / 420 [...]``, axial and torsional
  ``(m L / 6) [2 1; 1 2]`` with ``m = rho A + added`` (torsion ``rho (Iy + Iz)``); lumped mass:
  ``m L / 2`` per node and direction, ``rho Ip L / 2`` in torsion, no rotary inertia in bending.
  The Timoshenko element keeps the Euler-Bernoulli mass (an O(phi) approximation).

Global matrices: ``k_global = L^T k_local L`` with ``L = diag(R, R, R, R)``, ``R`` the rows
of the local axes. Assembly: COO triplets summed into CSR.

Gravity uses the *consistent* (work-equivalent) load of the member's weight per length
``w = (rho A + added) g`` whatever the mass option: ``wL/2`` at each end and the fixed-end
moments ``wL^2/12``; truss bars take ``wL/2`` at each end. Nodal masses take ``m g``.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.model._fields import ModelError
from bearingfw.model.dofs import DofMap
from bearingfw.model.elements import FrameElement, TrussElement

__all__ = [
    "FrameArrays",
    "TrussArrays",
    "frame_arrays",
    "truss_arrays",
    "frame_axes",
    "NEAR_VERTICAL",
    "frame_local_stiffness",
    "frame_local_mass",
    "frame_uniform_load",
    "to_global",
    "assemble",
    "stiffness_matrix",
    "mass_matrix",
    "gravity_load",
]

_GLOBAL_X = np.array([1.0, 0.0, 0.0])
_GLOBAL_Z = np.array([0.0, 0.0, 1.0])
#: A member whose axis is within this angle (sine, ~0.06 degrees) of global Z counts as vertical.
NEAR_VERTICAL = 1e-3
#: A given ``orientation`` within this angle (sine) of the member axis is rejected as parallel.
_PARALLEL = 1e-9


def frame_axes(
    xi: np.ndarray, xj: np.ndarray, orientation: np.ndarray | None, names: Sequence[str] | None = None
) -> np.ndarray:
    """Local axes of frame members, shape (n, 3, 3), rows ``x, y, z``.

    ``orientation`` (n, 3) with NaN rows for "default" (see :mod:`bearingfw.model.elements`):
    ``v = Z``, except for a member within ``NEAR_VERTICAL`` of vertical, where ``v = -X``.
    Then ``y = normalize(v x x) = (0, x_z, -x_y) / |.|`` is continuous in the tilt, whatever
    its direction: a vertical member has ``y = +Y`` (pointing up) or ``-Y`` (down) and
    ``z = -X``, and a member tilted by a small angle ``a`` has axes within ``a`` of those.
    ``names`` (the members' names) let an error name the member.
    """
    x = xj - xi
    x = x / np.linalg.norm(x, axis=1, keepdims=True)
    v = np.broadcast_to(_GLOBAL_Z, x.shape).copy()
    # Near vertical, v = Z would make y = normalize(Z x x) swing with the direction of the
    # tilt; v = -X keeps it continuous there. No rule is continuous for every axis direction
    # (hairy-ball theorem): this one jumps at 0.06 degrees of tilt, beyond which a sloping
    # member gets the horizontal-member rule, as its user expects.
    vertical = np.linalg.norm(np.cross(v, x), axis=1) < NEAR_VERTICAL
    v[vertical] = -_GLOBAL_X
    if orientation is not None:
        given = ~np.isnan(orientation[:, 0])
        v[given] = orientation[given]
    y = np.cross(v, x)
    norm = np.linalg.norm(y, axis=1)
    parallel = norm < _PARALLEL * np.linalg.norm(v, axis=1)
    if np.any(parallel):
        k = int(np.flatnonzero(parallel)[0])
        who = f"FrameElement {names[k]!r}" if names is not None else "frame element"
        raise ModelError(f"{who}: field 'orientation' {tuple(v[k].tolist())} is parallel to the element axis")
    y = y / norm[:, None]
    z = np.cross(x, y)
    return np.stack([x, y, z], axis=1)


#: Local DOFs of the bending planes: (v_i, theta_z,i, v_j, theta_z,j) and (w_i, theta_y,i, w_j, theta_y,j).
_XY_PLANE = np.array([1, 5, 7, 11])
_XZ_PLANE = np.array([2, 4, 8, 10])
#: In the x-z plane theta_y = -w': the rotation rows and columns of a block change sign.
_XZ_FLIP = np.array([1.0, -1.0, 1.0, -1.0])


def _embed_bending(out: np.ndarray, xy: np.ndarray, xz: np.ndarray) -> None:
    """Put (n, 4, 4) bending blocks written for ``theta = +w'`` into (n, 12, 12) element matrices."""
    out[:, _XY_PLANE[:, None], _XY_PLANE[None, :]] = xy
    out[:, _XZ_PLANE[:, None], _XZ_PLANE[None, :]] = xz * _XZ_FLIP[None, :, None] * _XZ_FLIP[None, None, :]


def frame_local_stiffness(L, E, G, A, Iy, Iz, J, phi_y, phi_z) -> np.ndarray:
    """Local stiffness matrices, shape (n, 12, 12) (Euler-Bernoulli when ``phi = 0``)."""
    n = L.size
    k = np.zeros((n, 12, 12))
    ea, gj = E * A / L, G * J / L
    for a, b, val in ((0, 0, ea), (6, 6, ea), (0, 6, -ea), (3, 3, gj), (9, 9, gj), (3, 9, -gj)):
        k[:, a, b] = val
        k[:, b, a] = val

    # Bending block [w_i, t_i, w_j, t_j] for a plane where theta = +w'.
    def block(EI, phi):
        c = EI / ((1.0 + phi) * L**3)
        b = np.zeros((n, 4, 4))
        b[:, 0, 0] = b[:, 2, 2] = 12 * c
        b[:, 0, 2] = b[:, 2, 0] = -12 * c
        b[:, 0, 1] = b[:, 1, 0] = b[:, 0, 3] = b[:, 3, 0] = 6 * L * c
        b[:, 2, 1] = b[:, 1, 2] = b[:, 2, 3] = b[:, 3, 2] = -6 * L * c
        b[:, 1, 1] = b[:, 3, 3] = (4 + phi) * L**2 * c
        b[:, 1, 3] = b[:, 3, 1] = (2 - phi) * L**2 * c
        return b

    _embed_bending(k, block(E * Iz, phi_y), block(E * Iy, phi_z))
    return k


def frame_local_mass(L, m_line, rho_ip, lumped) -> np.ndarray:
    """Local mass matrices, shape (n, 12, 12); ``lumped`` is a boolean array."""
    n = L.size
    mass = np.zeros((n, 12, 12))
    mL = m_line * L
    # consistent
    for a, b, val in ((0, 0, 2), (6, 6, 2), (0, 6, 1)):
        mass[:, a, b] = mass[:, b, a] = val * mL / 6
    for a, b, val in ((3, 3, 2), (9, 9, 2), (3, 9, 1)):
        mass[:, a, b] = mass[:, b, a] = val * rho_ip * L / 6
    # Cubic Hermitian bending mass, (m L / 420) [...] for [w_i, t_i, w_j, t_j] with theta = +w'.
    c = mL / 420
    herm = np.zeros((n, 4, 4))
    herm[:, 0, 0] = herm[:, 2, 2] = 156 * c
    herm[:, 0, 2] = herm[:, 2, 0] = 54 * c
    herm[:, 0, 1] = herm[:, 1, 0] = 22 * L * c
    herm[:, 2, 3] = herm[:, 3, 2] = -22 * L * c
    herm[:, 1, 2] = herm[:, 2, 1] = 13 * L * c
    herm[:, 0, 3] = herm[:, 3, 0] = -13 * L * c
    herm[:, 1, 1] = herm[:, 3, 3] = 4 * L**2 * c
    herm[:, 1, 3] = herm[:, 3, 1] = -3 * L**2 * c
    _embed_bending(mass, herm, herm)
    # lumped
    if np.any(lumped):
        lump = np.zeros((n, 12, 12))
        for d in (0, 1, 2, 6, 7, 8):
            lump[:, d, d] = mL / 2
        for d in (3, 9):
            lump[:, d, d] = rho_ip * L / 2
        mass = np.where(np.asarray(lumped)[:, None, None], lump, mass)
    return mass


def frame_uniform_load(L: np.ndarray, q_local: np.ndarray) -> np.ndarray:
    """Work-equivalent end loads (n, 12) of a uniform load ``q_local`` (n, 3) per length, local axes."""
    qx, qy, qz = q_local.T
    f = np.zeros((L.size, 12))
    f[:, [0, 6]] = (qx * L / 2)[:, None]
    f[:, [1, 7]] = (qy * L / 2)[:, None]
    f[:, [2, 8]] = (qz * L / 2)[:, None]
    f[:, 5], f[:, 11] = qy * L**2 / 12, -qy * L**2 / 12
    f[:, 4], f[:, 10] = -qz * L**2 / 12, qz * L**2 / 12
    return f


def to_global(k_local: np.ndarray, R: np.ndarray) -> np.ndarray:
    """``L^T k L`` for every element, ``L = diag(R, R, R, R)``."""
    n, size, _ = k_local.shape
    blocks = size // 3
    kb = k_local.reshape(n, blocks, 3, blocks, 3)
    return np.einsum("nsp,nasbt,ntq->napbq", R, kb, R).reshape(n, size, size)


def assemble(n_dof: int, dofs: np.ndarray, matrices: np.ndarray) -> sp.csr_matrix:
    """Sum element matrices (n, m, m) at DOFs (n, m) into an (n_dof, n_dof) CSR matrix."""
    m = dofs.shape[1]
    rows = np.repeat(dofs, m, axis=1).reshape(-1)
    cols = np.tile(dofs, (1, m)).reshape(-1)
    return sp.csr_matrix((matrices.reshape(-1), (rows, cols)), shape=(n_dof, n_dof))


@attrs.frozen(eq=False)
class FrameArrays:
    """The frame elements of a model as arrays (element order of ``Model.elements``)."""

    index: np.ndarray  # positions in Model.elements
    dofs: np.ndarray  # (n, 12) full DOFs
    L: np.ndarray
    R: np.ndarray  # (n, 3, 3) local axes (rows)
    k_local: np.ndarray  # (n, 12, 12)
    m_local: np.ndarray  # (n, 12, 12)
    weight_local: np.ndarray  # (n, 12) end loads of the member's weight per unit g

    @property
    def n(self) -> int:
        return int(self.index.size)

    def transform(self) -> np.ndarray:
        """``diag(R, R, R, R)`` per element, (n, 12, 12)."""
        lam = np.zeros((self.n, 12, 12))
        for b in range(4):
            lam[:, 3 * b : 3 * b + 3, 3 * b : 3 * b + 3] = self.R
        return lam


@attrs.frozen(eq=False)
class TrussArrays:
    """The truss bars of a model as arrays."""

    index: np.ndarray
    dofs: np.ndarray  # (n, 6): translations of i then j
    L: np.ndarray
    e: np.ndarray  # (n, 3) unit axis
    EA: np.ndarray
    k_global: np.ndarray  # (n, 6, 6)
    m_global: np.ndarray  # (n, 6, 6)
    weight_line: np.ndarray  # (n,) mass per length (for gravity)


def frame_arrays(model, dofmap: DofMap) -> FrameArrays:
    elems = [(k, e) for k, e in enumerate(model.elements) if isinstance(e, FrameElement)]
    index = np.array([k for k, _ in elems], dtype=int)
    if not elems:
        z = np.zeros
        return FrameArrays(index, z((0, 12), int), z(0), z((0, 3, 3)), z((0, 12, 12)), z((0, 12, 12)), z((0, 12)))
    es = [e for _, e in elems]
    coords = model.coordinates
    xi = coords[[model.node_index(e.i) for e in es]]
    xj = coords[[model.node_index(e.j) for e in es]]
    orient = np.array([e.orientation if e.orientation is not None else (np.nan,) * 3 for e in es], dtype=float)
    R = frame_axes(xi, xj, orient, [e.name for e in es])
    L = np.linalg.norm(xj - xi, axis=1)
    get = lambda f: np.array([f(e) for e in es], dtype=float)  # noqa: E731
    E, G = get(lambda e: e.material.E), get(lambda e: e.material.shear_modulus)
    A, Iy, Iz, J = (get(lambda e, a=a: getattr(e.section, a)) for a in ("A", "Iy", "Iz", "J"))
    timo = np.array([e.shear_deformation for e in es])
    avy = get(lambda e: e.section.Avy if e.shear_deformation else np.inf)
    avz = get(lambda e: e.section.Avz if e.shear_deformation else np.inf)
    phi_y = np.where(timo, 12 * E * Iz / (G * avy * L**2), 0.0)
    phi_z = np.where(timo, 12 * E * Iy / (G * avz * L**2), 0.0)
    k_local = frame_local_stiffness(L, E, G, A, Iy, Iz, J, phi_y, phi_z)
    rho = get(lambda e: e.material.density)
    m_line = rho * A + get(lambda e: e.added_mass)
    lumped = np.array([e.mass == "lumped" for e in es])
    m_local = frame_local_mass(L, m_line, rho * (Iy + Iz), lumped)
    q_local = np.einsum("nij,j->ni", R, -_GLOBAL_Z) * m_line[:, None]  # weight per length per unit g
    weight_local = frame_uniform_load(L, q_local)
    dofs = np.concatenate([dofmap.node_dofs([e.i for e in es]), dofmap.node_dofs([e.j for e in es])], axis=1)
    return FrameArrays(index, dofs, L, R, k_local, m_local, weight_local)


def truss_arrays(model, dofmap: DofMap) -> TrussArrays:
    elems = [(k, e) for k, e in enumerate(model.elements) if isinstance(e, TrussElement)]
    index = np.array([k for k, _ in elems], dtype=int)
    es = [e for _, e in elems]
    coords = model.coordinates
    if not es:
        z = np.zeros
        return TrussArrays(index, z((0, 6), int), z(0), z((0, 3)), z(0), z((0, 6, 6)), z((0, 6, 6)), z(0))
    xi = coords[[model.node_index(e.i) for e in es]]
    xj = coords[[model.node_index(e.j) for e in es]]
    L = np.linalg.norm(xj - xi, axis=1)
    e = (xj - xi) / L[:, None]
    EA = np.array([t.material.E * t.area for t in es])
    nn = np.einsum("ni,nj->nij", e, e) * (EA / L)[:, None, None]
    k = np.block([[nn, -nn], [-nn, nn]])
    m_line = np.array([t.material.density * t.area + t.added_mass for t in es])
    eye = np.eye(3)[None]
    lumped = np.array([t.mass == "lumped" for t in es])[:, None, None]
    mc = np.block([[2 * eye, eye], [eye, 2 * eye]]) / 6
    ml = np.block([[eye, 0 * eye], [0 * eye, eye]]) / 2
    m = np.where(lumped, ml, mc) * (m_line * L)[:, None, None]
    dofs = np.concatenate(
        [dofmap.node_dofs([t.i for t in es])[:, :3], dofmap.node_dofs([t.j for t in es])[:, :3]], axis=1
    )
    return TrussArrays(index, dofs, L, e, EA, k, m, m_line)


def stiffness_matrix(n_dof: int, frames: FrameArrays, trusses: TrussArrays) -> sp.csr_matrix:
    """Element stiffness in global axes, full DOFs."""
    K = assemble(n_dof, frames.dofs, to_global(frames.k_local, frames.R))
    return (K + assemble(n_dof, trusses.dofs, trusses.k_global)).tocsr()


def mass_matrix(model, dofmap: DofMap, frames: FrameArrays, trusses: TrussArrays) -> sp.csr_matrix:
    """Element and nodal masses in global axes, full DOFs."""
    M = assemble(dofmap.n_dof, frames.dofs, to_global(frames.m_local, frames.R))
    M = M + assemble(dofmap.n_dof, trusses.dofs, trusses.m_global)
    diag = np.zeros(dofmap.n_dof)
    for nm in model.masses:
        d = dofmap.node_dofs(nm.node)
        diag[d] += (nm.mass, nm.mass, nm.mass, nm.ixx, nm.iyy, nm.izz)
    return (M + sp.diags(diag)).tocsr()


def gravity_load(model, dofmap: DofMap, frames: FrameArrays, trusses: TrussArrays, g: float) -> np.ndarray:
    """Full load vector of self-weight and superimposed dead load under gravity ``g`` (down -z)."""
    f = np.zeros(dofmap.n_dof)
    if frames.n:
        fg = np.einsum("nji,nj->ni", frames.transform(), frames.weight_local) * g
        np.add.at(f, frames.dofs, fg)
    if trusses.index.size:
        w = -(trusses.weight_line * trusses.L * g / 2)
        np.add.at(f, trusses.dofs[:, 2], w)
        np.add.at(f, trusses.dofs[:, 5], w)
    for nm in model.masses:
        f[dofmap.dof(nm.node, "uz")] -= nm.mass * g
    return f
