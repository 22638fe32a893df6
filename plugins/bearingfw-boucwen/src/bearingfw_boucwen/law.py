"""The Bouc-Wen smooth hysteretic law, 1-D and biaxial (Park-Wen), integrated in displacement.

Force (SI: N, m)::

    F = alpha k u + (1 - alpha) k uy z

with the dimensionless hysteretic variable ``z`` obeying, in 1-D (Bouc 1971, Wen 1976)::

    uy dz = A du - beta |du| |z|^(n-1) z - gamma du |z|^n

and, for ``dims = 2``, the biaxial form of Park, Wen & Ang (1986) written for any exponent n::

    uy dz = A du - |z|^(n-2) (beta (|du_x z_x| + |du_y z_y|) + gamma z . du) z =: Phi(z, du)

which is the 1-D law when one component is zero and Park-Wen-Ang's equation for n = 2.
Both are rate independent, so ``z`` is integrated in ``u``: ``dt`` plays no part, and the path
between the committed and the trial displacement is the straight segment.

Admissible parameters. ``beta + gamma > 0`` bounds ``z`` by ``z_max = (A/(beta+gamma))^(1/n)``:
on ``|z| = z_max``, ``uy z . dz = A beta (z . du - sum_i |du_i z_i|) / (beta+gamma) <= 0``.
``beta >= |gamma|`` makes the dissipation non-negative at every instant. With the stored energy
``psi = (1-alpha) k uy^2 |z|^2 / (2 A)`` of the hysteretic spring (initial stiffness
``(1-alpha) k A``) the dissipation is ``(1-alpha) k uy |z|^n (beta sum_i |du_i z_i| +
gamma z . du) / A``, non-negative for every ``du`` exactly when ``beta >= |gamma|`` (the
thermodynamic-admissibility condition, cf. Erlicher & Point 2004). Together: ``beta > 0`` and
``-beta < gamma <= beta``. ``n >= 1`` keeps ``Phi`` Lipschitz at ``z = 0``.

Integration. The increment ``du = u - u_committed`` is cut into substeps of length at most
``h`` (see :attr:`BoucWen.substep`) along the segment, and each substep ``delta`` is a
backward-Euler step ``z1 = z0 + Phi(z1, delta) / uy`` solved by Newton for all connectors at once.
Backward Euler keeps ``|z| <= z_max`` for any step (``z . Phi(z) <= 0`` wherever ``|z| >= z_max``,
so a root outside the ball would satisfy ``|z1|^2 <= z1 . z0``, impossible) and, with
``beta >= |gamma|``, dissipates at every step. The returned tangent is the exact derivative of
this discrete map, chain-ruled through the substeps, so the kernel's Newton converges
quadratically.
"""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

import bearingfw


@attrs.frozen
class BoucWen:
    """Smooth hysteresis: stiffness ``k`` at first, ``alpha k`` after yield at about ``uy``.

    State: ``{"z": (n, dims), "u": (n, dims)}``, the hysteretic variable and the displacement
    at the last committed step (``z`` is driven by the increment from it). The normal force is
    accepted and ignored: this form does not scale with N (a sliding bearing modelled with it
    has a yield force fixed by ``k uy``).
    """

    name: ClassVar[str] = "bouc-wen"
    rigid: ClassVar[bool] = False
    symmetric: ClassVar[bool] = True
    #: Substep length times the largest rate |d(dz/du)/dz| over the admissible ball.
    SUBSTEP_RATIO: ClassVar[float] = 0.03
    #: Substeps per call at most: a longer increment is cut into this many equal substeps.
    MAX_SUBSTEPS: ClassVar[int] = 1000
    MAX_NEWTON_ITERATIONS: ClassVar[int] = 30

    k: float = bearingfw.parameter(
        low=0.0, low_open=True, unit="N/m", doc="elastic stiffness (the initial stiffness when A = 1)", typical=4e8
    )
    alpha: float = bearingfw.parameter(low=0.0, high=1.0, high_open=True, doc="post-yield to elastic stiffness ratio")
    uy: float = bearingfw.parameter(low=0.0, low_open=True, unit="m", doc="yield displacement", typical=1e-3)
    A: float = bearingfw.parameter(low=0.0, low_open=True, default=1.0, doc="hysteretic stiffness factor", typical=1.0)
    beta: float = bearingfw.parameter(
        low=0.0, low_open=True, default=0.5, doc="loop shape; beta >= |gamma| and beta + gamma > 0", typical=0.5
    )
    gamma: float = bearingfw.parameter(default=0.5, doc="loop shape; -beta < gamma <= beta", typical=0.5)
    n: float = bearingfw.parameter(low=1.0, default=1.0, doc="smoothness exponent (larger: sharper yield)", typical=1.0)
    dims: int = bearingfw.dims_parameter()

    def __attrs_post_init__(self):
        # The single-parameter ranges are checked by the fields; these two involve both shape parameters.
        conditions = [
            ("beta + gamma > 0 (else z and the force grow without bound)", self.beta + self.gamma > 0),
            ("beta >= |gamma| (else the law creates energy on some unloading paths)", self.beta >= abs(self.gamma)),
        ]
        violated = [condition for condition, holds in conditions if not holds]
        if violated:
            raise bearingfw.ParameterError(
                f"{self.name}: parameters 'beta' = {self.beta!r} and 'gamma' = {self.gamma!r} must satisfy "
                f"{' and '.join(violated)}; allowed: -beta < gamma <= beta"
            )

    @property
    def z_max(self) -> float:
        """The bound of ``|z|``, ``(A/(beta+gamma))^(1/n)``.

        The hysteretic force ``F - alpha k u`` never exceeds ``(1-alpha) k uy z_max`` and tends to it
        on a long monotonic path.
        """
        return (self.A / (self.beta + self.gamma)) ** (1.0 / self.n)

    @property
    def substep(self) -> float:
        """The longest substep (m): ``SUBSTEP_RATIO / lambda``.

        ``lambda = n (beta + |gamma|) z_max^(n-1) / uy`` is the largest ``|d(dz/du)/dz|`` of the 1-D law
        over ``|z| <= z_max``, the inverse of the shortest displacement over which ``z`` changes (the
        approach to saturation). A substep of ``0.03 / lambda`` (``0.03 uy`` for the defaults) keeps
        the backward-Euler lag in the knee to about 0.6 % of ``z_max`` (validation/laws.py: within
        1 % of an accurate solution on random paths, as the validation asks), and the Newton matrix within 0.1 of
        the identity (2-D included), so its root in the ball is unique and found in a few iterations.
        """
        rate = self.n * (self.beta + abs(self.gamma)) * self.z_max ** (self.n - 1.0) / self.uy
        return self.SUBSTEP_RATIO / rate

    def initial_state(self, n: int) -> dict:
        return {"z": np.zeros((n, self.dims)), "u": np.zeros((n, self.dims))}

    def slip(self, state) -> np.ndarray:
        """The plastic part of the displacement: ``u`` less the hysteretic spring's elastic part.

        The hysteretic spring has initial stiffness ``(1 - alpha) k A`` and force
        ``(1 - alpha) k uy z``, so its elastic deformation is ``uy z / A``.
        """
        return state["u"] - self.uy * state["z"] / self.A

    def respond(self, state, u, normal_force, dt) -> bearingfw.LawResponse:
        u = np.array(u, dtype=float)  # a copy: the state must not alias the caller's array
        du = u - state["u"]
        z = state["z"]
        # The signs of every substep's delta: those of du (so that the tangent is the derivative
        # in the direction of motion even where a substep is empty, at the jumps of their count).
        # Where du_i = 0 the law has a kink; take the unloading side (z_i moving towards 0): the
        # stiffer one, like an elastic predictor, and the one the friction law takes there too.
        direction = np.where(du != 0, np.sign(du), -np.sign(z))
        # dz/du so far, chain-ruled through the substeps; the committed z does not depend on u.
        dz_du = np.zeros(z.shape + (self.dims,))
        for delta, d_delta in self._substeps(du):
            z, newton_matrix = self._backward_euler(z, delta)
            # Differentiate z1 - z0 - Phi(z1, delta)/uy = 0:  (I - dPhi/dz) dz1 = dz0 + dPhi/ddelta ddelta.
            dz_du = _solve(newton_matrix, dz_du + self._flow_delta_derivative(z, direction) @ d_delta)
        hysteretic = (1.0 - self.alpha) * self.k * self.uy
        force = self.alpha * self.k * u + hysteretic * z
        tangent = self.alpha * self.k * np.eye(self.dims) + hysteretic * dz_du
        # An increment with nothing to do hands z0 back: never share an array with the old state.
        z = z.copy() if z is state["z"] else z
        return bearingfw.LawResponse(force, tangent, {"z": z, "u": u})

    def _substeps(self, du):
        """Yield ``(delta, d delta / d du)`` per substep, ``(n, dims)`` and ``(n, dims, dims)``.

        Full substeps of length ``s = max(h, |du| / MAX_SUBSTEPS)`` along ``e = du/|du|``, then the
        remainder. A remainder (rather than equal substeps) keeps the result continuous in ``du``:
        where the count of full substeps jumps, the remainder is zero on one side and a full
        substep on the other. The tangent has a kink there (a step's derivative in its own
        length is smaller at ``h`` than at 0, by up to ``1/(1 + lambda h)``, about 9 %), as at a
        reversal; exactly at the jump it is the derivative on the side of longer increments.
        Connectors that need fewer substeps get empty ones, which leave ``z`` unchanged.
        """
        eye = np.eye(self.dims)
        h = self.substep
        length = _norm(du)[:, 0]
        if length.max(initial=0.0) < h:  # the common case of a short increment: one step
            yield du, np.broadcast_to(eye, du.shape + (self.dims,))
            return
        safe_length = np.where(length > 0, length, 1.0)
        e = du / safe_length[:, None]
        s = np.maximum(h, length / self.MAX_SUBSTEPS)
        full = np.floor(length / s)
        # d(s e)/d du = s'(L) e e^T + s (I - e e^T)/L, with s' = 0 or 1/MAX_SUBSTEPS.
        eet = e[:, :, None] * e[:, None, :]
        slope = np.where(h >= length / self.MAX_SUBSTEPS, 0.0, 1.0 / self.MAX_SUBSTEPS)
        # s/L only matters where there are full substeps (L >= s): elsewhere keep it finite.
        d_full = slope[:, None, None] * eet + (s / np.maximum(length, s))[:, None, None] * (eye - eet)
        full_step = s[:, None] * e
        remainder = du - full[:, None] * full_step
        d_remainder = eye - full[:, None, None] * d_full
        for j in range(int(full.max()) + 1):
            is_full, is_last = (j < full)[:, None], (j == full)[:, None]
            delta = is_full * full_step + is_last * remainder
            yield delta, is_full[:, :, None] * d_full + is_last[:, :, None] * d_remainder

    def _backward_euler(self, z0, delta):
        """Solve ``R(z) = z - z0 - Phi(z, delta)/uy = 0`` by Newton; return ``z`` and ``dR/dz`` there.

        Iterates are kept in the ball ``|z| <= z_max``: the root lies in it, so pulling an iterate
        back radially only brings it closer (and keeps ``|z|^n`` finite for large n). Converged
        when the residual is at round-off level, so the returned matrix is the exact ``dR/dz`` at
        the returned ``z``.
        """
        z_max = self.z_max
        eye = np.eye(self.dims)
        # Round-off of R is about eps (|z| + |A delta / uy|): stop well above it, per connector.
        tolerance = 1e-13 * (z_max + self.A * np.abs(delta) / self.uy)
        z = z0
        for _ in range(self.MAX_NEWTON_ITERATIONS):
            flow, flow_z = self._flow(z, delta)
            residual = z - z0 - flow
            newton_matrix = eye - flow_z
            if np.all(np.abs(residual) <= tolerance):
                return z, newton_matrix
            z = z - _solve(newton_matrix, residual[:, :, None])[:, :, 0]
            if self.dims == 1:
                z = np.clip(z, -z_max, z_max)
            else:
                norm = _norm(z)
                z = np.where(norm > z_max, z * (z_max / np.maximum(norm, z_max)), z)
        raise FloatingPointError(
            f"{self.name}: the backward-Euler Newton iteration did not converge "
            f"in {self.MAX_NEWTON_ITERATIONS} iterations"
        )

    def _flow(self, z, delta):
        """``Phi(z, delta)/uy`` and its derivative in ``z``, all connectors at once.

        With ``q = beta sum_i |delta_i z_i| + gamma z . delta`` and ``r = |z|``,
        ``Phi = A delta - r^(n-2) q z``. Since ``q`` is linear in ``z``, ``r^(n-2) q = r^(n-1) q_hat``
        with ``q_hat = q / r`` evaluated at the unit vector ``z_hat``: finite at ``z = 0`` for
        ``n >= 1`` (``z_hat`` is taken as 0 there). The derivative::

            d(r^(n-2) q z)/dz = r^(n-1) q_hat I + r^(n-1) z_hat ((n-2) q_hat z_hat + dq/dz)^T

        with ``dq/dz = beta |delta| sgn(z) + gamma delta`` (``sgn(0) = 0``: the mean of the one-sided
        derivatives). In 1-D, ``q_hat = beta |delta| + gamma delta sgn(z)`` and the derivative is
        ``n |z|^(n-1) q_hat``, evaluated in that closed form: guided bearings are the common case.
        """
        if self.dims == 1:
            c = np.abs(z) ** (self.n - 1.0) * (self.beta * np.abs(delta) + self.gamma * delta * np.sign(z))
            return (self.A * delta - c * z) / self.uy, (c * (self.n / -self.uy))[:, :, None]
        r = _norm(z)
        z_hat = z / np.where(r > 0, r, 1.0)  # 0 at z = 0
        r_n1 = r ** (self.n - 1.0)
        abs_delta = np.abs(delta)
        q_hat = (self.beta * abs_delta * np.abs(z_hat) + self.gamma * z_hat * delta).sum(axis=1)[:, None]
        c = r_n1 * q_hat
        flow = (self.A * delta - c * z) / self.uy
        dq_dz = self.beta * abs_delta * np.sign(z) + self.gamma * delta
        dw_dz = c[:, :, None] * np.eye(self.dims)
        dw_dz += (r_n1 * z_hat)[:, :, None] * ((self.n - 2.0) * q_hat * z_hat + dq_dz)[:, None, :]
        return flow, dw_dz / -self.uy

    def _flow_delta_derivative(self, z, direction):
        """``d(Phi/uy)/d delta = (A I - r^(n-1) z_hat (beta |z| sgn(delta) + gamma z)^T) / uy``.

        ``sgn(delta)`` is taken as ``direction``, the signs of the whole increment (see respond).
        In 1-D: ``(A - |z|^(n-1) (beta z sgn(delta) + gamma |z|)) / uy``.
        """
        if self.dims == 1:
            abs_z = np.abs(z)
            slope = self.A - abs_z ** (self.n - 1.0) * (self.beta * z * direction + self.gamma * abs_z)
            return (slope / self.uy)[:, :, None]
        r = _norm(z)
        z_hat = z / np.where(r > 0, r, 1.0)
        dq_ddelta = self.beta * np.abs(z) * direction + self.gamma * z
        dw_ddelta = (r ** (self.n - 1.0) * z_hat)[:, :, None] * dq_ddelta[:, None, :]
        return (self.A * np.eye(self.dims) - dw_ddelta) / self.uy


def _norm(v):
    """Row norms of ``v`` (n, dims) as (n, 1); hypot does not underflow for tiny components."""
    return np.abs(v) if v.shape[1] == 1 else np.hypot(v[:, :1], v[:, 1:])


def _solve(matrix, rhs):
    """Solve ``matrix x = rhs`` for stacks of 1x1 or 2x2 matrices, ``rhs`` (n, dims, k).

    Closed form (the adjugate over the determinant): several times faster than LAPACK on so
    small systems, and these solves are the inner loop. The matrices are near the identity
    (see :attr:`BoucWen.substep`), so the closed form is well conditioned.
    """
    if matrix.shape[-1] == 1:
        return rhs / matrix
    # adj [[a, b], [c, d]] = [[d, -b], [-c, a]]: the reversed matrix, transposed, signs flipped.
    adjugate = matrix[:, ::-1, ::-1].transpose(0, 2, 1) * _ADJUGATE_SIGNS
    det = matrix[:, 0, 0] * matrix[:, 1, 1] - matrix[:, 0, 1] * matrix[:, 1, 0]
    return (adjugate @ rhs) / det[:, None, None]


_ADJUGATE_SIGNS = np.array([[1.0, -1.0], [-1.0, 1.0]])
