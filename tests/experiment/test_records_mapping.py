"""experiment/records.py with records mapped to x, y, z and every kind of scale target."""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from bearingfw.experiment.records import (
    ground_acceleration,
    load_record,
    record_info,
    record_inputs,
    record_readers,
    scaled_record,
    target_inputs,
)
from bearingfw.experiment.spec import parse_experiment
from bearingfw.motion import (
    G,
    ScaleTarget,
    VerticalComponentError,
    horizontal_pga,
    horizontal_sa,
    record_pga_h10,
    response_spectrum,
)
from bearingfw.parameters import ParameterError

RECORDS = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"
EW, NS, UD = (RECORDS / f"RSN4843_CHUETSU_65006{c}.AT2" for c in ("EW", "NS", "UD"))


def at2(path):
    lines = path.read_bytes().decode("ascii").split("\r\n")
    return np.array([float(token) for line in lines[4:] for token in line.split()]) * G


def experiment(records: str, base_dir=RECORDS, intensities='levels = ["as-recorded", "D_II"]'):
    return parse_experiment(
        f'name = "mapping"\n[models.M1]\npreset = "M1"\n{records}\n[intensities]\n{intensities}\n', base_dir=base_dir
    )


ONE = f'[records.one]\ny = "{NS.name}"\n'
THREE = f'[records.three]\nx = "-{EW.name}"\ny = "{NS.name}"\nz = "{UD.name}"\n'


def test_a_single_component_record_drives_its_direction_only():
    exp = experiment(ONE)
    spec = exp.record("one")
    record = load_record(exp, spec)
    ag = ground_acceleration(record, spec.components)
    assert ag.shape == (6000, 3)
    assert np.array_equal(ag[:, 1], at2(NS)) and not np.any(ag[:, 0]) and not np.any(ag[:, 2])
    info = record_info(record, spec.components)
    assert info["missing"] == ["x", "z"] and info["directions"] == {"y": NS.name}
    assert info["axes"] == {"x": "h1", "y": "h2", "z": "v"}
    assert "no component is mapped to x: its ground acceleration is zero" in info["notes"]
    assert record_readers(exp, spec) == ("peer-at2",)


def test_three_components_with_a_flip_land_on_their_axes():
    exp = experiment(THREE)
    spec = exp.record("three")
    ag = ground_acceleration(load_record(exp, spec), spec.components)
    assert np.array_equal(ag, np.column_stack([-at2(EW), at2(NS), at2(UD)]))


def test_a_vertical_on_x_is_refused_unless_the_experiment_says_so():
    exp = experiment(f'[records.r]\nx = "{UD.name}"\ny = "{NS.name}"\n')
    with pytest.raises(VerticalComponentError) as caught:
        load_record(exp, exp.record("r"))
    message = str(caught.value)
    assert str(UD) in message and "ends in 'UD'" in message and "PEER header names the component 'UD'" in message
    assert "vertical_as_horizontal = true" in message
    exp = experiment(f'[records.r]\nx = "{UD.name}"\ny = "{NS.name}"\nvertical_as_horizontal = true\n')
    record = load_record(exp, exp.record("r"))
    assert np.array_equal(record.h1, at2(UD)) and any("looks vertical" in n for n in record.notes)


def test_every_kind_of_target_against_hand_computed_factors():
    exp = experiment(THREE, intensities='levels = ["as-recorded", "D_II"]\npga = [2.0]\nsa = [3.0]\nperiod = 0.5')
    record = load_record(exp, exp.record("three"))
    x, y = -at2(EW), at2(NS)
    by_hand = {
        "as-recorded": 1.0,
        "D_II": 0.46 / record_pga_h10(record),
        "pga=2": 2.0 / np.max(np.sqrt(x**2 + y**2)),
        "sa=3@0.5s": 3.0 / math.sqrt(response_spectrum(x, 0.01, [0.5]).psa[0] * response_spectrum(y, 0.01, [0.5]).psa[0]),
    }
    names = [i.name for i in exp.intensity_list]
    assert names == list(by_hand)
    for intensity in exp.intensity_list:
        scaled = scaled_record(record, intensity, exp.intensities, exp.integration.dt_integration)
        assert scaled.metadata["scale_factor"] == pytest.approx(by_hand[intensity.name], rel=1e-12), intensity.name
        assert scaled.metadata["target"] == intensity.name
    d2 = scaled_record(record, exp.intensity_list[1], exp.intensities)
    assert record_pga_h10(d2) == pytest.approx(0.46, rel=1e-12) and d2.metadata["degree"] == "II"
    assert horizontal_pga(scaled_record(record, exp.intensity_list[2])) == pytest.approx(2.0, rel=1e-12)
    assert horizontal_sa(scaled_record(record, exp.intensity_list[3]), 0.5) == pytest.approx(3.0, rel=1e-12)


def test_an_sa_target_at_the_first_mode_takes_the_period_given():
    exp = experiment(ONE)
    record = load_record(exp, exp.record("one"))
    target = ScaleTarget(kind="sa", value=1.5)  # "T1": the caller knows the structure's first period
    with pytest.raises(ParameterError, match="must be resolved to a number"):
        scaled_record(record, target)
    scaled = scaled_record(record, target, period=0.83)
    own = response_spectrum(at2(NS), 0.01, [0.83]).psa[0]  # one horizontal: its own Sa
    assert scaled.metadata["scale_factor"] == pytest.approx(1.5 / own, rel=1e-12)
    assert scaled.metadata["target"] == "sa=1.5@T1" and scaled.metadata["target_period"] == 0.83


def test_a_resampling_that_loses_the_peak_is_refused():
    exp = experiment(ONE)
    record = load_record(exp, exp.record("one"))
    with pytest.raises(ParameterError, match=r"resampling from dt = 0.01 s to the integration step dt_integration = "
                                             r"0.5 s cuts y: NS to 0.\d+ of its peak"):
        scaled_record(record, ScaleTarget(kind="as-recorded"), dt_integration=0.5)
    kept = scaled_record(record, ScaleTarget(kind="as-recorded"), dt_integration=0.5, min_peak_ratio=None)
    assert kept.dt == 0.5 and kept.min_peak_ratio < 0.5
    assert scaled_record(record, ScaleTarget(kind="as-recorded"), dt_integration=0.005).dt == 0.01  # divides: kept


def test_the_digest_input_covers_the_mapping_not_the_paths(tmp_path):
    exp = experiment(THREE)
    inputs = record_inputs(exp, exp.record("three"))
    assert set(inputs["mapping"]) == {"x", "y", "z"}
    assert inputs["mapping"]["x"]["flip"] is True and inputs["mapping"]["y"]["flip"] is False
    assert inputs["vertical_as_horizontal"] is False
    # The same files elsewhere: the same inputs. Another sign, component or file: other inputs.
    for path in (EW, NS, UD):
        shutil.copy(path, tmp_path / path.name)
    assert record_inputs(experiment(THREE, base_dir=tmp_path), exp.record("three")) == inputs
    flipped = experiment(THREE.replace(f'-{EW.name}', EW.name))
    assert record_inputs(flipped, flipped.record("three")) != inputs
    swapped = experiment(f'[records.three]\nx = "-{NS.name}"\ny = "{EW.name}"\nz = "{UD.name}"\n')
    assert record_inputs(swapped, swapped.record("three")) != inputs


def test_a_files_record_keeps_its_digest_input():
    # The inputs of a files record are what they were before x/y/z existed (no new keys), so
    # stored cells keep their digests.
    exp = experiment(f'[records.legacy]\nfiles = ["{EW.name}", "{NS.name}", "{UD.name}"]\n')
    inputs = record_inputs(exp, exp.record("legacy"))
    assert set(inputs) == {"seed", "tremor", "format", "dt", "units", "components", "file_sha256"}
    assert len(inputs["file_sha256"]) == 3


def test_target_inputs_tell_targets_apart():
    targets = [ScaleTarget(kind="sa", value=2.0, period=0.5), ScaleTarget(kind="sa", value=2.0, period=0.6),
               ScaleTarget(kind="pga", value=2.0), ScaleTarget(kind="as-recorded")]
    inputs = [target_inputs(t) for t in targets]
    assert all(a != b for i, a in enumerate(inputs) for b in inputs[i + 1:])
    assert inputs[0] == {"kind": "sa", "value": 2.0, "period": 0.5, "label": "sa=2@0.5s", "level": None}


def test_a_directional_record_cannot_be_remapped_by_components():
    exp = experiment(ONE)
    record = load_record(exp, exp.record("one"))
    with pytest.raises(ParameterError, match="maps its components to x, y, z itself"):
        ground_acceleration(record, ("h2", "h1", "v"))
