"""Pairing computed modes with measurements: by label, by MAC, and only where the sensors are."""

from __future__ import annotations

import numpy as np
import pytest
from models import beam_nodes, cantilever

from bearingfw.analysis import solve_modal
from bearingfw.parameters import ParameterError
from bearingfw.tuning import Measurement, Observation, PairingError, as_measurements, observed_modes, pair_modes


@pytest.fixture(scope="module")
def beam():
    return solve_modal(cantilever(), 8)


@pytest.fixture(scope="module")
def beam_and_mast():
    return solve_modal(cantilever(mast=True), 12)


def test_label_pairing_takes_the_kth_mode_of_that_label(beam):
    labels = beam.numbered_labels
    pairing = pair_modes(beam, [("lateral 2", 1.0), ("vertical 1", 1.0), ("lateral 1", 1.0)])
    assert [labels[m] for m in pairing.modes] == ["lateral 2", "vertical 1", "lateral 1"]
    np.testing.assert_allclose(pairing.frequencies, beam.frequencies[list(pairing.modes)])
    np.testing.assert_allclose(pairing.errors, pairing.frequencies - 1.0)


def test_mac_pairing_finds_shuffled_modes(beam):
    order = np.array([3, 0, 5, 1, 4, 2])
    measured = [Measurement(1.0 + k, shape=beam.shapes[:, m]) for k, m in enumerate(order)]
    pairing = pair_modes(beam, measured, by="mac")
    assert list(pairing.modes) == list(order)
    np.testing.assert_allclose(pairing.mac, 1.0)


def test_mac_pairing_at_sensor_dofs_with_noise(beam):
    obs = Observation(beam_nodes()[::2], components=("uy", "uz"), min_share=0.0)
    dofs = obs.dofs(beam.system)
    rng = np.random.default_rng(1)
    order = [2, 0, 1, 3]
    shapes = [beam.shapes[dofs, m] * (1 + 0.05 * rng.standard_normal(dofs.size)) for m in order]
    pairing = pair_modes(beam, [(s, 1.0) for s in shapes], by="mac", observation=obs)
    assert list(pairing.modes) == order
    assert np.all(pairing.mac > 0.9)


def test_modes_the_sensors_do_not_see_are_left_out(beam_and_mast):
    """The mast's own modes are lateral too; seen from the beam they do not count."""
    everything = beam_and_mast.numbered_labels
    obs = Observation(beam_nodes(), min_share=0.5)
    seen = observed_modes(beam_and_mast, obs)
    mast_modes = np.flatnonzero(seen.share < 1e-6)
    assert mast_modes.size >= 2  # the mast sways first, at lower frequency than the beam
    first_beam_lateral = pair_modes(beam_and_mast, [("lateral 1", 1.0)], observation=obs).modes[0]
    assert first_beam_lateral not in mast_modes
    assert everything.index("lateral 1") in mast_modes  # by the global labels the mast would win


def test_missing_label_is_a_pairing_error_that_lists_what_there_is(beam):
    with pytest.raises(PairingError, match=r"torsional 3.*they are: .*vertical 1") as info:
        pair_modes(beam, [("torsional 3", 5.0)])
    assert "observation" not in str(info.value) and "eligible" not in str(info.value)  # no internal words


def test_two_measurements_with_one_label_are_refused(beam):
    """Both would pair with the same computed mode (the second one's frequency fitted to the first's)."""
    with pytest.raises(ParameterError, match="two measured modes have the label 'vertical 1'"):
        pair_modes(beam, [Measurement(2.5, label="vertical 1", name="a"), Measurement(2.6, label="vertical 1",
                                                                                        name="b")])


@pytest.mark.parametrize(
    "item, message",
    [
        (("sideways 1", 1.0), "label"),
        (("vertical 0", 1.0), "label"),
        (("vertical 1", -1.0), "frequency"),
        ((None, 1.0), "label"),
    ],
)
def test_bad_measurements_are_named(item, message):
    with pytest.raises(ParameterError, match=message):
        as_measurements([item])


def test_pairing_options_are_checked(beam):
    with pytest.raises(ParameterError, match="'by'"):
        pair_modes(beam, [("vertical 1", 1.0)], by="index")
    with pytest.raises(ParameterError, match="shape"):
        pair_modes(beam, [("vertical 1", 1.0)], by="mac")
    with pytest.raises(ParameterError, match="components"):
        pair_modes(beam, [(np.ones(3), 1.0)], by="mac")
