"""What ``[output] table`` may name: a family's items are those of the response it reads (elements,
connectors, deck directions) unless the family has its own (``MetricFamily.items``): the support
motion's ``differential_displacement`` is measured in the directions x, y, z, not per bearing."""

from __future__ import annotations

import math

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, load_experiment, run_experiment
from bearingfw.experiment.metrics import metric_families
from bearingfw.experiment.runner import check_experiment, family_items
from bearingfw.experiment.spec import SpecError

WAVE = """
[records.wave]
seed = 1
tremor = { duration = 10.0, dt = 0.01, decay = 2.0 }
spatial = { apparent_velocity = 480.0, baseline = "none" }

[intensities]"""


def _spec(folder, table: str):
    return write_tiny(folder, models=("M2",), levels=("D_II",), **{
        "[records.tremor]\nseed = 1\ntremor = { duration = 10.0, dt = 0.01, decay = 2.0 }\n\n[intensities]": WAVE,
        'table = ["stress.G4", "stress_dynamic.G4", "bearing_force.1B", "friction_ratio.1B", "deck_acceleration.y"]':
            f"table = {table}"})


def test_a_family_with_its_own_items_lists_them_whatever_the_structure_records():
    items = family_items(metric_families(), ["G4"], [], ["1A", "1B"])
    assert items["differential_displacement"] == ("x", "y", "z")
    assert items["quasi_static_share"] == ("1A", "1B")  # per bearing, as the response it reads
    assert items["deck_acceleration"] == ()  # no deck nodes recorded: nothing


def test_an_unknown_item_of_such_a_family_names_the_items_it_has(tmp_path):
    experiment = load_experiment(_spec(tmp_path, '["differential_displacement.1B"]'))
    with pytest.raises(SpecError, match=r"'1B' is not recorded; differential_displacement has x, y, z"):
        check_experiment(experiment)


def test_the_support_motion_metrics_can_be_tabled_and_are_measured(tmp_path):
    spec = _spec(tmp_path, '["differential_displacement.x", "quasi_static_share.3B", "bearing_force.3B"]')
    result = run_experiment(load_experiment(spec), tmp_path / "out", SerialExecutor())
    assert not result.failed
    m = result.matrices
    # a wave at 480 m/s over the 48 m girder: the abutments 0.1 s apart, so they move differently
    moved = m.value("differential_displacement.x", "M2", "D_II")
    assert math.isfinite(moved) and moved > 1e-5
    share = m.value("quasi_static_share.3B", "M2", "D_II")
    assert math.isfinite(share) and share > 0.0
