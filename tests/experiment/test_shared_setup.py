"""What the cells of one model share in a process (issue 16): the model, its system and dead load,
and the record as read, are made once per model (record) and run, not once per cell; a cell whose
inputs differ gets its own; and the results are those of cells that make their own. The run
prepares each record and intensity once for its cells, so that a worker computing a cell does not
import scipy's signal module."""

from __future__ import annotations

import json

from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, load_experiment, run_experiment
from bearingfw.experiment import execute


def _counting(monkeypatch):
    """Count the models built and the records loaded by the cells (not by the run's own checks)."""
    counts = {"models": 0, "records": 0}
    build_model, load_record = execute.build_model, execute.load_record

    def counted_model(*args, **kwargs):
        counts["models"] += 1
        return build_model(*args, **kwargs)

    def counted_record(*args, **kwargs):
        counts["records"] += 1
        return load_record(*args, **kwargs)

    monkeypatch.setattr(execute, "build_model", counted_model)
    monkeypatch.setattr(execute, "load_record", counted_record)
    return counts


def _metrics(out):
    return {
        path.relative_to(out).as_posix(): json.loads(path.read_text())["metrics"]
        for path in sorted((out / "cells").rglob("*.json"))
    }


def test_the_cells_of_a_model_share_its_model_system_and_record(tmp_path, monkeypatch):
    path = write_tiny(tmp_path / "spec", models=("M0", "M2"), levels=("D_0", "D_I", "D_II"))
    counts = _counting(monkeypatch)
    summary = run_experiment(load_experiment(path), tmp_path / "out", SerialExecutor())
    assert len(summary.computed) == 6 and not summary.failed
    assert counts == {"models": 2, "records": 1}  # one per model, one record for all six cells

    # made again for each run (a builder or a plugin edited between two runs of one process)
    counts.update(models=0, records=0)
    run_experiment(load_experiment(path), tmp_path / "again", SerialExecutor())
    assert counts == {"models": 2, "records": 1}

    # the same numbers as cells that build their models themselves (the run still prepares each
    # record and intensity once for its cells: prepare_records)
    monkeypatch.setattr(execute, "_SHARED_SIZE", 0)
    counts.update(models=0, records=0)
    run_experiment(load_experiment(path), tmp_path / "alone", SerialExecutor())
    assert counts == {"models": 6, "records": 3}
    shared, alone = _metrics(tmp_path / "out"), _metrics(tmp_path / "alone")
    assert shared.keys() == alone.keys() and len(shared) == 6
    for cell in shared:  # as text: NaN equals NaN
        assert json.dumps(shared[cell], sort_keys=True) == json.dumps(alone[cell], sort_keys=True), cell


def test_a_model_of_other_inputs_is_not_taken_for_a_shared_one(tmp_path, monkeypatch):
    """Two models with the same preset but other parameters are two entries, with their own results."""
    extra = '[models.M2b]\npreset = "M2"\nfriction = 0.2\n'
    path = write_tiny(tmp_path / "spec", models=("M2",), levels=("D_II",), extra=extra)
    counts = _counting(monkeypatch)
    run_experiment(load_experiment(path), tmp_path / "out", SerialExecutor())
    assert counts["models"] == 2
    cells = _metrics(tmp_path / "out")
    first, second = (cells[f"cells/{m}/tremor/D_II.json"]["friction_ratio.1B"]["value"] for m in ("M2", "M2b"))
    assert first != second


def test_a_cell_with_its_record_prepared_runs_without_scipy_signal(tmp_path):
    """A worker computes a prepared cell without importing scipy.signal (a second of CPU per process)."""
    import pickle
    import subprocess
    import sys

    from bearingfw.experiment import plan_cells

    path = write_tiny(tmp_path / "spec", models=("M2",), levels=("D_II",))
    (job,) = execute.prepare_records(plan_cells(load_experiment(path)))
    assert job.prepared is not None
    (tmp_path / "job.pickle").write_bytes(pickle.dumps(job))
    script = (
        "import pickle, sys\n"
        "from bearingfw.experiment.execute import compute_cell\n"
        f"job = pickle.loads(open({str(tmp_path / 'job.pickle')!r}, 'rb').read())\n"
        "outcome = compute_cell(job)\n"
        "print(outcome.document['status'], 'scipy.signal' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-2:] == ["ok", "False"]
