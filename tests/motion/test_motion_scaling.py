"""Scale targets (PGA_H10, PGA, Sa(T), as recorded) against hand-computed scale factors."""

import math

import numpy as np
import pytest

from bearingfw.motion import (
    DEFAULT_LEVELS,
    IntensityMismatchError,
    Record,
    ScaleTarget,
    horizontal_pga,
    horizontal_sa,
    parse_target,
    record_pga_h10,
    response_spectrum,
    scale_factor,
    scale_record,
    scale_to_level,
)
from bearingfw.parameters import ParameterError


def smooth_ramp(t, rise):
    x = np.minimum(t / rise, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * x)


def harmonic_record(amplitudes, forcing_period, dt=0.002, duration=60.0):
    """Horizontals A_i sin(2 pi t / Tf), ramped in over 15 s; a small vertical."""
    t = np.arange(int(duration / dt) + 1) * dt
    shape = smooth_ramp(t, 15.0) * np.sin(2 * np.pi / forcing_period * t)
    h1, h2 = (a * shape for a in amplitudes)
    return Record(h1=h1, h2=h2, v=0.1 * shape, dt=dt, source="harmonic")


def steady_psa(amplitude, period, forcing_period, zeta=0.05):
    """psa of a 5 % oscillator of period T in steady state under A sin(W t): A / sqrt((1 - r^2)^2 + (2 z r)^2)."""
    r = period / forcing_period
    return amplitude / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)


def test_pga_of_a_two_component_record_is_the_peak_of_the_resultant():
    # By hand: at sample 2 the resultant is sqrt(3^2 + 4^2) = 5; h1 alone reaches 4.5 at sample 5
    # (resultant sqrt(4.5^2 + 1^2) = 4.61) and h2 alone -4.8 at sample 8: the PGA is 5, not 4.8.
    h1 = np.array([0, 1, 3, 0, 0, 4.5, 0, 0, 0, 0.0])
    h2 = np.array([0, 0, 4, 0, 0, 1.0, 0, 0, -4.8, 0.0])
    record = Record(h1=h1, h2=h2, v=np.full(10, 9.0), dt=0.01)  # the vertical does not count
    assert horizontal_pga(record) == 5.0
    assert scale_factor(record, ScaleTarget(kind="pga", value=2.0)) == pytest.approx(2.0 / 5.0, rel=1e-15)
    scaled = scale_record(record, ScaleTarget(kind="pga", value=2.0))
    assert horizontal_pga(scaled) == pytest.approx(2.0, rel=1e-15)
    assert scaled.metadata["target"] == "pga=2" and scaled.metadata["target_pga"] == 2.0


def test_pga_of_a_single_horizontal_is_its_own_peak():
    h1 = np.array([0, -3.5, 1, 2.0, 0])
    record = Record(h1=h1, h2=np.zeros(5), v=np.zeros(5), dt=0.01)
    assert scale_factor(record, ScaleTarget(kind="pga", value=7.0)) == pytest.approx(2.0, rel=1e-15)


def test_pga_h10_of_a_slow_circular_motion_is_its_radius():
    # h1 = A cos, h2 = A sin at 1 Hz: the 10 Hz low-pass passes it whole (gain 1 / (1 + 0.1^8)),
    # the resultant is A while the motion is at full strength (it fades in and out over 5 s, so
    # that the filter's ends see rest), so the factor for a target P is P / A.
    dt, radius = 0.005, 0.8
    t = np.arange(6001) * dt
    envelope = smooth_ramp(t, 5.0) * smooth_ramp(t[::-1], 5.0)
    h1, h2 = radius * envelope * np.cos(2 * np.pi * t), radius * envelope * np.sin(2 * np.pi * t)
    record = Record(h1=h1, h2=h2, v=np.zeros(t.size), dt=dt)
    factor = scale_factor(record, ScaleTarget(kind="pga_h10", value=0.46))
    assert factor == pytest.approx(0.46 / radius, rel=1e-4)


@pytest.mark.parametrize("forcing_period", [0.5, 0.8, 0.3])  # at resonance, below it, above it
def test_sa_factor_of_a_harmonic_record_is_the_closed_form(forcing_period):
    # Sa(T) of each horizontal is the steady-state psa A_i / sqrt(...); the target combines them by
    # the geometric mean, so the factor is S / (sqrt(A1 A2) / sqrt(...)).
    a1, a2, period, target = 1.2, 0.3, 0.5, 2.0
    record = harmonic_record((a1, a2), forcing_period)
    by_hand = target / (math.sqrt(a1 * a2) * steady_psa(1.0, period, forcing_period))
    factor = scale_factor(record, ScaleTarget(kind="sa", value=target, period=period))
    assert factor == pytest.approx(by_hand, rel=2e-3)
    if forcing_period == 0.5:  # at resonance: Sa = A / (2 zeta) = 10 A
        assert horizontal_sa(record, period) == pytest.approx(10 * math.sqrt(a1 * a2), rel=2e-3)
    scaled = scale_record(record, ScaleTarget(kind="sa", value=target, period=period))
    assert horizontal_sa(scaled, period) == pytest.approx(target, rel=1e-12)
    assert scaled.metadata["target_period"] == period


def test_sa_of_a_single_horizontal_is_its_own_spectrum():
    record = harmonic_record((1.2, 0.0), 0.8)
    own = response_spectrum(record.h1, record.dt, [0.5]).psa[0]
    assert horizontal_sa(record, 0.5) == pytest.approx(own, rel=1e-14)
    assert scale_factor(record, ScaleTarget(kind="sa", value=1.0, period=0.5)) == pytest.approx(
        1.0 / steady_psa(1.2, 0.5, 0.8), rel=2e-3
    )


def test_as_recorded_is_factor_one_and_leaves_the_record():
    record = harmonic_record((1.2, 0.3), 0.8, duration=5.0)
    target = parse_target("as-recorded")
    assert scale_factor(record, target) == 1.0
    scaled = scale_record(record, target)
    assert np.array_equal(scaled.h1, record.h1) and scaled.metadata["target"] == "as-recorded"


def test_a_level_target_is_the_level_pga_h10_and_checks_the_degree(chuetsu):
    # A level's target scales as scale_to_level does (same factor, same metadata) and checks the degree.
    target = ScaleTarget.for_level("D_0")
    assert target.kind == "pga_h10" and target.value == DEFAULT_LEVELS["D_0"] and target.level == "D_0"
    too_strong = ScaleTarget(kind="pga_h10", value=1.5, label="D_IV")  # the level is taken from the label
    assert too_strong.level == "D_IV"
    with pytest.raises(IntensityMismatchError, match="is degree above IV, not IV"):
        scale_record(chuetsu, too_strong)  # t_Ha = 18.6 s: degree IV ends at 1.3 m/s^2 there
    scaled = scale_record(chuetsu, target)
    reference = scale_to_level(chuetsu, "D_0")
    assert scaled.metadata["scale_factor"] == reference.metadata["scale_factor"]
    assert scaled.metadata["level"] == reference.metadata["level"] == "D_0"
    assert record_pga_h10(scaled) == pytest.approx(0.10, rel=1e-9)


def test_target_labels_and_parsing():
    assert parse_target("pga_h10=0.46") == ScaleTarget(kind="pga_h10", value=0.46)
    assert parse_target("pga_h10=0.46").label == "PGA_H10=0.46"
    assert parse_target("PGA = 2").label == "pga=2"
    assert parse_target("sa=2@0.5").label == "sa=2@0.5s" and parse_target("sa=2@0.5s").period == 0.5
    t1 = parse_target("sa=2@T1")
    assert t1.needs_period and t1.label == "sa=2@T1"
    resolved = t1.with_period(0.83)
    assert resolved.period == 0.83 and resolved.label == "sa=2@T1" and not resolved.needs_period
    assert parse_target("d2") == ScaleTarget(kind="pga_h10", value=0.46, label="D_II", level="D_II")
    assert parse_target("as_recorded").kind == "as-recorded"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"kind": "peak"}, "parameter 'kind' must be one of 'pga_h10', 'pga', 'sa', 'as-recorded'"),
        ({"kind": "pga"}, "kind 'pga' needs a 'value' > 0"),
        ({"kind": "pga", "value": -1.0}, "parameter 'value' = -1.0 is outside the allowed range value > 0"),
        ({"kind": "pga", "value": 1.0, "period": 0.5}, "'period' goes with kind 'sa'"),
        ({"kind": "sa", "value": 1.0, "period": 0.0}, "parameter 'period' = 0.0 is outside the allowed range period > 0"),
        ({"kind": "as-recorded", "value": 1.0}, "takes no 'value'"),
        ({"kind": "pga", "value": 1.0, "level": "D_II"}, "goes with kind 'pga_h10'"),
        ({"kind": "pga_h10", "value": 1.0, "level": "D_9"}, "parameter 'level' must be one of D_0"),
    ],
)
def test_target_errors_name_the_field(kwargs, message):
    with pytest.raises(ParameterError, match=message.replace("(", r"\(").replace(")", r"\)")):
        ScaleTarget(**kwargs)


@pytest.mark.parametrize("text", ["sa=2", "pga=2@0.5", "pga=", "sa=two@1", "D_V"])
def test_unparsable_targets(text):
    with pytest.raises(ParameterError, match="scale target"):
        parse_target(text)


def test_scaling_needs_a_period_and_horizontal_motion():
    record = harmonic_record((1.0, 1.0), 0.8, duration=5.0)
    with pytest.raises(ParameterError, match="must be resolved to a number"):
        scale_factor(record, parse_target("sa=2@T1"))
    vertical_only = Record(h1=np.zeros(100), h2=np.zeros(100), v=np.ones(100), dt=0.01, source="v only")
    for text in ("pga=1", "pga_h10=1", "sa=1@0.5"):
        with pytest.raises(ParameterError, match="v only: .* is zero"):
            scale_factor(vertical_only, parse_target(text))
