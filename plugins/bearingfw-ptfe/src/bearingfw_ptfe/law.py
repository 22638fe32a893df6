"""PTFE sliding friction whose coefficient depends on the sliding velocity and the bearing pressure.

The friction coefficient (Constantinou, Mokha & Reinhorn 1990; the form of OpenSees's
``VelDependent`` and ``VelPressureDep`` friction models)::

    mu(v, N) = f_max(N) - (f_max(N) - f_min) exp(-a |v|)
    f_max(N) = f_max - delta_mu tanh(alpha N / area)          (pressure p = N / area)

``|v|`` is the speed of sliding (the norm of the 2-D relative velocity). It rises from ``f_min`` at
rest to ``f_max(N)`` at high speed, ``a`` setting how fast; ``f_max(N)`` falls from ``f_max`` at
zero pressure towards ``f_max - delta_mu`` at high pressure. Without ``area`` (or with
``delta_mu = 0`` or ``alpha = 0``) the coefficient does not depend on the pressure. The code
evaluates it as ``f_min + (f_max(N) - f_min) (1 - exp(-a |v|))`` with ``expm1``, so that ``a = 0``
or ``|v| = 0`` gives exactly ``f_min``.

Plasticity: regularized (elastic-stick) Coulomb friction on the circle ``|F| <= mu N``, as
``regularized-coulomb``: ``u = u_e + u_p``, ``F = k (u - u_p)`` in stick, and a backward-Euler
radial return onto ``|F| = mu(v, N) N`` in slip, with ``mu`` evaluated at the trial point
(the trial velocity given by the kernel and the trial normal force), exactly as OpenSees's
``flatSliderBearing`` does. ``N <= 0`` (tension, uplift) leaves no contact: zero force and
tangent, and the slip follows ``u`` (so contact is re-made at zero force, as in OpenSees).

Derivatives at the trial point (what the kernel puts into Newton):

- ``tangent`` (d F / d u at fixed v and N): ``k`` in stick; ``k (mu N / |F_trial|) (I - n n^T)``
  in slip (``n`` the slip direction; zero in 1-D);
- ``dforce_dvelocity``: zero in stick; ``n (d(mu N)/d v)^T`` in slip, with
  ``d mu / d v = a (f_max(N) - f_min) exp(-a |v|) v / |v|`` (taken as zero at ``v = 0``, the kink
  of ``|v|``, as OpenSees does);
- ``dforce_dnormal``: zero in stick; ``(mu + N d mu / d N) n`` in slip, with
  ``d mu / d N = -(delta_mu alpha / area) (1 - tanh^2(alpha N / area)) (1 - exp(-a |v|))``.

Rate-independent limit: with ``a = 0`` the coefficient is ``f_min`` at every velocity and
pressure, and the law is ``regularized-coulomb`` with ``k`` and ``mu = f_min``, bit for bit
(``rate_independent_limit``). Equally, ``f_min = f_max`` (which forces ``delta_mu = 0``) is
``regularized-coulomb`` with ``mu = f_max`` at every velocity.
"""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.laws import friction_return_map, respond_inputs, velocity_input
from bearingfw.parameters import check_per_bearing


#: The smallest friction coefficient accepted (f_min and f_max).
MIN_COEFFICIENT = 0.001


def _values(value) -> np.ndarray:
    """A per-bearing parameter as a float array: shape () for a scalar, (n,) for an array."""
    return np.asarray(value, dtype=float)


@attrs.frozen
class PTFEFriction:
    """Stick stiffness ``k`` up to the friction force ``mu(v, N) N``, then sliding.

    State: ``{"slip": (n, dims)}``, the accumulated slip ``u_p`` in metres. The velocity and the
    normal force are read on every call (``velocity=None``, an older caller, means at rest).
    """

    name: ClassVar[str] = "ptfe-friction"
    rigid: ClassVar[bool] = False
    symmetric: ClassVar[bool] = True
    uses_velocity: ClassVar[bool] = True
    rate_dependent: ClassVar[bool] = True
    normal_coupling: ClassVar[bool] = True
    friction: ClassVar[bool] = True
    per_bearing: ClassVar[bool] = True

    k: float = bearingfw.parameter(
        low=0.0, low_open=True, unit="N/m", doc="stick stiffness (OpenSees kInit)", typical=4e8, per_bearing=True
    )
    # 0.001 is below any measured PTFE coefficient; OpenSees requires muSlow, muFast > 0. (A smaller
    # positive f_min would only make the stick range at rest vanishingly narrow.)
    f_min: float = bearingfw.parameter(
        low=MIN_COEFFICIENT, high=1.0, high_open=True, doc="friction coefficient at rest (OpenSees muSlow)",
        typical=0.02, per_bearing=True,
    )
    f_max: float = bearingfw.parameter(
        low=MIN_COEFFICIENT, high=1.0, high_open=True,
        doc="friction coefficient at high sliding speed, at zero pressure (OpenSees muFast / muFast0)",
        typical=0.04, per_bearing=True,
    )
    a: float = bearingfw.parameter(
        low=0.0, unit="s/m", doc="rate of the transition from f_min to f_max with the speed (OpenSees transRate)",
        typical=25.0, per_bearing=True,
    )
    area: float | None = bearingfw.parameter(
        low=0.0, low_open=True, optional=True, unit="m^2",
        doc="nominal contact area A, pressure p = N / A (OpenSees A); None: no pressure dependence",
        typical=0.1, per_bearing=True,
    )
    delta_mu: float = bearingfw.parameter(
        low=0.0, high=1.0, high_open=True, default=0.0,
        doc="fall of f_max from zero to very high pressure (OpenSees deltaMu)", typical=0.01, per_bearing=True,
    )
    alpha: float = bearingfw.parameter(
        low=0.0, default=0.0, unit="1/Pa",
        doc="pressure scale of the fall, f_max - delta_mu tanh(alpha p) (OpenSees alpha)", typical=3e-8,
        per_bearing=True,
    )
    dims: int = bearingfw.dims_parameter()

    def __attrs_post_init__(self):
        f_min, f_max, delta_mu = _values(self.f_min), _values(self.f_max), _values(self.delta_mu)
        if np.any(f_min > f_max):
            raise bearingfw.ParameterError(
                f"{self.name}: parameters 'f_min' = {self.f_min!r} and 'f_max' = {self.f_max!r} must satisfy "
                f"f_min <= f_max (the coefficient rises from f_min at rest to f_max at speed)"
            )
        if np.any(delta_mu > f_max - f_min):
            raise bearingfw.ParameterError(
                f"{self.name}: parameters 'delta_mu' = {self.delta_mu!r}, 'f_max' = {self.f_max!r} and 'f_min' = "
                f"{self.f_min!r} must satisfy delta_mu <= f_max - f_min (so that f_max(p) >= f_min at every pressure)"
            )
        if self.area is None and np.any((delta_mu > 0) & (_values(self.alpha) > 0)):
            raise bearingfw.ParameterError(
                f"{self.name}: parameters 'delta_mu' and 'alpha' make f_max depend on the pressure N / area: "
                f"give 'area' (m^2, > 0), or set delta_mu = 0"
            )

    # --- the coefficient ---------------------------------------------------------------------

    def _fast_coefficient(self, contact_force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``f_max(N)`` and ``d f_max / d N`` for compressive ``N >= 0``, each (n,) (or broadcastable)."""
        f_max = _values(self.f_max)
        if self.area is None:
            return f_max, np.zeros(())
        scale = _values(self.alpha) / _values(self.area)
        delta_mu = _values(self.delta_mu)
        saturation = np.tanh(scale * contact_force)
        return f_max - delta_mu * saturation, -delta_mu * scale * (1.0 - saturation * saturation)

    def coefficient(self, speed, normal_force) -> np.ndarray:
        """The friction coefficient ``mu(|v|, N)`` at sliding speeds ``speed`` (m/s) and normal forces (N)."""
        contact_force = np.maximum(np.asarray(normal_force, dtype=float), 0.0)
        fast, _ = self._fast_coefficient(contact_force)
        growth = -np.expm1(-_values(self.a) * np.abs(np.asarray(speed, dtype=float)))
        f_min = _values(self.f_min)
        return f_min + (fast - f_min) * growth

    # --- the protocol ------------------------------------------------------------------------

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"slip": np.zeros((n, self.dims))}

    def force_bound(self, normal_force) -> np.ndarray:
        """``f_max(N) N``: the coefficient never exceeds its high-speed value."""
        contact_force = np.maximum(np.asarray(normal_force, dtype=float), 0.0)
        fast, _ = self._fast_coefficient(contact_force)
        return fast * contact_force

    def slip(self, state) -> np.ndarray:
        return state["slip"]

    def rate_independent_limit(self):
        """(this law with ``a = 0``, ``regularized-coulomb(k, mu=f_min)``): they respond identically."""
        frozen = attrs.evolve(self, a=0.0)
        return frozen, bearingfw.create_law("regularized-coulomb", k=self.k, mu=self.f_min, dims=self.dims)

    def respond(self, state, u, normal_force, dt, velocity=None) -> bearingfw.LawResponse:
        # Shapes, and a finite normal force, checked naming the law (numpy would broadcast a wrong shape
        # into a plausible answer, and a NaN normal force compares as stick).
        u, normal = respond_inputs(self, u, normal_force)
        n = u.shape[0]
        check_per_bearing(self, n)
        k = _values(self.k)[..., None]  # () -> (1,), (n,) -> (n, 1): broadcasts over (n, dims)
        contact_force = np.maximum(normal, 0.0)

        if velocity is None:
            speed = np.zeros(n)
            velocity = np.zeros_like(u)
        else:
            velocity = velocity_input(self, velocity, u)
            speed = np.sqrt(np.einsum("ij,ij->i", velocity, velocity))
        a = _values(self.a)
        f_min = _values(self.f_min)
        fast, dfast_dnormal = self._fast_coefficient(contact_force)
        growth = -np.expm1(-a * speed)  # 1 - exp(-a|v|), exactly 0 at a = 0 or v = 0
        mu = f_min + (fast - f_min) * growth
        capacity = mu * contact_force

        # The return map of regularized-coulomb, with this call's capacity.
        force, new_slip, direction, sliding, tangent = friction_return_map(k, u, state["slip"], capacity)

        # In slip F = mu(v, N) N n with n fixed by the trial force: the derivatives of mu N.
        slipping = sliding & (normal > 0.0)
        decay = 1.0 - growth  # exp(-a|v|)
        safe_speed = np.where(speed > 0.0, speed, 1.0)
        dmu_dspeed = a * (fast - f_min) * decay
        dcapacity_dvelocity = (contact_force * dmu_dspeed / safe_speed * (speed > 0.0))[:, None] * velocity
        dforce_dvelocity = np.where(
            slipping[:, None, None], np.einsum("ij,ik->ijk", direction, dcapacity_dvelocity), 0.0
        )
        dcapacity_dnormal = mu + contact_force * dfast_dnormal * growth
        dforce_dnormal = np.where(slipping[:, None], dcapacity_dnormal[..., None] * direction, 0.0)
        return bearingfw.LawResponse(
            force, tangent, {"slip": new_slip}, dforce_dnormal=dforce_dnormal, dforce_dvelocity=dforce_dvelocity
        )
