import os

import pytest
from hypothesis import settings

# CI runs the same examples every time; locally hypothesis explores new ones.
settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")


def pytest_collection_modifyitems(config, items):
    """Long studies (``@pytest.mark.slow``) run only when the marker expression asks for them."""
    if "slow" in (config.getoption("markexpr") or ""):
        return
    skip = pytest.mark.skip(reason="slow study: run with -m slow")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
