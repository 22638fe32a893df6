"""The plugin layer: hook specifications and the registry built from installed plugins."""

from bearingfw.plugins.hookspecs import hookimpl, hookspec
from bearingfw.plugins.registry import (
    BrokenPlugin,
    Registry,
    UnknownLawError,
    create_law,
    describe_parameters,
    get_registry,
    load_registry,
)

__all__ = [
    "BrokenPlugin",
    "Registry",
    "UnknownLawError",
    "create_law",
    "describe_parameters",
    "get_registry",
    "hookimpl",
    "hookspec",
    "load_registry",
]
