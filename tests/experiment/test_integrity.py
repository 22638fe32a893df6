"""Results integrity: a stored cell is kept only while its files are as written (checksums), and the
cell digest covers the source of bearingfw and of the plugin packages whose laws the cell uses."""

from __future__ import annotations

import json

import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, Store, load_experiment, plan_cells, run_experiment
from bearingfw.experiment import structure as structure_module
from bearingfw.experiment.structure import package_source_digest

CELL = "M1/tremor/D_0"


@pytest.fixture
def stored(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    out = tmp_path / "out"
    first = run_experiment(load_experiment(spec), out, SerialExecutor())
    assert first.computed == (CELL,) and first.exit_code == 0
    return spec, out


def _edit(store: Store, change) -> None:
    path = store.cell_json(CELL)
    document = json.loads(path.read_text())
    change(document)
    path.write_text(json.dumps(document, indent=2))


@pytest.mark.parametrize("change", [
    lambda d: d.__setitem__("metrics", {}),  # the issue: emptied metrics kept their "ok"
    lambda d: d["metrics"]["stress.G4"].__setitem__("value", d["metrics"]["stress.G4"]["value"] * 2),
    lambda d: d.pop("checksum"),
], ids=["emptied", "edited", "no-checksum"])
def test_an_edited_cell_is_computed_again_and_the_report_says_so(stored, change):
    spec, out = stored
    store = Store(out)
    jobs = plan_cells(load_experiment(spec))
    assert store.is_finished(CELL, jobs[0].digest, 1) and store.damage(CELL) is None
    before = json.loads((out / "matrices.json").read_text())["stress.G4"]["M1"]["D_0"]
    _edit(store, change)
    assert store.damage(CELL) is not None and not store.is_finished(CELL, jobs[0].digest, 1)
    rerun = run_experiment(load_experiment(spec), out, SerialExecutor())
    assert rerun.computed == (CELL,) and [c for c, _ in rerun.damaged] == [CELL]
    assert store.damage(CELL) is None and store.read_cell(CELL)["status"] == "ok"
    assert json.loads((out / "matrices.json").read_text())["stress.G4"]["M1"]["D_0"] == before
    report = (out / "report.md").read_text()
    assert f"1 stored cell(s) failed their integrity check (checksums) and were computed again:\n  - {CELL}: " in report
    assert json.loads((out / "summary.json").read_text())["damaged"][0]["id"] == CELL


def test_a_replaced_histories_file_is_computed_again(stored):
    spec, out = stored
    store = Store(out)
    npz = store.cell_npz(CELL)
    npz.write_bytes(npz.read_bytes() + b"\0")
    assert store.damage(CELL) == "the cell's histories file does not match the checksum committed with it"
    rerun = run_experiment(load_experiment(spec), out, SerialExecutor())
    assert rerun.computed == (CELL,) and store.damage(CELL) is None


def test_thinning_the_histories_keeps_the_checksums_right(stored):
    spec, out = stored
    spec.write_text(spec.read_text().replace("[output]\n", "[output]\nevery = 5\n"))
    rerun = run_experiment(load_experiment(spec), out, SerialExecutor())
    assert rerun.thinned == (CELL,) and rerun.computed == () and Store(out).damage(CELL) is None


def test_the_source_of_a_package_is_hashed(tmp_path, monkeypatch):
    package = tmp_path / "h13_fake_plugin"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "law.py").write_text("K = 1.0\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    first = package_source_digest("h13_fake_plugin")
    (package / "law.py").write_text("K = 2.0\n")  # the same version, another law
    package_source_digest.cache_clear()
    assert package_source_digest("h13_fake_plugin") != first and first is not None
    assert package_source_digest("no_such_package_h13") is None


def test_the_digest_covers_the_source_of_bearingfw_and_of_the_laws_packages(tmp_path, monkeypatch):
    pytest.importorskip("bearingfw_boucwen")
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",), extra='[models.bw]\nlaw = "bouc-wen"\n')
    jobs = {j.model: j for j in plan_cells(load_experiment(spec))}
    own = package_source_digest("bearingfw")
    assert jobs["M1"].inputs["code"]["package_sources"] == {"bearingfw": own}
    assert set(jobs["bw"].inputs["code"]["package_sources"]) == {"bearingfw", "bearingfw_boucwen"}
    real = structure_module.package_source_digest

    def edited(package):
        return "edited" if package == "bearingfw_boucwen" else real(package)

    monkeypatch.setattr(structure_module, "package_source_digest", edited)  # a law edited in a checkout
    again = {j.model: j for j in plan_cells(load_experiment(spec))}
    assert again["bw"].digest != jobs["bw"].digest and again["M1"].digest == jobs["M1"].digest
