"""The built-in study (``bearingfw run`` with no file) and the paper's findings on it (slow: minutes).

Where this bridge departs from the paper, the finding is an expected failure with the reason
(strict: if the departure disappears, the test says so, and the explanation must be revisited).
"""

from __future__ import annotations

import json

import pytest

from bearingfw.experiment import ProcessExecutor, default_experiment, run_experiment

pytestmark = pytest.mark.slow

STICKING_AT_D0 = (
    "on this bridge M2 already slides at D_0: with springs (M1) the abutment bearings 1A/1B/6A/6B would need "
    "abs(F)/N = 0.11-0.20 and 4B 0.09 against mu = 0.04 (little dead load, 0.5-0.9 MN, on stiff seats), so M2 is "
    "softer than M1 (M2/M1 = 0.70 at S1, 0.55 at 3B); with those five bearings kept elastic it is 0.94 and 0.96"
)
VERTICAL_AT_3B = (
    "the synthetic tremor's vertical component (0.6 x PGA_H10, an assumption) bends the girder at 3B whatever the "
    "bearings do: M0/M1 = 0.44 at D_0 with it, about 0.32 without it, not the paper's tenth"
)
EXPECTED = {
    "D_0, S1: M1 and M2 within 15 %": STICKING_AT_D0,
    "D_0, 3B: M1 and M2 within 15 %": STICKING_AT_D0,
    "D_0, S1: M0 below 0.7 x M1": None,
    "D_0, 3B: M0 below 0.3 x M1": VERTICAL_AT_3B,
    "S1: M0/M1 the same under D_0 and D_II (linear models)": None,
    "3B: M0/M1 the same under D_0 and D_II (linear models)": None,
    "D_II, 3B: M2 below 0.7 x M1": None,
    "D_II: M2's maximum friction ratio at 3B equals mu = 0.04": None,
    "D_III: M2's maximum friction ratio at 3B equals mu = 0.04": None,
    "D_IV: M2's maximum friction ratio at 3B equals mu = 0.04": None,
}


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper-study")
    return out, run_experiment(default_experiment(), out, ProcessExecutor())


def test_the_default_run_completes_the_matrix_and_writes_everything(study):
    out, summary = study
    assert summary.exit_code == 0 and len(summary.computed) == 25
    matrices = json.loads((out / "matrices.json").read_text())
    assert list(matrices["stress.S1"]) == ["M0", "M1", "M2", "fixed", "bouc-wen"]
    assert list(matrices["stress.S1"]["M2"]) == ["D_0", "D_I", "D_II", "D_III", "D_IV"]
    assert all(v is not None for row in matrices["stress_dynamic.3B"].values() for v in row.values())
    assert (out / "report.md").stat().st_size > 10_000
    assert (out / "figures" / "stress_tremor_D_II.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    "statement",
    [pytest.param(s, marks=pytest.mark.xfail(strict=True, reason=r)) if r else s for s, r in EXPECTED.items()],
)
def test_the_papers_findings(study, statement):
    _, summary = study
    finding = next(f for f in summary.findings if f.statement == statement)
    assert finding.holds, f"{finding.statement}: {finding.measured}"
