"""The Dask executor gives the same matrices as the local processes (skipped without dask.distributed)."""

from __future__ import annotations

import json

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import (
    DaskExecutor,
    ExecutorError,
    ProcessExecutor,
    load_experiment,
    run_experiment,
)

distributed = pytest.importorskip("distributed")


def test_dask_and_local_processes_give_the_same_matrices(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1", "M2"), levels=("D_0", "D_II"))
    experiment = load_experiment(spec)
    local = run_experiment(experiment, tmp_path / "local", ProcessExecutor(2))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        on_dask = run_experiment(experiment, tmp_path / "dask", DaskExecutor(cluster.scheduler_address))
    assert on_dask.executor == "dask" and len(on_dask.computed) == 4 and on_dask.exit_code == 0
    assert json.loads((tmp_path / "dask" / "matrices.json").read_text()) == json.loads(
        (tmp_path / "local" / "matrices.json").read_text())
    assert local.exit_code == 0


def test_an_unreachable_scheduler_is_an_executor_error(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    with pytest.raises(ExecutorError, match="cannot reach the Dask scheduler at tcp://127.0.0.1:1"):
        run_experiment(load_experiment(spec), tmp_path / "out", DaskExecutor("tcp://127.0.0.1:1", timeout="1s"))
