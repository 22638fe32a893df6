"""The result of a transient run: time histories as numpy arrays, the energy table, run statistics.

Saved as one NPZ file that opens without bearingfw::

    import json, numpy as np
    z = np.load("run.npz")
    z["time"], z["connectors.friction_ratio"], z["energy.imbalance"]
    meta = json.loads(str(z["meta"]))      # what each array is: names, units; settings, stats

Keys: ``time`` (committed integration steps), every recorder's arrays (``<name>...``, see
:mod:`bearingfw.analysis.recorders`), ``energy.<column>`` (``time`` and
:data:`~bearingfw.analysis.energy.ENERGY_COLUMNS`, J, one row per integration step), ``meta``
(JSON: ``recorders``, ``settings``, ``stats``, ``uplift``, ``completed``, ``message``; a non-finite number,
e.g. the residual of a failed step, is written as ``null``, so the file is strict JSON).

The file is written member by member (not through ``np.savez(**arrays)``), so any key is safe,
``"file"`` or ``"allow_pickle"`` included; keys that would clash with ``time``, ``meta`` or the
``energy.`` columns are refused.
"""

from __future__ import annotations

import json
import math
import zipfile
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.analysis.energy import ENERGY_COLUMNS, balance_error, energy_error, numerical_dissipation

__all__ = ["TransientResult", "FORMAT"]

FORMAT = "bearingfw-transient/1"


@attrs.frozen(eq=False)
class TransientResult:
    """Recorded histories of a transient run (complete, or up to a failure).

    ``data[key]`` (or ``result[key]``) are the recorders' arrays; ``recorders`` describes them
    (names, components, units) by recorder name. ``energy`` maps ``"time"`` and each energy column
    to an array; :attr:`energy_error` is ``max |imbalance| / max |W_input|``, which for HHT
    ``alpha < 0`` includes the scheme's numerical dissipation; :attr:`balance_error` is the part
    that is not (see :mod:`bearingfw.analysis.energy`). ``stats``: ``steps``, ``substeps``,
    ``subdivisions`` (step halvings), ``iterations`` and ``max_iterations`` (Newton iterations of
    the converged sub-steps), ``failed_iterations`` (those spent in sub-steps that were then
    halved), ``backtracks`` (line-search halvings), ``factorizations``, ``setup_time``,
    ``loop_time`` and ``wall_time`` (s), ``preload_residual``, ``alpha`` (HHT), ``energy_error``,
    ``balance_error``, ``numerical_dissipation``.

    ``uplift``: per connector with ``uplift=True`` (by name), over every integration step (not
    only the recorded samples): ``lift_offs`` (how many times its gap opened), ``lifted_time``
    (s, the time it was open; a step in which it opens or closes counts the part with the gap
    open, the gap taken linear over the step) and ``peak_gap`` (m, the largest opening, 0 if it
    never lifted). Empty for a model without uplift connectors.
    """

    time: np.ndarray
    data: dict[str, np.ndarray]
    energy: dict[str, np.ndarray]
    stats: dict[str, Any]
    recorders: dict[str, dict] = attrs.field(factory=dict)
    settings: dict[str, Any] = attrs.field(factory=dict)
    completed: bool = True
    message: str = ""
    uplift: dict[str, dict[str, float]] = attrs.field(factory=dict)

    def __getitem__(self, key: str) -> np.ndarray:
        try:
            return self.data[key]
        except KeyError:
            raise KeyError(f"no recorded array {key!r}; recorded: {', '.join(sorted(self.data)) or 'nothing'}") from None

    def keys(self) -> list[str]:
        return sorted(self.data)

    @property
    def energy_error(self) -> float:
        """``max |imbalance| / max |W_input|`` over the run (see :mod:`bearingfw.analysis.energy`)."""
        return energy_error(self.energy)

    @property
    def balance_error(self) -> float:
        """``max |imbalance - numerical| / max |W_input|``: the energy error without HHT's numerical
        dissipation; round-off and Newton tolerance only, for every ``alpha`` (NaN for a file
        written before the ``numerical`` column existed)."""
        return balance_error(self.energy)

    @property
    def numerical_dissipation(self) -> float:
        """HHT's numerical dissipation over the run, as a fraction of ``max |W_input|`` (0 for ``alpha = 0``)."""
        return numerical_dissipation(self.energy)

    def save(self, path: str | Path) -> Path:
        """Write the result to an NPZ file (``.npz`` appended if missing); returns the path."""
        path = Path(path)
        if path.suffix != ".npz":
            path = path.with_name(path.name + ".npz")
        meta = {
            "format": FORMAT,
            "recorders": self.recorders,
            "settings": self.settings,
            "stats": self.stats,
            "uplift": self.uplift,
            "completed": self.completed,
            "message": self.message,
        }
        clash = sorted(k for k in self.data if k in _RESERVED or k.startswith("energy."))
        if clash:
            raise ValueError(f"TransientResult.save: recorded keys {clash} clash with the file's own keys (time, meta, energy.*)")
        arrays = {
            "meta": np.array(json.dumps(_json_safe(meta), allow_nan=False)),
            "time": self.time,
            **self.data,
            **{f"energy.{k}": v for k, v in self.energy.items()},
        }
        _write_npz(path, arrays)
        return path

    @classmethod
    def load(cls, path: str | Path) -> TransientResult:
        """Read a file written by :meth:`save`."""
        with np.load(Path(path), allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            if meta.get("format") != FORMAT:
                raise ValueError(f"{path}: not a bearingfw transient result (format {meta.get('format')!r})")
            energy = {k[len("energy."):]: z[k] for k in z.files if k.startswith("energy.")}
            data = {k: z[k] for k in z.files if k not in ("meta", "time") and not k.startswith("energy.")}
            time = z["time"]
        return cls(
            time=time,
            data=data,
            energy=energy,
            stats=meta["stats"],
            recorders=meta["recorders"],
            settings=meta["settings"],
            completed=meta["completed"],
            message=meta["message"],
            uplift=meta.get("uplift", {}),
        )


_RESERVED = ("time", "meta")


def _write_npz(path: Path, arrays: dict[str, np.ndarray]) -> None:
    """What ``np.savez`` writes (a zip of ``<key>.npy`` members), without passing the keys as keyword
    arguments (``np.savez(file, **arrays)`` breaks on a key named ``file`` and drops ``allow_pickle``)."""
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as zf:
        for key, value in arrays.items():
            with zf.open(f"{key}.npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.asanyarray(value), allow_pickle=False)


def _json_safe(value):
    """``value`` with numpy scalars as Python numbers and NaN / infinities as ``None`` (strict JSON)."""
    if isinstance(value, dict):
        return {str(k): _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    if isinstance(value, np.ndarray):
        return _json_safe(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def energy_table(rows: list[tuple[float, ...]], times: list[float]) -> dict[str, np.ndarray]:
    """Columns of the energy table from per-step rows (:meth:`Energy.row`)."""
    table = np.array(rows, dtype=float).reshape(-1, len(ENERGY_COLUMNS))
    return {"time": np.array(times, dtype=float), **{c: table[:, k] for k, c in enumerate(ENERGY_COLUMNS)}}
