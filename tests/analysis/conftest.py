"""Fixtures of the kernel tests: a registry with a law from a test plugin."""

from __future__ import annotations

import importlib.metadata as metadata
import sys
import types

import pytest
from kernel_models import DoubledSpring, FreeSliding2D, GuidedOnly, NormalSpring

import bearingfw
from bearingfw.plugins import load_registry


@pytest.fixture
def plugin_registry(monkeypatch):
    """The installed plugins plus a test plugin module registering four extra laws."""
    module = types.ModuleType("bearingfw_kernel_test_plugin")

    @bearingfw.hookimpl
    def bearingfw_register_laws():
        return [DoubledSpring, GuidedOnly, FreeSliding2D, NormalSpring]

    module.bearingfw_register_laws = bearingfw_register_laws
    monkeypatch.setitem(sys.modules, module.__name__, module)
    eps = list(metadata.entry_points(group="bearingfw"))
    eps.append(metadata.EntryPoint(name="kernel-test-laws", value=module.__name__, group="bearingfw"))
    registry = load_registry(eps)
    assert not [b for b in registry.broken if b.plugin == "kernel-test-laws"], registry.broken
    return registry
