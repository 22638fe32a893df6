"""``bearingfw modal`` and ``bearingfw tune`` through the CLI's entry point."""

from __future__ import annotations

import json

import pytest

from bearingfw.bridges.paper import MODES, TABLE2_FE
from bearingfw.cli.main import main


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_modal_json(capsys):
    code, out, _ = run(capsys, "modal", "--json", "--modes", "12")
    assert code == 0
    data = json.loads(out)
    assert data["model"] == "M0"
    assert len(data["modes"]) == 12
    assert all({"frequency", "label"} <= set(m) for m in data["modes"])
    freqs = [m["frequency"] for m in data["modes"]]
    assert freqs == sorted(freqs)
    for name in ("vertical 1", "lateral 1", "vertical 2"):
        entry = data["paper"][name]
        assert entry["frequency"] == pytest.approx(TABLE2_FE[name], rel=0.05)
        assert data["modes"][entry["index"] - 1]["deck_label"] == name


def test_modal_table_and_model_choice(capsys):
    code, out, _ = run(capsys, "modal", "--model", "M1", "--ks", "4e8", "--modes", "6")
    assert code == 0 and "bearing model M1" in out and "vertical 1" in out
    code, _, err = run(capsys, "modal", "--model", "M9")
    assert code == 2 and "--model must be one of" in err


def test_modal_plot_writes_shapes_and_the_mac_heatmap(capsys, tmp_path):
    code, out, _ = run(capsys, "modal", "--modes", "40", "--plot", str(tmp_path), "--json")
    assert code == 0
    data = json.loads(out)
    names = {p.name for p in tmp_path.iterdir()}
    for stem in [f"mode-{m.replace(' ', '-')}" for m in MODES] + ["automac"]:
        assert {f"{stem}.png", f"{stem}.svg"} <= names
    assert all((tmp_path / p.split("/")[-1]).stat().st_size > 1000 for p in data["figures"])


def test_tune_json(capsys, tune_once):
    code, out, _ = run(capsys, "tune", "--json")
    assert code == 0 and tune_once == [None]
    data = json.loads(out)
    assert data["ks_eq11"] == pytest.approx(462e6, rel=0.05)
    assert data["ks_fit"] > 0
    assert set(data["before"]) == set(data["after"]) == set(MODES)
    assert data["error_before"]["lateral 1"] < -0.2
    assert max(abs(e) for e in data["error_after"].values()) < 0.08
    assert data["damping"]["rayleigh_paper_ratios"]["alpha"] == pytest.approx(0.21, abs=0.005)


def test_tune_table(capsys, tune_once):
    code, out, _ = run(capsys, "tune")
    assert code == 0 and tune_once == [None]
    assert "eq. 11" in out and "least squares" in out and "Rayleigh" in out


def test_modal_structure_reference_is_the_model_option(capsys):
    """``--structure reference`` with ``--option preset=M1 --option ks=...`` is ``--model M1 --ks ...``; other
    options are BridgeParameters fields."""
    code, out, _ = run(capsys, "modal", "--model", "M1", "--ks", "4e8", "--modes", "5", "--json")
    assert code == 0
    by_flags = json.loads(out)
    code, out, _ = run(capsys, "modal", "--structure", "reference", "--option", "preset=M1", "--option", "ks=4e8",
                       "--modes", "5", "--json")
    assert code == 0
    by_options = json.loads(out)
    assert by_options["structure"] == by_flags["structure"] == "reference"
    assert (by_options["model"], by_options["ks"]) == ("M1", 4e8)
    assert [m["frequency"] for m in by_options["modes"]] == [m["frequency"] for m in by_flags["modes"]]
    # a heavier deck lowers every frequency
    code, out, _ = run(capsys, "modal", "--option", "superimposed_dead_load=8000", "--modes", "5", "--json")
    assert code == 0
    heavier = json.loads(out)
    assert heavier["options"] == {"superimposed_dead_load": 8000}
    code, out, _ = run(capsys, "modal", "--modes", "5", "--json")
    default = json.loads(out)
    assert all(h["frequency"] < d["frequency"] for h, d in zip(heavier["modes"], default["modes"], strict=True))


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--option", "spanz=[30]"], "unknown option 'spanz' (did you mean spans?)"),
        (["--option", "girder_depth=-1"], "structure 'reference': "),
        (["--ks", "4e8", "--option", "ks=3e8"], "--ks and --option ks=... both give the ks"),
    ],
)
def test_modal_reference_option_errors(capsys, argv, message):
    code, _, err = run(capsys, "modal", *argv)
    assert code == 2 and message in err and "Traceback" not in err
