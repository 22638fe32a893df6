"""Spatially varying records in the experiment (``[records.<name>.spatial]``): the digest, the errors, a
wave-passage cell run from TOML, interrupted and resumed, its differential displacements against a hand
computation, uniform motion through the per-support path bit for bit, and per-group record files."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest
from tiny_experiment import write_tiny

import bearingfw.experiment.executors as executors
from bearingfw.experiment import SerialExecutor, Store, load_experiment, run_experiment
from bearingfw.experiment.cells import canonical_json
from bearingfw.experiment.records import (
    SpatialGround,
    ground_motion,
    load_record,
    record_inputs,
    scaled_record,
    spatial_spec,
)
from bearingfw.experiment.spec import SpecError
from bearingfw.experiment.structure import build_model, import_paths, registry_for
from bearingfw.model import as_system

RECORDS = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"
MANJIL = [RECORDS / f"RSN1633_MANJIL_ABBAR--{c}.AT2" for c in "LTV"]

#: record_inputs of these entries before ``spatial`` existed (canonical JSON, SHA-256): an entry without a
#: spatial table must keep them, so that no existing cell is computed again because of the new field.
BEFORE = {
    "tremor": "8903d36baeb64cced6377c31c2e3f09642f61ffc939c34c796fe1076f58afe0a",
    "manjil": "5fde2499f8eca6ee4df94745aeb9cd0a26ae549e948068d975681e74101ffdaf",
    "mapped": "5f861f12285e6a88671001cf9d80d6f792ee71e7b9837e5baba71de5274a1640",
}
FILE_RECORDS = f"""
[records.manjil]
files = ["{MANJIL[0].as_posix()}", "{MANJIL[1].as_posix()}", "{MANJIL[2].as_posix()}"]
[records.mapped]
x = "{MANJIL[0].as_posix()}"
y = "-{MANJIL[1].as_posix()}"
"""


def _hash(data) -> str:
    return hashlib.sha256(canonical_json(data).encode()).hexdigest()


def test_entries_without_spatial_keep_their_record_inputs(tmp_path):
    experiment = load_experiment(write_tiny(tmp_path, models=("M1",), levels=("D_0",), extra=FILE_RECORDS))
    assert {r.name: _hash(record_inputs(experiment, r)) for r in experiment.records} == BEFORE


def _with_spatial(tmp_path, table: str, name="tiny"):
    text = f"[records.tremor.spatial]\n{table}\n\n[intensities]"
    return write_tiny(tmp_path / name, models=("M1",), levels=("D_0",), **{"[intensities]": text})


def test_the_spatial_table_is_an_input(tmp_path):
    def inputs(table, name):
        experiment = load_experiment(_with_spatial(tmp_path, table, name))
        return _hash(record_inputs(experiment, experiment.record("tremor")))

    plain = inputs("", "plain")
    wave = inputs("apparent_velocity = 500.0", "wave")
    faster = inputs("apparent_velocity = 800.0", "faster")
    coherent = inputs('apparent_velocity = 500.0\ncoherency = "luco-wong"\nseed = 3', "coh")
    other_seed = inputs('apparent_velocity = 500.0\ncoherency = "luco-wong"\nseed = 4', "coh4")
    params = inputs('apparent_velocity = 500.0\ncoherency = "luco-wong"\nseed = 3\nparams = { lw_a = 3e-4 }', "par")
    assert plain == BEFORE["tremor"]  # an empty table is no table
    assert len({plain, wave, faster, coherent, other_seed, params}) == 6


def test_a_group_record_file_is_hashed_by_content(tmp_path):
    table = ('groups = { west = ["1A.seat", "1B.seat"], pier = ["P0"], east = ["3A.seat", "3B.seat"] }\n'
             '[records.tremor.spatial.motions.east]\nx = "FILE"')
    first, second = tmp_path / "a.AT2", tmp_path / "b.AT2"
    first.write_bytes(MANJIL[0].read_bytes())
    second.write_bytes(MANJIL[0].read_bytes().replace(b".1647381E-02", b".1647382E-02", 1))
    digests = []
    for k, path in enumerate((first, second, first)):
        experiment = load_experiment(_with_spatial(tmp_path, table.replace("FILE", path.as_posix()), f"g{k}"))
        digests.append(_hash(record_inputs(experiment, experiment.record("tremor"))))
    assert digests[0] == digests[2] != digests[1]


@pytest.mark.parametrize(("table", "message"), [
    ("apparent_velocity = -5.0", r"records\.tremor\.spatial\.apparent_velocity: .*outside the allowed range"),
    ('coherency = "gauss"', r"records\.tremor\.spatial\.coherency: .*one of 'none', 'harichandran-vanmarcke'"),
    ("azimuth = 400.0", r"records\.tremor\.spatial\.azimuth: .*-360"),
    ("seed = -1", r"records\.tremor\.spatial\.seed"),
    ('coherency = "luco-wong"\nparams = { lw_a = 1.0 }', r"records\.tremor\.spatial\.params\.lw_a: .*outside"),
    ('coherency = "luco-wong"\nparams = { speed = 1.0 }', r"records\.tremor\.spatial\.params\.speed: unknown key"),
    ("velocity = 500.0", r"records\.tremor\.spatial\.velocity: unknown key; allowed in .*apparent_velocity"),
    ('axis = "z"', r"records\.tremor\.spatial\.axis: .*one of 'x', 'y'"),
    ("tolerance = -1.0", r"records\.tremor\.spatial\.tolerance: .*outside the allowed range"),
    ('groups = "by-pier"', r"records\.tremor\.spatial\.groups: .*\"auto\""),
    ('groups = { a = ["1A.seat"], b = ["1A.seat"] }', r"records\.tremor\.spatial\.groups: .*puts node '1A.seat' in"),
    ('groups = { a = ["1A.seat"] }\nreference = "b"', r"records\.tremor\.spatial: .*'reference' names group 'b'"),
    ('apparent_velocity = 500.0\n[records.tremor.spatial.motions.S2]\nfiles = ["x.AT2", "y.AT2", "z.AT2"]',
     r"records\.tremor\.spatial: .*not both"),
    ("[records.tremor.spatial.motions.S2]\nseed = 2\nspatial = { apparent_velocity = 1.0 }",
     r"records\.tremor\.spatial\.motions\.S2\.spatial: not allowed"),
    ('[records.tremor.spatial.motions.S2]\nfiles = ["missing1.AT2", "missing2.AT2", "missing3.AT2"]',
     r"records\.tremor\.spatial\.motions\.S2: .*missing1\.AT2"),
])
def test_bad_spatial_entries_name_the_key_and_the_range(tmp_path, table, message):
    experiment = load_experiment(_with_spatial(tmp_path, table))
    with pytest.raises(SpecError, match=message):
        load_record(experiment, experiment.record("tremor"))


# ---- a run ----------------------------------------------------------------------------------------------------
#: Three records of the same tremor: uniform as ever; "per support" without variation (the per-support
#: path with every group alike); and a wave at 480 m/s along the 48 m bridge: 0.1 s = 10 samples from
#: abutment to abutment, so that the delay is an exact shift, without baseline correction (checked by hand).
RECORDS_TOML = """
[records.same]
seed = 1
tremor = { duration = 10.0, dt = 0.01, decay = 2.0 }
spatial = { groups = "auto" }

[records.wave]
seed = 1
tremor = { duration = 10.0, dt = 0.01, decay = 2.0 }
spatial = { apparent_velocity = 480.0, baseline = "none" }

[intensities]"""


def _spec(folder):
    return write_tiny(folder, models=("M2",), levels=("D_II",), **{
        "[intensities]": RECORDS_TOML,
        'table = ["stress.G4"': 'table = ["bearing_force.3B", "stress.G4"'})


@pytest.fixture(scope="module")
def runs(tmp_path_factory, request):
    """The experiment interrupted (Ctrl-C) while its second cell computes, then run again; and run whole."""
    folder = tmp_path_factory.mktemp("wave")
    experiment = load_experiment(_spec(folder / "spec"))
    real = executors.compute_and_store
    calls = []

    def interrupted(job, root):
        calls.append(job.id)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(job, root)

    monkeypatch = pytest.MonkeyPatch()
    monkeypatch.setattr(executors, "compute_and_store", interrupted)
    try:
        with pytest.raises(KeyboardInterrupt):
            run_experiment(experiment, folder / "out", SerialExecutor())
    finally:
        monkeypatch.undo()
    resumed = run_experiment(experiment, folder / "out", SerialExecutor())
    whole = run_experiment(experiment, folder / "whole", SerialExecutor())
    return experiment, folder, calls, resumed, whole


def _cell(out, cell_id):
    return json.loads((out / "cells" / f"{cell_id}.json").read_text())


def test_a_wave_passage_cell_is_resumed_like_any_cell(runs):
    experiment, folder, calls, resumed, whole = runs
    assert calls == ["M2/tremor/D_II", "M2/same/D_II"]  # the second cell was interrupted
    assert resumed.skipped == ("M2/tremor/D_II",)
    assert set(resumed.computed) == {"M2/same/D_II", "M2/wave/D_II"} and resumed.exit_code == 0
    assert (folder / "out" / "matrices.json").read_bytes() == (folder / "whole" / "matrices.json").read_bytes()
    for cell in ("M2/same/D_II", "M2/wave/D_II"):
        assert _cell(folder / "out", cell)["metrics"] == _cell(folder / "whole", cell)["metrics"]  # seeded, exact
    again = run_experiment(experiment, folder / "out", SerialExecutor())
    assert again.computed == () and len(again.skipped) == 3


def test_the_report_shows_the_differential_displacements(runs):
    _, folder, _, _, _ = runs
    report = (folder / "out" / "report.md").read_text()
    wave = _cell(folder / "out", "M2/wave/D_II")["metrics"]
    assert "## Support motion" in report
    assert "wave passage at an apparent velocity of 480 m/s towards azimuth 0 deg" in report
    dx = wave["differential_displacement.x"]
    assert dx["at"] == "support1-support3" and dx["unit"] == "m" and dx["value"] > 1e-4
    assert f"| M2/wave/D_II | {dx['value'] * 1e3:.4g} (support1-support3) |" in report
    assert "`bearing_force.3B` [kN]" in report  # the table's metrics per record, uniform beside the wave
    units = json.loads((folder / "out" / "units.json").read_text())["matrices.json"]
    assert units["differential_displacement.x"] == "m" and units["quasi_static_share.3B"] == "-"
    rows = [line.split(",") for line in (folder / "out" / "cells.csv").read_text().splitlines()]
    row = next(r for r in rows if r[:3] == ["M2", "wave", "D_II"] and r[5] == "differential_displacement.x")
    assert float(row[6]) == dx["value"] and row[7] == "m" and row[9] == "support1-support3"


def test_uniform_motion_through_the_per_support_path_is_bit_for_bit_the_uniform_run(runs):
    _, folder, _, _, _ = runs
    uniform, same = _cell(folder / "out", "M2/tremor/D_II")["metrics"], _cell(folder / "out", "M2/same/D_II")["metrics"]
    assert "differential_displacement.x" not in uniform  # a uniform record records no support motion
    for name, metric in uniform.items():
        assert same[name] == metric, name  # value, time and place: identical
    assert all(same[f"differential_displacement.{d}"]["value"] == 0.0 for d in "xyz")
    assert all(same[k]["value"] in (0.0, None) for k in same if k.startswith("quasi_static_share."))
    histories = Store(folder / "out").read_histories("M2/same/D_II")[0]
    assert np.array_equal(histories["ground.acceleration"],
                          Store(folder / "out").read_histories("M2/tremor/D_II")[0]["ground.acceleration"])


def test_differential_displacements_equal_the_hand_computed_delayed_motion(runs):
    """S3 (x = 48 m) gets the record 0.1 s after S1 (x = 0); without baseline correction the differential
    displacement is the exact double integral of a(t - 0.1) - a(t): its peak in x, y, z is the metric."""
    experiment, folder, _, _, _ = runs
    spec = experiment.record("wave")
    record = scaled_record(load_record(experiment, spec), _intensity(experiment), experiment.intensities,
                           experiment.integration.dt_integration)
    a = np.column_stack([record.h1, record.h2, record.v])
    shifted = np.vstack([np.zeros((10, 3)), a])
    padded = np.vstack([a, np.zeros((10, 3))])
    u = _displacement(shifted - padded, record.dt)
    metrics = _cell(folder / "out", "M2/wave/D_II")["metrics"]
    for d, direction in enumerate("xyz"):
        k = int(np.argmax(np.abs(u[:, d])))
        assert metrics[f"differential_displacement.{direction}"]["value"] == pytest.approx(abs(u[k, d]), rel=1e-9)
        assert metrics[f"differential_displacement.{direction}"]["time"] == pytest.approx(k * record.dt, abs=1e-9)
    histories = Store(folder / "out").read_histories("M2/wave/D_II")[0]
    np.testing.assert_allclose(histories["supports.displacement"][:, 2], u[: histories["supports.displacement"].shape[0]],
                               atol=1e-7 * np.abs(u).max())  # S3 minus S1 (float32 in the file)


def _displacement(a, h):
    """Displacement from rest of an acceleration linear between samples (a step-by-step loop, by hand)."""
    u, v = np.zeros_like(a), np.zeros(a.shape[1])
    for n in range(a.shape[0] - 1):
        u[n + 1] = u[n] + h * v + h * h * (2 * a[n] + a[n + 1]) / 6
        v = v + h * (a[n] + a[n + 1]) / 2
    return u


def _intensity(experiment):
    from bearingfw.experiment.structure import resolved_setup

    intensities, _ = resolved_setup(experiment, registry_for(experiment.plugins, import_paths(experiment)))
    return intensities[0]


def test_group_records_replace_the_record_at_their_groups_only(tmp_path):
    """``motions``: the east abutment gets the Manjil record (resampled to the run's step, times the entry's scale
    factor), the others the tremor; the reference is the first group moving with the entry's record."""
    table = (f'groups = {{ west = ["1A.seat", "1B.seat"], pier = ["P0"], east = ["3A.seat", "3B.seat"] }}\n'
             f'[records.tremor.spatial.motions.east]\nfiles = ["{MANJIL[0].as_posix()}", "{MANJIL[1].as_posix()}", '
             f'"{MANJIL[2].as_posix()}"]')
    experiment = load_experiment(_with_spatial(tmp_path, table))
    spec = experiment.record("tremor")
    assert set(spatial_spec(spec).motions) == {"east"}
    record = scaled_record(load_record(experiment, spec), _intensity(experiment), experiment.intensities,
                           experiment.integration.dt_integration)
    ground = ground_motion(experiment, spec, record)
    assert isinstance(ground, SpatialGround) and np.array_equal(np.asarray(ground), np.column_stack(
        [record.h1, record.h2, record.v]))
    registry = registry_for(experiment.plugins, import_paths(experiment))
    model = build_model(experiment, experiment.model("M1"), registry)
    motion = ground.support_motion(as_system(model, registry), record.dt)
    assert motion.reference_group == "west" and list(motion.groups) == ["west", "pier", "east"]
    manjil = load_record(experiment, spatial_spec(spec).motions["east"]).resampled(record.dt)
    factor = record.metadata["scale_factor"]
    east = motion.acceleration["east"]
    assert east.shape[0] == max(manjil.n, record.n)
    np.testing.assert_allclose(east[: manjil.n, 0], factor * manjil.h1, rtol=1e-12)
    np.testing.assert_array_equal(motion.acceleration["pier"][: record.n], np.asarray(ground))
    assert not np.any(motion.acceleration["pier"][record.n:])  # padded with zeros


def test_unknown_groups_are_refused_when_the_structure_is_known(tmp_path):
    experiment = load_experiment(_with_spatial(tmp_path, 'reference = "S9"\napparent_velocity = 500.0'))
    spec = experiment.record("tremor")
    record = load_record(experiment, spec)
    registry = registry_for(experiment.plugins, import_paths(experiment))
    system = as_system(build_model(experiment, experiment.model("M1"), registry), registry)
    with pytest.raises(ValueError, match=r"records\.tremor\.spatial: names group\(s\) \['S9'\].*\['support1', 'support2', 'support3'\]"):
        ground_motion(experiment, spec, record).support_motion(system, record.dt)



def test_the_paper_study_wave_passage_example_is_valid():
    """examples/paper-study/wave-passage.toml: M0/M1/M2 under the uniform tremor and three apparent velocities,
    every model built and every record read by the runner's checks."""
    from bearingfw.experiment import check_experiment, plan_cells

    path = Path(__file__).resolve().parents[2] / "examples" / "paper-study" / "wave-passage.toml"
    experiment = load_experiment(path)
    checked = check_experiment(experiment)
    assert len(plan_cells(experiment)) == 24
    velocities = {r.name: (spatial_spec(r).variation.apparent_velocity if r.spatial else None)
                  for r in experiment.records}
    assert velocities == {"uniform": None, "wave-250": 250.0, "wave-500": 500.0, "wave-1000": 1000.0}
    assert any("250 m/s" in note for note in checked.records["wave-250"].notes)
