"""Record readers: the real PEER files, the other formats, and malformed files."""

import math

import numpy as np
import pytest
from conftest import CHUETSU, G, MANJIL, RECORDS, at2_values

from bearingfw.motion import Record, RecordFormatError, Trace, assemble, read_at2, read_record, resample
from bearingfw.motion.errors import UnknownReaderError
from bearingfw.parameters import ParameterError


def test_copied_records_keep_their_crlf_line_ends():
    for path in CHUETSU + MANJIL:
        raw = path.read_bytes()
        assert b"\r\n" in raw and raw.count(b"\n") == raw.count(b"\r\n"), path.name
    assert (RECORDS / "README.md").is_file()


@pytest.mark.parametrize("files", [CHUETSU, MANJIL], ids=["chuetsu", "manjil"])
def test_real_record_peaks_equal_file_maximum_times_g(files):
    record = read_record(files)
    for path, values in zip(files, record.components):
        expected = max(abs(v) for v in at2_values(path)) * G
        assert math.isclose(np.max(np.abs(values)), expected, rel_tol=1e-12), path.name


def test_chuetsu_header_data(chuetsu):
    assert chuetsu.n == 6000 and chuetsu.dt == pytest.approx(0.01)
    assert chuetsu.names == ("EW", "NS", "UD")
    assert chuetsu.source_units == ("g", "g", "g")
    assert not chuetsu.padded
    # Sample by sample, not just the peak: the first values of the NS file, in m/s^2.
    assert chuetsu.h2[:3] == pytest.approx(np.array([-0.4825759e-04, -0.4824364e-04, -0.4821235e-04]) * G, rel=1e-12)


def test_manjil_unequal_lengths_are_padded_and_reported(manjil):
    lengths = tuple(len(at2_values(p)) for p in MANJIL)
    assert lengths[0] != lengths[1]  # the premise of the test
    assert manjil.n == max(lengths)
    assert manjil.original_lengths == lengths
    assert manjil.padded
    assert set(manjil.padded_components) == {n for n, k in zip(manjil.names, lengths) if k < max(lengths)}
    short = manjil.h2
    assert np.all(short[lengths[1]:] == 0.0)
    assert short[lengths[1] - 1] == pytest.approx(at2_values(MANJIL[1])[-1] * G, rel=1e-12)


def _old_style(text: str) -> str:
    lines = text.split("\r\n")
    npts, dt = lines[3].replace("NPTS=", "").replace("DT=", "").replace("SEC", "").split(",")
    lines[3] = f"  {int(npts)}    {float(dt):.4f}    NPTS, DT"
    return "\r\n".join(lines)


def test_both_at2_header_styles_read_the_same(tmp_path):
    source = MANJIL[2]
    old = tmp_path / "old_style.AT2"
    old.write_text(_old_style(source.read_bytes().decode("ascii")), newline="")
    assert "NPTS, DT" in old.read_text()
    (new_trace,), (old_trace,) = read_at2(source), read_at2(old)
    assert old_trace.dt == new_trace.dt == pytest.approx(0.02)
    np.testing.assert_array_equal(old_trace.values, new_trace.values)


def test_columns_with_time_column_and_units_in_names(tmp_path):
    t = np.arange(500) * 0.004
    data = np.column_stack([t, np.sin(t), 2 * np.cos(t), 0.5 * t])
    path = tmp_path / "motion.csv"
    np.savetxt(path, data, delimiter=",", header="time [s],EW [cm/s^2],NS [cm/s^2],Z [cm/s^2]", comments="")
    record = read_record(path)
    assert record.dt == pytest.approx(0.004)
    assert record.names == ("EW", "NS", "Z")
    np.testing.assert_allclose(record.h2, 0.02 * np.cos(t), atol=1e-12)


def test_whitespace_columns_with_given_dt_and_units(tmp_path):
    values = np.random.default_rng(3).normal(size=(200, 3))
    path = tmp_path / "motion.txt"
    np.savetxt(path, values)
    with pytest.raises(RecordFormatError, match="dt"):
        read_record(path, units="g")  # no time column, no dt
    with pytest.raises(RecordFormatError, match="units"):
        read_record(path, dt=0.01)  # units unknown
    record = read_record(path, dt=0.01, units="g")
    np.testing.assert_allclose(record.components.T, values * G, rtol=1e-6)


def test_unnamed_time_column_is_recognised(tmp_path):
    t = 1.0 + np.arange(300) * 0.005
    values = np.random.default_rng(4).normal(size=(300, 3))
    path = tmp_path / "with_time.txt"
    np.savetxt(path, np.column_stack([t, values]), header="units: m/s^2")
    record = read_record(path)
    assert record.dt == pytest.approx(0.005)
    np.testing.assert_allclose(record.components.T, values, rtol=1e-6)


def test_three_single_column_files_form_one_record_in_order(tmp_path):
    paths = []
    for k, name in enumerate(("a", "b", "c")):
        path = tmp_path / f"{name}.dat"
        path.write_text("# units: m/s^2\n# dt: 0.01\n" + "\n".join(str(k + 0.001 * i) for i in range(50)) + "\n")
        paths.append(path)
    record = read_record([paths[2], paths[0], paths[1]])
    assert record.h1[0] == 2 and record.h2[0] == 0 and record.v[0] == 1


def test_npz_round_trip(tmp_path, manjil):
    path = manjil.to_npz(tmp_path / "manjil.npz")
    again = read_record(path)
    np.testing.assert_array_equal(again.components, manjil.components)
    assert again.dt == manjil.dt and again.names == manjil.names


def test_npz_stacked_array_and_time(tmp_path):
    t = np.arange(100) * 0.02
    acc = np.vstack([np.sin(t), np.cos(t), t]) * 100.0
    np.savez(tmp_path / "stack.npz", acc=acc, time=t, units="cm/s^2")
    record = read_record(tmp_path / "stack.npz")
    assert record.dt == pytest.approx(0.02)
    np.testing.assert_allclose(record.components, acc / 100.0)


def test_mixed_time_steps_are_resampled_to_the_finest():
    t_fine = np.arange(0, 4, 0.005)
    t_coarse = np.arange(0, 4, 0.02)
    traces = [
        Trace(np.sin(2 * np.pi * 1.5 * t_fine), 0.005, "m/s^2"),
        Trace(np.sin(2 * np.pi * 1.5 * t_coarse), 0.02, "m/s^2"),
        Trace(np.cos(2 * np.pi * 1.0 * t_coarse), 0.02, "g"),
    ]
    record = assemble(traces)
    assert record.dt == 0.005
    interior = slice(100, 600)
    np.testing.assert_allclose(record.h2[interior], record.h1[interior], atol=0.01)
    np.testing.assert_allclose(record.v[interior], G * np.cos(2 * np.pi * record.time[interior]), atol=0.01 * G)


def test_resample_down_and_rejects_incommensurate_steps():
    t = np.arange(0, 5, 0.005)
    x = np.sin(2 * np.pi * 2.0 * t)
    y = resample(x, 0.005, 0.01)
    assert y.size == math.ceil(x.size / 2)
    np.testing.assert_allclose(y[50:-50], x[::2][50:-50], atol=0.01)
    with pytest.raises(ParameterError, match="cannot resample"):
        resample(x, 0.005, 0.005 * math.pi)


def test_record_rejects_unequal_lengths_and_nan():
    with pytest.raises(ParameterError, match="equal lengths"):
        Record(h1=np.zeros(10), h2=np.zeros(9), v=np.zeros(10), dt=0.01)
    with pytest.raises(ParameterError, match="non-finite"):
        Record(h1=np.array([0.0, np.nan]), h2=np.zeros(2), v=np.zeros(2), dt=0.01)
    with pytest.raises(ParameterError, match="dt"):
        Record(h1=np.zeros(2), h2=np.zeros(2), v=np.zeros(2), dt=-0.01)


def test_wrong_number_of_components_names_the_files():
    with pytest.raises(ParameterError, match=r"3 acceleration components.*RSN4843_CHUETSU_65006EW.AT2: 1"):
        read_record(CHUETSU[:2])


def test_unknown_format_lists_the_readers(tmp_path):
    path = tmp_path / "motion.xyz"
    path.write_bytes(b"\x00\x01binary")
    with pytest.raises(UnknownReaderError, match="peer-at2"):
        read_record(path)
    with pytest.raises(UnknownReaderError, match="unknown record format 'nope'"):
        read_record(CHUETSU, format="nope")


# -- malformed files: every error names the file and the line --------------------------------


def _lines(path):
    return path.read_bytes().decode("ascii").split("\r\n")


def _write(tmp_path, lines, name="bad.AT2"):
    path = tmp_path / name
    path.write_bytes("\r\n".join(lines).encode("ascii"))
    return path


def _replace_token(line: str, new: str) -> str:
    tokens = line.split()
    tokens[2] = new
    return "   ".join(tokens)


def _truncated(lines):
    kept = lines[:600] + [""]  # cut after line 600, with its line end
    return kept, 600, "truncated"


def _npts_too_small(lines):
    npts = len(at2_values(CHUETSU[0]))
    lines = list(lines)
    lines[3] = lines[3].replace(f"NPTS=   {npts}", f"NPTS=   {npts - 10}")
    per_line = len(lines[4].split())
    return lines, 5 + (npts - 10) // per_line, "more values than NPTS"


def _npts_too_large(lines):
    lines = list(lines)
    lines[3] = lines[3].replace("NPTS=   6000", "NPTS=   6007")
    last = max(i for i, line in enumerate(lines) if line.strip()) + 1  # the last line holding data
    return lines, last, "truncated"


def _non_numeric(lines):
    lines = list(lines)
    lines[99] = _replace_token(lines[99], "0.12x3")
    return lines, 100, "not a number"


def _nan(lines):
    lines = list(lines)
    lines[199] = _replace_token(lines[199], "NaN")
    return lines, 200, "not finite"


def _negative_dt(lines):
    lines = list(lines)
    lines[3] = lines[3].replace("DT=   .0100", "DT=  -.0100")
    return lines, 4, "must be > 0"


def _zero_dt(lines):
    lines = list(lines)
    lines[3] = lines[3].replace("DT=   .0100", "DT=   .0000")
    return lines, 4, "must be > 0"


@pytest.mark.parametrize(
    "corrupt", [_truncated, _npts_too_small, _npts_too_large, _non_numeric, _nan, _negative_dt, _zero_dt]
)
def test_malformed_at2_names_file_and_line(tmp_path, corrupt):
    lines, line, what = corrupt(_lines(CHUETSU[0]))
    path = _write(tmp_path, lines)
    with pytest.raises(RecordFormatError, match=what) as info:
        read_record([path, CHUETSU[1], CHUETSU[2]])
    message = str(info.value)
    assert str(path) in message and f"line {line}:" in message, message
    assert info.value.line == line


def test_malformed_at2_header(tmp_path):
    lines = _lines(CHUETSU[0])
    lines[3] = "points: 6000"
    with pytest.raises(RecordFormatError, match=r"bad.AT2, line 4: expected 'NPTS="):
        read_at2(_write(tmp_path, lines))
    with pytest.raises(RecordFormatError, match=r"line 3: the file ends inside the 4-line PEER header"):
        read_at2(_write(tmp_path, lines[:2]))


@pytest.mark.parametrize(
    "rows, line, what",
    [
        (["t,a,b,c [g]", "0,1,2,3", "0.01,1,2", "0.02,1,2,3"], 3, "3 values where the first data row has 4"),
        (["t,a [g],b [g],c [g]", "0,1,2,3", "0.01,1,x,3", "0.02,1,2,3"], 3, "'x' is not a number"),
        (["t,a [g],b [g],c [g]", "0,1,2,3", "0.01,1,nan,3", "0.02,1,2,3"], 3, "not finite"),
        (["t,a [g],b [g],c [g]", "0,1,2,3", "-0.01,1,2,3", "0.02,1,2,3"], 3, "must increase"),
        (["t,a [g],b [g],c [g]", "0,1,2,3"], 2, "at least 2 rows"),
        (["# units: g", "# dt: -0.01", "1 2 3", "4 5 6"], 2, "must be > 0"),
        (["# units: g", "# dt: 0", "1 2 3", "4 5 6"], 2, "must be > 0"),
    ],
    ids=["short-row", "non-numeric", "nan", "time-backwards", "truncated", "negative-dt", "zero-dt"],
)
def test_malformed_columns_name_file_and_line(tmp_path, rows, line, what):
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(RecordFormatError, match=what) as info:
        read_record(path)
    assert f"{path}, line {line}:" in str(info.value)


def test_zero_dt_option_is_rejected(tmp_path):
    path = tmp_path / "cols.txt"
    path.write_text("1 2 3\n4 5 6\n7 8 8\n")
    with pytest.raises(RecordFormatError, match=r"cols.txt: dt = 0.0 s; the time step must be > 0"):
        read_record(path, dt=0.0, units="g")


def test_malformed_npz_names_array_and_index(tmp_path):
    h = np.zeros(20)
    h[7] = np.nan
    np.savez(tmp_path / "bad.npz", h1=np.zeros(20), h2=h, v=np.zeros(20), dt=0.01, units="g")
    with pytest.raises(RecordFormatError, match=r"bad.npz, array 'h2', index 7: value nan is not finite"):
        read_record(tmp_path / "bad.npz")
    np.savez(tmp_path / "neg.npz", h1=np.zeros(20), h2=np.zeros(20), v=np.zeros(20), dt=-0.01, units="g")
    with pytest.raises(RecordFormatError, match=r"neg.npz: array 'dt' = -0.01 s; the time step must be > 0"):
        read_record(tmp_path / "neg.npz")
