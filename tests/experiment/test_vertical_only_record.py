"""A record with no horizontal motion (only ``z``): it runs as recorded, with t_Ha and the degree
reported as undefined; a level or a pga_h10/pga/sa target is refused before any cell runs, naming
``records.<name>``. Before the fix both failed with "the acceleration is zero everywhere" and no key."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from tiny_experiment import write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment.records import load_record, record_info, scaled_record
from bearingfw.experiment.spec import SpecError, parse_experiment
from bearingfw.motion import G, load_directional, record_degree, record_summary, record_t_ha, t_ha
from bearingfw.motion.metrics import has_horizontal_motion
from bearingfw.parameters import ParameterError

RECORDS = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"
UD = RECORDS / "RSN4843_CHUETSU_65006UD.AT2"
TREMOR = "[records.tremor]\nseed = 1\ntremor = { duration = 10.0, dt = 0.01, decay = 2.0 }"


def ud_values() -> np.ndarray:
    """The UD component's values (g) from its PEER file."""
    return np.array([float(t) for line in UD.read_text().splitlines()[4:] for t in line.split()])


def experiment(intensities: str):
    return parse_experiment(
        f'name = "v"\n[models.M1]\npreset = "M1"\n[records.ew]\nz = "{UD.name}"\n[intensities]\n{intensities}\n',
        base_dir=RECORDS,
    )


def test_the_horizontal_measures_of_a_vertical_only_record_are_undefined_not_errors():
    record = load_directional({"z": UD})
    assert not has_horizontal_motion(record) and np.any(record.v)
    assert math.isnan(record_t_ha(record)) and record_degree(record) is None
    summary = record_summary(record, periods=[0.5])
    assert summary["t_ha"] is None and summary["pga_h10"] == 0.0 and summary["arias"] == 0.0
    assert summary["pga"]["v"] > 0.5  # the vertical is there: 0.65 m/s^2
    with pytest.raises(ParameterError, match="zero everywhere"):  # the array function keeps its contract
        t_ha(record.h1, record.h2, record.dt)
    # With horizontal motion nothing changes.
    both = load_directional({"x": RECORDS / "RSN4843_CHUETSU_65006EW.AT2", "z": UD})
    assert has_horizontal_motion(both) and record_t_ha(both) == pytest.approx(t_ha(both.h1, both.h2, both.dt))


def test_as_recorded_loads_and_reports_undefined_measures():
    exp = experiment('levels = ["as-recorded"]')
    record = load_record(exp, exp.record("ew"))
    info = record_info(scaled_record(record, exp.intensity_list[0], exp.intensities, 0.01))
    assert math.isnan(info["t_ha"]) and info["degree"] is None and info["pga_h10"] == 0.0
    peak = np.max(np.abs(ud_values())) * G  # the vertical's own peak, as recorded
    assert info["scale_factor"] == 1.0 and info["components"][2]["pga"] == pytest.approx(peak, rel=1e-12)


@pytest.mark.parametrize(
    ("intensities", "named"),
    [('levels = ["D_0"]', "D_0"), ('levels = ["as-recorded", "D_II"]', "D_II"), ("pga_h10 = [0.5]", "PGA_H10=0.5"),
     ("pga = [2.0]", "pga=2"), ("sa = [1.0]\nperiod = 0.5", "sa=1@0.5s"), ("sa = [1.0]\nperiod = \"T1\"", "sa=1@T1")],
)
def test_a_scaled_intensity_on_a_vertical_only_record_is_refused_naming_the_record(intensities, named):
    exp = experiment(intensities)
    with pytest.raises(SpecError) as caught:
        load_record(exp, exp.record("ew"))
    message = str(caught.value)
    assert message.startswith("records.ew: the record has no horizontal motion (x and y are zero everywhere: only z")
    assert f"cannot be scaled to the intensities {named}" in message
    assert 'levels = ["as-recorded"]' in message


def vertical_csv(folder: Path) -> Path:
    """The first 4 s of the Chuetsu-oki UD component as a CSV (g, dt = 0.01 s)."""
    values = ud_values()[:400]
    path = folder / "ud.csv"
    path.write_text("# dt: 0.01\n# units: g\n" + "".join(f"{float(v)!r}\n" for v in values))
    return path


def run(capsys, *argv):
    code = main(["run", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_a_vertical_only_study_runs_as_recorded_and_is_refused_at_a_level(tmp_path, capsys):
    folder = tmp_path / "spec"
    folder.mkdir()
    vertical_csv(folder)
    spec = write_tiny(folder, models=("M0",), levels=("as-recorded",), **{TREMOR: '[records.ud]\nz = "ud.csv"'})
    out = tmp_path / "out"
    code, _, err = run(capsys, str(spec), "--out", str(out), "--executor", "serial", "--quiet")
    assert code == 0, err
    records = json.loads((out / "records.json").read_text())["ud"]
    assert records["t_ha"] is None and records["degree"] is None and records["pga_h10"] == 0.0
    assert records["intensities"]["as-recorded"]["degree"] is None
    cell = json.loads((out / "cells" / "M0" / "ud" / "as-recorded.json").read_text())
    assert cell["status"] == "ok" and cell["record_measures"]["t_ha"] is None
    report = (out / "report.md").read_text()
    assert "| undefined | 0 | undefined (no horizontal motion) |" in report and "| 1, undefined |" in report

    spec = write_tiny(folder, models=("M0",), levels=("as-recorded", "D_0"), **{TREMOR: '[records.ud]\nz = "ud.csv"'})
    out = tmp_path / "out2"
    code, stdout, err = run(capsys, str(spec), "--out", str(out), "--executor", "serial", "--quiet")
    assert code == 2 and stdout == "" and "Traceback" not in err
    assert err.startswith("bearingfw run: error: records.ud: the record has no horizontal motion")
    assert not (out / "cells").exists()  # refused before any cell ran


def test_record_info_prints_a_vertical_only_record(capsys):
    assert main(["record", "info", "--z", str(UD)]) == 0
    out = capsys.readouterr().out
    assert "t_Ha    = undefined  (no horizontal motion" in out and "Degree  = undefined  (no horizontal motion" in out
    assert "PGA_H10 = 0 m/s^2" in out
    assert main(["record", "info", "--z", str(UD), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["t_ha"] is None and data["degree"] is None
    assert main(["record", "info", "--z", str(UD), "--level", "D_0"]) == 2
    err = capsys.readouterr().err
    assert "PGA_H10 is zero (no horizontal motion)" in err and "used as recorded" in err
