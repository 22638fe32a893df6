"""Executors: who computes the cells. Serial, local processes (the default), or Dask distributed.

Each cell is independent. Every executor calls ``done(summary)`` in the running process as each
cell finishes, in completion order.

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
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from bearingfw.experiment.cells import CellJob
from bearingfw.experiment.execute import (
    CellSummary,
    compute_and_store,
    compute_cell,
    failed_outcome,
    write_outcome,
)
from bearingfw.experiment.store import Store

__all__ = [
    "EXECUTORS",
    "DaskExecutor",
    "ExecutorError",
    "ProcessExecutor",
    "SerialExecutor",
    "local_workers",
    "make_executor",
    "map_in_processes",
]

EXECUTORS = ("serial", "processes", "dask")

Done = Callable[[CellSummary], None]


class ExecutorError(RuntimeError):
    """An executor cannot run (Dask missing, a scheduler unreachable)."""


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
    workers = 1

    def run(self, jobs: Sequence[CellJob], store: Store, done: Done) -> None:
        for job in jobs:
            done(compute_and_store(job, str(store.root)))


class WorkerDied(RuntimeError):
    """The worker process running a cell ended without a result."""


class ProcessExecutor:
    """A pool of local worker processes (module docstring)."""

    name = "processes"

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
        try:
            while pending or running:
                # At most one cell per worker in flight: a broken pool then only takes down the
                # cells that were really running, and Ctrl-C has no queue to drain.
                while pending and len(running) < self.workers:
                    job = pending.pop(0)
                    running[pool.submit(compute_and_store, job, str(store.root))] = job
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
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

    @staticmethod
    def _failed(store: Store, job: CellJob, done: Done) -> None:
        # A dying worker breaks the whole pool: siblings that had already committed their cell
        # also report BrokenProcessPool. Their stored result stands; never overwrite it.
        document = store.read_cell(job.id)
        if document is not None and document.get("digest") == job.digest and document.get("status") == "ok":
            done(CellSummary(document["id"], document["model"], "ok", document["wall_time"]))
            return
        exc = WorkerDied(
            "the worker process running this cell died (killed, or crashed, e.g. out of memory); the cells "
            "running beside it were lost with it. It is tried again on the next run."
        )
        outcome = failed_outcome(job, exc)
        write_outcome(store, outcome)
        done(outcome.summary)


def _terminate(pool: ProcessPoolExecutor) -> None:
    """Stop a pool now: cancel what has not started and end the workers (their cells are abandoned)."""
    pool.shutdown(wait=False, cancel_futures=True)
    terminate = getattr(pool, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        with contextlib.suppress(Exception):
            process.terminate()


class DaskExecutor:
    """Cells on a Dask cluster (module docstring)."""

    name = "dask"

    def __init__(self, scheduler: str | None = None, workers: int | None = None, timeout: str = "20s"):
        self.scheduler = scheduler
        self.workers = max(1, workers or _cores())
        self.timeout = timeout

    def _client(self, stack: contextlib.ExitStack):
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise ExecutorError(
                "the dask executor needs Dask distributed, an optional extra: pip install 'bearingfw[dask]'"
            ) from None
        if self.scheduler:
            try:
                return stack.enter_context(Client(self.scheduler, timeout=self.timeout))
            except (OSError, TimeoutError) as exc:
                raise ExecutorError(f"cannot reach the Dask scheduler at {self.scheduler}: {exc}") from None
        cluster = stack.enter_context(
            LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True, dashboard_address=None,
                         silence_logs=logging.ERROR)
        )
        return stack.enter_context(Client(cluster))

    def run(self, jobs: Sequence[CellJob], store: Store, done: Done) -> None:
        if not jobs:
            return
        with contextlib.ExitStack() as stack:
            client = self._client(stack)
            from distributed import as_completed

            futures = {client.submit(compute_cell, job, pure=False): job for job in jobs}
            try:
                for future in as_completed(futures):
                    job = futures[future]
                    try:
                        outcome = future.result()
                    except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: the cell failed, not the run
                        outcome = failed_outcome(job, exc)
                    write_outcome(store, outcome)
                    done(outcome.summary)
            except BaseException:
                client.cancel(list(futures))
                raise


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


def make_executor(name: str = "processes", workers: int | None = None, scheduler: str | None = None):
    """The executor called ``name`` (:data:`EXECUTORS`)."""
    if name not in EXECUTORS:
        raise ExecutorError(f"unknown executor {name!r}; executors: {', '.join(EXECUTORS)}")
    if scheduler and name != "dask":
        raise ExecutorError("a scheduler address is for the dask executor (--executor dask)")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ExecutorError(f"workers must be an integer >= 1, got {workers!r}")
    if name == "serial":
        return SerialExecutor()
    if name == "processes":
        return ProcessExecutor(workers)
    return DaskExecutor(scheduler, workers)
