"""What the cells of one model share in a process (issue 16): the model, its system and dead load,
and the record as read, are made once per model (record) and run, not once per cell; a cell whose
inputs differ gets its own; and the results are those of cells that make their own. The run
prepares each record and intensity once for its cells, so that a worker computing a cell does not
import scipy's signal module."""

from __future__ import annotations

import json
from pathlib import Path

from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, load_experiment, plan_cells, run_experiment
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
    # record and intensity once for its cells: prepare_cells)
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

    path = write_tiny(tmp_path / "spec", models=("M2",), levels=("D_II",))
    (job,) = execute.prepare_cells(plan_cells(load_experiment(path)))
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


def test_a_process_that_outlives_a_run_builds_the_model_again_for_the_next(tmp_path):
    """A Dask worker lives across runs, and only the run's own process empties its cache: what it
    shares is the run's (``CellJob.run``). Here a builder reads its added dead load from a data file
    (not in the cells' code digest), which is edited between two runs computed in this process."""
    builder = tmp_path / "builder"
    builder.mkdir()
    (builder / "file_bridge.py").write_text(
        "import json, pathlib\n"
        "from small_bridge import build as _build\n\n\n"
        "def build(elements_per_span=4):\n"
        "    data = json.loads(pathlib.Path(__file__).with_name('bridge.json').read_text())\n"
        "    return _build(elements_per_span=elements_per_span, superimposed_dead_load=data['sdl'])\n"
    )
    path = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_II",),
                      **{'builder = "small_bridge:build"': 'builder = "file_bridge:build"',
                         "python_path = [": f'python_path = ["{builder.as_posix()}", '})

    def cell(sdl: float) -> float:
        (builder / "bridge.json").write_text(json.dumps({"sdl": sdl}))
        (job,) = execute.prepare_cells(plan_cells(load_experiment(path)))
        return execute.compute_cell(job).document["metrics"]["stress.G4"]["value"]  # as a worker computes it

    execute.forget_shared()
    light, heavy = cell(3000.0), cell(9000.0)
    execute.forget_shared()
    assert heavy == cell(9000.0) and abs(heavy - light) > 1e-3 * abs(light)


def test_each_cell_reports_the_warnings_of_what_it_shares(tmp_path, monkeypatch):
    """A law that warns at every call: each cell's document counts the warnings of its own model's
    dead load and of its record too, as a cell that builds them itself (nothing kept aside) does."""
    path = write_tiny(tmp_path / "spec", models=("noisy",), levels=("D_0", "D_II"))
    jobs = plan_cells(load_experiment(path))
    shared = {}
    execute.forget_shared()
    for job in execute.prepare_cells(jobs):
        shared[job.id] = execute.compute_cell(job).document["warnings"]
    alone = {}
    with monkeypatch.context() as patched:  # warnings straight to the cell, nothing shared
        patched.setattr(execute, "_recording_warnings", lambda make: (make(), ()))
        for job in jobs:
            execute.forget_shared()
            alone[job.id] = execute.compute_cell(job).document["warnings"]
    assert shared == alone and all(alone.values())


def test_two_record_entries_of_the_same_contents_keep_their_own_names(tmp_path):
    """Record files with the same bytes under other names: each entry's cells name their own files."""
    import shutil

    records = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"
    names = {}
    for site in ("a", "b"):
        names[site] = []
        for component in "LTV":
            copy = tmp_path / f"site_{site}_{component}.AT2"
            shutil.copy(records / f"RSN1633_MANJIL_ABBAR--{component}.AT2", copy)
            names[site].append(copy.as_posix())
    entries = "".join(
        f"[records.{site.upper()}]\nfiles = [{', '.join(json.dumps(p) for p in files)}]\n\n" for site, files in names.items()
    )
    tremor = "[records.tremor]\nseed = 1\ntremor = { duration = 10.0, dt = 0.01, decay = 2.0 }\n"
    path = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",), **{tremor: entries})
    execute.forget_shared()
    for job in plan_cells(load_experiment(path)):  # each cell reads its record itself (nothing prepared)
        source = execute.compute_cell(job).document["record_measures"]["source"]
        assert f"site_{job.record.lower()}_" in source and f"site_{'b' if job.record == 'A' else 'a'}_" not in source


def test_a_law_that_changes_its_state_in_place_does_not_carry_it_into_the_next_cell(tmp_path, monkeypatch):
    """The dead load's law states are shared by the cells of a model; each cell starts from a copy.
    The impure law writes into the committed state it is given only under more than the purity
    check's normal force (so the check passes), and runs through ``respond`` (no compiled law)."""
    import numpy as np

    from bearingfw.analysis import hht
    from bearingfw.experiment.purity import NORMAL_FORCE
    from bearingfw.laws.coulomb import RegularizedCoulomb

    monkeypatch.setattr(hht, "COMPILED_NEWTON", False)
    respond = RegularizedCoulomb.respond

    def mutating(self, state, u, normal_force, dt):
        if np.max(normal_force) > 2 * NORMAL_FORCE:
            state["slip"][...] += 1e-4
        return respond(self, state, u, normal_force, dt)

    path = write_tiny(tmp_path / "spec", models=("M2",), levels=("D_0", "D_II"))
    jobs = execute.prepare_cells(plan_cells(load_experiment(path)))
    execute.forget_shared()
    first = execute.compute_cell(jobs[0]).document["metrics"]
    monkeypatch.setattr(RegularizedCoulomb, "respond", mutating)
    execute.compute_cell(jobs[1])  # its impure law writes into the states it is handed
    monkeypatch.setattr(RegularizedCoulomb, "respond", respond)
    again = execute.compute_cell(jobs[0]).document["metrics"]
    assert json.dumps(again, sort_keys=True) == json.dumps(first, sort_keys=True)
