"""The results store: one directory per experiment, a file per finished cell, written atomically.

Layout (every file opens without bearingfw)::

    DIR/experiment.toml                  the experiment as run
    DIR/manifest.json                    cells, their digests and states; versions; the last run
    DIR/cells/<model>/<record>/<intensity>.json   one cell: inputs, digest, status, metrics, stats,
                                                  error (a failed cell), record measures, laws
    DIR/cells/<model>/<record>/<intensity>.npz    its time histories (float32; key "meta": JSON)
    DIR/records.json, DIR/modal.json     record measures and modal results per model
    DIR/matrices.json, DIR/ratios.json   {metric: {model: {intensity: value}}}
    DIR/matrices/<metric>.csv, DIR/ratios/<metric>.csv, DIR/cells.csv
    DIR/figures/*.png, *.svg, DIR/report.md, DIR/summary.json

Atomic writes: a file is written to a temporary name in its folder, flushed to disk, then
renamed over the target (``os.replace``, atomic on POSIX and Windows), so a reader sees the old
file or the new one, never a part. A cell writes its histories first and its JSON last: the JSON
is the cell's commit, and a cell counts as finished only when its JSON is there, reads, carries
the current digest and status ``ok`` (and its histories file exists, when histories are kept).
So an interrupted run (Ctrl-C, kill -9, a crash, a power cut between the two files) loses at
most the cells in progress. A failed cell is recorded (status ``failed`` with the error) and is
tried again on the next run.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import uuid
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

__all__ = ["CELL_FORMAT", "Store", "atomic_write", "dumps", "jsonable"]

CELL_FORMAT = "bearingfw-cell/1"
_TEMPORARY = ".partial-"


def atomic_write(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and a rename (module docstring)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.parent / f"{_TEMPORARY}{path.name}.{os.getpid()}.{uuid.uuid4().hex[:12]}"
    # os.open, not tempfile.mkstemp: the file gets the umask's permissions (mkstemp's are 0600)
    fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, path)
    except BaseException:  # interrupted or failed: leave no partial file behind
        temporary.unlink(missing_ok=True)
        raise
    return path


def jsonable(value):
    """``value`` with NaN and infinities as None (JSON has no NaN), numpy scalars and tuples as plain data."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (np.floating, float)):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, (np.bool_,)):
        return bool(value)
    if isinstance(value, Path):
        return str(value)
    return value


def dumps(data) -> bytes:
    """Indented JSON (NaN as null) as bytes."""
    return (json.dumps(jsonable(data), indent=2) + "\n").encode()


class Store:
    """The results directory of one experiment (module docstring)."""

    def __init__(self, root: str | Path):
        self.root = Path(root)

    # ---- paths ----------------------------------------------------------------------------------
    def cell_json(self, cell_id: str) -> Path:
        return self.root / "cells" / f"{cell_id}.json"

    def cell_npz(self, cell_id: str) -> Path:
        return self.root / "cells" / f"{cell_id}.npz"

    def path(self, *parts: str) -> Path:
        return self.root.joinpath(*parts)

    # ---- generic files --------------------------------------------------------------------------
    def write_json(self, name: str, data) -> Path:
        return atomic_write(self.root / name, dumps(data))

    def write_text(self, name: str, text: str) -> Path:
        return atomic_write(self.root / name, text.encode())

    def write_csv(self, name: str, header: Iterable, rows: Iterable[Iterable]) -> Path:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(rows)
        return atomic_write(self.root / name, buffer.getvalue().encode())

    def read_json(self, name: str):
        try:
            return json.loads((self.root / name).read_text())
        except (OSError, ValueError):
            return None

    def clean_temporaries(self) -> int:
        """Remove temporary files an interrupted writer left behind; return how many."""
        count = 0
        if self.root.is_dir():
            for leftover in self.root.rglob(f"{_TEMPORARY}*"):
                leftover.unlink(missing_ok=True)
                count += 1
        return count

    # ---- cells ----------------------------------------------------------------------------------
    def write_cell(self, document: dict, histories: Mapping[str, np.ndarray] | None, meta: dict | None = None) -> Path:
        """Commit a cell: its histories (if any) first, then its JSON document."""
        cell_id = document["id"]
        if histories is not None:
            buffer = io.BytesIO()
            arrays = {k: np.asarray(v, dtype=np.float32) for k, v in histories.items()}
            np.savez_compressed(buffer, meta=np.array(json.dumps(jsonable(meta or {}))), **arrays)
            atomic_write(self.cell_npz(cell_id), buffer.getvalue())
        return atomic_write(self.cell_json(cell_id), dumps({"format": CELL_FORMAT, **document}))

    def read_cell(self, cell_id: str) -> dict | None:
        """The cell's document, or None if it is missing or unreadable."""
        try:
            document = json.loads(self.cell_json(cell_id).read_text())
        except (OSError, ValueError):
            return None
        return document if isinstance(document, dict) and document.get("format") == CELL_FORMAT else None

    def is_finished(self, cell_id: str, digest: str, histories: bool) -> bool:
        """True if the cell is stored with status ok, this digest, and its histories when they are kept."""
        document = self.read_cell(cell_id)
        if document is None or document.get("digest") != digest or document.get("status") != "ok":
            return False
        return not histories or self.cell_npz(cell_id).is_file()

    def read_histories(self, cell_id: str) -> tuple[dict[str, np.ndarray], dict] | None:
        """The cell's histories and their description, or None."""
        try:
            with np.load(self.cell_npz(cell_id), allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                return {k: z[k] for k in z.files if k != "meta"}, meta
        except (OSError, ValueError, KeyError):
            return None
