"""A time stated with a unit (a time column ``time [ms]``, ``# dt: 5 ms``, ``DT= 10 MSEC``) is read in
that unit; a unit that is not a time unit is refused naming where it is and the units allowed. Before
the fix the column's unit was ignored: times in ms were read as seconds (1000 times too long)."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw.cli.main import main
from bearingfw.motion import G, RecordFormatError, read_at2, read_columns

VALUES = [0.011, -0.0076, 0.0109, 0.019, -0.022, 0.003]  # g


def columns_file(tmp_path, header: str, times, name="rec.csv"):
    rows = "\n".join(f"{t!r},{a!r}" for t, a in zip(times, VALUES))
    path = tmp_path / name
    path.write_text(f"{header}\n{rows}\n")
    return path


@pytest.mark.parametrize(
    ("header", "times", "dt"),
    [
        ("time [ms],EW [g]", [0.0, 0.5, 1.0, 1.5, 2.0, 2.5], 0.0005),  # the reviewer's file: 0.5 ms, not 0.5 s
        ("time [ms],EW [g]", [0, 10, 20, 30, 40, 50], 0.01),  # 10 ms: was refused as "10 s"
        ("Time (msec),EW [g]", [0, 10, 20, 30, 40, 50], 0.01),
        ("time ms,EW [g]", [0, 10, 20, 30, 40, 50], 0.01),  # a unit without brackets
        ("time_ms,EW [g]", [0, 10, 20, 30, 40, 50], 0.01),
        ("t_s,EW [g]", [0.0, 0.01, 0.02, 0.03, 0.04, 0.05], 0.01),
        ("t [s],EW [g]", [0.0, 0.01, 0.02, 0.03, 0.04, 0.05], 0.01),
        ("time (SEC.),EW [g]", [0.0, 0.01, 0.02, 0.03, 0.04, 0.05], 0.01),
        ("time in seconds,EW [g]", [0.0, 0.01, 0.02, 0.03, 0.04, 0.05], 0.01),
        ("time,EW [g]", [0.0, 0.01, 0.02, 0.03, 0.04, 0.05], 0.01),  # no unit: seconds, as documented
    ],
)
def test_the_time_column_is_read_in_its_unit(tmp_path, header, times, dt):
    (trace,) = read_columns(columns_file(tmp_path, header, times))
    assert trace.dt == pytest.approx(dt, rel=1e-12)
    assert np.array_equal(trace.values, VALUES) and trace.units == "g" and trace.label == "EW"


@pytest.mark.parametrize("unit", ["min", "h", "mm/s2", "g", "us", "since trigger"])
def test_a_time_column_in_another_unit_is_refused_naming_the_column(tmp_path, unit):
    header = f"time [{unit}],EW [g]" if unit != "since trigger" else f"time {unit},EW [g]"
    path = columns_file(tmp_path, header, [0, 1, 2, 3, 4, 5])
    with pytest.raises(RecordFormatError) as caught:
        read_columns(path)
    message = str(caught.value)
    assert f"line 1: the time column '{header.split(',')[0]}': '{unit}' is not a time unit" in message
    assert "allowed: s (sec, seconds) or ms (msec, milliseconds)" in message


@pytest.mark.parametrize(("comment", "dt"), [("5 ms", 0.005), ("0.005 s", 0.005), ("0.005s", 0.005),
                                             ("5e-3", 0.005), ("2 msec", 0.002)])
def test_a_dt_comment_may_carry_a_time_unit(tmp_path, comment, dt):
    path = tmp_path / "rec.txt"
    path.write_text(f"# dt: {comment}\n# units: g\n" + "\n".join(map(repr, VALUES)) + "\n")
    (trace,) = read_columns(path)
    assert trace.dt == pytest.approx(dt, rel=1e-12)


def test_a_dt_comment_in_another_unit_is_refused(tmp_path):
    path = tmp_path / "rec.txt"
    path.write_text("# dt: 1 min\n# units: g\n0.1\n0.2\n0.3\n")
    with pytest.raises(RecordFormatError, match=r"line 1: the '# dt' comment: 'min' is not a time unit; allowed: s"):
        read_columns(path)


def at2_file(tmp_path, dt_text: str):
    path = tmp_path / "rec.AT2"
    path.write_text(
        "PEER NGA STRONG MOTION DATABASE RECORD\nTest, station, EW\nACCELERATION TIME SERIES IN UNITS OF G\n"
        f"NPTS=    6, DT= {dt_text}\n" + "  ".join(map(repr, VALUES)) + "\n"
    )
    return path


@pytest.mark.parametrize(("dt_text", "dt"), [(".0100 SEC", 0.01), ("10 MSEC", 0.01), ("1.0E-02SEC", 0.01),
                                             (".0050", 0.005), ("5 ms", 0.005)])
def test_the_at2_time_step_is_read_in_its_unit(tmp_path, dt_text, dt):
    (trace,) = read_at2(at2_file(tmp_path, dt_text))
    assert trace.dt == pytest.approx(dt, rel=1e-12)
    assert np.allclose(trace.values * G, np.array(VALUES) * G)


def test_an_at2_time_step_in_another_unit_is_refused(tmp_path):
    with pytest.raises(RecordFormatError, match=r"line 4: DT: 'MIN' is not a time unit; allowed: s \(sec, seconds\)"):
        read_at2(at2_file(tmp_path, "0.01 MIN"))


def test_record_info_reports_the_ms_column_in_seconds_and_refuses_minutes(tmp_path, capsys):
    times = np.arange(1000) * 0.5  # ms
    path = tmp_path / "h_ms2.csv"
    path.write_text("time [ms],EW [g]\n" + "".join(f"{t},{0.01 * np.sin(t)}\n" for t in times))
    assert main(["record", "info", "--x", str(path)]) == 0
    assert "1000 samples at dt = 0.0005 s (0.50 s)" in capsys.readouterr().out
    path.write_text("time [min],EW [g]\n" + "".join(f"{t},{0.01 * np.sin(t)}\n" for t in times))
    assert main(["record", "info", "--x", str(path)]) == 2
    err = capsys.readouterr().err
    assert "the time column 'time [min]': 'min' is not a time unit" in err and "Traceback" not in err
