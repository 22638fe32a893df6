"""Record readers: the real PEER files, the other formats, and malformed files."""

import math
import re

import numpy as np
import pytest
from motion_records import CHUETSU, G, MANJIL, RECORDS, at2_values

import types

from bearingfw.motion import (
    Record,
    RecordFormatError,
    Trace,
    assemble,
    find_reader,
    fourier_spectrum,
    read_at2,
    read_record,
    record_summary,
    resample,
    synthetic_tremor,
)
from bearingfw.motion.errors import UnknownReaderError
from bearingfw.parameters import ParameterError
from bearingfw.plugins.contracts import RecordReader, check_suffixes


def test_copied_records_keep_their_crlf_line_ends():
    for path in CHUETSU + MANJIL:
        raw = path.read_bytes()
        assert b"\r\n" in raw and raw.count(b"\n") == raw.count(b"\r\n"), path.name
    assert (RECORDS / "README.md").is_file()


MIXED = [CHUETSU[0], MANJIL[1], MANJIL[2]]  # 0.01 s and 0.02 s: two components are resampled


@pytest.mark.parametrize("files", [CHUETSU, MANJIL, MIXED], ids=["chuetsu", "manjil", "mixed-dt"])
def test_real_record_peaks_equal_file_maximum_times_g(files):
    # The acceptance check is on each file's trace as read, before any resampling.
    record = read_record(files)
    summary = record_summary(record)
    for i, path in enumerate(files):
        expected = max(abs(v) for v in at2_values(path)) * G
        (trace,) = read_at2(path)
        assert math.isclose(np.max(np.abs(trace.in_si())), expected, rel_tol=1e-12), path.name
        assert math.isclose(summary["components"][i]["pga_before_resampling"], expected, rel_tol=1e-12), path.name
        if not record.was_resampled[i]:
            assert math.isclose(np.max(np.abs(record.components[i])), expected, rel_tol=1e-12), path.name


def test_resampled_peaks_are_reported_before_and_after():
    record = read_record(MIXED)
    assert record.dt == pytest.approx(0.01)
    assert record.was_resampled == (False, True, True)
    assert record.resampled_components == ("T", "V")
    # Band-limited upsampling raises the peaks (Manjil T by about 4 %): the record says so.
    before = [max(abs(v) for v in at2_values(p)) * G for p in MIXED]
    assert record.metadata["peaks_before_resampling"] == pytest.approx(before, rel=1e-12)
    assert np.max(np.abs(record.h2)) > 1.02 * before[1]
    notes = record.notes
    assert len(notes) == 2 and all("resampled from dt = 0.02 s to 0.01 s" in n for n in notes)
    assert f"{before[1]:.4g} m/s^2 before" in notes[0]
    summary = record_summary(record)
    assert [c["resampled"] for c in summary["components"]] == [False, True, True]
    assert summary["notes"] == list(notes)
    # Scaling scales the stored peaks with the record.
    scaled = record.scaled(2.0)
    assert record_summary(scaled)["components"][1]["pga_before_resampling"] == pytest.approx(2 * before[1])


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
    assert again.padded_components == manjil.padded_components and again.lengths == manjil.lengths
    assert again.source_units == ("g", "g", "g")
    assert again.source == manjil.source and again.title == manjil.title


def test_npz_round_trip_keeps_scale_factor_and_synthetic_metadata(tmp_path, manjil):
    scaled = manjil.scaled(2.5)
    again = read_record(scaled.to_npz(tmp_path / "scaled.npz"))
    np.testing.assert_array_equal(again.components, scaled.components)
    assert again.metadata["scale_factor"] == 2.5
    assert again.source == manjil.source and again.title == scaled.title  # not "scaled x2.5" twice
    assert again.padded_components == manjil.padded_components
    tremor = synthetic_tremor(3).resampled(0.0025)
    back = read_record(tremor.to_npz(tmp_path / "tremor.npz"))
    assert back.synthetic and back.title == tremor.title
    assert back.metadata["seed"] == 3 and back.metadata["parameters"] == tremor.metadata["parameters"]
    assert back.was_resampled == tremor.was_resampled == (True, True, True)
    assert back.notes == tremor.notes


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


@pytest.mark.parametrize("n, dt_from, dt_to", [(1000, 0.005, 0.01), (999, 0.005, 0.01), (301, 0.02, 0.005), (77, 0.01, 0.004)])
def test_resample_covers_the_input_up_to_its_last_sample_plus_one_step(n, dt_from, dt_to):
    y = resample(np.ones(n), dt_from, dt_to)
    # One output sample at every k dt_to < n dt_from, as the docstring says.
    assert (y.size - 1) * dt_to < n * dt_from - 1e-12 and y.size * dt_to >= n * dt_from - 1e-12


@pytest.mark.parametrize("dt_to", [0, 0.0, -0.01, float("nan")])
def test_resample_rejects_a_non_positive_step(dt_to):
    with pytest.raises(ParameterError, match=r"dt_to = .* is outside the allowed range dt_to > 0"):
        resample(np.ones(10), 0.01, dt_to)
    with pytest.raises(ParameterError, match=r"dt_from = .* is outside the allowed range dt_from > 0"):
        resample(np.ones(10), dt_to, 0.01)


def test_resampling_to_a_coarser_step_removes_what_would_alias():
    dt, coarse = 0.005, 0.02  # Nyquist 100 Hz -> 25 Hz: 40 Hz would fold onto 10 Hz
    t = np.arange(0, 20, dt)
    x = np.sin(2 * np.pi * 2.0 * t) + np.sin(2 * np.pi * 40.0 * t)
    y = resample(x, dt, coarse)
    f, amplitude = fourier_spectrum(y, coarse)
    at = lambda freq: amplitude[np.argmin(np.abs(f - freq))]  # noqa: E731
    assert at(2.0) == pytest.approx(20.0 / 2, rel=0.02)  # A T / 2 of the kept 2 Hz sine
    assert at(10.0) < 0.01 * at(2.0)  # plain decimation x[::4] would put the 40 Hz sine here
    f_naive, naive = fourier_spectrum(x[::4], coarse)
    assert naive[np.argmin(np.abs(f_naive - 10.0))] > 0.5 * at(2.0)


def test_resampling_a_padded_record_keeps_its_padding_zero(manjil):
    fine = manjil.resampled(0.005)
    assert fine.padded_components == manjil.padded_components
    for values, k_old, k_new in zip(fine.components, manjil.original_lengths, fine.original_lengths):
        assert k_new == 4 * k_old
        assert np.all(values[k_new:] == 0.0)  # the filter's ringing stays inside the component
    # Each component is the component resampled on its own, not the padded one.
    short = manjil.original_lengths[1]
    np.testing.assert_allclose(fine.h2[: 4 * short], resample(manjil.h2[:short], 0.02, 0.005), rtol=0, atol=1e-12)


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


# -- what a file states wins over the arguments ---------------------------------------------


def test_units_argument_is_only_for_files_that_do_not_state_units(tmp_path):
    with pytest.raises(RecordFormatError, match="states g but units = 'cm/s\\^2' was given") as info:
        read_record(CHUETSU, units="cm/s^2")
    assert info.value.path == str(CHUETSU[0]) and info.value.line == 3
    assert read_record(CHUETSU, units="G").source_units == ("g", "g", "g")  # agreeing is fine
    # Columns: a '# units' comment and a bracketed unit are statements too.
    path = tmp_path / "stated.txt"
    path.write_text("# units: g\n# dt: 0.01\n1 2 3\n-4 5 6\n")
    with pytest.raises(RecordFormatError, match=r"stated.txt, line 1: the '# units' comment states g but units = 'm/s\^2'"):
        read_record(path, units="m/s^2")
    named = tmp_path / "named.csv"
    named.write_text("a [cm/s^2],b [cm/s^2],c [cm/s^2]\n1,2,3\n-4,5,6\n")
    with pytest.raises(RecordFormatError, match=r"named.csv, line 1: column 'a \[cm/s\^2\]' states cm/s\^2"):
        read_record(named, dt=0.01, units="g")
    # A file that does not state them takes the argument.
    bare = tmp_path / "bare.txt"
    bare.write_text("1 2 3\n-4 5 6\n")
    assert read_record(bare, dt=0.01, units="cm/s^2").h1[1] == pytest.approx(-0.04)
    # .npz: the 'units' array.
    np.savez(tmp_path / "u.npz", h1=np.ones(4), h2=np.ones(4), v=np.ones(4), dt=0.01, units="g")
    with pytest.raises(RecordFormatError, match=r"u.npz: array 'units' states g but units = 'cm/s\^2'"):
        read_record(tmp_path / "u.npz", units="cm/s^2")


def _at2(tmp_path, units_line, data_lines, npts, name="x.AT2"):
    header = _lines(CHUETSU[0])[:2] + [units_line, f"NPTS=   {npts}, DT=   .0100 SEC"]
    return _write(tmp_path, header + data_lines + [""], name)


@pytest.mark.parametrize(
    "units_line, units",
    [
        ("ACCELERATION TIME SERIES IN UNITS OF CM/S^2", "cm/s^2"),
        ("ACCELERATION TIME SERIES IN UNITS OF CM/SEC/SEC", "cm/s^2"),
        ("ACCELERATION TIME SERIES IN UNITS OF G.", "g"),
        ("ACCELERATION (G)", "g"),
        ("ACCELERATION TIME SERIES, UNITS OF (G)", "g"),
        ("acceleration in units of g", "g"),
    ],
)
def test_at2_unit_spellings(tmp_path, units_line, units):
    (trace,) = read_at2(_at2(tmp_path, units_line, ["  .1000000E+01  -.2500000E+01"], 2))
    assert trace.units == units
    np.testing.assert_array_equal(trace.values, [1.0, -2.5])


def test_at2_in_cm_per_s2_is_converted(tmp_path):
    path = _at2(tmp_path, "ACCELERATION TIME SERIES IN UNITS OF CM/S^2", ["  .1250000E+02  -.5000000E+01   .0"], 3)
    record = read_record([path, path, path])
    assert record.source_units == ("cm/s^2",) * 3
    np.testing.assert_allclose(record.h1, [0.125, -0.05, 0.0], rtol=1e-12)


def test_at2_without_units_takes_the_argument(tmp_path):
    path = _at2(tmp_path, "ACCELERATION (FILTERED)", ["  .1  .2"], 2)
    with pytest.raises(RecordFormatError, match=r"line 3: no units on line 3"):
        read_at2(path)
    assert read_at2(path, units="m/s^2")[0].units == "m/s^2"


def test_at2_glued_fixed_width_values(tmp_path):
    data = ["  0.1000000E-02-0.1230000E-02-0.4560000E-02", " -0.7000000E-03+.5E-3 1.0D-03"]
    (trace,) = read_at2(_at2(tmp_path, "UNITS OF G", data, 6))
    np.testing.assert_array_equal(trace.values, [0.001, -0.00123, -0.00456, -0.0007, 0.0005, 0.001])


@pytest.mark.parametrize("token", ["0.1E-02junk", "1_0", "1.0-103", "1.2.3", "0x10", "--1.0"])
def test_at2_line_must_be_read_to_its_end(tmp_path, token):
    # float() would take '1_0'; a tokeniser that stops early would drop 'junk' silently.
    path = _at2(tmp_path, "UNITS OF G", ["  .1   .2", f"  .3  {token}"], 4)
    with pytest.raises(RecordFormatError, match=f"x.AT2, line 6: '{re.escape(token)}' is not a number"):
        read_at2(path)


# -- column files: first rows, delimiters, time columns --------------------------------------


def test_byte_order_mark_does_not_hide_the_first_sample(tmp_path):
    path = tmp_path / "bom.csv"
    path.write_bytes("0.1,0.2,0.3\n-0.4,0.5,0.6\n0.7,0.8,0.9\n".encode("utf-8-sig"))
    record = read_record(path, dt=0.01, units="m/s^2")
    np.testing.assert_array_equal(record.h1, [0.1, -0.4, 0.7])
    commented = tmp_path / "bom_comment.csv"
    commented.write_bytes("# units: g\n# dt: 0.02\n1,2,3\n-4,5,6\n".encode("utf-8-sig"))
    assert read_record(commented).dt == 0.02


def test_latin1_header_is_still_read(tmp_path):
    path = tmp_path / "latin.csv"
    path.write_bytes("time [s],Ost [g],Nord [g],Höhe [g]\n0,1,2,3\n0.01,1,2,3\n0.02,1,2,3\n".encode("latin-1"))
    assert read_record(path).names == ("Ost", "Nord", "Höhe")


def test_a_typo_in_the_first_row_is_an_error_not_a_header(tmp_path):
    path = tmp_path / "typo.csv"
    path.write_text("0.1,0.2,x3\n-0.4,0.5,0.6\n0.7,0.8,0.9\n")
    with pytest.raises(RecordFormatError, match=r"typo.csv, line 1: 'x3' is not a number"):
        read_record(path, dt=0.01, units="g")


def test_trailing_delimiters_are_ignored(tmp_path):
    path = tmp_path / "trailing.csv"
    path.write_text("t,a [g],b [g],c [g],\n0,1,2,3,\n0.01,-1,2,3,\n0.02,1,2,3,\n")
    record = read_record(path)
    assert record.dt == pytest.approx(0.01) and record.names == ("a", "b", "c")
    np.testing.assert_allclose(record.h1 / G, [1, -1, 1])


@pytest.mark.parametrize("header", ["t;a [g];b [g];c [g]\n", "# units: g\n"], ids=["named", "unnamed"])
def test_decimal_commas_with_semicolons(tmp_path, header):
    path = tmp_path / "comma.csv"
    path.write_text(header + "0,00;1,5;-2,5;3,5\n0,01;1,25;2,5;3,5\n0,02;1,5;2,5;3,5\n")
    record = read_record(path)
    assert record.dt == pytest.approx(0.01) and record.n == 3
    np.testing.assert_allclose(record.h1 / G, [1.5, 1.25, 1.5])
    np.testing.assert_allclose(record.h2 / G, [-2.5, 2.5, 2.5])


def test_time_column_is_found_when_dt_is_also_given(tmp_path):
    path = tmp_path / "timed.txt"
    path.write_text("# units: g\n" + "".join(f"{0.005 * k:.3f} {(-1) ** k} 2 3\n" for k in range(20)))
    record = read_record(path, dt=0.005)  # the time column is not taken for a fourth component
    assert record.dt == 0.005 and record.h1[:2] == pytest.approx([G, -G])
    with pytest.raises(RecordFormatError, match=r"timed.txt, line 3: the first column .* gives dt = 0.005 s but dt = 0.01 s"):
        read_record(path, dt=0.01)
    commented = tmp_path / "commented.txt"
    commented.write_text("# dt: 0.01\n" + path.read_text())
    with pytest.raises(RecordFormatError, match=r"commented.txt, line 1: the '# dt' comment gives dt = 0.01 s but"):
        read_record(commented)


@pytest.mark.parametrize("named", [True, False], ids=["named", "unnamed"])
def test_irregular_time_column_is_reported_as_such(tmp_path, named):
    path = tmp_path / "irregular.txt"
    rows = [f"{t:g} {(-1) ** k} 2 3" for k, t in enumerate([0.0, 0.01, 0.02, 0.035, 0.04, 0.05])]
    path.write_text("\n".join((["time ax[g] ay[g] az[g]"] if named else ["# units: g"]) + rows) + "\n")
    with pytest.raises(RecordFormatError, match=r"irregular.txt, line 5: .*time step 0.015 s differs from the mean step"):
        read_record(path)


def test_time_step_tolerance_is_one_per_mille(tmp_path):
    def write(name, jitter):
        # Times k dt +- jitter: each step deviates from dt by up to 2 jitter.
        times = np.arange(50) * 0.01 + jitter * (-1.0) ** np.arange(50)
        path = tmp_path / name
        path.write_text("# units: g\n" + "".join(f"{t:.8f} {(-1) ** k} 2 3\n" for k, t in enumerate(times)))
        return path

    assert read_record(write("jitter.txt", 0.4e-3 * 0.01 / 2)).dt == pytest.approx(0.01, rel=1e-4)  # 0.04 %
    with pytest.raises(RecordFormatError, match=r"uneven.txt, line 3: .*by more than 0.1%: samples must be equally spaced"):
        read_record(write("uneven.txt", 1.2e-3 * 0.01 / 2))  # 0.12 %
    ts = np.arange(5) * 0.01
    ts[3] += 0.6e-5  # the steps around it are 0.06 % longer and shorter: equal within the tolerance
    np.savez(tmp_path / "t.npz", h1=np.ones(5), h2=np.ones(5), v=np.ones(5), time=ts, units="g")
    assert read_record(tmp_path / "t.npz").dt == pytest.approx(0.01, rel=1e-3)
    ts[3] += 1.0e-5
    np.savez(tmp_path / "t.npz", h1=np.ones(5), h2=np.ones(5), v=np.ones(5), time=ts, units="g")
    with pytest.raises(RecordFormatError, match=r"t.npz, array 'time', index 3: time step .* samples must be equally spaced"):
        read_record(tmp_path / "t.npz")


# -- .npz archives -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "arrays, where",
    [
        (dict(h1=np.array([1, "a"], dtype=object)), "array 'h1': cannot load the array"),
        (dict(dt=np.array([0.01, 0.02])), r"array 'dt': must be a single number, got an array of shape \(2,\)"),
        (dict(dt="fast"), r"array 'dt': must be a single number, got 'fast'"),
        (dict(h1=np.zeros((2, 4))), r"array 'h1': must be 1-D with at least 2 samples, got shape \(2, 4\)"),
        (dict(units=np.array(["g", "g"])), r"array 'units': must be a single text"),
        (dict(names=np.array(["a", "b"])), r"array 'names': must be 3 strings"),
        (dict(time=np.arange(4) * 0.02), r": array 'time' gives dt = 0.02 s but array 'dt' gives 0.01 s"),
        (dict(lengths=np.array([4, 9, 4])), r"array 'lengths', index 1: 9 is not between 2 and the length 4"),
        (dict(metadata="{oops"), r"array 'metadata': is not a JSON object"),
    ],
    ids=["object", "dt-vector", "dt-text", "2-d", "units-vector", "names", "dt-vs-time", "lengths", "metadata"],
)
def test_malformed_npz_names_the_array(tmp_path, arrays, where):
    base = dict(h1=np.zeros(4), h2=np.zeros(4), v=np.zeros(4), dt=0.01, units="g")
    path = tmp_path / "bad.npz"
    np.savez(path, **{**base, **arrays})  # np.savez pickles object arrays; the reader must refuse them
    with pytest.raises(RecordFormatError, match=rf"bad.npz(, |){where}"):
        read_record(path)


def test_npz_that_is_not_an_archive(tmp_path):
    np.save(tmp_path / "single.npy", np.zeros(5))
    with pytest.raises(RecordFormatError, match="a single .npy array, not an .npz archive"):
        read_record(tmp_path / "single.npy", format="npz")


# -- readers of plugins ------------------------------------------------------------------------


def test_reader_suffixes_match_whatever_their_case(tmp_path):
    read = lambda path, **kw: []  # noqa: E731
    upper = types.SimpleNamespace(name="upper", suffixes=(".FAKE",), read=read, sniff=None)
    registry = types.SimpleNamespace(record_readers={"upper": types.SimpleNamespace(value=upper)})
    for name in ("motion.fake", "MOTION.FAKE", "motion.Fake"):
        assert find_reader(tmp_path / name, registry=registry) is upper
    assert RecordReader(name="r", suffixes=(".AT2", ".Txt"), read=read).suffixes == (".at2", ".txt")


@pytest.mark.parametrize("suffixes", [".at2", ("at2",), (".",), (".at2", 3), None])
def test_one_suffix_check_for_readers_and_the_registry(suffixes):
    from bearingfw.plugins.registry import _reader_key

    with pytest.raises(ParameterError, match=r"record reader 'r': 'suffixes' must be a tuple of file-name endings"):
        check_suffixes("r", suffixes)
    with pytest.raises(ParameterError, match=r"record reader 'r': 'suffixes' must be a tuple"):
        _reader_key(types.SimpleNamespace(name="r", suffixes=suffixes, read=print))
    if not isinstance(suffixes, str):  # RecordReader takes one ending as a string, for convenience
        with pytest.raises(ParameterError, match=r"record reader 'r': 'suffixes' must be a tuple"):
            RecordReader(name="r", suffixes=suffixes, read=print)


# -- bounds on dt, samples and duration; directories; peaks lost by resampling (issue 15) ------


def header_variant(tmp_path, old, new, name="variant.AT2"):
    """A copy of the real Chuetsu EW file with one piece of its 4th header line replaced."""
    raw = CHUETSU[0].read_bytes()
    assert old in raw
    path = tmp_path / name
    path.write_bytes(raw.replace(old, new, 1))
    return path


@pytest.mark.parametrize(
    "old, new, message",
    [
        (b"DT=   .0100", b"DT= 1.0E+10", "line 4: the time step 1e+10 s (DT) is outside the allowed range 1e-06 s <= dt <= 1 s"),
        (b"DT=   .0100", b"DT= 100.0", "line 4: the time step 100 s (DT) is outside the allowed range"),
        (b"DT=   .0100", b"DT= 1.0E-09", "line 4: the time step 1e-09 s (DT) is outside the allowed range"),
        (b"NPTS=   6000", b"NPTS= 1000000000", "line 4: 1000000000 samples is outside the allowed range 2 <= samples <= 100000000"),
    ],
)
def test_at2_header_bounds(tmp_path, old, new, message):
    path = header_variant(tmp_path, old, new)
    with pytest.raises(RecordFormatError, match=re.escape(f"{path}, {message}")):
        read_at2(path)


def test_record_duration_bound(tmp_path):
    from bearingfw.motion.readers import MAX_DURATION

    path = tmp_path / "long.csv"
    path.write_text("# units: g\n# dt: 1.0\n" + "0.1\n" * (int(MAX_DURATION) + 2))
    with pytest.raises(RecordFormatError, match=re.escape(f"{path}, line 2: {int(MAX_DURATION) + 2} samples at dt = 1 s last")):
        read_record(path)


@pytest.mark.parametrize(
    "text, message",
    [
        ("# units: g\n# dt: 1e300\n0.1\n0.2\n", "line 2: the time step 1e+300 s (the '# dt' comment) is outside the allowed range"),
        ("t, a [g]\n0, 0.1\n2, 0.2\n4, 0.1\n", "line 3: the time step 2 s (the time column 't') is outside the allowed range"),
    ],
)
def test_column_file_dt_bounds(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(RecordFormatError, match=re.escape(f"{path}, {message}")):
        read_record([path, path, path])


def test_npz_dt_bound_and_dt_option_bound(tmp_path):
    path = tmp_path / "r.npz"
    np.savez(path, h1=np.ones(10), h2=np.ones(10), v=np.ones(10), dt=np.float64(5.0), units=np.str_("g"))
    with pytest.raises(RecordFormatError, match=re.escape(f"{path}: the time step 5 s (array 'dt') is outside")):
        read_record(path)
    columns = tmp_path / "cols.txt"
    columns.write_text("1 2 3\n4 5 6\n")
    with pytest.raises(RecordFormatError, match=re.escape(f"{columns}: the time step 2 s (dt) is outside")):
        read_record(columns, dt=2.0, units="g")


def test_a_directory_is_named_as_one(tmp_path):
    with pytest.raises(RecordFormatError, match=re.escape(f"{tmp_path}: is a directory, not a record file")):
        read_record([tmp_path])


def test_peak_lost_by_resampling_is_exposed():
    # The Manjil vertical (5.28 m/s^2 peak, 0.02 s) resampled to 0.5 s keeps a small part of its peak.
    record = read_record(MANJIL)
    coarse = record.resampled(0.5)
    ratios = coarse.peak_ratios
    assert all(r is not None for r in ratios) and coarse.min_peak_ratio == min(ratios)
    v_before = max(map(abs, at2_values(MANJIL[2]))) * G
    assert ratios[2] == pytest.approx(np.max(np.abs(coarse.v)) / v_before, rel=1e-12)
    assert coarse.min_peak_ratio < 0.2
    assert any("(ratio " in note and note.startswith("V resampled from dt = 0.02 s to 0.5 s") for note in coarse.notes)
    assert record.peak_ratios == (None, None, None) and record.min_peak_ratio == 1.0
    finer = record.resampled(0.005)  # refining keeps the peaks (band-limited interpolation: at least as high)
    assert finer.min_peak_ratio >= 0.99
