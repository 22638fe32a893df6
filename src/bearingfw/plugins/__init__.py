"""The plugin layer: hook specifications and the registry built from installed plugins."""

from bearingfw.plugins.contracts import BearingPreset, PresetBearing
from bearingfw.plugins.hookspecs import hookimpl, hookspec
from bearingfw.plugins.registry import (
    BrokenPlugin,
    Registry,
    UnknownLawError,
    UnknownPresetError,
    create_law,
    describe_parameters,
    get_registry,
    load_registry,
)

__all__ = [
    "BearingPreset",
    "PresetBearing",
    "BrokenPlugin",
    "Registry",
    "UnknownLawError",
    "UnknownPresetError",
    "create_law",
    "describe_parameters",
    "get_registry",
    "hookimpl",
    "hookspec",
    "load_registry",
]
