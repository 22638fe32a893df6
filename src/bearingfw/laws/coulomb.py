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

from bearingfw.jit import kernel_array
from bearingfw.laws.inputs import respond_inputs
from bearingfw.parameters import ParameterError, check_per_bearing, dims_parameter, parameter
from bearingfw.protocol import CompiledLaw, LawResponse

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
    Where ``capacity <= 0`` the force is identically zero, also at a zero trial force. Computed by
    the compiled loop :func:`bearingfw.laws.friction_kernel.return_map`.
    """
    global _return_map
    if _return_map is None:
        from bearingfw.laws.friction_kernel import return_map as _return_map
    u = np.asarray(u, dtype=float)
    n = u.shape[0]
    k = np.asarray(k, dtype=float).reshape(-1)  # a scalar, (1,) or a column (n, 1): one value per connector
    if k.size != n:
        k = np.full(n, k[0]) if k.size == 1 else np.broadcast_to(k, (n,))  # broadcast_to: numpy's error
    # broadcast as the numpy formulas did (a wrong shape raises numpy's ValueError, as it did)
    slip, capacity = np.asarray(slip, dtype=float), np.asarray(capacity, dtype=float)
    if slip.shape != u.shape:
        slip = np.broadcast_to(slip, u.shape)
    if capacity.shape != (n,):
        capacity = np.broadcast_to(capacity, (n,))
    return ReturnMap(*_return_map(kernel_array(k), kernel_array(u), kernel_array(slip), kernel_array(capacity)))


#: the compiled return map, imported at the first call (numba's import is not free)
_return_map = None


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
        n = u.shape[0]
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
        force, new_slip, direction, sliding, tangent = friction_return_map(k, u, slip, capacity)
        # F = mu N n on the slip surface; zero in stick and without contact (N <= 0).
        mu = np.asarray(mu, dtype=float)[..., None] if isinstance(mu, np.ndarray) else mu
        dforce_dnormal = np.where((sliding & (normal_force > 0.0))[:, None], mu * direction, 0.0)
        return LawResponse(force, tangent, {"slip": new_slip}, dforce_dnormal=dforce_dnormal)

    def compiled(self, n: int) -> CompiledLaw:
        """This law as a compiled function (:func:`bearingfw.laws.friction_kernel.regularized_coulomb`)."""
        from bearingfw.laws.friction_kernel import regularized_coulomb

        check_per_bearing(self, n)
        dims = self.dims
        parameters = np.concatenate([np.broadcast_to(np.asarray(p, dtype=float), (n,)) for p in (self.k, self.mu)])
        return CompiledLaw(
            regularized_coulomb, parameters, dims,
            pack=lambda state: kernel_array(state["slip"]).reshape(-1),
            unpack=lambda array: {"slip": array.reshape(n, dims)},
        )  # fmt: skip
