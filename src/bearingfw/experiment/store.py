"""The results store: one directory per experiment, a file per finished cell, written atomically.

Layout (every file opens without bearingfw)::

    DIR/experiment.toml                  the experiment as run
    DIR/manifest.json                    cells, their digests and states; versions; the last run
    DIR/.lock                            held by the run writing into DIR: its pid, host, experiment
    DIR/cells/<model>/<record>/<intensity>.json   one cell: inputs, digest, status, metrics, stats,
                                                  error (a failed cell), record measures, laws
    DIR/cells/<model>/<record>/<intensity>.npz    its time histories (float32; key "meta": JSON,
                                                  with the cell's digest and the thinning "every")
    DIR/records.json, DIR/modal.json     record measures and modal results per model
    DIR/matrices.json, DIR/ratios.json   {metric: {model: {intensity: value}}}
    DIR/matrices/<metric>.csv, DIR/ratios/<metric>.csv, DIR/cells.csv
    DIR/figures/*.png, *.svg, DIR/report.md, DIR/summary.json

Atomic writes: a file is written to a temporary name in its folder (``.partial-<name>.<host>-<pid>.<random>``),
flushed to disk, then renamed over the target (``os.replace``, atomic on POSIX and Windows), so a
reader sees the old file or the new one, never a part. A cell writes its histories first and its
JSON last: the JSON is the cell's commit, and a cell counts as finished only when its JSON is
there, reads, carries the current digest and status ``ok``, and, when histories are kept, its
histories file carries the same digest and thinning. So an interrupted run (Ctrl-C, kill -9, a
crash, a power cut between the two files) loses at most the cells in progress. A failed cell is
recorded (status ``failed`` with the error) and is tried again on the next run.

Integrity: a cell's JSON carries the SHA-256 of its own content (``checksum``) and of its
histories file (``histories_sha256``); a stored cell counts as finished only while both match
(:meth:`Store.damage`). A cell whose files were edited, emptied or damaged after they were
written is computed again, and the run says so; it is never kept as ``ok``.

One run at a time (:meth:`Store.claim`): a run holds an exclusive lock on ``DIR/.lock``
(``flock``; the operating system releases it when the process ends, however it ends, so a lock
is never stale) and writes its pid, host and experiment into it; a second run into the same
directory stops at once with an error naming the holder. The directory belongs to one
experiment (its ``name``): a run of another experiment, or into a non-empty directory that is no
results store, stops with an error and changes nothing, unless it is told to take the directory
over (``bearingfw run --take-over``). Taking over: the run's own files (``experiment.toml``,
the manifest, matrices, figures, report) are then the new experiment's, written over the old
ones; a stored cell at a place (model/record/intensity) the new experiment also has is reused
when its digest is the new one's (the same computation: names are not inputs) and recomputed and
replaced otherwise; the other cells stay on disk untouched, outside the new results.

Nothing is deleted but the run's own temporaries and those a *dead* writer of this host left
behind (its pid is in the name); a temporary of a live process, or of another host, is left
alone (and never read: only complete files are).
"""

from __future__ import annotations

import contextlib
import csv
import datetime
import hashlib
import io
import json
import math
import os
import platform
import re
import sys
import tomllib
import uuid
import zipfile
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path

import numpy as np

__all__ = ["CELL_FORMAT", "LOCK_NAME", "Store", "StoreError", "atomic_write", "dumps", "jsonable", "thinned"]

CELL_FORMAT = "bearingfw-cell/1"
LOCK_NAME = ".lock"
_TEMPORARY = ".partial-"
# The host in a temporary's name, reduced to characters that cannot be confused with the separators.
_HOST = re.sub(r"[^A-Za-z0-9]+", "_", platform.node() or "localhost")
_TEMPORARY_NAME = re.compile(rf"^{re.escape(_TEMPORARY)}.+\.(?P<host>[A-Za-z0-9_]+)-(?P<pid>\d+)\.[0-9a-f]{{12}}$")


class StoreError(RuntimeError):
    """The results directory cannot take this run: another run holds it, or it holds something else."""


def atomic_write(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and a rename (module docstring)."""
    path = Path(path)
    temporary = path.parent / f"{_TEMPORARY}{path.name}.{_HOST}-{os.getpid()}.{uuid.uuid4().hex[:12]}"
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        # os.open, not tempfile.mkstemp: the file gets the umask's permissions (mkstemp's are 0600)
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    except OSError as exc:
        raise _naming(exc, path) from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, path)
    except BaseException as exc:  # interrupted or failed: leave no partial file behind
        with contextlib.suppress(OSError):
            temporary.unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise _naming(exc, path) from None
        raise
    return path


def _naming(exc: OSError, path: Path) -> OSError:
    """``exc`` naming the file that was being written (a full disk's error names none, a failed
    create names the temporary): "DIR/x.json: No space left on device", not a bare "[Errno 28]"."""
    if exc.filename is not None and _TEMPORARY not in Path(exc.filename).name:
        return exc
    return type(exc)(exc.errno, exc.strerror or str(exc), str(path))


def _alive(pid: int) -> bool:
    """True unless process ``pid`` of this host certainly does not exist."""
    if pid == os.getpid():
        return True
    if os.name == "nt":  # os.kill(pid, 0) would terminate the process there: assume it runs
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # e.g. another user's process: it exists
        return True
    return True


def thinned(histories: Mapping[str, np.ndarray], every: int) -> dict:
    """Every ``every``-th sample of each time history (the first, the dead-load state, always); the ground
    acceleration (``ground.*``, the record's own samples) is kept whole."""
    return {k: (v if k.startswith("ground.") else v[::every]) for k, v in histories.items()}


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


def _try_lock(fd: int) -> bool:
    """Take the exclusive lock on the open file ``fd`` without waiting; False if another holds it."""
    try:
        import fcntl
    except ImportError:  # Windows: lock one byte far past the holder's text, which stays readable
        import msvcrt

        os.lseek(fd, 1 << 20, os.SEEK_SET)
        try:
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        except OSError:
            return False
        return True
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except (BlockingIOError, PermissionError):
        return False
    return True


def _unlock(fd: int) -> None:
    try:
        import fcntl
    except ImportError:
        import msvcrt

        os.lseek(fd, 1 << 20, os.SEEK_SET)
        msvcrt.locking(fd, msvcrt.LK_UNLCK, 1)
        return
    fcntl.flock(fd, fcntl.LOCK_UN)


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
        """Remove the temporaries that writers of this host which no longer run left behind (an
        interrupted run's); return how many. Others' are left alone (module docstring)."""
        count = 0
        if self.root.is_dir():
            for leftover in self.root.rglob(f"{_TEMPORARY}*"):
                found = _TEMPORARY_NAME.match(leftover.name)
                if found and found["host"] == _HOST and not _alive(int(found["pid"])) and leftover.is_file():
                    leftover.unlink(missing_ok=True)
                    count += 1
        return count

    # ---- one run, one experiment ----------------------------------------------------------------
    def experiment_name(self) -> str | None:
        """The name of the experiment the directory holds (its manifest's, else its experiment.toml's)."""
        manifest = self.read_json("manifest.json")
        if isinstance(manifest, dict) and isinstance(manifest.get("experiment"), str):
            return manifest["experiment"]
        try:
            name = tomllib.loads(self.path("experiment.toml").read_text(encoding="utf-8")).get("name")
        except (OSError, ValueError):
            return None
        return name if isinstance(name, str) else None

    def holder(self) -> dict | None:
        """What the lock file says about the run holding (or last holding) the directory."""
        holder = self.read_json(LOCK_NAME)
        return holder if isinstance(holder, dict) else None

    def check_owner(self, experiment: str, take_over: bool = False) -> None:
        """Raise :class:`StoreError` unless the directory is new, empty, or holds ``experiment``
        (or ``take_over``: then any directory will do)."""
        if not self.root.exists() or take_over:
            return
        if not self.root.is_dir():
            raise StoreError(f"{self.root} is not a directory")
        held = self.experiment_name()
        if held == experiment:
            return
        if held is None:
            if not any(p.name != LOCK_NAME for p in self.root.iterdir()):
                return
            raise StoreError(
                f"{self.root} is not empty and holds no bearingfw results (no manifest.json or experiment.toml); "
                "nothing was written. Choose another output directory, or take it over (bearingfw run --take-over) "
                "to write the results among its files"
            )
        raise StoreError(
            f"{self.root} holds the results of experiment {held!r}, not {experiment!r}; nothing was changed. "
            f"Choose another output directory, or let {experiment!r} take it over (bearingfw run --take-over): "
            f"its cells with the same inputs are reused, the other cells of {held!r} stay on disk but leave the "
            "matrices and the report"
        )

    @contextlib.contextmanager
    def claim(self, experiment: str, take_over: bool = False) -> Iterator[Store]:
        """Hold the directory for one run of ``experiment`` (module docstring); :class:`StoreError` if
        another run holds it or it holds something else. Nothing is written before both checks pass,
        except the lock file itself in a directory that is new, empty or a results store."""
        self.check_owner(experiment, take_over)  # before the lock file: a stranger's folder stays untouched
        self.root.mkdir(parents=True, exist_ok=True)
        fd = os.open(self.path(LOCK_NAME), os.O_RDWR | os.O_CREAT | getattr(os, "O_BINARY", 0), 0o666)
        try:
            if not _try_lock(fd):
                raise StoreError(f"{self.root} is in use by another bearingfw run ({_describe(self.holder())}); "
                                 "wait for it to end, stop it, or choose another output directory")
            try:
                # The holder's text stays in the file when the lock is released: it shows who last ran here.
                os.ftruncate(fd, 0)
                os.lseek(fd, 0, os.SEEK_SET)
                os.write(fd, dumps({
                    "pid": os.getpid(), "host": platform.node(), "experiment": experiment,
                    "since": datetime.datetime.now().isoformat(timespec="seconds"),
                    "command": " ".join(sys.argv),
                }))
                self.check_owner(experiment, take_over)  # the run that held it before may have changed it
                yield self
            finally:
                _unlock(fd)
        finally:
            os.close(fd)

    # ---- cells ----------------------------------------------------------------------------------
    def write_cell(self, document: dict, histories: Mapping[str, np.ndarray] | None, meta: dict | None = None) -> Path:
        """Commit a cell: its histories (if any) first, then its JSON document, which carries the
        checksums of both (module docstring, integrity)."""
        document = {k: v for k, v in document.items() if k not in ("checksum", "histories_sha256")}
        if histories is not None:
            document["histories_sha256"] = self.write_histories(document["id"], histories, meta or {})[1]
        return self._commit({"format": CELL_FORMAT, **document})

    def _commit(self, document: dict) -> Path:
        data = jsonable({k: v for k, v in document.items() if k != "checksum"})
        return atomic_write(self.cell_json(document["id"]), dumps({**data, "checksum": _checksum(data)}))

    def write_histories(self, cell_id: str, histories: Mapping[str, np.ndarray], meta: dict) -> tuple[Path, str]:
        """Write a cell's histories file; its path and the SHA-256 of its bytes."""
        buffer = io.BytesIO()
        with np.errstate(over="ignore"):  # beyond float32's range is inf (the cell's checks judge the values)
            arrays = {k: np.asarray(v, dtype=np.float32) for k, v in histories.items()}
        _savez(buffer, {"meta": np.array(json.dumps(jsonable(meta))), **arrays})
        data = buffer.getvalue()
        return atomic_write(self.cell_npz(cell_id), data), hashlib.sha256(data).hexdigest()

    def damage(self, cell_id: str) -> str | None:
        """What is wrong with the stored files of a cell whose JSON reads (None if they are as written):
        a JSON whose content no longer matches its checksum (edited, emptied, truncated by hand or by
        a fault), or a histories file that is not the one committed with it."""
        document = self.read_cell(cell_id)
        if document is None:
            return None
        stored = document.get("checksum")
        if stored is None:
            return "the cell's JSON carries no checksum (written by an older bearingfw, or edited)"
        if _checksum({k: v for k, v in document.items() if k != "checksum"}) != stored:
            return "the cell's JSON does not match its checksum (edited or damaged after it was written)"
        expected = document.get("histories_sha256")
        if expected is not None:
            try:
                actual = hashlib.sha256(self.cell_npz(cell_id).read_bytes()).hexdigest()
            except OSError:
                return "the cell's histories file is missing or unreadable"
            if actual != expected:
                return "the cell's histories file does not match the checksum committed with it"
        return None

    def read_cell(self, cell_id: str) -> dict | None:
        """The cell's document, or None if it is missing or unreadable."""
        try:
            document = json.loads(self.cell_json(cell_id).read_text())
        except (OSError, ValueError):
            return None
        return document if isinstance(document, dict) and document.get("format") == CELL_FORMAT else None

    def is_finished(self, cell_id: str, digest: str, every: int | None) -> bool:
        """True if the cell is stored with status ok and this digest and, when histories are kept
        (``every``: the thinning; None: none kept), histories of this digest thinned so."""
        document = self.read_cell(cell_id)
        if document is None or document.get("digest") != digest or document.get("status") != "ok":
            return False
        if self.damage(cell_id) is not None:
            return False
        if every is None:
            return True
        meta = self.history_meta(cell_id)
        return meta is not None and meta.get("digest") == digest and meta.get("every") == every

    def history_meta(self, cell_id: str) -> dict | None:
        """The description stored with the cell's histories (reads only that), or None."""
        try:
            with np.load(self.cell_npz(cell_id), allow_pickle=False) as z:
                return json.loads(str(z["meta"]))
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
            return None

    def read_histories(self, cell_id: str) -> tuple[dict[str, np.ndarray], dict] | None:
        """The cell's histories and their description, or None."""
        try:
            with np.load(self.cell_npz(cell_id), allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                return {k: z[k] for k in z.files if k != "meta"}, meta
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
            return None

    def rethin(self, cell_id: str, digest: str, every: int) -> bool:
        """Make the stored histories of a finished cell ``every``-thinned without computing it again,
        when they are this digest's and finer by a whole factor; True if done (or nothing to do)."""
        stored = self.read_histories(cell_id)
        if stored is None:
            return False
        histories, meta = stored
        have = meta.get("every")
        if meta.get("digest") != digest or not isinstance(have, int) or have < 1 or every % have:
            return False
        if have != every:
            document = self.read_cell(cell_id)
            if document is None:
                return False
            _, checksum = self.write_histories(cell_id, thinned(histories, every // have), {**meta, "every": every})
            self._commit({**document, "histories_sha256": checksum})  # the new histories' checksum
        return True


def _checksum(data: dict) -> str:
    """SHA-256 of a cell document's canonical JSON (sorted keys, no spaces)."""
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _describe(holder: dict | None) -> str:
    if not holder:
        return "a process that has not said who it is yet"
    return (f"pid {holder.get('pid')} on host {holder.get('host')}, experiment {holder.get('experiment')!r}, "
            f"since {holder.get('since')}")


def _savez(file, arrays: Mapping[str, np.ndarray]) -> None:
    """``np.savez_compressed`` at zlib's fastest level: float32 histories shrink about as much at
    level 1 as at numpy's level 6 (within 1 %) in half the time. ``np.load`` reads it as any .npz."""
    with zipfile.ZipFile(file, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as archive:
        for name, value in arrays.items():
            with archive.open(f"{name}.npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.asanyarray(value), allow_pickle=False)
