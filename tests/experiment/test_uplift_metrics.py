"""The uplift metric families (lift_offs, uplift_time, uplift_gap) against the kernel's own uplift summary."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingfw.analysis import TransientSettings, gravity, solve_transient
from bearingfw.experiment.metrics import CellResponse, metric_families, recorders
from bearingfw.experiment.uplift import UPLIFT_FAMILIES
from bearingfw.model import Connector, Model, NodalMass, Node, Support

MASS, KV, G, DT = 1000.0, 1e7, 9.81, 1e-4


def two_bearings() -> Model:
    """A mass on a compression-only bearing 'lifts' beside a mass on an ordinary one 'pulls'."""
    def bearing(name, i, j, uplift):
        return Connector(name, i, j, "axial", law="linear-spring", law_params={"k": 1e6}, vertical_stiffness=KV,
                         uplift=uplift)

    nodes = [Node("g1", 0, 0, 0), Node("m1", 0, 0, 0), Node("g2", 5, 0, 0), Node("m2", 5, 0, 0)]
    return Model(nodes, connectors=[bearing("lifts", "g1", "m1", True), bearing("pulls", "g2", "m2", False)],
                 supports=[Support("g1"), Support("g2")], masses=[NodalMass("m1", MASS), NodalMass("m2", MASS)])


@pytest.fixture(scope="module")
def thrown():
    """Both masses pulled up with 2 m g for 50 ms: the uplift bearing lifts twice, the other one pulls."""
    model = two_bearings()
    pre = gravity(model)
    n = int(round(0.4 / DT)) + 1
    t = DT * np.arange(n)
    loads = np.zeros((n, pre.system.n_dof))
    for node in ("m1", "m2"):
        loads[t <= 0.05 + 1e-12, pre.system.dofmap.dof(node, "uz")] = 2 * MASS * G
    result = solve_transient(pre.system, np.zeros((n, 3)), DT, preload=pre, nodal_loads=loads,
                             recorders=recorders((), (), model), settings=TransientSettings(alpha=0.0))
    return model, result


def test_the_families_count_time_and_peak_of_the_lift_offs(thrown):
    model, result = thrown
    response = CellResponse(result, model)
    peaks = {f.name: f.reduce(response) for f in UPLIFT_FAMILIES}
    summary = result.uplift["lifts"]
    assert summary["lift_offs"] == 2
    assert peaks["lift_offs"]["lifts"].value == 2
    # the families count whole steps; the kernel's summary interpolates the opening within a step
    assert peaks["uplift_time"]["lifts"].value == pytest.approx(summary["lifted_time"], abs=2 * DT)
    assert peaks["uplift_gap"]["lifts"].value == pytest.approx(summary["peak_gap"], rel=1e-12)
    assert peaks["uplift_gap"]["lifts"].value > 1e-3
    # the ordinary bearing cannot lift: "does not apply", not zero - and it did pull (tension)
    for family in peaks.values():
        assert math.isnan(family["pulls"].value)
    assert np.min(result["bearings.normal_force"][:, 1]) < 0.0
    assert np.min(result["bearings.normal_force"][:, 0]) >= 0.0


def test_a_model_without_uplift_bearings_has_no_uplift_metrics():
    model = Model([Node("g", 0, 0, 0), Node("m", 0, 0, 0)],
                  connectors=[Connector("b", "g", "m", "axial", law="linear-spring", law_params={"k": 1e6},
                                        vertical_stiffness=KV)],
                  supports=[Support("g")], masses=[NodalMass("m", MASS)])
    result = solve_transient(model, np.zeros((11, 3)), 0.01, recorders=recorders((), (), model))
    response = CellResponse(result, model)
    assert all(math.isnan(f.reduce(response)["b"].value) for f in UPLIFT_FAMILIES)


def test_the_uplift_families_are_registered():
    assert {"lift_offs", "uplift_time", "uplift_gap"} <= set(metric_families())
