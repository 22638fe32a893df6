"""Built-in bearing laws. Use them by name through :func:`bearingfw.create_law`."""

from bearingfw.laws.coulomb import RegularizedCoulomb, ReturnMap, friction_return_map
from bearingfw.laws.elastic import Fixed, Frictionless, LinearSpring
from bearingfw.laws.inputs import respond_inputs, velocity_input

__all__ = [
    "Fixed", "Frictionless", "LinearSpring", "RegularizedCoulomb", "ReturnMap", "friction_return_map", "respond_inputs",
    "velocity_input",
]
