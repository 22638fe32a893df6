"""A study file saved as UTF-8 with a byte-order mark (Windows Notepad) is read like one without.
Before the fix it was refused: "not valid TOML: Invalid statement (at line 1, column 1)"."""

from __future__ import annotations

import pytest

from bearingfw.cli.main import main
from bearingfw.experiment.spec import SpecError, load_experiment, parse_experiment

STUDY = 'name = "bom"\n[models.M1]\npreset = "M1"\n[records.r]\nseed = 0\n[intensities]\nlevels = ["D_0"]\n'


def test_one_leading_bom_is_dropped(tmp_path):
    plain, marked = tmp_path / "plain.toml", tmp_path / "marked.toml"
    plain.write_bytes(STUDY.encode())
    marked.write_bytes(b"\xef\xbb\xbf" + STUDY.encode())
    with_bom, without = load_experiment(marked), load_experiment(plain)
    assert with_bom.name == "bom" and with_bom.model_names == without.model_names == ("M1",)
    assert with_bom.source == without.source == STUDY  # the copy kept with the results has no BOM
    assert parse_experiment("\ufeff" + STUDY).name == "bom"


def test_a_bom_inside_the_file_is_still_an_error(tmp_path):
    path = tmp_path / "twice.toml"
    path.write_bytes(b"\xef\xbb\xbf\xef\xbb\xbf" + STUDY.encode())  # only one mark is an encoding's
    with pytest.raises(SpecError, match="not valid TOML"):
        load_experiment(path)


def test_the_cli_checks_a_study_file_with_a_bom(tmp_path, capsys):
    path = tmp_path / "study.toml"
    path.write_bytes(b"\xef\xbb\xbf" + STUDY.replace('preset = "M1"', 'preset = "M7"').encode())
    code = main(["run", str(path), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    # Read past the mark: the error is the study's own (an unknown preset), at its key.
    assert code == 2 and "models.M7" not in err and "models.M1.preset" in err and "not valid TOML" not in err
