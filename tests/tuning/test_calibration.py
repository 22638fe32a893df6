"""Least-squares calibration of any model parameter against measured frequencies."""

from __future__ import annotations

import json

import numpy as np
import pytest
from models import cantilever

from bearingfw.analysis import solve_modal
from bearingfw.parameters import ParameterError
from bearingfw.tuning import calibrate

TRUE = {"Iy": 6e-3, "Iz": 0.7e-3}


def measured(n=3):
    modal = solve_modal(cantilever(**TRUE), 8)
    return [(label, modal.frequencies[modal.numbered_labels.index(label)]) for label in
            ("vertical 1", "lateral 1", "vertical 2")[:n]]


def test_one_variable_gets_the_value_and_is_recovered():
    seen = []

    def build(Iy):
        seen.append(Iy)
        return cantilever(Iy=Iy, Iz=TRUE["Iz"])

    report = calibrate(build, measured(), {"Iy": (3e-3, 1e-4, 1e-1)}, n_modes=6)
    assert all(isinstance(v, float) for v in seen)
    assert report.values["Iy"] == pytest.approx(TRUE["Iy"], rel=1e-4)
    assert np.max(np.abs(report.errors_after)) < 1e-5
    assert np.max(np.abs(report.errors_before)) > 0.1


def test_two_variables_get_a_dict_and_are_recovered():
    report = calibrate(lambda v: cantilever(**v), measured(), {"Iy": (3e-3, 1e-4, 1e-1), "Iz": (2e-3, 1e-4, 1e-1)},
                       n_modes=6)
    for name, value in TRUE.items():
        assert report.values[name] == pytest.approx(value, rel=1e-4)


def test_report_tables_and_json():
    report = calibrate(lambda Iy: cantilever(Iy=Iy, Iz=TRUE["Iz"]), measured(), {"Iy": (3e-3, 1e-4, 1e-1)}, n_modes=6)
    data = json.loads(json.dumps(report.to_dict()))
    assert [m["name"] for m in data["modes"]] == ["vertical 1", "lateral 1", "vertical 2"]
    assert data["variables"]["Iy"]["initial"] == 3e-3
    # a uniform bending stiffness leaves the shapes as they were: MAC 1 on the diagonal; the
    # vertical and lateral modes move in perpendicular planes: MAC 0 between them
    np.testing.assert_allclose(np.diag(report.mac_before_after), 1.0, rtol=1e-9)
    np.testing.assert_allclose(report.automac_after[[0, 1, 2, 1], [1, 0, 1, 2]], 0.0, atol=1e-12)


@pytest.mark.parametrize(
    "variables, message",
    [({}, "at least one"), ({"Iy": (1.0, 2.0, 3.0)}, "low <= initial"), ({"Iy": (1.0,)}, "initial, low, high")],
)
def test_bad_variables_are_named(variables, message):
    with pytest.raises(ParameterError, match=message):
        calibrate(lambda v: cantilever(), measured(1), variables)


def test_build_must_return_a_model():
    with pytest.raises(ParameterError, match="Model"):
        calibrate(lambda v: "not a model", measured(1), {"Iy": (3e-3, 1e-4, 1e-1)})
