"""bearingfw-boucwen: the Bouc-Wen smooth hysteretic bearing law, as a bearingfw plugin.

Installing the distribution is all it takes: its entry point (group ``bearingfw``) registers
the law ``bouc-wen``, so ``bearingfw.create_law("bouc-wen", k=..., alpha=..., uy=...)`` works and
``bearingfw plugins`` lists it. The class is importable too, for tests and scripts.
"""

from importlib.metadata import PackageNotFoundError, version

from bearingfw_boucwen.law import BoucWen

try:
    __version__ = version("bearingfw-boucwen")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = ["BoucWen", "__version__"]
