"""Records whose components are mapped explicitly to the global axes x, y, z.

``load_directional({"x": "EW.AT2", "y": "-NS.AT2"})`` reads one, two or three components, each
from its own file or as the k-th component of a multi-component file (``"rec.csv#2"``, 1-based),
with an optional leading ``-`` to flip its sign. A direction given no component has zero ground
acceleration, and the record's notes say so. A component that looks vertical (file name, PEER
header or column name, amplitudes: :mod:`bearingfw.motion.vertical`) is refused on x or y unless
``vertical_as_horizontal=True``.

The result is an ordinary :class:`~bearingfw.motion.Record` whose roles are the axes (``h1`` = x,
``h2`` = y, ``v`` = z): every measure, scaling and printout works on it unchanged, PGA_H10 and
t_Ha read x and y as the horizontals.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.motion.errors import VerticalComponentError
from bearingfw.motion.readers import read_file, vertical_evidence
from bearingfw.motion.record import AXIS_ROLES, G, Record, Trace, _pad_to_longest, _peak, resample
from bearingfw.parameters import ParameterError

__all__ = ["AXES", "ComponentRef", "load_directional", "parse_component"]

#: The global axes a component can drive: x and y horizontal, z vertical (up).
AXES = tuple(AXIS_ROLES)
_HORIZONTAL_AXES = ("x", "y")
_INDEX = re.compile(r"#(\d+)$")


@attrs.frozen
class ComponentRef:
    """One entry of a mapping: ``axis = "[-]FILE[#k]"`` parsed (``index`` 1-based or None)."""

    axis: str
    text: str
    path: Path
    index: int | None = None
    flip: bool = False


def parse_component(axis: str, text: Any, base_dir: str | Path | None = None) -> ComponentRef:
    """Parse ``"[-]FILE[#k]"`` for ``axis``; a relative FILE is taken relative to ``base_dir``.

    A file whose name starts with ``-`` is written ``./-name``; a ``#`` not followed by digits
    up to the end belongs to the file name.
    """
    if not isinstance(text, (str, Path)) or not str(text).strip():
        raise ParameterError(f"{axis} = {text!r}: expected a file path, optionally '#k' (k-th component) and a leading "
                             "'-' (flip the sign), e.g. \"-records/tremor.csv#2\"")
    raw = str(text).strip()
    flip = raw.startswith("-")
    rest = raw[1:].strip() if flip else raw
    index = None
    found = _INDEX.search(rest)
    if found:
        index = int(found[1])
        rest = rest[: found.start()]
        if index < 1:
            raise ParameterError(f"{axis} = {text!r}: the component number after '#' is 1-based (k >= 1), got {index}")
    if not rest:
        raise ParameterError(f"{axis} = {text!r}: no file name")
    path = Path(rest).expanduser()
    if not path.is_absolute() and base_dir is not None:
        path = Path(base_dir) / path
    return ComponentRef(axis=axis, text=raw, path=path, index=index, flip=flip)


def _pick(ref: ComponentRef, traces: list[Trace]) -> Trace:
    where = f"{ref.axis} = {ref.text!r}: {ref.path}"
    if ref.index is None:
        if len(traces) > 1:
            raise ParameterError(
                f"{where} holds {len(traces)} components; pick one with '#k', e.g. \"{ref.text}#1\" (k = 1 .. {len(traces)})"
            )
        return traces[0]
    if ref.index > len(traces):
        raise ParameterError(f"{where} holds {len(traces)} component(s); '#{ref.index}' must be between 1 and {len(traces)}")
    return traces[ref.index - 1]


def _name(ref: ComponentRef, trace: Trace, count: int) -> str:
    label = trace.label or (ref.path.stem + (f"#{ref.index}" if count > 1 else ""))
    return f"{ref.axis}: {'-' if ref.flip else ''}{label}"


def load_directional(
    mapping: Mapping[str, Any],
    *,
    base_dir: str | Path | None = None,
    format: str | None = None,
    dt: float | None = None,
    units: str | None = None,
    vertical_as_horizontal: bool = False,
    registry=None,
) -> Record:
    """One record from components mapped to the global axes: ``{"x": FILE, "y": FILE, "z": FILE}``.

    Any subset of x, y, z (at least one); each value ``"[-]FILE[#k]"`` (:func:`parse_component`).
    ``format``, ``dt``, ``units`` go to the readers as in :func:`~bearingfw.motion.read_record`
    (used only for files that do not state them). The components are converted to m/s^2,
    resampled to the finest time step among them and padded with trailing zeros to the longest;
    a direction without a component is zero and named in the notes (``metadata['missing']``).

    A component on x or y that looks vertical raises :class:`~bearingfw.motion.VerticalComponentError`
    naming the file and the evidence, unless ``vertical_as_horizontal`` (then a note says it).
    """
    if not isinstance(mapping, Mapping) or not mapping:
        raise ParameterError(f"a directional record needs at least one of x, y, z mapped to a file, got {mapping!r}")
    unknown = [k for k in mapping if k not in AXES]
    if unknown:
        raise ParameterError(f"unknown direction(s) {', '.join(map(repr, unknown))}; the directions are x, y, z")
    if not isinstance(vertical_as_horizontal, bool):
        raise ParameterError(f"vertical_as_horizontal must be true or false, got {vertical_as_horizontal!r}")
    refs = [parse_component(axis, mapping[axis], base_dir) for axis in AXES if axis in mapping]

    read: dict[Path, tuple[Any, list[Trace]]] = {}
    for ref in refs:
        if ref.path not in read:
            read[ref.path] = read_file(ref.path, format=format, dt=dt, units=units, registry=registry)
    picked = {ref.axis: (ref, _pick(ref, read[ref.path][1])) for ref in refs}

    notes = []
    for axis in _HORIZONTAL_AXES:
        if axis not in picked:
            continue
        ref, trace = picked[axis]
        others = [t for other, (_, t) in picked.items() if other != axis]
        evidence = vertical_evidence(trace, ref.path, len(read[ref.path][1]), others)
        if not evidence:
            continue
        reasons = "; ".join(e.reason for e in evidence)
        component = f" (component {ref.index})" if ref.index is not None else ""
        if not vertical_as_horizontal:
            raise VerticalComponentError(
                ref.path, axis, evidence,
                f"{axis} = {ref.text!r}: the component{component} looks vertical and x, y are horizontal: {reasons}. "
                f"Map it to z, or set vertical_as_horizontal = true if a vertical motion should drive {axis}",
            )
        notes.append(f"{axis}: {ref.path.name}{component} looks vertical ({reasons}) and drives {axis} as asked "
                     "(vertical_as_horizontal)")

    traces = [t for _, t in picked.values()]
    target = min(t.dt for t in traces)
    series = {axis: (-1.0 if ref.flip else 1.0) * resample(t.in_si(), t.dt, target) for axis, (ref, t) in picked.items()}
    padded, lengths = _pad_to_longest(list(series.values()))
    n = padded[0].size
    columns = dict(zip(series, padded))
    counts = dict(zip(series, lengths or [n] * len(series)))
    missing = [axis for axis in AXES if axis not in picked]
    for axis in missing:
        columns[axis] = np.zeros(n)
        counts[axis] = n
        notes.append(f"no component is mapped to {axis}: its ground acceleration is zero")

    def per_axis(given, absent):
        return [given(*picked[axis]) if axis in picked else absent for axis in AXES]

    stored = next((t.metadata["record"] for t in traces if "record" in t.metadata), {})
    meta: dict[str, Any] = {
        **stored,
        "files": [str(p) for p in read],
        "readers": [reader.name for reader, _ in read.values()],
        "g": G,
        "directions": {ref.axis: ref.text for ref in refs},
        "missing": missing,
    }
    if notes or stored.get("notes"):
        meta["notes"] = [*stored.get("notes", ()), *notes]
    if any(not math.isclose(t.dt, target, rel_tol=1e-12) for t in traces):
        meta["resampled_from"] = per_axis(lambda ref, t: t.dt, target)
        meta["peaks_before_resampling"] = per_axis(lambda ref, t: _peak(t.in_si()), 0.0)
    lengths_out = tuple(counts[axis] for axis in AXES)
    return Record(
        h1=columns["x"], h2=columns["y"], v=columns["z"], dt=target,
        names=tuple(
            _name(*picked[axis], len(read[picked[axis][0].path][1])) if axis in picked else f"{axis}: none"
            for axis in AXES
        ),
        source=", ".join(f"{ref.axis}={'-' if ref.flip else ''}{ref.path.name}"
                         + (f"#{ref.index}" if ref.index is not None else "") for ref in refs),
        synthetic=any(t.metadata.get("synthetic", False) for t in traces),
        lengths=None if all(k == n for k in lengths_out) else lengths_out,
        # A missing axis has no units of its own: it takes the first component's, so that a
        # printout of the source units lists only what the files hold.
        source_units=per_axis(lambda ref, t: t.metadata.get("source_units") or t.units,
                              traces[0].metadata.get("source_units") or traces[0].units),
        metadata=meta,
    )
