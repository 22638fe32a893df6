"""Engine messages that say what is wrong: an intensity out of range names its key and range (not a
derived quantity), an OS error names the file, and warnings inside a cell are reported once in the
cell's document instead of leaking to stderr."""

from __future__ import annotations

import os
import warnings

import pytest
from tiny_experiment import tiny_toml, write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment import SerialExecutor, SpecError, Store, load_experiment, parse_experiment, run_experiment


@pytest.mark.parametrize("key", ["pga_h10", "pga"])
def test_a_huge_intensity_names_its_key_and_range(key):
    text = tiny_toml(models=("M1",)).replace('levels = ["D_0", "D_II"]', f"{key} = [1e300]")
    with pytest.raises(SpecError) as caught:
        parse_experiment(text)
    message = str(caught.value)
    assert f"intensities.{key}: " in message and "> 0 and <= 1000 (m/s^2" in message and "t_Ha" not in message
    assert parse_experiment(text.replace("1e300", "1000.0")).intensities.resolve()  # the bound itself is fine


def test_a_full_disk_names_the_file(tmp_path, capsys, monkeypatch):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    out = tmp_path / "out"

    def full(fd):
        raise OSError(28, "No space left on device")  # what a full disk gives: no file name

    monkeypatch.setattr(os, "fsync", full)
    code = main(["run", str(spec), "--out", str(out), "--executor", "serial"])
    err = capsys.readouterr().err
    assert code == 3, err
    assert f"bearingfw run: error: {out / 'experiment.toml'}: No space left on device" in err
    assert "Errno" not in err and "Traceback" not in err
    assert not list(out.rglob(".partial-*"))  # no temporary left behind


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="permissions bind only a non-root POSIX user")
def test_a_read_only_output_names_the_path(tmp_path, capsys):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o500)
    try:
        code = main(["run", str(spec), "--out", str(out), "--executor", "serial"])
    finally:
        out.chmod(0o700)
    err = capsys.readouterr().err
    assert code == 3 and str(out) in err and "Permission denied" in err and "Traceback" not in err


def test_warnings_in_a_cell_go_into_its_document_once(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("noisy",), levels=("D_0",))
    with warnings.catch_warnings(record=True) as leaked:
        warnings.simplefilter("always")
        summary = run_experiment(load_experiment(spec), tmp_path / "out", SerialExecutor())
    assert summary.exit_code == 0
    notes = Store(tmp_path / "out").read_cell("noisy/tremor/D_0")["warnings"]
    assert len(notes) == 1 and notes[0].startswith("RuntimeWarning: overflow encountered in exp (bfw_test_laws.py:")
    in_cell = int(notes[0].rsplit(", ", 1)[1].split()[0])
    assert in_cell > 100  # every call counted, reported once
    # Only the run's own check (model, modal analysis: a few calls, outside any cell) may warn out here.
    outside = [w for w in leaked if "overflow encountered in exp" in str(w.message)]
    assert len(outside) < in_cell / 10, (len(outside), in_cell)
    assert "RuntimeWarning: overflow encountered in exp" in (tmp_path / "out" / "report.md").read_text()
