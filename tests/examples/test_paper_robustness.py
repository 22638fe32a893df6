"""examples/paper-study/robustness.py: the paper's findings per record (slow: a subset, about 2-4 minutes).

Two synthetic seeds at D_0 and D_II, M0/M1/M2. The table must be the findings' own evaluation on each
record's matrices, and the default tremor's column (seed 0) must say what the default study says
(default_study_reference.json: the same cells, the same verdicts and ratios).
"""

from __future__ import annotations

import json
import math
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "paper-study"
REFERENCE = json.loads((ROOT / "tests" / "experiment" / "default_study_reference.json").read_text())


def _numbers(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"\d+\.\d+(?:e[+-]?\d+)?", text)]


def _script():
    sys.path.insert(0, str(EXAMPLE))
    try:
        import robustness
    finally:
        sys.path.remove(str(EXAMPLE))
    return robustness


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    robustness = _script()
    out = tmp_path_factory.mktemp("robustness")
    experiment = robustness.experiment_subset(records=["seed0", "seed1"], levels=["D_0", "D_II"])
    summary = robustness.run(experiment, out)
    return robustness, experiment, out, summary


def test_the_subset_keeps_what_its_levels_can_judge():
    robustness = _script()
    e = robustness.experiment_subset(records=["seed0"], levels=["D_0", "D_II"])
    assert [r.name for r in e.records] == ["seed0"] and e.model_names == ("M0", "M1", "M2")
    assert all(set(f.level) <= {"D_0", "D_II"} for f in e.findings)
    friction = [f for f in e.findings if f.metric == "friction_ratio.3B"]
    assert [f.level for f in friction] == [("D_II",)]  # D_III and D_IV dropped from the list, D_II kept


@pytest.mark.slow
def test_the_table_is_each_records_own_findings(study):
    robustness, experiment, out, summary = study
    assert summary.exit_code == 0 and len(summary.computed) == 12
    per_record = robustness.per_record_findings(experiment, out)
    rows = robustness.findings_table(per_record)
    assert [r["finding"] for r in rows] == [f.statement for f in per_record["seed0"]]
    from bearingfw.experiment import check_findings

    for record, matrices in robustness.record_matrices(experiment, out).items():
        own = check_findings(experiment.findings, matrices)
        assert [row[record]["holds"] for row in rows] == [f.holds for f in own]
        assert [row[record]["measured"] for row in rows] == [f.measured for f in own]
        # a finding that fails says why
        assert all(row[record]["explanation"] for row in rows if row[record]["holds"] is False)
    text = robustness.markdown(rows, robustness.ratio_table(experiment, out))
    assert "| finding | seed0 | seed1 |" in text and "| seed1 | D_0 |" in text


@pytest.mark.slow
def test_the_default_tremor_column_is_the_default_studys(study):
    robustness, experiment, out, _ = study
    expected = {f["statement"]: f for f in REFERENCE["findings"]}
    checked = 0
    for f in robustness.per_record_findings(experiment, out)["seed0"]:
        if f.statement in expected:
            assert f.holds == expected[f.statement]["holds"], f.statement
            # the numbers (the former engine wrote the friction ratio's value in other words)
            assert _numbers(f.measured) == pytest.approx(_numbers(expected[f.statement]["measured"]), rel=1e-9,
                                                         abs=5e-7), f.statement
            checked += 1
    assert checked == 8  # the four D_0 findings, the two D_0/D_II comparisons and the two D_II ones
    ratios = robustness.ratio_table(experiment, out)["seed0"]
    m = REFERENCE["matrices"]
    for element, a, b in robustness.RATIOS:
        rows = m[f"stress_dynamic.{element}"]
        assert ratios[f"{element} {a}/{b}"] == pytest.approx(rows[a]["D_0"] / rows[b]["D_0"], rel=1e-8)
    assert not math.isnan(robustness.ratio_table(experiment, out)["seed1"]["S1 M0/M1"])


def test_the_robustness_experiment_is_valid():
    from bearingfw.experiment import check_experiment, load_experiment, plan_cells

    experiment = load_experiment(EXAMPLE / "robustness.toml")
    check_experiment(experiment)  # builds every model, reads every record
    assert len(plan_cells(experiment)) == 3 * 6 * 5
    assert {f.metric.partition(".")[0] for f in experiment.findings} == {"stress_dynamic", "friction_ratio"}
