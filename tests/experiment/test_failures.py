"""A failing cell (a law that raises) is recorded; the rest of the matrix completes; the exit code says so."""

from __future__ import annotations

import json

import pytest
from tiny_experiment import write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment import SerialExecutor, Store, load_experiment, run_experiment


@pytest.fixture(scope="module")
def failed_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("boom")
    path = write_tiny(folder / "spec", models=("M1", "boom", "M2"), levels=("D_0",))
    out = folder / "out"
    return path, out, run_experiment(load_experiment(path), out, SerialExecutor())


def test_the_failing_cell_is_recorded_and_the_others_complete(failed_run):
    _, out, summary = failed_run
    assert summary.exit_code == 1
    assert [cell for cell, _ in summary.failed] == ["boom/tremor/D_0"]
    assert "test-exploding-spring: exploded on purpose" in summary.failed[0][1]
    assert sorted(summary.computed) == ["M1/tremor/D_0", "M2/tremor/D_0", "boom/tremor/D_0"]
    store = Store(out)
    document = store.read_cell("boom/tremor/D_0")
    assert document["status"] == "failed" and document["metrics"] == {}
    assert document["error"]["type"] == "TransientError"
    assert "exploded on purpose" in document["error"]["message"]
    assert "bfw_test_laws.py" in document["error"]["traceback"]
    for other in ("M1/tremor/D_0", "M2/tremor/D_0"):
        assert store.read_cell(other)["status"] == "ok"
    matrices = json.loads((out / "matrices.json").read_text())
    assert matrices["stress.G4"]["boom"] == {"D_0": None}
    assert matrices["stress.G4"]["M1"]["D_0"] > 0 and matrices["stress.G4"]["M2"]["D_0"] > 0


def test_the_report_lists_the_failure(failed_run):
    _, out, _ = failed_run
    report = (out / "report.md").read_text()
    failures = report.split("## Failed cells")[1]
    assert "### boom/tremor/D_0" in failures and "exploded on purpose" in failures and "<details>" in failures
    assert "| boom/tremor/D_0 | failed |" in report
    assert "1 failed" in report.split("## Inputs")[0]


def test_a_failed_cell_is_tried_again_and_the_exit_code_says_it_failed(failed_run, capsys):
    path, out, _ = failed_run
    code = main(["run", str(path), "--out", str(out), "--executor", "serial", "--json"])
    captured = capsys.readouterr()
    assert code == 1
    data = json.loads(captured.out)
    assert data["computed"] == ["boom/tremor/D_0"] and data["exit_code"] == 1
    assert data["failed"][0]["id"] == "boom/tremor/D_0"
    assert "1 cell(s) failed" in captured.err and "boom/tremor/D_0" in captured.err
