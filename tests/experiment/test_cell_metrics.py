"""The definitions of the stress metrics and of the friction ratio (the built-in metric families), on
made-up histories."""

from __future__ import annotations

import math

import numpy as np
import pytest
from tiny_experiment import EXAMPLE

from bearingfw.experiment.metrics import (
    MIN_NORMAL_FRACTION,
    CellResponse,
    friction_ratio,
    metric_families,
)

STRESS = ("stress", "stress_dynamic", "stress_increase")


@pytest.fixture(scope="module")
def model():
    import sys

    sys.path.insert(0, str(EXAMPLE))
    try:
        from small_bridge import build
    finally:
        sys.path.remove(str(EXAMPLE))
    return build(elements_per_span=4)


T = np.linspace(0.0, 2.0, 201)
#: Section forces N Vy Vz T My Mz: a dead load (a prestressed girder: every point compressed, some shear
#: and moment) and a tremor's pattern (which turns some points to tension).
DEAD = np.array([-8.0e6, 0.0, 5.0e5, 0.0, 1.0e6, 0.0])
TREMOR = np.sin(2 * np.pi * 1.7 * T)[:, None] * np.array([1.0e5, 4.0e4, 6.0e4, 2.0e3, 1.5e6, 9.0e5])


def _stress_metrics(model, dead, tremor) -> dict:
    forces = (dead + tremor)[:, None, None, :].repeat(2, axis=2)  # (t, 1 element, 2 ends, 6)
    forces[0] = dead  # sample 0 is the dead-load state
    response = CellResponse({"sections": forces, "sections.time": T}, model, ("G2",))
    families = metric_families()
    out = {}
    for family in STRESS:
        peaks = families[family].reduce(response)
        assert set(peaks) == {"G2"} and peaks["G2"].history.shape == T.shape  # the maximum over points, per step
        out[family] = peaks["G2"].value
    return out


def test_the_dynamic_stress_is_the_tremors_own_stress_state(model):
    one = _stress_metrics(model, DEAD, TREMOR)
    three = _stress_metrics(model, DEAD, 3 * TREMOR)
    # positively homogeneous: a linear model's value scales exactly with the record ...
    assert three["stress_dynamic"] == pytest.approx(3 * one["stress_dynamic"], rel=1e-12)
    # ... whatever the dead load (it is the tremor's stress state alone) ...
    assert _stress_metrics(model, 0.3 * DEAD, TREMOR)["stress_dynamic"] == pytest.approx(one["stress_dynamic"],
                                                                                          rel=1e-12)
    # ... while the rise of the total principal stress is neither proportional nor independent of it
    assert three["stress_increase"] > 1.1 * 3 * one["stress_increase"]
    assert _stress_metrics(model, 0.3 * DEAD, TREMOR)["stress_increase"] > 1.1 * one["stress_increase"]
    for values in (one, three):  # sigma1 is subadditive and >= 0
        assert 0 < values["stress_increase"] <= values["stress_dynamic"]
        assert values["stress_increase"] <= values["stress"]


def test_without_dead_load_the_three_stresses_agree(model):
    values = _stress_metrics(model, np.zeros(6), TREMOR)
    assert values["stress"] == values["stress_dynamic"] == values["stress_increase"] > 0


def test_the_friction_ratio_leaves_out_the_instants_near_uplift():
    normal = np.array([[1.0e6, 0.0], [1.0e6, 0.0], [0.5e5, 0.0], [2.0e5, 0.0], [0.0, 0.0], [-1.0e3, 0.0]])
    ratio = np.array([[0.0, 0.1], [0.03, 0.1], [0.9, 0.1], [0.05, 0.1], [np.nan, 0.1], [np.nan, 0.1]])
    masked = friction_ratio(ratio, normal)
    np.testing.assert_array_equal(masked[:, 0], [0.0, 0.03, np.nan, 0.05, np.nan, np.nan])
    assert np.isnan(masked[:, 1]).all()  # no dead load on it: never defined
    assert MIN_NORMAL_FRACTION == 0.1
    at_the_limit = friction_ratio(np.array([[0.0], [0.5]]), np.array([[1.0e6], [1.0e5]]))
    assert np.isnan(at_the_limit[1, 0])  # defined only *above* 10 % of the dead load


def test_the_friction_ratio_metric_and_history_of_a_bearing_that_lifts_off(model):
    """Bearing 1B's normal force dips to 5 % of its dead load while abs(F)/N spikes to 0.9: the metric is the
    largest ratio while it is pressed (0.05), and the history is NaN at the dip."""
    names = [c.name for c in model.connectors]
    n = len(T)
    c1b, c3b = names.index("1B"), names.index("3B")
    normal = np.full((n, len(names)), 1.0e6)
    normal[100, c1b] = 0.05e6
    normal[:, c3b] = 0.0
    ratio = np.full((n, len(names)), 0.02)
    ratio[100, c1b] = 0.9
    ratio[150, c1b] = 0.05
    result = {
        "bearings.time": T, "bearings.force": np.zeros((n, len(names), 3)),
        "bearings.displacement": np.zeros((n, len(names), 3)), "bearings.slip": np.full((n, len(names), 3), np.nan),
        "bearings.normal_force": normal, "bearings.friction_ratio": ratio,
    }
    response = CellResponse(result, model)
    peaks = metric_families()["friction_ratio"].reduce(response)
    histories = response.histories()
    assert peaks["1B"].value == 0.05 and peaks["1B"].time == T[150]
    assert math.isnan(peaks["3B"].value)
    assert peaks["1A"].value == 0.02
    assert np.isnan(histories["bearings.friction_ratio"][100, c1b])
    assert histories["bearings.friction_ratio"][150, c1b] == 0.05
