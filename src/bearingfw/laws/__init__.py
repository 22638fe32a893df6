"""Built-in bearing laws. Use them by name through :func:`bearingfw.create_law`."""

from bearingfw.laws.coulomb import RegularizedCoulomb
from bearingfw.laws.elastic import Fixed, Frictionless, LinearSpring
from bearingfw.laws.inputs import respond_inputs

__all__ = ["Fixed", "Frictionless", "LinearSpring", "RegularizedCoulomb", "respond_inputs"]
