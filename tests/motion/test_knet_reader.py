"""The NIED K-NET / KiK-net ASCII reader: files written here from known counts and scale factors."""

import json
import re

import numpy as np
import pytest

from bearingfw.cli.main import main
from bearingfw.motion import RecordFormatError, load_directional, read_record
from bearingfw.motion.errors import VerticalComponentError
from bearingfw.motion.readers import KNET_SAMPLE_SLACK, find_reader, read_file, read_knet
from bearingfw.plugins import get_registry

NUMERATOR, DENOMINATOR = 7845, 8223790  # the Scale Factor of real K-NET files: 7845(gal)/8223790
GAL = 0.01  # m/s^2
OFFSET = 13320  # counts: the offset a K-NET record carries


def sine_counts(n=2000, amplitude=20000, frequency=1.5, phase=0.0):
    """Counts of a sine sampled at 100 Hz on the offset (the peak is not at the mean)."""
    t = np.arange(n) / 100.0
    return OFFSET + np.round(amplitude * np.sin(2 * np.pi * frequency * t + phase)).astype(int)


def expected_si(counts):
    """The acceleration in m/s^2 the reader must return, computed independently."""
    counts = np.asarray(counts, dtype=float)
    return (counts - counts.mean()) * NUMERATOR / DENOMINATOR * GAL


def knet_text(counts, *, direction="N-S", frequency="100Hz", duration=None, scale=None, max_acc=None, newline="\n"):
    """A K-NET ASCII file: the 17-line header (values from column 19), then counts 8 a line."""
    counts = list(counts)
    peak_gal = float(np.max(np.abs(expected_si(counts)))) / GAL if counts else 0.0
    fields = [
        ("Origin Time", "2004/10/23 17:56:00"),
        ("Lat.", "37.292"),
        ("Long.", "138.867"),
        ("Depth. (km)", "13"),
        ("Mag.", "6.8"),
        ("Station Code", "NIG019"),
        ("Station Lat.", "37.3105"),
        ("Station Long.", "138.8505"),
        ("Station Height(m)", "80"),
        ("Record Time", "2004/10/23 17:56:15"),
        ("Sampling Freq(Hz)", frequency),
        ("Duration Time(s)", f"{len(counts) / 100:g}" if duration is None else duration),
        ("Dir.", direction),
        ("Scale Factor", f"{NUMERATOR}(gal)/{DENOMINATOR}" if scale is None else scale),
        ("Max. Acc. (gal)", f"{peak_gal:.3f}" if max_acc is None else max_acc),
        ("Last Correction", "2004/10/23 17:56:00"),
        ("Memo.", ""),
    ]
    header = [f"{label:<18}{value}" for label, value in fields]
    data = ["".join(f"{c:9d}" for c in counts[i:i + 8]) + " " for i in range(0, len(counts), 8)]
    return newline.join(header + data) + newline


def write_knet(path, counts, **options):
    path.write_bytes(knet_text(counts, **options).encode("ascii"))
    return path


def replace_line(path, number, text):
    """Replace line ``number`` (1-based) of a written file; None deletes it."""
    lines = path.read_text().split("\n")
    if text is None:
        del lines[number - 1]
    else:
        lines[number - 1] = text
    path.write_text("\n".join(lines))
    return path


# -- reading ----------------------------------------------------------------------------------


def test_time_step_samples_units_and_direction(tmp_path):
    counts = sine_counts()
    (trace,) = read_knet(write_knet(tmp_path / "NIG0190410231756.NS", counts))
    assert trace.dt == 0.01 and trace.values.size == 2000
    assert trace.units == "cm/s^2"  # gal
    assert trace.label == "NS" and trace.metadata["direction"] == "NS" and trace.metadata["format"] == "knet"
    assert trace.metadata["header"][5] == "Station Code      NIG019"


def test_amplitude_is_counts_times_scale_factor_minus_the_mean(tmp_path):
    # The peak is at neither the offset nor zero counts: a reader that kept the offset, or divided
    # by the scale factor, would be off by orders of magnitude; one that removed another mean
    # (the first samples') would be off by the sine's own mean over them.
    counts = sine_counts(n=2050, phase=0.4)
    (trace,) = read_knet(write_knet(tmp_path / "x.EW", counts))
    expected = expected_si(counts)
    values = trace.in_si()
    assert np.max(np.abs(values)) == pytest.approx(np.max(np.abs(expected)), rel=1e-12, abs=0)
    np.testing.assert_allclose(values, expected, rtol=0, atol=1e-12 * np.max(np.abs(expected)))
    assert trace.metadata["offset_removed"] == pytest.approx(np.mean(counts) * NUMERATOR / DENOMINATOR, rel=1e-12)


def test_crlf_file_reads_the_same(tmp_path):
    counts = sine_counts()
    (lf,) = read_knet(write_knet(tmp_path / "lf.UD", counts))
    (crlf,) = read_knet(write_knet(tmp_path / "crlf.UD", counts, newline="\r\n"))
    assert np.array_equal(lf.values, crlf.values) and crlf.dt == lf.dt


@pytest.mark.parametrize(
    "suffix, direction, label, sensor",
    [
        (".NS", "N-S", "NS", None),
        (".EW", "E-W", "EW", None),
        (".UD", "U-D", "UD", None),
        (".NS1", "1", "NS1", "borehole"),
        (".EW1", "2", "EW1", "borehole"),
        (".UD1", "3", "UD1", "borehole"),
        (".NS2", "4", "NS2", "surface"),
        (".EW2", "5", "EW2", "surface"),
        (".ud2", "6", "UD2", "surface"),
        (".ns2", "N-S", "NS", None),
    ],
)
def test_knet_and_kiknet_directions_and_suffixes(tmp_path, suffix, direction, label, sensor):
    path = write_knet(tmp_path / f"ABSH060410231756{suffix}", sine_counts(), direction=direction)
    assert find_reader(path).name == "knet"
    reader, (trace,) = read_file(path)
    assert reader.name == "knet"
    assert trace.label == label and trace.metadata["direction"] == label[:2]
    assert trace.metadata.get("sensor") == sensor


def test_sniffed_without_a_claimed_suffix(tmp_path):
    # ".knet" is no reader's suffix: the file is recognised by its header, not taken for a column
    # file (whose sniffer accepts any row of numbers, such as the counts).
    path = write_knet(tmp_path / "record.knet", sine_counts())
    assert find_reader(path).name == "knet"
    columns = tmp_path / "columns.knet"
    columns.write_text("0.0 1.0\n0.01 2.0\n0.02 3.0\n")
    assert find_reader(columns).name == "columns"


def test_sample_count_may_exceed_duration_times_frequency_by_the_slack(tmp_path):
    for n in (2000, 2001, 2000 + KNET_SAMPLE_SLACK, 2000 - KNET_SAMPLE_SLACK):
        (trace,) = read_knet(write_knet(tmp_path / f"n{n}.NS", sine_counts(n=n), duration="20"))
        assert trace.values.size == n


def test_peak_within_one_percent_of_the_header_is_accepted(tmp_path):
    counts = sine_counts()
    peak = float(np.max(np.abs(expected_si(counts)))) / GAL
    (trace,) = read_knet(write_knet(tmp_path / "x.NS", counts, max_acc=f"{peak * 1.009:.3f}"))
    assert trace.values.size == 2000


def test_dt_and_units_arguments_must_agree_with_the_header(tmp_path):
    path = write_knet(tmp_path / "x.NS", sine_counts())
    (trace,) = read_knet(path, dt=0.01, units="gal")
    assert trace.dt == 0.01 and trace.units == "cm/s^2"
    with pytest.raises(RecordFormatError, match=r"line 11: the header \(Sampling Freq\) gives dt = 0.01 s but dt = 0.02 s"):
        read_knet(path, dt=0.02)
    with pytest.raises(RecordFormatError, match=r"line 14: the Scale Factor states cm/s\^2 but units = 'g' was given"):
        read_knet(path, units="g")


# -- records, directions, the command line, the registry --------------------------------------


def three_files(tmp_path):
    counts = [sine_counts(frequency=1.5), sine_counts(frequency=1.2, amplitude=15000), sine_counts(frequency=4.0, amplitude=6000)]
    paths = [
        write_knet(tmp_path / f"MYG0041103111446.{c}", k, direction=d)
        for c, d, k in zip(("NS", "EW", "UD"), ("N-S", "E-W", "U-D"), counts)
    ]
    return paths, counts


def test_read_record_from_three_files(tmp_path):
    paths, counts = three_files(tmp_path)
    record = read_record(paths)
    assert record.names == ("NS", "EW", "UD") and record.dt == 0.01 and record.n == 2000
    assert record.source_units == ("cm/s^2",) * 3 and record.metadata["readers"] == ["knet"] * 3
    assert "notes" not in record.metadata  # the vertical is where it belongs
    for component, k in zip(record.components, counts):
        np.testing.assert_allclose(component, expected_si(k), rtol=0, atol=1e-12 * np.max(np.abs(expected_si(k))))


def test_a_ud_file_counts_as_vertical(tmp_path):
    paths, _ = three_files(tmp_path)
    record = load_directional({"x": str(paths[0]), "y": str(paths[1]), "z": str(paths[2])})
    assert record.names == ("x: NS", "y: EW", "z: UD")
    with pytest.raises(VerticalComponentError, match=r"K-NET direction \(Dir\.\) 'UD'"):
        load_directional({"x": str(paths[2])})
    # A KiK-net channel number says it as well (the label keeps the sensor: UD1).
    borehole = write_knet(tmp_path / "ABSH060410231756.UD1", sine_counts(), direction="3")
    with pytest.raises(VerticalComponentError, match=r"'UD'"):
        load_directional({"y": str(borehole)})
    assert read_record([paths[0], paths[1], borehole]).names == ("NS", "EW", "UD1")


def test_record_info_on_knet_files(tmp_path, capsys):
    paths, counts = three_files(tmp_path)
    assert main(["record", "info", *map(str, paths), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["dt"] == 0.01
    for role, k in zip(("h1", "h2", "v"), counts):
        assert data["pga"][role] == pytest.approx(np.max(np.abs(expected_si(k))), rel=1e-12)
    assert main(["record", "info", "--x", str(paths[1]), "--z", str(paths[2])]) == 0
    assert "x: EW" in capsys.readouterr().out


def test_registered_and_listed_by_plugins(capsys):
    reader = get_registry().record_readers["knet"].value
    assert reader.suffixes == (".ns", ".ew", ".ud", ".ns1", ".ew1", ".ud1", ".ns2", ".ew2", ".ud2")
    assert main(["plugins", "--json"]) == 0
    listed = {r["name"] for r in json.loads(capsys.readouterr().out)["record_readers"]}
    assert {"knet", "peer-at2", "columns", "npz"} <= listed
    assert main(["plugins"]) == 0
    assert "knet" in capsys.readouterr().out


# -- malformed files --------------------------------------------------------------------------


def refused(path, pattern, **options):
    """The error names the file and matches ``pattern`` (which names the line)."""
    with pytest.raises(RecordFormatError, match=pattern) as info:
        read_file(path, **options)
    assert str(path) in str(info.value)
    return info.value


@pytest.mark.parametrize(
    "line, text, pattern",
    [
        (14, "Scale Factor      7845(gal)8223790", r"line 14: expected 'Scale Factor  <numerator>\(gal\)/<denominator>'"),
        (14, "Scale Factor      7845(gal)/0", r"line 14: expected 'Scale Factor .*got Scale Factor '7845\(gal\)/0'"),
        (14, "Scale Factor      7845(kine)/8223790", r"line 14: the Scale Factor: unknown acceleration unit 'kine'"),
        (11, "Sampling Freq(Hz) 0Hz", r"line 11: expected 'Sampling Freq\(Hz\) <f>Hz' with f > 0"),
        (11, "Sampling Freq(Hz) -100Hz", r"line 11: expected 'Sampling Freq\(Hz\) <f>Hz'.*'-100Hz'"),
        (11, "Sampling Freq(Hz) fastHz", r"line 11: expected 'Sampling Freq\(Hz\) <f>Hz'.*'fastHz'"),
        (11, "Sampling Freq(Hz) 1e-9Hz", r"line 11: the time step 1e\+09 s \(1 / Sampling Freq\(Hz\)\) is outside"),
        (12, "Duration Time(s)  long", r"line 12: expected 'Duration Time\(s\)  <s>'"),
        (13, "Dir.              N-E", r"line 13: expected 'Dir\.  N-S', 'E-W', 'U-D' or a KiK-net channel 1 .* got Dir\. 'N-E'"),
        (15, "Max. Acc. (gal)   big", r"line 15: expected 'Max\. Acc\. \(gal\)  <peak>'"),
        (1, "Origin 2004/10/23 17:56:00", r"line 1: expected 'Origin Time"),
        (17, "Memorandum", r"line 17: expected 'Memo\.'"),
    ],
)
def test_malformed_header_lines(tmp_path, line, text, pattern):
    path = replace_line(write_knet(tmp_path / "bad.NS", sine_counts()), line, text)
    refused(path, pattern)


def test_missing_header_line(tmp_path):
    path = replace_line(write_knet(tmp_path / "bad.NS", sine_counts()), 13, None)  # no Dir.
    refused(path, r"line 13: expected 'Dir\..*got 'Scale Factor      7845\(gal\)/8223790'")


def test_file_ending_inside_the_header(tmp_path):
    path = tmp_path / "short.EW"
    path.write_text("\n".join(knet_text(sine_counts()).split("\n")[:10]))
    refused(path, r"line 11: the file ends inside the 17-line K-NET header")


def test_a_file_with_a_knet_suffix_but_another_format_is_not_a_number_puzzle(tmp_path):
    path = tmp_path / "data.NS"
    path.write_text("0.0 1.0\n0.01 2.0\n")
    refused(path, r"line 1: expected 'Origin Time")


@pytest.mark.parametrize("token", ["12.5", "1e3", "12a", "--3", "１２"])
def test_data_token_that_is_not_an_integer(tmp_path, token):
    path = write_knet(tmp_path / "bad.UD", sine_counts())
    lines = path.read_text().split("\n")
    cells = lines[19].split()  # line 20: the third data line
    cells[4] = token
    lines[19] = " ".join(cells)
    path.write_text("\n".join(lines), encoding="utf-8")
    refused(path, rf"line 20: {re.escape(repr(token))} is not an integer count")


def test_absurdly_long_count(tmp_path):
    path = write_knet(tmp_path / "bad.UD", sine_counts())
    replace_line(path, 18, "1" + "0" * 400)
    refused(path, r"line 18: count 10+ has more than 15 digits")


@pytest.mark.parametrize("n", [2000 - KNET_SAMPLE_SLACK - 1, 2000 + KNET_SAMPLE_SLACK + 1, 1000])
def test_samples_not_matching_the_duration(tmp_path, n):
    path = write_knet(tmp_path / "bad.EW", sine_counts(n=n), duration="20")
    last = 17 + -(-n // 8)
    refused(path, rf"line {last}: {n} samples, but the header says 20 s at 100 Hz = 2000 samples")


def test_empty_data_block(tmp_path):
    path = write_knet(tmp_path / "empty.NS", [], duration="0")
    refused(path, r"line 18: no data after the 17-line header")


@pytest.mark.parametrize("factor", [2.0, 0.5, 1.02])
def test_peak_disagreeing_with_the_header(tmp_path, factor):
    counts = sine_counts()
    peak = float(np.max(np.abs(expected_si(counts)))) / GAL
    stated = f"{peak * factor:.3f}"
    error = refused(write_knet(tmp_path / "x.NS", counts, max_acc=stated), r"line 15: the data's peak")
    assert f"{peak:.6g} gal" in str(error) and f"states {stated} gal" in str(error)


def test_inverted_scale_factor_is_caught_by_the_peak(tmp_path):
    counts = sine_counts()
    path = write_knet(tmp_path / "x.NS", counts, scale=f"{DENOMINATOR}(gal)/{NUMERATOR}")
    refused(path, r"line 15: the data's peak .* a wrong scale factor or a corrupt file")


def test_the_header_spelling_of_nieds_own_format_page_is_read(tmp_path):
    """NIED's description of the format writes ``Lon.``, ``Station Lon.`` and ``Max Acc. (gal)``
    where many files write ``Long.`` and ``Max. Acc. (gal)``: both are read."""
    n = 10800
    t = np.arange(n) / 100.0
    counts = np.round(8000 + 3000 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.05 * t)).astype(int)
    scale = 3920 / 6182761
    peak = np.max(np.abs((counts - counts.mean()) * scale))
    header = [
        "Origin Time       2006/01/18 23:25:00", "Lat.              37.798", "Lon.              142.200",
        "Depth. (km)       36", "Mag.              5.7", "Station Code      MYG002", "Station Lat.      38.7262",
        "Station Lon.      141.5109", "Station Height(m) 79", "Record Time       2006/01/18 23:25:46",
        "Sampling Freq(Hz) 100Hz", "Duration Time(s)  108", "Dir.              N-S",
        "Scale Factor      3920(gal)/6182761", f"Max Acc. (gal)    {peak:.3f}", "Last Correction   2006/01/18 23:25:31",
        "Memo.",
    ]
    rows = [" ".join(f"{c:8d}" for c in counts[i : i + 8]) for i in range(0, n, 8)]
    path = tmp_path / "MYG0020601182325.NS"
    path.write_text("\n".join(header + rows) + "\n")
    (trace,) = read_knet(path)
    assert trace.dt == 0.01 and trace.values.size == n and trace.label == "NS"
    np.testing.assert_allclose(trace.values, (counts - counts.mean()) * scale, rtol=1e-12, atol=1e-12)
