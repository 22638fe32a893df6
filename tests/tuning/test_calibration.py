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
    # at the initial values: "start" (the commands keep "before" for the model before tuning)
    assert {"start", "error_start", "label_start"} <= set(data["modes"][0]) and "before" not in data["modes"][0]
    first = data["modes"][0]
    assert first["error_start"] == pytest.approx(first["start"] / first["measured"] - 1)
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


@pytest.mark.parametrize(
    "bounds",
    [(TRUE["Iy"] / 1.3, 1e-1), (1e-4, TRUE["Iy"] * 1.05)],
    ids=["truth 1.3 x LOW, start at LOW", "truth near HIGH, start at HIGH"],
)
def test_a_start_on_a_bound_still_moves(bounds):
    """A start exactly on a bound (where a scan often ends) must not freeze the fit: a finite-difference
    step relative to a scaled variable near 0 there would vanish, and so would the Jacobian."""
    low, high = bounds
    start = low if TRUE["Iy"] / low < 2 else high
    report = calibrate(lambda Iy: cantilever(Iy=Iy, Iz=TRUE["Iz"]), measured(), {"Iy": (start, low, high)}, n_modes=6)
    assert report.values["Iy"] == pytest.approx(TRUE["Iy"], rel=1e-6)
    assert np.max(np.abs(report.errors_after)) < 1e-6
    assert report.evaluations > 3  # it iterated


def test_every_trial_stays_within_the_bounds():
    """The Jacobian is one-sided at a bound: a builder that refuses values outside [low, high] is never asked."""
    low, high = 2e-3, TRUE["Iy"]  # the truth on the upper bound: the fit ends there

    def build(Iy):
        if not low <= Iy <= high:
            raise AssertionError(f"asked for Iy = {Iy!r} outside [{low}, {high}]")
        return cantilever(Iy=Iy, Iz=TRUE["Iz"])

    report = calibrate(build, measured(), {"Iy": (3e-3, low, high)}, n_modes=6)
    assert report.values["Iy"] == pytest.approx(high, rel=1e-4)
