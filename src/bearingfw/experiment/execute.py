"""Computing one cell: build the model, preload it, shake it, reduce the response to metrics.

:func:`compute_cell` never raises for a failing cell: non-convergence
(:class:`~bearingfw.analysis.TransientError`), a law that raises, a record that cannot be read or
scaled, anything, becomes an outcome with status ``failed``, its error and traceback, so that
the rest of the matrix completes. (``KeyboardInterrupt`` and ``SystemExit`` still stop it: an
interrupted cell is not a result.) Before the analysis, the laws' purity is checked
(:mod:`~bearingfw.experiment.purity`); after it, the result passes the acceptance checks
(:mod:`~bearingfw.experiment.acceptance`) or is stored as ``suspect``. A cell running longer than
``[run] cell_timeout`` is ended and fails (:func:`time_limit`); warnings it raises are kept in its
document (``warnings``, each once with its count), not printed. :func:`compute_and_store` is what a worker process runs: it
also commits the cell to the results store itself, so that a finished cell survives the death of
the process that started the run.
"""

from __future__ import annotations

import contextlib
import copy
import datetime
import os
import platform
import signal
import threading
import time
import traceback
import uuid
import warnings

import attrs

from bearingfw.analysis import Rayleigh, TransientError, gravity, solve_transient
from bearingfw.experiment.acceptance import SUSPECT, accept_cell
from bearingfw.experiment.cells import CellJob, canonical_json, recording
from bearingfw.experiment.metrics import MIN_NORMAL_FRACTION, metric_families, recorders, reduce_result
from bearingfw.experiment.purity import LawPurityError, law_purity_problems
from bearingfw.experiment.records import ground_motion, load_record, scaled_record
from bearingfw.experiment.store import Store, thinned
from bearingfw.experiment.structure import (
    build_model,
    deck_nodes,
    import_paths,
    registry_for,
    response_elements,
)
from bearingfw.model import as_system
from bearingfw.motion import get_scale, record_degree, record_pga_h10, record_t_ha

__all__ = [
    "CellOutcome", "CellSummary", "CellTimeout", "compute_and_store", "compute_cell", "failed_outcome",
    "forget_shared", "prepare_cells", "time_limit", "write_outcome",
]

#: Lines of traceback kept with a failed cell.
TRACEBACK_LINES = 40


@attrs.frozen
class CellSummary:
    """What the process that runs the experiment hears of a cell (no arrays)."""

    id: str
    model: str
    status: str
    wall_time: float
    error: str | None = None


@attrs.frozen(eq=False)
class CellOutcome:
    """A computed cell: its JSON document and its histories (None if not kept or none recorded)."""

    document: dict
    histories: dict | None = None
    meta: dict | None = None

    @property
    def summary(self) -> CellSummary:
        d = self.document
        error = d["error"]["message"] if d.get("error") else None
        return CellSummary(d["id"], d["model"], d["status"], d["wall_time"], error)


def _now() -> str:
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")


def _laws(model) -> dict:
    return {
        c.name: {"kind": c.kind.value, "law": c.law, "params": dict(c.law_params), "sliding": list(c.law_directions)}
        for c in model.connectors
    }


def _history_meta(job: CellJob, model, elements, nodes, every: int) -> dict:
    return {
        "cell": job.id,
        "digest": job.digest,
        "every": every,
        "description": "bearingfw cell histories, every `every`-th integration step from the dead-load state: "
        "time (s); <family>.<element> of the stress families (Pa, maximum over the "
        "element's recovery points and ends); bearings.<quantity> (t, connectors[, local x y z]; friction_ratio "
        "NaN where the normal force is at most the fraction min_normal_fraction of its dead-load value); "
        "deck.acceleration (t, nodes, global x y z, absolute); ground.acceleration (record samples, global x y z)",
        "min_normal_fraction": MIN_NORMAL_FRACTION,
        "elements": list(elements),
        "bearings": [c.name for c in model.connectors],
        "sliding": {c.name: list(c.law_directions) for c in model.connectors},
        "deck_nodes": list(nodes),
        "units": {"stress": "Pa", "force": "N", "displacement": "m", "slip": "m", "normal_force": "N",
                  "friction_ratio": "-", "acceleration": "m/s^2", "time": "s"},
    }


def _document(job: CellJob) -> dict:
    return {
        "id": job.id, "model": job.model, "record": job.record, "intensity": job.intensity.name,
        "digest": job.digest, "inputs": job.inputs, "started": _now(), "host": platform.node(), "pid": os.getpid(),
    }


def _error(exc: BaseException) -> dict:
    text = "".join(traceback.format_exception(exc))
    message = str(exc) + "".join(f" ({note})" for note in getattr(exc, "__notes__", ()))  # e.g. the law that raised
    if isinstance(exc, SystemExit):  # str() is the bare exit code
        message = (f"sys.exit({exc.code!r}) was called while the cell was computed (by a law, the structure's "
                   "builder or a plugin; the traceback shows where): a cell's code must raise an exception instead")
    return {"type": type(exc).__name__, "message": message, "traceback": text[-200 * TRACEBACK_LINES:]}


def failed_outcome(job: CellJob, exc: BaseException, wall_time: float = 0.0) -> CellOutcome:
    """A failed cell whose error happened outside :func:`compute_cell` (e.g. its worker process died)."""
    document = {**_document(job), "status": "failed", "metrics": {}, "error": _error(exc), "finished": _now(),
                "wall_time": wall_time, "histories": None}
    return CellOutcome(document)


def prepare_cells(jobs: list[CellJob]) -> list[CellJob]:
    """The cells ``jobs`` of one run, stamped with the run (:attr:`CellJob.run`), each with its record
    prepared once for all the cells of its record and intensity (:attr:`CellJob.prepared`): a worker
    then neither reads nor scales it (nor imports the filters that measure it). The warnings that
    raised go into each of those cells. A record that cannot be prepared here (an error, or longer
    than ``[run] cell_timeout``) is left to its cells, which fail as they would have."""
    run = uuid.uuid4().hex
    prepared: dict = {}
    out = []
    for job in jobs:
        key = (job.record, job.intensity.name)
        if key not in prepared:
            experiment = job.experiment
            registry = registry_for(experiment.plugins, import_paths(experiment))
            try:
                with time_limit(experiment.run.cell_timeout):
                    prepared[key] = _recording_warnings(lambda job=job, registry=registry: _scaled_record(job, registry))
            except (Exception, CellTimeout):  # noqa: BLE001 - each cell reads it again and records the failure
                prepared[key] = None
        out.append(attrs.evolve(job, prepared=prepared[key], run=run))
    return out


def _scaled_record(job: CellJob, registry):
    """The cell's record, read, on the integration grid and scaled to the cell's intensity, its ground motion
    (a (steps, 3) array, or for a spatially varying entry a :class:`~bearingfw.experiment.records.SpatialGround`
    that is the reference group's acceleration as an array) and its measures."""
    if job.prepared is not None:
        value, caught = job.prepared
        _warn_again(caught)
        return value
    experiment = job.experiment
    spec = experiment.record(job.record)
    # the record entry by name too: two entries of the same contents name other files
    inputs = {"entry": job.record, **{k: job.inputs.get(k) for k in ("record", "code", "integration", "plugins")}}
    loaded = _shared(job, "record", inputs, lambda: load_record(experiment, spec, registry))
    record = scaled_record(loaded, job.intensity, experiment.intensities,
                           experiment.integration.dt_integration, registry,
                           min_peak_ratio=experiment.run.min_peak_ratio)
    measures = {
        "source": record.title, "synthetic": record.synthetic, "dt": record.dt, "samples": record.n,
        "scale_factor": record.metadata.get("scale_factor", 1.0), "target": job.intensity.target.to_dict(),
        "pga_h10": record_pga_h10(record), "t_ha": record_t_ha(record),
        "degree": record_degree(record, get_scale(experiment.intensities.scale, registry)),
        "notes": list(record.notes), "peak_ratio": record.min_peak_ratio,
    }
    ground = ground_motion(experiment, spec, record, registry)
    if hasattr(ground, "support_motion"):
        measures["spatial"] = ground.spatial.describe()
    return record, ground, measures


def _shake(job: CellJob, model, system, preload, ag, dt, elements, nodes):
    """The dead load, then the ground motion ``ag``: the transient result (a failed analysis: what it computed
    up to the failure, and the error to raise once that is kept)."""
    experiment = job.experiment
    damping = Rayleigh(job.inputs["damping"]["alpha"], job.inputs["damping"]["beta"])
    try:
        return solve_transient(system, ag, dt, settings=experiment.integration, damping=damping,
                               recorders=recorders(elements, nodes, model), preload=preload), None
    except TransientError as exc:  # keep what was computed up to the failure, for diagnosis
        return exc.result, exc


class CellTimeout(BaseException):
    """The cell ran longer than ``[run] cell_timeout``. A BaseException, as KeyboardInterrupt is, so
    that no ``except Exception`` on the way (the solver's, a law's) takes it for a failed step."""

    def __init__(self, seconds: float):
        super().__init__(f"the cell ran longer than [run] cell_timeout = {seconds:g} s and was ended (a law that "
                         "does not return? raise the limit if the cell is just long)")


@contextlib.contextmanager
def time_limit(seconds: float):
    """Raise :class:`CellTimeout` in this thread after ``seconds`` of wall time (an interval timer and
    SIGALRM; only where they exist and in the main thread, as in the serial executor and in each worker
    process of the processes executor; elsewhere, e.g. in a Dask worker's threads, no limit)."""
    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        yield
        return

    def on_alarm(signum, frame):
        raise CellTimeout(seconds)

    previous = signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@contextlib.contextmanager
def _caught_warnings():
    """Record the warnings a cell raises (numpy's overflow and invalid-value warnings, say) instead of
    printing them to the worker's stderr: they go into the cell's document, once each.

    In the main thread (the serial executor, each process of the pool) the warnings machinery is the
    cell's own for its duration. Elsewhere (a Dask worker computes cells in threads) the filters and
    ``warnings.showwarning`` are global to the process and cannot be swapped per cell: a router
    (:func:`_route_thread_warnings`) sends what a thread computing a cell raises into that cell's list.
    """
    if threading.current_thread() is threading.main_thread():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)  # every one counted, not once per place
            yield caught
        return
    caught: list = []
    _route_thread_warnings()
    _cell_thread.caught = caught
    try:
        yield caught
    finally:
        _cell_thread.caught = None


#: Per thread: the warnings list of the cell the thread is computing (None: not computing a cell).
_cell_thread = threading.local()
_route_lock = threading.Lock()


def _routed(message, category, filename, lineno, file=None, line=None):
    """``warnings.showwarning`` while cells run in threads: a warning raised by a thread computing a
    cell goes into the cell's list; any other is shown as it would have been."""
    caught = getattr(_cell_thread, "caught", None)
    if caught is not None:
        caught.append(warnings.WarningMessage(message, category, filename, lineno, file, line))
        return
    previous = _routed.previous
    if previous is getattr(warnings, "_showwarning_orig", None) and hasattr(warnings, "_showwarnmsg_impl"):
        # the default: through the implementation a catch_warnings(record=True) may have replaced
        warnings._showwarnmsg_impl(warnings.WarningMessage(message, category, filename, lineno, file, line))
    else:
        previous(message, category, filename, lineno, file, line)


def _route_thread_warnings() -> None:
    """Install :func:`_routed` (again, if a ``catch_warnings`` has since restored another) and let
    every RuntimeWarning through the filters ("always": counted per call, not shown once per place,
    which would leave a second cell on the same worker without its notes). Process-wide: a process
    whose threads compute cells shows its other RuntimeWarnings each time too."""
    with _route_lock:
        if warnings.showwarning is not _routed:
            _routed.previous = warnings.showwarning
            warnings.showwarning = _routed
        first = warnings.filters[0] if warnings.filters else None
        if not (first and first[0] == "always" and first[2] is RuntimeWarning and first[1] is None and first[3] is None):
            warnings.filterwarnings("always", category=RuntimeWarning)


def _warning_notes(caught) -> list[str]:
    """Each distinct warning once: ``Category: message (file:line), N time(s)``."""
    counts: dict = {}
    for w in caught:
        key = f"{w.category.__name__}: {w.message} ({os.path.basename(w.filename)}:{w.lineno})"
        counts[key] = counts.get(key, 0) + 1
    return [f"{key}, {n} time(s)" for key, n in counts.items()]


def compute_cell(job: CellJob) -> CellOutcome:
    """Compute one cell (module docstring); failures are outcomes, not exceptions."""
    experiment = job.experiment
    wall = time.perf_counter()
    document = _document(job)
    kept: dict = {}
    with _caught_warnings() as caught:
        try:
            with time_limit(experiment.run.cell_timeout):
                _compute(job, document, kept)
        # SystemExit too: a law calling sys.exit must fail its cell, not end the run (exit 0 with no results)
        except (Exception, CellTimeout, SystemExit) as exc:  # noqa: BLE001 - any failure of one cell is recorded
            document["status"] = "failed"
            document["metrics"] = {}
            document["error"] = _error(exc)
    document["warnings"] = _warning_notes(caught)
    document["finished"] = _now()
    document["wall_time"] = time.perf_counter() - wall
    histories = kept.get("histories")
    document["histories"] = f"{job.intensity.name}.npz" if histories is not None else None
    return CellOutcome(document, histories, kept.get("meta"))


#: Per process, what the cells of one bearing model (and of one record) share: the model, its system
#: and dead load, and the record as read, so that the intensities of a model computed in one process
#: build them once (:func:`_shared`). Keyed by the run (:attr:`CellJob.run`: a worker that outlives a
#: run, as a Dask cluster's does, starts again at the next) and by the cells' inputs they are made
#: from. The run's own process also empties it at each run (:func:`forget_shared`).
_SHARED: dict[str, tuple] = {}
_SHARED_SIZE = 8


def _shared(job: CellJob, what: str, inputs: dict, make):
    """``make()``, or what it gave for a cell of this run with these ``inputs`` (module-level cache).
    The warnings ``make`` raised are raised again for every cell that uses what it made."""
    key = canonical_json([what, job.run, inputs])
    entry = _SHARED.get(key)
    if entry is None:
        entry = _recording_warnings(make)  # an exception is the cell's failure, and nothing is kept
        if _SHARED_SIZE > 0:
            while len(_SHARED) >= _SHARED_SIZE:
                _SHARED.pop(next(iter(_SHARED)))  # the oldest
            _SHARED[key] = entry
    value, caught = entry
    _warn_again(caught)
    return value


def _recording_warnings(make) -> tuple:
    """``(make(), the warnings it raised)``; in a thread other than the main one (a Dask worker's) the
    warnings machinery is the process's, so they go where they would have gone, and none are kept."""
    if threading.current_thread() is not threading.main_thread():
        return make(), ()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            value = make()
        except BaseException as exc:
            error = exc
        else:
            error = None
    if error is not None:
        _warn_again(_warning_list(caught))  # a failure keeps the warnings that led to it
        raise error
    return value, _warning_list(caught)


def _warning_list(caught) -> tuple:
    return tuple((w.message, w.category, w.filename, w.lineno) for w in caught)


def _warn_again(caught) -> None:
    for message, category, filename, lineno in caught:
        warnings.warn_explicit(message, category, filename, lineno)


def forget_shared() -> None:
    """Empty the per-process cache of models, systems and records (:func:`_shared`); each run starts
    with it empty."""
    _SHARED.clear()


def _compute(job: CellJob, document: dict, kept: dict) -> None:
    """The cell's work: fills ``document`` (status ok or suspect) and ``kept`` (``histories`` and their
    ``meta``, if kept: also those of a failed analysis, up to the failure); raises on a failure."""
    experiment = job.experiment
    registry = registry_for(experiment.plugins, import_paths(experiment))

    def assemble():
        model = build_model(experiment, experiment.model(job.model), registry)
        system = as_system(model, registry)
        return model, system, gravity(system)

    # every input but the record and the intensity: the cells of one model (the damping, derived from
    # its modes, changes with a data file its builder reads, which the code digest does not hold)
    inputs = {k: v for k, v in job.inputs.items() if k not in ("record", "intensity")}
    model, system, preload = _shared(job, "model", inputs, assemble)
    # each cell from the committed states as the dead load left them (a law that changes its state
    # in place must not carry one cell's history into the next)
    preload = attrs.evolve(preload, law_states=copy.deepcopy(preload.law_states))
    document["laws"] = _laws(model)
    elements = response_elements(experiment.structure, model)
    nodes = deck_nodes(experiment.structure, model)
    record, ag, document["record_measures"] = _scaled_record(job, registry)
    impure = law_purity_problems(system, model, record.dt)  # cheap; under the cell's time limit
    if impure:
        raise LawPurityError("; ".join(impure))
    result, failure = _shake(job, model, system, preload, ag, record.dt, elements, nodes)
    if result is not None:
        reduced, metrics = reduce_result(result, model, elements, nodes, metric_families(registry))
        document["stats"] = result.stats
        document["settings"] = result.settings
        if failure is None:
            document["acceptance"] = accept_cell(result.stats, reduced, metrics, model,
                                                 record.min_peak_ratio, experiment.run)
        every = recording(experiment)
        if every is not None:
            kept["histories"] = thinned({**reduced, "ground.acceleration": ag}, every)
            kept["meta"] = _history_meta(job, model, elements, nodes, every)
    if failure is not None:
        raise failure
    document["metrics"] = metrics
    if document["acceptance"]["passed"]:
        document["status"] = "ok"
        document["error"] = None
    else:  # it ran, but its result is not to be trusted (module acceptance)
        document["status"] = SUSPECT
        document["error"] = {"type": "AcceptanceCheck", "message": "; ".join(document["acceptance"]["problems"]),
                             "traceback": ""}


def write_outcome(store: Store, outcome: CellOutcome) -> None:
    """Commit a computed cell to the store (histories first, then the JSON)."""
    store.write_cell(outcome.document, outcome.histories, outcome.meta)


def compute_and_store(job: CellJob, root: str) -> CellSummary:
    """Compute a cell and commit it to the store at ``root`` from this process (what workers run)."""
    outcome = compute_cell(job)
    write_outcome(Store(root), outcome)
    return outcome.summary

