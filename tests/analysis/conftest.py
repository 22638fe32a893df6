"""Fixtures of the kernel tests: a registry with laws from a test plugin."""

from __future__ import annotations

import pytest
from kernel_models import DoubledSpring, FreeSliding2D, GuidedOnly, NormalSpring, registry_with


@pytest.fixture
def plugin_registry():
    """The installed plugins plus a test plugin module registering four extra laws."""
    laws = [DoubledSpring, GuidedOnly, FreeSliding2D, NormalSpring]
    with registry_with(laws, "kernel-test-laws", "bearingfw_kernel_test_plugin") as registry:
        assert not [b for b in registry.broken if b.plugin == "kernel-test-laws"], registry.broken
        yield registry
