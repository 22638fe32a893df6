"""What the commands print is what they promise: ``run --json`` leaves the JSON alone on stdout even
when the study's own code prints, and ``modal`` on a structure with fewer massive DOFs than the
default 20 modes says which option to change (both found by an adversarial review)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

from tiny_experiment import write_tiny

from bearingfw.cli.main import main

PRINTING_BUILDER = """
from small_bridge import build as _build

def build(**options):
    print("hello from the builder")  # a user's debugging print
    return _build(**options)
"""

ONE_MASS = """
from bearingfw.model import Connector, Model, NodalMass, Node, Support

def build():
    return Model(
        nodes=[Node("G", 0.0, 0.0, 0.0), Node("D", 0.0, 0.0, 0.0)],
        connectors=[Connector("B", "G", "D", "planar", law="linear-spring", law_params={"k": 4e6},
                              vertical_stiffness=1e10)],
        supports=[Support("G"), Support("D", ("rx", "ry", "rz"))],
        masses=[NodalMass("D", 1e5)],
        name="one-mass",
    )
"""


def _printing_study(tmp_path):
    (tmp_path / "printing_bridge.py").write_text(textwrap.dedent(PRINTING_BUILDER))
    return write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",),
                      **{'builder = "small_bridge:build"': 'builder = "printing_bridge:build"',
                         'python_path = [': f'python_path = ["{tmp_path.as_posix()}", '})


def test_json_stays_alone_on_stdout_when_the_builder_prints(capsys, tmp_path):
    spec = _printing_study(tmp_path)
    code = main(["run", str(spec), "--out", str(tmp_path / "out"), "--executor", "serial", "--json", "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0 and json.loads(out)["exit_code"] == 0
    assert "hello from the builder" in err


def test_json_stays_alone_on_stdout_also_from_worker_processes(tmp_path):
    spec = _printing_study(tmp_path)
    done = subprocess.run(
        [sys.executable, "-m", "bearingfw", "run", str(spec), "--out", str(tmp_path / "out"), "--executor",
         "processes", "--workers", "1", "--json", "--quiet"],
        capture_output=True, text=True, timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["exit_code"] == 0  # nothing but the JSON
    assert "hello from the builder" in done.stderr


def test_modal_with_more_modes_than_the_structure_has_names_the_option(capsys, tmp_path):
    (tmp_path / "one_mass.py").write_text(textwrap.dedent(ONE_MASS))
    code = main(["modal", "--structure", f"{tmp_path / 'one_mass.py'}:build"])
    _, err = capsys.readouterr()
    assert code == 2
    assert "--modes 20 (the default is 20) is more than this structure has: it has 3 DOFs with mass" in err
    assert main(["modal", "--structure", f"{tmp_path / 'one_mass.py'}:build", "--modes", "3"]) == 0
