"""The linear laws: free sliding, a rigid tie and a linear spring."""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

from bearingfw.parameters import dims_parameter, parameter
from bearingfw.protocol import LawResponse


@attrs.frozen
class Frictionless:
    """Free sliding: no resisting force (the paper's M0)."""

    name: ClassVar[str] = "frictionless"
    rigid: ClassVar[bool] = False
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        n = np.shape(u)[0]
        return LawResponse(np.zeros((n, self.dims)), np.zeros((n, self.dims, self.dims)), state)


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
    """F = k u in every governed direction (the paper's M1, k = K_s)."""

    name: ClassVar[str] = "linear-spring"
    rigid: ClassVar[bool] = False
    k: float = parameter(low=0.0, low_open=True, unit="N/m", doc="spring stiffness", typical=4e8)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        u = np.asarray(u, dtype=float)
        tangent = np.broadcast_to(self.k * np.eye(self.dims), (u.shape[0], self.dims, self.dims))
        return LawResponse(self.k * u, tangent.copy(), state)
