"""Fuzzing the record readers: .AT2, text columns, .npz and junk, with random headers, time steps from
1e-300 to 1e300 s, NaN and infinities, huge NPTS claims, empty and binary files, non-UTF-8 text.

Every drawn file gives what the model in fuzz_support expects, exactly: its values, or a
RecordFormatError / UnknownReaderError whose message names the file; no other exception, no hang,
no impossible record accepted. The default run is derandomized and short; ``-m slow`` explores.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fuzz_support import (
    DT_RANGE,
    MAX_ACCELERATION,
    MAX_DURATION,
    PROFILES,
    DrawnFile,
    any_record_file,
    at2_files,
    column_files,
    fuzz_settings,
    number_text,
    time_limit,
    time_steps,
)
from hypothesis import event, given, note
from hypothesis import strategies as st

from bearingfw.motion import RecordFormatError, UnknownReaderError, read_file, read_record
from bearingfw.parameters import ParameterError
from bearingfw.motion.record import Record

SECONDS = 20.0  # far beyond what reading any drawn file takes: past it, a hang


def check_trace(trace) -> None:
    """What an accepted component must be, whatever the file said."""
    values = trace.in_si()
    assert DT_RANGE[0] <= trace.dt <= DT_RANGE[1]
    assert values.size >= 2 and (values.size - 1) * trace.dt <= MAX_DURATION
    assert np.isfinite(values).all() and np.abs(values).max() <= MAX_ACCELERATION


def check_record(record: Record) -> None:
    assert DT_RANGE[0] <= record.dt <= DT_RANGE[1] and record.n >= 2
    assert np.isfinite(record.components).all()


def read_as_told(drawn: DrawnFile, folder):
    """Read a drawn file and hold the outcome against the file's model."""
    path = folder / drawn.name
    path.write_bytes(drawn.content)
    note(f"{drawn.why}\n{drawn.content[:600]!r}")
    try:
        with time_limit(SECONDS, f"reading {drawn.why}"):
            _, traces = read_file(path, **drawn.kwargs)
    except (RecordFormatError, UnknownReaderError) as refusal:
        message = str(refusal)
        assert str(path) in message and len(message) > len(str(path)) + 5, message
        assert drawn.expected is None or drawn.expected is ..., f"a valid file was refused: {message}"
        event(f"refused ({type(refusal).__name__})")
        return None
    assert drawn.expected is not None, f"an impossible file was accepted ({drawn.why})"
    event("accepted" + (" (not modelled)" if drawn.expected is ... else ", values checked"))
    for trace in traces:
        check_trace(trace)
    if drawn.expected is not ...:
        assert len(traces) == len(drawn.expected)
        for trace, expected in zip(traces, drawn.expected):
            np.testing.assert_array_equal(trace.in_si(), expected)
            assert trace.dt == pytest.approx(drawn.dt, rel=1e-9)
    return path if len(traces) == 3 else None


@pytest.mark.parametrize("profile", PROFILES)
def test_at2_files(tmp_path, profile):
    @fuzz_settings(profile, scale=3)
    @given(at2_files())
    def check(drawn):
        read_as_told(drawn, tmp_path)

    check()


@pytest.mark.parametrize("profile", PROFILES)
def test_column_files(tmp_path, profile):
    @fuzz_settings(profile, scale=3)
    @given(column_files())
    def check(drawn):
        path = read_as_told(drawn, tmp_path)
        if path is not None:  # three components: a whole record, resampling and all
            with time_limit(SECONDS, "read_record"):
                check_record(read_record(path, **drawn.kwargs))

    check()


@pytest.mark.parametrize("profile", PROFILES)
def test_any_file(tmp_path, profile):
    @fuzz_settings(profile, scale=2)
    @given(any_record_file)
    def check(drawn):
        read_as_told(drawn, tmp_path)

    check()


def _at2(dt: float, n: int, seed: int) -> bytes:
    values = np.random.default_rng(seed).normal(scale=0.1, size=n)
    body = "\n".join("  ".join(number_text(v) for v in values[k:k + 5]) for k in range(0, n, 5))
    return f"fuzz\nfuzz, H\nUNITS OF G\nNPTS= {n}, DT= {dt!r} SEC\n{body}\n".encode()


@pytest.mark.parametrize("profile", PROFILES)
def test_three_files_of_any_time_steps_make_a_record_or_a_clear_refusal(tmp_path, profile):
    """Components of different time steps are resampled to the finest: never a MemoryError or a hang,
    whatever the ratio of the steps and the length of the coarse ones."""

    @fuzz_settings(profile)
    @given(st.lists(st.tuples(time_steps, st.integers(2, 3000)), min_size=3, max_size=3))
    def check(parts):
        paths = []
        for k, (dt, n) in enumerate(parts):
            paths.append(tmp_path / f"c{k}.AT2")
            paths[-1].write_bytes(_at2(dt, n, k))
        note(repr(parts))
        try:
            with time_limit(SECONDS, f"read_record of {parts}"):
                record = read_record(paths)
        except (RecordFormatError, ParameterError) as refusal:
            message = str(refusal)
            assert message and ("dt" in message or "time step" in message or "samples" in message), message
            return
        assert all(DT_RANGE[0] <= dt <= DT_RANGE[1] for dt, _ in parts)
        check_record(record)
        assert record.dt == min(dt for dt, _ in parts)
        longest = max((n - 1) * dt for dt, n in parts)
        assert (record.n - 1) * record.dt >= longest * (1 - 1e-9) - max(dt for dt, _ in parts)

    check()


def test_the_model_knows_a_valid_file(tmp_path):
    """The oracle is not vacuous: a plain valid .AT2 file is expected to be read, value for value."""
    path = tmp_path / "plain.AT2"
    path.write_bytes(_at2(0.01, 12, 0))
    _, (trace,) = read_file(path)
    assert trace.dt == 0.01 and trace.values.size == 12 and math.isclose(trace.in_si()[0] / trace.values[0], 9.80665)
