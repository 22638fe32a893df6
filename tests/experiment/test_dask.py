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


def test_an_unreachable_scheduler_leaves_nothing_in_a_new_directory_and_exits_3(tmp_path, capsys, monkeypatch):
    from bearingfw.cli.main import main

    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    out = tmp_path / "new"
    with pytest.raises(ExecutorError, match="cannot reach the Dask scheduler"):
        run_experiment(load_experiment(spec), out, DaskExecutor("tcp://127.0.0.1:1", timeout="1s"))
    assert not out.exists()  # no .lock, experiment.toml nor manifest.json
    original = DaskExecutor.__init__  # the command's executor with a short connection timeout

    def quick(self, scheduler=None, workers=None, timeout="1s"):
        original(self, scheduler, workers, timeout)

    monkeypatch.setattr(DaskExecutor, "__init__", quick)
    code = main(["run", str(spec), "--out", str(out), "--scheduler", "tcp://127.0.0.1:1"])
    err = capsys.readouterr().err
    assert code == 3 and "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in err and not out.exists()


def test_a_cluster_without_live_workers_stops_the_run_with_a_message(tmp_path):
    from bearingfw.experiment import ExecutorUnavailable

    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",),
                      extra="[run]\ndask_no_worker_timeout = 2.0\n")
    out = tmp_path / "out"
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        with pytest.raises(ExecutorUnavailable, match=r"no live worker for 2 s .*1 cell\(s\) not computed"):
            run_experiment(load_experiment(spec), out, DaskExecutor(cluster.scheduler_address))
    assert json.loads((out / "manifest.json").read_text())["state"] == "stopped"
