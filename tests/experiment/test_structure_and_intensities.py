"""The experiment on a user's structure: ``run --structure/--option``, tables and figures that default to
what the structure has, and intensities as scale targets (as recorded, PGA, Sa at the first mode)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from tiny_experiment import EXAMPLE, HERE, write_tiny

from bearingfw.analysis import solve_modal
from bearingfw.cli.main import main
from bearingfw.experiment import check_experiment, load_experiment, parse_experiment, plan_cells
from bearingfw.experiment.execute import _scaled_record
from bearingfw.experiment.runner import figure_plan
from bearingfw.experiment.structure import structure_model
from bearingfw.model import as_system
from bearingfw.motion import horizontal_sa

USER = """\
name = "mine"
python_path = ["EXAMPLE"]

[structure]
builder = "small_bridge:build"
options = { elements_per_span = 4 }
ELEMENTS

[models.springs]
preset = "M1"
[models.friction]
law = "regularized-coulomb"
params = { k = 4e8, mu = 0.05 }

[records.tremor]
seed = 1
tremor = { duration = 10.0, dt = 0.01, decay = 2.0 }

[intensities]
INTENSITIES

[integration]
dt_integration = 0.01
""".replace("EXAMPLE", EXAMPLE.as_posix())


def _text(elements='elements = ["G2", "G4"]\ndeck_nodes = ["G2"]', intensities='levels = ["D_0"]') -> str:
    return USER.replace("ELEMENTS", elements).replace("INTENSITIES", intensities)


def _user(tmp_path, **parts):
    path = tmp_path / "mine.toml"
    path.write_text(_text(**parts))
    return load_experiment(path)


def test_tables_and_figures_default_to_what_the_structure_has(tmp_path):
    experiment = _user(tmp_path)
    checked = check_experiment(experiment)
    assert checked.bearings == ("1A", "1B", "2B", "3A", "3B")  # every connector that is not JOIN
    assert checked.table == ("stress.G2", "stress.G4", "stress_dynamic.G2", "stress_dynamic.G4", "bearing_force.1A",
                             "slip.1A", "friction_ratio.1A", "deck_acceleration.x", "deck_acceleration.y",
                             "deck_acceleration.z")
    plan = figure_plan(experiment, checked, None)
    assert plan["elements"] == ("G2", "G4") and plan["bearing"] == "1A" and plan["compare"] == ("springs", "friction")
    assert plan["mu"] == {"springs": None, "friction": 0.05}  # the friction figure: laws with a coefficient
    bare = check_experiment(_user(tmp_path, elements=""))  # no elements, no deck nodes: no such metrics
    assert bare.table == ("bearing_force.1A", "slip.1A", "friction_ratio.1A")
    assert figure_plan(_user(tmp_path, elements=""), bare, None)["elements"] == ()
    assert experiment.reference_model == "springs"  # the first model, whatever its name


def test_the_default_damping_is_two_percent_at_the_structures_first_two_frequencies(tmp_path):
    experiment = _user(tmp_path)
    checked = check_experiment(experiment)
    modal = solve_modal(as_system(structure_model(experiment), checked.registry), 2)
    w1, w2 = 2 * np.pi * modal.frequencies[:2]
    # zeta(w) = alpha / (2 w) + beta w / 2 = 0.02 at w1 and w2, by hand
    beta = 2 * 0.02 / (w1 + w2)
    alpha = beta * w1 * w2
    assert checked.rayleigh.alpha == pytest.approx(alpha, rel=1e-9)
    assert checked.rayleigh.beta == pytest.approx(beta, rel=1e-9)
    assert plan_cells(experiment)[0].inputs["damping"] == {"alpha": checked.rayleigh.alpha,
                                                           "beta": checked.rayleigh.beta}


def test_as_recorded_pga_and_sa_at_the_first_mode_scale_as_computed_by_hand(tmp_path):
    experiment = _user(tmp_path, intensities='levels = ["as-recorded"]\npga = [0.3]\nsa = [0.5]\nperiod = "T1"')
    checked = check_experiment(experiment)
    assert [i.name for i in checked.intensities] == ["as-recorded", "pga=0.3", "sa=0.5@T1"]
    t1 = 1.0 / solve_modal(as_system(structure_model(experiment), checked.registry), 1).frequencies[0]
    jobs = {j.intensity.name: j for j in plan_cells(experiment, checked.registry, checked.models,
                                                    (checked.intensities, checked.rayleigh)) if j.model == "springs"}
    assert jobs["sa=0.5@T1"].intensity.target.period == pytest.approx(t1, rel=1e-12)
    assert jobs["sa=0.5@T1"].inputs["intensity"]["target"]["period"] == pytest.approx(t1, rel=1e-12)
    raw = checked.records["tremor"]  # dt 0.01 = the integration step: no resampling
    h1, h2 = raw.h1, raw.h2
    expected = {"as-recorded": 1.0, "pga=0.3": 0.3 / np.max(np.sqrt(h1**2 + h2**2)),
                "sa=0.5@T1": 0.5 / horizontal_sa(raw, t1)}
    for name, factor in expected.items():
        record, ag, measures = _scaled_record(jobs[name], checked.registry)
        assert measures["scale_factor"] == pytest.approx(factor, rel=1e-12), name
        np.testing.assert_allclose(ag, factor * np.column_stack([h1, h2, raw.v]), rtol=1e-12, atol=0)
    # Sa itself, independently: the peak pseudo-acceleration of a 5 % oscillator at T1 in each
    # horizontal (the geometric mean of the two), against the scaled record's own
    scaled, _, _ = _scaled_record(jobs["sa=0.5@T1"], checked.registry)
    assert horizontal_sa(scaled, t1) == pytest.approx(0.5, rel=1e-9)


def test_the_first_mode_period_of_sa_is_refused_when_the_structure_has_none(tmp_path):
    from bearingfw.experiment import SpecError

    text = (tmp_path / "x").with_suffix(".toml")
    text.write_text(_text(elements="", intensities='sa = [0.5]\nperiod = "T1"').replace(
        'builder = "small_bridge:build"', 'builder = "no_modes:build"'))
    (tmp_path / "no_modes.py").write_text("def build(**options):\n    raise ValueError('not today')\n")
    with pytest.raises(SpecError, match="structure: structure 'no_modes:build': calling the builder failed"):
        check_experiment(load_experiment(text))


def test_run_takes_a_structure_and_options_from_the_command_line(tmp_path, capsys):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    out = tmp_path / "out"
    argv = ["run", str(spec), "--out", str(out), "--executor", "serial", "--no-figures", "--json",
            "--structure", f"{EXAMPLE.relative_to(HERE.parents[1]).as_posix()}/small_bridge.py:build",
            "--option", "elements_per_span=4", "--option", "span=20"]
    import os

    cwd = os.getcwd()
    os.chdir(HERE.parents[1])  # the file is named relative to here
    try:
        code = main(argv)
    finally:
        os.chdir(cwd)
    summary = json.loads(capsys.readouterr().out)
    assert code == 0 and summary["experiment"] == "tiny+small_bridge.build" and summary["failed"] == []
    document = json.loads((out / "cells" / "M1" / "tremor" / "D_0.json").read_text())
    structure = document["inputs"]["structure"]
    assert structure["builder"] == f"{(EXAMPLE / 'small_bridge.py').resolve()}:build"
    assert structure["options"] == {"elements_per_span": 4, "span": 20} and structure["elements"] is None
    matrices = json.loads((out / "matrices.json").read_text())
    assert not any(m.startswith("stress") for m in matrices)  # the file's elements were its own structure's
    assert "bearing_force.1A" in matrices  # the table defaults to what this structure has
    # --option alone adds to the file's options, keeping the rest of its [structure]
    code = main(["run", str(spec), "--out", str(tmp_path / "o2"), "--executor", "serial", "--no-figures", "--json",
                 "--option", "span=30", "--only", "M1", "--levels", "D_0"])
    summary = json.loads(capsys.readouterr().out)
    document = json.loads((tmp_path / "o2" / "cells" / "M1" / "tremor" / "D_0.json").read_text())
    assert code == 0 and document["inputs"]["structure"]["options"] == {"elements_per_span": 4, "span": 30}
    assert summary["experiment"] == "tiny" and document["inputs"]["structure"]["elements"] == ["G2", "G4"]


def test_run_refuses_a_structure_that_cannot_be_had(tmp_path, capsys):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    code = main(["run", str(spec), "--out", str(tmp_path / "out"), "--structure", str(tmp_path / "nope.py") + ":build"])
    err = capsys.readouterr().err
    assert code == 2 and "structure.builder: structure " in err and "nope.py" in err and "not found" in err
    code = main(["run", str(spec), "--out", str(tmp_path / "out"), "--option", "spam=1"])
    err = capsys.readouterr().err
    assert code == 2 and "structure.options: structure 'small_bridge:build': unknown option 'spam'" in err
    assert not parse_experiment(_text()).findings
