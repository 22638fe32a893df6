"""The linear laws: free sliding, a rigid tie and a linear spring."""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

from bearingfw.laws.inputs import respond_inputs
from bearingfw.parameters import check_per_bearing, dims_parameter, parameter
from bearingfw.protocol import CompiledLaw, LawResponse

#: identity blocks of the tangent, shared read-only (allocating one per call costs more than the law)
_EYE = {d: np.eye(d) for d in (1, 2)}
for _e in _EYE.values():
    _e.setflags(write=False)


@attrs.frozen
class Frictionless:
    """Free sliding: no resisting force (the paper's M0)."""

    name: ClassVar[str] = "frictionless"
    rigid: ClassVar[bool] = False
    linear: ClassVar[bool] = True  # F = 0: the kernel folds it (zero) into its matrix
    friction: ClassVar[bool] = True  # trivially: it never resists, in contact or not
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        n = respond_inputs(self, u, normal_force)[0].shape[0]
        return LawResponse(np.zeros((n, self.dims)), np.zeros((n, self.dims, self.dims)), state)

    def compiled(self, n: int) -> CompiledLaw:
        """Free sliding as a compiled law: a linear spring of zero stiffness (no state)."""
        from bearingfw.laws.elastic_kernel import linear_spring

        return CompiledLaw(linear_spring, np.zeros(n), 0, pack=_no_state, unpack=lambda array: {})


@attrs.frozen
class Fixed:
    """A fixed pot bearing: the kernel ties the governed directions (Abaqus JOIN)."""

    name: ClassVar[str] = "fixed"
    rigid: ClassVar[bool] = True
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        raise TypeError("the 'fixed' law is rigid: the kernel ties its directions and never calls respond()")


@attrs.frozen
class LinearSpring:
    """F = k u in every governed direction (the paper's M1, k = K_s); ``k`` may be one value per connector."""

    name: ClassVar[str] = "linear-spring"
    rigid: ClassVar[bool] = False
    linear: ClassVar[bool] = True  # F = k u: the kernel folds k into its matrix
    per_bearing: ClassVar[bool] = True
    k: float = parameter(low=0.0, low_open=True, unit="N/m", doc="spring stiffness", typical=4e8, per_bearing=True)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        u = respond_inputs(self, u, normal_force)[0]
        n = u.shape[0]
        check_per_bearing(self, n)
        k = np.asarray(self.k, dtype=float)[..., None]  # (1,) or (n, 1): broadcasts over (n, dims)
        tangent = np.empty((n, self.dims, self.dims))
        tangent[...] = k[..., None] * _EYE[self.dims]
        return LawResponse(k * u, tangent, state)

    def compiled(self, n: int) -> CompiledLaw:
        """This law as a compiled function (:func:`bearingfw.laws.elastic_kernel.linear_spring`; no state)."""
        from bearingfw.laws.elastic_kernel import linear_spring

        check_per_bearing(self, n)
        k = np.array(np.broadcast_to(np.asarray(self.k, dtype=float), (n,)))
        return CompiledLaw(linear_spring, k, 0, pack=_no_state, unpack=lambda array: {})


def _no_state(state) -> np.ndarray:
    return np.zeros(0)
