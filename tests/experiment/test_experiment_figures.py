"""Figures drawn by worker processes are the figures drawn in the run's own process, file for file; a
rerun with nothing new draws none again."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from tiny_experiment import write_tiny

from bearingfw.experiment import (
    ProcessExecutor,
    SerialExecutor,
    load_experiment,
    run_experiment,
)


def _relative(summary, root) -> list[Path]:
    return [Path(p).relative_to(root) for p in summary.files["figures"]]


def test_figures_drawn_in_processes_equal_those_drawn_here(tmp_path):
    experiment = load_experiment(write_tiny(tmp_path / "spec", models=("M1", "M2"), levels=("D_0",), figures=True,
                                            **{"draw = true": 'draw = "all"\nformats = ["png", "svg"]'}))
    here = tmp_path / "here"
    serial = run_experiment(experiment, here, SerialExecutor())  # figures one after the other, in this process
    pooled = tmp_path / "pooled"
    shutil.copytree(here, pooled, ignore=shutil.ignore_patterns("figures"))
    parallel = run_experiment(experiment, pooled, ProcessExecutor(2))  # no cell to run; figures on 2 processes
    assert parallel.computed == ()
    figures = _relative(serial, here)
    assert figures == _relative(parallel, pooled) and len(figures) == 2 * 11
    for path in figures:
        assert (pooled / path).is_file(), path
        if path.suffix == ".png":  # SVG files carry a date and random ids; the PNG pixels and text must agree
            assert (pooled / path).read_bytes() == (here / path).read_bytes(), path
    assert json.loads((pooled / "figures" / "index.json").read_text()) == json.loads(
        (here / "figures" / "index.json").read_text())

    stamps = {p: (pooled / p).stat().st_mtime_ns for p in figures}
    again = run_experiment(experiment, pooled, ProcessExecutor(2))
    assert _relative(again, pooled) == figures
    assert {p: (pooled / p).stat().st_mtime_ns for p in figures} == stamps  # nothing drawn again
