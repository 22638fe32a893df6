"""examples/ambient-oma: the simulated ambient data set of the reference bridge, through the README's commands
(``bearingfw oma`` then ``bearingfw tune --measured``): the identified frequencies are the model's, and the
fit finds the K_s the data were simulated with."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from bearingfw.analysis import mac, solve_modal
from bearingfw.bridges import DEFAULT_KS, reference_bridge
from bearingfw.cli.main import main
from bearingfw.oma import channel_dofs, read_channels

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "ambient-oma"
DATA = EXAMPLE / "ambient.npz"


def _script():
    sys.path.insert(0, str(EXAMPLE))
    try:
        import simulate_ambient
    finally:
        sys.path.remove(str(EXAMPLE))
    return simulate_ambient


def test_the_data_set_is_small_labelled_simulated_and_what_the_script_writes(tmp_path):
    assert DATA.stat().st_size < 400_000
    record = read_channels(DATA)
    assert record.synthetic and "SIMULATED" in record.source and "not a measurement" in record.source
    assert record.n_channels == 14 and all(n.startswith("GA") for n in record.names)
    script = _script()
    again = script.write(*script.simulate(), tmp_path / "again.npz")
    np.testing.assert_array_equal(read_channels(again).data, record.data)  # seeded: the file is reproducible
    assert "SIMULATED" in (EXAMPLE / "README.md").read_text()


@pytest.mark.slow
def test_oma_then_tune_find_the_models_modes_and_its_ks(tmp_path, capsys):
    """About 40 s: the README's two commands as a user runs them."""
    modes = tmp_path / "modes.json"
    assert main(["oma", str(DATA), "--structure", "reference", "--fmax", "5", "--output", str(modes), "--json"]) == 0
    identified = json.loads(capsys.readouterr().out)["modes"]
    record = read_channels(DATA)
    modal = solve_modal(reference_bridge("M1", ks=DEFAULT_KS), 40)
    computed = modal.shapes[channel_dofs(modal.system, record.names)]
    assert len(identified) >= 3
    for mode in identified:  # each one is a mode of the model: MAC > 0.95, frequency within 1 %
        shape = np.array([mode["shape"][c] for c in record.names])
        table = mac(shape[:, None], computed)[0]
        best = int(np.argmax(table))
        assert table[best] > 0.95 and mode["frequency"] == pytest.approx(modal.frequencies[best], rel=0.01)

    assert main(["tune", "--measured", str(modes), "--json"]) == 0
    fit = json.loads(capsys.readouterr().out)
    assert fit["synthetic"] and fit["dropped"] == []
    assert {"vertical 1", "lateral 1", "vertical 2"} <= set(fit["label_after"].values())
    assert fit["ks_fit"] == pytest.approx(DEFAULT_KS, rel=0.05)  # 388.7 MN/m against 400
    assert max(abs(e) for e in fit["error_after"].values()) < 0.01
