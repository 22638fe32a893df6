"""bearingfw: dynamic analysis of bridges whose bearings are interchangeable models."""

from importlib.metadata import PackageNotFoundError, version

from bearingfw.parameters import ParameterError, check_per_bearing, dims_parameter, parameter
from bearingfw.plugins import BearingPreset, PresetBearing, create_law, get_registry, hookimpl
from bearingfw.protocol import BearingLaw, CompiledLaw, LawResponse

try:
    __version__ = version("bearingfw")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = [
    "BearingLaw",
    "BearingPreset",
    "PresetBearing",
    "CompiledLaw",
    "LawResponse",
    "ParameterError",
    "__version__",
    "check_per_bearing",
    "create_law",
    "dims_parameter",
    "get_registry",
    "hookimpl",
    "parameter",
]
