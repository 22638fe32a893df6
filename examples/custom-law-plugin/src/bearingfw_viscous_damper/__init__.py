"""A linear viscous damper as a bearingfw law: the smallest complete law plugin.

F = c v, with v the relative velocity the time integrator gives the law at the trial point
(``uses_velocity``). The force does not depend on the displacement at fixed velocity, so
``tangent`` is zero and the velocity derivative ``dforce_dvelocity = c I`` goes to the kernel,
which scales it by the integrator's dv/du. The law is a plain attrs class: bearingfw needs no base
class, only the five protocol members; ``bearingfw.parameter`` gives ``c`` its range and unit
(``bearingfw plugins`` lists them) and lets it be one value per connector (``per_bearing``).
"""

from typing import ClassVar

import attrs
import numpy as np

import bearingfw


@attrs.frozen
class ViscousDamper:
    name: ClassVar[str] = "viscous-damper"  # the registry key
    rigid: ClassVar[bool] = False
    uses_velocity: ClassVar[bool] = True  # respond(..., velocity=v) from the integrator
    rate_dependent: ClassVar[bool] = True  # its force depends on the rate (implied by uses_velocity)
    per_bearing: ClassVar[bool] = True  # c may be an array, one value per connector
    c: float = bearingfw.parameter(low=0.0, low_open=True, unit="N s/m", doc="damping coefficient", per_bearing=True)
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}  # no history: the force depends on the velocity alone

    def respond(self, state, u, normal_force, dt, velocity=None) -> bearingfw.LawResponse:
        n = len(u)
        bearingfw.check_per_bearing(self, n)
        v = np.zeros((n, self.dims)) if velocity is None else np.asarray(velocity, dtype=float)
        c = np.asarray(self.c, dtype=float)[..., None]  # scalar -> (1,), array -> (n, 1)
        dforce_dvelocity = np.broadcast_to(c[..., None] * np.eye(self.dims), (n, self.dims, self.dims)).copy()
        return bearingfw.LawResponse(c * v, np.zeros((n, self.dims, self.dims)), state, dforce_dvelocity=dforce_dvelocity)


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [ViscousDamper]
