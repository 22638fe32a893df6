"""Executors: who computes the cells. Serial, local processes (the default), or Dask distributed.

The executor protocol. An executor is a class registered through the plugin hook
``bearingfw_register_executors`` (the built-in ones by :mod:`bearingfw.experiment.builtin`), with

- ``name`` (class attribute, str): what ``bearingfw run --executor NAME`` calls it;
- ``description`` (class attribute, str): one line for ``bearingfw plugins``;
- a constructor taking ``workers`` (int or None: the executor's default) as a keyword, and
  ``scheduler`` (an address, str or None) if it connects to one;
- ``workers`` (int): how many cells it computes at once (the progress line and the figures use it);
- ``run(jobs, store, done)``: compute every :class:`~bearingfw.experiment.cells.CellJob` of
  ``jobs``, commit each to the :class:`~bearingfw.experiment.store.Store` ``store``
  (:func:`~bearingfw.experiment.execute.compute_and_store` does both in the process that runs
  it; or :func:`~bearingfw.experiment.execute.compute_cell` remotely, then
  :func:`~bearingfw.experiment.execute.write_outcome` here), and call ``done(summary)`` here as
  each finishes, in completion order. A cell that fails is an outcome, not an exception; an
  exception from ``run`` stops the run (``KeyboardInterrupt`` must abandon the cells in progress);
- optionally ``check()``: raise :class:`ExecutorUnavailable` if it cannot run (a scheduler that
  cannot be reached); the run calls it before it writes anything into the results directory.

A new executor is one module with such a class and a ``@hookimpl`` returning it, loaded by an
entry point or by an experiment's ``plugins = [...]``; :func:`make_executor` finds it by name.

Each cell is independent. The built-in executors (:data:`BUILTIN`):

- :class:`SerialExecutor`: one after the other in this process (debugging, tiny runs).
- :class:`ProcessExecutor`: a pool of worker processes (default: one per core). A worker computes
  a cell and commits it to the results store *itself*, so a finished cell survives even a
  ``kill -9`` of the process that started the run. Workers are started with ``spawn`` (a clean
  interpreter: no state inherited from the parent, the same on every platform), and end as soon
  as that process dies, however it dies: an orphan must not go on writing into a results
  directory that the next run holds by then. If a worker dies (killed, out of memory), the
  cells it and its siblings were running are recorded as failed and the remaining cells go on
  in a fresh pool.
- :class:`DaskExecutor`: ``dask.distributed``, on the cluster at ``scheduler`` (an address such as
  ``tcp://10.0.0.5:8786``) or on a local cluster of ``workers`` processes. Workers return each
  cell to this process, which commits it: the workers need bearingfw (and the experiment's
  modules and record files) but not the results directory. Dask is an optional extra:
  ``pip install 'bearingfw[dask]'``.

Ctrl-C stops every executor promptly: cells not started are not run, cells in progress are
abandoned (nothing partial is written), finished cells stay.

:func:`map_in_processes` is the plain parallel map the run's other work uses (the figures), in
such a pool of local processes.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import multiprocessing.connection
import os
import threading
import time
import inspect
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Protocol

from bearingfw.experiment.cells import CellJob
from bearingfw.experiment.execute import (
    CellSummary,
    CellTimeout,
    compute_and_store,
    compute_cell,
    failed_outcome,
    write_outcome,
)
from bearingfw.experiment.store import Store

__all__ = [
    "BUILTIN",
    "EXECUTORS",
    "Executor",
    "DaskExecutor",
    "ExecutorError",
    "ExecutorUnavailable",
    "ProcessExecutor",
    "SerialExecutor",
    "local_workers",
    "make_executor",
    "map_in_processes",
]

Done = Callable[[CellSummary], None]


class Executor(Protocol):
    """What an executor is (module docstring); the registry only checks ``name``."""

    name: str
    description: str
    workers: int

    def run(self, jobs: Sequence[CellJob], store: Store, done: Done) -> None: ...


class ExecutorError(RuntimeError):
    """An executor cannot run: an unknown name or a bad option (bad input), or :class:`ExecutorUnavailable`."""


class ExecutorUnavailable(ExecutorError):
    """The executor exists but the environment does not let it run (Dask missing, a scheduler unreachable,
    a cluster without workers): the same command can succeed once that is fixed."""


#: How often a Dask run looks at its cluster while it waits for cells (s).
_DASK_POLL = 1.0


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _end_with_parent() -> None:
    """Worker initializer: end this worker as soon as the process that started it dies."""
    parent = multiprocessing.parent_process()
    if parent is None:
        return

    def watch():
        multiprocessing.connection.wait([parent.sentinel])  # ready when the parent is gone
        os._exit(1)

    threading.Thread(target=watch, name="bearingfw-watch-parent", daemon=True).start()


def _pool(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=_end_with_parent)


class SerialExecutor:
    """Cells one after the other in this process."""

    name = "serial"
    description = "one cell after the other in this process (debugging, tiny runs)"

    def __init__(self, workers: int | None = None):
        self.workers = 1

    def run(self, jobs: Sequence[CellJob], store: Store, done: Done) -> None:
        for job in jobs:
            done(compute_and_store(job, str(store.root)))


class WorkerDied(RuntimeError):
    """The worker process running a cell ended without a result."""


class ProcessExecutor:
    """A pool of local worker processes (module docstring)."""

    name = "processes"
    description = "a pool of local worker processes, one per core by default; each commits its own cells"

    def __init__(self, workers: int | None = None):
        self.workers = max(1, workers or _cores())

    def run(self, jobs: Sequence[CellJob], store: Store, done: Done) -> None:
        pending = list(jobs)
        while pending:  # a fresh pool whenever a dead worker broke the last one
            pending = self._run_pool(pending, store, done)

    def _run_pool(self, pending: list[CellJob], store: Store, done: Done) -> list[CellJob]:
        """Run cells until all are done (returns []) or the pool breaks (returns those not started)."""
        pool = _pool(min(self.workers, len(pending)))
        running = {}
        started = {}
        try:
            while pending or running:
                # At most one cell per worker in flight: a broken pool then only takes down the
                # cells that were really running, and Ctrl-C has no queue to drain.
                while pending and len(running) < self.workers:
                    job = pending.pop(0)
                    future = pool.submit(compute_and_store, job, str(store.root))
                    running[future], started[future] = job, time.monotonic()
                deadline = min(started[f] + _hard_limit(j) for f, j in running.items())
                finished, _ = wait(running, timeout=max(0.0, deadline - time.monotonic()) + 0.1,
                                   return_when=FIRST_COMPLETED)
                if not finished:
                    overdue = [f for f, j in running.items() if time.monotonic() - started[f] > _hard_limit(j)]
                    if overdue:
                        return self._end_overdue(pool, overdue, running, pending, store, done)
                    continue
                broken = False
                for future in finished:
                    job = running.pop(future)
                    try:
                        done(future.result())
                    except BrokenProcessPool:
                        broken = True
                        self._failed(store, job, done)
                if broken:
                    for job in running.values():
                        self._failed(store, job, done)
                    return pending
            return []
        except BaseException:
            _terminate(pool)
            raise
        finally:
            pool.shutdown(wait=True, cancel_futures=True)

    def _end_overdue(self, pool, overdue, running: dict, pending: list, store: Store, done: Done) -> list[CellJob]:
        """A worker stuck past its cell's limit that the cell's own alarm did not stop (a law stuck in
        compiled code): end the pool, record the stuck cells as failed; the others run again in a fresh pool."""
        _terminate(pool)
        for future in overdue:
            job = running.pop(future)
            outcome = failed_outcome(job, CellTimeout(job.experiment.run.cell_timeout))
            write_outcome(store, outcome)
            done(outcome.summary)
        again = []
        for job in running.values():
            if not self._committed(store, job, done):
                again.append(job)
        return again + pending

    @staticmethod
    def _committed(store: Store, job: CellJob, done: Done) -> bool:
        """If the cell's result for these inputs is stored (ok or suspect), report it and say True."""
        document = store.read_cell(job.id)
        if (document is not None and document.get("digest") == job.digest
                and document.get("status") in ("ok", "suspect")):
            error = (document.get("error") or {}).get("message")
            done(CellSummary(document["id"], document["model"], document["status"], document["wall_time"], error))
            return True
        return False

    @staticmethod
    def _failed(store: Store, job: CellJob, done: Done) -> None:
        # A dying worker breaks the whole pool: siblings that had already committed their cell
        # also report BrokenProcessPool. Their stored result stands; never overwrite it.
        if ProcessExecutor._committed(store, job, done):
            return
        exc = WorkerDied(
            "the worker process running this cell died (killed, or crashed, e.g. out of memory); the cells "
            "running beside it were lost with it. It is tried again on the next run."
        )
        outcome = failed_outcome(job, exc)
        write_outcome(store, outcome)
        done(outcome.summary)


def _hard_limit(job: CellJob) -> float:
    """When the run ends a cell's worker itself (s after submitting it): the cell's own alarm
    (``[run] cell_timeout``, :func:`~bearingfw.experiment.execute.time_limit`) should have ended it
    before; this is for a worker that the alarm cannot reach, with room for a worker's start."""
    limit = job.experiment.run.cell_timeout
    return limit + max(_HARD_MARGIN, 0.1 * limit)


#: The least time the run gives a cell's own alarm before it ends the worker itself (s).
_HARD_MARGIN = 10.0


#: How long a terminated worker has to end before it is killed (s).
_TERMINATE_GRACE = 1.0


def _end_processes(processes) -> None:
    """SIGTERM each process, then SIGKILL those still alive after :data:`_TERMINATE_GRACE`."""
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    deadline = time.monotonic() + _TERMINATE_GRACE
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(max(0.0, deadline - time.monotonic()))
            if process.is_alive():
                process.kill()
                process.join(1.0)


def _terminate(pool: ProcessPoolExecutor) -> None:
    """Stop a pool now: end the workers (their cells are abandoned), then cancel what has not started.

    The workers first: ``shutdown`` empties ``pool._processes`` (CPython 3.11), after which they
    could no longer be reached, and a worker stuck in a cell would hold the run forever."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    _end_processes(processes)
    pool.shutdown(wait=False, cancel_futures=True)


class DaskExecutor:
    """Cells on a Dask cluster (module docstring)."""

    name = "dask"
    description = "Dask distributed: a cluster at --scheduler ADDRESS, or a local one (the 'dask' extra)"

    def __init__(self, scheduler: str | None = None, workers: int | None = None, timeout: str = "20s"):
        self.scheduler = scheduler
        self.workers = max(1, workers or _cores())
        self.timeout = timeout

    def _client(self, stack: contextlib.ExitStack):
        distributed = self._distributed()
        Client, LocalCluster = distributed.Client, distributed.LocalCluster
        if self.scheduler:
            try:
                return stack.enter_context(Client(self.scheduler, timeout=self.timeout))
            except (OSError, TimeoutError) as exc:
                raise ExecutorUnavailable(f"cannot reach the Dask scheduler at {self.scheduler}: {exc}") from None
        cluster = stack.enter_context(
            LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True, dashboard_address=None,
                         silence_logs=logging.ERROR)
        )
        return stack.enter_context(Client(cluster))

    def check(self) -> None:
        """Raise :class:`ExecutorUnavailable` if the run could not start (Dask missing, the scheduler
        unreachable): called before anything is written into the results directory."""
        with contextlib.ExitStack() as stack:
            if self.scheduler:
                self._client(stack)
            else:
                self._distributed()

    @staticmethod
    def _distributed():
        try:
            import distributed
        except ImportError:
            raise ExecutorUnavailable(
                "the dask executor needs Dask distributed, an optional extra: pip install 'bearingfw[dask]'"
            ) from None
        return distributed

    def run(self, jobs: Sequence[CellJob], store: Store, done: Done) -> None:
        if not jobs:
            return
        distributed = self._distributed()
        limit = jobs[0].experiment.run.dask_no_worker_timeout
        with contextlib.ExitStack() as stack:
            client = self._client(stack)
            futures = {client.submit(compute_cell, job, pure=False): job for job in jobs}
            try:
                pending, alone_since = set(futures), None
                while pending:
                    try:
                        finished, pending = distributed.wait(pending, timeout=_DASK_POLL, return_when="FIRST_COMPLETED")
                    except TimeoutError:
                        finished = set()
                    for future in finished:
                        self._commit(future, futures[future], store, done)
                    if not pending:
                        break
                    # A cluster whose workers all died waits for new ones; not forever.
                    if client.scheduler_info().get("workers"):
                        alone_since = None
                    elif alone_since is None:
                        alone_since = time.monotonic()
                    elif time.monotonic() - alone_since > limit:
                        raise ExecutorUnavailable(
                            f"the Dask cluster has had no live worker for {limit:g} s ([run] dask_no_worker_timeout); "
                            f"{len(pending)} cell(s) not computed: start workers and run again to continue")
            except BaseException:
                client.cancel(list(futures))
                raise

    @staticmethod
    def _commit(future, job: CellJob, store: Store, done: Done) -> None:
        try:
            outcome = future.result()
        except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: the cell failed, not the run
            outcome = failed_outcome(job, exc)
        write_outcome(store, outcome)
        done(outcome.summary)


def local_workers(executor) -> int:
    """How many local processes the run's other work (figures) may use beside ``executor``: none
    besides this one for the serial executor, else its workers, at most one per core here."""
    return 1 if executor.name == "serial" else min(executor.workers, _cores())


def map_in_processes(fn: Callable, items: Sequence[tuple], extra: Callable | None = None, workers: int = 1) -> list:
    """``[fn(*item) for item in items]``, in order, computed in a pool of ``workers`` processes
    (here, one after the other, for one worker or fewer than two items); ``extra()`` runs here
    meanwhile. The first exception (or Ctrl-C) ends the workers and is raised."""
    if workers <= 1 or len(items) < 2:
        if extra is not None:
            extra()
        return [fn(*item) for item in items]
    pool = _pool(min(workers, len(items)))
    try:
        futures = [pool.submit(fn, *item) for item in items]
        if extra is not None:
            extra()
        return [future.result() for future in futures]
    except BaseException:
        _terminate(pool)
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


#: The built-in executors, registered by :mod:`bearingfw.experiment.builtin`.
BUILTIN = (SerialExecutor, ProcessExecutor, DaskExecutor)
#: Their names.
EXECUTORS = tuple(e.name for e in BUILTIN)


def _takes(factory, keyword: str) -> bool:
    try:
        parameters = inspect.signature(factory).parameters.values()
    except (TypeError, ValueError):
        return False
    return any(p.name == keyword or p.kind is p.VAR_KEYWORD for p in parameters)


def make_executor(name: str = "processes", workers: int | None = None, scheduler: str | None = None,
                  registry=None):
    """The executor registered as ``name`` (module docstring), with ``workers`` and, for one that
    connects to a scheduler, its address; ``registry``: where to look (default: the installed plugins)."""
    from bearingfw.plugins import get_registry

    executors = (registry or get_registry()).executors
    if name not in executors:
        raise ExecutorError(f"unknown executor {name!r}; executors: {', '.join(executors)}")
    factory = executors[name].value
    if scheduler and not _takes(factory, "scheduler"):
        takers = [n for n, e in executors.items() if _takes(e.value, "scheduler")]
        raise ExecutorError(f"a scheduler address is for the {' or '.join(takers) or 'no'} executor "
                            f"(--executor {takers[0] if takers else 'NAME'}), not {name!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ExecutorError(f"workers must be an integer >= 1, got {workers!r}")
    try:
        return factory(workers=workers, scheduler=scheduler) if scheduler else factory(workers=workers)
    except ExecutorError:
        raise
    except Exception as exc:  # noqa: BLE001 - a plugin's executor that cannot start
        raise ExecutorError(f"executor {name!r} could not start: {type(exc).__name__}: {exc}") from None
