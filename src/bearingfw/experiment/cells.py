"""Cells: one (model, record, intensity) analysis each, with a hash of everything it depends on.

A cell's *inputs* are what its physics depends on, as plain data: the structure (builder and its
options, recorded elements and nodes), the bearing model, the record (the files' contents, not
their paths; or the synthetic tremor's seed and parameters), the intensity (its name and scale
target: a level's PGA_H10, a PGA or Sa value with its period; the scale a level is checked on),
the integration settings, the Rayleigh coefficients, the acceptance tolerances of ``[run]``
(they decide whether the cell is ``ok`` or ``suspect``), and the code
(:func:`bearingfw.experiment.structure.code_inputs`: bearingfw's version, the versions of the
distributions of the laws this cell's model uses, of its record's readers, of the intensity
scale and of the metric families; a digest of the source of bearingfw and of those distributions'
packages, so that an edit in a development checkout counts; and the source files of the
experiment's own builder and plugin modules with the modules they import from the experiment's
folders). The *digest* is the SHA-256 of their canonical JSON.
The results store keeps a finished cell with its digest: a rerun skips it while the digest is
unchanged and recomputes it otherwise. Names (the model's, the record's) are not inputs: they
only place the files.

What is *recorded* (``[output] histories`` and ``every``, :func:`recording`) is not an input: it
changes the histories file, not the physics, nor the metrics (always from every step). The
histories file carries its own digest and thinning, so a change of these settings touches only
the cells whose histories do not fit: histories thinned more coarsely by a whole factor are cut
from the stored ones (:meth:`~bearingfw.experiment.store.Store.rethin`), finer ones or histories
that were not kept need the cell computed again, and turning histories off keeps every cell.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping

import attrs

from bearingfw.experiment.acceptance import acceptance_tolerances
from bearingfw.experiment.records import record_inputs, record_readers
from bearingfw.experiment.spec import Experiment, Intensity
from bearingfw.experiment.structure import (
    build_model,
    code_inputs,
    import_paths,
    registry_for,
    resolved_setup,
)
from bearingfw.model import Model
from bearingfw.plugins import Registry

__all__ = ["CellJob", "canonical_json", "cell_id", "plan_cells", "recording"]


def cell_id(model: str, record: str, intensity: str) -> str:
    """``"model/record/intensity"``: also the cell's place in the results store."""
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
    #: ``((record, ground motion, record measures), warnings)`` when the run prepared them once for
    #: all the cells of a record and intensity (:func:`bearingfw.experiment.execute.prepare_cells`);
    #: None: the cell makes them itself
    prepared: tuple | None = attrs.field(default=None, eq=False, repr=False)
    #: the run the cell is computed for (what a process shares between cells is the run's own)
    run: str = attrs.field(default="", eq=False, repr=False)

    @property
    def id(self) -> str:
        return cell_id(self.model, self.record, self.intensity.name)


def _without_name(data: dict) -> dict:
    return {k: v for k, v in data.items() if k != "name"}


def recording(experiment: Experiment) -> int | None:
    """The thinning of the histories the experiment keeps (``[output] every``), or None if it keeps none."""
    return experiment.output.every if experiment.output.histories else None


def plan_cells(
    experiment: Experiment, registry: Registry | None = None, models: Mapping[str, Model] | None = None,
    setup: tuple | None = None,
) -> list[CellJob]:
    """Every cell of the experiment, model-major, then record, then intensity, with its digest.

    ``models``: the built model of each bearing model (the laws it uses count in the digest), and
    ``setup``: the resolved ``(intensities, rayleigh)`` (:func:`~bearingfw.experiment.structure.resolved_setup`),
    if the caller has them (:func:`~bearingfw.experiment.runner.check_experiment` does); else made here.
    """
    paths = import_paths(experiment)
    registry = registry or registry_for(experiment.plugins, paths)
    if models is None:
        models = {m.name: build_model(experiment, m, registry) for m in experiment.models}
    intensities, rayleigh = setup or resolved_setup(experiment, registry)
    common = {
        # mode_labels only names modes in the report: not an input of any cell
        "structure": attrs.asdict(experiment.structure, filter=lambda a, _: a.name != "mode_labels"),
        "integration": attrs.asdict(experiment.integration),
        "damping": {"alpha": rayleigh.alpha, "beta": rayleigh.beta},
        "plugins": list(experiment.plugins),
        # what decides a cell's status (ok or suspect), not its physics: changing it judges the cells again
        "acceptance": acceptance_tolerances(experiment.run),
    }
    records = {r.name: (record_inputs(experiment, r), record_readers(experiment, r, registry))
               for r in experiment.records}
    scale = experiment.intensities.scale
    jobs = []
    for model in experiment.models:
        laws = {c.law for c in models[model.name].connectors if c.law is not None}
        for record in experiment.records:
            data, readers = records[record.name]
            code = code_inputs(experiment, registry, laws, readers)
            for intensity in intensities:
                inputs = {
                    **common,
                    "code": code,
                    "model": _without_name(attrs.asdict(model)),
                    "record": data,
                    "intensity": {**intensity.inputs(), "scale": scale},
                }
                digest = hashlib.sha256(canonical_json(inputs).encode()).hexdigest()
                jobs.append(CellJob(experiment, model.name, record.name, intensity, inputs, digest))
    return jobs
