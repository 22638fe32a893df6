"""bearingfw-elastomeric: the lead-rubber (elastomeric) bearing law, as a bearingfw plugin.

Installing the distribution registers the law ``elastomeric-plasticity`` and the bridge preset
``lead-rubber`` (entry-point group ``bearingfw``), so
``bearingfw.create_law("elastomeric-plasticity", k=..., qd=..., alpha=...)`` works and
``bearingfw plugins`` lists both.
"""

from importlib.metadata import PackageNotFoundError, version

from bearingfw_elastomeric.law import ElastomericPlasticity, lead_rubber_parameters

try:
    __version__ = version("bearingfw-elastomeric")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = ["ElastomericPlasticity", "__version__", "lead_rubber_parameters"]
