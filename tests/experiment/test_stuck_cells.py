"""A stuck cell never hangs a run: Ctrl-C to the run's process ends its workers within seconds on every
executor, and a cell that runs past ``[run] cell_timeout`` is ended and recorded as failed.

The law ``test-blocking-spring`` (bfw_test_laws.py) never returns once displaced: the run's check
passes, the first time step of each of its cells hangs."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import ProcessExecutor, SerialExecutor, Store, load_experiment, run_experiment

psutil = pytest.importorskip("psutil")
pytestmark = pytest.mark.skipif(os.name != "posix", reason="signals to a process: POSIX")


def _sigint_as_at_a_terminal() -> None:
    # a job started in the background by a non-interactive shell (as CI scripts may be) inherits SIGINT
    # ignored, and Python then never raises KeyboardInterrupt; a run started at a terminal has the default
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start(spec, out, executor: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "bearingfw", "run", str(spec), "--out", str(out), "--executor", executor,
         "--workers", "2", "--quiet"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True,
        preexec_fn=_sigint_as_at_a_terminal,
    )


def _descendants(process: psutil.Process) -> list[psutil.Process]:
    try:
        return process.children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def _wait_until_cells_run(process: subprocess.Popen, out, expected_children: int, timeout: float = 90.0) -> list:
    """Wait until the run holds its directory and has its workers (then each is in a stuck cell)."""
    run = psutil.Process(process.pid)
    deadline = time.monotonic() + timeout
    children: list = []
    while time.monotonic() < deadline and process.poll() is None:
        children = _descendants(run)
        manifest = out / "manifest.json"
        if manifest.exists() and len(children) >= expected_children:
            break
        time.sleep(0.1)
    time.sleep(1.5)  # into the first time step
    assert process.poll() is None, process.stderr.read().decode()
    return _descendants(run)


@pytest.mark.parametrize("executor, children", [("serial", 0), ("processes", 2), ("dask", 2)])
def test_ctrl_c_ends_a_run_with_stuck_cells_and_its_workers(tmp_path, executor, children):
    if executor == "dask":
        pytest.importorskip("distributed")
    spec = write_tiny(tmp_path / "spec", models=("block",), levels=("D_0", "D_II"))
    out = tmp_path / "out"
    process = _start(spec, out, executor)
    workers = []
    try:
        workers = _wait_until_cells_run(process, out, children)
        assert len(workers) >= children
        sent = time.monotonic()
        process.send_signal(signal.SIGINT)  # to the run's process only, as the issue did
        try:
            code = process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            pytest.fail(f"the {executor} run did not end within 15 s of SIGINT")
        took = time.monotonic() - sent
        _, alive = psutil.wait_procs(workers, timeout=2)
        assert not alive, f"workers outlived the interrupted run: {alive}"
        assert code == 130, process.stderr.read().decode()
        assert took < (10 if executor == "dask" else 5), took
    finally:
        for p in [*workers, psutil.Process(process.pid) if process.poll() is None else None]:
            if p is not None and p.is_running():
                p.kill()
    assert json.loads((out / "manifest.json").read_text())["state"] == "stopped"
    assert Store(out).read_cell("block/tremor/D_0") is None  # an abandoned cell leaves nothing


#: The limit of the alarm tests: a few times a tiny M1 cell's wall time on a loaded machine (~1-3 s), so that
#: M1 finishes under it while the blocked cell cannot.
CELL_TIMEOUT = 5.0


def test_a_stuck_cell_times_out_on_the_processes_executor_and_the_rest_goes_on(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("block", "M1"), levels=("D_0",),
                      extra=f"[run]\ncell_timeout = {CELL_TIMEOUT}\n")
    start = time.monotonic()
    summary = run_experiment(load_experiment(spec), tmp_path / "out", ProcessExecutor(2))
    assert time.monotonic() - start < 60
    assert summary.exit_code == 1
    assert [c for c, _ in summary.failed] == ["block/tremor/D_0"]
    assert f"ran longer than [run] cell_timeout = {CELL_TIMEOUT:g} s" in summary.failed[0][1]
    document = Store(tmp_path / "out").read_cell("block/tremor/D_0")
    assert document["status"] == "failed" and document["error"]["type"] == "CellTimeout"
    assert Store(tmp_path / "out").read_cell("M1/tremor/D_0")["status"] == "ok"


@pytest.mark.skipif(not hasattr(signal, "SIGALRM"), reason="the serial executor's limit needs SIGALRM")
def test_a_stuck_cell_times_out_on_the_serial_executor(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("block", "M1"), levels=("D_0",),
                      extra=f"[run]\ncell_timeout = {CELL_TIMEOUT}\n")
    summary = run_experiment(load_experiment(spec), tmp_path / "out", SerialExecutor())
    assert [c for c, _ in summary.failed] == ["block/tremor/D_0"]
    assert f"ran longer than [run] cell_timeout = {CELL_TIMEOUT:g} s" in summary.failed[0][1]
    assert Store(tmp_path / "out").read_cell("M1/tremor/D_0")["status"] == "ok"
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # no alarm left behind


@pytest.mark.skipif(not hasattr(signal, "SIGALRM"), reason="the limit of a cell needs SIGALRM")
def test_a_worker_deaf_to_the_alarm_is_ended_by_the_run(tmp_path, monkeypatch):
    """A law stuck where the cell's alarm cannot reach it (here: SIGALRM ignored): the run ends that
    worker once the cell is past its limit and a margin, records the cell as failed, and the others go on."""
    from bearingfw.experiment import executors

    # The run's own limit counts from a cell's submission, a fresh pool's worker start included: the M1
    # cells run again in a fresh pool once the deaf workers are ended and must start and finish within
    # cell_timeout + margin there, on a loaded machine too (13 s).
    monkeypatch.setattr(executors, "_HARD_MARGIN", 8.0)
    spec = write_tiny(tmp_path / "spec", models=("deaf", "M1"), levels=("D_0", "D_II"),
                      extra=f"[run]\ncell_timeout = {CELL_TIMEOUT}\n")
    start = time.monotonic()
    summary = run_experiment(load_experiment(spec), tmp_path / "out", ProcessExecutor(2))
    assert time.monotonic() - start < 120
    assert sorted(c for c, _ in summary.failed) == ["deaf/tremor/D_0", "deaf/tremor/D_II"], summary.failed
    assert all(f"ran longer than [run] cell_timeout = {CELL_TIMEOUT:g} s" in e for _, e in summary.failed)
    store = Store(tmp_path / "out")
    assert store.read_cell("deaf/tremor/D_0")["error"]["type"] == "CellTimeout"
    assert {store.read_cell(f"M1/tremor/{level}")["status"] for level in ("D_0", "D_II")} == {"ok"}
