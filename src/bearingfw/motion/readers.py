"""The built-in record readers (PEER ``.AT2``, NIED K-NET/KiK-net ASCII, CSV/whitespace columns,
NumPy ``.npz``) and :func:`read_record`, which turns one or more files into a
:class:`~bearingfw.motion.Record`.

Every reader returns :class:`~bearingfw.motion.Trace` objects in the file's own units and
time step; unit conversion, resampling and padding happen once, in
:func:`~bearingfw.motion.record.assemble`. A malformed file raises
:class:`~bearingfw.motion.RecordFormatError` naming the file and the line.

What a file states wins: the ``dt`` and ``units`` arguments (``--dt``, ``--units``) are used
only for files that do not state them, and an argument that contradicts the file is an error.
"""

from __future__ import annotations

import json
import math
import re
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from bearingfw.motion.errors import RecordFormatError, UnknownReaderError
from bearingfw.motion.metrics import dominant_frequency, peak
from bearingfw.motion.record import MAX_SAMPLES, ROLES, UNIT_FACTORS, G, Record, Trace, assemble, normalize_units
from bearingfw.motion.vertical import Evidence, amplitude_evidence, label_evidence, name_evidence
from bearingfw.parameters import ParameterError
from bearingfw.plugins.contracts import RecordReader

__all__ = [
    "AT2_READER",
    "COLUMNS_READER",
    "KNET_READER",
    "NPZ_READER",
    "DT_RANGE",
    "KNET_PEAK_RTOL",
    "KNET_SAMPLE_SLACK",
    "MAX_ACCELERATION",
    "MAX_DURATION",
    "MAX_SAMPLES",
    "STEP_RTOL",
    "TIME_UNITS",
    "find_reader",
    "read_at2",
    "read_columns",
    "read_file",
    "read_knet",
    "read_npz",
    "read_record",
    "vertical_evidence",
]

#: Relative tolerance of time steps: each step of a time column or array may differ from the
#: mean step by this fraction (times are printed with few digits), and two statements of the
#: time step (file header, time column, ``--dt``) must agree to it.
STEP_RTOL = 1e-3

#: Allowed time step of a record (s): a header saying ``DT= 1.0E+10`` is a typo, not a record,
#: and would exhaust the memory of the response spectrum and the resampling.
DT_RANGE = (1e-6, 1.0)
#: Longest record (s): a day, ambient vibration included.
MAX_DURATION = 86_400.0
#: Largest ground acceleration a file may hold (m/s^2): 100 g, some twenty times the strongest
#: recorded. Beyond it a value is a unit mistake or junk, and would overflow the Arias intensity.
MAX_ACCELERATION = 100.0 * G
#: Units a time column or a time step may be stated in (case ignored), in seconds. Nothing else:
#: a record sampled in minutes is not a record, and an unknown unit read as seconds would scale
#: every time (and so every frequency) silently.
TIME_UNITS = {
    "s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0,
    "ms": 1e-3, "msec": 1e-3, "millisecond": 1e-3, "milliseconds": 1e-3,
}
_TIME_UNITS_ALLOWED = "s (sec, seconds) or ms (msec, milliseconds)"


# -- text and numbers -------------------------------------------------------------------------


def _decode(raw: bytes) -> str:
    # UTF-8, dropping a byte-order mark (which would glue itself to the first cell); latin-1
    # never fails, for odd bytes in free-text headers.
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


_LINE_BREAK = re.compile(r"\r\n|\r|\n")


def _lines(path: Path, limit: int | None = None) -> list[str]:
    """The file's lines (CRLF, CR or LF); only the first ``limit`` bytes if given (for sniffing)."""
    try:
        with open(path, "rb") as handle:
            raw = handle.read() if limit is None else handle.read(limit)
    except OSError as exc:
        raise RecordFormatError(path, None, f"cannot read the file ({exc.strerror or exc})") from exc
    # Not str.splitlines(), which also breaks at form feeds and at U+0085, what a latin-1 header
    # byte 0x85 (an ellipsis in Windows-1252) decodes to: that would shift the lines after it.
    lines = _LINE_BREAK.split(_decode(raw))
    return lines[:-1] if lines and lines[-1] == "" else lines


# One number as Python, C and Fortran write it (1.0D-03 included); no underscores, no hex, and
# ASCII digits only (Python's \d and float() also take "１" or "٣": junk in a record file).
_NUMBER = r"[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?|nan|inf(?:inity)?)"
_NUMBER_RE = re.compile(_NUMBER, re.IGNORECASE | re.ASCII)
# Fixed-width output glues a negative value to the one before it: "-0.123E-02-0.456E-02". A glued
# value must start with its sign and have a decimal point, so that "1.0-103" (a Fortran exponent
# without its letter) is an error rather than two numbers.
_GLUED_RE = re.compile(rf"{_NUMBER}(?:[+-](?:\d+\.\d*|\.\d+)(?:[EeDd][+-]?\d+)?)*", re.IGNORECASE | re.ASCII)


def _number(token: str, path: Path, line: int) -> float:
    """One number; ``float`` alone would also take ``1_0`` and surrounding spaces."""
    if not _NUMBER_RE.fullmatch(token):
        raise RecordFormatError(path, line, f"{token!r} is not a number")
    value = float(token.replace("D", "E").replace("d", "e"))
    if not math.isfinite(value):
        raise RecordFormatError(path, line, f"value {token!r} is not finite")
    return value


def _numbers(text: str, path: Path, line: int) -> list[float]:
    """Every number on a line of whitespace-separated (possibly glued) values; all of it must be read."""
    values = []
    for token in text.split():
        if not _GLUED_RE.fullmatch(token):
            raise RecordFormatError(path, line, f"{token!r} is not a number")
        values.extend(_number(part, path, line) for part in _NUMBER_RE.findall(token))
    return values


def _looks_numeric(cell: str) -> bool:
    return bool(_GLUED_RE.fullmatch(cell))


def _checked_units(units: str, path: Path, line: int | None, what: str) -> str:
    try:
        return normalize_units(units)
    except ParameterError as exc:
        raise RecordFormatError(path, line, f"{what}: {exc}") from None


def _checked_dt(dt: float, path: Path, line: int | None, what: str, location: str | None = None) -> float:
    if not math.isfinite(dt) or dt <= 0:
        raise RecordFormatError(path, line, f"{what} = {dt!r} s; the time step must be > 0", location)
    if not DT_RANGE[0] <= dt <= DT_RANGE[1]:
        raise RecordFormatError(
            path, line,
            f"the time step {dt:g} s ({what}) is outside the allowed range {DT_RANGE[0]:g} s <= dt <= {DT_RANGE[1]:g} s",
            location,
        )
    return dt


def _check_extent(path: Path, n: int, dt: float, line: int | None, location: str | None = None) -> None:
    """Refuse a record too long to be meant: more than MAX_SAMPLES samples or MAX_DURATION s."""
    if n > MAX_SAMPLES:
        raise RecordFormatError(path, line, f"{n} samples is outside the allowed range 2 <= samples <= {MAX_SAMPLES}", location)
    duration = (n - 1) * dt
    if duration > MAX_DURATION:
        raise RecordFormatError(
            path, line, f"{n} samples at dt = {dt:g} s last {duration:.4g} s, outside the allowed range duration <= "
            f"{MAX_DURATION:g} s",
            location,
        )


class _Stated(NamedTuple):
    """A value the file states, and where (for the error message)."""

    value: Any
    what: str  # e.g. "the header (DT)", "the '# dt' comment", "array 'dt'"
    line: int | None = None  # None in an archive, which has no lines


def _time_factor(unit: str, path: Path, line: int | None, what: str) -> float:
    """Seconds per ``unit`` (one of TIME_UNITS; a trailing period as in "SEC." is dropped)."""
    factor = TIME_UNITS.get(unit.strip().rstrip(".").lower())
    if factor is None:
        raise RecordFormatError(
            path, line, f"{what}: {unit.strip()!r} is not a time unit; allowed: {_TIME_UNITS_ALLOWED}"
        )
    return factor


# A time step with an optional unit: "0.01", "0.01 s", "10 ms", "1.0E-02SEC".
_STEP_WITH_UNIT = re.compile(rf"\s*(?P<number>{_NUMBER})\s*(?P<unit>[^\d\s].*?)?\s*", re.IGNORECASE | re.ASCII)


def _step_in_seconds(text: str, path: Path, line: int | None, what: str) -> float:
    """A stated time step in seconds: a number, optionally followed by a time unit (default s)."""
    found = _STEP_WITH_UNIT.fullmatch(text)
    if not found:
        raise RecordFormatError(path, line, f"{what}: {text.strip()!r} is not a time step (a number, e.g. 0.01 or 10 ms)")
    value = _number(found["number"], path, line)
    return value * (_time_factor(found["unit"], path, line, what) if found["unit"] else 1.0)


def _resolve_dt(
    path: Path, stated: Sequence[_Stated], given: float | None, missing: str, line: int | None = None
) -> float:
    """The time step: what the file states (all statements agreeing), else the argument ``given``.

    ``given`` must agree with the file when the file states one; ``missing`` is the message when
    neither does.
    """
    if given is not None:
        given = _checked_dt(float(given), path, None, "dt")
    for other in stated[1:]:
        if not math.isclose(other.value, stated[0].value, rel_tol=STEP_RTOL):
            raise RecordFormatError(
                path, other.line, f"{other.what} gives dt = {other.value:g} s but {stated[0].what} gives {stated[0].value:g} s"
            )
    if stated:
        first = stated[0]
        if given is not None and not math.isclose(given, first.value, rel_tol=STEP_RTOL):
            raise RecordFormatError(path, first.line, f"{first.what} gives dt = {first.value:g} s but dt = {given:g} s was given")
        return float(first.value)
    if given is None:
        raise RecordFormatError(path, line, missing)
    return given


def _resolve_units(path: Path, stated: _Stated | None, given: str | None, missing: str, line: int | None = None) -> str:
    """The units: what the file states, else the argument ``given`` (which must not contradict the file)."""
    wanted = None if given is None else _checked_units(given, path, None, "units")
    if stated is None:
        if wanted is None:
            raise RecordFormatError(path, line, missing)
        return wanted
    found = _checked_units(stated.value, path, stated.line, stated.what)
    if wanted is not None and wanted != found:
        raise RecordFormatError(
            path, stated.line,
            f"{stated.what} states {found} but units = {given!r} was given; the units argument (--units) is only "
            "for files that do not state their units",
        )
    return found


def _time_step(times: np.ndarray) -> tuple[float, int | None, str]:
    """Mean step of a time axis and, if it is not increasing in equal steps, the index of the
    first bad sample and what is wrong with it (else ``None`` and "")."""
    steps = np.diff(times)
    if steps.size == 0:
        return math.nan, 0, "a time axis needs at least 2 samples"
    backwards = np.flatnonzero(steps <= 0)
    if backwards.size:
        k = int(backwards[0])
        return math.nan, k + 1, f"time {times[k + 1]:g} s after {times[k]:g} s: the time must increase (dt > 0)"
    step = float(times[-1] - times[0]) / steps.size
    uneven = np.flatnonzero(np.abs(steps - step) > STEP_RTOL * step)
    if uneven.size:
        k = int(uneven[0])
        return step, k + 1, (
            f"time step {steps[k]:g} s differs from the mean step {step:g} s by more than {STEP_RTOL:.1%}: "
            "samples must be equally spaced"
        )
    return step, None, ""


# -- PEER NGA .AT2 ----------------------------------------------------------------------------

# The time step's unit, if any, follows it ("DT= .0100 SEC"); read by _step_in_seconds.
_NEW_HEADER = re.compile(
    r"NPTS\s*=\s*(?P<npts>\S+?)\s*,\s*DT\s*=\s*(?P<dt>[^\s,]+(?:\s*[A-Za-z]+\b\.?)?)", re.IGNORECASE
)
_OLD_HEADER = re.compile(r"^\s*(?P<npts>\S+)\s+(?P<dt>\S+)\s+NPTS\s*,\s*DT", re.IGNORECASE)
# "UNITS OF G", "units: cm/s^2", "UNITS = G." (punctuation is stripped by normalize_units) ...
_UNITS_WORD = re.compile(r"\bUNITS?\b\s*(?:OF\b|IN\b|[:=])?\s*(?P<units>[^\s,;]+)", re.IGNORECASE)
# ... or a unit in brackets: "ACCELERATION (G)", "[cm/s^2]".
_BRACKETED_UNIT = re.compile(r"[\[(]\s*([^\])]+?)\s*[\])]")


def _at2_units(text: str) -> str | None:
    """The units stated on line 3 of an .AT2 file, or None if it states none."""
    word = _UNITS_WORD.search(text)
    if word:
        return word["units"]  # checked by the caller: an unknown unit here is an error
    for bracket in _BRACKETED_UNIT.finditer(text):
        try:
            return normalize_units(bracket[1])
        except ParameterError:
            continue  # "(FILTERED)" and such: not a unit
    return None


def _sniff_at2(path: Path) -> bool:
    try:
        head = _lines(path, limit=4096)[:4]
    except RecordFormatError:
        return False
    return len(head) == 4 and bool(_NEW_HEADER.search(head[3]) or _OLD_HEADER.search(head[3]))


def read_at2(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """One component from a PEER NGA ``.AT2`` file.

    Lines 1-3 are free text (line 2 names event, station and component; line 3 the units, e.g.
    ``ACCELERATION TIME SERIES IN UNITS OF G``, ``UNITS OF G.`` or ``ACCELERATION (CM/S^2)``);
    line 4 is ``NPTS= 6000, DT= .0100 SEC`` (NGA-West2) or ``6000 0.0100 NPTS, DT`` (older NGA);
    then NPTS values in free format, possibly glued in fixed-width columns
    (``-0.123E-02-0.456E-02``). ``units`` is used only if line 3 states none and must agree with
    it otherwise; ``dt``, if given, must agree with line 4.
    """
    path = Path(path)
    lines = _lines(path)
    if len(lines) < 4:
        raise RecordFormatError(path, len(lines) + 1, "the file ends inside the 4-line PEER header")
    match = _NEW_HEADER.search(lines[3]) or _OLD_HEADER.search(lines[3])
    if not match:
        raise RecordFormatError(
            path, 4, f"expected 'NPTS= <n>, DT= <dt> SEC' or '<n> <dt> NPTS, DT', got {lines[3].strip()!r}"
        )
    npts_value = _number(match["npts"], path, 4)
    if npts_value != int(npts_value) or npts_value < 2:
        raise RecordFormatError(path, 4, f"NPTS = {match['npts']} must be a whole number >= 2")
    npts = int(npts_value)
    header_dt = _checked_dt(_step_in_seconds(match["dt"], path, 4, "DT"), path, 4, "DT")
    file_dt = _resolve_dt(path, [_Stated(header_dt, "the header (DT)", 4)], dt, "")
    _check_extent(path, npts, file_dt, 4)
    stated_units = _at2_units(lines[2])
    file_units = _resolve_units(
        path,
        None if stated_units is None else _Stated(stated_units, "the units line", 3),
        units,
        f"no units on line 3 ({lines[2].strip()!r}); give them (--units g|m/s^2|cm/s^2)",
        line=3,
    )

    values: list[float] = []
    last_line = 4
    for number, text in enumerate(lines[4:], start=5):
        found = _numbers(text, path, number)
        if found:
            last_line = number
        if len(values) + len(found) > npts:
            raise RecordFormatError(path, number, f"more values than NPTS = {npts} (the header disagrees with the data)")
        values.extend(found)
    if len(values) < npts:
        raise RecordFormatError(
            path, last_line, f"truncated: NPTS = {npts} but the data end after {len(values)} values"
        )
    label = lines[1].rsplit(",", 1)[-1].strip() if "," in lines[1] else ""
    header = [line.rstrip() for line in lines[:4]]
    return [Trace(np.array(values), file_dt, file_units, label=label, metadata={"header": header, "format": "peer-at2"})]


# -- NIED K-NET / KiK-net ASCII ---------------------------------------------------------------

#: The 17 header lines of a K-NET/KiK-net ASCII file, in order: a label, then its value (from
#: column 19). Only the lines the reader uses are checked; the others are kept as metadata.
_KNET_LABELS = (
    "Origin Time", "Lat.", "Long.", "Depth. (km)", "Mag.", "Station Code", "Station Lat.", "Station Long.",
    "Station Height(m)", "Record Time", "Sampling Freq(Hz)", "Duration Time(s)", "Dir.", "Scale Factor",
    "Max. Acc. (gal)", "Last Correction", "Memo.",
)
_KNET_HEADER_LINES = len(_KNET_LABELS)
#: What the lines the reader uses must look like (for the error message).
_KNET_EXPECTED = {
    "Origin Time": "'Origin Time  <yyyy/mm/dd hh:mm:ss>'",
    "Sampling Freq(Hz)": "'Sampling Freq(Hz) <f>Hz' with f > 0, e.g. '100Hz'",
    "Duration Time(s)": "'Duration Time(s)  <s>' with s >= 0",
    "Dir.": "'Dir.  N-S', 'E-W', 'U-D' or a KiK-net channel 1 .. 6",
    "Scale Factor": "'Scale Factor  <numerator>(gal)/<denominator>', both > 0",
    "Max. Acc. (gal)": "'Max. Acc. (gal)  <peak>' with peak >= 0",
    "Memo.": "'Memo.' (the last of the 17 header lines; its text is optional)",
}
#: KiK-net numbers its channels: 1-3 the borehole sensor, 4-6 the surface one.
_KIKNET_CHANNELS = {
    "1": ("NS", "borehole"), "2": ("EW", "borehole"), "3": ("UD", "borehole"),
    "4": ("NS", "surface"), "5": ("EW", "surface"), "6": ("UD", "surface"),
}
_KNET_DIRECTIONS = ("NS", "EW", "UD")

#: Samples a K-NET file may hold beyond ``Duration Time(s) x Sampling Freq(Hz)`` either way. NIED
#: files hold that product exactly (AOM002 of 2018-01-24: 108 s x 100 Hz = 10800 samples) or one
#: more; a little slack forgives a writer that rounds the other way, while a truncated or
#: concatenated file still fails.
KNET_SAMPLE_SLACK = 2
#: Relative tolerance of the header's ``Max. Acc. (gal)`` against the peak of the data after
#: scaling and removing the mean (besides half a unit of its last printed digit): beyond it the
#: scale factor is wrong or the file corrupt.
KNET_PEAK_RTOL = 0.01

_KNET_FREQUENCY = re.compile(rf"(?P<number>{_NUMBER})\s*(?:Hz)?", re.IGNORECASE | re.ASCII)
_KNET_SCALE = re.compile(
    rf"(?P<numerator>{_NUMBER})\s*(?:\(\s*(?P<unit>[^()]*?)\s*\))?\s*/\s*(?P<denominator>{_NUMBER})",
    re.IGNORECASE | re.ASCII,
)
_KNET_COUNT = re.compile(r"[+-]?\d+", re.ASCII)
#: Digits a count may have: K-NET counts have at most 8; more is junk (and could overflow a float).
_KNET_COUNT_DIGITS = 15


def _knet_label(label: str) -> re.Pattern:
    """``label`` as it may be written: its letters and digits in order, case aside, with any
    punctuation or spaces between them (NIED's own page writes ``Max Acc. (gal)`` and ``Lon.``,
    files ``Max. Acc. (gal)`` and ``Long.``), and the punctuation that closes it, then a space or
    the end of the line (``Memorandum`` is not ``Memo.``)."""
    key = re.sub(r"[^0-9a-z]", "", label.lower())
    return re.compile(r"\s*" + r"[\W_]*".join(re.escape(c) for c in key) + r"[^\w\s]*(?=\s|$)", re.IGNORECASE)


def _knet_value(path: Path, lines: list[str], label: str) -> str:
    """The value of the header line ``label`` (at its fixed place in the 17-line header)."""
    number = _KNET_LABELS.index(label) + 1
    text = lines[number - 1]
    match = _knet_label(label).match(text)
    if match is None:
        raise RecordFormatError(path, number, f"expected {_KNET_EXPECTED[label]}, got {text.strip()!r}")
    return text[match.end():].strip()


def _knet_malformed(path: Path, label: str, value: str) -> RecordFormatError:
    return RecordFormatError(
        path, _KNET_LABELS.index(label) + 1, f"expected {_KNET_EXPECTED[label]}, got {label} {value!r}"
    )


def _knet_positive(path: Path, label: str, value: str, number_text: str, allow_zero: bool = False) -> float:
    """A header number that must be > 0 (>= 0 with ``allow_zero``)."""
    line = _KNET_LABELS.index(label) + 1
    if not _NUMBER_RE.fullmatch(number_text):
        raise _knet_malformed(path, label, value)
    number = _number(number_text, path, line)
    if number < 0 or (number == 0 and not allow_zero):
        raise _knet_malformed(path, label, value)
    return number


def _knet_frequency(path: Path, lines: list[str]) -> float:
    """The sampling frequency in Hz ("100Hz", "100", "200 Hz")."""
    label = "Sampling Freq(Hz)"
    value = _knet_value(path, lines, label)
    found = _KNET_FREQUENCY.fullmatch(value)
    if not found:
        raise _knet_malformed(path, label, value)
    return _knet_positive(path, label, value, found["number"])


def _knet_scale(path: Path, lines: list[str]) -> tuple[float, str | None, str]:
    """The scale factor ``numerator/denominator`` (counts to the numerator's unit), the unit as
    written (None if the numerator has none) and the text."""
    label = "Scale Factor"
    value = _knet_value(path, lines, label)
    found = _KNET_SCALE.fullmatch(value)
    if not found:
        raise _knet_malformed(path, label, value)
    numerator = _knet_positive(path, label, value, found["numerator"])
    denominator = _knet_positive(path, label, value, found["denominator"])
    factor = numerator / denominator
    if not math.isfinite(factor) or factor == 0:
        raise _knet_malformed(path, label, value)
    return factor, found["unit"], value


def _knet_direction(path: Path, lines: list[str]) -> tuple[str, str | None]:
    """The component ``NS``, ``EW`` or ``UD`` and, for a numbered KiK-net channel, its sensor
    ("borehole" or "surface"; None when the header does not say)."""
    label = "Dir."
    value = _knet_value(path, lines, label)
    if value in _KIKNET_CHANNELS:
        return _KIKNET_CHANNELS[value]
    code = value.replace("-", "").upper()
    if code not in _KNET_DIRECTIONS:
        raise _knet_malformed(path, label, value)
    return code, None


def _knet_counts(path: Path, lines: list[str]) -> tuple[np.ndarray, int]:
    """The integer counts after the header, and the line of the last one."""
    counts: list[int] = []
    last_line = _KNET_HEADER_LINES
    for number, text in enumerate(lines[_KNET_HEADER_LINES:], start=_KNET_HEADER_LINES + 1):
        tokens = text.split()
        for token in tokens:
            if not _KNET_COUNT.fullmatch(token):
                raise RecordFormatError(path, number, f"{token!r} is not an integer count (K-NET data are whole numbers)")
            if len(token.lstrip("+-")) > _KNET_COUNT_DIGITS:
                raise RecordFormatError(path, number, f"count {token} has more than {_KNET_COUNT_DIGITS} digits")
        if tokens:
            counts.extend(int(token) for token in tokens)
            last_line = number
    if not counts:
        raise RecordFormatError(
            path, _KNET_HEADER_LINES + 1, "no data after the 17-line header: expected integer counts, 8 a line"
        )
    return np.array(counts, dtype=float), last_line


def _check_knet_samples(path: Path, n: int, duration: float, frequency: float, line: int) -> None:
    """The number of samples must be ``Duration Time(s) x Sampling Freq(Hz)``, give or take
    :data:`KNET_SAMPLE_SLACK`."""
    expected = duration * frequency
    if abs(n - expected) > KNET_SAMPLE_SLACK:
        raise RecordFormatError(
            path, line,
            f"{n} samples, but the header says {duration:g} s at {frequency:g} Hz = {expected:g} samples "
            f"(allowed: {KNET_SAMPLE_SLACK} more or fewer; line {_KNET_LABELS.index('Duration Time(s)') + 1}): "
            "a truncated or corrupt file?",
        )


def _check_knet_peak(path: Path, lines: list[str], values: np.ndarray, units: str) -> None:
    """The header's ``Max. Acc. (gal)`` must be the data's peak (after scaling and removing the
    mean) within :data:`KNET_PEAK_RTOL` and half a unit of its last printed digit."""
    label = "Max. Acc. (gal)"
    value = _knet_value(path, lines, label)
    stated = _knet_positive(path, label, value, value, allow_zero=True)
    decimals = len(value.partition(".")[2]) if "." in value else 0
    in_gal = float(np.max(np.abs(values))) * UNIT_FACTORS[units] / UNIT_FACTORS["cm/s^2"]
    if abs(in_gal - stated) > KNET_PEAK_RTOL * stated + 0.5 * 10.0**-decimals:
        raise RecordFormatError(
            path, _KNET_LABELS.index(label) + 1,
            f"the data's peak after scaling and removing the mean is {in_gal:.6g} gal but the header states "
            f"{value} gal (more than {KNET_PEAK_RTOL:.0%} apart): a wrong scale factor or a corrupt file",
        )


def _sniff_knet(path: Path) -> bool:
    try:
        head = _lines(path, limit=4096)[:_KNET_HEADER_LINES]
    except RecordFormatError:
        return False
    return (
        bool(head) and head[0].startswith("Origin Time")
        and any(line.startswith("Scale Factor") for line in head)
        and any(line.startswith("Sampling Freq") for line in head)
    )


def read_knet(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """One component from an NIED K-NET or KiK-net ASCII file (``.NS``, ``.EW``, ``.UD``; KiK-net
    ``.NS1`` ... ``.UD1`` borehole, ``.NS2`` ... ``.UD2`` surface).

    A 17-line header of ``label  value`` lines (``Origin Time`` ... ``Memo.``), then integer counts,
    8 a line. Acceleration = counts x the ``Scale Factor`` ``<numerator>(gal)/<denominator>``, in
    the numerator's unit (gal, i.e. cm/s^2); the time step is 1 / ``Sampling Freq(Hz)``
    (``100Hz``). The counts carry an offset, so the mean of the whole record is removed, as NIED
    describes and common tools do; the header's ``Max. Acc. (gal)`` must then agree with the peak
    (:data:`KNET_PEAK_RTOL`), and the number of samples with ``Duration Time(s)`` x the frequency
    (:data:`KNET_SAMPLE_SLACK`). ``Dir.`` (``N-S``, ``E-W``, ``U-D``, or KiK-net's channels
    1 .. 6) gives the label ``NS``, ``EW`` or ``UD`` (with ``1``/``2`` appended for a numbered
    KiK-net borehole/surface channel), so that a ``U-D`` file counts as vertical. ``dt`` and
    ``units``, if given, must agree with the header.
    """
    path = Path(path)
    lines = _lines(path)
    if lines:  # first: a file of another format given a K-NET suffix is told so at once
        _knet_value(path, lines, "Origin Time")
    if len(lines) < _KNET_HEADER_LINES:
        raise RecordFormatError(path, len(lines) + 1, f"the file ends inside the {_KNET_HEADER_LINES}-line K-NET header")
    # In line order, so that a missing line is reported where it should be.
    frequency = _knet_frequency(path, lines)
    duration_text = _knet_value(path, lines, "Duration Time(s)")
    duration = _knet_positive(path, "Duration Time(s)", duration_text, duration_text, allow_zero=True)
    direction, sensor = _knet_direction(path, lines)
    factor, unit, scale_text = _knet_scale(path, lines)
    _knet_value(path, lines, "Memo.")

    line = _KNET_LABELS.index("Sampling Freq(Hz)") + 1
    header_dt = _checked_dt(1.0 / frequency, path, line, "1 / Sampling Freq(Hz)")
    file_dt = _resolve_dt(path, [_Stated(header_dt, "the header (Sampling Freq)", line)], dt, "")
    line = _KNET_LABELS.index("Scale Factor") + 1
    # The format gives counts in gal; a numerator without its unit in brackets means gal.
    file_units = _resolve_units(path, _Stated(unit or "gal", "the Scale Factor", line), units, "")

    counts, last_line = _knet_counts(path, lines)
    if counts.size < 2:
        raise RecordFormatError(path, last_line, f"{counts.size} sample; a record needs at least 2")
    _check_knet_samples(path, counts.size, duration, frequency, last_line)
    _check_extent(path, counts.size, file_dt, last_line)
    offset = float(np.mean(counts))
    values = (counts - offset) * factor
    _check_knet_peak(path, lines, values, file_units)

    meta: dict[str, Any] = {
        "format": "knet",
        "header": [text.rstrip() for text in lines[:_KNET_HEADER_LINES]],
        "direction": direction,
        "scale": scale_text,
        "offset_removed": offset * factor,  # in the trace's units
    }
    if sensor is not None:
        meta["sensor"] = sensor
    label = direction + {"borehole": "1", "surface": "2", None: ""}[sensor]
    return [Trace(values, file_dt, file_units, label=label, metadata=meta)]


# -- columns (CSV, whitespace) ----------------------------------------------------------------

# "t", "time", and with a unit: "time [ms]", "t (s)", "time ms", "time_ms" (not "t1", "timestamp").
_TIME_NAME = re.compile(r"^\s*(?:t|time)(?![A-Za-z0-9])(?P<rest>.*)$", re.IGNORECASE)
# What may stand between a time column's name and an unbracketed unit: "time ms", "t/s", "time in s".
_UNIT_LEAD = re.compile(r"^[\s_:/-]*(?:in\s+)?", re.IGNORECASE)
_COMMENT_KEY = re.compile(r"^[#%]\s*(?P<key>units?|dt)\s*[:=]\s*(?P<value>.+?)\s*$", re.IGNORECASE)
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+(?:[EeDd][+-]?\d+)?$", re.ASCII)


def _time_column_factor(name: str, path: Path, line: int) -> float:
    """Seconds per unit of the time column named ``name`` ("time [ms]", "t (s)", "time ms"): the
    unit in brackets, else the words after t/time; none is seconds. Any other unit is an error."""
    rest = _TIME_NAME.match(name)["rest"]
    bracket = _BRACKETED_UNIT.search(rest)
    unit = bracket[1] if bracket else rest[_UNIT_LEAD.match(rest).end():].strip()
    return _time_factor(unit, path, line, f"the time column {name!r}") if unit else 1.0


def _delimiter(line: str) -> str | None:
    # ';' and tab first: a file with decimal commas ("1,5;2,5") contains ',' as well.
    return next((d for d in (";", "\t", ",") if d in line), None)


def _cells(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    if line.endswith(delimiter):  # a trailing delimiter ends the row, it does not open a column
        line = line[: -len(delimiter)]
    return [cell.strip() for cell in line.split(delimiter)]


def _numeric_text(cell: str, delimiter: str | None) -> str:
    # With ';' or tab between cells a comma can only be a decimal comma: "1,5" is 1.5.
    return cell.replace(",", ".") if delimiter in (";", "\t") and _DECIMAL_COMMA.match(cell) else cell


def _row(cells: list[str], delimiter: str | None, path: Path, line: int) -> list[float]:
    if delimiter is None:  # whitespace columns may be fixed-width, with glued values
        return _numbers(" ".join(cells), path, line)
    values = []
    for j, cell in enumerate(cells):
        if not cell:
            raise RecordFormatError(path, line, f"column {j + 1} is empty")
        values.append(_number(_numeric_text(cell, delimiter), path, line))
    return values


def read_columns(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """Components from a text file with one column per component (CSV, ``;``, tab or spaces).

    Lines starting with ``#`` or ``%`` are comments; ``# units: g`` and ``# dt: 0.01`` (or
    ``# dt: 10 ms``) are understood. An optional first row of column names (no cell of it a
    number) may carry units (``ax [g]``, ``a_ew (m/s^2)``). With ``;`` or tab between cells,
    ``1,5`` is read as 1.5; a trailing delimiter is ignored. The first column is a time column if
    its name is ``t``/``time``, optionally with a unit among :data:`TIME_UNITS` (``time [ms]``,
    ``t (s)``; seconds if none, an error if another), or, in a file without names, if it
    increases from row to row (at least 3 rows; seconds; it must then increase in equal steps).
    Every other column is one acceleration
    component, in file order. ``dt`` and ``units`` are used only when the file states neither a
    time column nor a ``# dt`` (resp. no units), and must agree with the file otherwise.
    """
    path = Path(path)
    lines = _lines(path)
    comments: dict[str, _Stated] = {}
    header: tuple[list[str], int] | None = None
    rows: list[tuple[int, list[float]]] = []
    delimiter: str | None = None
    for number, text in enumerate(lines, start=1):
        stripped = text.strip()
        if not stripped:
            continue
        if stripped[0] in "#%":
            found = _COMMENT_KEY.match(stripped)
            if found:
                key = "units" if found["key"].lower().startswith("unit") else "dt"
                comments[key] = _Stated(found["value"], f"the '# {key}' comment", number)
            continue
        if delimiter is None:
            delimiter = _delimiter(stripped)
        cells = _cells(stripped, delimiter)
        # Only a row without a single number is a header: "1,2,x" is data with a typo, and taking
        # it for names would silently drop a sample.
        if header is None and not rows and not any(_looks_numeric(_numeric_text(c, delimiter)) for c in cells):
            header = (cells, number)
            continue
        rows.append((number, _row(cells, delimiter, path, number)))
    if len(rows) < 2:
        raise RecordFormatError(path, len(lines) or 1, f"expected at least 2 rows of numbers, found {len(rows)}")
    width = len(rows[0][1])
    if header is not None and len(header[0]) != width:
        raise RecordFormatError(path, header[1], f"{len(header[0])} column names but {width} columns of data")
    for number, values in rows:
        if len(values) != width:
            raise RecordFormatError(path, number, f"{len(values)} values where the first data row has {width} (truncated row?)")
    data = np.array([values for _, values in rows])

    names = header[0] if header else [""] * width
    if header:
        has_time = bool(_TIME_NAME.match(names[0]))
        what = f"the time column {names[0]!r}"
    else:
        # An acceleration never rises from row to row, so such a first column is a time axis.
        has_time = width > 1 and len(rows) >= 3 and bool(np.all(np.diff(data[:, 0]) > 0))
        what = "the first column (increasing, so taken for time; a header row naming the columns says otherwise)"
    stated_dt = []
    if has_time:
        if header:
            data[:, 0] *= _time_column_factor(names[0], path, header[1])
        step, bad, problem = _time_step(data[:, 0])
        if bad is not None:
            raise RecordFormatError(path, rows[bad][0], f"{what}: {problem}")
        stated_dt.append(_Stated(step, what, rows[1][0]))
        data, names = data[:, 1:], names[1:]
        if data.shape[1] == 0:
            raise RecordFormatError(path, rows[0][0], "only a time column, no acceleration columns")
    if "dt" in comments:
        comment = comments["dt"]
        value = _checked_dt(_step_in_seconds(comment.value, path, comment.line, comment.what), path, comment.line, comment.what)
        stated_dt.append(comment._replace(value=value))
    file_dt = _resolve_dt(
        path, stated_dt, dt, "no time column and no dt: give dt (--dt) or a '# dt: <s>' comment", line=rows[0][0]
    )
    where = stated_dt[0].line if stated_dt else None
    _checked_dt(file_dt, path, where, stated_dt[0].what if stated_dt else "dt")
    _check_extent(path, data.shape[0], file_dt, where)

    file_units = []
    for name in names:
        bracket = _BRACKETED_UNIT.search(name)
        if bracket:
            stated = _Stated(bracket[1], f"column {name!r}", header[1])
        else:
            stated = comments.get("units")
        file_units.append(
            _resolve_units(
                path, stated, units,
                "the units are not stated: give them (--units g|m/s^2|cm/s^2), a '# units: ...' comment or "
                "column names like 'ax [g]'",
                line=header[1] if header else rows[0][0],
            )
        )
    labels = [_BRACKETED_UNIT.sub("", name).strip() for name in names]
    return [
        Trace(data[:, j], file_dt, file_units[j], label=labels[j], metadata={"format": "columns", "column": j})
        for j in range(data.shape[1])
    ]


def _sniff_columns(path: Path) -> bool:
    try:
        lines = _lines(path, limit=65536)
    except RecordFormatError:
        return False
    for text in lines[:50]:
        stripped = text.strip()
        if stripped and stripped[0] not in "#%":
            delimiter = _delimiter(stripped)
            if all(_looks_numeric(_numeric_text(c, delimiter)) for c in _cells(stripped, delimiter)):
                return True
    return False


# -- NumPy .npz -------------------------------------------------------------------------------

_NPZ_TIME_KEYS = ("time", "t")
_NPZ_STACK_KEYS = ("acc", "acceleration")
# Arrays that describe the record rather than hold a component.
_NPZ_META_KEYS = {
    "dt", "units", "names", "source", "synthetic", "lengths", "source_units", "scale_factor", "metadata",
    *_NPZ_TIME_KEYS,
}


def _npz_arrays(path: Path) -> dict[str, np.ndarray]:
    """Every array of the archive; one that cannot be loaded (pickled objects) names itself."""
    try:
        archive = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise RecordFormatError(path, None, f"not a readable .npz archive ({exc})") from None
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise RecordFormatError(path, None, "a single .npy array, not an .npz archive of named arrays (np.savez)")
    arrays = {}
    with archive:
        for key in archive.files:
            try:
                arrays[key] = archive[key]
            except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
                # allow_pickle=False: an object array (strings of mixed length, lists) cannot be loaded.
                raise RecordFormatError(path, None, f"cannot load the array ({exc})", f"array {key!r}") from None
    return arrays


def _npz_scalar(arrays: dict[str, np.ndarray], key: str, path: Path, kind: str) -> Any:
    """The single value of array ``key``: ``kind`` is "number", "text" or "flag"."""
    array = arrays[key]
    if array.size != 1:
        raise RecordFormatError(path, None, f"must be a single {kind}, got an array of shape {array.shape}", f"array {key!r}")
    value = array.reshape(()).item()
    ok = {
        "number": isinstance(value, (int, float)) and not isinstance(value, bool),
        "text": isinstance(value, str),
        "flag": isinstance(value, bool),
    }[kind]
    if not ok:
        raise RecordFormatError(path, None, f"must be a single {kind}, got {value!r} (dtype {array.dtype})", f"array {key!r}")
    return value


def _npz_texts(arrays: dict[str, np.ndarray], key: str, path: Path, count: int) -> list[str]:
    array = arrays[key]
    if array.dtype.kind not in "US" or array.shape != (count,):
        raise RecordFormatError(
            path, None, f"must be {count} strings, one per component, got shape {array.shape} (dtype {array.dtype})",
            f"array {key!r}",
        )
    return [str(s) for s in array]


def _npz_series(path: Path, key: str, values: np.ndarray) -> np.ndarray:
    where = f"array {key!r}"
    if values.dtype.kind not in "iuf":
        raise RecordFormatError(path, None, f"is not real numbers (dtype {values.dtype})", where)
    if values.ndim != 1 or values.size < 2:
        raise RecordFormatError(path, None, f"must be 1-D with at least 2 samples, got shape {values.shape}", where)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise RecordFormatError(path, None, f"value {values[bad[0]]} is not finite", f"{where}, index {bad[0]}")
    return values.astype(float)


def read_npz(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """Components from a NumPy ``.npz`` archive (``np.savez``; no pickled objects).

    Components: the arrays ``h1``, ``h2``, ``v`` if present; else an ``acc`` (or
    ``acceleration``) array of shape ``(3, n)`` or ``(n, 3)``; else every other numeric array
    (each must be 1-D) in stored order. Time step: a scalar ``dt`` and/or a ``time``/``t``
    array (equally spaced; both must agree); the argument ``dt`` only if the archive has
    neither, and it must agree otherwise. Units: a string ``units``; the argument only if there
    is none (an error if it differs). Optional: ``names`` (component labels), ``source``,
    ``synthetic``, and what :meth:`Record.to_npz` writes besides: ``lengths`` (the components'
    unpadded lengths), ``source_units``, ``scale_factor`` and ``metadata`` (a JSON object).
    Problems are located by array name and index (an archive has no lines).
    """
    path = Path(path)
    arrays = _npz_arrays(path)
    if all(k in arrays for k in ROLES):
        series = [(k, _npz_series(path, k, arrays[k])) for k in ROLES]
    elif any(k in arrays for k in _NPZ_STACK_KEYS):
        key = next(k for k in _NPZ_STACK_KEYS if k in arrays)
        stack = arrays[key]
        if stack.ndim != 2 or 3 not in stack.shape:
            raise RecordFormatError(path, None, f"must have shape (3, n) or (n, 3), got {stack.shape}", f"array {key!r}")
        stack = stack if stack.shape[0] == 3 else stack.T
        series = [(f"{key}[{i}]", _npz_series(path, f"{key}[{i}]", stack[i])) for i in range(3)]
    else:
        # Text arrays (notes, comments) cannot be components; every numeric one must be.
        others = [(k, a) for k, a in arrays.items() if k not in _NPZ_META_KEYS and a.dtype.kind not in "US"]
        series = [(k, _npz_series(path, k, a)) for k, a in others]
    if not series:
        raise RecordFormatError(path, None, f"no acceleration arrays found (arrays: {', '.join(arrays) or 'none'})")

    if "lengths" in arrays:  # written by Record.to_npz: the components before zero padding
        lengths = arrays["lengths"]
        where = "array 'lengths'"
        if lengths.dtype.kind not in "iu" or lengths.shape != (len(series),):
            raise RecordFormatError(path, None, f"must be {len(series)} whole numbers, got {lengths!r}", where)
        for i, ((key, values), k) in enumerate(zip(series, lengths)):
            if not 2 <= k <= values.size:
                raise RecordFormatError(
                    path, None, f"{k} is not between 2 and the length {values.size} of {key!r}", f"{where}, index {i}"
                )
        series = [(key, values[:k]) for (key, values), k in zip(series, lengths)]

    stated_dt = []
    if "dt" in arrays:
        step = _checked_dt(float(_npz_scalar(arrays, "dt", path, "number")), path, None, "array 'dt'")
        stated_dt.append(_Stated(step, "array 'dt'"))
    time_key = next((k for k in _NPZ_TIME_KEYS if k in arrays), None)
    if time_key is not None:
        where = f"array {time_key!r}"
        times = _npz_series(path, time_key, arrays[time_key])
        longest = max(values.size for _, values in series)
        if times.size != longest:
            raise RecordFormatError(path, None, f"has {times.size} times for {longest} samples", where)
        step, bad, problem = _time_step(times)
        if bad is not None:
            raise RecordFormatError(path, None, problem, f"{where}, index {bad}")
        stated_dt.append(_Stated(step, where))
    file_dt = _resolve_dt(path, stated_dt, dt, "no 'dt' or 'time' array and no dt given (--dt)")
    where = stated_dt[0].what if stated_dt else None
    _checked_dt(file_dt, path, None, "dt", where)
    _check_extent(path, max(values.size for _, values in series), file_dt, None, where)

    stated_units = None if "units" not in arrays else _Stated(_npz_scalar(arrays, "units", path, "text"), "array 'units'")
    file_units = _resolve_units(
        path, stated_units, units, "no 'units' array and no units given (--units g|m/s^2|cm/s^2)"
    )
    if "names" in arrays:
        labels = _npz_texts(arrays, "names", path, len(series))
    else:
        labels = [key if key in ROLES else "" for key, _ in series]

    meta: dict[str, Any] = {"format": "npz"}
    if "source" in arrays:
        meta["source"] = _npz_scalar(arrays, "source", path, "text")
    if "synthetic" in arrays:
        meta["synthetic"] = _npz_scalar(arrays, "synthetic", path, "flag")
    record_meta: dict[str, Any] = {}
    if "metadata" in arrays:
        try:
            record_meta = json.loads(_npz_scalar(arrays, "metadata", path, "text"))
        except json.JSONDecodeError as exc:
            raise RecordFormatError(path, None, f"is not a JSON object ({exc})", "array 'metadata'") from None
        if not isinstance(record_meta, dict):
            raise RecordFormatError(path, None, "is not a JSON object", "array 'metadata'")
    if "scale_factor" in arrays:
        factor = float(_npz_scalar(arrays, "scale_factor", path, "number"))
        if not math.isfinite(factor) or factor <= 0:
            raise RecordFormatError(path, None, f"{factor!r} must be finite and > 0", "array 'scale_factor'")
        if factor != 1.0:
            record_meta["scale_factor"] = factor
    if record_meta:
        meta["record"] = record_meta
    originals = [None] * len(series)
    if "source_units" in arrays:
        originals = [
            _checked_units(u, path, None, f"array 'source_units', index {i}")
            for i, u in enumerate(_npz_texts(arrays, "source_units", path, len(series)))
        ]
    return [
        Trace(values, file_dt, file_units, label=label, metadata={**meta, **({"source_units": o} if o else {})})
        for (_, values), label, o in zip(series, labels, originals)
    ]


def _sniff_npz(path: Path) -> bool:
    try:
        with open(path, "rb") as handle:
            return handle.read(4) == b"PK\x03\x04"  # a zip archive, which is what np.savez writes
    except OSError:
        return False


AT2_READER = RecordReader(
    name="peer-at2",
    suffixes=(".at2",),
    read=read_at2,
    sniff=_sniff_at2,
    description="PEER NGA strong-motion file, one component (both NPTS/DT header styles)",
)
COLUMNS_READER = RecordReader(
    name="columns",
    suffixes=(".csv", ".txt", ".dat", ".tsv", ".asc"),
    read=read_columns,
    sniff=_sniff_columns,
    description="text columns (CSV, ';', tab or spaces), optional time column, units in names or comments",
)
KNET_READER = RecordReader(
    name="knet",
    suffixes=(".ns", ".ew", ".ud", ".ns1", ".ew1", ".ud1", ".ns2", ".ew2", ".ud2"),
    read=read_knet,
    sniff=_sniff_knet,
    description="NIED K-NET/KiK-net ASCII file, one component (counts x scale factor, mean removed; gal)",
)
NPZ_READER = RecordReader(
    name="npz",
    suffixes=(".npz",),
    read=read_npz,
    sniff=_sniff_npz,
    description="NumPy .npz archive: h1, h2, v (or acc), dt or time, units",
)


# -- choosing a reader and assembling a record ------------------------------------------------


def _readers(registry) -> dict[str, Any]:
    from bearingfw.plugins import get_registry  # the registry is built on first use

    registry = registry or get_registry()
    return {name: entry.value for name, entry in registry.record_readers.items()}


def _known(readers: dict[str, Any]) -> str:
    return "; ".join(f"{name} ({' '.join(getattr(r, 'suffixes', ())) or 'by name'})" for name, r in sorted(readers.items())) or (
        "none: is bearingfw installed with pip?"
    )


def find_reader(path: str | Path, name: str | None = None, registry=None):
    """The registered reader for ``path``: by ``name`` if given, else by suffix, else by sniffing."""
    path = Path(path)
    readers = _readers(registry)
    if name is not None:
        if name not in readers:
            raise UnknownReaderError(f"unknown record format {name!r}; known formats: {_known(readers)}")
        return readers[name]
    lower = path.name.lower()
    # Case-insensitive both ways: a third-party reader may declare ".DAT" (not every reader is a
    # RecordReader, which lower-cases its suffixes).
    by_suffix = [r for r in readers.values() if any(lower.endswith(s.lower()) for s in getattr(r, "suffixes", ()))]

    def sniffs(reader) -> bool:
        sniff = getattr(reader, "sniff", None)
        try:
            return bool(sniff(path)) if sniff is not None else False
        except Exception:  # a third-party sniffer must not break the choice
            return False

    confirmed = [r for r in by_suffix if getattr(r, "sniff", None) is None or sniffs(r)]
    if confirmed:
        return confirmed[0]
    if by_suffix:
        return by_suffix[0]  # the reader will say precisely what is wrong with the file
    sniffed = [r for r in readers.values() if sniffs(r)]
    if sniffed:
        return sniffed[0]
    raise UnknownReaderError(f"{path}: no reader recognises this file; choose one with --format: {_known(readers)}")


def read_record(
    paths: str | Path | Sequence[str | Path],
    *,
    format: str | None = None,
    dt: float | None = None,
    units: str | None = None,
    registry=None,
) -> Record:
    """Read one record from one or more files.

    The components of all files, in the order given and within each file in the file's order,
    are horizontal 1, horizontal 2 and vertical: three ``.AT2`` files, or one file with three
    acceleration columns. ``format`` names a reader (default: chosen per file); ``dt`` and
    ``units`` are passed to the readers, which use them only for files that do not state them
    (and reject them when they contradict a file).
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    paths = [Path(p) for p in paths]
    if not paths:
        raise ParameterError("read_record: no files given")
    traces: list[Trace] = []
    used = []
    counts = []
    per_file = []
    for path in paths:
        reader, found = read_file(path, format=format, dt=dt, units=units, registry=registry)
        traces.extend(found)
        per_file.extend([(path, len(found))] * len(found))
        used.append(reader.name)
        counts.append(f"{path.name}: {len(found)}")
    if len(traces) != 3:
        raise ParameterError(
            "a record needs 3 acceleration components (horizontal 1, horizontal 2, vertical), "
            f"the files give {len(traces)} ({', '.join(counts)})"
        )
    synthetic = any(t.metadata.get("synthetic", False) for t in traces)
    stored_source = next((t.metadata["source"] for t in traces if "source" in t.metadata), None)
    source = stored_source or ", ".join(p.name for p in paths)
    stored = next((t.metadata["record"] for t in traces if "record" in t.metadata), {})  # an archive bearingfw wrote
    # The roles are fixed by the order here, so a vertical-looking horizontal is only noted: a
    # directional mapping (load_directional) refuses it.
    notes = list(stored.get("notes", ()))
    for role, trace, (path, count) in zip(("horizontal 1", "horizontal 2"), traces, per_file):
        others = [t for t in traces if t is not trace]
        evidence = vertical_evidence(trace, path, count, others)
        note = f"{path.name} is given as {role} but looks vertical: " + "; ".join(e.reason for e in evidence)
        if evidence and note not in notes:  # an archive bearingfw wrote keeps its notes
            notes.append(note)
    meta = {**stored, "files": [str(p) for p in paths], "readers": used, "g": G}
    if notes:
        meta["notes"] = notes
    return assemble(traces, source=source, synthetic=synthetic, metadata=meta)


def read_file(
    path: str | Path, *, format: str | None = None, dt: float | None = None, units: str | None = None, registry=None
) -> tuple[Any, list[Trace]]:
    """The reader chosen for one file and the traces it read (at least one)."""
    path = Path(path)
    if path.is_dir():
        raise RecordFormatError(path, None, "is a directory, not a record file")
    if not path.is_file():
        raise RecordFormatError(path, None, "no such file")
    reader = find_reader(path, format, registry)
    found = list(reader.read(path, dt=dt, units=units))
    for trace in found:
        if not isinstance(trace, Trace):
            raise TypeError(f"record reader {reader.name!r} returned {trace!r} for {path}, not bearingfw.motion.Trace")
    if not found:
        raise RecordFormatError(path, None, f"the {reader.name} reader found no acceleration component in it")
    for k, trace in enumerate(found):
        _check_amplitude(path, k, trace)
    return reader, found


def _check_amplitude(path: Path, k: int, trace: Trace) -> None:
    """Refuse a component with a value beyond MAX_ACCELERATION (in m/s^2, whatever the file's units)."""
    factor = UNIT_FACTORS[trace.units]
    i = int(np.argmax(np.abs(trace.values)))
    value = float(trace.values[i])
    if abs(value) * factor > MAX_ACCELERATION:
        what = f"component {k + 1}" + (f" ({trace.label})" if trace.label else "")
        raise RecordFormatError(
            path, None,
            f"value {value:g} {trace.units}" + (f" = {value * factor:.4g} m/s^2" if factor != 1.0 else "")
            + f" is outside the allowed range "
            f"|a| <= {MAX_ACCELERATION:g} m/s^2 (100 g): are the units right?",
            f"{what}, sample {i + 1}",
        )


def _trace_frequency(trace: Trace) -> float | None:
    values = trace.in_si()
    return dominant_frequency(values, trace.dt) if np.any(values) and values.size >= 8 else None


def vertical_evidence(trace: Trace, path: str | Path, count: int, others: Sequence[Trace] = ()) -> list[Evidence]:
    """Why ``trace`` (read from ``path``, a file of ``count`` components) looks vertical: its file
    name (one-component files only), its label (PEER header, K-NET ``Dir.``, column or array name) and its
    amplitudes against ``others``, the other components of the event (see
    :mod:`bearingfw.motion.vertical`). Empty if nothing says so."""
    found = []
    if count == 1:
        found.append(name_evidence(path))
    form = trace.metadata.get("format")
    header = trace.metadata.get("header") if form == "peer-at2" else None
    what = {"columns": "column name", "npz": "array name", "knet": "K-NET direction (Dir.)"}.get(form, "label")
    # A KiK-net label may end in its sensor digit ("UD1"): the direction alone is the code.
    label = trace.metadata.get("direction", trace.label) if form == "knet" else trace.label
    found.append(label_evidence(label, header=header, what=what))
    if others:
        compared = [(o.label or f"component {i + 1}", peak(o.in_si()), _trace_frequency(o)) for i, o in enumerate(others)]
        found.append(amplitude_evidence(peak(trace.in_si()), _trace_frequency(trace), compared))
    return [e for e in found if e is not None]

