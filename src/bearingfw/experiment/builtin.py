"""The built-in metric families and executors of the experiment runner, registered through the
``bearingfw`` entry point (``builtin-experiment``) like any plugin's.

A plugin adds its own the same way: a module with ``@hookimpl`` functions returning a list of
:class:`~bearingfw.experiment.metrics.MetricFamily` records or of executor classes
(:mod:`bearingfw.experiment.executors`), named by an entry point or by an experiment's
``plugins = [...]``.
"""

from bearingfw.plugins.hookspecs import hookimpl


@hookimpl
def bearingfw_register_metrics():
    from bearingfw.experiment.metrics import BUILTIN, SUPPORT_FAMILIES
    from bearingfw.experiment.uplift import UPLIFT_FAMILIES

    return [*BUILTIN, *UPLIFT_FAMILIES, *SUPPORT_FAMILIES]


@hookimpl
def bearingfw_register_executors():
    from bearingfw.experiment.executors import BUILTIN

    return list(BUILTIN)
