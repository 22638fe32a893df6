"""A whole run of the tiny experiment: the store, matrices, CSVs, figures, report; reruns and changes."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import (
    ProcessExecutor,
    SerialExecutor,
    Store,
    load_experiment,
    plan_cells,
    run_experiment,
)

MODELS = ("M0", "M1", "M2")
LEVELS = ("D_0", "D_II")


@pytest.fixture(scope="module")
def first(tmp_path_factory):
    """The tiny experiment run once on the default executor (local processes), every figure in PNG and SVG."""
    folder = tmp_path_factory.mktemp("tiny")
    path = write_tiny(folder / "spec", figures=True, **{"draw = true": 'draw = "all"\nformats = ["png", "svg"]'})
    out = folder / "out"
    summary = run_experiment(load_experiment(path), out, ProcessExecutor(2))
    return path, out, summary


def _json(path):
    return json.loads(path.read_text())


def test_every_cell_is_computed_and_stored_with_its_digest(first):
    path, out, summary = first
    assert summary.exit_code == 0 and not summary.failed and not summary.missing
    assert summary.cells == 6 and len(summary.computed) == 6 and not summary.skipped
    jobs = plan_cells(load_experiment(path))
    store = Store(out)
    for job in jobs:
        document = store.read_cell(job.id)
        assert document["status"] == "ok" and document["digest"] == job.digest and document["error"] is None
        assert store.cell_npz(job.id).stat().st_size > 1000
        histories, meta = store.read_histories(job.id)
        assert histories["time"].shape[0] == 1001  # 10 s at 0.01 s, the preload state first
        assert meta["bearings"] == ["1A", "1B", "2A", "2B", "3A", "3B"] and meta["sliding"]["2A"] == []
    manifest = _json(out / "manifest.json")
    assert manifest["state"] == "finished" and all(c["finished"] for c in manifest["cells"])
    assert not list(out.rglob(".partial-*"))  # no temporary file left behind


def test_matrices_json_is_metric_model_intensity(first):
    _, out, _ = first
    matrices = _json(out / "matrices.json")
    for metric in ("stress.G2", "stress_dynamic.G4", "bearing_force.1B", "bearing_shear.2A", "slip.1B",
                   "bearing_displacement.3B", "friction_ratio.1B", "deck_acceleration.y"):
        assert set(matrices[metric]) == set(MODELS)
        assert all(list(matrices[metric][m]) == list(LEVELS) for m in MODELS)
    # not applicable: no friction in a spring, nothing slides in the fixed bearing 2A
    assert matrices["friction_ratio.1B"]["M1"]["D_II"] > 0.04 and matrices["friction_ratio.1B"]["M0"]["D_0"] == 0.0
    assert matrices["slip.1B"]["M1"]["D_0"] is None and matrices["bearing_force.2A"]["M2"]["D_0"] is None
    assert matrices["friction_ratio.2A"]["M1"]["D_0"] is None
    # the rise of the total principal stress never exceeds the tremor's own principal stress (sigma1 is
    # subadditive), nor the total
    for model in MODELS:
        for level in LEVELS:
            rise = matrices["stress_increase.G4"][model][level]
            assert 0 < rise <= matrices["stress_dynamic.G4"][model][level] * (1 + 1e-12)
            assert rise <= matrices["stress.G4"][model][level]
    # the friction law caps the bearing's force at mu N: the ratio reaches mu = 0.04 and not more
    assert matrices["friction_ratio.1B"]["M2"]["D_II"] == pytest.approx(0.04, rel=1e-9)
    ratios = _json(out / "ratios.json")  # reference M1 in the tiny file
    assert ratios["stress.G4"]["M1"] == {"D_0": 1.0, "D_II": 1.0}
    assert ratios["stress.G4"]["M0"]["D_II"] == pytest.approx(
        matrices["stress.G4"]["M0"]["D_II"] / matrices["stress.G4"]["M1"]["D_II"], rel=1e-12)


def test_dynamic_stresses_of_the_linear_models_scale_with_the_record(first):
    """M0 and M1 are linear: their tremor stresses scale by D_II / D_0 = 4.6, so the ratio is the same."""
    _, out, _ = first
    matrices = _json(out / "matrices.json")
    for element in ("G2", "G4"):
        m = matrices[f"stress_dynamic.{element}"]
        for model in ("M0", "M1"):
            assert m[model]["D_II"] / m[model]["D_0"] == pytest.approx(0.46 / 0.10, rel=1e-6)
        total = matrices[f"stress.{element}"]
        assert total["M1"]["D_II"] / total["M1"]["D_0"] < 2  # the dead load does not scale


def test_csv_files_hold_the_matrices_with_their_units(first):
    _, out, _ = first
    matrices = _json(out / "matrices.json")
    with open(out / "matrices" / "stress.G4.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["model", *(f"{level} [Pa]" for level in LEVELS)]  # the header carries the unit
    assert [r[0] for r in rows[1:]] == list(MODELS)
    for row in rows[1:]:
        assert [float(v) for v in row[1:]] == [matrices["stress.G4"][row[0]][i] for i in LEVELS]
    with open(out / "matrices" / "slip.1B.csv", newline="") as handle:
        slip = list(csv.reader(handle))
    assert slip[0][1] == "D_0 [m]" and slip[2] == ["M1", "", ""]  # not applicable: empty
    with open(out / "ratios" / "stress.G4.csv", newline="") as handle:
        assert next(csv.reader(handle)) == ["model", "D_0 [-]", "D_II [-]"]
    with open(out / "cells.csv", newline="") as handle:
        cells = list(csv.DictReader(handle))
    row = next(r for r in cells if r["model"] == "M2" and r["intensity"] == "D_II" and r["metric"] == "stress.G4")
    assert float(row["value"]) == matrices["stress.G4"]["M2"]["D_II"] and row["unit"] == "Pa"
    assert 0 < float(row["time [s]"]) <= 10 and row["at"].startswith("end ")
    assert float(row["pga_h10 [m/s^2]"]) == pytest.approx(0.46) and float(row["scale_factor [-]"]) > 0
    assert len(cells) == 6 * len(matrices)


def test_units_agree_in_the_files_the_terminal_and_the_report(first):
    """units.json names the SI unit of every matrix; the cell files, the text tables and the report show the same
    quantity in its display unit (Pa -> MPa, N -> kN, m -> mm)."""
    from bearingfw.experiment import format_tables

    _, out, summary = first
    units = _json(out / "units.json")
    matrices = _json(out / "matrices.json")
    assert set(units["matrices.json"]) == set(matrices)
    assert units["matrices.json"]["stress.G4"] == "Pa" and units["matrices.json"]["bearing_force.1B"] == "N"
    assert units["matrices.json"]["slip.1B"] == "m" and units["matrices.json"]["friction_ratio.1B"] == "-"
    assert units["matrices.json"]["deck_acceleration.y"] == "m/s^2" and units["ratios.json"] == "-"
    assert units["modal.json"]["modes.frequency"] == "Hz" and units["records.json"]["pga_h10"] == "m/s^2"
    cell = _json(out / "cells" / "M2" / "tremor" / "D_II.json")
    assert {m: e["unit"] for m, e in cell["metrics"].items()} == units["matrices.json"]
    value = matrices["bearing_force.1B"]["M2"]["D_II"]
    text = format_tables(summary.matrices, ["bearing_force.1B"])
    assert text.startswith("bearing_force.1B [kN]") and f"{value * 1e-3:.4g}" in text
    report = (out / "report.md").read_text()
    assert "### `bearing_force.1B` [kN]" in report and f"| {value * 1e-3:.4g} (" in report
    assert "- `bearing_force` (N, peak force in the bearing's sliding directions)" in report
    assert _json(out / "summary.json")["units"] == {"wall_time": "s", "run_time": "s"}


def test_every_figure_is_written_in_each_format_asked_for(first):
    _, out, summary = first
    figures = out / "figures"
    table = ("stress.G4", "stress_dynamic.G4", "bearing_force.1B", "friction_ratio.1B", "deck_acceleration.y")
    stems = ["intensity-chart", *(f"heatmap_{m}" for m in table)]
    for level in LEVELS:
        stems += [f"stress_tremor_{level}", f"bearing-force_1B_tremor_{level}", f"friction-ratio_1B_tremor_{level}"]
        stems += [f"hysteresis_{m}_tremor_{level}" for m in MODELS]
    expected = sorted(f"{stem}.{suffix}" for stem in stems for suffix in ("png", "svg"))
    assert sorted(p.name for p in figures.iterdir() if p.name != "index.json") == expected  # nothing else, no temporary
    assert sorted(Path(p).name for p in summary.files["figures"]) == expected
    for stem in stems:
        assert (figures / f"{stem}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", stem
        assert "</svg>" in (figures / f"{stem}.svg").read_text()[-100:], stem  # whole files


def _svg_texts(path) -> list[str]:
    """The texts of a matplotlib SVG (it draws text as paths, each preceded by a comment with the text)."""
    import re

    return re.findall(r"<!-- (.*?) -->", path.read_text(), flags=re.DOTALL)


def _png(path):
    import matplotlib.image

    return matplotlib.image.imread(path)[..., :3]


def _pixels_near(image, colour: str, tolerance: float = 0.08) -> int:
    from matplotlib.colors import to_rgb

    return int((np.abs(image - np.array(to_rgb(colour))).max(axis=-1) < tolerance).sum())


def test_figures_show_what_they_claim(first):
    """Content, not size: the heatmaps print the matrices' own values and ratios, every history figure has
    a legend entry and a drawn line (its colour in the PNG) for each model, and no PNG is blank."""
    _, out, _ = first
    figures = out / "figures"
    matrices, ratios = _json(out / "matrices.json"), _json(out / "ratios.json")
    texts = _svg_texts(figures / "heatmap_stress.G4.svg")
    assert "stress.G4 [MPa], ratio to M1" in texts and set(MODELS) <= set(texts) and set(LEVELS) <= set(texts)
    for model in MODELS:
        for level in LEVELS:
            assert f"{matrices['stress.G4'][model][level] * 1e-6:.3g}" in texts, (model, level)
            assert f"×{ratios['stress.G4'][model][level]:.2f}" in texts, (model, level)
    for level in LEVELS:
        stress = _svg_texts(figures / f"stress_tremor_{level}.svg")
        assert [t for t in stress if t in MODELS] == ["M1", "M2"]  # [figures] compare, each once in the legend
        assert {"G2: total", "G4: total", "G4: ground motion's part", "time [s]"} <= set(stress)
        image = _png(figures / f"stress_tremor_{level}.png")
        assert 400 < image.shape[0] < 1000 and 900 < image.shape[1] < 1600
        for k, model in enumerate(MODELS):  # a line of each compared model's colour is drawn, none of the other
            assert (_pixels_near(image, f"C{k}") > 100) == (model in ("M1", "M2")), (level, model)
        force = _svg_texts(figures / f"bearing-force_1B_tremor_{level}.svg")
        assert [t for t in force if t in MODELS] == ["M1", "M2"]  # [figures] compare of the tiny experiment
        friction = _svg_texts(figures / f"friction-ratio_1B_tremor_{level}.svg")
        assert "M2" in friction and any(t.startswith("mu = ") and t.endswith("(M2)") for t in friction)  # M2 has a mu
        for model in MODELS:
            hysteresis = _svg_texts(figures / f"hysteresis_{model}_tremor_{level}.svg")
            assert "1B" in hysteresis and any(t.startswith("force against displacement") for t in hysteresis)
    for png in figures.glob("*.png"):
        image = _png(png)
        assert (image.min(axis=-1) < 0.9).mean() > 0.01, png.name  # not blank: ink on more than 1 %


def test_report_has_every_section(first):
    _, out, _ = first
    text = (out / "report.md").read_text()
    for heading in ("# tiny: bearingfw experiment report", "## Summary", "## Inputs", "### Structure",
                    "### Bearing models", "### Records", "### Intensities", "### Analysis", "## Modal results",
                    "## Comparison matrices", "### `stress.G4` [MPa]", "## Figures", "## Run statistics",
                    "## Failed cells"):
        assert heading in text, heading
    assert "SYNTHETIC" in text and "None." in text.split("## Failed cells")[1]
    definitions = text.split("Definitions:")[1].split("## Figures")[0]
    assert "- `stress_dynamic`: sigma1 of the stress state of the ground motion's own section forces" in definitions
    assert "- `stress_increase`: sigma1(F(t)) - sigma1(F_dead)" in definitions
    assert "- `friction_ratio`: abs(F)/N only while the bearing is pressed with more than 10%" in definitions
    assert "![stress_tremor_D_II](figures/stress_tremor_D_II.png)" in text
    assert "| M2/tremor/D_II | ok |" in text
    modal = _json(out / "modal.json")
    assert modal["M0"]["modes"][0]["label"] == "longitudinal 1"  # frictionless: the deck swings along the bridge
    assert modal["M1"]["modes"][0]["frequency"] > modal["M0"]["modes"][0]["frequency"]


def test_a_rerun_computes_nothing_and_gives_the_same_files(first, tmp_path):
    path, out, _ = first
    before = (out / "matrices.json").read_bytes()
    again = run_experiment(load_experiment(path), out, SerialExecutor())
    assert again.computed == () and len(again.skipped) == 6 and again.exit_code == 0
    assert (out / "matrices.json").read_bytes() == before


def test_changed_inputs_recompute_only_their_cells(first, tmp_path):
    path, out, _ = first
    copy = tmp_path / "out"
    import shutil

    shutil.copytree(out, copy)
    text = path.read_text().replace('[models.M2]\npreset = "M2"', '[models.M2]\npreset = "M2"\nfriction = 0.03')
    text = text.replace('draw = "all"', "draw = false")  # figures are not what this test is about
    changed = path.parent / "changed.toml"
    changed.write_text(text)
    summary = run_experiment(load_experiment(changed), copy, SerialExecutor())
    assert sorted(summary.computed) == ["M2/tremor/D_0", "M2/tremor/D_II"]
    matrices = _json(copy / "matrices.json")
    assert matrices["friction_ratio.1B"]["M2"]["D_II"] == pytest.approx(0.03, rel=1e-9)
    assert matrices["stress.G4"]["M1"] == _json(out / "matrices.json")["stress.G4"]["M1"]
    forced = run_experiment(load_experiment(changed), copy, SerialExecutor(), force=True, models=("M0",),
                            intensities=("D_0",))
    assert forced.computed == ("M0/tremor/D_0",) and forced.skipped == ()


def test_a_record_file_is_hashed_by_content(tmp_path):
    """A record read from a file: editing the file recomputes the cell, moving it does not."""
    from bearingfw.motion import TremorParameters, synthetic_tremor

    record = synthetic_tremor(1, TremorParameters(duration=10.0, dt=0.01, decay=2.0))
    data = tmp_path / "data"
    data.mkdir()
    rows = "\n".join(f"{a:.8e},{b:.8e},{c:.8e}" for a, b, c in zip(record.h1, record.h2, record.v))
    (data / "tremor.csv").write_text(rows + "\n")
    spec = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",))
    text = spec.read_text().replace(
        "seed = 1\ntremor = { duration = 10.0, dt = 0.01, decay = 2.0 }",
        f'files = ["{(data / "tremor.csv").as_posix()}"]\ndt = 0.01\nunits = "m/s^2"')
    spec.write_text(text)
    out = tmp_path / "out"
    assert run_experiment(load_experiment(spec), out, SerialExecutor()).computed == ("M1/tremor/D_0",)
    moved = tmp_path / "moved"
    (data).rename(moved)
    spec.write_text(text.replace(data.as_posix(), moved.as_posix()))
    assert run_experiment(load_experiment(spec), out, SerialExecutor()).computed == ()
    values = (moved / "tremor.csv").read_text().replace("e-", "E-", 1)  # same numbers, other bytes
    (moved / "tremor.csv").write_text(values)
    assert run_experiment(load_experiment(spec), out, SerialExecutor()).computed == ("M1/tremor/D_0",)
    assert not math.isnan(_json(out / "matrices.json")["stress.G4"]["M1"]["D_0"])


def test_without_histories_the_run_completes_without_figures(tmp_path):
    """Figures draw the stored histories; with none kept the run still writes matrices and report."""
    path = write_tiny(tmp_path / "spec", models=("M0",), levels=("D_0",), figures=True,
                      **{"[output]\n": "[output]\nhistories = false\n"})
    out = tmp_path / "out"
    summary = run_experiment(load_experiment(path), out, SerialExecutor())
    assert summary.failed == () and summary.files["figures"] == []
    assert (out / "matrices.json").is_file() and (out / "report.md").is_file()
    assert json.loads((out / "manifest.json").read_text())["state"] == "finished"


def test_several_records_combine_as_the_report_says(tmp_path):
    """Two records, EC8 rule: fewer than seven, so the matrix holds the larger of the two values."""
    second = "[records.tremor2]\nseed = 2\ntremor = { duration = 10.0, dt = 0.01, decay = 2.0 }\n"
    path = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",), extra=second)
    out = tmp_path / "out"
    summary = run_experiment(load_experiment(path), out, SerialExecutor())
    assert sorted(summary.computed) == ["M1/tremor/D_0", "M1/tremor2/D_0"]
    with open(out / "cells.csv", newline="") as handle:
        values = [float(r["value"]) for r in csv.DictReader(handle) if r["metric"] == "stress_dynamic.G4"]
    assert len(values) == 2 and values[0] != values[1]
    assert _json(out / "matrices.json")["stress_dynamic.G4"]["M1"]["D_0"] == max(values)
    report = (out / "report.md").read_text()
    assert ('Each entry combines the 2 records (`aggregate = "ec8"`): the most unfavourable (largest) of the records\' '
            "values (EN 1998-1 4.3.3.4.3: the mean of at least seven records, else the most unfavourable)") in report
