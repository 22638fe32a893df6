"""The OMA readers bound what they read and name the file: a modes file with 1e300 (which gave an
internal error, exit 4, in the pairing), one that is not UTF-8, and channel files with absurd values
or that are directories."""

from __future__ import annotations

import io
import json
import math
from contextlib import redirect_stderr, redirect_stdout

import pytest

from bearingfw.motion import RecordFormatError
from bearingfw.oma import read_channels, read_modes
from bearingfw.oma.io import MAX_FREQUENCY, MAX_SHAPE
from bearingfw.parameters import ParameterError


def modes_file(tmp_path, **changes) -> object:
    """A hand-written modes file of two modes; ``changes`` replace fields of the second."""
    second = {"frequency": 3.3, "damping": 0.02, "shape": {"a": 1.0, "b": -0.9}, **changes}
    data = {"modes": [{"frequency": 1.5, "damping": 0.02, "shape": {"a": 1.0, "b": 0.9}}, second]}
    path = tmp_path / "modes.json"
    path.write_text(json.dumps(data))  # Python's json writes nan and inf as NaN and Infinity
    return path


@pytest.mark.parametrize("changes, message", [
    ({"frequency": 1e300}, f"mode 2: field 'frequency' = 1e+300 is out of range: 0 < frequency <= {MAX_FREQUENCY:g} Hz"),
    ({"frequency": math.inf}, "mode 2: field 'frequency' = inf is out of range"),
    ({"frequency": 0.0}, "mode 2: field 'frequency' = 0.0 is out of range"),
    ({"shape": {"a": 1e300, "b": 1.0}}, f"mode 2: shape value 1e+300 at channel 'a' is out of range: shape values must be "
                                        f"finite, |value| <= {MAX_SHAPE:g}"),
    ({"shape": {"a": math.nan, "b": 1.0}}, "mode 2: shape value nan at channel 'a' is out of range"),
    ({"shape": {"a": 0.0, "b": 0.0}}, "mode 2: the shape is zero at every channel"),
    ({"damping": 5.0}, "mode 2: "),
    ({"mpc": 2.0}, "mode 2: field 'mpc' = 2.0 is out of range: 0 <= mpc <= 1"),
    ({"frequency_std": -1.0}, "mode 2: field 'frequency_std' = -1.0 is out of range"),
    ({"damping_std": "x"}, "mode 2: field 'damping_std' = 'x' is out of range"),
    ({"poles": math.inf}, "mode 2: field 'poles' = inf must be a whole number >= 1"),
    ({"poles": 2.5}, "mode 2: field 'poles' = 2.5 must be a whole number >= 1"),
])
def test_read_modes_bounds_every_value_naming_the_file_and_the_mode(tmp_path, changes, message):
    path = modes_file(tmp_path, **changes)
    with pytest.raises(ParameterError) as refused:
        read_modes(path)
    assert str(refused.value).startswith(f"{path}: {message}"), str(refused.value)


def test_read_modes_accepts_the_edges(tmp_path):
    modes = read_modes(modes_file(tmp_path, frequency=MAX_FREQUENCY, shape={"a": -MAX_SHAPE, "b": 0.0}, poles=3.0))
    assert modes.modes[1].frequency == MAX_FREQUENCY and modes.modes[1].poles == 3
    assert list(modes.modes[1].shape) == [-MAX_SHAPE, 0.0]


def test_read_modes_names_the_line_of_a_byte_that_is_not_utf8(tmp_path):
    path = tmp_path / "modes.json"
    path.write_bytes(b'{"modes": [\n  {"frequency": 2.0,\n   "name": "\xe9", "shape": {"a": 1.0}}]}')
    with pytest.raises(ParameterError, match=r"modes\.json: not UTF-8 text \(byte b'\\xe9' at offset 45\) on line 3;"):
        read_modes(path)


def test_read_modes_of_a_directory_says_so(tmp_path):
    with pytest.raises(ParameterError, match=r": is a directory, not a modes file"):
        read_modes(tmp_path)


def test_tune_with_a_huge_frequency_exits_2_naming_it(tmp_path):
    """Before: ValueError 'matrix contains invalid numeric entries' from the pairing, exit status 4."""
    from bearingfw.cli.main import main

    path = tmp_path / "modes.json"
    path.write_text(json.dumps({"channels": ["GA12.uz", "GB12.uz"], "modes": [
        {"frequency": 1.6, "shape": {"GA12.uz": 1.0, "GB12.uz": 0.9}},
        {"frequency": 3.3, "shape": {"GA12.uz": 1e300, "GB12.uz": -0.9}}]}))
    err = io.StringIO()
    with redirect_stdout(io.StringIO()), redirect_stderr(err):
        status = main(["tune", "--measured", str(path)])
    assert status == 2, err.getvalue()
    assert "mode 2: shape value 1e+300 at channel 'GA12.uz' is out of range" in err.getvalue()


def test_read_channels_bounds_values_and_names_the_sample(tmp_path):
    """Before: a CSV without units holding 1e300 was read (as m/s^2) and went on into the identification."""
    path = tmp_path / "big.csv"
    path.write_text("time,GA12.uz,GB12.uz\n0,1,2\n0.01,1e300,2\n0.02,1,2\n")
    with pytest.raises(RecordFormatError, match=r"big\.csv, component 1 \(GA12\.uz\), sample 2: value 1e\+300 m/s\^2 is "
                                             r"outside the allowed range"):
        read_channels(path)


def test_read_channels_of_a_directory_says_so(tmp_path):
    folder = tmp_path / "channels.csv"
    folder.mkdir()
    with pytest.raises(RecordFormatError, match=r"channels\.csv: is a directory"):
        read_channels(folder)


def test_read_channels_names_the_line_of_a_byte_that_is_not_utf8(tmp_path):
    path = tmp_path / "latin.csv"
    path.write_bytes(b"time,GA12.uz\n0,1\n0.01,\xe9\n0.02,1\n")
    with pytest.raises(RecordFormatError, match=r"latin\.csv, line 3: "):
        read_channels(path, units="g")
