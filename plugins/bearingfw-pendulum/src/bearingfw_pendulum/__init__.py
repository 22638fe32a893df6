"""bearingfw-pendulum: the single concave friction pendulum bearing, as a bearingfw plugin.

Installing the distribution is all it takes: its entry point (group ``bearingfw``) registers the
laws ``friction-pendulum`` (constant friction) and ``friction-pendulum-vel`` (velocity-dependent
friction) and the preset ``pendulum``; ``bearingfw plugins`` lists them. The classes are
importable too, for tests and scripts.
"""

from importlib.metadata import PackageNotFoundError, version

from bearingfw_pendulum.law import FrictionPendulum, VelocityFrictionPendulum

try:
    __version__ = version("bearingfw-pendulum")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = ["FrictionPendulum", "VelocityFrictionPendulum", "__version__"]
