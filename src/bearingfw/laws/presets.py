"""The built-in bearing presets, registered through the ``bearingfw`` entry point like any plugin.

(Filled in by the presets work: M0, M1, M2, fixed.)
"""

from bearingfw.plugins.hookspecs import hookimpl


@hookimpl
def bearingfw_register_presets():
    return []
