"""Regularized (elastoplastic) Coulomb friction: the paper's M2, section 2.5, eqs. (3)-(6).

The relative displacement splits into an elastic stick part and an irreversible slip,
``u = u_e + u_p``. The force is ``F = k (u - u_p)`` while ``|F| < mu N``; on the slip surface
``|F| = mu N`` the slip grows along ``F`` (associated rule). With N held constant and one
direction this is an elastic-perfectly-plastic spring with yield force ``mu N``.

Integration is a backward-Euler return mapping, which has a closed form because the surface is a
circle (a pair of points in 1-D): the trial force ``k (u - u_p,n)`` is scaled back onto the
circle. The tangent is the derivative of that map, ``k`` in stick and
``k (mu N / |F_trial|) (I - n n^T)`` in slip (zero in 1-D), so Newton converges quadratically.

Where there is no capacity (``mu = 0``, or ``N <= 0``: tension, lift-off) the force is
identically zero, so force and tangent are zero even at ``u = u_p``, where the trial force
vanishes and the map would otherwise count as stick.

Normal-force coupling: ``d F / d N`` at fixed ``u`` is ``mu n`` in slip (``n`` the slip
direction; ``mu sgn`` in 1-D) and zero in stick or without contact.

Per-bearing parameters: ``k`` and ``mu`` may be arrays of one value per connector; the arithmetic
is written so that a scalar gives the same bits as before (``np.asarray(p)[..., None]``
broadcasts a scalar as a length-1 axis and an array as a column).
"""

from __future__ import annotations

from typing import ClassVar, NamedTuple

import attrs
import numpy as np

from bearingfw.laws.inputs import respond_inputs
from bearingfw.parameters import ParameterError, check_per_bearing, dims_parameter, parameter
from bearingfw.protocol import LawResponse

#: identity blocks of the tangent, shared read-only (an allocation per call costs more than the law)
_EYE = {d: np.eye(d) for d in (1, 2)}
for _e in _EYE.values():
    _e.setflags(write=False)
#: 0.0 as a numpy array: a ufunc takes it faster than the Python float (the same comparison)
_ZERO = np.zeros(())
_ZERO.setflags(write=False)


class ReturnMap(NamedTuple):
    """What :func:`friction_return_map` gives, per connector."""

    force: np.ndarray  # (n, dims): the trial force, scaled back onto the slip surface where it lies beyond
    slip: np.ndarray  # (n, dims): the slip after the step
    direction: np.ndarray  # (n, dims): the trial force's direction where it slides (else the trial force itself)
    sliding: np.ndarray  # (n,) bool: on the slip surface, or without capacity (a force identically zero)
    tangent: np.ndarray  # (n, dims, dims): d force / d u


def friction_return_map(k, u: np.ndarray, slip: np.ndarray, capacity: np.ndarray) -> ReturnMap:
    """The backward-Euler return map of a stick spring ``k`` on a circular slip surface of radius
    ``capacity`` (module docstring), for the friction laws that differ only in their capacity
    (this module's, the PTFE and pendulum plugins').

    ``k``: a scalar or a column ``(n, 1)``; ``u``, ``slip``: ``(n, dims)``; ``capacity``: ``(n,)``.
    Where ``capacity <= 0`` the force is identically zero, also at a zero trial force.
    """
    trial = k * (u - slip)
    # |trial| per connector (in 1-D |t| itself, which sqrt(t * t) equals but for underflow)
    trial_norm = np.abs(trial[:, 0]) if u.shape[1] == 1 else np.sqrt(np.einsum("ij,ij->i", trial, trial))
    sliding = (trial_norm > capacity) | (capacity <= 0.0)
    safe_norm = np.where(sliding & (trial_norm > 0.0), trial_norm, 1.0)
    scale = np.where(sliding, capacity / safe_norm, 1.0)
    force = trial * scale[:, None]
    new_slip = np.where(sliding[:, None], u - force / k, slip)
    direction = trial / safe_norm[:, None]
    projector = _EYE[u.shape[1]] - sliding[:, None, None] * (direction[:, :, None] * direction[:, None, :])
    tangent = np.asarray(k, dtype=float)[..., None] * scale[:, None, None] * projector
    return ReturnMap(force, new_slip, direction, sliding, tangent)


@attrs.frozen
class RegularizedCoulomb:
    """Stick stiffness ``k`` up to the friction force ``mu N``, then sliding.

    State: ``{"slip": (n, dims)}``, the accumulated slip ``u_p`` in metres. ``N`` is read on every
    call; ``N <= 0`` (no contact or uplift) leaves no friction capacity.
    """

    name: ClassVar[str] = "regularized-coulomb"
    rigid: ClassVar[bool] = False
    per_bearing: ClassVar[bool] = True
    friction: ClassVar[bool] = True
    normal_coupling: ClassVar[bool] = True
    k: float = parameter(low=0.0, low_open=True, unit="N/m", doc="stick stiffness (K_s)", typical=4e8, per_bearing=True)
    mu: float = parameter(low=0.0, high=1.0, high_open=True, doc="friction coefficient", typical=0.04, per_bearing=True)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"slip": np.zeros((n, self.dims))}

    def force_bound(self, normal_force) -> np.ndarray:
        return self.mu * np.maximum(np.asarray(normal_force, dtype=float), 0.0)

    def slip(self, state) -> np.ndarray:
        return state["slip"]

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        u, normal_force = respond_inputs(self, u, normal_force)
        n, dims = u.shape
        k, mu = self.k, self.mu
        if isinstance(k, np.ndarray) or isinstance(mu, np.ndarray):
            check_per_bearing(self, n)
        # a scalar multiplies as itself; an array per connector as a column over (n, dims)
        k = np.asarray(k, dtype=float)[..., None] if isinstance(k, np.ndarray) else k
        slip = state["slip"]
        if slip.shape != u.shape:  # a state of other connectors would broadcast into nonsense
            raise ParameterError(
                f"law {self.name!r}: respond() argument 'state' holds a slip of shape {slip.shape} but 'u' has shape "
                f"{u.shape}: give the state of the same connectors (initial_state({u.shape[0]}))"
            )
        capacity = self.mu * np.maximum(normal_force, _ZERO)  # force_bound: normal_force is a float array
        trial = k * (u - slip)
        # |trial| per connector (in 1-D sqrt(t * t) is |t| exactly)
        trial_norm = np.abs(trial[:, 0]) if dims == 1 else np.sqrt(np.einsum("ij,ij->i", trial, trial))
        beyond = trial_norm > capacity
        # (count_nonzero: one C call, a fraction of a ufunc reduction's cost at these sizes)
        if np.count_nonzero(capacity > _ZERO) == n:  # every connector in contact with friction (the usual case)
            n_beyond = np.count_nonzero(beyond)
            if not n_beyond:
                # every connector sticks: the map below with scale 1 and no slip, in closed form
                tangent = np.empty((n, dims, dims))
                tangent[...] = k[..., None] * _EYE[dims] if isinstance(k, np.ndarray) else k * _EYE[dims]
                return LawResponse(trial, tangent, {"slip": slip}, dforce_dnormal=np.zeros((n, dims)))
            if n_beyond == n:
                # every connector slides (trial_norm > capacity > 0): the map below without its
                # selections, the same operations on the same numbers
                scale = capacity / trial_norm
                force = trial * scale[:, None]
                direction = trial / trial_norm[:, None]
                if dims == 1:
                    tangent = np.zeros((n, 1, 1))  # k scale (1 - 1)
                else:
                    column = scale[:, None, None]
                    kscale = k[..., None] * column if isinstance(k, np.ndarray) else k * column
                    tangent = kscale * (_EYE[dims] - direction[:, :, None] * direction[:, None, :])
                mu = np.asarray(mu, dtype=float)[..., None] if isinstance(mu, np.ndarray) else mu
                return LawResponse(force, tangent, {"slip": u - force / k}, dforce_dnormal=mu * direction)
        if not isinstance(k, np.ndarray):
            k = np.asarray(k, dtype=float)[..., None]
        if not ((beyond | (capacity <= 0.0)).any()):
            tangent = np.empty((n, dims, dims))
            tangent[...] = k[..., None] * _EYE[dims]
            return LawResponse(trial, tangent, {"slip": slip}, dforce_dnormal=np.zeros((n, dims)))
        mu = np.asarray(mu, dtype=float)[..., None]
        force, new_slip, direction, sliding, tangent = friction_return_map(k, u, slip, capacity)
        # F = mu N n on the slip surface; zero in stick and without contact (N <= 0).
        in_contact = sliding & (normal_force > 0.0)
        dforce_dnormal = np.where(in_contact[:, None], mu * direction, 0.0)
        return LawResponse(force, tangent, {"slip": new_slip}, dforce_dnormal=dforce_dnormal)
