"""Intensity scales as data, degrees, levels D_0..D_IV, scaling, and the plugin hook."""

import importlib.metadata as metadata
import sys
import types

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bearingfw.motion import (
    DEFAULT_LEVELS,
    DEFAULT_SCALE,
    IntensityLevels,
    IntensityMismatchError,
    LEVEL_NAMES,
    IntensityScale,
    Record,
    get_scale,
    level_degree,
    pga_h10,
    record_degree,
    scale_to_level,
    scale_to_pga_h10,
    t_ha,
)
from bearingfw.motion.errors import UnknownScaleError
from bearingfw.parameters import ParameterError
from bearingfw.plugins import get_registry, hookimpl, load_registry

DEGREES = ["0", "I", "II", "III", "IV"]


def design_table_bound(degree: int, t: float) -> float:
    """The DESIGN.md table written out row by row (independent of the interpolation in the code)."""
    if degree == 0:
        return 0.15
    if t <= 1.5:
        return [0.6, 0.9, 1.2, 1.6][degree - 1]
    if t <= 3.0:
        return [0.9, 1.2, 1.5, 1.9][degree - 1] - 0.2 * t
    return [0.3, 0.6, 0.9, 1.3][degree - 1]


def test_the_papers_classifications():
    assert DEFAULT_SCALE.degree(0.10, 3.5) == "0"  # D_0, the scaled-down tremor
    assert DEFAULT_SCALE.degree(0.46, 3.5) == "II"  # D_II, the recorded tremor
    for t in (0.5, 1.5, 2.2, 3.0, 10.0):
        assert DEFAULT_SCALE.degree(0.10, t) == "0"


@pytest.mark.parametrize(
    "pga, t, degree",
    [
        (0.15, 3.5, "0"), (0.3, 3.5, "I"), (0.6, 3.5, "II"), (0.9, 3.5, "III"), (1.3, 3.5, "IV"),
        (0.6, 1.0, "I"), (0.9, 1.5, "II"), (1.6, 0.2, "IV"),
        (0.5, 2.0, "I"), (0.8, 2.0, "II"), (1.1, 2.0, "III"), (1.5, 2.0, "IV"),  # 0.9 - 0.2 t etc. at t = 2
        (0.3, 3.0, "I"), (0.6, 3.0, "II"),
    ],
)
def test_a_value_on_a_boundary_goes_to_the_lower_degree(pga, t, degree):
    assert DEFAULT_SCALE.degree(pga, t) == degree
    higher = DEGREES[DEGREES.index(degree) + 1] if degree != "IV" else "above IV"
    assert DEFAULT_SCALE.degree(pga * (1 + 1e-6), t) == higher


@given(pga=st.floats(0.0, 2.5), t=st.floats(0.0, 8.0))
def test_default_scale_is_the_design_table(pga, t):
    expected = next((DEGREES[d] for d in range(5) if pga <= design_table_bound(d, t) + 1e-12), "above IV")
    # Within rounding of a boundary both answers are defensible; elsewhere they must agree.
    if min(abs(pga - design_table_bound(d, t)) for d in range(5)) > 1e-9:
        assert DEFAULT_SCALE.degree(pga, t) == expected


def test_default_levels_lie_inside_their_degrees_for_long_tremors():
    assert DEFAULT_LEVELS.as_dict() == {"D_0": 0.10, "D_I": 0.23, "D_II": 0.46, "D_III": 0.75, "D_IV": 1.10}
    for t in (3.01, 3.5, 5.0, 20.0):
        for (name, value), degree in zip(DEFAULT_LEVELS.as_dict().items(), DEGREES):
            assert DEFAULT_SCALE.degree(value, t) == degree, (name, t)


def test_levels_can_be_overridden_and_are_checked():
    levels = IntensityLevels.with_overrides({"D_II": 0.5, "d3": 0.8})
    assert levels["D_II"] == 0.5 and levels["III"] == 0.8 and levels["D_0"] == 0.10
    assert IntensityLevels.with_overrides([("D_IV", 1.2), ("1", 0.2)]).as_dict()["D_I"] == 0.2
    with pytest.raises(ParameterError, match=r"must increase from D_0 to D_IV, got D_0 = 0.1, D_I = 0.05"):
        IntensityLevels(d1=0.05)
    with pytest.raises(ParameterError, match=r"D_0 = -0.1 is outside the allowed range D_0 > 0"):
        IntensityLevels(d0=-0.1)
    with pytest.raises(ParameterError, match=r"D_III = str 'x' is outside the allowed range D_III > 0"):
        IntensityLevels(d3="x")
    with pytest.raises(ParameterError, match="unknown intensity level"):
        levels["D_V"]


@pytest.mark.parametrize(
    "overrides",
    [{"D_II": 0.5, "d2": 0.6}, {"II": 0.5, "2": 0.5}, [("D_II", 0.5), ("D_II", 0.6)]],
    ids=["two-spellings", "same-value", "pairs"],
)
def test_a_level_given_twice_is_an_error(overrides):
    with pytest.raises(ParameterError, match=r"intensity level D_II is given twice"):
        IntensityLevels.with_overrides(overrides)


def test_level_names_come_from_the_default_scale():
    assert LEVEL_NAMES == tuple(f"D_{d}" for d in DEFAULT_SCALE.degrees) == ("D_0", "D_I", "D_II", "D_III", "D_IV")
    assert [level_degree(name) for name in LEVEL_NAMES] == list(DEFAULT_SCALE.degrees)


def test_scale_table_is_validated():
    good = dict(name="x", degrees=("a", "b"), durations=(1.0, 2.0), bounds=((0.1, 0.2), (0.3, 0.4)))
    assert IntensityScale(**good).degree(0.35, 5.0) == "b"
    with pytest.raises(ParameterError, match=r"at t_Ha = 2 s the upper bounds \[0.2, 0.1\] must increase"):
        IntensityScale(**{**good, "bounds": ((0.1, 0.2), (0.3, 0.1))})
    with pytest.raises(ParameterError, match="one row per degree"):
        IntensityScale(**{**good, "bounds": ((0.1, 0.2),)})
    with pytest.raises(ParameterError, match="strictly increasing"):
        IntensityScale(**{**good, "durations": (2.0, 1.0)})
    with pytest.raises(ParameterError, match="PGA_H10 must be finite"):
        IntensityScale(**good).degree(float("nan"), 1.0)
    assert IntensityScale.from_dict(DEFAULT_SCALE.to_dict()) == DEFAULT_SCALE
    with pytest.raises(ParameterError, match=r"every bound must be a finite number > 0"):
        IntensityScale(**{**good, "bounds": ((0.1, "x"), (0.3, 0.4))})


def test_degrees_must_be_a_sequence_of_labels_not_a_string():
    good = dict(name="x", degrees=("a", "b"), durations=(1.0,), bounds=((0.1,), (0.3,)))
    with pytest.raises(ParameterError, match=r"'degrees' must be distinct non-empty labels.*got 'ab'"):
        IntensityScale(**{**good, "degrees": "ab"})
    assert IntensityScale(**{**good, "degrees": ["a", "b"]}).degrees == ("a", "b")


def test_from_dict_names_missing_and_unknown_fields():
    data = DEFAULT_SCALE.to_dict()
    del data["bounds"], data["durations"]
    with pytest.raises(ParameterError, match=r"intensity scale 'usb-pga-h10': missing field\(s\) 'durations', 'bounds'"):
        IntensityScale.from_dict(data)
    with pytest.raises(ParameterError, match=r"unknown field\(s\) 'colour'"):
        IntensityScale.from_dict({**DEFAULT_SCALE.to_dict(), "colour": "red"})
    assert IntensityScale.from_dict({k: v for k, v in DEFAULT_SCALE.to_dict().items() if k != "description"}).name


def boxcar_sine(duration: float, dt: float = 0.005, f: float = 4.0) -> Record:
    n = int(round((duration + 4.0) / dt))
    t = np.arange(n) * dt
    window = (t >= 1.0) & (t < 1.0 + duration)
    h1 = np.where(window, np.sin(2 * np.pi * f * t), 0.0)
    h2 = np.where(window, 0.7 * np.cos(2 * np.pi * f * t), 0.0)
    return Record(h1=h1, h2=h2, v=0.5 * h1, dt=dt, source="test sine")


def test_scaling_hits_the_target_and_keeps_the_duration():
    record = boxcar_sine(5.0)
    scaled = scale_to_pga_h10(record, 0.75)
    assert pga_h10(scaled.h1, scaled.h2, scaled.dt) == pytest.approx(0.75, rel=1e-9)
    assert t_ha(scaled.h1, scaled.h2, scaled.dt) == pytest.approx(t_ha(record.h1, record.h2, record.dt), rel=1e-9)
    assert scaled.metadata["scale_factor"] == pytest.approx(0.75 / pga_h10(record.h1, record.h2, record.dt))
    for level, degree in zip(["D_0", "D_I", "D_II", "D_III", "D_IV"], DEGREES):
        assert record_degree(scale_to_level(record, level)) == degree


def test_a_scaled_record_outside_its_degree_is_an_error():
    short = boxcar_sine(1.0)  # t_Ha = 0.9 s: degree II starts only above 0.6 m/s^2
    assert t_ha(short.h1, short.h2, short.dt) < 1.5
    with pytest.raises(IntensityMismatchError, match=r"scaled to D_II .* is degree I, not II"):
        scale_to_level(short, "D_II")
    assert record_degree(scale_to_level(short, "D_II", IntensityLevels(d2=0.7, d3=1.0, d4=1.5))) == "II"


def test_default_scale_is_registered_and_unknown_names_are_listed():
    assert get_scale() is DEFAULT_SCALE
    assert get_registry().intensity_scales["usb-pga-h10"].origin.distribution == "bearingfw"
    with pytest.raises(UnknownScaleError, match="known scales: .*usb-pga-h10"):
        get_scale("nope")


def test_plugins_register_scales_and_readers_and_bad_ones_are_reported(monkeypatch):
    custom = IntensityScale(name="flat", degrees=("low", "high"), durations=(0.0,), bounds=((0.2,), (1.0,)))
    plugin = types.ModuleType("fake_motion_plugin")

    @hookimpl
    def bearingfw_register_intensity_scales():
        return [custom, {"name": "not-a-scale"}]

    @hookimpl
    def bearingfw_register_record_readers():
        good = types.SimpleNamespace(name="fake", suffixes=(".fake",), read=lambda path, **kw: [], sniff=None)
        bad = types.SimpleNamespace(name="broken", suffixes=("fake",), read=lambda path, **kw: [])
        return [good, bad]

    plugin.bearingfw_register_intensity_scales = bearingfw_register_intensity_scales
    plugin.bearingfw_register_record_readers = bearingfw_register_record_readers
    monkeypatch.setitem(sys.modules, "fake_motion_plugin", plugin)
    eps = [
        *metadata.entry_points(group="bearingfw"),
        metadata.EntryPoint(name="fake-motion", value="fake_motion_plugin", group="bearingfw"),
    ]
    registry = load_registry(eps)
    assert registry.intensity_scales["flat"].value is custom
    assert get_scale("flat", registry=registry).degree(0.5, 3.0) == "high"
    assert "fake" in registry.record_readers and "peer-at2" in registry.record_readers
    errors = [b.error for b in registry.broken if b.plugin == "fake-motion"]
    assert any("IntensityScale" in e for e in errors)
    assert any("'broken'" in e and "suffixes" in e for e in errors)
    assert "broken" not in registry.record_readers
