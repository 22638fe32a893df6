"""The parametric frame of validation/_multispan.py (the models validation/models.py and
benchmarks/opensees.py compare with OpenSees). No OpenSees needed."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "validation"))

import _multispan  # noqa: E402

from bearingfw.analysis import gravity  # noqa: E402


def test_bearing_layout_has_fixed_guided_and_free_bearings():
    frame = _multispan.Frame(spans=(20.0, 30.0, 20.0), lines=2)
    model = _multispan.frame_model(frame)
    kinds = {c.name: (c.kind.value, c.guided) for c in model.connectors}
    assert len(kinds) == frame.axes * frame.lines
    assert kinds["B2.0"] == ("join", None)  # the middle axis holds the deck
    assert kinds["B2.1"] == ("axial", "y")
    assert kinds["B0.0"] == ("axial", "x")
    assert kinds["B0.1"] == ("planar", None)
    assert _multispan.sliding_bearings(model) == [n for n, (kind, _) in kinds.items() if kind != "join"]


def test_dead_load_moves_no_bearing_on_the_girder_axis():
    """The premise of comparing bearings set after the dead load (bearingfw's default) with
    OpenSees's bearings acting under gravity: without offsets they see no dead-load displacement."""
    preload = gravity(_multispan.frame_model(_multispan.Frame(per_span=4)))
    assert np.abs(preload.law_reference).max() < 1e-12
    assert np.all(preload.normal_forces[[c.law_directions != () for c in preload.system.model.connectors]] > 0)


@pytest.mark.parametrize("spans, per_span", [((1.0, 1.0), 100), ((3.0, 3.0), 150)])
def test_gravity_with_bearings_set_after_the_dead_load_converges_on_a_very_fine_mesh(spans, per_span):
    """1-2 cm elements make |K| |q| so large that the residual's round-off exceeded tol * load:
    the preload reported a load "along motions only the bearings restrain" (a false mechanism)."""
    model = _multispan.frame_model(_multispan.Frame(spans=spans, per_span=per_span, pier_elements=1))
    preload = gravity(model)
    assert preload.iterations <= 5
    residual = preload.system.K_free @ preload.q - preload.system.reduce(preload.load)
    assert np.abs(residual).max() < 1e-6 * np.abs(preload.load).sum()
