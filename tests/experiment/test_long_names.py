"""Names that become file names are refused before anything is written when too long for one
(a 300-character model name got as far as writing ``manifest.json``, then failed every cell)."""

from __future__ import annotations

import pytest

from bearingfw.cli.main import main
from bearingfw.experiment import SpecError, parse_experiment
from bearingfw.experiment.fields import NAME_LENGTH


def _study(model: str, record: str = "r") -> str:
    return f'name = "x"\n[models.{model}]\npreset = "M2"\n[records.{record}]\nseed = 0\n'


@pytest.mark.parametrize("where", ["model", "record"])
def test_a_name_of_the_longest_length_is_taken_and_one_more_character_is_refused(where):
    longest, too_long = "M" + "x" * (NAME_LENGTH - 1), "M" + "x" * NAME_LENGTH
    text = _study(longest) if where == "model" else _study("M2", longest)
    parse_experiment(text, origin="exp.toml")
    with pytest.raises(SpecError, match=f"at most {NAME_LENGTH} letters"):
        parse_experiment(_study(too_long) if where == "model" else _study("M2", too_long), origin="exp.toml")


def test_a_run_with_a_300_character_model_name_writes_nothing(tmp_path, capsys):
    study = tmp_path / "long.toml"
    study.write_text(_study("M" + "x" * 299))
    out = tmp_path / "out"
    assert main(["run", str(study), "--out", str(out), "--figures", "none", "--quiet"]) == 2
    assert not out.exists()
    assert f"at most {NAME_LENGTH} letters" in capsys.readouterr().err
