"""A linear viscous damper as a bearingfw law: the smallest complete law plugin.

F = c v with the velocity of the step, v = (u - u_committed) / dt (backward Euler), so the
consistent tangent is c / dt. The law is a plain class: bearingfw needs no base class, only the
five protocol members. Its state is the committed displacement.
"""

import math

import numpy as np

import bearingfw


class ViscousDamper:
    name = "viscous-damper"  # the registry key
    rigid = False

    def __init__(self, c: float, dims: int = 1):
        # bearingfw turns these errors into messages that also name the law.
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not math.isfinite(c) or c <= 0:
            raise ValueError(f"parameter 'c' (damping coefficient, N s/m) must be a finite number > 0, got {c!r}")
        if dims not in (1, 2):
            raise ValueError(f"parameter 'dims' must be 1 or 2, got {dims!r}")
        self.c, self.dims = float(c), dims

    def initial_state(self, n: int) -> dict:
        return {"u": np.zeros((n, self.dims))}

    def respond(self, state, u, normal_force, dt) -> bearingfw.LawResponse:
        u = np.asarray(u, dtype=float)
        force = self.c * (u - state["u"]) / dt
        tangent = np.broadcast_to(self.c / dt * np.eye(self.dims), (len(u), self.dims, self.dims)).copy()
        # A new state object: respond must never change the one it was given.
        return bearingfw.LawResponse(force, tangent, {"u": u.copy()})


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [ViscousDamper]
