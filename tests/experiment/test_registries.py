"""Metric families and executors come from the plugin registry: the built-in ones, and a new one of
each from a plugin module (one definition plus a registration, tests/experiment/bfw_test_registry.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from tiny_experiment import write_tiny

from bearingfw.cli.main import main
from bearingfw.experiment import (
    EXECUTORS,
    ExecutorError,
    SerialExecutor,
    load_experiment,
    make_executor,
    metric_families,
)
from bearingfw.experiment.structure import import_paths, registry_for
from bearingfw.plugins import get_registry

PLUGINS = {'plugins = ["bfw_test_laws"]': 'plugins = ["bfw_test_laws", "bfw_test_registry"]'}


def test_the_built_in_families_and_executors_are_registered_with_a_description():
    registry = get_registry()
    assert list(registry.metrics) == ["stress", "stress_dynamic", "stress_increase", "bearing_force", "bearing_shear",
                                      "bearing_displacement", "slip", "friction_ratio", "deck_acceleration",
                                      "lift_offs", "uplift_time", "uplift_gap",  # experiment/uplift.py
                                      "differential_displacement", "quasi_static_share"]  # per-support motion
    assert tuple(registry.executors) == EXECUTORS == ("serial", "processes", "dask")
    for entry in (*registry.metrics.values(), *registry.executors.values()):
        assert isinstance(entry.value.description, str) and entry.value.description
        assert entry.origin.plugin == "builtin-experiment"
    units = {name: family.unit for name, family in metric_families().items()}
    assert units["stress"] == "Pa" and units["bearing_force"] == "N" and units["slip"] == "m"
    assert units["friction_ratio"] == "-" and units["deck_acceleration"] == "m/s^2"


def test_an_unknown_executor_lists_the_registered_ones():
    with pytest.raises(ExecutorError, match="unknown executor 'threads'; executors: serial, processes, dask"):
        make_executor("threads")


@pytest.fixture(scope="module")
def plugged(tmp_path_factory):
    """The tiny experiment with the test plugin, run once by the plugin's executor through the CLI."""
    import bfw_test_registry

    folder = tmp_path_factory.mktemp("plugged")
    spec = write_tiny(folder / "spec", models=("M1", "M2"), levels=("D_0",), **PLUGINS)
    out = folder / "out"
    code = main(["run", str(spec), "--out", str(out), "--executor", "reversed", "--quiet", "--json"])
    return spec, out, code, bfw_test_registry


def test_a_plugin_executor_runs_the_cells_when_named(plugged, capsys):
    spec, out, code, plugin = plugged
    assert code == 0
    assert plugin.RUNS[-1] == ["M2/tremor/D_0", "M1/tremor/D_0"]  # its own order: it ran them
    summary = json.loads((out / "summary.json").read_text())
    assert summary["executor"] == "reversed" and sorted(summary["computed"]) == ["M1/tremor/D_0", "M2/tremor/D_0"]
    registry = registry_for(load_experiment(spec).plugins, import_paths(load_experiment(spec)))
    assert make_executor("reversed", registry=registry).name == "reversed"
    with pytest.raises(ExecutorError, match="a scheduler address is for the dask executor"):
        make_executor("reversed", scheduler="tcp://x:1", registry=registry)


def test_a_plugin_metric_family_is_measured_stored_and_reported(plugged):
    spec, out, _, _ = plugged
    matrices = json.loads((out / "matrices.json").read_text())
    units = json.loads((out / "units.json").read_text())["matrices.json"]
    assert units["normal_force_drop.1B"] == "N"
    assert list(matrices)[-len([m for m in matrices if m.startswith("normal_force_drop.")]):] == [
        m for m in matrices if m.startswith("normal_force_drop.")]  # after the built-in families
    # the definition, by hand from the stored histories: max over t of N(0) - N(t)
    from bearingfw.experiment import Store

    histories, meta = Store(out).read_histories("M1/tremor/D_0")
    normal = histories["bearings.normal_force"][:, meta["bearings"].index("1B")].astype(float)
    assert matrices["normal_force_drop.1B"]["M1"]["D_0"] == pytest.approx(np.max(normal[0] - normal), rel=1e-5)
    assert matrices["normal_force_drop.1B"]["M1"]["D_0"] > 0
    report = (out / "report.md").read_text()
    assert "- `normal_force_drop` (N, largest fall of the normal force below its dead-load value): 1A" in report
    assert "- `normal_force_drop`: N(0) - N(t), the most the vertical motion unloads the bearing." in report


def test_a_plugin_family_is_an_input_of_the_cells(tmp_path):
    """A metric family's code is part of a cell's result: the plugin module's source is in the digest."""
    from bearingfw.experiment import plan_cells

    plain = plan_cells(load_experiment(write_tiny(tmp_path / "a", models=("M1",), levels=("D_0",))))[0]
    plugged = plan_cells(load_experiment(write_tiny(tmp_path / "b", models=("M1",), levels=("D_0",), **PLUGINS)))[0]
    assert "bfw_test_registry" in plugged.inputs["code"]["sources"] and plain.digest != plugged.digest


def test_the_serial_executor_takes_the_common_arguments():
    assert isinstance(make_executor("serial", 4), SerialExecutor) and make_executor("serial", 4).workers == 1
