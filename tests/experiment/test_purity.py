"""Purity in the runner: a law that changes the committed state it is given fails its cells, naming the
law (the issue: such a law ran to ``ok`` with histories off by orders of magnitude)."""

from __future__ import annotations

import numpy as np
from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, Store, load_experiment, run_experiment
from bearingfw.experiment.purity import fingerprint


def test_a_mutating_law_fails_its_cells_naming_the_law(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("mutate", "M1"), levels=("D_0",))
    summary = run_experiment(load_experiment(spec), tmp_path / "out", SerialExecutor())
    assert summary.exit_code == 1 and [c for c, _ in summary.failed] == ["mutate/tremor/D_0"]
    message = summary.failed[0][1]
    assert "law 'test-mutating-spring' (bearings 1A, 2B, 3A)" in message  # its first group
    assert "changed the committed state it was given in respond" in message
    document = Store(tmp_path / "out").read_cell("mutate/tremor/D_0")
    assert document["status"] == "failed" and document["error"]["type"] == "LawPurityError"
    assert Store(tmp_path / "out").read_cell("M1/tremor/D_0")["status"] == "ok"  # pure laws pass


def test_the_fingerprint_sees_every_array_of_a_state():
    state = {"z": np.zeros((2, 2)), "history": [np.ones(3), (1.5, "stick")]}
    before = fingerprint(state)
    assert fingerprint({"z": np.zeros((2, 2)), "history": [np.ones(3), (1.5, "stick")]}) == before
    state["history"][0][1] = 1.0 + 1e-15
    assert fingerprint(state) != before
    assert fingerprint(np.zeros(2, dtype=np.float32)) != fingerprint(np.zeros(2))
    assert fingerprint(None) == fingerprint(None)
