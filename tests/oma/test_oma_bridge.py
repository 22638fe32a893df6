"""A simulated ambient test of the reference bridge at the paper's P1..P7, identified and fed to 'bearingfw tune'.

The bridge is the tuned M1 model (linear springs K_s on the sliding directions, K_s the paper's
400 MN/m) with the paper's Rayleigh damping as the transient analysis applies it, excited by a
white-noise support acceleration alone (the issue's ambient test). Everything is compared with
the model's own modal analysis at run time (the geometry may change), never with fixed numbers.
The record goes through the commands as a user would run them: ``bearingfw oma FILE --fmax 5``
(default order and criteria; 5 Hz read off the spectrum, not from the model), then
``bearingfw tune --measured``.

Over seeds 1-9 of this record (``/tmp``-free: rerun with ``seed=k``): the three modes within
0.4 % in frequency and MAC > 0.99; damping within 16 % except once (lateral 1, +21 %, seed 2);
no identified mode that is not the model's. Seed 1 is the one tested.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from oma_systems import BRIDGE_DT, BRIDGE_DURATION, BRIDGE_FMAX, BRIDGE_GROUND

from bearingfw.analysis import Rayleigh, mac, solve_modal
from bearingfw.bridges import DEFAULT_KS, BridgeParameters, reference_bridge
from bearingfw.bridges.paper import RAYLEIGH
from bearingfw.bridges.study import deck_observation, paper_sensors
from bearingfw.cli.main import main
from bearingfw.oma import channel_dofs, modal_damping, simulate_ambient
from bearingfw.tuning import observed_modes

#: The Table 2 modes the deck sensors identify in this model. (Its "torsional 1", near 14 Hz,
#: moves mostly the arches: about a quarter of its kinetic energy is in the deck, and the deck
#: sensors see it some thirty times more weakly than its neighbours; it is not identified.)
IDENTIFIED = ("vertical 1", "lateral 1", "vertical 2")


@pytest.fixture(scope="module")
def bridge():
    params = BridgeParameters()
    modal = solve_modal(reference_bridge("M1", ks=DEFAULT_KS, params=params), 60)
    channels = [c for point in paper_sensors(params).values() for c in point]
    record = simulate_ambient(
        modal, channels, BRIDGE_DURATION, BRIDGE_DT, damping=Rayleigh(*RAYLEIGH), ground=BRIDGE_GROUND, seed=1
    )
    seen = observed_modes(modal, deck_observation(params)).numbered
    return params, modal, record, seen


@pytest.fixture(scope="module")
def identified(bridge, tmp_path_factory):
    """``bearingfw oma FILE --fmax 5 --output modes.json --json``: the printed object and the modes file."""
    _, _, record, _ = bridge
    folder = tmp_path_factory.mktemp("bridge")
    data = record.to_npz(folder / "ambient.npz")
    modes = folder / "modes.json"
    argv = ["oma", str(data), "--fmax", str(BRIDGE_FMAX), "--output", str(modes), "--json"]
    return argv, modes


def test_the_paper_sensors_are_deck_channels_of_the_model(bridge):
    params, modal, record, _ = bridge
    points = paper_sensors(params)
    assert list(points) == [f"P{k}" for k in range(1, 8)]
    assert record.n_channels == 28 and record.synthetic
    assert record.metadata["loads_rms"] == {} and record.metadata["ground_rms"] == list(BRIDGE_GROUND)
    dofs = channel_dofs(modal.system, record.names)
    assert np.unique(dofs).size == 28
    x = {
        p: modal.system.model.coordinates[modal.system.model.node_index(c[0].split(".")[0])][0]
        for p, c in points.items()
    }
    axes = params.axis_positions
    assert x["P2"] == pytest.approx(axes[1]) and x["P5"] == pytest.approx(axes[2])
    assert x["P1"] < x["P2"] < x["P3"] < x["P4"] < x["P5"] < x["P6"] < x["P7"]
    assert x["P6"] - axes[2] == pytest.approx(18.22, abs=params.element_length / 2)


def test_table_2_modes_are_identified_within_1_percent_20_percent_and_mac_095(bridge, identified, capsys):
    _, modal, record, seen = bridge
    argv, _ = identified
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["ssi"]["max_order"] == 60 and data["dt_analysed"] > record.dt  # the defaults, band-limited
    frequencies = np.array([m["frequency"] for m in data["modes"]])
    damping = np.array([m["damping"] for m in data["modes"]])
    shapes = np.array([[m["shape"][c] for c in record.names] for m in data["modes"]])
    computed = modal.shapes[channel_dofs(modal.system, record.names)]
    zeta = modal_damping(modal, Rayleigh(*RAYLEIGH))
    table = mac(shapes.T, computed)
    for name in IDENTIFIED:
        m = seen[name]
        best = int(np.argmax(table[:, m]))
        assert table[best, m] > 0.95, name
        assert frequencies[best] == pytest.approx(modal.frequencies[m], rel=0.01), name
        assert damping[best] == pytest.approx(zeta[m], rel=0.20), name
    # every identified mode is one of the model's: MAC > 0.95 with a mode within 1 % of its frequency
    for k, f in enumerate(frequencies):
        near = np.abs(modal.frequencies / f - 1) < 0.01
        assert np.any(table[k, near] > 0.95), f
    assert data["warnings"] == []


def test_tune_recovers_ks_from_the_identified_modes_and_drops_a_spurious_one(bridge, identified, capsys):
    """'bearingfw oma', then 'bearingfw tune --measured': K_s within 10 % of the model's.

    A spurious mode (2.9 Hz, a shape like no mode's) is added to the modes file: it must be
    left out and named, not drive K_s to a bound.
    """
    _, _, record, _ = bridge
    argv, modes = identified
    if not modes.exists():
        assert main(argv) == 0
    content = json.loads(modes.read_text())
    shape = np.random.default_rng(0).standard_normal(len(record.names))
    content["modes"].append(
        {"name": "spurious", "frequency": 2.9, "damping": 0.02, "shape": dict(zip(record.names, shape.tolist()))}
    )
    modes.write_text(json.dumps(content))
    capsys.readouterr()
    assert main(["tune", "--measured", str(modes), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["ks_fit"] == pytest.approx(DEFAULT_KS, rel=0.10)
    assert [d["name"] for d in out["dropped"]] == ["spurious"] and out["dropped"][0]["best_mac"] < 0.5
    assert any("spurious" in w for w in out["warnings"])
    assert "spurious" not in out["measured"]
    labels = out["label_after"].values()
    assert set(IDENTIFIED) <= set(labels)
    assert all(v > 0.9 for v in out["mac_after"].values())
    # the first lateral mode carries K_s among Table 2's: its sensitivity is the largest of the three
    s = {out["label_after"][n]: out["sensitivity"][n] for n in out["sensitivity"]}
    assert s["lateral 1"] > 10 * max(abs(s["vertical 1"]), abs(s["vertical 2"]))
