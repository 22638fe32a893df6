"""A record that lasts less than one integration step is refused before any cell runs, naming
``records.<name>`` and ``integration.dt_integration``. Before the fix the cell failed (exit 1) with
the internal "Record: 'h1' must be a 1-D array of at least 2 numbers"."""

from __future__ import annotations

import pytest
from tiny_experiment import write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment.records import check_length, load_record, scaled_record
from bearingfw.experiment.spec import SpecError, parse_experiment
from bearingfw.motion import ScaleTarget
from bearingfw.parameters import ParameterError

TREMOR = "[records.tremor]\nseed = 1\ntremor = { duration = 10.0, dt = 0.01, decay = 2.0 }"


def at2(folder, npts: int, dt: str):
    values = [0.011 * (-1) ** k * (1 + k % 7) for k in range(npts)]
    path = folder / "short.AT2"
    path.write_text(
        "PEER NGA STRONG MOTION DATABASE RECORD\nTest, station, EW\nACCELERATION TIME SERIES IN UNITS OF G\n"
        f"NPTS= {npts}, DT= {dt} SEC\n" + "\n".join(" ".join(f"{v:.6E}" for v in values[i:i + 5])
                                                for i in range(0, npts, 5)) + "\n"
    )
    return path


def experiment(folder, dt_integration: float):
    return parse_experiment(
        f'name = "short"\n[models.M1]\npreset = "M1"\n[records.ew]\nx = "short.AT2"\n[intensities]\n'
        f'levels = ["as-recorded"]\n[integration]\ndt_integration = {dt_integration}\n', base_dir=folder,
    )


def test_a_record_shorter_than_one_integration_step_is_refused_naming_both_keys(tmp_path):
    at2(tmp_path, 1000, ".00001")  # 1000 samples over 0.00999 s; the reviewer's file
    exp = experiment(tmp_path, 0.01)
    with pytest.raises(SpecError) as caught:
        load_record(exp, exp.record("ew"))
    message = str(caught.value)
    assert message.startswith("records.ew: the record lasts 0.00999 s (1000 samples at dt = 1e-05 s), which gives "
                              "1 sample(s) at integration.dt_integration = 0.01 s, fewer than the 2")
    assert "use a dt_integration below 0.01 s" in message and "or a longer record" in message


def test_one_more_sample_is_enough_and_gives_two_steps(tmp_path):
    at2(tmp_path, 1001, ".00001")  # 1001 x 1e-5 s = 0.01001 s: ceil(1.001) = 2 samples at 0.01 s
    exp = experiment(tmp_path, 0.01)
    record = load_record(exp, exp.record("ew"))
    resampled = scaled_record(record, ScaleTarget(kind="as-recorded"), dt_integration=0.01, min_peak_ratio=None)
    assert resampled.n == 2 and resampled.dt == 0.01


def test_scaled_record_refuses_it_too_with_the_same_reason(tmp_path):
    at2(tmp_path, 1000, ".00001")
    record = load_record(experiment(tmp_path, 0.00001), experiment(tmp_path, 0.00001).record("ew"))  # divides: kept
    assert record.n == 1000
    with pytest.raises(ParameterError, match=r"gives 1 sample\(s\) at integration.dt_integration = 0.01 s"):
        scaled_record(record, ScaleTarget(kind="as-recorded"), dt_integration=0.01)


def test_a_step_that_divides_the_record_s_never_shortens_it(tmp_path):
    at2(tmp_path, 2, ".0100")  # two samples, 0.01 s: integrated at 0.005 s with sub-steps, no resampling
    exp = experiment(tmp_path, 0.005)
    record = load_record(exp, exp.record("ew"))
    check_length(record, 0.005)
    check_length(record, None)
    assert record.n == 2


def test_the_cli_exits_2_before_any_cell_runs(tmp_path, capsys):
    folder = tmp_path / "spec"
    folder.mkdir()
    at2(folder, 1000, ".00001")
    spec = write_tiny(folder, models=("M0",), levels=("as-recorded",), **{TREMOR: '[records.ew]\nx = "short.AT2"'})
    out = tmp_path / "out"
    code = main(["run", str(spec), "--out", str(out), "--executor", "serial", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    assert err.startswith("bearingfw run: error: records.ew: the record lasts 0.00999 s")
    assert "integration.dt_integration = 0.01 s" in err
    assert not (out / "cells").exists()
