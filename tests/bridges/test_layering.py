"""Layering of the bridge and tuning packages, and the calibrated defaults' consistency."""

from __future__ import annotations

from pathlib import Path

import attrs
import pytest
from import_graph import imported_modules as imports

import bearingfw
from bearingfw.bridges import CALIBRATED, BridgeParameters
from bearingfw.bridges.calibrate_defaults import fit_defaults

ROOT = Path(bearingfw.__file__).parent
NEVER = ("bearingfw.motion", "bearingfw.experiment", "bearingfw.cli")
#: The two bridge modules that join the model with the tuning method.
GLUE = {"study.py", "calibrate_defaults.py"}


@pytest.mark.parametrize("package", ["bridges", "tuning"])
def test_no_higher_layer_is_imported(package):
    for path in sorted((ROOT / package).glob("*.py")):
        for name in imports(path):
            assert not name.startswith(NEVER), f"{package}/{path.name} imports {name}"


def test_tuning_does_not_know_the_bridge_and_the_bridge_only_in_its_glue():
    for path in (ROOT / "tuning").glob("*.py"):
        assert not any(n.startswith("bearingfw.bridges") for n in imports(path)), path.name
    for path in (ROOT / "bridges").glob("*.py"):
        if path.name not in GLUE:
            assert not any(n.startswith("bearingfw.tuning") for n in imports(path)), path.name


def test_the_calibrated_defaults_are_the_fit_of_table_2():
    """Re-running the offline fit from the defaults leaves them where they are (to the rounding)."""
    fitted = fit_defaults(BridgeParameters(), rounds=1, log=lambda *_: None)
    defaults = BridgeParameters()
    for name in CALIBRATED:
        assert getattr(fitted, name) == pytest.approx(getattr(defaults, name), rel=3e-3), name
    assert attrs.evolve(defaults, **{n: getattr(fitted, n) for n in CALIBRATED})
