"""The results directory: one run at a time (a lock naming its holder), one experiment per directory
(another one only when told to take it over), and no file deleted that a live writer may still need."""

from __future__ import annotations

import json
import os
import platform
import signal
import subprocess
import sys

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import (
    SerialExecutor,
    Store,
    StoreError,
    load_experiment,
    run_experiment,
)
from bearingfw.experiment.store import LOCK_NAME, atomic_write

#: Holds the lock of the directory argv[1] until killed; says "held" once it has it.
HOLDER = """
import sys, time
from bearingfw.experiment import Store
with Store(sys.argv[1]).claim("tiny"):
    print("held", flush=True)
    time.sleep(120)
"""


def _tree(root) -> dict[str, bytes]:
    """Every file under ``root`` but the lock file (whose text names the last holder) with its bytes."""
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and p.name != LOCK_NAME}


def test_a_second_claim_stops_and_names_the_directory_and_the_holder(tmp_path):
    out = tmp_path / "out"
    with Store(out).claim("tiny"):
        with pytest.raises(StoreError) as caught, Store(out).claim("tiny"):
            pass
        message = str(caught.value)
        assert message.startswith(f"{out} is in use by another bearingfw run (pid {os.getpid()} on host "
                                  f"{platform.node()}, experiment 'tiny', since ")
        assert json.loads((out / LOCK_NAME).read_text())["pid"] == os.getpid()
    with Store(out).claim("tiny"):  # released at the end of the block
        pass


def test_the_lock_of_a_killed_run_is_not_stale(tmp_path):
    """Another process holds the directory: refused; once it is killed (no chance to clean up), free."""
    out = tmp_path / "out"
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(StoreError, match=rf"in use by another bearingfw run \(pid {holder.pid} on host "), \
                Store(out).claim("tiny"):
            pass
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()
        holder.stdout.close()
    with Store(out).claim("tiny"):
        pass


def test_a_run_into_a_held_directory_changes_nothing(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    experiment = load_experiment(spec)
    out = tmp_path / "out"
    run_experiment(experiment, out, SerialExecutor())
    before = _tree(out)
    with Store(out).claim("tiny"), pytest.raises(StoreError, match=f"^{out} is in use by another bearingfw run"):
        run_experiment(experiment, out, SerialExecutor(), force=True)
    assert _tree(out) == before


def test_another_experiment_is_refused_unless_it_takes_over(tmp_path):
    first = load_experiment(write_tiny(tmp_path / "a", name="first", models=("M1", "M2"), levels=("D_0",)))
    second = load_experiment(write_tiny(tmp_path / "b", name="second", models=("M0", "M2"), levels=("D_0",)))
    out = tmp_path / "out"
    run_experiment(first, out, SerialExecutor())
    before = _tree(out)
    with pytest.raises(StoreError) as caught:
        run_experiment(second, out, SerialExecutor())
    assert str(caught.value).startswith(f"{out} holds the results of experiment 'first', not 'second'; nothing was "
                                        "changed.")
    assert "--take-over" in str(caught.value)
    assert _tree(out) == before

    taken = run_experiment(second, out, SerialExecutor(), take_over=True)
    # M2's cell is the same computation in both (names and the reference model are not inputs): reused
    assert taken.skipped == ("M2/tremor/D_0",) and taken.computed == ("M0/tremor/D_0",)
    after = _tree(out)
    for name in ("cells/M1/tremor/D_0.json", "cells/M1/tremor/D_0.npz", "cells/M2/tremor/D_0.json"):
        assert after[name] == before[name]  # first's other cell is left alone, the shared one reused as it is
    assert set(json.loads((out / "matrices.json").read_text())["stress.G4"]) == {"M0", "M2"}
    assert json.loads((out / "manifest.json").read_text())["experiment"] == "second"
    with pytest.raises(StoreError, match="holds the results of experiment 'second', not 'first'"):
        run_experiment(first, out, SerialExecutor())


def test_a_folder_of_other_files_is_refused_untouched(tmp_path):
    experiment = load_experiment(write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",)))
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    with pytest.raises(StoreError, match=f"^{out} is not empty and holds no bearingfw results"):
        run_experiment(experiment, out, SerialExecutor())
    assert [p.name for p in out.iterdir()] == ["notes.txt"]  # not even a lock file
    assert run_experiment(experiment, out, SerialExecutor(), take_over=True).exit_code == 0
    assert (out / "notes.txt").read_text() == "my notes" and (out / "matrices.json").is_file()
    assert run_experiment(experiment, out, SerialExecutor()).computed == ()  # it is the experiment's now


#: Writes argv[1] atomically but stops for good before the rename (says "writing" then).
WRITER = """
import os, sys, time
from bearingfw.experiment import store

def stuck(fd):
    print("writing", flush=True)
    time.sleep(120)

os.fsync = stuck
store.atomic_write(sys.argv[1], b"new" * 1000)
"""


def test_a_killed_writer_leaves_the_old_file_and_a_temporary_that_only_a_later_run_removes(tmp_path):
    from bearingfw.experiment.store import _HOST

    store = Store(tmp_path)
    target = tmp_path / "cells" / "a.json"
    atomic_write(target, b"old")
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(target)], stdout=subprocess.PIPE, text=True)
    try:
        assert writer.stdout.readline().strip() == "writing"
    finally:
        writer.send_signal(signal.SIGKILL)
        writer.wait()
        writer.stdout.close()
    dead = list(target.parent.glob(".partial-*"))
    assert len(dead) == 1 and dead[0].name.startswith(f".partial-a.json.{_HOST}-{writer.pid}.")
    assert target.read_bytes() == b"old"
    # temporaries that may still be needed: a live writer's (this process), another host's; and a file
    # that merely looks like one
    live = target.parent / f".partial-b.json.{_HOST}-{os.getpid()}.{'0' * 12}"
    elsewhere = target.parent / f".partial-c.json.{_HOST}x-{writer.pid}.{'1' * 12}"
    lookalike = target.parent / ".partial-notes"
    for path in (live, elsewhere, lookalike):
        path.write_bytes(b"x")
    assert store.clean_temporaries() == 1
    assert not dead[0].exists()
    assert live.exists() and elsewhere.exists() and lookalike.exists() and target.read_bytes() == b"old"
