"""A run killed with SIGKILL loses no finished cell and leaves nothing a rerun could mistake for a result:
every file in the store is then a whole cell, a cell's histories without its commit (not finished),
or a temporary of a dead writer (removed by the rerun). The rerun computes exactly the missing cells,
and the matrices equal those of an uninterrupted run exactly. Worker processes do not outlive the run."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from bfw_test_laws import HOLD
from tiny_experiment import write_tiny

from bearingfw.experiment import (
    ProcessExecutor,
    Store,
    load_experiment,
    plan_cells,
    recording,
    run_experiment,
)
from bearingfw.experiment.store import CELL_FORMAT, LOCK_NAME
from bearingfw.experiment.structure import package_source_digest

pytestmark = pytest.mark.skipif(not hasattr(os, "killpg"), reason="needs POSIX process groups")

#: The killed run computes M1's cells, then the held ones, which never end in that run (it has
#: BFW_TEST_HOLD set, see bfw_test_laws.py): the kill after its first finished cell lands before its last
#: whatever the machine's load. Without the variable (here, for the reference and the rerun) they are
#: plain springs, computed at full speed with the same digests.
MODELS = ("M1", "held")
LEVELS = ("D_0", "D_II")


def _finished(store: Store, jobs, every) -> set[str]:
    return {j.id for j in jobs if store.is_finished(j.id, j.digest, every)}


def _start(spec, out, workers: int = 2, **kwargs) -> subprocess.Popen:
    """``bearingfw run`` in a new process, with the held cells held (its standard error next to ``out``)."""
    with open(f"{out}.stderr", "wb") as stderr:
        return subprocess.Popen(
            [sys.executable, "-m", "bearingfw", "run", str(spec), "--out", str(out), "--executor", "processes",
             "--workers", str(workers), "--quiet"],
            stdout=subprocess.DEVNULL, stderr=stderr, env={**os.environ, HOLD: "1"}, **kwargs,
        )


def _wait_for_a_cell(process, store, jobs, timeout=120.0) -> None:
    """Until the run commits its first cell; the run must still be running then."""
    deadline = time.monotonic() + timeout
    stored = {}
    while not any(stored.values()) and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.02)
        stored = {j.id: (store.read_cell(j.id) or {}).get("digest") for j in jobs}
    assert all(stored.get(j.id) in (None, j.digest) for j in jobs), (
        "the run stored cells under other digests than this process's plan: were bearingfw's sources edited "
        "while the test ran?")
    # The held cells never end, so the run cannot end by itself; if it did, say why.
    assert process.poll() is None, (
        f"the run ended (status {process.returncode}) before the test saw a finished cell: "
        + Path(f"{store.root}.stderr").read_text(errors="replace")[-2000:])


def _classify(out, jobs, every) -> dict[str, set[str]]:
    """Every file of a killed run's store by what it is; what fits no kind is under "unexplained"."""
    store = Store(out)
    by_path = {}
    for j in jobs:
        by_path[store.cell_json(j.id)] = ("json", j)
        by_path[store.cell_npz(j.id)] = ("npz", j)
    kinds: dict[str, set[str]] = {k: set() for k in ("cell", "histories only", "temporary", "run file", "unexplained")}
    for path in (p for p in out.rglob("*") if p.is_file()):
        name = str(path.relative_to(out))
        if path.name.startswith(".partial-"):
            kinds["temporary"].add(name)
        elif path.parent == out and path.name in ("experiment.toml", "manifest.json", LOCK_NAME):
            kinds["run file"].add(name)
        elif path in by_path:
            kind, job = by_path[path]
            document = store.read_cell(job.id)
            histories = store.read_histories(job.id)
            if kind == "json":  # a commit: whole, this digest, ok, and its histories are there
                whole = (document is not None and document["format"] == CELL_FORMAT and document["status"] == "ok"
                         and store.is_finished(job.id, job.digest, every))
                kinds["cell" if whole else "unexplained"].add(name)
            elif histories is not None and histories[1]["digest"] == job.digest:
                # histories whose commit did not happen: the cell is not finished and will be computed again
                kinds["cell" if document is not None else "histories only"].add(name)
            else:
                kinds["unexplained"].add(name)
        else:
            kinds["unexplained"].add(name)
    return kinds


def test_kill_minus_nine_then_rerun(tmp_path):
    # The digests of this process's plan are compared with those the run's new process computes: make this
    # process's source digest that of the sources as they are now (it is cached from the first run).
    package_source_digest.cache_clear()
    spec = write_tiny(tmp_path / "spec", models=MODELS, levels=LEVELS)
    experiment = load_experiment(spec)
    every = recording(experiment)
    jobs = plan_cells(experiment)
    everything = {j.id for j in jobs}

    reference = run_experiment(experiment, tmp_path / "uninterrupted", ProcessExecutor(2))
    assert set(reference.computed) == everything

    out = tmp_path / "killed"
    store = Store(out)
    process = _start(spec, out, start_new_session=True)
    try:
        _wait_for_a_cell(process, store, jobs)
    finally:
        with contextlib.suppress(ProcessLookupError):  # (gone only if the run ended by itself: a failure above)
            os.killpg(process.pid, signal.SIGKILL)  # the run and its worker processes, with no chance to clean up
        process.wait()
    kept = _finished(store, jobs, every)
    assert 0 < len(kept) < len(everything), "the kill should land after the first cell and before the last"

    kinds = _classify(out, jobs, every)
    assert not kinds["unexplained"], kinds["unexplained"]
    assert {n.rsplit(".", 1)[0] for n in kinds["cell"] if n.endswith(".json")} == {f"cells/{c}" for c in kept}
    for cell in kept:  # what is there is whole
        assert store.read_cell(cell)["status"] == "ok" and store.read_histories(cell) is not None
    leftovers = {out / n for n in kinds["temporary"]}  # all the killed processes'

    rerun = run_experiment(experiment, out, ProcessExecutor(2))
    assert set(rerun.skipped) == kept
    assert set(rerun.computed) == everything - kept
    assert rerun.exit_code == 0
    assert not any(p.exists() for p in leftovers)  # dead writers' temporaries are removed
    assert not list(out.rglob(".partial-*"))
    assert _finished(store, jobs, every) == everything
    assert json.loads((out / "matrices.json").read_text()) == json.loads(
        (tmp_path / "uninterrupted" / "matrices.json").read_text())


def test_the_workers_end_when_the_run_is_killed(tmp_path):
    """Only the run's own process gets SIGKILL: its workers notice and end, so that none goes on writing
    into the directory (which the next run may hold by then)."""
    psutil = pytest.importorskip("psutil")
    spec = write_tiny(tmp_path / "spec", models=("held",), levels=LEVELS)  # workers held in their cells
    experiment = load_experiment(spec)
    jobs, every = plan_cells(experiment), recording(experiment)
    out = tmp_path / "out"
    process = _start(spec, out)
    workers = []
    try:
        run = psutil.Process(process.pid)
        deadline = time.monotonic() + 60
        while not workers and time.monotonic() < deadline and process.poll() is None:
            workers = [p for p in run.children() if "spawn_main" in " ".join(p.cmdline())]
            time.sleep(0.05)
        assert workers, "the run should have started its workers"
        process.send_signal(signal.SIGKILL)
        process.wait()
        _, alive = psutil.wait_procs(workers, timeout=20)
        assert not alive, f"workers outlived the run: {alive}"
    finally:
        for worker in workers:  # only if the test failed: do not leave them behind
            if worker.is_running():
                worker.kill()
    rerun = run_experiment(experiment, out, ProcessExecutor(2))
    assert rerun.exit_code == 0 and _finished(Store(out), jobs, every) == {j.id for j in jobs}
