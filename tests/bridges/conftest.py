"""Shared, session-cached analyses of the reference bridge (each modal analysis takes a fraction of a second)."""

from __future__ import annotations

import pytest

from bearingfw.bridges import BridgeParameters
from bearingfw.bridges.paper import TABLE2_FE
from bearingfw.bridges.study import deck_observation, modes, paper_measurements


@pytest.fixture(scope="session")
def params():
    return BridgeParameters()


@pytest.fixture(scope="session")
def observation(params):
    return deck_observation(params)


@pytest.fixture(scope="session")
def untuned(params):
    """M0 (frictionless sliding): the modal result and its pairing with Table 2's FE column."""
    return modes("M0", params, paper_measurements(TABLE2_FE))
