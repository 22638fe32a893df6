"""Named support groups of a spatially varying record are checked against the structure before any
cell runs (exit 2, naming records.<name>.spatial.groups); they were checked inside every cell, which
then failed (exit 1) with the kernel's words, as an adversarial review found."""

from __future__ import annotations

import pytest
from tiny_experiment import write_tiny

from bearingfw.cli.main import main

FULL = '{ west = ["1A.seat", "1B.seat"], pier = ["P0"], east = ["3A.seat", "3B.seat"] }'


def _study(tmp_path, groups: str):
    text = f"[records.tremor.spatial]\ngroups = {groups}\napparent_velocity = 500.0\n\n[intensities]"
    return write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",), **{"[intensities]": text})


@pytest.mark.parametrize(("groups", "problem"), [
    ('{ west = ["NOPE"], rest = ["1A.seat", "1B.seat", "P0", "3A.seat", "3B.seat"] }', "name unknown nodes ['NOPE']"),
    ('{ west = ["1A.seat", "1B.seat"], east = ["3A.seat", "3B.seat"] }', "leave supported nodes ['P0'] in no group"),
])
def test_groups_that_do_not_fit_the_structure_are_refused_before_any_cell(capsys, tmp_path, groups, problem):
    out = tmp_path / "out"
    code = main(["run", str(_study(tmp_path, groups)), "--out", str(out), "--executor", "serial"])
    _, err = capsys.readouterr()
    assert code == 2
    assert f"records.tremor.spatial.groups: support groups {problem}" in err
    assert not (out / "cells").exists()


def test_groups_that_fit_run(tmp_path):
    code = main(["run", str(_study(tmp_path, FULL)), "--out", str(tmp_path / "out"), "--executor", "serial",
                 "--quiet", "--figures", "none"])
    assert code == 0
