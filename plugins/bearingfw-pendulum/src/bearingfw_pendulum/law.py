"""The single concave friction pendulum bearing (small-displacement form of OpenSees's singleFPBearing).

A slider on a spherical surface of effective radius ``R`` under the compressive normal force ``N``
resists a horizontal displacement ``u`` with the pendulum's restoring force ``N u / R`` plus the
friction force of the sliding surface, at most ``mu N``, in the direction of sliding. As in
OpenSees's ``SingleFPSimple2d/3d``, the force splits into a linear *restoring* part of stiffness
``k2 = N / R`` and a *hysteretic* (friction) part of initial stiffness ``k0 = k - N / R``, so that
``k`` (OpenSees's ``kInit``) is the stiffness of the whole bearing before it slides::

    q = k0 (u - u_p)                       while |k0 (u - u_p,n)| <= mu N    (stick)
    q = mu N t / |t|, t = k0 (u - u_p,n)     otherwise, u_p = u - q / k0      (slip: radial return)
    F = q + (N / R) u

``u_p`` is the slip, the slider's position on the surface. In stick ``F = k (u - u_p) + N u_p / R``
(tangent ``k``); in slip the tangent is ``k0 (mu N / |t|) (I - n n^T) + (N / R) I`` (``n = t / |t|``).
Both parts vary with ``N``, read at every call. ``N <= 0`` (uplift) leaves no contact: no force,
and the slip follows ``u`` (as in OpenSees).

``k0 > 0`` needs ``N < k R``: the stick stiffness must exceed the pendulum stiffness, as in any real
bearing (``k`` is typically 50 to 100 times ``N / R``); a call with ``N >= k R`` raises
:class:`bearingfw.ParameterError`.

Normal-force coupling, at fixed ``u``: ``dF/dN = u_p,n / R`` in stick (``F = k (u - u_p) + N u_p / R``)
and ``(mu + N dmu/dN) n + u / R`` in slip.

The coefficient: ``friction-pendulum`` has a constant ``mu``; ``friction-pendulum-vel`` the
velocity-dependent ``mu(v) = f_max - (f_max - f_min) exp(-a |v|)`` of Constantinou et al. (1990)
(OpenSees's ``VelDependent``), with ``dF/dv = n (N dmu/dv)^T`` in slip, and its
``rate_independent_limit()`` (``a = 0``) is ``friction-pendulum`` with ``mu = f_min``, bit for bit.

Small displacements: ``R`` is the same in every direction and ``N`` is the vertical force the
kernel gives (OpenSees's large-displacement element uses the radii ``sqrt(R^2 - u_other^2)`` per
axis, the force normal to the surface ``N + F . u / R`` and the speed along it, which differ by
terms of order ``u / R`` times ``mu`` and ``(u / R)^2``). The rise of the slider ``u^2 / (2 R)`` is not
modelled: the connector's vertical direction is its spring.
"""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.laws import friction_return_map, respond_inputs, velocity_input
from bearingfw.parameters import check_per_bearing

#: The smallest friction coefficient accepted: a smaller positive one leaves a stick range
#: ``mu N / k0`` too narrow for any time step or finite difference to resolve.
MIN_COEFFICIENT = 0.001


def _values(value) -> np.ndarray:
    """A per-bearing parameter as a float array: shape () for a scalar, (n,) for an array."""
    return np.asarray(value, dtype=float)


def _radius_parameter():
    return bearingfw.parameter(
        low=0.0, low_open=True, unit="m", doc="effective radius of the sliding surface (OpenSees Reff)", typical=2.0,
        per_bearing=True,
    )


def _stiffness_parameter():
    return bearingfw.parameter(
        low=0.0, low_open=True, unit="N/m", doc="stiffness of the bearing before sliding, with N/R (OpenSees kInit)",
        typical=4e8, per_bearing=True,
    )


def pendulum_response(law, state, u, normal_force, mu, dmu_dvelocity=None) -> bearingfw.LawResponse:
    """The response of friction-pendulum law ``law`` (fields ``k``, ``R``, ``dims``) for the
    coefficients ``mu`` (n,) and, for a velocity-dependent coefficient, ``dmu_dvelocity`` (n, dims)."""
    u = np.asarray(u, dtype=float)
    n = u.shape[0]
    normal = np.asarray(normal_force, dtype=float)
    contact = normal > 0.0
    load = np.where(contact, normal, 0.0)
    k = np.broadcast_to(_values(law.k), (n,))
    gravity = load / _values(law.R)  # the pendulum stiffness N / R, (n,)
    if np.any(gravity >= k):
        i = int(np.flatnonzero(gravity >= k)[0])
        raise bearingfw.ParameterError(
            f"{law.name}: respond() argument 'normal_force': connector {i} carries N = {load[i]:.6g} N, so its pendulum "
            f"stiffness N/R = {gravity[i]:.6g} "
            f"N/m reaches the parameter 'k' = {k[i]:.6g} N/m; 'k' (the stiffness before sliding, with N/R) must "
            f"exceed N/R (typically 50 to 100 times it): raise 'k' or 'R'"
        )
    k0 = (k - gravity)[:, None]  # the friction part's stiffness
    capacity = mu * load

    slip = state["slip"]
    # the friction part: regularized-coulomb's return map with stiffness k - N/R; then the pendulum's N/R
    friction, new_slip, direction, sliding, friction_tangent = friction_return_map(k0, u, slip, capacity)
    force = friction + gravity[:, None] * u
    tangent = friction_tangent + gravity[:, None, None] * np.eye(law.dims)

    slipping = sliding & contact
    sticking = ~sliding & contact
    dforce_dnormal = np.where(
        slipping[:, None],
        mu[:, None] * direction + u / _values(law.R)[..., None],
        np.where(sticking[:, None], slip / _values(law.R)[..., None], 0.0),
    )
    dforce_dvelocity = None
    if dmu_dvelocity is not None:
        dforce_dvelocity = np.where(
            slipping[:, None, None], np.einsum("ij,ik->ijk", direction, load[:, None] * dmu_dvelocity), 0.0
        )
    return bearingfw.LawResponse(
        force, tangent, {"slip": new_slip}, dforce_dnormal=dforce_dnormal, dforce_dvelocity=dforce_dvelocity
    )


class _PendulumBase:
    """What both pendulum laws share: state, slip, protocol flags."""

    rigid: ClassVar[bool] = False
    symmetric: ClassVar[bool] = True
    normal_coupling: ClassVar[bool] = True
    friction: ClassVar[bool] = True
    per_bearing: ClassVar[bool] = True

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"slip": np.zeros((n, self.dims))}

    def slip(self, state) -> np.ndarray:
        return state["slip"]


@attrs.frozen
class FrictionPendulum(_PendulumBase):
    """Single friction pendulum with a constant friction coefficient ``mu`` (module docstring).

    State: ``{"slip": (n, dims)}``, the slider's position ``u_p`` (m).
    """

    name: ClassVar[str] = "friction-pendulum"

    k: float = _stiffness_parameter()
    R: float = _radius_parameter()
    mu: float = bearingfw.parameter(
        low=MIN_COEFFICIENT, high=1.0, high_open=True, doc="friction coefficient of the sliding surface", typical=0.05,
        per_bearing=True,
    )
    dims: int = bearingfw.dims_parameter()

    def respond(self, state, u, normal_force, dt) -> bearingfw.LawResponse:
        # Shapes and a finite normal force checked naming the law (a NaN N would compare as no contact).
        u, normal_force = respond_inputs(self, u, normal_force)
        check_per_bearing(self, u.shape[0])
        mu = np.broadcast_to(_values(self.mu), (u.shape[0],))
        return pendulum_response(self, state, u, normal_force, mu)

    def compiled(self, n: int) -> bearingfw.CompiledLaw:
        """This law as a compiled function (``_kernel.friction_pendulum``): ``k``, ``R``, ``mu`` per
        connector; the state the slip."""
        from bearingfw_pendulum._kernel import friction_pendulum

        check_per_bearing(self, n)
        dims = self.dims
        parameters = np.concatenate([np.broadcast_to(_values(v), (n,)) for v in (self.k, self.R, self.mu)])
        return bearingfw.CompiledLaw(
            friction_pendulum, parameters, dims,
            pack=lambda state: np.ascontiguousarray(state["slip"], dtype=float).reshape(-1),
            unpack=lambda array: {"slip": array.reshape(n, dims)},
        )  # fmt: skip


@attrs.frozen
class VelocityFrictionPendulum(_PendulumBase):
    """Single friction pendulum whose coefficient rises with the sliding speed (module docstring).

    State: ``{"slip": (n, dims)}``, the slider's position ``u_p`` (m). ``velocity=None`` (an older
    caller) means at rest.
    """

    name: ClassVar[str] = "friction-pendulum-vel"
    uses_velocity: ClassVar[bool] = True
    rate_dependent: ClassVar[bool] = True

    k: float = _stiffness_parameter()
    R: float = _radius_parameter()
    f_min: float = bearingfw.parameter(
        low=MIN_COEFFICIENT, high=1.0, high_open=True, doc="friction coefficient at rest (OpenSees muSlow)",
        typical=0.03, per_bearing=True,
    )
    f_max: float = bearingfw.parameter(
        low=MIN_COEFFICIENT, high=1.0, high_open=True, doc="friction coefficient at high speed (OpenSees muFast)",
        typical=0.06, per_bearing=True,
    )
    a: float = bearingfw.parameter(
        low=0.0, unit="s/m", doc="rate of the transition from f_min to f_max with the speed (OpenSees transRate)",
        typical=25.0, per_bearing=True,
    )
    dims: int = bearingfw.dims_parameter()

    def __attrs_post_init__(self):
        if np.any(_values(self.f_min) > _values(self.f_max)):
            raise bearingfw.ParameterError(
                f"{self.name}: parameters 'f_min' = {self.f_min!r} and 'f_max' = {self.f_max!r} must satisfy "
                f"f_min <= f_max (the coefficient rises from f_min at rest to f_max at speed)"
            )

    def coefficient(self, speed) -> np.ndarray:
        """``mu(|v|) = f_min + (f_max - f_min) (1 - exp(-a |v|))`` at sliding speeds ``speed`` (m/s)."""
        growth = -np.expm1(-_values(self.a) * np.abs(np.asarray(speed, dtype=float)))
        f_min = _values(self.f_min)
        return f_min + (_values(self.f_max) - f_min) * growth

    def rate_independent_limit(self):
        """(this law with ``a = 0``, ``friction-pendulum(k, R, mu=f_min)``): they respond identically."""
        return attrs.evolve(self, a=0.0), FrictionPendulum(k=self.k, R=self.R, mu=self.f_min, dims=self.dims)

    def respond(self, state, u, normal_force, dt, velocity=None) -> bearingfw.LawResponse:
        u, normal_force = respond_inputs(self, u, normal_force)
        n = u.shape[0]
        check_per_bearing(self, n)
        velocity = np.zeros((n, self.dims)) if velocity is None else velocity_input(self, velocity, u)
        speed = np.sqrt(np.einsum("ij,ij->i", velocity, velocity))
        a = _values(self.a)
        f_min, f_max = _values(self.f_min), _values(self.f_max)
        growth = -np.expm1(-a * speed)  # exactly 0 at a = 0 or v = 0
        mu = np.broadcast_to(f_min + (f_max - f_min) * growth, (n,))
        # d mu / d v = a (f_max - f_min) exp(-a |v|) v / |v|, taken as 0 at v = 0 (the kink of |v|)
        rate = np.broadcast_to(a * (f_max - f_min) * (1.0 - growth), (n,))
        dmu_dvelocity = np.where(speed[:, None] > 0.0, (rate / np.where(speed > 0.0, speed, 1.0))[:, None] * velocity,
                                 0.0)  # fmt: skip
        return pendulum_response(self, state, u, normal_force, mu, dmu_dvelocity)
