"""Matrices from cell documents: aggregation over records, ratios, NaN, the text tables; cell digests."""

from __future__ import annotations

import math

import attrs
import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import (
    check_findings,
    collect_matrices,
    default_experiment,
    format_tables,
    load_experiment,
    plan_cells,
)


def paper_findings(matrices):
    """The built-in study's findings that the matrix can judge."""
    return [f for f in check_findings(default_experiment().findings, matrices) if f.holds is not None]


def _doc(model, record, intensity, **values):
    return {"model": model, "record": record, "intensity": intensity, "status": "ok",
            "metrics": {m.replace("_", ".", 1) if m.startswith("stress") else m: {"value": v, "time": 1.0, "at": None}
                        for m, v in values.items()}}


def test_records_combine_by_max_below_seven_records_and_by_mean_from_seven():
    few = [_doc("A", f"r{k}", "D_0", stress_S1=float(k)) for k in range(3)]
    assert collect_matrices(few, ["A"], ["r0", "r1", "r2"], ["D_0"], "A").value("stress.S1", "A", "D_0") == 2.0
    mean = collect_matrices(few, ["A"], ["r0", "r1", "r2"], ["D_0"], "A", aggregate="mean")
    assert mean.value("stress.S1", "A", "D_0") == 1.0
    seven = [_doc("A", f"r{k}", "D_0", stress_S1=float(k)) for k in range(7)]
    names = [f"r{k}" for k in range(7)]
    assert collect_matrices(seven, ["A"], names, ["D_0"], "A").value("stress.S1", "A", "D_0") == 3.0
    assert collect_matrices(seven, ["A"], names, ["D_0"], "A", "max").value("stress.S1", "A", "D_0") == 6.0
    # a record's cell missing (or failed): the entry is unknown, not the value of the others
    assert math.isnan(collect_matrices(few[:2], ["A"], ["r0", "r1", "r2"], ["D_0"], "A").value("stress.S1", "A", "D_0"))


def test_ratios_and_tables():
    docs = [_doc("M0", "r", "D_0", stress_S1=1e6, friction_ratio_x=None),
            _doc("M2", "r", "D_0", stress_S1=2e6, friction_ratio_x=0.04),
            {"model": "M1", "record": "r", "intensity": "D_0", "status": "failed", "metrics": {}}]
    docs[0]["metrics"]["friction_ratio.3B"] = docs[0]["metrics"].pop("friction_ratio_x")
    docs[1]["metrics"]["friction_ratio.3B"] = docs[1]["metrics"].pop("friction_ratio_x")
    m = collect_matrices(docs, ["M0", "M1", "M2"], ["r"], ["D_0"], "M2")
    assert m.metrics == ("stress.S1", "friction_ratio.3B")
    assert m.ratio("stress.S1", "M0", "D_0") == 0.5 and math.isnan(m.ratio("stress.S1", "M1", "D_0"))
    assert math.isnan(m.value("friction_ratio.3B", "M0", "D_0"))
    text = format_tables(m, ["stress.S1", "friction_ratio.3B", "not.there"])
    assert text.splitlines()[0] == "stress.S1 [MPa]  (ratio to M2)"
    assert text.splitlines()[1:5] == ["  model       D_0", "  M0     1 (0.50)", "  M1            -", "  M2     2 (1.00)"]
    assert "  M2     0.04 (1.00)" in text
    assert "not.there" not in text
    assert paper_findings(m) == []  # no D_II, no 3B stress: the paper's findings cannot be judged


def test_findings_on_a_made_up_matrix():
    values = {"D_0": {"M0": (0.05, 0.01), "M1": (0.1, 0.1), "M2": (0.095, 0.098)},
              "D_II": {"M0": (0.23, 0.046), "M1": (0.46, 0.46), "M2": (0.25, 0.1)}}
    docs = []
    for level, models in values.items():
        for model, (s1, b3) in models.items():
            d = _doc(model, "r", level)
            d["metrics"] = {"stress_dynamic.S1": {"value": s1, "time": 0, "at": None},
                            "stress_dynamic.3B": {"value": b3, "time": 0, "at": None},
                            "friction_ratio.3B": {"value": 0.04 if model == "M2" else 0.0, "time": 0, "at": None}}
            docs.append(d)
    m = collect_matrices(docs, ["M0", "M1", "M2"], ["r"], ["D_0", "D_II"], "M2")
    findings = paper_findings(m)
    assert len(findings) == 8 and all(f.holds for f in findings), findings
    broken = attrs.evolve(m, values={**m.values, "stress_dynamic.3B": {**m.values["stress_dynamic.3B"],
                                                                       "M0": {"D_0": 0.05, "D_II": 0.23}}})
    failing = [f.statement for f in paper_findings(broken) if f.holds is False]
    assert failing == ["D_0, 3B: M0 below 0.3 x M1"]


def test_digests_follow_the_inputs_and_not_the_names(tmp_path):
    base = load_experiment(write_tiny(tmp_path / "a", models=("M1", "M2"), levels=("D_0",)))
    again = {j.id: j.digest for j in plan_cells(base)}
    assert again == {j.id: j.digest for j in plan_cells(base)}  # stable
    text = write_tiny(tmp_path / "b", models=("M1", "M2"), levels=("D_0",)).read_text()
    changed = tmp_path / "b" / "changed.toml"
    changed.write_text(text.replace('preset = "M2"', 'preset = "M2"\nfriction = 0.05'))
    digests = {j.id: j.digest for j in plan_cells(load_experiment(changed))}
    assert digests["M1/tremor/D_0"] == again["M1/tremor/D_0"] and digests["M2/tremor/D_0"] != again["M2/tremor/D_0"]
    renamed = tmp_path / "b" / "renamed.toml"
    renamed.write_text(text.replace("[models.M2]", "[models.friction]").replace('compare = ["M1", "M2"]', ""))
    digests = {j.id: j.digest for j in plan_cells(load_experiment(renamed))}
    assert digests["friction/tremor/D_0"] == again["M2/tremor/D_0"]
    settings = tmp_path / "b" / "settings.toml"
    settings.write_text(text.replace("dt_integration = 0.01", "dt_integration = 0.005"))
    assert all(d != again[i] for i, d in {j.id: j.digest for j in plan_cells(load_experiment(settings))}.items())


def test_the_default_study_plans_five_models_times_five_levels():
    from bearingfw.experiment import default_experiment

    jobs = plan_cells(default_experiment())
    assert len(jobs) == 25 and len({j.digest for j in jobs}) == 25
    assert jobs[0].id == "M0/tremor/D_0" and jobs[-1].id == "bouc-wen/tremor/D_IV"
    assert jobs[0].inputs["intensity"] == {"name": "D_0", "pga_h10": pytest.approx(0.1), "level": "D_0", "scale": None}
