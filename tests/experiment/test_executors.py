"""Executors, the progress display and its ETA, without running a whole experiment."""

from __future__ import annotations

import io
import sys

import pytest

from bearingfw.experiment import (
    EXECUTORS,
    DaskExecutor,
    ExecutorError,
    ProcessExecutor,
    SerialExecutor,
    make_executor,
)
from bearingfw.experiment.execute import CellSummary
from bearingfw.experiment.progress import Progress, estimate_remaining, format_duration


def test_make_executor_checks_its_arguments():
    assert EXECUTORS == ("serial", "processes", "dask")
    assert isinstance(make_executor("serial"), SerialExecutor)
    assert make_executor("processes", 3).workers == 3 and make_executor().workers >= 1
    assert make_executor("dask", 2, "tcp://x:1").scheduler == "tcp://x:1"
    with pytest.raises(ExecutorError, match="unknown executor 'threads'; executors: serial, processes, dask"):
        make_executor("threads")
    with pytest.raises(ExecutorError, match="a scheduler address is for the dask executor"):
        make_executor("processes", scheduler="tcp://x:1")
    with pytest.raises(ExecutorError, match="workers must be an integer >= 1, got 0"):
        make_executor("processes", 0)


def test_without_dask_the_error_names_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    with pytest.raises(ExecutorError, match=r"pip install 'bearingfw\[dask\]'"):
        DaskExecutor().run([object()], store=None, done=print)


def test_process_executor_records_a_dead_worker_and_goes_on(tmp_path, monkeypatch):
    """A worker that dies (here: os._exit in the worker) breaks the pool; its cell is recorded as failed."""
    from tiny_experiment import write_tiny

    from bearingfw.experiment import Store, load_experiment, plan_cells

    jobs = plan_cells(load_experiment(write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0", "D_II"))))
    store = Store(tmp_path / "out")
    seen = []
    executor = ProcessExecutor(1)
    from bearingfw.experiment import executors

    monkeypatch.setattr(executors, "compute_and_store", _die_on_d0)
    executor.run(jobs, store, seen.append)
    assert [(s.id, s.status) for s in seen] == [("M1/tremor/D_0", "failed"), ("M1/tremor/D_II", "ok")]
    assert "worker process running this cell died" in store.read_cell("M1/tremor/D_0")["error"]["message"]


def _die_on_d0(job, root):
    import os

    from bearingfw.experiment.execute import compute_and_store

    if job.intensity.name == "D_0":
        os._exit(9)
    return compute_and_store(job, root)


def test_durations_and_the_eta_weigh_each_model():
    assert format_duration(7.2) == "7 s" and format_duration(245) == "4:05" and format_duration(3723) == "1:02:03"
    assert estimate_remaining({}, {"a": 3}, 2) is None
    # two fast cells done, the slow model not seen yet: counted at the mean (1 s) -> (3 + 2) / 2 workers
    assert estimate_remaining({"fast": [1.0, 1.0]}, {"fast": 3, "slow": 2}, 2) == pytest.approx(2.5)
    # once a slow cell is known, the slow model's cells cost what it did
    assert estimate_remaining({"fast": [1.0], "slow": [100.0]}, {"fast": 1, "slow": 1}, 2) == pytest.approx(50.5)


def test_progress_lines_show_done_of_total_and_an_eta():
    stream = io.StringIO()
    progress = Progress(stream)
    progress.begin(["a", "a", "b"], skipped=2, executor="serial", workers=1)
    progress.cell(CellSummary("a/r/D_0", "a", "ok", 1.5))
    progress.cell(CellSummary("a/r/D_I", "a", "failed", 0.5, "boom"))
    progress.finish("done")
    lines = stream.getvalue().splitlines()
    assert lines[0] == "running 3 cell(s) on serial (1 worker(s)); 2 finished cell(s) kept"
    assert lines[1].startswith("[1/3] a/r/D_0 ok (1.5 s) | elapsed ") and "ETA" in lines[1]
    assert lines[2].startswith("[2/3] a/r/D_I FAILED: boom (0.5 s)")
    assert lines[-1] == "done"
    quiet = io.StringIO()
    Progress(quiet, quiet=True).begin(["a"], 0, "serial", 1)
    assert quiet.getvalue() == ""


def test_a_broken_pool_never_overwrites_a_cell_already_committed(tmp_path):
    """When one worker dies, its siblings' futures fail too, though they may have stored their cell."""
    from tiny_experiment import write_tiny

    from bearingfw.experiment import Store, load_experiment, plan_cells
    from bearingfw.experiment.execute import compute_and_store

    job = plan_cells(load_experiment(write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))))[0]
    store = Store(tmp_path / "out")
    compute_and_store(job, str(store.root))
    before = store.read_cell(job.id)
    seen = []
    ProcessExecutor._failed(store, job, seen.append)
    assert store.read_cell(job.id) == before and before["status"] == "ok"
    assert [(s.id, s.status) for s in seen] == [(job.id, "ok")]


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_on_a_terminal_the_progress_line_is_rewritten_in_place():
    stream = _Terminal()
    progress = Progress(stream)
    progress.begin(["a", "a", "a"], skipped=0, executor="processes", workers=2, thinned=0)
    progress.cell(CellSummary("a/r/D_0", "a", "ok", 1.0))
    progress.cell(CellSummary("a/r/D_I", "a", "failed", 0.5, "boom"))
    progress.cell(CellSummary("a/r/D_II", "a", "ok", 1.0))
    progress.note("drawing the figures (2 process(es))")
    progress.finish("done")
    text = stream.getvalue()
    first, failed, last = "[1/3] a/r/D_0 ok", "[2/3] a/r/D_I FAILED: boom", "[3/3] a/r/D_II ok"
    assert text.startswith("running 3 cell(s) on processes (2 worker(s))\n\r\033[K" + first)
    assert f"\r\033[K{failed}" in text  # replaces the open line, and stays (a newline follows)
    assert "\r" not in text.split(failed)[1].split("\n")[0] and " | ETA " in text.split(failed)[1].split("\n")[0]
    # the last cell's line stays, the notes follow on lines of their own
    assert text.endswith("\n") and text.splitlines()[-2:] == ["drawing the figures (2 process(es))", "done"]
    assert last in text.splitlines()[-3]


def test_progress_begin_says_what_is_kept_and_thinned():
    stream = io.StringIO()
    Progress(stream).begin(["a"], skipped=4, executor="serial", workers=1, thinned=3)
    assert stream.getvalue() == ("running 1 cell(s) on serial (1 worker(s)); 4 finished cell(s) kept (3 with their "
                                 "histories thinned to the new [output] every)\n")
