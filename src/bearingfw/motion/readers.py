"""The built-in record readers (PEER ``.AT2``, CSV/whitespace columns, NumPy ``.npz``) and
:func:`read_record`, which turns one or more files into a :class:`~bearingfw.motion.Record`.

Every reader returns :class:`~bearingfw.motion.Trace` objects in the file's own units and
time step; unit conversion, resampling and padding happen once, in
:func:`~bearingfw.motion.record.assemble`. A malformed file raises
:class:`~bearingfw.motion.RecordFormatError` naming the file and the line.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from bearingfw.motion.errors import RecordFormatError, UnknownReaderError
from bearingfw.motion.record import G, Record, Trace, assemble, normalize_units
from bearingfw.parameters import ParameterError
from bearingfw.plugins.contracts import RecordReader

__all__ = [
    "AT2_READER",
    "COLUMNS_READER",
    "NPZ_READER",
    "find_reader",
    "read_at2",
    "read_columns",
    "read_npz",
    "read_record",
]


def _lines(path: Path) -> list[str]:
    # latin-1 never fails on odd bytes in free-text headers; splitlines() handles CRLF and CR.
    try:
        return path.read_text(encoding="latin-1").splitlines()
    except OSError as exc:
        raise RecordFormatError(path, None, f"cannot read the file ({exc.strerror or exc})") from exc


def _number(token: str, path: Path, line: int) -> float:
    try:
        value = float(token)
    except ValueError:
        try:  # Fortran double-precision exponent, e.g. 1.0D-03
            value = float(token.replace("D", "E").replace("d", "e"))
        except ValueError:
            raise RecordFormatError(path, line, f"{token!r} is not a number") from None
    if not math.isfinite(value):
        raise RecordFormatError(path, line, f"value {token!r} is not finite")
    return value


def _checked_units(units: str | None, path: Path, line: int | None, what: str) -> str:
    try:
        return normalize_units(units)
    except ParameterError as exc:
        raise RecordFormatError(path, line, f"{what}: {exc}") from None


def _checked_dt(dt: float, path: Path, line: int | None, what: str) -> float:
    if not math.isfinite(dt) or dt <= 0:
        raise RecordFormatError(path, line, f"{what} = {dt!r} s; the time step must be > 0")
    return dt


# -- PEER NGA .AT2 ----------------------------------------------------------------------------

_NEW_HEADER = re.compile(r"NPTS\s*=\s*(?P<npts>\S+?)\s*,\s*DT\s*=\s*(?P<dt>\S+)", re.IGNORECASE)
_OLD_HEADER = re.compile(r"^\s*(?P<npts>\S+)\s+(?P<dt>\S+)\s+NPTS\s*,\s*DT", re.IGNORECASE)
_UNITS_LINE = re.compile(r"UNITS\s+OF\s+(?P<units>\S+)", re.IGNORECASE)


def _sniff_at2(path: Path) -> bool:
    try:
        with open(path, encoding="latin-1") as handle:
            head = [handle.readline() for _ in range(4)]
    except OSError:
        return False
    return bool(_NEW_HEADER.search(head[3]) or _OLD_HEADER.search(head[3])) if len(head) == 4 else False


def read_at2(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """One component from a PEER NGA ``.AT2`` file.

    Lines 1-3 are free text (line 2 names event, station and component; line 3 the units, e.g.
    ``ACCELERATION TIME SERIES IN UNITS OF G``); line 4 is ``NPTS= 6000, DT= .0100 SEC``
    (NGA-West2) or ``6000 0.0100 NPTS, DT`` (older NGA); then NPTS values in free format.
    ``units`` overrides line 3; ``dt``, if given, must agree with line 4.
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
    file_dt = _checked_dt(_number(match["dt"], path, 4), path, 4, "DT")
    if dt is not None and not math.isclose(float(dt), file_dt, rel_tol=1e-6):
        raise RecordFormatError(path, 4, f"the file says DT = {file_dt:g} s but dt = {dt:g} s was given")
    if units is None:
        unit_match = _UNITS_LINE.search(lines[2])
        if not unit_match:
            raise RecordFormatError(path, 3, f"no 'UNITS OF ...' in {lines[2].strip()!r}; give the units explicitly")
        file_units = _checked_units(unit_match["units"], path, 3, "units")
    else:
        file_units = _checked_units(units, path, None, "units")

    values: list[float] = []
    last_line = 4
    for number, text in enumerate(lines[4:], start=5):
        tokens = text.split()
        if tokens:
            last_line = number
        for token in tokens:
            if len(values) == npts:
                raise RecordFormatError(path, number, f"more values than NPTS = {npts} (the header disagrees with the data)")
            values.append(_number(token, path, number))
    if len(values) < npts:
        raise RecordFormatError(
            path, last_line, f"truncated: NPTS = {npts} but the data end after {len(values)} values"
        )
    label = lines[1].rsplit(",", 1)[-1].strip() if "," in lines[1] else ""
    header = [line.rstrip() for line in lines[:4]]
    return [Trace(np.array(values), file_dt, file_units, label=label, metadata={"header": header, "format": "peer-at2"})]


# -- columns (CSV, whitespace) ----------------------------------------------------------------

_TIME_NAME = re.compile(r"^\s*(t|time)\b", re.IGNORECASE)
_BRACKETED_UNIT = re.compile(r"[\[(]\s*([^\])]+?)\s*[\])]")
_COMMENT_KEY = re.compile(r"^[#%]\s*(?P<key>units?|dt)\s*[:=]\s*(?P<value>.+?)\s*$", re.IGNORECASE)


def _split(text: str, delimiter: str | None) -> list[str]:
    return [cell.strip() for cell in text.split(delimiter)] if delimiter else text.split()


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def read_columns(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """Components from a text file with one column per component (CSV, ``;``, tab or spaces).

    Lines starting with ``#`` or ``%`` are comments; ``# units: g`` and ``# dt: 0.01`` are
    understood. An optional first row of column names may carry units (``ax [g]``,
    ``a_ew (m/s^2)``). The first column is a time column if its name is ``t``/``time...`` or, in a
    file without names, if it increases in equal steps; otherwise ``dt`` must be given (argument
    or comment). Every other column is one acceleration component, in file order.
    """
    path = Path(path)
    lines = _lines(path)
    comment_values: dict[str, tuple[str, int]] = {}
    header: tuple[list[str], int] | None = None
    rows: list[tuple[int, list[str]]] = []
    delimiter: str | None = None
    for number, text in enumerate(lines, start=1):
        stripped = text.strip()
        if not stripped:
            continue
        if stripped[0] in "#%":
            found = _COMMENT_KEY.match(stripped)
            if found:
                key = "units" if found["key"].lower().startswith("unit") else "dt"
                comment_values[key] = (found["value"], number)
            continue
        if delimiter is None:
            delimiter = next((d for d in (",", ";", "\t") if d in stripped), None)
        cells = _split(stripped, delimiter)
        if header is None and not rows and not all(_is_number(c) for c in cells):
            header = (cells, number)
            continue
        rows.append((number, cells))
    if len(rows) < 2:
        raise RecordFormatError(path, len(lines) or 1, f"expected at least 2 rows of numbers, found {len(rows)}")
    width = len(rows[0][1])
    if header is not None and len(header[0]) != width:
        raise RecordFormatError(path, header[1], f"{len(header[0])} column names but {width} columns of data")
    data = np.empty((len(rows), width))
    for i, (number, cells) in enumerate(rows):
        if len(cells) != width:
            raise RecordFormatError(path, number, f"{len(cells)} values where the first data row has {width} (truncated row?)")
        data[i] = [_number(c, path, number) for c in cells]

    names = header[0] if header else [""] * width
    if header:
        has_time = bool(_TIME_NAME.match(names[0]))
    else:
        # Guess only when nothing else gives the step; a lone column is always acceleration.
        has_time = dt is None and "dt" not in comment_values and width > 1 and _uniformly_increasing(data[:, 0])
    if has_time:
        steps = np.diff(data[:, 0])
        step = float(steps.mean()) if steps.size else math.nan
        if not np.all(steps > 0):
            bad = int(np.flatnonzero(steps <= 0)[0])
            raise RecordFormatError(path, rows[bad + 1][0], "the time column must increase (the time step must be > 0)")
        irregular = np.flatnonzero(np.abs(steps - step) > 1e-3 * step)
        if irregular.size:
            bad = int(irregular[0])
            raise RecordFormatError(
                path, rows[bad + 1][0], f"time step {steps[bad]:g} s differs from the mean {step:g} s: samples must be equally spaced"
            )
        if dt is not None and not math.isclose(float(dt), step, rel_tol=1e-3):
            raise RecordFormatError(path, rows[1][0], f"the time column has dt = {step:g} s but dt = {dt:g} s was given")
        file_dt = step
        data, names = data[:, 1:], names[1:]
        if data.shape[1] == 0:
            raise RecordFormatError(path, rows[0][0], "only a time column, no acceleration columns")
    elif dt is not None:
        file_dt = _checked_dt(float(dt), path, None, "dt")
    elif "dt" in comment_values:
        text, number = comment_values["dt"]
        file_dt = _checked_dt(_number(text, path, number), path, number, "dt")
    else:
        raise RecordFormatError(path, rows[0][0], "no time column and no dt: give dt (--dt) or a '# dt: <s>' comment")

    if units is not None:
        file_units = [_checked_units(units, path, None, "units")] * data.shape[1]
    else:
        file_units = []
        for name in names:
            bracket = _BRACKETED_UNIT.search(name)
            if bracket:
                file_units.append(_checked_units(bracket[1], path, header[1], f"units of column {name!r}"))
            elif "units" in comment_values:
                text, number = comment_values["units"]
                file_units.append(_checked_units(text, path, number, "units"))
            else:
                raise RecordFormatError(
                    path, header[1] if header else rows[0][0],
                    "the units are not stated: give them (--units g|m/s^2|cm/s^2), a '# units: ...' comment or "
                    "column names like 'ax [g]'",
                )
    labels = [_BRACKETED_UNIT.sub("", name).strip() for name in names]
    return [
        Trace(data[:, j], file_dt, file_units[j], label=labels[j], metadata={"format": "columns", "column": j})
        for j in range(data.shape[1])
    ]


def _uniformly_increasing(column: np.ndarray) -> bool:
    # An acceleration never rises in equal steps, so such a first column is a time axis.
    steps = np.diff(column)
    return column.size >= 3 and bool(np.all(steps > 0)) and float(np.ptp(steps)) <= 1e-6 * float(steps.mean())


def _sniff_columns(path: Path) -> bool:
    try:
        with open(path, encoding="latin-1") as handle:
            for _ in range(50):
                text = handle.readline()
                if not text:
                    return False
                stripped = text.strip()
                if stripped and stripped[0] not in "#%":
                    cells = re.split(r"[,;\s]+", stripped)
                    if all(_is_number(c) for c in cells if c):
                        return True
    except (OSError, UnicodeDecodeError):
        return False
    return False


# -- NumPy .npz -------------------------------------------------------------------------------

_NPZ_ROLE_KEYS = ("h1", "h2", "v")
_NPZ_TIME_KEYS = ("time", "t")


def read_npz(path: str | Path, *, dt: float | None = None, units: str | None = None) -> list[Trace]:
    """Components from a NumPy ``.npz`` archive (``np.savez``; no pickled objects).

    Components: the arrays ``h1``, ``h2``, ``v`` if present; else an ``acc`` (or
    ``acceleration``) array of shape ``(3, n)``; else every other 1-D numeric array in stored
    order. Time step: a scalar ``dt`` or a ``time``/``t`` array; the argument ``dt`` if neither.
    Units: a string ``units`` (the argument overrides it). Optional ``names``: component labels.
    Problems are located by array name and index (an archive has no lines).
    """
    path = Path(path)
    try:
        archive = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise RecordFormatError(path, None, f"not a readable .npz archive ({exc})") from None
    with archive:
        arrays = {key: archive[key] for key in archive.files}
    meta_keys = {"dt", "units", "names", "source", "synthetic", *_NPZ_TIME_KEYS}
    if all(k in arrays for k in _NPZ_ROLE_KEYS):
        series = [(k, arrays[k]) for k in _NPZ_ROLE_KEYS]
    elif "acc" in arrays or "acceleration" in arrays:
        key = "acc" if "acc" in arrays else "acceleration"
        stack = arrays[key]
        if stack.ndim != 2 or 3 not in stack.shape:
            raise RecordFormatError(path, None, f"array {key!r} must have shape (3, n) or (n, 3), got {stack.shape}", f"array {key!r}")
        stack = stack if stack.shape[0] == 3 else stack.T
        series = [(f"{key}[{i}]", stack[i]) for i in range(3)]
    else:
        series = [(k, a) for k, a in arrays.items() if k not in meta_keys and a.ndim == 1]
    if not series:
        raise RecordFormatError(path, None, f"no acceleration arrays found (arrays: {', '.join(arrays) or 'none'})")
    for key, values in series:
        if not np.issubdtype(values.dtype, np.number) or np.iscomplexobj(values):
            raise RecordFormatError(path, None, f"array {key!r} is not real numbers (dtype {values.dtype})", f"array {key!r}")
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise RecordFormatError(path, None, f"value {values[bad[0]]} is not finite", f"array {key!r}, index {bad[0]}")

    if "dt" in arrays:
        file_dt = _checked_dt(float(arrays["dt"]), path, None, "array 'dt'")
        if dt is not None and not math.isclose(float(dt), file_dt, rel_tol=1e-6):
            raise RecordFormatError(path, None, f"the archive says dt = {file_dt:g} s but dt = {dt:g} s was given")
    elif any(k in arrays for k in _NPZ_TIME_KEYS):
        key = next(k for k in _NPZ_TIME_KEYS if k in arrays)
        steps = np.diff(arrays[key].astype(float))
        if steps.size == 0 or not np.all(steps > 0) or float(np.ptp(steps)) > 1e-3 * float(steps.mean()):
            raise RecordFormatError(path, None, "the time array must increase in equal steps", f"array {key!r}")
        file_dt = float(steps.mean())
    elif dt is not None:
        file_dt = _checked_dt(float(dt), path, None, "dt")
    else:
        raise RecordFormatError(path, None, "no 'dt' or 'time' array and no dt given (--dt)")

    if units is not None:
        file_units = _checked_units(units, path, None, "units")
    elif "units" in arrays:
        file_units = _checked_units(str(arrays["units"]), path, None, "array 'units'")
    else:
        raise RecordFormatError(path, None, "no 'units' array and no units given (--units g|m/s^2|cm/s^2)")
    labels = [str(s) for s in arrays["names"]] if "names" in arrays and arrays["names"].size == len(series) else [
        key if key in _NPZ_ROLE_KEYS else "" for key, _ in series
    ]
    meta: dict[str, Any] = {"format": "npz"}
    if "source" in arrays:
        meta["source"] = str(arrays["source"])
    if "synthetic" in arrays:
        meta["synthetic"] = bool(arrays["synthetic"])
    return [Trace(values, file_dt, file_units, label=label, metadata=meta) for (key, values), label in zip(series, labels)]


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
    by_suffix = [r for r in readers.values() if any(lower.endswith(s) for s in getattr(r, "suffixes", ()))]

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
    ``units`` are passed to the readers for files that do not state them.
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    paths = [Path(p) for p in paths]
    if not paths:
        raise ParameterError("read_record: no files given")
    traces: list[Trace] = []
    used = []
    counts = []
    for path in paths:
        if not path.is_file():
            raise RecordFormatError(path, None, "no such file")
        reader = find_reader(path, format, registry)
        found = list(reader.read(path, dt=dt, units=units))
        for trace in found:
            if not isinstance(trace, Trace):
                raise TypeError(f"record reader {reader.name!r} returned {trace!r} for {path}, not bearingfw.motion.Trace")
        traces.extend(found)
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
    return assemble(
        traces,
        source=source,
        synthetic=synthetic,
        metadata={"files": [str(p) for p in paths], "readers": used, "g": G},
    )

