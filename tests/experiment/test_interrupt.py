"""A run killed with SIGKILL loses no finished cell: the rerun computes only the missing ones, and the
matrices equal those of an uninterrupted run exactly."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import (
    ProcessExecutor,
    Store,
    load_experiment,
    plan_cells,
    run_experiment,
)

pytestmark = pytest.mark.skipif(not hasattr(os, "killpg"), reason="needs POSIX process groups")

#: Slow cells (the test law sleeps in every call), so that the kill lands in the middle of the run.
MODELS = ("slow", "M1", "M2")
LEVELS = ("D_0", "D_II")


def _finished(store: Store, jobs) -> set[str]:
    return {j.id for j in jobs if store.is_finished(j.id, j.digest, histories=True)}


def test_kill_minus_nine_then_rerun(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=MODELS, levels=LEVELS, delay=5e-4)
    experiment = load_experiment(spec)
    jobs = plan_cells(experiment)
    everything = {j.id for j in jobs}

    reference = run_experiment(experiment, tmp_path / "uninterrupted", ProcessExecutor(2))
    assert set(reference.computed) == everything

    out = tmp_path / "killed"
    process = subprocess.Popen(
        [sys.executable, "-m", "bearingfw", "run", str(spec), "--out", str(out), "--executor", "processes",
         "--workers", "2", "--quiet"],
        start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    store = Store(out)
    deadline = time.monotonic() + 120
    try:
        while not _finished(store, jobs) and time.monotonic() < deadline and process.poll() is None:
            time.sleep(0.02)
    finally:
        os.killpg(process.pid, signal.SIGKILL)  # the run and its worker processes, with no chance to clean up
        process.wait()
    kept = _finished(store, jobs)
    assert 0 < len(kept) < len(everything), "the kill should land after the first cell and before the last"
    for cell in kept:  # what is there is whole
        assert store.read_cell(cell)["status"] == "ok" and store.read_histories(cell) is not None

    rerun = run_experiment(experiment, out, ProcessExecutor(2))
    assert set(rerun.skipped) == kept
    assert set(rerun.computed) == everything - kept
    assert rerun.exit_code == 0
    assert not list(out.rglob(".partial-*"))
    assert json.loads((out / "matrices.json").read_text()) == json.loads(
        (tmp_path / "uninterrupted" / "matrices.json").read_text())
