"""The built-in laws, registered through the ``bearingfw`` entry point like any plugin."""

from bearingfw.laws.coulomb import RegularizedCoulomb
from bearingfw.laws.elastic import Fixed, Frictionless, LinearSpring
from bearingfw.plugins.hookspecs import hookimpl


@hookimpl
def bearingfw_register_laws():
    return [Frictionless, Fixed, LinearSpring, RegularizedCoulomb]
