"""Measured-mode files and OMA mode files saved with a UTF-8 BOM (as Windows editors save them) are
read as without it (they failed at line 1, column 1, like study files did)."""

from __future__ import annotations

import json

from bearingfw.oma import IdentifiedMode, IdentifiedModes, read_modes, write_modes
from bearingfw.tuning import read_measured

BOM = "\ufeff"


def test_a_measured_modes_file_with_a_bom_reads_as_without(tmp_path):
    text = json.dumps({"modes": [{"frequency": 1.0, "label": "lateral 1"}, {"frequency": 2.0, "label": "vertical 1"}]})
    plain, marked = tmp_path / "plain.json", tmp_path / "marked.json"
    plain.write_text(text, encoding="utf-8")
    marked.write_text(BOM + text, encoding="utf-8")
    assert [m.label for m in read_measured(marked).measurements] == ["lateral 1", "vertical 1"]
    toml = 'pair_by = "label"\n[[modes]]\nfrequency = 1.0\nlabel = "lateral 1"\n'
    (tmp_path / "marked.toml").write_text(BOM + toml, encoding="utf-8")
    assert [m.frequency for m in read_measured(tmp_path / "marked.toml").measurements] == [1.0]


def test_an_oma_modes_file_with_a_bom_reads_as_without(tmp_path):
    identified = IdentifiedModes(("N1.uz",), [IdentifiedMode(1.5, 0.02, [1.0], poles=12, mpc=0.99)], {"source": "test"})
    path = write_modes(identified, tmp_path / "oma.json")
    path.write_text(BOM + path.read_text(encoding="utf-8"), encoding="utf-8")
    assert read_modes(path).modes[0].frequency == 1.5
