"""Fixtures of the experiment tests; the tiny experiment itself is in tiny_experiment.py."""

import pytest
from tiny_experiment import write_tiny


@pytest.fixture
def tiny(tmp_path):
    """The tiny experiment file (M0, M1, M2 x D_0, D_II, no figures) in a fresh folder."""
    return write_tiny(tmp_path / "spec")
