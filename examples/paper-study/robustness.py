"""Where the paper's findings hold on bearingfw's reference bridge: per record, per finding (robustness.toml).

Runs the experiment (cells already in ``--out`` are kept), then checks the experiment's own
``[[findings]]`` on each record's matrices separately (the run's ``matrices.json`` combines the
records) with the same :func:`bearingfw.experiment.check_findings` the report uses, and prints

1. the findings table: one row per finding, one column per record, the measured ratio and
   whether it holds;
2. the stress ratios at D_0 (the issue's table): M2/M1 and M0/M1 at S1 and 3B per record.

    python examples/paper-study/robustness.py --out bearingfw-results/robustness
    python examples/paper-study/robustness.py --records seed0 seed1 --levels D_0 D_II   # a quick subset

``--json`` prints the tables as data. The test ``tests/examples/test_paper_robustness.py`` runs a
subset and checks the table against the findings of each record.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import attrs

HERE = Path(__file__).resolve().parent
EXPERIMENT = HERE / "robustness.toml"
#: The ratios of the issue's table: (element, numerator, denominator).
RATIOS = (("S1", "M2", "M1"), ("3B", "M2", "M1"), ("S1", "M0", "M1"), ("3B", "M0", "M1"))


def experiment_subset(path=EXPERIMENT, records=None, levels=None):
    """The experiment of ``path`` with only ``records`` and ``levels`` (default all); findings on other levels
    dropped (a per-level finding keeps its levels that remain)."""
    from bearingfw.experiment import load_experiment

    e = load_experiment(path)
    if records:
        unknown = set(records) - {r.name for r in e.records}
        if unknown:
            raise SystemExit(f"unknown record(s) {sorted(unknown)}; the experiment has {[r.name for r in e.records]}")
        e = attrs.evolve(e, records=tuple(r for r in e.records if r.name in records))
    if levels:
        kept = []
        for f in e.findings:
            present = tuple(level for level in f.level if level in levels)
            if present == f.level or (present and f.test != "same"):
                kept.append(attrs.evolve(f, level=present))
        e = attrs.evolve(e, intensities=attrs.evolve(e.intensities, levels=tuple(levels)), findings=tuple(kept))
    return e


def run(experiment, out, executor=None):
    """Run ``experiment`` into ``out`` (finished cells are kept) and return its summary."""
    from bearingfw.experiment import ProcessExecutor, run_experiment

    return run_experiment(experiment, out, executor or ProcessExecutor())


def record_matrices(experiment, out) -> dict:
    """``{record: Matrices}`` of each record's own finished cells (the documents under ``out/cells``)."""
    from bearingfw.experiment.matrices import collect_matrices

    documents = {}
    for path in sorted(Path(out, "cells").glob("*/*/*.json")):
        d = json.loads(path.read_text())
        documents.setdefault(d["record"], []).append(d)
    levels = [i.name for i in experiment.intensity_list]
    return {
        spec.name: collect_matrices(documents.get(spec.name, []), experiment.model_names, [spec.name], levels,
                                    experiment.reference_model, aggregate="max")
        for spec in experiment.records
    }


def per_record_findings(experiment, out) -> dict:
    """``{record: findings}``: the experiment's findings checked on each record's matrices."""
    from bearingfw.experiment import check_findings

    return {name: check_findings(experiment.findings, m) for name, m in record_matrices(experiment, out).items()}


def findings_table(per_record: dict) -> list[dict]:
    """One row per finding: ``{"finding": statement, record: {"measured", "holds"}, ...}``."""
    records = list(per_record)
    statements = [f.statement for f in next(iter(per_record.values()))] if per_record else []
    rows = []
    for k, statement in enumerate(statements):
        row = {"finding": statement}
        for r in records:
            f = per_record[r][k]
            row[r] = {"measured": f.measured, "holds": f.holds, "explanation": f.explanation}
        rows.append(row)
    return rows


def ratio_table(experiment, out, level: str = "D_0") -> dict:
    """``{record: {"S1 M2/M1": ratio, ...}}`` of ``stress_dynamic`` at ``level`` (NaN where a cell is missing)."""
    out_table = {}
    for name, m in record_matrices(experiment, out).items():
        row = {}
        for element, a, b in RATIOS:
            va, vb = (m.value(f"stress_dynamic.{element}", model, level) for model in (a, b))
            row[f"{element} {a}/{b}"] = va / vb if vb else float("nan")
        out_table[name] = row
    return out_table


def _short(measured: str) -> str:
    return measured.split("=")[-1].strip() if "=" in measured else measured


def markdown(rows: list[dict], ratios: dict, level: str = "D_0") -> str:
    records = [k for k in rows[0] if k != "finding"] if rows else list(ratios)
    mark = {True: "yes", False: "**no**", None: "n/a"}
    lines = ["| finding | " + " | ".join(records) + " |", "|---|" + "---|" * len(records)]
    for row in rows:
        lines.append(f"| {row['finding']} | " + " | ".join(
            f"{_short(row[r]['measured'])} {mark[row[r]['holds']]}" for r in records) + " |")
    names = [f"{e} {a}/{b}" for e, a, b in RATIOS]
    lines += ["", f"| record | level | " + " | ".join(names) + " |", "|---|---|" + "---:|" * len(names)]
    for record, row in ratios.items():
        lines.append(f"| {record} | {level} | " + " | ".join(f"{row[n]:.2f}" for n in names) + " |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--experiment", default=str(EXPERIMENT), help="the experiment file (default robustness.toml)")
    parser.add_argument("--out", default="bearingfw-results/paper-robustness", help="output folder")
    parser.add_argument("--records", nargs="*", help="run only these records (default all)")
    parser.add_argument("--levels", nargs="*", help="run only these intensity levels (default all)")
    parser.add_argument("--json", action="store_true", help="print the tables as JSON")
    args = parser.parse_args(argv)
    experiment = experiment_subset(args.experiment, args.records, args.levels)
    summary = run(experiment, args.out)
    rows = findings_table(per_record_findings(experiment, args.out))
    ratios = ratio_table(experiment, args.out)
    if args.json:
        print(json.dumps({"findings": rows, "ratios": ratios}, indent=2, default=str))
    else:
        print(markdown(rows, ratios))
    return summary.exit_code


if __name__ == "__main__":
    sys.exit(main())
