"""The built-in metric families and executors of the experiment runner, registered through the
``bearingfw`` entry point like any plugin.

(Filled in by the experiment-engine work.)
"""

from bearingfw.plugins.hookspecs import hookimpl


@hookimpl
def bearingfw_register_metrics():
    return []


@hookimpl
def bearingfw_register_executors():
    return []
