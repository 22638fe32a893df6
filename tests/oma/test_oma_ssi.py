"""SSI-COV and the stabilisation diagram on a 3-DOF chain with closed-form modes."""

from __future__ import annotations

import numpy as np
import pytest
from oma_systems import CHANNELS, chain_modes, chain_record

from bearingfw.analysis import mac
from bearingfw.oma import Criteria, SSISettings, identify, ssi_cov, stability
from bearingfw.oma.ssi import (
    GRAM_LIMIT,
    block_toeplitz,
    complex_mac,
    correlations,
    leading_singular,
    modal_phase_collinearity,
    real_shape,
    shift_operators,
)
from bearingfw.parameters import ParameterError


@pytest.fixture(scope="module")
def chain():
    record = chain_record()
    return record, identify(record)


def test_the_three_modes_are_identified_within_1_percent_and_20_percent(chain):
    """The default settings (order 60; the paper's 2 %, 2 %, 90 %) on 10 minutes with 5 % measurement noise."""
    _, result = chain
    f, zeta, shapes = chain_modes()
    modes = result.modes.modes
    assert len(modes) == 3, [m.frequency for m in modes]
    for k, mode in enumerate(modes):
        assert mode.frequency == pytest.approx(f[k], rel=0.01)
        assert mode.damping == pytest.approx(zeta[k], rel=0.20)
        assert mac(mode.shape, shapes[:, k])[0, 0] > 0.95
        assert mode.poles >= 5 and mode.mpc > 0.95


def test_shapes_are_real_normalised_and_keyed_by_channel(chain):
    _, result = chain
    data = result.to_dict()
    assert data["channels"] == list(CHANNELS)
    for entry, mode in zip(data["modes"], result.modes.modes, strict=True):
        assert list(entry["shape"]) == list(CHANNELS)
        assert max(entry["shape"].values(), key=abs) == 1.0
        assert entry["frequency"] == mode.frequency
    assert data["pole_counts"]["stable"] == int(result.stability.stable.sum()) > 0


def test_stable_poles_sit_at_the_modes_and_noise_poles_do_not(chain):
    """At the paper's order 30 (at 60 the six-state chain has ten times as many noise poles to sort out)."""
    result = identify(chain[0], SSISettings(max_order=30))
    f = chain_modes()[0]
    poles, state = result.poles, result.stability
    at_a_mode = np.min(np.abs(poles.frequency[:, None] / f[None, :] - 1), axis=1) < 0.01
    # the system has 6 states: above order 6 each order adds noise poles, nearly all unstable;
    # a noise pole is occasionally stable between two orders, never long enough to be a mode
    assert np.count_nonzero(~at_a_mode) > 10 * np.count_nonzero(~at_a_mode & state.stable)
    assert np.count_nonzero(at_a_mode & state.stable) > 0.9 * np.count_nonzero(state.stable)


@pytest.mark.parametrize("order, found", [(30, 3), (10, 2)])
def test_an_order_too_low_misses_the_last_mode_and_says_so(chain, order, found):
    """The chain's modes become stable from orders 4, 6 and 8: at order 10 the third is stable at two
    orders only, too few to count (three needed), and the warning names it; at the paper's 30 all three."""
    record, _ = chain
    f = chain_modes()[0]
    result = identify(record, SSISettings(max_order=order))
    found_f = result.modes.frequencies
    assert found_f.size == found
    np.testing.assert_allclose(found_f, f[:found], rtol=0.01)
    late = [w for w in result.warnings if "top orders still add" in w]
    if found == 3:
        assert not late
    else:
        assert len(late) == 1 and f"{f[2]:.2f}" in late[0] and "raise the order above 10" in late[0]


def test_a_band_limit_resamples_and_keeps_only_the_modes_in_it():
    record = chain_record(duration=300.0)
    result = identify(record, SSISettings(max_order=20), Criteria(fmax=4.0))
    assert result.decimation == 5 and result.channels.dt == pytest.approx(0.1)
    found = [m.frequency for m in result.modes.modes]
    f = chain_modes()[0]
    assert len(found) == 2
    np.testing.assert_allclose(found, f[:2], rtol=0.01)


def test_block_toeplitz_layout():
    # R_j = j * ones(l, r) makes every block readable
    R = np.arange(6)[:, None, None] * np.ones((6, 2, 1))
    T = block_toeplitz(R, 3)
    assert T.shape == (6, 3)
    np.testing.assert_array_equal(T[::2], [[3, 2, 1], [4, 3, 2], [5, 4, 3]])


def test_correlations_of_white_noise_and_of_a_delay():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(20000)
    y = np.column_stack([x, np.roll(x, 2)])  # channel 2 is channel 1 two samples later
    R = correlations(y, 4)
    assert R.shape == (4, 2, 2)
    assert R[0, 0, 0] == pytest.approx(1.0, rel=0.03)
    assert R[2, 1, 0] == pytest.approx(1.0, rel=0.03)  # y2(k+2) y1(k)... = x(k) x(k)
    assert abs(R[1, 0, 0]) < 0.03


def test_real_shape_and_phase_collinearity():
    real = np.array([[1.0, -0.5, 0.25]])
    turned = real * np.exp(1j * 0.7)
    np.testing.assert_allclose(real_shape(-turned), real, atol=1e-12)
    assert modal_phase_collinearity(turned)[0] == pytest.approx(1.0)
    assert complex_mac(turned, real)[0, 0] == pytest.approx(1.0)
    other = np.array([[1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    table = complex_mac(np.vstack([turned, other[1]]), other)
    np.testing.assert_allclose(complex_mac(np.vstack([turned, other[1]]), other, rowwise=True), np.diag(table))
    spread = np.array([[1.0, 1j, -1.0, -1j]])  # components all round the circle
    assert modal_phase_collinearity(spread)[0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    "kwargs, message",
    [({"max_order": 31}, "even"), ({"max_order": 0}, "max_order"), ({"block_rows": 0}, "block_rows")],
)
def test_bad_settings_are_named(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        SSISettings(**kwargs)


@pytest.mark.parametrize(
    "channels, references, block_rows, allowed",
    [
        (2, None, 5, "16 <= block_rows <= 250"),  # T holds 5 x 2 = 10 < 30 states; 15 x 2 shift rows are needed
        (4, [0], 29, "30 <= block_rows <= 250"),  # one reference: T holds 29 < 30 states
        (1, None, 30, "31 <= block_rows <= 250"),  # one channel: the shift equation has 29 rows for 30 unknowns
        (2, None, 300, "16 <= block_rows <= 250"),  # lags up to 599 from 1000 samples
    ],
)
def test_block_rows_outside_their_range_are_an_error_naming_it(channels, references, block_rows, allowed):
    y = np.random.default_rng(1).standard_normal((1000, channels))
    with pytest.raises(ParameterError, match=f"block_rows = {block_rows} .* allowed: {allowed}"):
        ssi_cov(y, 0.01, SSISettings(max_order=30, block_rows=block_rows), references)


def test_the_default_block_rows_determine_the_shift_equation():
    """One channel at order 60: 40 block rows leave 39 shift rows for 60 states; the default takes 61."""
    assert SSISettings(max_order=60).rows_for(1, 1, 100000) == 61
    assert SSISettings(max_order=60).rows_for(28, 28, 100000) == 40


def test_the_shift_equation_from_small_gram_matrices_is_the_least_squares_solution(chain):
    record, _ = chain
    settings = SSISettings(max_order=20)
    T = block_toeplitz(correlations(record.data, 80), 40)
    U, s = leading_singular(T, 20)
    for n, A in zip(settings.orders, shift_operators(U, s, 3, settings.orders), strict=True):
        observability = U[:, :n] * np.sqrt(s[:n])
        direct = np.linalg.lstsq(observability[:-3], observability[3:], rcond=None)[0]
        np.testing.assert_allclose(A, direct, atol=1e-9 * np.abs(direct).max())


def test_leading_singular_matches_the_svd_and_falls_back_to_it_when_squaring_would_lose_accuracy():
    rng = np.random.default_rng(0)
    q1, _ = np.linalg.qr(rng.standard_normal((120, 120)))
    q2, _ = np.linalg.qr(rng.standard_normal((90, 90)))
    for spread in (1e-3, 1e-9):  # the 20th singular value relative to the first
        values = np.concatenate([np.logspace(0, np.log10(spread), 20), spread * np.logspace(-1, -3, 70)])
        T = (q1[:, :90] * values) @ q2.T
        U, s = leading_singular(T, 20)
        np.testing.assert_allclose(s, values[:20], rtol=1e-8)
        np.testing.assert_allclose(np.abs(np.sum(U * q1[:, :20], axis=0)), 1.0, atol=1e-8)
        assert (values[19] < GRAM_LIMIT) == (spread == 1e-9)


@pytest.mark.parametrize(
    "kwargs, message",
    [({"frequency": 0.0}, "frequency"), ({"mac": 1.5}, "mac"), ({"fmin": 5.0, "fmax": 2.0}, "fmax")],
)
def test_bad_criteria_are_named(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Criteria(**kwargs)


def test_stricter_criteria_keep_fewer_stable_poles(chain):
    _, result = chain
    loose = stability(result.poles, Criteria(damping=0.2))
    strict = stability(result.poles, Criteria(damping=0.005, mac=0.999))
    assert strict.stable.sum() < result.stability.stable.sum() < loose.stable.sum()


def test_a_single_channel_is_identified_with_a_warning(chain):
    """One channel: frequencies and damping, but shapes of one number each, which MAC cannot tell apart."""
    record, _ = chain
    result = identify(record.select(["m3.ux"]))
    np.testing.assert_allclose(result.modes.frequencies, chain_modes()[0], rtol=0.01)
    assert any("single channel" in w for w in result.warnings)
