"""The example experiments load, pass the checks, and the paper-study file is the built-in study."""

from __future__ import annotations

from pathlib import Path

import pytest

from bearingfw.experiment import (
    check_experiment,
    default_experiment,
    load_experiment,
    plan_cells,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize(
    ("path", "cells"),
    [("paper-study/paper-study.toml", 25), ("small-bridge/small-bridge.toml", 24),
     ("real-records/friction-sweep.toml", 36)],
)
def test_examples_are_valid(path, cells):
    experiment = load_experiment(EXAMPLES / path)
    checked = check_experiment(experiment)  # builds every model, reads every record
    assert len(plan_cells(experiment)) == cells
    assert set(checked.table) == set(experiment.output.table)


def test_the_paper_study_example_is_the_built_in_study():
    example = {j.id: j.digest for j in plan_cells(load_experiment(EXAMPLES / "paper-study" / "paper-study.toml"))}
    assert example == {j.id: j.digest for j in plan_cells(default_experiment())}


def test_the_real_records_are_read_with_their_own_time_steps():
    checked = check_experiment(load_experiment(EXAMPLES / "real-records" / "friction-sweep.toml"))
    assert checked.records["chuetsu"].dt == 0.01 and checked.records["manjil"].dt == 0.02
    assert checked.records["manjil"].padded  # its components differ in length


@pytest.mark.slow
def test_the_small_bridge_example_runs_with_its_own_findings(tmp_path, capsys):
    """From the command line alone: the user's bridge, a single-component record beside the tremor, and the
    findings the file declares, checked and reported."""
    import json

    from bearingfw.cli.main import main

    code = main(["run", str(EXAMPLES / "small-bridge" / "small-bridge.toml"), "--out", str(tmp_path), "--only", "M1",
                 "--only", "M2", "--levels", "D_0", "--no-figures", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and sorted(data["computed"]) == ["M1/chuetsu-ew/D_0", "M1/tremor/D_0", "M2/chuetsu-ew/D_0",
                                                      "M2/tremor/D_0"]
    first = data["findings"][0]
    assert first["statement"] == "D_0, over the pier: friction (M2) within 25 % of the springs (M1)"
    assert first["holds"] is True and first["measured"].startswith("M2/M1 = ")
    assert "| D_0, over the pier: friction (M2) within 25 % of the springs (M1) |" in (tmp_path / "report.md").read_text()
    record = json.loads((tmp_path / "records.json").read_text())["chuetsu-ew"]
    assert record["missing"] == ["y", "z"]  # one component: the other directions at rest
