"""Correct reference laws and broken copies of them (mutants), each with one classic mistake.

``Coulomb`` is a self-contained copy of the built-in ``regularized-coulomb`` on protocol v2
(per-bearing ``k`` and ``mu``, ``friction``, ``normal_coupling``); ``Spring`` one of
``linear-spring``; ``VelocityFriction`` a PTFE-like friction law whose coefficient grows with the
sliding speed (``uses_velocity``, with its ``rate_independent_limit``); ``Damper`` a linear
viscous damper that computes its own velocity from ``dt`` (``rate_dependent``). Every mutant
breaks its reference in one way a third party might, and ``MUTANTS`` maps it to the properties
of the conformance kit expected to catch it. Some mutants compute their tangent by finite
differences of their own (broken) map, so that only the property aimed at can catch them.
"""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

from bearingfw.parameters import ParameterError, check_per_bearing, dims_parameter, parameter
from bearingfw.protocol import LawResponse


def _per_connector(value, n: int) -> np.ndarray:
    """A per-bearing parameter as (n, 1), to broadcast over (n, dims)."""
    return np.broadcast_to(np.asarray(value, dtype=float), (n,))[:, None]


def _numeric_tangent(force_of, u: np.ndarray) -> np.ndarray:
    """d force / d u by central differences of ``force_of(u) -> (n, dims)``, for the self-consistent mutants."""
    n, dims = u.shape
    h = 1e-7 * np.maximum(np.abs(u).max(axis=1), 1e-6)[:, None]
    tangent = np.empty((n, dims, dims))
    for j in range(dims):
        step = np.zeros_like(u)
        step[:, j] = h[:, 0]
        tangent[:, :, j] = (force_of(u + step) - force_of(u - step)) / (2 * h)
    return tangent


# --- regularized Coulomb friction --------------------------------------------------------------


@attrs.frozen
class Coulomb:
    """A correct copy of ``regularized-coulomb``: stick stiffness k up to mu N, radial return."""

    name: ClassVar[str] = "copy-of-regularized-coulomb"
    rigid: ClassVar[bool] = False
    per_bearing: ClassVar[bool] = True
    friction: ClassVar[bool] = True
    normal_coupling: ClassVar[bool] = True
    k: float = parameter(low=0.0, low_open=True, unit="N/m", typical=4e8, per_bearing=True)
    mu: float = parameter(low=0.0, high=1.0, high_open=True, typical=0.04, per_bearing=True)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"slip": np.zeros((n, self.dims))}

    def force_bound(self, normal_force) -> np.ndarray:
        return np.asarray(self.mu, dtype=float) * np.maximum(np.asarray(normal_force, dtype=float), 0.0)

    def slip(self, state) -> np.ndarray:
        return state["slip"]

    # The steps of respond, one method each, so that a mutant can break one of them.
    def _capacity(self, state, normal, n):
        return _per_connector(self.mu, n)[:, 0] * np.maximum(normal, 0.0)

    def _trial(self, state, u, k):
        return k * (u - state["slip"])

    def _return(self, trial, capacity):
        norm = np.sqrt(np.einsum("ij,ij->i", trial, trial))
        sliding = (norm > capacity) | (capacity <= 0.0)
        safe = np.where(sliding & (norm > 0.0), norm, 1.0)
        scale = np.where(sliding, capacity / safe, 1.0)
        return trial * scale[:, None], sliding, scale, trial / safe[:, None]

    def _new_state(self, state, u, force, k, sliding):
        return {"slip": np.where(sliding[:, None], u - force / k, state["slip"])}

    def _tangent(self, k, scale, sliding, direction):
        projector = np.eye(self.dims) - sliding[:, None, None] * np.einsum("ij,ik->ijk", direction, direction)
        return k[:, :, None] * scale[:, None, None] * projector

    def _dforce_dnormal(self, normal, sliding, direction, n):
        return np.where((sliding & (normal > 0.0))[:, None], _per_connector(self.mu, n) * direction, 0.0)

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        u = np.array(u, dtype=float)
        n = len(u)
        check_per_bearing(self, n)
        k = _per_connector(self.k, n)
        normal = np.asarray(normal_force, dtype=float)
        capacity = self._capacity(state, normal, n)
        force, sliding, scale, direction = self._return(self._trial(state, u, k), capacity)
        return LawResponse(
            force,
            self._tangent(k, scale, sliding, direction),
            self._new_state(state, u, force, k, sliding),
            dforce_dnormal=self._dforce_dnormal(normal, sliding, direction, n),
        )


class NonAssociatedSlip(Coulomb):
    """The slip grows along the displacement increment, not along the force (non-associated rule).

    The force stays on the circle ``|F| = mu N`` and the tangent is that of this map (by finite
    differences): only normality tells it from the real thing."""

    normal_coupling: ClassVar[bool] = False

    def initial_state(self, n):
        return {**super().initial_state(n), "u": np.zeros((n, self.dims))}

    def _map(self, state, u, normal):
        n = len(u)
        k = _per_connector(self.k, n)
        capacity = self._capacity(state, normal, n)
        trial = k * (u - state["slip"])
        du = u - state["u"]
        length = np.linalg.norm(du, axis=1, keepdims=True)
        e = np.where(length > 0, du / np.where(length > 0, length, 1.0), trial / np.maximum(np.linalg.norm(trial, axis=1, keepdims=True), 1e-300))
        # |trial - k lam e| = capacity: lam = (t.e - sqrt((t.e)^2 - |t|^2 + c^2)) / k, if the trial is outside.
        te = np.einsum("ij,ij->i", trial, e)
        tt = np.einsum("ij,ij->i", trial, trial)
        disc = te * te - tt + capacity * capacity
        outside = tt > capacity * capacity
        lam = np.where(outside & (disc >= 0), te - np.sqrt(np.maximum(disc, 0.0)), 0.0) / k[:, 0]
        force = trial - k * lam[:, None] * e
        # Where the line along e misses the circle, and without capacity, the radial return.
        radial, _, _, _ = self._return(trial, capacity)
        force = np.where((outside & ((disc < 0) | (capacity <= 0)))[:, None], radial, force)
        return force, {"slip": u - force / k, "u": u}

    def respond(self, state, u, normal_force, dt):
        u, normal = np.array(u, dtype=float), np.asarray(normal_force, dtype=float)
        force, new_state = self._map(state, u, normal)
        return LawResponse(force, _numeric_tangent(lambda x: self._map(state, x, normal)[0], u), new_state)


class ForceAlongDisplacement(Coulomb):
    """In slip the force points along the total displacement u instead of the trial force."""

    normal_coupling: ClassVar[bool] = False

    def respond(self, state, u, normal_force, dt):
        u, normal = np.array(u, dtype=float), np.asarray(normal_force, dtype=float)

        def force_of(x):
            n = len(x)
            k = _per_connector(self.k, n)
            capacity = self._capacity(state, normal, n)
            force, sliding, _, _ = self._return(self._trial(state, x, k), capacity)
            along_u = x / np.maximum(np.linalg.norm(x, axis=1, keepdims=True), 1e-300)
            return np.where(sliding[:, None], capacity[:, None] * along_u, force), sliding

        force, sliding = force_of(u)
        k = _per_connector(self.k, len(u))
        return LawResponse(force, _numeric_tangent(lambda x: force_of(x)[0], u),
                           {"slip": np.where(sliding[:, None], u - force / k, state["slip"])})  # fmt: skip


class FrictionInTension(Coulomb):
    """The capacity is mu |N|: a bearing in tension still has friction."""

    def _capacity(self, state, normal, n):
        return _per_connector(self.mu, n)[:, 0] * np.abs(normal)

    def _dforce_dnormal(self, normal, sliding, direction, n):
        return np.sign(normal)[:, None] * _per_connector(self.mu, n) * direction * sliding[:, None]


class UnclampedNormalForce(Coulomb):
    """The capacity is mu N without clamping N at zero (negative in tension), in respond and in force_bound."""

    def force_bound(self, normal_force):
        return np.asarray(self.mu, dtype=float) * np.asarray(normal_force, dtype=float)

    def _capacity(self, state, normal, n):
        return _per_connector(self.mu, n)[:, 0] * normal

    def _return(self, trial, capacity):
        norm = np.sqrt(np.einsum("ij,ij->i", trial, trial))
        sliding = norm > capacity
        safe = np.where(sliding & (norm > 0.0), norm, 1.0)
        scale = np.where(sliding, capacity / safe, 1.0)
        return trial * scale[:, None], sliding, scale, trial / safe[:, None]

    def _dforce_dnormal(self, normal, sliding, direction, n):
        return np.where(sliding[:, None], _per_connector(self.mu, n) * direction, 0.0)


class SlipUpdateWrongSign(Coulomb):
    """The slip is stored as u + F/k instead of u - F/k."""

    def _new_state(self, state, u, force, k, sliding):
        return {"slip": np.where(sliding[:, None], u + force / k, state["slip"])}


class BoxFriction(Coulomb):
    """2-D: each axis clipped to mu N on its own (uncoupled per-axis limits): |F| reaches sqrt(2) mu N."""

    per_axis_limit: ClassVar[float] = 1.0

    def respond(self, state, u, normal_force, dt):
        u = np.array(u, dtype=float)
        n = len(u)
        k = _per_connector(self.k, n)
        normal = np.asarray(normal_force, dtype=float)
        limit = self.per_axis_limit * self._capacity(state, normal, n)[:, None]
        trial = k * (u - state["slip"])
        force = np.clip(trial, -limit, limit)
        sticking = np.abs(trial) < limit  # no capacity: no force, no stiffness
        tangent = k[:, :, None] * np.einsum("ij,jk->ijk", sticking.astype(float), np.eye(self.dims))
        clipped = ~sticking & (normal > 0)[:, None]
        dforce_dnormal = np.where(clipped, np.sign(trial) * self.per_axis_limit * _per_connector(self.mu, n), 0.0)
        return LawResponse(force, tangent, {"slip": u - force / k}, dforce_dnormal=dforce_dnormal)


class InscribedBoxFriction(BoxFriction):
    """2-D per-axis limits of mu N / sqrt(2): the force never leaves the circle, yet depends on the axes."""

    per_axis_limit: ClassVar[float] = 1.0 / np.sqrt(2.0)


class ForgetsHistory(Coulomb):
    """Returns the state it was given: the slip is never stored (a clipped elastic spring)."""

    def _new_state(self, state, u, force, k, sliding):
        return {"slip": state["slip"].copy()}


class ElasticTangentInSlip(Coulomb):
    """The stick stiffness k returned as the tangent while sliding."""

    def _tangent(self, k, scale, sliding, direction):
        return np.broadcast_to(k[:, :, None] * np.eye(self.dims), (len(k), self.dims, self.dims)).copy()


class TrialTangent(Coulomb):
    """2-D: the tangent of the trial direction without the return's scale, k (I - n n^T)."""

    def _tangent(self, k, scale, sliding, direction):
        return super()._tangent(k, np.where(sliding & (scale > 0), 1.0, scale), sliding, direction)


class WrongTangentSign(Coulomb):
    """The tangent with the wrong sign."""

    def _tangent(self, k, scale, sliding, direction):
        return -super()._tangent(k, scale, sliding, direction)


class StickTangentWithoutContact(Coulomb):
    """No capacity (mu = 0 or N = 0) and a trial at zero: the stick stiffness k, though the force is identically zero."""

    def _return(self, trial, capacity):
        norm = np.sqrt(np.einsum("ij,ij->i", trial, trial))
        sliding = norm > capacity
        safe = np.where(sliding, norm, 1.0)
        scale = np.where(sliding, capacity / safe, 1.0)
        return trial * scale[:, None], sliding, scale, trial / safe[:, None]


class MutatesState(Coulomb):
    """Writes the new slip into the state it was given."""

    def _new_state(self, state, u, force, k, sliding):
        new = super()._new_state(state, u, force, k, sliding)
        state["slip"][...] = new["slip"]
        return new


class AliasesCallerArray(Coulomb):
    """Computes the new slip in the caller's u array (no copy), so the state is the caller's array."""

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        if isinstance(u, np.ndarray) and u.dtype == float:
            u[...] = response.state["slip"]  # "reuse the buffer"
            return LawResponse(response.force, response.tangent, {"slip": u}, dforce_dnormal=response.dforce_dnormal)
        return response


class NaNAtZero(Coulomb):
    """The slip direction divides by |trial| unguarded: NaN where the trial is zero."""

    def _return(self, trial, capacity):
        norm = np.sqrt(np.einsum("ij,ij->i", trial, trial))
        sliding = norm > capacity
        with np.errstate(all="ignore"):
            scale = np.where(sliding, capacity / norm, 1.0)
            direction = trial / norm[:, None]
        return trial * scale[:, None], sliding, scale, direction


class ReturnsList(Coulomb):
    """Returns the force as a nested list instead of an array."""

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(response.force.tolist(), response.tangent, response.state, dforce_dnormal=response.dforce_dnormal)


class WeakerInReverse(Coulomb):
    """Sliding in the negative direction (first axis) reaches only 0.9 mu N: not odd."""

    def _return(self, trial, capacity):
        capacity = np.where(trial[:, 0] < 0, 0.9 * capacity, capacity)
        return super()._return(trial, capacity)


class FirstNormalForceForAll(Coulomb):
    """Reads only the first connector's normal force (a loop written for one bearing)."""

    def _capacity(self, state, normal, n):
        return _per_connector(self.mu, n)[:, 0] * max(float(normal[0]), 0.0)


class IgnoresNormalForceChanges(Coulomb):
    """Keeps the first normal force it saw in its state and ignores later changes."""

    def initial_state(self, n):
        return {**super().initial_state(n), "normal": np.full(n, np.nan)}

    def _capacity(self, state, normal, n):
        first = np.where(np.isnan(state["normal"]), normal, state["normal"])
        return _per_connector(self.mu, n)[:, 0] * np.maximum(first, 0.0)

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        first = np.where(np.isnan(state["normal"]), np.asarray(normal_force, dtype=float), state["normal"])
        return LawResponse(response.force, response.tangent, {**response.state, "normal": first},
                           dforce_dnormal=response.dforce_dnormal)  # fmt: skip


class WrongNormalDerivative(Coulomb):
    """dF/dN with the wrong sign."""

    def _dforce_dnormal(self, normal, sliding, direction, n):
        return -super()._dforce_dnormal(normal, sliding, direction, n)


class MissingNormalDerivative(Coulomb):
    """Declares normal_coupling but returns no dforce_dnormal."""

    def _dforce_dnormal(self, normal, sliding, direction, n):
        return None


class FirstParameterForAll(Coulomb):
    """Per-bearing arrays: uses the first connector's k and mu for every connector."""

    def _first(self, value, n):
        return _per_connector(np.asarray(value, dtype=float).reshape(-1)[0], n)

    def _capacity(self, state, normal, n):
        return self._first(self.mu, n)[:, 0] * np.maximum(normal, 0.0)

    def respond(self, state, u, normal_force, dt):
        u = np.array(u, dtype=float)
        n = len(u)
        k = self._first(self.k, n)
        normal = np.asarray(normal_force, dtype=float)
        capacity = self._capacity(state, normal, n)
        force, sliding, scale, direction = self._return(self._trial(state, u, k), capacity)
        return LawResponse(force, self._tangent(k, scale, sliding, direction), self._new_state(state, u, force, k, sliding),
                           dforce_dnormal=np.where((sliding & (normal > 0))[:, None], self._first(self.mu, n) * direction, 0.0))  # fmt: skip


class NoLengthCheck(Coulomb):
    """Per-bearing arrays recycled to any number of connectors (np.resize) instead of checking the length."""

    def initial_state(self, n):
        return {"slip": np.zeros((n, self.dims))}

    def respond(self, state, u, normal_force, dt):
        n = len(u)
        resized = attrs.evolve(self, k=np.resize(np.asarray(self.k, dtype=float), n), mu=np.resize(np.asarray(self.mu, dtype=float), n))
        return Coulomb.respond(resized, state, u, normal_force, dt)


@attrs.define(frozen=True, slots=False)
class HiddenMemory(Coulomb):
    """Remembers the slip of its last call in the law object and starts from it, not from the state."""

    def respond(self, state, u, normal_force, dt):
        last = self.__dict__.get("_last")
        start = state if last is None or last["slip"].shape != state["slip"].shape else last
        response = super().respond(start, u, normal_force, dt)
        object.__setattr__(self, "_last", response.state)
        return response


class DtDependentStiffness(Coulomb):
    """The stick stiffness scaled down for small time steps ("regularised" by dt): not rate independent."""

    def respond(self, state, u, normal_force, dt):
        factor = min(1.0, 100.0 * dt)
        return Coulomb(k=np.asarray(self.k) * factor, mu=self.mu, dims=self.dims).respond(state, u, normal_force, dt)


class StoresCallersArray(Coulomb):
    """Keeps the caller's u array itself (not a copy) in its state and derives the slip from it later."""

    def initial_state(self, n):
        return {"u": np.zeros((n, self.dims)), "elastic": np.zeros((n, self.dims))}

    def slip(self, state):
        return state["u"] - state["elastic"]

    def respond(self, state, u, normal_force, dt):
        response = super().respond({"slip": self.slip(state)}, u, normal_force, dt)
        held = np.asarray(u)  # no copy: the caller's array
        return LawResponse(response.force, response.tangent, {"u": held, "elastic": held - response.state["slip"]},
                           dforce_dnormal=response.dforce_dnormal)  # fmt: skip


# --- linear spring -------------------------------------------------------------------------------


@attrs.frozen
class Spring:
    """A correct copy of ``linear-spring``: F = k u, per-bearing k."""

    name: ClassVar[str] = "copy-of-linear-spring"
    rigid: ClassVar[bool] = False
    per_bearing: ClassVar[bool] = True
    k: float = parameter(low=0.0, low_open=True, unit="N/m", typical=4e8, per_bearing=True)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        u = np.array(u, dtype=float)
        check_per_bearing(self, len(u))
        k = _per_connector(self.k, len(u))
        return LawResponse(k * u, k[:, :, None] * np.eye(self.dims), state)


class NegativeSpring(Spring):
    """F = -k u (the force on the bearing instead of the force it resists with), tangent -k."""

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(-response.force, -response.tangent, state)


class SpringWithoutTangent(Spring):
    """Returns a zero tangent ("the kernel will iterate")."""

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(response.force, np.zeros_like(response.tangent), state)


class SpringMeanStiffness(Spring):
    """Per-bearing k averaged over the connectors."""

    def respond(self, state, u, normal_force, dt):
        u = np.array(u, dtype=float)
        k = float(np.mean(self.k))
        return LawResponse(k * u, np.broadcast_to(k * np.eye(self.dims), (len(u), self.dims, self.dims)).copy(), state)


class SpringInPlace(Spring):
    """Scales the caller's u in place to make the force."""

    def respond(self, state, u, normal_force, dt):
        k = _per_connector(self.k, len(u))
        u *= k
        return LawResponse(u, k[:, :, None] * np.eye(self.dims), state)


# --- velocity-dependent friction ------------------------------------------------------------------


@attrs.frozen
class VelocityFriction:
    """PTFE-like friction: mu(v) = f_max - (f_max - f_min) exp(-a |v|), radial return, stick stiffness k."""

    name: ClassVar[str] = "copy-of-velocity-friction"
    rigid: ClassVar[bool] = False
    uses_velocity: ClassVar[bool] = True
    rate_dependent: ClassVar[bool] = True
    friction: ClassVar[bool] = True
    normal_coupling: ClassVar[bool] = True
    k: float = parameter(low=0.0, low_open=True, unit="N/m", typical=4e8)
    f_min: float = parameter(low=1e-3, high=0.5, typical=0.02)
    f_max: float = parameter(low=1e-3, high=0.5, typical=0.05)
    a: float = parameter(low=0.0, unit="s/m", typical=25.0)
    dims: int = dims_parameter()

    def __attrs_post_init__(self):
        if self.f_min > self.f_max:
            raise ParameterError(f"{self.name}: f_min = {self.f_min} must not exceed f_max = {self.f_max}")

    def initial_state(self, n: int) -> dict:
        return {"slip": np.zeros((n, self.dims))}

    def force_bound(self, normal_force):
        return self.f_max * np.maximum(np.asarray(normal_force, dtype=float), 0.0)

    def slip(self, state):
        return state["slip"]

    def rate_independent_limit(self):
        return attrs.evolve(self, a=0.0), Coulomb(k=self.k, mu=self.f_min, dims=self.dims)

    def _speed(self, state, u, velocity, dt):
        v = np.zeros_like(u) if velocity is None else np.asarray(velocity, dtype=float)
        return v, np.sqrt(np.einsum("ij,ij->i", v, v))

    def respond(self, state, u, normal_force, dt, velocity=None) -> LawResponse:
        u = np.array(u, dtype=float)
        v, speed = self._speed(state, u, velocity, dt)
        decay = np.exp(-self.a * speed)
        mu = self.f_max - (self.f_max - self.f_min) * decay
        normal = np.asarray(normal_force, dtype=float)
        contact = np.maximum(normal, 0.0)
        capacity = mu * contact
        trial = self.k * (u - state["slip"])
        norm = np.sqrt(np.einsum("ij,ij->i", trial, trial))
        sliding = (norm > capacity) | (capacity <= 0.0)
        safe = np.where(sliding & (norm > 0), norm, 1.0)
        scale = np.where(sliding, capacity / safe, 1.0)
        force = trial * scale[:, None]
        direction = trial / safe[:, None]
        projector = np.eye(self.dims) - sliding[:, None, None] * np.einsum("ij,ik->ijk", direction, direction)
        slipping = sliding & (normal > 0)
        dmu_dv = (self.a * (self.f_max - self.f_min) * decay / np.where(speed > 0, speed, 1.0) * (speed > 0))[:, None] * v
        return LawResponse(
            force,
            self.k * scale[:, None, None] * projector,
            self._new_state(state, u, force, sliding),
            dforce_dnormal=np.where(slipping[:, None], mu[:, None] * direction, 0.0),
            dforce_dvelocity=self._dforce_dvelocity(slipping, direction, contact, dmu_dv),
        )

    def _new_state(self, state, u, force, sliding):
        return {"slip": np.where(sliding[:, None], u - force / self.k, state["slip"])}

    def _dforce_dvelocity(self, slipping, direction, contact, dmu_dv):
        return np.where(slipping[:, None, None], np.einsum("ij,ik->ijk", direction, contact[:, None] * dmu_dv), 0.0)


@attrs.define(frozen=True, slots=False)
class VelocityFromLastTrial(VelocityFriction):
    """Ignores the kernel's velocity: (u - u of its last call) / dt, remembered in the law object."""

    def _speed(self, state, u, velocity, dt):
        last = self.__dict__.get("_last_u")
        v = np.zeros_like(u) if last is None or last.shape != u.shape else (u - last) / dt
        object.__setattr__(self, "_last_u", u.copy())
        return v, np.sqrt(np.einsum("ij,ij->i", v, v))

    def _dforce_dvelocity(self, slipping, direction, contact, dmu_dv):
        return None


class VelocityFromCommittedDisplacement(VelocityFriction):
    """Ignores the kernel's velocity and takes (u - u_committed) / dt, stored in its state."""

    def initial_state(self, n):
        return {**super().initial_state(n), "u": np.zeros((n, self.dims))}

    def _speed(self, state, u, velocity, dt):
        v = (u - state["u"]) / dt
        return v, np.sqrt(np.einsum("ij,ij->i", v, v))

    def _new_state(self, state, u, force, sliding):
        return {**super()._new_state(state, u, force, sliding), "u": u}

    def _dforce_dvelocity(self, slipping, direction, contact, dmu_dv):
        return None

    def respond(self, state, u, normal_force, dt, velocity=None):
        # Its tangent in u is that of its own map (the speed moves with u): consistent in u.
        u = np.array(u, dtype=float)
        response = super().respond(state, u, normal_force, dt, velocity)
        tangent = _numeric_tangent(lambda x: super(VelocityFromCommittedDisplacement, self).respond(state, x, normal_force, dt).force, u)
        return LawResponse(response.force, tangent, response.state, dforce_dnormal=response.dforce_dnormal)


class VelocityDerivativeMissing(VelocityFriction):
    """Uses the velocity but returns no dforce_dvelocity."""

    def _dforce_dvelocity(self, slipping, direction, contact, dmu_dv):
        return None


class LimitStillRateDependent(VelocityFriction):
    """rate_independent_limit() forgets to switch the rate dependence off."""

    def rate_independent_limit(self):
        return self, Coulomb(k=self.k, mu=self.f_min, dims=self.dims)


class VelocityFrictionInTension(VelocityFriction):
    """|N| instead of N clamped at zero."""

    def respond(self, state, u, normal_force, dt, velocity=None):
        return super().respond(state, u, np.abs(np.asarray(normal_force, dtype=float)), dt, velocity)


# --- a viscous damper that computes its own velocity ----------------------------------------------


@attrs.frozen
class Damper:
    """F = c (u - u_committed) / dt (backward Euler), tangent c / dt; declares rate_dependent."""

    name: ClassVar[str] = "copy-of-viscous-damper"
    rigid: ClassVar[bool] = False
    rate_dependent: ClassVar[bool] = True
    c: float = parameter(low=0.0, low_open=True, unit="N s/m", typical=2e6)
    dims: int = dims_parameter()

    def initial_state(self, n):
        return {"u": np.zeros((n, self.dims))}

    def _reference(self, state, u):
        return state["u"]

    def respond(self, state, u, normal_force, dt):
        u = np.array(u, dtype=float)
        force = self.c * (u - self._reference(state, u)) / dt
        tangent = np.broadcast_to(self.c / dt * np.eye(self.dims), (len(u), self.dims, self.dims)).copy()
        return LawResponse(force, tangent, {"u": u})


@attrs.define(frozen=True, slots=False)
class DamperFromLastTrial(Damper):
    """The velocity from the last *trial* displacement it was called with (kept in the object), not the committed one."""

    def _reference(self, state, u):
        last = self.__dict__.get("_last")
        object.__setattr__(self, "_last", u.copy())
        return state["u"] if last is None or last.shape != u.shape else last


class UndeclaredDamper(Damper):
    """The same damper without rate_dependent = True."""

    rate_dependent: ClassVar[bool] = False


# --- the catalogue ------------------------------------------------------------------------------

COULOMB = {"k": 4e8, "mu": 0.04}
VELOCITY = {"k": 4e8, "f_min": 0.02, "f_max": 0.05, "a": 25.0}

#: The correct laws: they pass the kit.
REFERENCES = [
    Coulomb(dims=1, **COULOMB),
    Coulomb(dims=2, **COULOMB),
    Coulomb(dims=2, k=np.array([4e8, 1e8, 6e8]), mu=np.array([0.04, 0.1, 0.0])),
    Spring(k=4e8, dims=2),
    VelocityFriction(dims=1, **VELOCITY),
    VelocityFriction(dims=2, **VELOCITY),
    Damper(c=2e6, dims=2),
]

#: (mutant, the properties expected to catch it).
MUTANTS = [
    (NonAssociatedSlip(dims=2, **COULOMB), {"normality", "tangent", "committed state"}),
    (ForceAlongDisplacement(dims=2, **COULOMB), {"normality", "tangent", "committed state", "history"}),
    (FrictionInTension(dims=1, **COULOMB), {"no contact", "force bound"}),
    (UnclampedNormalForce(dims=2, **COULOMB), {"no contact", "force bound", "response shapes", "tangent"}),
    (SlipUpdateWrongSign(dims=1, **COULOMB), {"committed state"}),
    (BoxFriction(dims=2, **COULOMB), {"force bound"}),
    (InscribedBoxFriction(dims=2, **COULOMB), {"rotation invariance", "normality"}),
    (ForgetsHistory(dims=2, **COULOMB), {"history"}),
    (ElasticTangentInSlip(dims=1, **COULOMB), {"tangent"}),
    (TrialTangent(dims=2, **COULOMB), {"tangent"}),
    (WrongTangentSign(dims=2, **COULOMB), {"tangent"}),
    (StickTangentWithoutContact(dims=1, **COULOMB), {"tangent", "no contact"}),
    (MutatesState(dims=2, **COULOMB), {"purity"}),
    (AliasesCallerArray(dims=2, **COULOMB), {"purity"}),
    (StoresCallersArray(dims=2, **COULOMB), {"purity"}),
    (NaNAtZero(dims=2, **COULOMB), {"response shapes", "zero force at rest"}),
    (ReturnsList(dims=2, **COULOMB), {"response shapes"}),
    (WeakerInReverse(dims=1, **COULOMB), {"odd symmetry"}),
    (FirstNormalForceForAll(dims=2, **COULOMB), {"vectorised"}),
    (IgnoresNormalForceChanges(dims=2, **COULOMB), {"force bound", "normal derivative", "tangent"}),
    (WrongNormalDerivative(dims=2, **COULOMB), {"normal derivative"}),
    (MissingNormalDerivative(dims=1, **COULOMB), {"response shapes"}),
    (FirstParameterForAll(dims=2, **COULOMB), {"per-bearing"}),
    (NoLengthCheck(dims=1, **COULOMB), {"per-bearing"}),
    # Memory in the law object shows wherever a call follows another: any property may see it first.
    (HiddenMemory(dims=2, **COULOMB), {"purity", "trial independence", "zero force at rest", "response shapes"}),
    (DtDependentStiffness(dims=1, **COULOMB), {"rate independence"}),
    (NegativeSpring(k=4e8, dims=2), {"dissipation"}),
    (SpringWithoutTangent(k=4e8, dims=1), {"tangent"}),
    (SpringMeanStiffness(k=4e8, dims=2), {"per-bearing"}),
    (SpringInPlace(k=4e8, dims=1), {"purity"}),
    (VelocityFromLastTrial(dims=1, **VELOCITY), {"purity", "trial independence"}),
    (VelocityFromCommittedDisplacement(dims=2, **VELOCITY), {"velocity from the kernel"}),
    (VelocityDerivativeMissing(dims=2, **VELOCITY), {"velocity derivative"}),
    (LimitStillRateDependent(dims=1, **VELOCITY), {"rate-independent limit"}),
    (VelocityFrictionInTension(dims=2, **VELOCITY), {"no contact", "force bound"}),
    (DamperFromLastTrial(c=2e6, dims=1), {"purity", "trial independence"}),
    (UndeclaredDamper(c=2e6, dims=1), {"committed state", "rate independence"}),
]
