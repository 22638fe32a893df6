"""``bearingfw run`` through the CLI's entry point: --print-default, errors, --json, --only/--levels."""

from __future__ import annotations

import json

from tiny_experiment import write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment import DEFAULT_TOML, parse_experiment


def run(capsys, *argv):
    code = main(["run", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_print_default_prints_the_built_in_experiment(capsys):
    code, out, _ = run(capsys, "--print-default")
    assert code == 0 and out == DEFAULT_TOML
    assert parse_experiment(out).model_names == ("M0", "M1", "M2", "fixed", "bouc-wen")


def test_a_bad_file_exits_2_with_the_key_path(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('name = "x"\n[models.M2]\npreset = "M2"\nmu = 0.1\n[records.r]\nseed = 0\n')
    code, out, err = run(capsys, str(path), "--out", str(tmp_path / "out"))
    assert code == 2 and out == ""
    assert err.startswith(f"bearingfw run: error: {path}: models.M2.mu: unknown key; allowed in [models.M2]: preset")
    code, _, err = run(capsys, str(tmp_path / "missing.toml"))
    assert code == 2 and "cannot read the experiment file" in err
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    code, _, err = run(capsys, str(spec), "--out", str(tmp_path / "o"), "--reference", "M7")
    assert code == 2 and "--reference: reference: 'M7' is not a model; models: M1" in err
    code, _, err = run(capsys, str(spec), "--out", str(tmp_path / "o"), "--only", "M7")
    assert code == 2 and "--only: 'M7' is not in the experiment; it has M1" in err
    code, _, err = run(capsys, str(spec), "--out", str(tmp_path / "o"), "--scheduler", "tcp://x:1", "--executor",
                       "serial")
    assert code == 2 and "a scheduler address is for the dask executor" in err


def test_json_summary_tables_and_a_partial_run(capsys, tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1", "M2"), levels=("D_0", "D_II"))
    out = tmp_path / "out"
    code, stdout, stderr = run(capsys, str(spec), "--out", str(out), "--executor", "serial", "--only", "M2",
                               "--levels", "D_II", "--json")
    assert code == 0
    data = json.loads(stdout)
    assert data["computed"] == ["M2/tremor/D_II"] and data["exit_code"] == 0 and data["failed"] == []
    assert sorted(data["missing"]) == ["M1/tremor/D_0", "M1/tremor/D_II", "M2/tremor/D_0"]
    assert data["files"]["matrices.json"] == str(out / "matrices.json") and data["files"]["report.md"].endswith("report.md")
    assert data["files"]["matrices"] == str(out / "matrices")  # the folder of CSVs
    assert "[1/1] M2/tremor/D_II ok" in stderr  # the progress goes to stderr
    assert "stress.G4 [MPa]  (ratio to M1)" in stderr  # with --json, the tables too
    code, stdout, stderr = run(capsys, str(spec), "--out", str(out), "--executor", "serial", "--quiet")
    assert code == 0 and stderr == "" and stdout == ""
    matrices = json.loads((out / "matrices.json").read_text())
    assert all(v is not None for v in matrices["stress.G4"]["M1"].values())
    code, stdout, _ = run(capsys, str(spec), "--out", str(out), "--executor", "serial", "--no-figures")
    assert code == 0
    assert "stress.G4 [MPa]  (ratio to M1)" in stdout and "friction_ratio.1B [-]" in stdout
    assert f"results: {out}" in stdout


def test_a_directory_of_another_experiment_exits_2_unless_taken_over(capsys, tmp_path):
    out = tmp_path / "out"
    first = write_tiny(tmp_path / "a", name="first", models=("M1",), levels=("D_0",))
    second = write_tiny(tmp_path / "b", name="second", models=("M1",), levels=("D_0",))
    assert run(capsys, str(first), "--out", str(out), "--executor", "serial", "--quiet")[0] == 0
    code, stdout, stderr = run(capsys, str(second), "--out", str(out), "--executor", "serial")
    assert code == 2 and stdout == ""
    assert stderr.startswith(f"bearingfw run: error: {out} holds the results of experiment 'first', not 'second'")
    code, stdout, _ = run(capsys, str(second), "--out", str(out), "--executor", "serial", "--take-over", "--json")
    assert code == 0 and json.loads(stdout)["skipped"] == ["M1/tremor/D_0"]  # the same computation


def test_a_directory_in_use_exits_2_naming_the_holder(capsys, tmp_path):
    import os

    from bearingfw.experiment import Store

    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    out = tmp_path / "out"
    with Store(out).claim("tiny"):
        code, _, stderr = run(capsys, str(spec), "--out", str(out), "--executor", "serial")
    assert code == 2
    assert stderr.startswith(f"bearingfw run: error: {out} is in use by another bearingfw run (pid {os.getpid()} ")


def test_json_into_a_closed_pipe_ends_quietly(tmp_path):
    """``bearingfw run ... --json | head``: the reader leaves before the summary is printed."""
    import subprocess
    import sys

    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    process = subprocess.Popen(
        [sys.executable, "-m", "bearingfw", "run", str(spec), "--out", str(tmp_path / "out"), "--executor", "serial",
         "--quiet", "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )
    process.stdout.close()  # the reader is gone before anything is written
    _, stderr = process.communicate(timeout=300)
    assert process.returncode == 141, stderr.decode()
    assert b"Traceback" not in stderr and b"BrokenPipe" not in stderr and stderr == b""
