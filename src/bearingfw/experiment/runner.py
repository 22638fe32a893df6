"""Running an experiment: check it, run the cells that are not finished, then write the matrices,
findings, figures and report from everything the store holds.

:func:`run_experiment` is what ``bearingfw run`` calls. Steps:

1. :func:`check_experiment`: check the experiment against the installed plugins and the user's
   code: every model is built (its laws and preset found), the records are read, the recorded
   elements, nodes and bearings exist, so do the items the table, the figures and the findings
   name (a problem is a :class:`~bearingfw.experiment.spec.SpecError` naming the key and listing
   what exists); the intensities and the damping that depend on the structure's modes are
   resolved;
2. plan the cells and their digests; take the results directory (a lock: one run at a time;
   and it must hold this experiment, :meth:`~bearingfw.experiment.store.Store.claim`);
   :func:`_work`: keep the finished cells (unless ``force``), thin the stored histories where only
   ``[output] every`` grew, and run the others on the executor (each is committed to the store as
   it finishes); meanwhile a record and intensity's figures are drawn, in a thread of this
   process, as soon as its cells are finished (:class:`~bearingfw.experiment.figures.FigureDrawer`);
3. :func:`_post_process`, from the store: :func:`_results` reads every cell back and writes the
   matrices (``matrices.json``, CSVs, ``units.json``), the records' measures and the modal results
   of each model; the findings are checked on the matrices; :func:`_draw` draws the figures and
   :func:`_write_report` writes ``report.md``.

Only the cells run; everything after is rebuilt from the store each time, so a rerun after an
interruption gives the same files as an uninterrupted run.
"""

from __future__ import annotations

import datetime
import math
import platform
import time
from collections.abc import Mapping
from pathlib import Path

import attrs

from bearingfw.analysis import Rayleigh, solve_modal
from bearingfw.analysis.excitation import support_group_problem
from bearingfw.analysis.static import initial_stiffness_error
from bearingfw.bridges import find_preset
from bearingfw.experiment.acceptance import SUSPECT
from bearingfw.experiment.cells import CellJob, plan_cells, recording
from bearingfw.experiment.execute import forget_shared, prepare_cells
from bearingfw.experiment.executors import ProcessExecutor, local_workers
from bearingfw.experiment.findings import Finding, check_findings
from bearingfw.experiment.matrices import Matrices, collect_matrices, units_table, write_matrices
from bearingfw.experiment.metrics import BEARINGS, DECK, DIRECTIONS, SECTIONS, MetricFamily, metric_families
from bearingfw.experiment.progress import Progress, format_duration
from bearingfw.experiment.records import load_record, record_info, scaled_record, spatial_spec
from bearingfw.experiment.spec import Experiment, Intensity, SpecError, key_path
from bearingfw.experiment.store import Store
from bearingfw.experiment.structure import (
    build_model,
    deck_nodes,
    governed_bearings,
    import_paths,
    mode_labeller,
    registry_for,
    resolved_setup,
    response_elements,
)
from bearingfw.model import Model, as_system
from bearingfw.motion import UnknownScaleError, get_scale
from bearingfw.parameters import ParameterError
from bearingfw.plugins import Registry, UnknownLawError, create_law

__all__ = ["Checked", "RunSummary", "check_experiment", "default_output", "default_table", "run_experiment"]

#: Modes per model in the report.
MODAL_MODES = 8


def default_output(experiment: Experiment) -> Path:
    """``bearingfw-results/<experiment name>`` in the current directory."""
    return Path("bearingfw-results") / experiment.name


@attrs.frozen
class Checked:
    """What the check found out, reused by the run: the registry, models, systems, recorded items
    (``items``: each metric family's items on this structure), records, the resolved intensities
    and damping, and the table."""

    registry: Registry
    models: dict
    systems: dict
    elements: tuple[str, ...]
    nodes: tuple[str, ...]
    bearings: tuple[str, ...]
    records: dict
    intensities: tuple[Intensity, ...]
    rayleigh: Rayleigh
    families: dict
    items: dict
    table: tuple[str, ...]

    @property
    def connectors(self) -> tuple[str, ...]:
        return tuple(c.name for c in next(iter(self.models.values())).connectors)


# ---- step 1: the check -------------------------------------------------------------------------------------
def family_items(families: Mapping[str, MetricFamily], elements, nodes, connectors) -> dict[str, tuple[str, ...]]:
    """The items of each metric family on a structure recording ``elements``, ``nodes`` and ``connectors``."""
    by_reads = {SECTIONS: tuple(elements), BEARINGS: tuple(connectors), DECK: DIRECTIONS if nodes else ()}
    return {name: by_reads[family.reads] if family.items is None else tuple(family.items)
            for name, family in families.items()}


def _check_metric(key: str, metric: str, items: Mapping[str, tuple[str, ...]]) -> None:
    family, _, item = metric.partition(".")
    if family not in items:
        raise SpecError(f"{key}: {metric!r}: unknown metric family {family!r}; families: {', '.join(items)}")
    if item not in items[family]:
        raise SpecError(f"{key}: {metric!r}: {item!r} is not recorded; {family} has "
                        f"{', '.join(items[family]) or 'nothing (the structure records none of its items)'}")


def default_table(experiment: Experiment, families: Mapping[str, MetricFamily], items: Mapping, bearings) -> tuple:
    """The table when ``[output] table`` is not given: the families shown by default (``table``), at the
    figures' elements (else every response element), the figures' bearing (else the first governed
    bearing) and every direction; only items the structure has."""
    elements = experiment.figures.elements
    bearing = experiment.figures.bearing or next(iter(bearings), None)
    out = []
    for name, family in families.items():
        if not family.table:
            continue
        chosen = {SECTIONS: elements if elements is not None else items[name],
                  BEARINGS: (bearing,) if bearing is not None else (), DECK: items[name]}[family.reads]
        out += [f"{name}.{item}" for item in chosen if item in items[name]]
    return tuple(out)


def _check_models(experiment: Experiment, registry: Registry) -> tuple[dict, dict]:
    models, systems = {}, {}
    for spec in experiment.models:
        if spec.preset is not None:
            try:
                find_preset(spec.preset, registry)
            except ParameterError as exc:
                raise SpecError(f"{key_path('models', spec.name, 'preset')}: {exc}") from None
        if spec.law is not None:  # the law and its parameters first, so that the message names the key
            try:
                create_law(spec.law, registry=registry, **spec.params)
            except UnknownLawError as exc:
                raise SpecError(f"{key_path('models', spec.name, 'law')}: {exc}") from None
            except ParameterError as exc:
                raise SpecError(f"{key_path('models', spec.name, 'params')}: {exc}") from None
        try:
            models[spec.name] = build_model(experiment, spec, registry)
            systems[spec.name] = as_system(models[spec.name], registry)
        except SpecError:
            raise
        except (ParameterError, KeyError, TypeError, ValueError) as exc:
            message = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
            raise SpecError(f"{key_path('models', spec.name)}: {message}") from None
        # a law stiffness no solve can take (not finite, or beyond 1/eps of the structure's stiffest
        # term) is bad input, refused before any cell runs; a merely stiff one is left to the cells
        error = initial_stiffness_error(systems[spec.name])
        if error is not None:
            raise SpecError(f"{key_path('models', spec.name)}: {error}")
    return models, systems


def _check_records(experiment: Experiment, registry: Registry) -> dict:
    records = {}
    for spec in experiment.records:
        try:
            records[spec.name] = load_record(experiment, spec, registry)
        except SpecError:
            raise
        except (ValueError, KeyError, OSError, RuntimeError) as exc:  # unreadable, unknown reader, no realisation
            raise SpecError(f"{key_path('records', spec.name)}: {exc}") from None
    return records


def _check_support_groups(experiment: Experiment, system) -> None:
    """A spatially varying record's named support groups fit the structure (every model has its supports)."""
    for spec in experiment.records:
        sp = spatial_spec(spec)
        if sp is not None and isinstance(sp.groups, dict):
            problem = support_group_problem(system, sp.groups)
            if problem is not None:
                raise SpecError(f"{key_path('records', spec.name, 'spatial', 'groups')}: {problem}")


def _check_figures(experiment: Experiment, elements, connectors) -> None:
    figures = experiment.figures
    for name in figures.elements or ():
        if name not in elements:
            raise SpecError(f"figures.elements: {name!r} is not a response element; they are "
                            f"{', '.join(elements) or 'none ([structure] elements)'}")
    if figures.bearing is not None and figures.bearing not in connectors:
        raise SpecError(f"figures.bearing: the model has no connector {figures.bearing!r}; it has "
                        f"{', '.join(connectors) or 'none'}")


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
    models, systems = _check_models(experiment, registry)
    first = next(iter(models.values()))
    elements = response_elements(experiment.structure, first)
    nodes = deck_nodes(experiment.structure, first)
    bearings = governed_bearings(experiment.structure, first)
    connectors = tuple(c.name for c in first.connectors)
    _check_figures(experiment, elements, connectors)
    mode_labeller(experiment)  # a wrong [structure] mode_labels fails the check, before any cell runs
    records = _check_records(experiment, registry)
    _check_support_groups(experiment, next(iter(systems.values())))
    intensities, rayleigh = resolved_setup(experiment, registry)
    families = metric_families(registry)
    items = family_items(families, elements, nodes, connectors)
    for metric in experiment.output.table:
        _check_metric("output.table", metric, items)
    for k, finding in enumerate(experiment.findings, start=1):
        _check_metric(f"findings[{k}].metric", finding.metric, items)
    table = experiment.output.table or default_table(experiment, families, items, bearings)
    return Checked(registry, models, systems, elements, nodes, bearings, records, intensities, rayleigh,
                   families, items, table)


# ---- step 2: the cells -----------------------------------------------------------------------------------
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
    #: Cells that ran but failed an acceptance check (:mod:`~bearingfw.experiment.acceptance`): (id, reasons).
    suspect: tuple[tuple[str, str], ...] = ()
    #: Stored cells whose files failed their integrity check and were computed again: (id, what was wrong).
    damaged: tuple[tuple[str, str], ...] = ()

    @property
    def exit_code(self) -> int:
        """0 if no cell of the experiment failed or is suspect, 1 if any is (cells left out with --only or
        --levels and not computed earlier are listed as missing, not failed)."""
        return 1 if self.failed or self.suspect else 0

    def to_dict(self) -> dict:
        data = attrs.asdict(self, recurse=False, filter=lambda a, v: a.name not in ("matrices", "table"))
        data["failed"] = [{"id": i, "error": e} for i, e in self.failed]
        data["suspect"] = [{"id": i, "reasons": e} for i, e in self.suspect]
        data["damaged"] = [{"id": i, "problem": e} for i, e in self.damaged]
        data["findings"] = [attrs.asdict(f) for f in self.findings]
        data["exit_code"] = self.exit_code
        data["units"] = {"wall_time": "s", "run_time": "s"}
        return data


@attrs.frozen
class _Work:
    """The planned cells, those wanted by this run, and what becomes of each."""

    jobs: list
    todo: list
    skipped: tuple[str, ...]
    thinned: tuple[str, ...]
    damaged: tuple[tuple[str, str], ...] = ()


def _check_selection(experiment: Experiment, checked: Checked, models, intensities) -> None:
    for field, given, known in (("--only", models, experiment.model_names),
                                ("--levels", intensities, tuple(i.name for i in checked.intensities))):
        bad = [g for g in (given or ()) if g not in known]
        if bad:
            raise SpecError(f"{field}: {bad[0]!r} is not in the experiment; it has {', '.join(known)}")


def _work(store: Store, jobs: list[CellJob], every: int | None, force: bool, models, intensities) -> _Work:
    """Which of the wanted cells to compute, keep, or keep with thinned histories (module docstring, step 2)."""
    wanted = [j for j in jobs
              if (not models or j.model in models) and (not intensities or j.intensity.name in intensities)]
    todo, thinned, damaged = [], [], []
    for j in wanted:
        document = store.read_cell(j.id)
        if document is not None and document.get("digest") == j.digest and document.get("status") == "ok":
            problem = store.damage(j.id)
            if problem is not None:  # a result for these inputs, but not as it was written: never kept
                damaged.append((j.id, problem))
        if force:
            todo.append(j)
        elif store.is_finished(j.id, j.digest, every):
            continue
        elif every is not None and store.is_finished(j.id, j.digest, None) and store.rethin(j.id, j.digest, every):
            thinned.append(j.id)  # only the recorded histories changed: cut from the stored ones
        else:
            todo.append(j)
    todo_ids = {j.id for j in todo}
    return _Work(jobs, todo, tuple(j.id for j in wanted if j.id not in todo_ids), tuple(thinned), tuple(damaged))


def _write_manifest(store: Store, experiment: Experiment, executor, jobs, every, state: str) -> None:
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

    ``executor``: an executor (:mod:`bearingfw.experiment.executors`; default: local processes on
    every core). ``force``: recompute finished cells too. ``models``, ``intensities``: run only
    these cells (the matrices still show every finished cell). ``take_over``: run even into a
    directory that holds another experiment's results, or other files
    (:mod:`~bearingfw.experiment.store`: what is reused, what is left alone). The directory is
    locked for the run: :class:`~bearingfw.experiment.store.StoreError` if another run holds it.
    """
    wall = time.perf_counter()
    forget_shared()  # what cells share in this process is made again for each run
    executor = executor or ProcessExecutor()
    progress = progress or Progress(quiet=True)
    store = Store(out or default_output(experiment))
    checked = check_experiment(experiment)
    _check_selection(experiment, checked, models, intensities)
    jobs = plan_cells(experiment, checked.registry, checked.models, (checked.intensities, checked.rayleigh))
    every = recording(experiment)
    check = getattr(executor, "check", None)  # an executor that cannot run (an unreachable scheduler)
    if check is not None:                    # stops here, before anything is written into the directory
        check()
    with store.claim(experiment.name, take_over):
        store.clean_temporaries()
        store.write_text("experiment.toml", experiment.source)
        work = _work(store, jobs, every, force, models, intensities)
        _write_manifest(store, experiment, executor, jobs, every, "running")
        for cell, problem in work.damaged:
            progress.note(f"{cell}: stored result not kept: {problem}; computing it again")
        progress.begin([j.model for j in work.todo], len(work.skipped), executor.name,
                       min(executor.workers, max(1, len(work.todo))), thinned=len(work.thinned))
        run_start = time.perf_counter()
        early = _early_figures(experiment, checked, store, work.todo, executor, progress)

        def finished(cell) -> None:
            progress.cell(cell)
            if early is not None:
                early.cell(cell.id)

        todo = work.todo
        if early is not None:  # a record and intensity's figures wait for all its cells: run them group by group
            groups = [(r, i.name) for i in checked.intensities for r in experiment.record_names]
            order = {group: k for k, group in enumerate(groups)}
            todo = sorted(work.todo, key=lambda j: order.get((j.record, j.intensity.name), len(order)))
        try:
            # each record and intensity read and scaled once, here, for all its cells
            executor.run(prepare_cells(todo), store, finished)
        except BaseException:
            if early is not None:  # the figure being written is finished (never a part of a file), no more
                early.stop(wait_for_queued=False)
            _write_manifest(store, experiment, executor, jobs, every, "stopped")
            raise
        run_time = time.perf_counter() - run_start
        try:
            summary = _post_process(experiment, checked, store, work, executor, progress, wall, run_time, early)
        except BaseException:
            if early is not None:
                early.stop(wait_for_queued=False)
            # The cells are safe in the store; say in the manifest that the summary step did not finish.
            _write_manifest(store, experiment, executor, jobs, every, "post-processing failed")
            raise
        store.write_json("summary.json", summary.to_dict())
        _write_manifest(store, experiment, executor, jobs, every, "finished")
    progress.finish(f"{len(work.todo)} cell(s) run in {format_duration(run_time)}, {len(work.skipped)} kept, "
                    f"{len(summary.failed)} failed, {len(summary.suspect)} suspect, {len(summary.missing)} not computed, "
                    f"{getattr(progress, 'figures', 0)} figure(s) drawn; results in {store.root}")
    return summary


# ---- step 3: the results -----------------------------------------------------------------------------------
def _documents(store: Store, jobs: list[CellJob]) -> list[dict | None]:
    """Each planned cell's document if it is stored for the current inputs (else None)."""
    out = []
    for job in jobs:
        d = store.read_cell(job.id)
        out.append(d if d is not None and d.get("digest") == job.digest else None)
    return out


def _records_info(experiment: Experiment, checked: Checked) -> tuple[dict, list]:
    """Each record's measures, as read and at every intensity, and the intensity chart's points."""
    scale = get_scale(experiment.intensities.scale, checked.registry)
    info, points = {}, []
    for spec in experiment.records:
        record = checked.records[spec.name]
        entry = record_info(record, spec.components, scale)
        entry["intensities"] = {}
        for intensity in checked.intensities:
            try:
                scaled = scaled_record(record, intensity, experiment.intensities,
                                       experiment.integration.dt_integration, checked.registry)
                measures = record_info(scaled, spec.components, scale)
                entry["intensities"][intensity.name] = {
                    k: measures[k] for k in ("scale_factor", "pga_h10", "t_ha", "arias", "degree")
                }
                points.append((f"{spec.name} {intensity.name}", measures["t_ha"], measures["pga_h10"]))
            except ValueError as exc:  # e.g. the scaled record is not of the level's degree
                entry["intensities"][intensity.name] = {"error": str(exc)}
        info[spec.name] = entry
    return info, points


def _labels(modal, labeller) -> tuple[tuple[str, ...], str | None]:
    """The modes' labels: the study's ``[structure] mode_labels`` function's, else the kernel's
    (also when that function fails, with the reason)."""
    if labeller is None:
        return tuple(modal.numbered_labels), None
    try:
        labels = tuple(str(label) for label in labeller(modal))
    except Exception as exc:  # noqa: BLE001 - the user's function: the kernel's labels, and why
        return tuple(modal.numbered_labels), f"structure.mode_labels failed ({type(exc).__name__}: {exc})"
    if len(labels) != modal.n_modes:
        return tuple(modal.numbered_labels), (
            f"structure.mode_labels returned {len(labels)} labels for {modal.n_modes} modes")
    return labels, None


def _modal(checked: Checked, labeller=None) -> dict:
    """The lowest modes of each model (every law at its initial tangent), labelled by ``labeller``."""
    out = {}
    for name, system in checked.systems.items():
        try:
            modal = solve_modal(system, MODAL_MODES)
        except Exception as exc:  # noqa: BLE001 - a model whose modes fail still gets its report
            out[name] = {"error": f"{type(exc).__name__}: {exc}"}
            continue
        ratios = modal.mass_ratios
        labels, problem = _labels(modal, labeller)
        out[name] = {"modes": [
            {"frequency": float(modal.frequencies[k]), "label": labels[k],
             "mass_ratio": {d: float(ratios[d][k]) for d in DIRECTIONS}}
            for k in range(min(MODAL_MODES, modal.n_modes))
        ]}
        if problem:
            out[name]["label_note"] = problem
    return out


@attrs.frozen(eq=False)
class _Results:
    """What the store holds for the planned cells, and the files written from it."""

    documents: list
    done: list
    failed: tuple
    suspect: tuple
    missing: tuple
    matrices: Matrices
    records: dict
    points: list
    modal: dict
    files: dict


def _results(experiment: Experiment, checked: Checked, store: Store, jobs: list[CellJob]) -> _Results:
    """Read every cell back; write the matrices, units, records' measures and modal results."""
    documents = _documents(store, jobs)
    done = [d for d in documents if d is not None]
    failed = tuple((d["id"], (d.get("error") or {}).get("message", "")) for d in done
                   if d.get("status") not in ("ok", SUSPECT))
    suspect = tuple((d["id"], (d.get("error") or {}).get("message", "")) for d in done if d.get("status") == SUSPECT)
    missing = tuple(j.id for j, d in zip(jobs, documents) if d is None)
    matrices = collect_matrices(done, experiment.model_names, experiment.record_names,
                                tuple(i.name for i in checked.intensities), experiment.reference_model,
                                experiment.output.aggregate, checked.families)
    write_matrices(store, matrices, done)
    files = {name: str(store.path(name))
             for name in ("matrices.json", "ratios.json", "matrices", "ratios", "cells.csv")}
    files["units.json"] = str(store.write_json("units.json", units_table(matrices)))
    records, points = _records_info(experiment, checked)
    modal = _modal(checked, mode_labeller(experiment))
    files["records.json"] = str(store.write_json("records.json", records))
    files["modal.json"] = str(store.write_json("modal.json", modal))
    return _Results(documents, done, failed, suspect, missing, matrices, records, points, modal, files)


def _friction_coefficient(experiment: Experiment, model: Model, name: str, bearing: str | None) -> float | None:
    """The mu of a model at ``bearing`` (the friction figure's line): its law's ``mu``, else the model's ``friction``."""
    if bearing is not None:
        value = dict(model.connector(bearing).law_params).get("mu")
        if isinstance(value, float | int) and not isinstance(value, bool) and math.isfinite(value):
            return float(value)
    return experiment.model(name).friction


def figure_plan(experiment: Experiment, checked: Checked, chart) -> dict:
    """What :func:`~bearingfw.experiment.figures.write_figures` draws: ``[figures]`` with its defaults
    filled in from the structure (the first two response elements, the first governed bearing, all
    models); the model drawn on top is the experiment's reference if the figures compare it, else
    the first compared one."""
    figures = experiment.figures
    bearing = figures.bearing or next(iter(checked.bearings or checked.connectors), None)
    compare = figures.compare or experiment.model_names
    return {
        "draw": figures.draw,
        "formats": figures.formats,
        "reference": experiment.reference_model if experiment.reference_model in compare else compare[0],
        "records": {r.name: checked.records[r.name].synthetic for r in experiment.records},
        "intensities": figures.intensities or tuple(i.name for i in checked.intensities),
        "models": experiment.model_names,
        "elements": figures.elements if figures.elements is not None else checked.elements[:2],
        "bearing": bearing,
        "compare": compare,
        "mu": {name: _friction_coefficient(experiment, model, name, bearing) for name, model in checked.models.items()},
        "hysteresis": figures.hysteresis,
        "table": checked.table,
        "chart": chart,
    }


def _draws(experiment: Experiment) -> bool:
    # the figures draw the cells' histories: without stored histories there is nothing to draw
    return experiment.figures.draw != "none" and experiment.output.histories


def _early_figures(experiment: Experiment, checked: Checked, store: Store, todo, executor, progress: Progress):
    """A :class:`~bearingfw.experiment.figures.FigureDrawer` that draws each record and intensity's
    figures as soon as this run's cells of it are finished (None: no figures, or the serial
    executor, whose cells keep this process busy: its figures are drawn after them)."""
    if not _draws(experiment) or not todo or executor.name == "serial":
        return None
    from bearingfw.experiment.figures import FigureDrawer  # here: matplotlib's import is not free
    every = recording(experiment)
    groups: dict = {}
    plan = {**figure_plan(experiment, checked, None), "every": every}
    shown = set(plan["models"] if plan["draw"] == "all" and plan["hysteresis"] else plan["compare"])
    for job in todo:
        if job.model in shown:  # a group's figures wait only for the cells they show
            groups.setdefault((job.record, job.intensity.name), set()).add(job.id)
    wanted = set(plan["intensities"])
    groups = {g: ids for g, ids in groups.items() if g[1] in wanted}

    def accept(document: dict) -> bool:
        return document.get("status") == "ok" and store.is_finished(document["id"], document["digest"], every)

    return FigureDrawer(store, plan, groups, accept, progress)


def _draw(experiment: Experiment, checked: Checked, store: Store, results: _Results, executor,
          progress: Progress, early=None) -> list:
    """The figures, from the histories stored for the current inputs of the finished cells (those
    ``early`` drew while the cells ran are not drawn again)."""
    drawn = {}
    if early is not None:
        early.stop()
        drawn = early.drawn()
    if not _draws(experiment):
        return []
    from bearingfw.experiment.figures import write_figures  # here: matplotlib's import is not free
    from bearingfw.motion.plot import plot_intensity_chart
    synthetic = next((checked.records[r] for r in experiment.record_names if checked.records[r].synthetic), None)
    scale = get_scale(experiment.intensities.scale, checked.registry)
    points = results.points
    chart = (points, lambda: plot_intensity_chart(points, scale, record=synthetic))
    every = recording(experiment)
    # A cell kept from an earlier run (--only, --levels) may hold histories of other inputs or thinning.
    cells = {(d["model"], d["record"], d["intensity"]): d for d in results.done
             if d.get("status") == "ok" and store.is_finished(d["id"], d["digest"], every)}
    workers = local_workers(executor)
    plan = {**figure_plan(experiment, checked, chart), "every": every}
    return write_figures(store, plan, results.matrices, cells, workers, drawn=drawn, progress=progress)


def _write_report(experiment: Experiment, checked: Checked, store: Store, jobs, results: _Results, summary,
                  figures) -> Path:
    from bearingfw.experiment.report import ReportData, render_report

    data = ReportData(
        experiment, store.root, summary, results.matrices, checked.table,
        tuple((j.id, d) for j, d in zip(jobs, results.documents)), results.records, results.modal, tuple(figures),
        summary.findings, checked.intensities, checked.rayleigh, checked.elements, checked.families,
    )
    return store.write_text("report.md", render_report(data))


def _post_process(experiment: Experiment, checked: Checked, store: Store, work: _Work, executor,
                  progress: Progress, wall: float, run_time: float, early=None) -> RunSummary:
    """Matrices, records and modal information, findings, figures, report and summary of a run whose cells are done."""
    results = _results(experiment, checked, store, work.jobs)
    findings = check_findings(experiment.findings, results.matrices)
    figures = _draw(experiment, checked, store, results, executor, progress, early)
    files = {**results.files, "figures": [str(p) for p in figures]}
    summary = RunSummary(
        experiment.name, str(store.root), executor.name, executor.workers, len(work.jobs),
        tuple(j.id for j in work.todo), work.skipped, results.failed, results.missing, time.perf_counter() - wall,
        run_time, files, findings, results.matrices, checked.table, work.thinned, results.suspect, work.damaged,
    )
    if experiment.output.report:
        files["report.md"] = str(_write_report(experiment, checked, store, work.jobs, results, summary, figures))
    return attrs.evolve(summary, wall_time=time.perf_counter() - wall)
