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


@pytest.fixture(scope="session")
def paper_tune():
    """``bearingfw tune``'s data (step 1 against Table 2, two least squares: ~10 s), computed once for the
    tests of the command's JSON, its table and the K_s it hands to the default study."""
    from bearingfw.cli.tune import tune_data

    return tune_data()


@pytest.fixture
def tune_once(paper_tune, monkeypatch):
    """The command calls :func:`bearingfw.cli.tune.tune_data` as usual; with the default ``--ks-max`` it gets
    a copy of :func:`paper_tune`'s (the same function, the same argument), any other value runs the fit."""
    import copy

    from bearingfw.cli import tune

    real = tune.tune_data
    calls = []

    def shared(ks_max=None):
        calls.append(ks_max)
        return copy.deepcopy(paper_tune) if ks_max is None else real(ks_max)

    monkeypatch.setattr(tune, "tune_data", shared)
    return calls


@pytest.fixture(scope="session")
def unbounded_step1():
    """Step 1's least squares against Table 2 without the paper's bound (:func:`calibrate_ks`, a few
    seconds), computed once for the tests of the calibration and of the bound."""
    from bearingfw.bridges.study import calibrate_ks

    return calibrate_ks()
