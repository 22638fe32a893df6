"""Running an experiment: check it, run the cells that are not finished, then write the matrices,
figures and report from everything the store holds.

:func:`run_experiment` is what ``bearingfw run`` calls. Steps:

1. check the experiment against the installed plugins and the user's code: every model is
   built (its laws created), the records are read, the recorded elements, nodes and bearings
   exist (a problem is a :class:`~bearingfw.experiment.spec.SpecError` naming the key);
2. plan the cells and their digests; take the results directory (a lock: one run at a time;
   and it must hold this experiment, :meth:`~bearingfw.experiment.store.Store.claim`); keep the
   finished cells (unless ``force``), thin the stored histories where only ``[output] every``
   grew, run the others on the executor (each is committed to the store as it finishes);
3. read every cell back from the store, build the matrices (``matrices.json``, CSVs), the
   records' measures, the modal results of each model, the figures and ``report.md``.

Only the cells run; everything after is rebuilt from the store each time, so a rerun after an
interruption gives the same files as an uninterrupted run.
"""

from __future__ import annotations

import datetime
import platform
import time
from pathlib import Path

import attrs

from bearingfw.analysis import solve_modal
from bearingfw.experiment.cells import CellJob, plan_cells, recording
from bearingfw.experiment.default import DEFAULT_TABLE
from bearingfw.experiment.executors import ProcessExecutor, local_workers
from bearingfw.experiment.findings import Finding, paper_findings
from bearingfw.experiment.matrices import Matrices, collect_matrices, write_matrices
from bearingfw.experiment.metrics import FAMILIES, STRESS_FAMILIES, metric_family
from bearingfw.experiment.progress import Progress, format_duration
from bearingfw.experiment.records import load_record, record_info, scaled_record
from bearingfw.experiment.spec import Experiment, SpecError, key_path
from bearingfw.experiment.store import Store
from bearingfw.experiment.structure import (
    build_model,
    deck_nodes,
    governed_bearings,
    import_paths,
    registry_for,
    response_elements,
)
from bearingfw.model import as_system
from bearingfw.motion import UnknownScaleError, get_scale
from bearingfw.parameters import ParameterError
from bearingfw.plugins import UnknownLawError, create_law

__all__ = ["RunSummary", "check_experiment", "default_output", "run_experiment"]

#: Modes per model in the report.
MODAL_MODES = 8


def default_output(experiment: Experiment) -> Path:
    """``bearingfw-results/<experiment name>`` in the current directory."""
    return Path("bearingfw-results") / experiment.name


@attrs.frozen
class Checked:
    """What the check found out, reused by the run: models, systems, recorded items, records."""

    models: dict
    systems: dict
    elements: tuple[str, ...]
    nodes: tuple[str, ...]
    bearings: tuple[str, ...]
    records: dict
    table: tuple[str, ...]


def _table(experiment: Experiment, elements, nodes, connectors) -> tuple[str, ...]:
    items = {f: elements if f in STRESS_FAMILIES else connectors for f in FAMILIES}
    items["deck_acceleration"] = ("x", "y", "z") if nodes else ()
    if not experiment.output.table:
        return tuple(m for m in DEFAULT_TABLE if m.partition(".")[2] in items[metric_family(m)])
    for metric in experiment.output.table:
        family, _, item = metric.partition(".")
        if family not in FAMILIES:
            raise SpecError(
                f"output.table: {metric!r}: unknown metric family {family!r}; families: {', '.join(FAMILIES)}"
            )
        if item not in items[family]:
            raise SpecError(f"output.table: {metric!r}: {item!r} is not recorded; {family} has "
                            f"{', '.join(items[family]) or 'nothing'}")
    return experiment.output.table


def check_experiment(experiment: Experiment) -> Checked:
    """Check what loading could not (module docstring, step 1); errors name the key."""
    paths = import_paths(experiment)
    for folder, given in zip(paths[1:], experiment.python_path):
        if not Path(folder).is_dir():
            raise SpecError(f"python_path: {given!r} is not a folder ({folder})")
    registry = registry_for(experiment.plugins, paths)
    try:
        get_scale(experiment.intensities.scale, registry)
    except UnknownScaleError as exc:
        raise SpecError(f"intensities.scale: {exc}") from None
    models, systems = {}, {}
    for spec in experiment.models:
        if spec.law is not None:  # the law and its parameters first, so that the message names the key
            try:
                create_law(spec.law, registry=registry, **spec.params)
            except UnknownLawError as exc:
                raise SpecError(f"{key_path('models', spec.name, 'law')}: {exc}") from None
            except ParameterError as exc:
                raise SpecError(f"{key_path('models', spec.name, 'params')}: {exc}") from None
        try:
            models[spec.name] = build_model(experiment.structure, spec, registry, paths)
            systems[spec.name] = as_system(models[spec.name], registry)
        except SpecError:
            raise
        except (ParameterError, KeyError, TypeError, ValueError) as exc:
            message = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
            raise SpecError(f"{key_path('models', spec.name)}: {message}") from None
    first = next(iter(models.values()))
    elements = response_elements(experiment.structure, first)
    nodes = deck_nodes(experiment.structure, first)
    bearings = governed_bearings(experiment.structure, first) if not experiment.structure.is_reference else ()
    connectors = tuple(c.name for c in first.connectors)
    figures = experiment.figures
    for name in figures.elements or ():
        if name not in elements:
            raise SpecError(f"figures.elements: {name!r} is not a response element; they are {', '.join(elements)}")
    if figures.bearing is not None and figures.bearing not in connectors:
        raise SpecError(f"figures.bearing: the model has no connector {figures.bearing!r}")
    records = {}
    for spec in experiment.records:
        try:
            records[spec.name] = load_record(experiment, spec, registry)
        except SpecError:
            raise
        except (ValueError, KeyError, OSError, RuntimeError) as exc:  # unreadable, unknown reader, no realisation
            raise SpecError(f"{key_path('records', spec.name)}: {exc}") from None
    table = _table(experiment, elements, nodes, connectors)
    return Checked(models, systems, elements, nodes, bearings, records, table)


@attrs.frozen
class RunSummary:
    """What a run did (``bearingfw run --json`` prints it)."""

    experiment: str
    out: str
    executor: str
    workers: int
    cells: int
    computed: tuple[str, ...]
    skipped: tuple[str, ...]
    failed: tuple[tuple[str, str], ...]
    missing: tuple[str, ...]
    wall_time: float
    run_time: float
    files: dict
    findings: tuple[Finding, ...] = ()
    matrices: Matrices | None = attrs.field(default=None, repr=False)
    table: tuple[str, ...] = ()
    #: Cells kept whose stored histories were only thinned to the new ``[output] every`` (in ``skipped`` too).
    thinned: tuple[str, ...] = ()

    @property
    def exit_code(self) -> int:
        """0 if no cell of the experiment failed, 1 if any did (cells left out with --only or --levels
        and not computed earlier are listed as missing, not failed)."""
        return 1 if self.failed else 0

    def to_dict(self) -> dict:
        data = attrs.asdict(self, recurse=False, filter=lambda a, v: a.name not in ("matrices", "table"))
        data["failed"] = [{"id": i, "error": e} for i, e in self.failed]
        data["findings"] = [attrs.asdict(f) for f in self.findings]
        data["exit_code"] = self.exit_code
        return data


def _documents(store: Store, jobs: list[CellJob]) -> list[dict | None]:
    """Each planned cell's document if it is stored for the current inputs (else None)."""
    out = []
    for job in jobs:
        d = store.read_cell(job.id)
        out.append(d if d is not None and d.get("digest") == job.digest else None)
    return out


def _records_info(experiment: Experiment, checked: Checked, registry) -> tuple[dict, list]:
    scale = get_scale(experiment.intensities.scale, registry)
    info, points = {}, []
    for spec in experiment.records:
        record = checked.records[spec.name]
        entry = record_info(record, spec.components, scale)
        entry["intensities"] = {}
        for intensity in experiment.intensity_list:
            try:
                scaled = scaled_record(record, intensity, experiment.intensities,
                                       experiment.integration.dt_integration, registry)
                measures = record_info(scaled, spec.components, scale)
                entry["intensities"][intensity.name] = {
                    k: measures[k] for k in ("scale_factor", "pga_h10", "t_ha", "arias", "degree")
                }
                points.append((f"{spec.name} {intensity.name}", measures["t_ha"], measures["pga_h10"]))
            except ValueError as exc:  # e.g. the scaled record is not of the level's degree
                entry["intensities"][intensity.name] = {"error": str(exc)}
        info[spec.name] = entry
    return info, points


def _modal(experiment: Experiment, checked: Checked) -> dict:
    """The lowest modes of each model; on the reference bridge also the paper's Table 2 modes as its
    deck sensors see them (:mod:`bearingfw.bridges.study`), so that step 1 of the tuning shows."""
    reference = experiment.structure.is_reference
    if reference:
        from bearingfw.bridges.paper import MODES
        from bearingfw.bridges.study import N_MODES, deck_observation
        from bearingfw.experiment.structure import bridge_parameters
        from bearingfw.tuning import observed_modes

        observation = deck_observation(bridge_parameters(experiment.structure))
    out = {}
    for name, system in checked.systems.items():
        try:
            modal = solve_modal(system, max(MODAL_MODES, N_MODES) if reference else MODAL_MODES)
        except Exception as exc:  # noqa: BLE001 - a model whose modes fail still gets its report
            out[name] = {"error": f"{type(exc).__name__}: {exc}"}
            continue
        ratios = modal.mass_ratios
        out[name] = {"modes": [
            {"frequency": float(modal.frequencies[k]), "label": modal.numbered_labels[k],
             "mass_ratio": {d: float(ratios[d][k]) for d in ("x", "y", "z")}}
            for k in range(min(MODAL_MODES, modal.n_modes))
        ]}
        if reference:
            seen = observed_modes(modal, observation).numbered
            out[name]["deck"] = {mode: float(modal.frequencies[seen[mode]]) for mode in MODES if mode in seen}
    return out


def _figure_plan(experiment: Experiment, checked: Checked, chart) -> dict:
    figures = experiment.figures
    models = experiment.model_names
    connectors = [c.name for c in next(iter(checked.models.values())).connectors]
    reference = experiment.structure.is_reference
    if figures.bearing is not None:
        bearing = figures.bearing
    elif reference:
        bearing = "3B"
    else:
        bearing = (checked.bearings or connectors or (None,))[0]
    compare = figures.compare or (tuple(m for m in ("M1", "M2") if m in models) if {"M1", "M2"} <= set(models)
                                  else models)
    return {
        "records": {r.name: checked.records[r.name].synthetic for r in experiment.records},
        "intensities": figures.intensities or tuple(i.name for i in experiment.intensity_list),
        "models": models,
        "elements": figures.elements if figures.elements is not None else
        (tuple(e for e in ("S1", "3B") if e in checked.elements) if reference else checked.elements[:2]),
        "bearing": bearing,
        "compare": compare,
        "mu": {m.name: m.friction_coefficient for m in experiment.models},
        "hysteresis": figures.hysteresis,
        "table": checked.table,
        "chart": chart,
    }


def _draw(experiment: Experiment, checked: Checked, store: Store, matrices: Matrices, points, registry,
          done: list[dict], executor, progress: Progress) -> list:
    """The figures, from the histories stored for the current inputs of the finished cells ``done``."""
    from bearingfw.experiment.figures import write_figures
    from bearingfw.motion.plot import plot_intensity_chart

    synthetic = next((checked.records[r] for r in experiment.record_names if checked.records[r].synthetic), None)
    scale = get_scale(experiment.intensities.scale, registry)
    chart = (points, lambda: plot_intensity_chart(points, scale, record=synthetic))
    every = recording(experiment)
    # A cell kept from an earlier run (--only, --levels) may hold histories of other inputs or thinning.
    cells = {(d["model"], d["record"], d["intensity"]): d for d in done
             if d.get("status") == "ok" and store.is_finished(d["id"], d["digest"], every)}
    workers = local_workers(executor)
    progress.note(f"drawing the figures ({workers} process(es))")
    return write_figures(store, {**_figure_plan(experiment, checked, chart), "every": every}, matrices, cells, workers)


def run_experiment(
    experiment: Experiment,
    out: str | Path | None = None,
    executor=None,
    *,
    force: bool = False,
    models: tuple[str, ...] | None = None,
    intensities: tuple[str, ...] | None = None,
    progress: Progress | None = None,
    take_over: bool = False,
) -> RunSummary:
    """Run ``experiment`` into ``out`` (default :func:`default_output`) and write its results.

    ``executor``: an object of :mod:`bearingfw.experiment.executors` (default: local processes on
    every core). ``force``: recompute finished cells too. ``models``, ``intensities``: run only
    these cells (the matrices still show every finished cell). ``take_over``: run even into a
    directory that holds another experiment's results, or other files
    (:mod:`~bearingfw.experiment.store`: what is reused, what is left alone). The directory is
    locked for the run: :class:`~bearingfw.experiment.store.StoreError` if another run holds it.
    """
    wall = time.perf_counter()
    executor = executor or ProcessExecutor()
    progress = progress or Progress(quiet=True)
    store = Store(out or default_output(experiment))
    checked = check_experiment(experiment)
    registry = registry_for(experiment.plugins, import_paths(experiment))
    for field, given, known in (("--only", models, experiment.model_names),
                                ("--levels", intensities, tuple(i.name for i in experiment.intensity_list))):
        bad = [g for g in (given or ()) if g not in known]
        if bad:
            raise SpecError(f"{field}: {bad[0]!r} is not in the experiment; it has {', '.join(known)}")
    jobs = plan_cells(experiment, registry, checked.models)
    with store.claim(experiment.name, take_over):
        store.clean_temporaries()
        store.write_text("experiment.toml", experiment.source)
        wanted = [j for j in jobs
                  if (not models or j.model in models) and (not intensities or j.intensity.name in intensities)]
        every = recording(experiment)
        todo, thinned = [], []
        for j in wanted:
            if force:
                todo.append(j)
            elif store.is_finished(j.id, j.digest, every):
                continue
            elif every is not None and store.is_finished(j.id, j.digest, None) and store.rethin(j.id, j.digest, every):
                thinned.append(j.id)  # only the recorded histories changed: cut from the stored ones
            else:
                todo.append(j)
        todo_ids = {j.id for j in todo}
        skipped = tuple(j.id for j in wanted if j.id not in todo_ids)

        def manifest(state: str) -> None:
            from bearingfw import __version__

            finished = {j.id for j in jobs if store.is_finished(j.id, j.digest, every)}
            store.write_json("manifest.json", {
                "experiment": experiment.name, "state": state, "bearingfw": __version__,
                "updated": datetime.datetime.now().isoformat(timespec="seconds"),
                "host": platform.node(), "executor": executor.name, "workers": executor.workers,
                "recording": {"histories": every is not None, "every": every},
                "cells": [{"id": j.id, "digest": j.digest, "finished": j.id in finished,
                           "files": [f"cells/{j.id}.json", f"cells/{j.id}.npz"]} for j in jobs],
            })

        manifest("running")
        progress.begin([j.model for j in todo], len(skipped), executor.name,
                       min(executor.workers, max(1, len(todo))), thinned=len(thinned))
        run_start = time.perf_counter()
        try:
            executor.run(todo, store, progress.cell)
        except BaseException:
            manifest("stopped")
            raise
        run_time = time.perf_counter() - run_start
        try:
            summary = _post_process(experiment, checked, store, jobs, todo, skipped, tuple(thinned), registry,
                                    executor, progress, wall, run_time)
        except BaseException:
            # The cells are safe in the store; say in the manifest that the summary step did not finish.
            manifest("post-processing failed")
            raise
        store.write_json("summary.json", summary.to_dict())
        manifest("finished")
    progress.finish(f"{len(todo)} cell(s) run in {format_duration(run_time)}, {len(skipped)} kept, "
                    f"{len(summary.failed)} failed, {len(summary.missing)} not computed; results in {store.root}")
    return summary


def _post_process(experiment, checked, store, jobs, todo, skipped, thinned, registry, executor, progress, wall,
                  run_time) -> RunSummary:
    """Matrices, records and modal information, figures, report and summary of a run whose cells are done."""
    documents = _documents(store, jobs)
    done = [d for d in documents if d is not None]
    failed = tuple((d["id"], (d.get("error") or {}).get("message", "")) for d in done if d.get("status") != "ok")
    missing = tuple(j.id for j, d in zip(jobs, documents) if d is None)
    matrices = collect_matrices(done, experiment.model_names, experiment.record_names,
                                tuple(i.name for i in experiment.intensity_list), experiment.reference_model,
                                experiment.output.aggregate)
    write_matrices(store, matrices, done)
    files = {name: str(store.path(name))
             for name in ("matrices.json", "ratios.json", "matrices", "ratios", "cells.csv")}
    records, points = _records_info(experiment, checked, registry)
    modal = _modal(experiment, checked)
    files["records.json"] = str(store.write_json("records.json", records))
    files["modal.json"] = str(store.write_json("modal.json", modal))
    mu = experiment.model("M2").friction_coefficient if "M2" in experiment.model_names else None
    findings = tuple(paper_findings(matrices, mu or 0.04))
    # The figures draw the cells' histories: without stored histories there is nothing to draw.
    draw = experiment.figures.draw and experiment.output.histories
    figures = _draw(experiment, checked, store, matrices, points, registry, done, executor, progress) if draw else []
    files["figures"] = [str(p) for p in figures]
    summary = RunSummary(
        experiment.name, str(store.root), executor.name, executor.workers, len(jobs), tuple(j.id for j in todo),
        skipped, failed, missing, time.perf_counter() - wall, run_time, files, findings, matrices, checked.table,
        thinned,
    )
    if experiment.output.report:
        from bearingfw.experiment.report import ReportData, render_report

        data = ReportData(
            experiment, store.root, summary, matrices, checked.table, tuple((j.id, d) for j, d in zip(jobs, documents)),
            records, modal, tuple(figures), findings, tuple(paper_findings(matrices, mu or 0.04, family="stress")),
        )
        files["report.md"] = str(store.write_text("report.md", render_report(data)))
    return attrs.evolve(summary, wall_time=time.perf_counter() - wall)
