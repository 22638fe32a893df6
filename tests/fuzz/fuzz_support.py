"""What the fuzz tests share: the two run lengths, a time limit per example, and record files drawn
together with what a reader must make of them.

A drawn file carries its *expected outcome*, derived here from how it was built rather than by
reading it: the values the reader must return (in m/s^2), or None when the file is impossible
(a time step, a sample count or a duration out of range, a value that is not finite or beyond
100 g, a header that disagrees with the data, no units ...). The tests then demand exactly that:
the values, or a RecordFormatError naming the file, never another exception, a hang or a silent
acceptance.
"""

from __future__ import annotations

import contextlib
import math
import signal
from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

G = 9.80665
DT_RANGE = (1e-6, 1.0)
MAX_DURATION = 86_400.0
MAX_ACCELERATION = 100.0 * G
UNITS = {"g": G, "m/s^2": 1.0, "cm/s^2": 0.01}

#: The default run: the same examples every time, few enough for seconds; the ``slow`` one explores.
PROFILES = [
    pytest.param({"max_examples": 40, "derandomize": True}, id="default"),
    pytest.param({"max_examples": 1500, "derandomize": False}, id="slow", marks=pytest.mark.slow),
]


def fuzz_settings(profile: dict, scale: float = 1.0):
    examples = max(1, int(profile["max_examples"] * scale))
    return settings(
        max_examples=examples, derandomize=profile["derandomize"], deadline=None, database=None,
        suppress_health_check=list(HealthCheck), print_blob=True,
    )


class Hang(Exception):
    """An example ran past its time limit."""


@contextlib.contextmanager
def time_limit(seconds: float, what: str):
    """Raise :class:`Hang` in the main thread if the block runs longer than ``seconds``."""

    def expire(signum, frame):
        raise Hang(f"{what} still running after {seconds:g} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


# -- pieces -------------------------------------------------------------------------------------

#: Acceleration values: mostly ordinary, some huge, tiny, negative zero; and the impossible ones.
ordinary = st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False)
extreme = st.sampled_from([1e3, -1e3, 99.0, 101.0, 1e30, -1e200, 1e300, 1e-300, 5e-324, -0.0])
impossible = st.sampled_from([math.nan, math.inf, -math.inf])
values = st.one_of(ordinary, ordinary, ordinary, extreme, impossible)

#: Time steps from far below to far above the allowed range, the edges, and junk.
time_steps = st.one_of(
    st.floats(1e-300, 1e300, allow_nan=False, allow_infinity=False),
    st.sampled_from([0.005, 0.01, 0.02, 1e-6, 1.0, 1.0000001, 9.9e-7, 100.0, 1e10, 0.0, -0.01]),
    st.floats(1e-3, 0.05),
)
#: Time steps within the allowed range, short enough records to stay within a day.
valid_time_steps = st.one_of(st.sampled_from([1e-6, 1.0, 0.005, 0.01, 0.02]), st.floats(1e-6, 1.0))
bad_dt_tokens = st.sampled_from(["nan", "inf", "-inf", "x", "", "1e", "0x10", "1_0", "１"])

#: Free text of header lines: any bytes but the three line breaks (latin-1 0x85, form feeds and
#: UTF-8 junk included: a header is free text).
header_text = st.binary(max_size=60).map(lambda b: b.replace(b"\r", b" ").replace(b"\n", b" "))

#: Line 3 of an .AT2 file and the unit it states (None: none stated; "bad": an unknown one).
unit_lines = st.sampled_from([
    (b"ACCELERATION TIME SERIES IN UNITS OF G", "g"),
    (b"UNITS: cm/s^2", "cm/s^2"),
    (b"ACCELERATION (M/S^2)", "m/s^2"),
    (b"UNITS OF FURLONGS", "bad"),
    (b"NO STATEMENT HERE", None),
])


def number_text(value: float) -> str:
    """A value as a record file writes it (the parsed float of this text is what a reader must return)."""
    if math.isnan(value):
        return "NaN"
    if math.isinf(value):
        return "Inf" if value > 0 else "-Inf"
    return f"{value:.7E}"


def parsed(value: float) -> float:
    return float(number_text(value)) if math.isfinite(value) else value


def acceptable_values(numbers, unit: str) -> bool:
    return all(math.isfinite(v) and abs(v) * UNITS[unit] <= MAX_ACCELERATION for v in numbers)


def acceptable_extent(n: int, dt: float) -> bool:
    return n >= 2 and DT_RANGE[0] <= dt <= DT_RANGE[1] and (n - 1) * dt <= MAX_DURATION


@dataclass
class DrawnFile:
    """A record file drawn by a strategy: its name, bytes, the reader arguments, the expected values
    (components in m/s^2, or None if the file must be refused) and its time step when accepted."""

    name: str
    content: bytes
    kwargs: dict
    expected: list[np.ndarray] | None
    dt: float | None = None
    why: str = ""


# -- PEER .AT2 ----------------------------------------------------------------------------------


@st.composite
def at2_files(draw) -> DrawnFile:
    # Half the files are built to be valid (else nearly none would be), then anything may go wrong.
    sound = draw(st.booleans())
    data = draw(st.lists(ordinary if sound else values, min_size=2 if sound else 0, max_size=40))
    n = len(data)
    npts_kind = "right" if sound else draw(st.sampled_from(["right", "more", "less", "zero", "huge", "fraction", "junk"]))
    npts = {"right": str(n), "more": str(n + 1), "less": str(max(n - 1, 0)), "zero": "0", "huge": "1000000000000",
            "fraction": f"{n}.5", "junk": "many"}[npts_kind]
    dt_is_number = sound or draw(st.booleans())
    dt = draw(valid_time_steps if sound else time_steps) if dt_is_number else None
    dt_token = repr(dt) if dt_is_number else draw(bad_dt_tokens)
    unit_line, unit = draw(unit_lines.filter(lambda u: u[1] not in (None, "bad")) if sound else unit_lines)
    given_units = None if sound else draw(st.sampled_from([None, None, "g", "m/s^2"]))
    old_style = draw(st.booleans())
    line4 = f"{npts} {dt_token} NPTS, DT" if old_style else f"NPTS= {npts}, DT= {dt_token} SEC"
    per_line = draw(st.integers(1, 8))
    glued = draw(st.booleans())
    rows = []
    for k in range(0, n, per_line):
        texts = [number_text(v) for v in data[k:k + per_line]]
        if glued:  # fixed-width columns glue a negative value to the one before it
            rows.append(" " + "".join(t if t.startswith("-") else " " + t for t in texts))
        else:
            rows.append("  ".join(texts))
    newline = draw(st.sampled_from([b"\r\n", b"\n"]))
    lines = [draw(header_text), draw(header_text), unit_line, line4.encode(), *(r.encode() for r in rows)]
    content = newline.join(lines) + newline

    resolved_unit = unit if unit is not None else given_units
    if unit is not None and unit != "bad" and given_units is not None and given_units != unit:
        resolved_unit = "bad"  # the file states other units than the argument
    ok = (
        npts_kind == "right" and dt is not None and math.isfinite(dt) and acceptable_extent(n, dt)
        and resolved_unit not in (None, "bad") and acceptable_values(data, resolved_unit)
    )
    expected = [np.array([parsed(v) for v in data]) * UNITS[resolved_unit]] if ok else None
    return DrawnFile("record.AT2", content, {"units": given_units}, expected, dt if ok else None,
                     why=f"npts {npts_kind}, dt {dt_token}, units {unit}/{given_units}, {n} values")


# -- text columns --------------------------------------------------------------------------------


@st.composite
def column_files(draw) -> DrawnFile:
    sound = draw(st.booleans())  # as for .AT2: half built to be valid
    width = draw(st.integers(1, 4))
    rows = draw(st.integers(3 if sound else 0, 30))
    data = [[draw(ordinary if sound else values) for _ in range(width)] for _ in range(rows)]
    delimiter = draw(st.sampled_from([",", ";", "\t", " "]))
    how_dt = draw(st.sampled_from(["time column", "comment", "argument"] + ([] if sound else ["none"])))
    dt = draw(valid_time_steps if sound else time_steps)
    unit_comment = draw(st.sampled_from(["g", "cm/s^2", "m/s^2"] + ([] if sound else [None, "parsecs"])))
    given_units = None if sound else draw(st.sampled_from([None, "m/s^2"]))
    named = sound or draw(st.booleans())
    lines = [b"# note " + draw(header_text)]  # a free comment first
    dt_token = repr(dt) if sound or draw(st.booleans()) else draw(bad_dt_tokens)
    if how_dt == "comment":
        lines.append(f"# dt: {dt_token}".encode())
    if unit_comment is not None:
        lines.append(f"# units: {unit_comment}".encode())
    time = how_dt == "time column"
    if named:
        names = (["time"] if time else []) + [f"a{j}" for j in range(width)]
        lines.append(delimiter.join(names).encode())
    for i, row in enumerate(data):
        cells = ([repr(i * dt)] if time else []) + [number_text(v) for v in row]
        lines.append(delimiter.join(cells).encode())
    content = b"\n".join(lines) + b"\n"

    unit = unit_comment if unit_comment is not None else given_units
    if unit_comment is not None and given_units is not None and unit_comment != given_units:
        unit = "parsecs"
    # Without names, the first column is time when it increases over at least 3 rows (documented):
    # a time column of fewer rows, or a first data column that happens to increase, is not modelled.
    first = [parsed(r[0]) for r in data]
    increasing = rows >= 3 and all(b > a for a, b in zip(first, first[1:]))
    sure = named or (rows >= 3 if time else not (width > 1 and increasing))
    ok = (
        sure and rows >= 2 and how_dt != "none" and math.isfinite(dt) and acceptable_extent(rows, dt)
        and (how_dt != "comment" or dt_token == repr(dt))
        and unit not in (None, "parsecs") and acceptable_values([v for r in data for v in r], unit)
    )
    kwargs = {"units": given_units, "dt": dt if how_dt == "argument" else None}
    expected = None
    if ok:
        expected = [np.array([parsed(r[j]) for r in data]) * UNITS[unit] for j in range(width)]
    elif not sure:
        expected = ...  # not modelled: either outcome, but never a traceback
    why = f"{rows}x{width}, dt by {how_dt} = {dt_token}, units {unit_comment}/{given_units}"
    name = f"record.{draw(st.sampled_from(['csv', 'txt', 'dat']))}"
    return DrawnFile(name, content, kwargs, expected, dt if ok else None, why=why)


# -- NumPy archives ------------------------------------------------------------------------------

npz_keys = st.sampled_from(["h1", "h2", "v", "acc", "dt", "time", "t", "units", "names", "lengths", "source",
                            "synthetic", "scale_factor", "metadata", "source_units", "x"])


@st.composite
def npz_arrays(draw):
    kind = draw(st.sampled_from(["float", "float", "int", "complex", "bool", "text", "empty", "matrix"]))
    size = draw(st.integers(0, 12))
    if kind == "float":
        return np.array(draw(st.lists(values, min_size=size, max_size=size)), dtype=float)
    if kind == "int":
        return np.array(draw(st.lists(st.integers(-(2**62), 2**62), min_size=size, max_size=size)), dtype=np.int64)
    if kind == "complex":
        return np.ones(size, dtype=complex)
    if kind == "bool":
        return np.array(draw(st.booleans()))
    if kind == "text":
        return np.array(draw(st.text(max_size=10)))
    if kind == "empty":
        return np.zeros((0,))
    return np.ones((draw(st.integers(1, 4)), draw(st.integers(1, 4))))


@st.composite
def npz_files(draw) -> DrawnFile:
    import io

    arrays = draw(st.dictionaries(npz_keys, npz_arrays(), max_size=8))
    if draw(st.booleans()):
        arrays["dt"] = np.array(draw(time_steps))
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    kwargs = {"units": draw(st.sampled_from([None, "g"])), "dt": draw(st.sampled_from([None, 0.01]))}
    return DrawnFile("record.npz", buffer.getvalue(), kwargs, ..., why=f"arrays {sorted(arrays)}")


# -- anything ------------------------------------------------------------------------------------


@st.composite
def junk_files(draw) -> DrawnFile:
    content = draw(st.one_of(st.binary(max_size=300), st.just(b""), st.just(b"PK\x03\x04" + b"\x00" * 40),
                             st.just(b"\xef\xbb\xbf" + "é,ü\n1,2\n".encode("utf-16"))))
    suffix = draw(st.sampled_from(["AT2", "csv", "npz", "dat", "bin"]))
    return DrawnFile(f"junk.{suffix}", content, {"units": "g", "dt": 0.01}, ..., why="junk")


any_record_file = st.one_of(at2_files(), column_files(), npz_files(), junk_files())
