"""Findings as data: ``[[findings]]`` of a user's file, each test on hand-made matrices, the errors that
name the key, and a run that checks and reports them as it does the built-in study's."""

from __future__ import annotations

import math

import pytest
from tiny_experiment import tiny_toml, write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment import (
    Matrices,
    SerialExecutor,
    SpecError,
    check_experiment,
    check_findings,
    load_experiment,
    parse_experiment,
    run_experiment,
)

BASE = 'name = "x"\n[models.A]\npreset = "M0"\n[models.B]\npreset = "M1"\n[records.r]\nseed = 0\n' \
       '[intensities]\nlevels = ["D_0", "D_II"]\n'

#: stress_dynamic.E: A = 1, 2 and B = 4, 8 at D_0, D_II (ratio A/B 0.25 at both); slip.E of B NaN at D_II.
VALUES = {"stress_dynamic.E": {"A": {"D_0": 1.0, "D_II": 2.0}, "B": {"D_0": 4.0, "D_II": 8.0}},
          "slip.E": {"A": {"D_0": 0.04, "D_II": 0.0400001}, "B": {"D_0": 0.0, "D_II": math.nan}}}
MATRICES = Matrices(tuple(VALUES), ("A", "B"), ("D_0", "D_II"), "B", VALUES)


def _findings(*tables: str):
    text = BASE + "".join("[[findings]]\n" + t + "\n" for t in tables)
    return check_findings(parse_experiment(text).findings, MATRICES)


@pytest.mark.parametrize(
    ("table", "holds", "measured"),
    [
        ('metric = "stress_dynamic.E"\nlevel = "D_0"\nmodels = ["A", "B"]\nwithin = 0.75', [True], "A/B = 0.250"),
        ('metric = "stress_dynamic.E"\nlevel = "D_0"\nmodels = ["A", "B"]\nwithin = 0.7', [False], "A/B = 0.250"),
        ('metric = "stress_dynamic.E"\nlevel = "D_0"\nmodels = ["A", "B"]\nbelow = 0.25', [False], "A/B = 0.250"),
        ('metric = "stress_dynamic.E"\nlevel = "D_0"\nmodels = ["B", "A"]\nabove = 3.99', [True], "B/A = 4.000"),
        ('metric = "stress_dynamic.E"\nlevel = ["D_0", "D_II"]\nmodel = "A"\nbelow = 1.5', [True, False], None),
        ('metric = "slip.E"\nlevel = ["D_0", "D_II"]\nmodel = "A"\nequals = 0.04', [True, False], None),
        ('metric = "slip.E"\nlevel = "D_II"\nmodel = "A"\nequals = 0.04\ntolerance = 1e-5', [True], None),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "B"\nequals = 0.0\ntolerance = 1e-9', [True], None),
        ('metric = "slip.E"\nlevel = "D_II"\nmodel = "B"\nabove = 0.0', [None], "slip.E of B = nan"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodels = ["A", "B"]\nbelow = 1.0', [None], "A/B = nan"),
        ('metric = "stress_dynamic.E"\nlevel = ["D_0", "D_II"]\nmodels = ["A", "B"]\nsame = 1e-12', [True],
         "0.250000 and 0.250000"),
        ('metric = "stress_dynamic.E"\nlevel = ["D_0", "D_II"]\nmodel = "A"\nsame = 0.5', [False],
         "1.000000 and 2.000000"),
    ],
)
def test_each_test_on_hand_made_matrices(table, holds, measured):
    findings = _findings(table)
    assert [f.holds for f in findings] == holds
    if measured is not None:
        assert findings[0].measured == measured


def test_statements_name_their_level_and_group():
    named, written = _findings(
        'name = "{level}: A caps its slip"\nmetric = "slip.E"\nlevel = ["D_0", "D_II"]\nmodel = "A"\nbelow = 1.0\n'
        'group = "Mine"',
        'metric = "stress_dynamic.E"\nlevel = "D_II"\nmodels = ["A", "B"]\nbelow = 0.3',
    )[1:]
    assert (named.statement, named.group) == ("D_II: A caps its slip", "Mine")
    assert (written.statement, written.group) == ("D_II, stress_dynamic.E: A below 0.3 x B", "Findings")
    assert written.holds is True and written.measured == "A/B = 0.250"


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        ('metric = "x"\nlevel = "D_0"\nmodel = "A"\nbelow = 1', "findings[1].metric: field 'metric' must be 'family.item'"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "A"', "findings[1]: give exactly one test of within, below, above"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "A"\nbelow = 1\nabove = 0', "got below, above"),
        ('metric = "slip.E"\nlevel = "D_0"\nbelow = 1', "findings[1]: give 'models' = [A, B] (the ratio A/B)"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodels = ["A", "A"]\nbelow = 1', "two different model names"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "C"\nbelow = 1',
         "findings[1].model: 'C' is not in the experiment; it has A, B"),
        ('metric = "slip.E"\nlevel = "D_IV"\nmodel = "A"\nbelow = 1',
         "findings[1].level: 'D_IV' is not in the experiment; it has D_0, D_II"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "A"\nsame = 0.1', "'same' compares levels"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "A"\nbelow = 1\ntolerance = 0.1', "'tolerance' goes with 'equals'"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "A"\nwithin = -0.1', "findings[1].within: parameter 'within'"),
        ('metric = "slip.E"\nlevel = "D_0"\nmodel = "A"\nbelow = 1\ncolour = 2',
         "findings[1].colour: unknown key; allowed in [findings[1]]: metric, level, models, model"),
    ],
)
def test_a_bad_finding_is_an_error_naming_its_key(table, expected):
    with pytest.raises(SpecError) as caught:
        parse_experiment(BASE + "[[findings]]\n" + table + "\n", origin="f.toml")
    assert expected in str(caught.value)


def test_a_finding_on_a_metric_the_structure_lacks_is_refused_before_running(tmp_path):
    extra = '[[findings]]\nmetric = "stress_dynamic.G9"\nlevel = "D_0"\nmodels = ["M1", "M2"]\nwithin = 0.1\n'
    with pytest.raises(SpecError, match=r"findings\[1\].metric: 'stress_dynamic.G9': 'G9' is not recorded; "
                                        r"stress_dynamic has G2, G4"):
        check_experiment(load_experiment(write_tiny(tmp_path, models=("M1", "M2"), levels=("D_0",), extra=extra)))


USER_FINDINGS = """
[[findings]]
name = "D_0, G4: friction and springs within 50 %"
metric = "stress_dynamic.G4"
level = "D_0"
models = ["M2", "M1"]
within = 0.5
group = "My findings"

[[findings]]
name = "{level}: M1 scales with the record"
metric = "stress_dynamic.G4"
level = ["D_0", "D_II"]
model = "M1"
above = 0.0
group = "My findings"

[[findings]]
metric = "friction_ratio.1B"
level = "D_II"
model = "M2"
equals = 0.04
"""


def test_a_run_checks_and_reports_the_users_findings(tmp_path, capsys):
    spec = write_tiny(tmp_path / "spec", models=("M1", "M2"), levels=("D_0", "D_II"), extra=USER_FINDINGS)
    out = tmp_path / "out"
    code = main(["run", str(spec), "--out", str(out), "--executor", "serial", "--no-figures"])
    printed = capsys.readouterr().out
    assert code == 0
    summary = run_experiment(load_experiment(spec), out, SerialExecutor())  # nothing to compute: from the store
    assert summary.computed == ()
    statements = [(f.group, f.statement, f.holds) for f in summary.findings]
    assert statements == [
        ("My findings", "D_0, G4: friction and springs within 50 %", True),
        ("My findings", "D_0: M1 scales with the record", True),
        ("My findings", "D_II: M1 scales with the record", True),
        ("Findings", "D_II, friction_ratio.1B: M2 equals 0.04", True),  # the law caps abs(F)/N at mu
    ]
    ratio = summary.matrices.value("stress_dynamic.G4", "M2", "D_0") / summary.matrices.value(
        "stress_dynamic.G4", "M1", "D_0")
    assert summary.findings[0].measured == f"M2/M1 = {ratio:.3f}"
    assert "\nMy findings:\n  [yes] D_0, G4: friction and springs within 50 %: M2/M1 = " in printed
    assert "\nFindings:\n  [yes] D_II, friction_ratio.1B: M2 equals 0.04: friction_ratio.1B of M2 = 0.04" in printed
    report = (out / "report.md").read_text()
    assert "### My findings" in report and "| D_II: M1 scales with the record | stress_dynamic.G4 of M1 = " in report
    assert tiny_toml().count("[[findings]]") == 0  # the tiny experiment itself declares none
