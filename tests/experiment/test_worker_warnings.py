"""Warnings raised inside a cell computed by a worker (a process of the pool, a thread of a Dask worker)
go into the cell's document, once each with their count, and never reach stderr raw.

``test-noisy-spring`` overflows ``np.exp`` at every call (a RuntimeWarning, result unused). The serial
executor's case is in test_messages.py.
"""

from __future__ import annotations

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import ProcessExecutor, Store, load_experiment, run_experiment

RAW = "RuntimeWarning: overflow encountered in exp"


def noted_once(store: Store, cell: str) -> int:
    """The count of the cell's one overflow note (asserting there is exactly one)."""
    notes = store.read_cell(cell)["warnings"]
    assert len(notes) == 1 and notes[0].startswith(f"{RAW} (bfw_test_laws.py:"), notes
    return int(notes[0].rsplit(", ", 1)[1].split()[0])


def test_warnings_in_a_process_pool_cell_reach_its_document_and_not_stderr(tmp_path, capfd):
    spec = write_tiny(tmp_path / "spec", models=("noisy", "M1"), levels=("D_0",))
    summary = run_experiment(load_experiment(spec), tmp_path / "out", ProcessExecutor(2))
    assert summary.exit_code == 0
    store = Store(tmp_path / "out")
    assert noted_once(store, "noisy/tremor/D_0") > 100  # every call counted
    assert store.read_cell("M1/tremor/D_0")["warnings"] == []  # a quiet cell stays quiet
    err = capfd.readouterr().err  # the workers' stderr is this process's file descriptor 2
    assert "overflow encountered" not in err, err


def test_warnings_in_a_dask_worker_thread_reach_its_document_and_not_stderr(tmp_path, capfd):
    """A Dask worker computes cells in threads, where the warnings filters (global to the process) cannot
    be swapped per cell: before, the warnings went raw to the worker's stderr and the document had none."""
    distributed = pytest.importorskip("distributed")
    from bearingfw.experiment import DaskExecutor

    spec = write_tiny(tmp_path / "spec", models=("noisy", "M1"), levels=("D_0", "D_II"))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        summary = run_experiment(load_experiment(spec), tmp_path / "out", DaskExecutor(cluster.scheduler_address))
    assert summary.exit_code == 0
    store = Store(tmp_path / "out")
    counts = [noted_once(store, f"noisy/tremor/{level}") for level in ("D_0", "D_II")]
    assert min(counts) > 100, counts  # both cells, also the second one a thread computes
    assert all(store.read_cell(f"M1/tremor/{level}")["warnings"] == [] for level in ("D_0", "D_II"))
    err = capfd.readouterr().err
    assert "overflow encountered" not in err, err
