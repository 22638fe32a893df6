"""A finding that does not hold says why, with the run's own numbers (bearings that slid, the friction
ratio they slid at against what the spring model asks, the ratio elsewhere); one that holds says nothing."""

from __future__ import annotations

import math
import re

import pytest

from bearingfw.experiment import Matrices, check_findings, parse_experiment
from bearingfw.experiment.findings import Finding
from bearingfw.experiment.report import _findings

BASE = ('name = "x"\n[models.F]\npreset = "M2"\n[models.S]\npreset = "M1"\n[records.r]\nseed = 0\n'
        '[intensities]\nlevels = ["D_0", "D_II"]\n')

NAN = math.nan
#: F: friction (b1 slid 0.3 mm at its cap 0.05, b2 stuck at 0.02); S: springs (no slip: NaN), b1 asks 0.2.
VALUES = {
    "stress_dynamic.E": {"F": {"D_0": 6.0, "D_II": 9.0}, "S": {"D_0": 10.0, "D_II": 30.0}},
    "stress_dynamic.G": {"F": {"D_0": 9.0, "D_II": 9.0}, "S": {"D_0": 10.0, "D_II": 10.0}},
    "slip.b1": {"F": {"D_0": 3e-4, "D_II": 2e-3}, "S": {"D_0": NAN, "D_II": NAN}},
    "slip.b2": {"F": {"D_0": 0.0, "D_II": 1e-3}, "S": {"D_0": NAN, "D_II": NAN}},
    "friction_ratio.b1": {"F": {"D_0": 0.05, "D_II": 0.05}, "S": {"D_0": 0.2, "D_II": 0.6}},
    "friction_ratio.b2": {"F": {"D_0": 0.02, "D_II": 0.05}, "S": {"D_0": 0.03, "D_II": 0.09}},
    "deck_acceleration.y": {"F": {"D_0": 0.5, "D_II": 1.0}, "S": {"D_0": 1.0, "D_II": 2.0}},
}
MATRICES = Matrices(tuple(VALUES), ("F", "S"), ("D_0", "D_II"), "F", VALUES)


def _check(*tables: str):
    text = BASE + "".join("[[findings]]\n" + t + "\n" for t in tables)
    return check_findings(parse_experiment(text).findings, MATRICES)


def _numbers(text: str) -> set[str]:
    return set(re.findall(r"\d+(?:\.\d+)?", text))


def test_a_failing_ratio_finding_names_the_bearings_that_slid_and_the_demand_against_the_cap():
    (f,) = _check('metric = "stress_dynamic.E"\nlevel = "D_0"\nmodels = ["F", "S"]\nwithin = 0.15')
    assert f.holds is False and f.measured == "F/S = 0.600"
    why = f.explanation
    assert "F slid at 1 of 2 bearings at D_0 (b1: peak slip 0.30 mm, abs(F)/N at its cap 0.05)" in why
    assert "S (no slip) needs abs(F)/N above F's cap 0.05 at 1 bearing (b1 0.2)" in why
    assert "F/S of stress_dynamic at D_0 elsewhere: G 0.90" in why  # the departure is local to E
    assert "F/S of the peak deck_acceleration at D_0: y 0.50" in why
    assert "abs(x - 1) = 0.400 > 0.15" in why


def test_every_slid_bearing_at_a_stronger_level_and_a_spring_within_the_cap():
    (f,) = _check('metric = "stress_dynamic.E"\nlevel = "D_II"\nmodels = ["F", "S"]\nabove = 0.5')
    assert f.holds is False
    assert "F slid at 2 of 2 bearings at D_II (b1, b2: peak slip 1.00-2.00 mm" in f.explanation
    assert "(b1 0.6, b2 0.09)" in f.explanation  # the largest demand first


def test_a_failing_value_finding_says_whether_the_bearing_slid():
    (f,) = _check('metric = "friction_ratio.b2"\nlevel = "D_0"\nmodel = "F"\nequals = 0.05')
    assert f.holds is False
    assert "0.02 != 0.05" in f.explanation and "b2 of F did not slide (it stuck) at D_0" in f.explanation


def test_a_failing_same_finding_gives_the_spread():
    (f,) = _check('metric = "stress_dynamic.E"\nlevel = ["D_0", "D_II"]\nmodels = ["F", "S"]\nsame = 0.01')
    assert f.holds is False and "F/S varies by 100.00% across D_0, D_II" in f.explanation


def test_findings_that_hold_or_cannot_be_judged_carry_no_explanation():
    held, unknown = _check('metric = "stress_dynamic.E"\nlevel = "D_0"\nmodels = ["F", "S"]\nbelow = 0.7',
                           'metric = "slip.b1"\nlevel = "D_0"\nmodel = "S"\nabove = 0.0')
    assert held.holds is True and held.explanation == ""
    assert unknown.holds is None and unknown.explanation == ""


def test_the_report_shows_the_explanation_column_only_when_one_is_given():
    plain = _findings([Finding("s", "A/B = 1.000", True, "G")])
    assert "| finding | this run | holds |" in plain and "why not" not in "\n".join(plain)
    failing = _findings([Finding("s", "A/B = 0.500", False, "G", "A slid at 3 of 4 bearings")])
    assert "| s | A/B = 0.500 | **no** | A slid at 3 of 4 bearings |" in failing


def test_the_default_studys_failing_findings_are_explained_with_the_runs_numbers():
    """On the reference matrices of the default study (no run needed): every failing finding has an explanation
    whose numbers are the matrices' (the reference keeps bearing 3B's metrics only: M1 asks abs(F)/N = 0.0489 of
    it at D_0, above M2's cap 0.04, and M2 slid there)."""
    from test_default_study import _reference_matrices

    from bearingfw.experiment import default_experiment

    findings = check_findings(default_experiment().findings, _reference_matrices())
    failing = [f for f in findings if f.holds is False]
    assert failing and all(f.explanation and _numbers(f.explanation) for f in failing)
    sticking = next(f for f in failing if f.statement == "D_0, S1: M1 and M2 within 15 %")
    assert "M2 slid at 1 of 1 bearing at D_0 (3B: peak slip 0.02 mm, abs(F)/N at its cap 0.04)" in sticking.explanation
    assert "M1 (no slip) needs abs(F)/N above M2's cap 0.04 at 1 bearing (3B 0.0489)" in sticking.explanation
    assert all(f.explanation == "" for f in findings if f.holds is not False)


@pytest.mark.parametrize("field", ["explanation"])
def test_the_summary_json_carries_the_explanation(field):
    import attrs

    assert field in attrs.asdict(Finding("s", "m", False, "G", "why"))
