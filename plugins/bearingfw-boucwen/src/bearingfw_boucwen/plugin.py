"""The module the ``bearingfw`` entry point names: bearingfw registers it with pluggy and calls its hooks."""

import bearingfw

from bearingfw_boucwen.law import BoucWen


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [BoucWen]
