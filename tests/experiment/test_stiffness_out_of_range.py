"""A bearing stiffness no solve can take is bad input: refused before any cell runs, naming the
model (exit 2), not a failure of every cell (exit 1), as an adversarial review found."""

from __future__ import annotations

from tiny_experiment import write_tiny

from bearingfw.cli.main import main


def test_an_absurd_stiffness_is_refused_naming_the_model(capsys, tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1", "M2"), levels=("D_0",),
                      **{'[models.M1]\npreset = "M1"': '[models.M1]\npreset = "M1"\nks = 1e30'})
    out = tmp_path / "out"
    code = main(["run", str(spec), "--out", str(out), "--executor", "serial"])
    _, err = capsys.readouterr()
    assert code == 2
    assert "models.M1: law 'linear-spring' of the bearing" in err and "tangent stiffness 1e+30 N/m" in err
    assert not (out / "cells").exists()  # nothing was computed


def test_a_stiff_but_solvable_bearing_still_runs(capsys, tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",),
                      **{'[models.M1]\npreset = "M1"': '[models.M1]\npreset = "M1"\nks = 4e9'})
    assert main(["run", str(spec), "--out", str(tmp_path / "out"), "--executor", "serial", "--quiet"]) == 0
