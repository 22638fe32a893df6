"""Cells: one (model, record, intensity) analysis each, with a hash of everything it depends on.

A cell's *inputs* are its resolved description as plain data: the structure (builder and its
options, recorded elements and nodes), the bearing model, the record (the files' contents, not
their paths; or the synthetic tremor's seed and parameters), the intensity (name, PGA_H10, the
scale it is checked on), the integration settings, the Rayleigh coefficients, what is kept of
the histories, and the code versions (:func:`bearingfw.experiment.structure.source_versions`:
bearingfw, every plugin distribution, and the source files of the experiment's own builder and
plugin modules). The *digest* is the SHA-256 of their canonical JSON. The results store keeps
a finished cell with its digest: a rerun skips it while the digest is unchanged and recomputes
it otherwise. Names (the model's, the record's) are not inputs: they only place the files.
"""

from __future__ import annotations

import hashlib
import json

import attrs

from bearingfw.experiment.records import record_inputs
from bearingfw.experiment.spec import Experiment, Intensity
from bearingfw.experiment.structure import import_paths, registry_for, source_versions
from bearingfw.plugins import Registry

__all__ = ["CellJob", "canonical_json", "cell_id", "plan_cells"]


def cell_id(model: str, record: str, intensity: str) -> str:
    """``"M2/tremor/D_II"``: also the cell's place in the results store."""
    return f"{model}/{record}/{intensity}"


def canonical_json(data) -> str:
    """Sorted keys, no spaces, shortest round-trip floats: equal data, equal text."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=True, default=str)


@attrs.frozen
class CellJob:
    """Everything a worker needs to compute one cell (picklable: it crosses process boundaries)."""

    experiment: Experiment
    model: str
    record: str
    intensity: Intensity
    inputs: dict = attrs.field(eq=False, repr=False)
    digest: str = ""

    @property
    def id(self) -> str:
        return cell_id(self.model, self.record, self.intensity.name)


def _without_name(data: dict) -> dict:
    return {k: v for k, v in data.items() if k != "name"}


def plan_cells(experiment: Experiment, registry: Registry | None = None) -> list[CellJob]:
    """Every cell of the experiment, model-major, then record, then intensity, with its digest."""
    registry = registry or registry_for(experiment.plugins, import_paths(experiment))
    rayleigh = experiment.damping.rayleigh()
    common = {
        "structure": attrs.asdict(experiment.structure),
        "integration": attrs.asdict(experiment.integration),
        "damping": {"alpha": rayleigh.alpha, "beta": rayleigh.beta},
        "histories": {"keep": experiment.output.histories, "every": experiment.output.every},
        "plugins": list(experiment.plugins),
        "code": source_versions(experiment, registry),
    }
    records = {r.name: record_inputs(experiment, r) for r in experiment.records}
    scale = experiment.intensities.scale
    jobs = []
    for model in experiment.models:
        for record in experiment.records:
            for intensity in experiment.intensity_list:
                inputs = {
                    **common,
                    "model": _without_name(attrs.asdict(model)),
                    "record": records[record.name],
                    "intensity": {**attrs.asdict(intensity), "scale": scale},
                }
                digest = hashlib.sha256(canonical_json(inputs).encode()).hexdigest()
                jobs.append(CellJob(experiment, model.name, record.name, intensity, inputs, digest))
    return jobs
