"""bearingfw-ptfe: PTFE sliding friction with a velocity- and pressure-dependent coefficient.

Installing the distribution is all it takes: its entry point (group ``bearingfw``) registers the
law ``ptfe-friction`` and the preset ``ptfe``, so
``bearingfw.create_law("ptfe-friction", k=..., f_min=..., f_max=..., a=...)`` works and
``bearingfw plugins`` lists it. The class is importable too, for tests and scripts.
"""

from importlib.metadata import PackageNotFoundError, version

from bearingfw_ptfe.law import PTFEFriction

try:
    __version__ = version("bearingfw-ptfe")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = ["PTFEFriction", "__version__"]
