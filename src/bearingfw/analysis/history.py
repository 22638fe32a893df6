"""The result of a transient run: time histories as numpy arrays, the energy table, run statistics.

Saved as one NPZ file that opens without bearingfw::

    import json, numpy as np
    z = np.load("run.npz")
    z["time"], z["connectors.friction_ratio"], z["energy.imbalance"]
    meta = json.loads(str(z["meta"]))      # what each array is: names, units; settings, stats

Keys: ``time`` (committed integration steps), every recorder's arrays (``<name>...``, see
:mod:`bearingfw.analysis.recorders`), ``energy.<column>`` (``time`` and
:data:`~bearingfw.analysis.energy.ENERGY_COLUMNS`, J, one row per integration step), ``meta``
(JSON: ``recorders``, ``settings``, ``stats``, ``completed``, ``message``).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.analysis.energy import ENERGY_COLUMNS, energy_error

__all__ = ["TransientResult", "FORMAT"]

FORMAT = "bearingfw-transient/1"


@attrs.frozen(eq=False)
class TransientResult:
    """Recorded histories of a transient run (complete, or up to a failure).

    ``data[key]`` (or ``result[key]``) are the recorders' arrays; ``recorders`` describes them
    (names, components, units) by recorder name. ``energy`` maps ``"time"`` and each energy column
    to an array; :attr:`energy_error` is ``max |imbalance| / max |W_input|``. ``stats``: steps,
    substeps, subdivisions, Newton iterations, factorisations, wall time.
    """

    time: np.ndarray
    data: dict[str, np.ndarray]
    energy: dict[str, np.ndarray]
    stats: dict[str, Any]
    recorders: dict[str, dict] = attrs.field(factory=dict)
    settings: dict[str, Any] = attrs.field(factory=dict)
    completed: bool = True
    message: str = ""

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
            "completed": self.completed,
            "message": self.message,
        }
        arrays = {"time": self.time, **self.data, **{f"energy.{k}": v for k, v in self.energy.items()}}
        np.savez(path, meta=np.array(json.dumps(meta)), **arrays)
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
        )


def energy_table(rows: list[tuple[float, ...]], times: list[float]) -> dict[str, np.ndarray]:
    """Columns of the energy table from per-step rows (:meth:`Energy.row`)."""
    table = np.array(rows, dtype=float).reshape(-1, len(ENERGY_COLUMNS))
    return {"time": np.array(times, dtype=float), **{c: table[:, k] for k, c in enumerate(ENERGY_COLUMNS)}}
