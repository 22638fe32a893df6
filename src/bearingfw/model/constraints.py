"""Constraints as a master-slave transformation ``u = T q``.

Supports, rigid links (offsets) and tied connector directions are all homogeneous linear
equations on the full DOF vector, ``C u = 0``. They are eliminated exactly (no penalty
numbers): each equation, after substituting the slaves found so far, picks one DOF (its
*slave*) and expresses it through the remaining independent (*master*) DOFs. Collecting the
expressions gives the sparse matrix ``T`` (full DOFs x independent DOFs) with ``u = T q``:
identity rows for masters, the expression for each slave. Any ``q`` satisfies every equation,
and the reduced matrices are ``T^T K T`` and ``T^T M T``.

- Support: ``u_d = 0``; the DOF is a slave with an empty expression.
- Rigid link (master ``m``, slave ``s``, arm ``r = X_s - X_m``): the six equations
  ``u_s - u_m - theta_m x r = 0`` and ``theta_s - theta_m = 0``; the slave node's DOFs are
  eliminated, so a rigid offset costs no DOFs.
- Tied connector direction ``e`` (a row of the connector frame): ``e . (u_j - u_i) = 0``.

Zero coefficients: after substitution a coefficient counts as zero below ``_RELATIVE_ZERO``
times the equation's largest coefficient. In a translation equation (one on translation DOFs:
supports of ``u*``, the first three rows of a link, ties) a rotation coefficient is a lever arm
(m): a row left with nothing but arms shorter than ``ARM_ZERO`` (the connector length
tolerance, within which the model treats two nodes as coincident) is redundant too. Without
this, a tie between two nodes rigidly linked to the same master a round-off distance apart
would keep the sub-micrometre arm terms and clamp the master's rotations. (A row that keeps a
real term keeps its short arms as well: the other equations stay exact.)

Slave choice: each equation lists preferred candidates (the slave node's DOFs for a link, the
girder-side node's translations for a tie) and falls back to other DOFs when those are already
eliminated, translations before rotations, largest coefficient first. An equation that
vanishes after substitution is *redundant* (e.g. a tie between two supported nodes): it is
skipped and carries no force.

Constraint forces: at equilibrium the full residual ``r = K u - f`` (plus inertia in dynamics)
lies in the range of ``C^T``; the Lagrange multipliers ``lambda`` solve ``C^T lambda = r``
(least squares via ``C C^T``). ``lambda`` of a support equation is the support reaction; of a
tie, the force the connector applies to node ``j`` along ``e``.

DOFs that nothing touches (no stiffness, mass or connector, e.g. rotations of a node reached
only by truss bars) are also removed from ``q`` (held at zero); they are listed in
``Constraints.inactive``.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence

import attrs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from bearingfw.model.dofs import NDOF_NODE, DofMap, component_index
from bearingfw.model.equations import Equation
from bearingfw.model.model import CONNECTOR_LENGTH_TOLERANCE, Model

__all__ = [
    "Equation",
    "Constraints",
    "support_equations",
    "rigid_link_equations",
    "eliminate",
    "build_constraints",
]

#: An equation's coefficients below this fraction of its largest original coefficient count as zero.
_RELATIVE_ZERO = 1e-10
#: Lever arms (rotation coefficients of a translation equation, m) shorter than this count as zero.
ARM_ZERO = CONNECTOR_LENGTH_TOLERANCE


def _only_short_arms(eq: Equation, row: dict[int, float]) -> bool:
    """Whether the reduced ``row`` of a translation equation holds nothing but lever arms below ``ARM_ZERO``.

    A translation equation's coefficients on translations are dimensionless and those on
    rotations are lengths (m), compared with ``ARM_ZERO`` times the size of its translation
    coefficients. A rotation equation has no arms.
    """
    pairs = zip(eq.dofs.tolist(), eq.coefficients.tolist(), strict=True)
    on_translations = [abs(c) for d, c in pairs if d % NDOF_NODE < 3]
    if not on_translations:
        return False
    arm_zero = ARM_ZERO * max(on_translations)
    return all(d % NDOF_NODE >= 3 and abs(c) <= arm_zero for d, c in row.items())


def support_equations(model: Model, dofmap: DofMap) -> list[Equation]:
    eqs = []
    for k, support in enumerate(model.supports):
        for comp in support.dofs:
            c = component_index(comp)
            d = dofmap.dof(support.node, c)
            eqs.append(Equation(np.array([d]), np.array([1.0]), "support", k, c, ((d,),)))
    return eqs


def rigid_link_equations(model: Model, dofmap: DofMap) -> list[Equation]:
    """``u_s = u_m + theta_m x r`` and ``theta_s = theta_m`` for every rigid link."""
    eqs = []
    coords = model.coordinates
    for k, link in enumerate(model.rigid_links):
        m = dofmap.node_dofs(link.master)
        s = dofmap.node_dofs(link.slave)
        rx, ry, rz = coords[model.node_index(link.slave)] - coords[model.node_index(link.master)]
        # (theta x r) = (ty rz - tz ry, tz rx - tx rz, tx ry - ty rx)
        rows = [
            ([s[0], m[0], m[4], m[5]], [1.0, -1.0, -rz, ry]),
            ([s[1], m[1], m[5], m[3]], [1.0, -1.0, -rx, rz]),
            ([s[2], m[2], m[3], m[4]], [1.0, -1.0, -ry, rx]),
            ([s[3], m[3]], [1.0, -1.0]),
            ([s[4], m[4]], [1.0, -1.0]),
            ([s[5], m[5]], [1.0, -1.0]),
        ]
        for c, (dofs, coeffs) in enumerate(rows):
            dofs, coeffs = np.array(dofs), np.array(coeffs)
            keep = coeffs != 0.0
            eqs.append(Equation(dofs[keep], coeffs[keep], "link", k, c, (tuple(s), tuple(m))))
    return eqs


def _pick_slave(row: dict[int, float], candidates: Sequence[Sequence[int]]) -> int:
    biggest = max(abs(c) for c in row.values())
    translations = tuple(d for d in row if d % NDOF_NODE < 3)
    for group in (*candidates, translations, tuple(row)):
        present = [d for d in group if d in row]
        if present:
            best = max(present, key=lambda d: (abs(row[d]), -d))
            # A tiny pivot would put huge numbers into T: skip the group then.
            if abs(row[best]) >= 1e-6 * biggest:
                return best
    return max(row, key=lambda d: (abs(row[d]), -d))


def eliminate(equations: Sequence[Equation]) -> tuple[dict[int, dict[int, float]], list[Equation], list[Equation]]:
    """Gaussian elimination of the equations, in order, into slave expressions.

    Returns ``(slaves, independent, redundant)``: ``slaves[s]`` maps master DOFs to the
    coefficients of ``u_s`` (every DOF in an expression is a master).
    """
    slaves: dict[int, dict[int, float]] = {}
    users: dict[int, set[int]] = defaultdict(set)  # master DOF -> slaves whose expression holds it
    independent: list[Equation] = []
    redundant: list[Equation] = []
    for eq in equations:
        row: dict[int, float] = defaultdict(float)
        for d, c in zip(eq.dofs.tolist(), eq.coefficients.tolist(), strict=True):
            if d in slaves:
                for m, cm in slaves[d].items():
                    row[m] += c * cm
            else:
                row[d] += c
        tol = _RELATIVE_ZERO * float(np.max(np.abs(eq.coefficients)))
        row = {d: c for d, c in row.items() if abs(c) > tol}
        if not row or _only_short_arms(eq, row):
            redundant.append(eq)
            continue
        s = _pick_slave(row, eq.candidates)
        cs = row.pop(s)
        expr = {m: -c / cs for m, c in row.items()}
        # Existing expressions that use s now get s's expression instead.
        for t in users.pop(s, ()):
            et = slaves[t]
            ct = et.pop(s, 0.0)
            if ct == 0.0:
                continue
            for m, cm in expr.items():
                et[m] = et.get(m, 0.0) + ct * cm
                users[m].add(t)
        slaves[s] = expr
        for m in expr:
            users[m].add(s)
        independent.append(eq)
    return slaves, independent, redundant


def _transformation(n_dof: int, slaves: dict[int, dict[int, float]], masters: np.ndarray) -> sp.csr_matrix:
    col = np.full(n_dof, -1)
    col[masters] = np.arange(masters.size)
    rows, cols, vals = [masters], [np.arange(masters.size)], [np.ones(masters.size)]
    for s, expr in slaves.items():
        if expr:
            ms = np.fromiter(expr.keys(), dtype=int, count=len(expr))
            rows.append(np.full(ms.size, s))
            cols.append(col[ms])
            vals.append(np.fromiter(expr.values(), dtype=float, count=len(expr)))
    rows, cols, vals = map(np.concatenate, (rows, cols, vals))
    if np.any(cols < 0):  # an expression names a DOF that was dropped: a bug, not user input
        raise AssertionError("constraint elimination left a slave depending on an inactive DOF")
    return sp.csr_matrix((vals, (rows, cols)), shape=(n_dof, masters.size))


@attrs.frozen(eq=False)
class Constraints:
    """The result of eliminating the constraint equations (see the module docstring)."""

    T: sp.csr_matrix
    masters: np.ndarray
    equations: tuple[Equation, ...]
    redundant: tuple[Equation, ...]
    inactive: np.ndarray
    C: sp.csr_matrix
    _gram: object = attrs.field(repr=False)

    @property
    def n_free(self) -> int:
        return self.T.shape[1]

    def multipliers(self, residual: np.ndarray) -> np.ndarray:
        """``lambda`` with ``C^T lambda = residual`` (one per independent equation)."""
        if not self.equations:
            return np.zeros(0)
        return self._gram.solve(self.C @ residual)

    def solve_gram(self, projected: np.ndarray) -> np.ndarray:
        """``(C C^T)^-1 projected``: :meth:`multipliers` for a residual already multiplied by ``C``."""
        if not self.equations:
            return np.zeros(0)
        return self._gram.solve(projected)


def build_constraints(n_dof: int, equations: Sequence[Equation], touched: np.ndarray) -> Constraints:
    """Eliminate ``equations`` and build ``T``; DOFs not ``touched`` (boolean, full) are dropped.

    ``touched[d]`` says whether anything (stiffness, mass, connector) acts on DOF ``d``; a
    master that neither it nor any slave depending on it touches is inactive.
    """
    slaves, independent, redundant = eliminate(equations)
    candidates = np.setdiff1d(np.arange(n_dof), np.fromiter(slaves.keys(), dtype=int, count=len(slaves)))
    T0 = _transformation(n_dof, slaves, candidates)
    # A master is active if some full DOF it drives is touched.
    reach = abs(T0).T @ touched.astype(float)
    active = reach > 0
    masters = candidates[active]
    inactive = candidates[~active]
    T = T0[:, np.flatnonzero(active)].tocsr()
    if independent:
        rows = np.concatenate([np.full(eq.dofs.size, k) for k, eq in enumerate(independent)])
        cols = np.concatenate([eq.dofs for eq in independent])
        vals = np.concatenate([eq.coefficients for eq in independent])
        C = sp.csr_matrix((vals, (rows, cols)), shape=(len(independent), n_dof))
        gram = spla.splu((C @ C.T).tocsc())
    else:
        C = sp.csr_matrix((0, n_dof))
        gram = None
    return Constraints(T, masters, tuple(independent), tuple(redundant), inactive, C, gram)
