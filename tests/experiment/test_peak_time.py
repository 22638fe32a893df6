"""The time a peak metric reports is the first instant the peak is reached, also on a plateau.

A force that saturates (friction at mu N, Bouc-Wen at its yield level) is at its peak over a
plateau whose samples differ in the last bits: which of them is largest is decided by round-off,
so reporting that sample's time made the time jump by seconds between two runs that agree to
1e-12 (the default study's Bouc-Wen bearing 1B, D_IV: 2.1 s or 3.765 s).
"""

import math

import numpy as np

from bearingfw.experiment.metrics import PLATEAU, _peak

TIME = np.arange(8) * 0.5


def test_a_single_peak_reports_its_own_instant():
    values = np.array([0.0, 1.0, 3.0, 2.0, 5.0, 4.0, 1.0, 0.0])
    assert _peak(values, TIME) == (5.0, 2.0, (4,))


def test_a_plateau_reports_its_first_instant_whatever_the_round_off():
    plateau = 7.0e4
    for noisy_sample in range(3, 7):
        values = np.array([0.0, 1e4, 5e4, plateau, plateau, plateau, plateau, 2e4])
        values[noisy_sample] = plateau * (1 + 4 * np.finfo(float).eps)  # the largest by a few ulps
        value, t, where = _peak(values, TIME)
        assert value == values[noisy_sample]  # the value is the true maximum
        assert (t, where) == (1.5, (3,))  # the instant is the plateau's first


def test_a_value_below_the_plateau_band_is_not_the_peak():
    values = np.array([1.0 - 10 * PLATEAU, 0.5, 1.0])
    assert _peak(values, TIME[:3]) == (1.0, 1.0, (2,))


def test_negative_peaks_nan_samples_and_several_axes():
    values = np.array([[-3.0, np.nan], [-2.0, -1.0], [-1.0, -5.0]])  # time x place
    assert _peak(values, TIME[:3]) == (-1.0, 0.5, (1, 1))  # the earliest instant, then the first place
    value, t, where = _peak(np.full((3, 2), np.nan), TIME[:3])
    assert math.isnan(value) and t is None and where is None
