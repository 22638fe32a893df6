"""The synthetic mining tremor: reproducible, labelled, and with the paper's tremor's properties."""

import numpy as np
import pytest

from bearingfw.motion import (
    DEFAULT_SCALE,
    LEVEL_NAMES,
    TremorParameters,
    pga_h10,
    record_degree,
    scale_to_level,
    synthetic_tremor,
    t_ha,
)
from bearingfw.parameters import ParameterError

SEEDS = range(6)


@pytest.fixture(scope="module")
def tremors():
    return {seed: synthetic_tremor(seed) for seed in SEEDS}


def horizontal_band_share(record, low=2.4, high=5.0):
    # Independent of bearingfw.motion.metrics: numpy's FFT, pooled over both horizontals.
    f = np.fft.rfftfreq(record.n, record.dt)
    energy = sum(np.abs(np.fft.rfft(c)) ** 2 for c in (record.h1, record.h2))
    return energy[(f >= low) & (f <= high)].sum() / energy.sum()


def test_same_seed_same_record_other_seed_other_record(tremors):
    again = synthetic_tremor(1)
    np.testing.assert_array_equal(again.components, tremors[1].components)
    assert again.dt == tremors[1].dt
    assert not np.allclose(tremors[1].h1, tremors[2].h1)


def test_always_labelled_synthetic(tremors):
    for record in tremors.values():
        assert record.synthetic
        assert "synthetic" in record.source.lower() and "synthetic" in record.title.lower()
        assert record.metadata["generator"] == "bearingfw.motion.synthetic"
        assert record.names == ("W-E", "N-S", "Z")


@pytest.mark.parametrize("seed", SEEDS)
def test_the_papers_tremor_in_kind(tremors, seed):
    record = tremors[seed]
    assert 3.0 <= t_ha(record.h1, record.h2, record.dt) <= 4.0
    assert pga_h10(record.h1, record.h2, record.dt) == pytest.approx(0.46, rel=1e-6)
    assert horizontal_band_share(record) > 0.5
    # Horizontal peaks near the recorded 0.35 (W-E) and 0.28 m/s^2 (N-S).
    assert 0.3 <= np.max(np.abs(record.h1)) <= 0.45
    assert 0.22 <= np.max(np.abs(record.h2)) <= 0.37
    # The vertical carries content up to about 30 Hz: much of it above 10, little beyond 30.
    f = np.fft.rfftfreq(record.n, record.dt)
    vertical = np.abs(np.fft.rfft(record.v)) ** 2
    assert vertical[f > 10].sum() / vertical.sum() > 0.3
    assert vertical[f > 32].sum() / vertical.sum() < 0.05
    assert record_degree(record) == "II"


@pytest.mark.parametrize("seed", [0, 3])
def test_degree_k_after_scaling_to_level_k(tremors, seed):
    for level, degree in zip(LEVEL_NAMES, DEFAULT_SCALE.degrees):
        scaled = scale_to_level(tremors[seed], level)
        assert record_degree(scaled) == degree
        assert scaled.synthetic and "synthetic" in scaled.title.lower()


def test_parameters_are_validated_and_used():
    with pytest.raises(ParameterError, match="'dt'"):
        TremorParameters(dt=0.05)
    with pytest.raises(ParameterError, match="seed"):
        synthetic_tremor(-1)
    short = synthetic_tremor(0, TremorParameters(t_ha=2.5, pga_h10=0.2, duration=12.0))
    assert t_ha(short.h1, short.h2, short.dt) == pytest.approx(2.5, abs=0.01)
    assert pga_h10(short.h1, short.h2, short.dt) == pytest.approx(0.2, rel=1e-6)
    assert short.duration == pytest.approx(12.0)
