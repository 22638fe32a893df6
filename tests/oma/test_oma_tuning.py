"""Identified modes in the tuning: measurements at sensor channels, paired by MAC at exactly those DOFs."""

from __future__ import annotations

import numpy as np
import pytest
from oma_systems import column_model

from bearingfw.analysis import solve_modal
from bearingfw.bridges.study import IdentifiedTuning, channel_warnings, screen_by_mac
from bearingfw.oma import IdentifiedMode, IdentifiedModes, channel_dofs
from bearingfw.parameters import ParameterError
from bearingfw.tuning import MIN_MAC, Measurement, Observation, calibrate, identified_measurements, pair_modes

SENSORS = ("C6.uy", "C3.ux", "C6.ux", "C3.uy", "C5.uy")


@pytest.fixture(scope="module")
def column():
    return solve_modal(column_model(), 8)


def measured(modal, order=(2, 0, 1)) -> IdentifiedModes:
    dofs = channel_dofs(modal.system, SENSORS)
    modes = [IdentifiedMode(modal.frequencies[m] * 1.01, 0.02, modal.shapes[dofs, m]) for m in order]
    return IdentifiedModes(SENSORS, modes)


def test_identified_modes_become_measurements_and_sensors(column):
    ms, sensors = identified_measurements(measured(column))
    assert sensors == SENSORS
    assert [m.name for m in ms] == ["mode 1", "mode 2", "mode 3"]
    assert all(m.shape.size == len(SENSORS) and m.label is None for m in ms)
    picked, _ = identified_measurements(measured(column), select=[3, "mode 1"])
    assert [m.name for m in picked] == ["mode 3", "mode 1"]
    with pytest.raises(ParameterError, match="no identified mode 7"):
        identified_measurements(measured(column), select=[7])


def test_pairing_by_mac_at_the_sensor_channels_in_their_order(column):
    ms, sensors = identified_measurements(measured(column))
    observation = Observation([f"C{k}" for k in range(7)], min_share=0.0, sensors=sensors)
    assert [column.system.dofmap.describe(d) for d in observation.shape_dofs(column.system)] == list(SENSORS)
    pairing = pair_modes(column, ms, by="mac", observation=observation)
    assert list(pairing.modes) == [2, 0, 1]
    np.testing.assert_allclose(pairing.mac, 1.0)
    # the same shapes read in another channel order would not pair
    wrong = Observation([f"C{k}" for k in range(7)], min_share=0.0, sensors=SENSORS[::-1])
    assert np.min(pair_modes(column, ms, by="mac", observation=wrong).mac) < 0.9


def test_calibration_with_sensor_shapes_recovers_a_stiffness(column):
    """The column's identified modes (at 1.01 x the frequencies of E = 210 GPa) give E = 1.0201 x 210 GPa."""
    ms, sensors = identified_measurements(measured(column))
    observation = Observation([f"C{k}" for k in range(7)], min_share=0.0, sensors=sensors)
    report = calibrate(
        lambda e: column_model(modulus=e), ms, {"E": (200e9, 50e9, 500e9)}, by="mac", observation=observation, n_modes=6
    )
    assert report.values["E"] == pytest.approx(210e9 * 1.01**2, rel=1e-4)
    assert report.mac_before_after.shape == (3, 3)


@pytest.mark.parametrize("sensors, message", [(["C6.uy", "C6.uy"], "distinct"), (["C6"], "does not name a DOF")])
def test_bad_sensors_are_named(sensors, message):
    with pytest.raises(ParameterError, match=message):
        Observation(["C6"], sensors=sensors)


# -- pairing by shape: weak pairs, undefined MAC ---------------------------------------------------

OBSERVED = [f"C{k}" for k in range(7)]


def test_weak_pairs_are_named_below_the_least_mac(column):
    ms, sensors = identified_measurements(measured(column))
    spurious = Measurement(2.0, shape=[1.0, -1.0, 1.0, -1.0, 0.0], name="spurious")
    observation = Observation(OBSERVED, min_share=0.0, sensors=sensors)
    pairing = pair_modes(column, (*ms, spurious), by="mac", observation=observation)
    assert pairing.mac[-1] < MIN_MAC <= pairing.mac[:-1].min()
    assert pairing.weak() == ("spurious",) and pairing.weak(0.0) == ()
    assert pair_modes(column, [("lateral 1", 1.0)]).weak() == ()  # by label: no MAC, nothing weak


def test_a_zero_measured_shape_is_an_error_naming_it(column):
    ms, sensors = identified_measurements(measured(column))
    zero = Measurement(2.0, shape=np.zeros(len(sensors)), name="flat")
    with pytest.raises(ParameterError, match="'flat' have a zero shape at every sensor"):
        pair_modes(column, (*ms, zero), by="mac", observation=Observation(OBSERVED, min_share=0.0, sensors=sensors))


def test_sensors_at_a_support_are_an_error_naming_them(column):
    sensors = ("C0.ux", "C6.ux", "C0.uy")
    dofs = channel_dofs(column.system, sensors)
    ms = [Measurement(column.frequencies[m], shape=column.shapes[dofs, m] + [0.1, 0, 0.1]) for m in (0, 1)]
    with pytest.raises(ParameterError, match="C0.ux, C0.uy are at supported DOFs"):
        pair_modes(column, ms, by="mac", observation=Observation(OBSERVED, min_share=0.0, sensors=sensors))


def test_a_computed_mode_still_at_every_sensor_is_no_match(column):
    """Bending in y does not move x sensors: those modes score MAC 0 instead of stopping the pairing."""
    sensors = ("C6.ux", "C3.ux")
    dofs = channel_dofs(column.system, sensors)
    x_mode = int(np.argmax(np.abs(column.shapes[dofs[0]])))
    ms = [Measurement(column.frequencies[x_mode], shape=column.shapes[dofs, x_mode])]
    pairing = pair_modes(column, ms, by="mac", observation=Observation(OBSERVED, min_share=0.0, sensors=sensors))
    assert pairing.modes == (x_mode,) and pairing.mac[0] == pytest.approx(1.0)


def test_the_screening_keeps_modes_that_pair_well_at_some_trial(column):
    ms, sensors = identified_measurements(measured(column))
    spurious = Measurement(2.0, shape=[1.0, -1.0, 1.0, -1.0, 0.0], name="spurious")
    observation = Observation(OBSERVED, min_share=0.0, sensors=sensors)
    pairing = pair_modes(column, (*ms, spurious), by="mac", observation=observation)
    kept, dropped = screen_by_mac((*ms, spurious), [None, pairing], MIN_MAC)
    assert [m.name for m in kept] == ["mode 1", "mode 2", "mode 3"]
    assert dropped == ({"name": "spurious", "frequency": 2.0, "best_mac": pytest.approx(pairing.mac[-1])},)
    assert screen_by_mac((*ms, spurious), [pairing], 0.0)[1] == ()


def test_a_single_channel_is_warned_about():
    assert channel_warnings(["GA20.uz", "GA20.uy"]) == []
    (warning,) = channel_warnings(["GA20.uz"])
    assert "single channel (GA20.uz)" in warning and "every MAC is 1" in warning


@pytest.mark.parametrize("kwargs, message", [({"min_mac": 1.5}, "min_mac"), ({"scan_points": 1}, "scan_points")])
def test_bad_tuning_options_are_named(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        IdentifiedTuning(**kwargs)
