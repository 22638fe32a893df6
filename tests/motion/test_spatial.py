"""Spatially varying ground motion (bearingfw.motion.spatial): exact fractional delays, the model
coherency recovered over seeds, reproducibility, and each support's response spectrum near the record's."""

from __future__ import annotations

from pathlib import Path

import attrs
import numpy as np
import pytest
from scipy import signal

from bearingfw.motion import read_record, response_spectrum
from bearingfw.motion import spatial
from bearingfw.motion.spatial import SpatialVariation, coherency, delayed, delays, spatial_motions
from bearingfw.parameters import ParameterError

RECORDS = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"


@pytest.fixture(scope="module")
def manjil():
    rec = read_record([RECORDS / f"RSN1633_MANJIL_ABBAR--{c}.AT2" for c in "LTV"])
    return np.column_stack([rec.h1, rec.h2, rec.v]), rec.dt


def test_delays_follow_the_apparent_velocity_and_direction():
    pos = {"A": (0.0, 0.0), "B": (100.0, 0.0), "C": (100.0, 50.0)}
    assert delays(pos, SpatialVariation(apparent_velocity=500.0)) == pytest.approx({"A": 0.0, "B": 0.2, "C": 0.2})
    # a wave travelling towards -x reaches B and C first
    assert delays(pos, SpatialVariation(apparent_velocity=500.0, azimuth=180.0)) == pytest.approx(
        {"A": 0.2, "B": 0.0, "C": 0.0})
    assert delays(pos, SpatialVariation(apparent_velocity=500.0, azimuth=90.0))["C"] == pytest.approx(0.1)


def test_fractional_delay_is_exact_for_a_band_limited_signal():
    dt = 0.01
    t = np.arange(1000) * dt
    f = 3.0
    x = np.sin(2 * np.pi * f * t) * np.exp(-(((t - 4.0) / 1.0) ** 2))
    tau = 0.0237  # 2.37 samples
    y = delayed(x, dt, tau)
    t_out = np.arange(y.size) * dt
    expected = np.sin(2 * np.pi * f * (t_out - tau)) * np.exp(-(((t_out - tau - 4.0) / 1.0) ** 2))
    assert np.max(np.abs(y - expected)) < 1e-6


def test_wave_passage_alone_delays_the_record(manjil):
    a, dt = manjil
    out = spatial_motions(a, dt, {"A": (0.0, 0.0), "B": (60.0, 0.0)}, SpatialVariation(apparent_velocity=300.0))
    assert out["A"].shape == out["B"].shape == (a.shape[0] + 10, 3)  # 0.2 s = 10 samples more
    assert np.allclose(out["A"][: a.shape[0]], a, atol=1e-10)
    assert np.allclose(out["B"][10:], out["A"][:-10], atol=1e-10)  # a whole-sample delay: a shift


def test_generation_is_seeded_and_reproducible(manjil):
    a, dt = manjil
    pos = {"A": (0.0, 0.0), "B": (80.0, 0.0)}
    var = SpatialVariation(apparent_velocity=800.0, coherency="luco-wong", seed=7, amplitude_iterations=0,
                           wavelet_iterations=0)
    first, again = spatial_motions(a, dt, pos, var), spatial_motions(a, dt, pos, var)
    other = spatial_motions(a, dt, pos, attrs.evolve(var, seed=8))
    assert np.array_equal(first["B"], again["B"])
    assert not np.allclose(first["B"], other["B"])
    assert np.allclose(first["A"][: a.shape[0]], a, atol=1e-10)  # the first-reached support keeps the record


@pytest.mark.parametrize("model", ["harichandran-vanmarcke", "luco-wong"])
def test_simulated_coherency_matches_the_model_over_seeds(manjil, model):
    """Ensemble coherency of 40 realisations between two supports 100 m apart, per band, against |gamma|.

    The magnitude of a 40-realisation average is biased upwards where the coherency is small (for
    incoherent parts of unit power, E|mean| ~ sqrt(pi / (4 N)) (1 - gamma^2)); averaged over the
    hundreds of frequencies of each band the random error is small, so the tolerance is 0.05 plus
    that bias: tight enough to catch a wrong factorisation (none: 0, full: 1)."""
    a, dt = manjil
    _check_coherency(a, dt, SpatialVariation(coherency=model, amplitude_iterations=0, wavelet_iterations=0))


def _check_coherency(a, dt, var):
    n = 8192
    f = np.fft.rfftfreq(n, dt)
    s11 = s22 = s12 = 0.0
    for seed in range(40):
        out = spatial_motions(a[:, :1], dt, {"A": (0.0, 0.0), "B": (100.0, 0.0)}, attrs.evolve(var, seed=seed))
        x, y = np.fft.rfft(out["A"][:, 0], n), np.fft.rfft(out["B"][:, 0], n)
        s11, s22, s12 = s11 + np.abs(x) ** 2, s22 + np.abs(y) ** 2, s12 + x * np.conj(y)
    estimate = np.abs(s12) / np.sqrt(s11 * s22)
    for lo, hi in [(1.0, 2.0), (2.0, 4.0), (4.0, 8.0), (8.0, 12.0)]:
        band = (f >= lo) & (f < hi)
        model_value = coherency(var, 100.0, f[band])
        bias = np.mean(np.sqrt(np.pi / (4 * 40)) * (1.0 - model_value**2))
        assert abs(estimate[band].mean() - model_value.mean()) < 0.05 + bias, (lo, hi)


def _spectrum_misfit(a, dt, out, names, frequencies):
    """|PSA_support / PSA_record - 1| (supports x components x frequencies), 5 % damping."""
    periods = 1.0 / frequencies
    refs = [response_spectrum(a[:, c], dt, periods).psa for c in range(a.shape[1])]
    return np.array([[np.abs(response_spectrum(out[n][:, c], dt, periods).psa / refs[c] - 1.0)
                      for c in range(a.shape[1])] for n in names])


def test_the_oscillator_bank_is_the_response_spectrum(manjil):
    """The generator's batched frequency-domain oscillators (spatial._Oscillators) give what response_spectrum
    gives, sub-steps included (at dt = 0.02 s: one sub-step below 5 Hz, two to 10 Hz, three and four above),
    to single precision; a signal shorter than the FFT and a peak taken over its first samples only."""
    a, dt = manjil
    frequencies = np.geomspace(0.3, 20.0, 37)
    bank = spatial._Oscillators(frequencies, dt, 8192)
    assert set(bank.substeps) == {1, 2, 3, 4}
    ours = bank.psa(a.T, a.shape[0])
    theirs = np.array([response_spectrum(a[:, c], dt, 1.0 / frequencies).psa for c in range(3)])
    assert np.max(np.abs(ours / theirs - 1.0)) < 1e-4
    early = bank.psa(a[:, :1].T, 600)[0]  # the peak over the first 12 s
    assert np.max(np.abs(early / response_spectrum(a[:600, 0], dt, 1.0 / frequencies).psa - 1.0)) < 1e-4


def test_the_wavelet_response_closed_form_is_the_integrated_response():
    """spatial._wavelet_response (complex error functions) against the exact recursion on a fine step, for an
    oscillator at, below and above the wavelet's frequency, before, during and long after the wavelet."""
    from bearingfw.motion.metrics import _oscillator_filters

    h = 5e-4
    for f, f_wavelet, width in [(2.0, 2.0, 3.0), (2.0, 2.3, 3.0), (8.0, 7.0, 0.75), (0.5, 0.5, 12.0)]:
        omega, centre = 2 * np.pi * f, 6.0 * width  # the wavelet is nil at t = 0, where the recursion starts
        t = np.arange(int((centre + 30.0) / h)) * h
        w = np.cos(2 * np.pi * f_wavelet * (t - centre)) * np.exp(-0.5 * ((t - centre) / width) ** 2)
        b, den = _oscillator_filters(np.array([omega]), 0.05, np.array([h]))
        direct = omega**2 * signal.lfilter(b[0], den[0], -w)
        closed = spatial._wavelet_response(omega, t, 2 * np.pi * f_wavelet, centre, width)
        assert np.max(np.abs(closed - direct)) < 1e-3 * np.max(np.abs(direct)), (f, f_wavelet)


def test_matched_generation_is_reproducible(manjil):
    a, dt = manjil
    pos = {"A": (0.0, 0.0), "B": (80.0, 0.0)}
    var = SpatialVariation(apparent_velocity=700.0, coherency="luco-wong", seed=4)
    first, again = spatial_motions(a[:, :1], dt, pos, var), spatial_motions(a[:, :1], dt, pos, var)
    assert np.array_equal(first["B"], again["B"])


def test_support_spectra_stay_near_the_record(manjil):
    """One realisation, two supports, after the ratio and wavelet passes (module docstring): mean and 95th
    percentile of the misfit over 0.5-10 Hz, and how far the passes moved it. Measured: mean 1.4 %, 95th
    percentile 3.1 %, largest 4.6 %; without the passes: mean 15 %, largest 49 % (with the ratio passes
    only: 4.7 % and 27 %)."""
    a, dt = manjil
    pos = {"A": (0.0, 0.0), "D": (160.0, 0.0)}
    var = SpatialVariation(apparent_velocity=600.0, coherency="harichandran-vanmarcke", seed=1)
    frequencies = np.geomspace(0.5, 10.0, 100)
    devs = _spectrum_misfit(a, dt, spatial_motions(a, dt, pos, var), "D", frequencies)
    raw = _spectrum_misfit(a, dt, spatial_motions(a, dt, pos, attrs.evolve(var, amplitude_iterations=0,
                                                                             wavelet_iterations=0)), "D", frequencies)
    assert devs.mean() < 0.025
    assert np.percentile(devs, 95) < 0.05
    assert devs.max() < 0.08
    assert raw.max() > 0.2  # the test sees what the passes do


def _worst_misfit(a, dt, model, seeds):
    pos = {"A": (0.0, 0.0), "B": (40.0, 0.0), "C": (100.0, 0.0), "D": (160.0, 0.0)}
    worst = {}
    for seed in seeds:
        out = spatial_motions(a, dt, pos, SpatialVariation(apparent_velocity=600.0, coherency=model, seed=seed))
        worst[seed] = float(_spectrum_misfit(a, dt, out, "BCD", np.geomspace(0.5, 10.0, 100)).max())
    return worst


def test_every_support_spectrum_is_within_ten_percent_of_the_record(manjil):
    """The issue's criterion on one realisation (the full one over seeds and models is the slow test below):
    each of three generated supports' 5 %-damped spectra within 10 % of the record's at every one of 100
    frequencies over 0.5-10 Hz, every component. Measured: 5.2 %."""
    a, dt = manjil
    worst = _worst_misfit(a, dt, "harichandran-vanmarcke", [2])
    assert max(worst.values()) <= 0.10, worst


@pytest.mark.slow  # three realisations per model, about 15 s
@pytest.mark.parametrize("model", ["harichandran-vanmarcke", "luco-wong"])
def test_every_support_spectrum_is_within_ten_percent_of_the_record_over_seeds(manjil, model):
    """The issue's criterion: each support's 5 %-damped spectrum within 10 % of the record's at every one of 100
    frequencies over 0.5-10 Hz, every component, three supports, three seeds. Measured: largest misfit 5.2-6.0 %
    per realisation (seeds 0-9, both models: at most 7.1 %, and 7.8 % on a grid of 1000 frequencies)."""
    a, dt = manjil
    worst = _worst_misfit(a, dt, model, range(3))
    assert max(worst.values()) <= 0.10, worst


@pytest.mark.slow  # 40 realisations per model, about 25 s
@pytest.mark.parametrize("model", ["harichandran-vanmarcke", "luco-wong"])
def test_the_spectral_passes_keep_the_model_coherency(manjil, model):
    """test_simulated_coherency_matches_the_model_over_seeds with the ratio and wavelet passes on: what they add
    is not coherent with the record, so the ensemble coherency drops, but it stays the model's within the same
    tolerance. Measured: 0.03-0.08 below the model in each band where it is above 0.2 (without the passes:
    within 0.02), against tolerances of 0.065-0.18; the closest, Harichandran-Vanmarcke at 1-2 Hz: 0.072
    against 0.084."""
    a, dt = manjil
    _check_coherency(a, dt, SpatialVariation(coherency=model))


def test_bad_input_names_the_field(manjil):
    a, dt = manjil
    with pytest.raises(ParameterError, match="apparent_velocity"):
        SpatialVariation(apparent_velocity=-1.0)
    with pytest.raises(ParameterError, match="coherency"):
        SpatialVariation(coherency="gaussian")
    with pytest.raises(ParameterError, match="'positions'"):
        spatial_motions(a, dt, {}, SpatialVariation())
    with pytest.raises(ParameterError, match="'acceleration'"):
        spatial_motions(a[:1], dt, {"A": (0, 0)}, SpatialVariation())
