"""A change of what is recorded (``[output] histories``, ``every``) touches only what it must: coarser
histories are cut from the stored ones, finer ones need the cell again, turning them off keeps all."""

from __future__ import annotations

import json

import numpy as np
from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, Store, load_experiment, run_experiment

CELLS = ("M1/tremor/D_0", "M2/tremor/D_0")


def _spec(folder, setting: str):
    return load_experiment(write_tiny(folder / setting.replace(" ", "").replace("=", "-"), models=("M1", "M2"),
                                      levels=("D_0",), **{"[output]\n": f"[output]\n{setting}\n"}))


def test_recording_changes_recompute_only_what_they_must(tmp_path):
    out = tmp_path / "out"
    store = Store(out)
    first = run_experiment(_spec(tmp_path, "every = 1"), out, SerialExecutor())
    assert sorted(first.computed) == list(CELLS)
    matrices = (out / "matrices.json").read_bytes()
    full = {c: store.read_histories(c) for c in CELLS}

    coarse = run_experiment(_spec(tmp_path, "every = 4"), out, SerialExecutor())
    assert coarse.computed == () and sorted(coarse.thinned) == sorted(coarse.skipped) == list(CELLS)
    for cell in CELLS:
        histories, meta = store.read_histories(cell)
        assert meta["every"] == 4 and meta["digest"] == full[cell][1]["digest"]
        assert histories["time"].shape == (251,)  # 1001 samples, every 4th from the dead-load state
        for key, values in full[cell][0].items():
            expected = values if key.startswith("ground.") else values[::4]
            np.testing.assert_array_equal(histories[key], expected, err_msg=key)
    assert (out / "matrices.json").read_bytes() == matrices  # the metrics use every step, always

    finer = run_experiment(_spec(tmp_path, "every = 2"), out, SerialExecutor())
    assert sorted(finer.computed) == list(CELLS)  # 2 is not a multiple of 4: only a new computation has them
    assert store.read_histories(CELLS[0])[0]["time"].shape == (501,)
    assert (out / "matrices.json").read_bytes() == matrices

    npz = {c: store.cell_npz(c).read_bytes() for c in CELLS}
    off = run_experiment(_spec(tmp_path, "histories = false"), out, SerialExecutor())
    assert off.computed == () and off.thinned == ()
    assert {c: store.cell_npz(c).read_bytes() for c in CELLS} == npz  # kept, not deleted
    again = run_experiment(_spec(tmp_path, "every = 2"), out, SerialExecutor())
    assert again.computed == () and again.thinned == ()  # the histories are still there
    assert json.loads((out / "manifest.json").read_text())["recording"] == {"histories": True, "every": 2}


def test_histories_of_other_inputs_never_pass_for_the_cells(tmp_path):
    """The histories file names its digest: a cell whose commit carries another digest is not finished
    (e.g. a run stopped between writing a recomputed cell's histories and its JSON)."""
    out = tmp_path / "out"
    experiment = _spec(tmp_path, "every = 1")
    run_experiment(experiment, out, SerialExecutor())
    store = Store(out)
    histories, meta = store.read_histories(CELLS[0])
    store.write_histories(CELLS[0], histories, {**meta, "digest": "0" * 64})
    assert not store.rethin(CELLS[0], store.read_cell(CELLS[0])["digest"], 2)
    rerun = run_experiment(experiment, out, SerialExecutor())
    assert rerun.computed == (CELLS[0],)
