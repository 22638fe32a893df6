"""Test-only bearing laws, loaded by experiments through ``plugins = ["bfw_test_laws"]``.

- ``test-exploding-spring``: a linear spring that raises as soon as it is displaced (a plugin bug):
  building the model, the gravity preload and the modal analysis (all at zero displacement) work,
  the first time step fails.
- ``test-slow-spring``: a linear spring that sleeps ``delay`` seconds in every call, so that a cell
  takes long enough for a test to kill the run in the middle.
"""

from __future__ import annotations

import time
from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.parameters import dims_parameter, parameter
from bearingfw.protocol import LawResponse


def _spring(k: float, u, dims: int) -> LawResponse:
    u = np.asarray(u, dtype=float)
    tangent = np.broadcast_to(k * np.eye(dims), (u.shape[0], dims, dims)).copy()
    return LawResponse(k * u, tangent, None)


@attrs.frozen
class ExplodingSpring:
    name: ClassVar[str] = "test-exploding-spring"
    rigid: ClassVar[bool] = False
    k: float = parameter(low=0.0, low_open=True, unit="N/m", default=4e8)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        if np.any(np.abs(np.asarray(u)) > 1e-12):
            raise RuntimeError("test-exploding-spring: exploded on purpose")
        response = _spring(self.k, u, self.dims)
        return LawResponse(response.force, response.tangent, state)


@attrs.frozen
class SlowSpring:
    name: ClassVar[str] = "test-slow-spring"
    rigid: ClassVar[bool] = False
    k: float = parameter(low=0.0, low_open=True, unit="N/m", default=4e8)
    delay: float = parameter(low=0.0, default=1e-3, unit="s")
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        time.sleep(self.delay)
        response = _spring(self.k, u, self.dims)
        return LawResponse(response.force, response.tangent, state)


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [ExplodingSpring, SlowSpring]
