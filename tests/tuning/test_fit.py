"""fit_parameters: any named parameters of a model builder against measured modes (by label or by MAC)."""

from __future__ import annotations

import inspect
import json
import math

import numpy as np
import pytest
from models import beam_nodes, cantilever

from bearingfw.analysis import solve_modal
from bearingfw.oma import channel_dofs
from bearingfw.parameters import ParameterError
from bearingfw.tuning import FitOptions, PairingError, fit_parameters, measured_modes

TRUE = {"Iy": 6e-3, "Iz": 0.7e-3}
CHANNELS = ("B3.uz", "B5.uz", "B10.uz", "B5.uy", "B10.uy")


def build(values):
    return cantilever(**{**TRUE, **values})


@pytest.fixture(scope="module")
def truth():
    return solve_modal(cantilever(**TRUE), 8)


def labelled(modal, labels=("vertical 1", "lateral 1", "vertical 2")):
    return measured_modes({"modes": [
        {"frequency": float(modal.frequencies[modal.numbered_labels.index(lab)]), "label": lab} for lab in labels
    ]})


def shaped(modal, order=(2, 0, 1), scale=1.0):
    """Modes with shapes at CHANNELS, given out of frequency order (pairing must not go by index)."""
    dofs = channel_dofs(modal.system, CHANNELS)
    return measured_modes({"channels": list(CHANNELS), "modes": [
        {"frequency": float(modal.frequencies[m]) * scale, "shape": (-2.0 * modal.shapes[dofs, m]).tolist(),
         "damping": 0.02} for m in order
    ]})


def test_by_label_recovers_a_parameter_and_its_closed_form_sensitivity(truth):
    """A cantilever's bending frequencies go as sqrt(E I): d ln f / d ln Iy is 1/2 for the vertical modes
    and 0 for the lateral one (Iy is the vertical bending's), exactly."""
    fit = fit_parameters(build, labelled(truth), {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=6))
    assert fit.by == "label" and fit.sensors is None
    assert fit.values["Iy"] == pytest.approx(TRUE["Iy"], rel=1e-5)
    np.testing.assert_allclose(fit.sensitivity[:, 0], [0.5, 0.0, 0.5], atol=1e-9)
    data = json.loads(json.dumps(fit.to_dict()))
    assert data["pairing"] == "label" and data["mac"] is None
    assert [m["label_after"] for m in data["modes"]] == ["vertical 1", "lateral 1", "vertical 2"]
    # before: at the start, Iy = 3e-3 = TRUE / 2: the vertical frequencies are sqrt(1/2) of the measured
    assert data["error_before"]["vertical 1"] == pytest.approx(math.sqrt(0.5) - 1, rel=1e-6)
    assert data["parameters"]["Iy"]["start"] == 3e-3 and data["parameters"]["Iy"]["scale"] == "log"
    assert abs(data["error_after"]["vertical 2"]) < 1e-6 and data["warnings"] == []


def test_two_parameters_by_mac_with_modes_out_of_order(truth):
    fit = fit_parameters(build, shaped(truth), {"Iy": (3e-3, 1e-4, 1e-1), "Iz": (2e-3, 1e-4, 1e-1)},
                         FitOptions(n_modes=6, scan_points=5))
    assert fit.by == "mac" and fit.sensors == CHANNELS
    for name, value in TRUE.items():
        assert fit.values[name] == pytest.approx(value, rel=1e-5)
    assert list(fit.report.after.modes) == [2, 0, 1]  # the given order, paired by shape
    np.testing.assert_allclose(np.diag(fit.mac_table), 1.0, rtol=1e-9)
    # given: lateral 2, lateral 1, vertical 1. Lateral and vertical move in perpendicular planes: MAC 0;
    # two lateral bending modes are orthogonal through the mass, not at five channels
    assert [truth.numbered_labels[m] for m in fit.report.after.modes] == ["lateral 2", "lateral 1", "vertical 1"]
    assert fit.mac_table[0, 2] == pytest.approx(0.0, abs=1e-12)
    assert fit.mac_table[0, 1] > 0.01
    np.testing.assert_allclose(fit.sensitivity, [[0.0, 0.5], [0.0, 0.5], [0.5, 0.0]], atol=1e-9)
    assert fit.to_dict()["modes"][0]["damping"] == 0.02
    assert len(fit.scan) == 10  # five values of each variable, the other at its start


def test_a_spurious_mode_is_left_out_and_named(truth):
    base = shaped(truth).measurements
    data = {"channels": list(CHANNELS), "modes": [
        {"frequency": m.frequency, "shape": m.shape.tolist()} for m in base
    ] + [{"name": "noise", "frequency": 7.0, "shape": [1.0, -1.0, 1.0, 1.0, -1.0]}]}
    fit = fit_parameters(build, measured_modes(data), {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=6))
    assert [d["name"] for d in fit.dropped] == ["noise"] and len(fit.used) == 3
    assert any("left out" in w and "noise" in w for w in fit.warnings)
    assert fit.values["Iy"] == pytest.approx(TRUE["Iy"], rel=1e-5)


def test_a_parameter_no_mode_depends_on_and_a_bound_are_warned(truth):
    vertical = labelled(truth, ("vertical 1", "vertical 2"))
    fit = fit_parameters(build, vertical, {"Iz": (1e-3, 1e-4, 1e-2)}, FitOptions(n_modes=6, scan_points=3))
    assert any("no measured mode is sensitive to Iz" in w for w in fit.warnings)
    fit = fit_parameters(build, vertical, {"Iy": (2e-3, 1e-3, 3e-3)}, FitOptions(n_modes=6, scan_points=3))
    assert fit.values["Iy"] == pytest.approx(3e-3)
    assert any("ends at a bound" in w for w in fit.warnings)


def test_a_channel_the_model_lacks_is_named_with_near_matches(truth):
    data = {"modes": [{"frequency": 1.0, "shape": {"B5.uz": 1.0, "B55.uz": 0.5}}]}
    with pytest.raises(ParameterError, match=r"channel 'B55.uz'.*no node 'B55'.*near matches: B5.uz"):
        fit_parameters(build, measured_modes(data), {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=4))


def test_a_label_without_a_computed_mode_says_so(truth):
    data = {"modes": [{"frequency": 30.0, "label": "torsional 3"}]}
    with pytest.raises(PairingError, match="no computed mode labelled torsional 3"):
        fit_parameters(build, measured_modes(data), {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=4))


def test_nothing_pairs_well_enough(truth):
    data = {"modes": [{"frequency": 5.0, "shape": {"B5.uz": 1.0, "B10.uz": -1.0, "B5.uy": 1.0, "B10.uy": 1.0}}]}
    with pytest.raises(ParameterError, match="no measured mode pairs"):
        fit_parameters(build, measured_modes(data), {"Iy": (3e-3, 1e-4, 1e-1)},
                       FitOptions(n_modes=4, scan_points=0, min_mac=0.99))


@pytest.mark.parametrize("field, value", [("min_mac", 1.5), ("scan_points", -1), ("n_modes", 0),
                                          ("sensitivity_step", 0.0)])
def test_options_are_checked(field, value):
    with pytest.raises(ParameterError, match=field):
        FitOptions(**{field: value})


def test_beam_nodes_are_the_channels_nodes():
    assert {c.partition(".")[0] for c in CHANNELS} <= set(beam_nodes())


def test_a_scan_that_ends_on_a_bound_still_moves(truth):
    """Truth 1.3 x LOW: the scan's best point is LOW itself, where the least squares must still move."""
    low = TRUE["Iy"] / 1.3
    fit = fit_parameters(build, labelled(truth), {"Iy": (1e-2, low, 1.0)}, FitOptions(n_modes=8))
    assert fit.scan_start["Iy"] == low
    assert fit.values["Iy"] == pytest.approx(TRUE["Iy"], rel=1e-6)
    assert not any("bound" in w for w in fit.warnings)


def test_sensitivities_at_a_bound_are_one_sided_and_stay_within_it(truth):
    """The fit ends on HIGH (the truth); the sensitivity step must not leave [LOW, HIGH], and a one-sided
    difference still gives the closed form d ln f / d ln Iy = 1/2 (f goes as sqrt(Iy) exactly)."""
    low, high = 2e-3, TRUE["Iy"]

    def bounded(values):
        if not low <= values["Iy"] <= high:
            raise ParameterError(f"Iy = {values['Iy']!r} is outside [{low}, {high}]")
        return build(values)

    fit = fit_parameters(bounded, labelled(truth), {"Iy": (3e-3, low, high)}, FitOptions(n_modes=6, scan_points=3))
    np.testing.assert_allclose(fit.sensitivity[:, 0], [0.5, 0.0, 0.5], atol=1e-9)


def test_a_refused_trial_value_is_named_with_its_trial(truth):
    def picky(values):
        if values["Iy"] < 2e-3:
            raise ParameterError("the girder is too slender")
        return build(values)

    describe = "--param {}".format
    with pytest.raises(ParameterError, match=r"^--param Iy = 0.001 \(LOW\): the girder is too slender$"):
        fit_parameters(picky, labelled(truth), {"Iy": (3e-3, 1e-3, 1e-1)}, FitOptions(n_modes=6), describe=describe)
    with pytest.raises(ParameterError, match=r"^--param Iy = 0.0015 \(START\): the girder is too slender$"):
        fit_parameters(picky, labelled(truth), {"Iy": (1.5e-3, 1e-3, 1e-1)}, FitOptions(n_modes=6), describe=describe)

    def gap(values):  # refuses a band inside the bounds, where the scan's second point falls (1e-3)
        if 5e-4 < values["Iy"] < 2e-3:
            raise ParameterError("no such section")
        return build(values)

    with pytest.raises(ParameterError, match=r"^Iy = 0.001 \(a scan point\): no such section$"):
        fit_parameters(gap, labelled(truth), {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=6, scan_points=4))


def test_frequencies_in_rad_per_second_are_warned_about(truth):
    """2 pi times the frequencies: no Iy within bounds matches, and the lateral mode does not depend on Iy."""
    data = labelled(truth)
    radians = measured_modes({"modes": [{"frequency": 2 * math.pi * m.frequency, "label": m.label}
                                        for m in data.measurements]})
    fit = fit_parameters(build, radians, {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=6, scan_points=3))
    (warning,) = [w for w in fit.warnings if "rad/s" in w]
    assert "lateral 1 is still -84.1% off" in warning and "in Hz" in warning


def test_json_before_is_at_the_start_everywhere(truth):
    """'before' means at START in every part of the JSON; the least squares' own start is 'calibration.from'."""
    fit = fit_parameters(build, labelled(truth), {"Iy": (3e-3, 1e-4, 1e-1)}, FitOptions(n_modes=6))
    data = json.loads(json.dumps(fit.to_dict()))
    assert data["parameters"]["Iy"]["start"] == 3e-3 != data["parameters"]["Iy"]["scan_start"]
    assert data["calibration"]["from"] == {"Iy": data["parameters"]["Iy"]["scan_start"]}
    assert "modes" not in data["calibration"] and "variables" not in data["calibration"]
    before_at_start = solve_modal(build({"Iy": 3e-3}), 6)
    for mode in data["modes"]:
        assert data["before"][mode["name"]] == mode["before"]
        at_start = before_at_start.numbered_labels.index(mode["label_before"])
        assert mode["before"] == pytest.approx(before_at_start.frequencies[at_start], rel=1e-12)


def test_the_reference_studys_fit_is_this_one():
    """bearingfw.bridges.study's fit of K_s to identified modes screens, scans and warns with tuning's code."""
    import bearingfw.tuning as tuning
    from bearingfw.bridges import study

    assert study.screen_by_mac is tuning.screen_by_mac and study.channel_warnings is tuning.channel_warnings
    assert "fit_parameters(" in inspect.getsource(study.calibrate_ks_to_identified)
