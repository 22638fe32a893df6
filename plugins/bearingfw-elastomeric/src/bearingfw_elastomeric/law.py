"""The lead-rubber (elastomeric) bearing as a bilinear elastic-plastic spring, 1-D and 2-D.

Model (SI units: N, m). A lead-rubber bearing is a rubber spring in parallel with a lead core
that yields. Written as two springs in parallel::

    F = alpha k u + q,        q = (1 - alpha) k (u - u_p),        |q| <= qd

``k`` is the initial stiffness ``K_u``, ``alpha k`` the post-yield stiffness ``K_d``, ``qd`` the
characteristic strength ``Q_d`` (the post-yield branch's force at zero displacement) and ``u_p``
the plastic displacement of the yielding component. ``|.|`` is the Euclidean norm, so in 2-D
the yield surface is a circle in the plane of the two shear directions: the law is isotropic
and couples the directions (a bearing yields once under the resultant, not per axis). The flow
is associated: ``u_p`` grows along ``q``.

The same law, written as plasticity with linear kinematic hardening: with ``u_p' = (1 - alpha) u_p``
(the displacement left at zero force, :meth:`ElastomericPlasticity.slip`), the hardening modulus
``H = alpha k / (1 - alpha)`` and the yield force ``F_y = qd / (1 - alpha)``::

    F = k (u - u_p'),   |F - H u_p'| <= F_y,   du_p' parallel to F - H u_p'

(``F - H u_p' = q / (1 - alpha)``, so the two descriptions have the same surface, flow and
force). The back force ``H u_p'`` moves the circle with the plastic displacement; the post-yield
stiffness is ``k H / (k + H) = alpha k``.

Integration: backward Euler, which is a closed-form radial return because the surface is a
circle. From the committed ``u_p``, the trial force ``q* = (1 - alpha) k (u - u_p)``; if
``|q*| <= qd`` the step is elastic, else ``q = qd q* / |q*|`` and
``u_p <- u_p + (1 - qd / |q*|) (u - u_p)``. This is the exact solution of the rate equations
along the straight increment in 1-D, and in 2-D when the increment is parallel to the force
(proportional loading); when the increment turns the force, backward Euler is the standard
first-order-accurate choice (and the one OpenSees's ``elastomericBearingPlasticity`` makes).

Consistent tangent, the derivative of that map: ``k I`` in the elastic case (also on the surface,
``|q*| = qd``: the unloading side, the stiffer one) and, in yield,
``alpha k I + (1 - alpha) k (qd / |q*|) (I - n n^T)`` with ``n = q* / |q*|`` (``alpha k`` in 1-D).
"""

from __future__ import annotations

import numbers
from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.laws import respond_inputs
from bearingfw.parameters import check_per_bearing


@attrs.frozen
class ElastomericPlasticity:
    """A lead-rubber bearing: stiffness ``k`` up to yield, ``alpha k`` after, characteristic strength ``qd``.

    Every numeric parameter may be one value per connector (``per_bearing``). State:
    ``{"plastic": (n, dims)}``, the plastic displacement ``u_p`` of the yielding component (m).
    The normal force, the time step and the velocity are accepted and play no part: the force does
    not depend on them (no friction: a bearing in tension or lift-off still resists shear).
    """

    name: ClassVar[str] = "elastomeric-plasticity"
    rigid: ClassVar[bool] = False
    symmetric: ClassVar[bool] = True
    per_bearing: ClassVar[bool] = True

    k: float = bearingfw.parameter(
        low=0.0, low_open=True, per_bearing=True, unit="N/m",
        doc="initial (elastic) shear stiffness K_u", typical=1.5e7,
    )  # fmt: skip
    qd: float = bearingfw.parameter(
        low=0.0, low_open=True, per_bearing=True, unit="N",
        doc="characteristic strength Q_d (yield force of the lead core; F_y = qd / (1 - alpha))", typical=1.5e5,
    )  # fmt: skip
    alpha: float = bearingfw.parameter(
        low=0.0, high=1.0, high_open=True, per_bearing=True,
        doc="post-yield to initial stiffness ratio K_d / K_u", typical=0.1,
    )  # fmt: skip
    dims: int = bearingfw.dims_parameter()

    # --- derived quantities (floats, or arrays for per-bearing parameters) -------------------

    @property
    def post_yield_stiffness(self):
        """``K_d = alpha k`` (N/m)."""
        return np.multiply(self.alpha, self.k)

    @property
    def yield_force(self):
        """``F_y = qd / (1 - alpha)`` (N): the force at first yield from rest."""
        return np.divide(self.qd, np.subtract(1.0, self.alpha))

    @property
    def yield_displacement(self):
        """``u_y = qd / ((1 - alpha) k)`` (m): the displacement at first yield from rest."""
        return np.divide(self.yield_force, self.k)

    # --- the protocol ----------------------------------------------------------------------

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"plastic": np.zeros((n, self.dims))}

    def compiled(self, n: int) -> bearingfw.CompiledLaw:
        """This law as a compiled function (``_kernel.elastomeric_plasticity``): ``k``, ``qd``, ``alpha``
        per connector; the state the plastic displacement."""
        from bearingfw_elastomeric._kernel import elastomeric_plasticity

        check_per_bearing(self, n)
        dims = self.dims
        parameters = np.concatenate([np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in (self.k, self.qd, self.alpha)])
        return bearingfw.CompiledLaw(
            elastomeric_plasticity, parameters, dims,
            pack=lambda state: np.ascontiguousarray(state["plastic"], dtype=float).reshape(-1),
            unpack=lambda array: {"plastic": array.reshape(n, dims)},
        )  # fmt: skip

    def slip(self, state) -> np.ndarray:
        """The irreversible displacement ``(1 - alpha) u_p``: where the bearing comes to rest at zero
        force when unloaded (the kinematic-hardening plastic displacement, module docstring)."""
        return (1.0 - np.asarray(self.alpha, dtype=float)[..., None]) * state["plastic"]

    def respond(self, state, u, normal_force, dt, velocity=None) -> bearingfw.LawResponse:
        # The shapes checked, naming the law (numpy would broadcast a wrong one); then a copy: no aliasing
        # between the caller's array and the state.
        u = np.array(respond_inputs(self, u, normal_force)[0])
        n = u.shape[0]
        check_per_bearing(self, n)
        # (1,) for a scalar parameter, (n, 1) for per-bearing values: both broadcast over (n, dims).
        k = np.asarray(self.k, dtype=float)[..., None]
        alpha = np.asarray(self.alpha, dtype=float)[..., None]
        qd = np.broadcast_to(np.asarray(self.qd, dtype=float), (n,))
        hysteretic_stiffness = (1.0 - alpha) * k
        plastic = state["plastic"]
        elastic_part = u - plastic
        trial = hysteretic_stiffness * elastic_part
        size = np.abs(trial[:, 0]) if self.dims == 1 else np.hypot(trial[:, 0], trial[:, 1])
        # On the surface (size == qd) the step counts as elastic: the unloading side's tangent.
        yielding = size > qd
        scale = np.where(yielding, qd / np.where(yielding, size, 1.0), 1.0)
        force = alpha * k * u + trial * scale[:, None]
        # u_p + (1 - qd/|q*|)(u - u_p): the return without dividing by (1 - alpha) k.
        new_plastic = plastic + (1.0 - scale)[:, None] * elastic_part
        direction = trial / np.where(yielding, size, 1.0)[:, None]
        identity = np.eye(self.dims)
        projector = identity - yielding[:, None, None] * np.einsum("ij,ik->ijk", direction, direction)
        tangent = (alpha * k)[..., None] * identity + (hysteretic_stiffness * scale[:, None])[..., None] * projector
        return bearingfw.LawResponse(force, tangent, {"plastic": new_plastic})


def lead_rubber_parameters(
    weight: float, *, period: float = 2.5, strength_ratio: float = 0.05, stiffness_ratio: float = 10.0, g: float = 9.81
) -> dict[str, float]:
    """Parameters of a lead-rubber bearing designed for the weight (N) it carries.

    The usual preliminary design of a bridge isolator (e.g. Buckle et al. 2006, MCEER-06-SP07;
    the AASHTO Guide Specifications for Seismic Isolation Design): the characteristic strength a
    fraction of the weight, ``qd = strength_ratio W``; the post-yield stiffness from the isolated
    period of the mass it carries, ``K_d = W (2 pi / period)^2 / g``; the initial stiffness
    ``k = stiffness_ratio K_d`` (``K_u ~ 10 K_d`` for lead-rubber bearings), so
    ``alpha = 1 / stiffness_ratio``. Returns ``{"k", "qd", "alpha"}`` for
    :class:`ElastomericPlasticity`.
    """
    allowed = {
        "weight": (weight, lambda v: v > 0, "weight > 0 N"),
        "period": (period, lambda v: v > 0, "period > 0 s"),
        "strength_ratio": (strength_ratio, lambda v: 0 < v < 1, "0 < strength_ratio < 1"),
        "stiffness_ratio": (stiffness_ratio, lambda v: v > 1, "stiffness_ratio > 1"),
        "g": (g, lambda v: v > 0, "g > 0 m/s^2"),
    }
    for name, (value, within, text) in allowed.items():
        real = isinstance(value, numbers.Real) and not isinstance(value, bool)
        if not (real and np.isfinite(value) and within(value)):
            raise bearingfw.ParameterError(
                f"lead_rubber_parameters: {name!r} = {value!r} is outside the allowed range {text}"
            )
    post_yield = weight * (2.0 * np.pi / period) ** 2 / g
    return {
        "k": float(stiffness_ratio * post_yield),
        "qd": float(strength_ratio * weight),
        "alpha": float(1.0 / stiffness_ratio),
    }
