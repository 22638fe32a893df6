"""The measured-modes file of ``bearingfw tune --measured``: TOML, JSON, ``bearingfw oma`` output; errors named."""

from __future__ import annotations

import json

import numpy as np
import pytest

from bearingfw.oma import IdentifiedMode, IdentifiedModes, write_modes
from bearingfw.parameters import ParameterError
from bearingfw.tuning import from_identified, identified_measurements, measured_modes, read_measured

TOML = """
source = "hand test"
channels = ["N1.uz", "N2.uz"]

[[modes]]
frequency = 2.5
label = "vertical 1"
shape = [1.0, 0.5]
damping = 0.02

[[modes]]
name = "second"
frequency = 4.0
shape = { "N2.uz" = -1.0, "N1.uz" = 1.0 }
"""


def test_toml_with_shapes_pairs_by_mac(tmp_path):
    path = tmp_path / "modes.toml"
    path.write_text(TOML)
    modes = read_measured(path)
    assert modes.pair_by == "mac" and modes.channels == ("N1.uz", "N2.uz")
    assert modes.names == ("vertical 1", "second")
    # an object shape is put in the file's channel order
    np.testing.assert_array_equal(modes.measurements[1].shape, [1.0, -1.0])
    assert modes.damping == {"vertical 1": 0.02, "second": None}
    assert modes.metadata["source"] == "hand test" and modes.metadata["file"] == str(path)
    assert modes.select([2]).names == ("second",) and modes.select(["vertical 1"]).names == ("vertical 1",)
    with pytest.raises(ParameterError, match=r"no measured mode 3; modes: 1 \(vertical 1"):
        modes.select([3])


def test_json_with_labels_pairs_by_label(tmp_path):
    path = tmp_path / "modes.json"
    path.write_text(json.dumps({"modes": [{"frequency": 1.0, "label": "lateral 1"},
                                          {"frequency": 2.0, "label": "vertical 1", "shape": {"N1.uz": 1.0}}]}))
    modes = read_measured(path)
    assert modes.pair_by == "label" and modes.channels is None
    assert [m.label for m in modes.measurements] == ["lateral 1", "vertical 1"]


def test_the_output_of_bearingfw_oma_is_a_measured_modes_file(tmp_path):
    identified = IdentifiedModes(("N1.uz", "N2.uy"), [IdentifiedMode(1.5, 0.02, [1.0, -0.3], poles=12, mpc=0.99)],
                                 {"synthetic": True, "source": "simulated"})
    modes = read_measured(write_modes(identified, tmp_path / "oma.json"))
    assert modes.pair_by == "mac" and modes.names == ("mode 1",) and modes.channels == ("N1.uz", "N2.uy")
    np.testing.assert_array_equal(modes.measurements[0].shape, [1.0, -0.3])
    assert modes.damping == {"mode 1": 0.02} and modes.metadata["synthetic"] is True


@pytest.mark.parametrize(
    "data, message",
    [
        ({}, "non-empty list 'modes'"),
        ({"modes": []}, "non-empty list 'modes'"),
        ({"modes": [{"label": "vertical 1"}]}, "mode 1: field 'frequency' .* is required"),
        ({"modes": [{"frequency": -1.0, "label": "vertical 1"}]}, "must be > 0 Hz"),
        ({"modes": [{"frequency": "2", "label": "vertical 1"}]}, "'frequency' must be a finite number"),
        ({"modes": [{"frequency": 2.0}]}, "give a 'label'"),
        ({"modes": [{"frequency": 2.0, "label": "bending 1"}]}, "mode 1: Measurement: field 'label'"),
        ({"modes": [{"frequency": 2.0, "lable": "vertical 1"}]}, "unknown field.*'lable'.*did you mean label"),
        ({"modes": [{"frequency": 2.0, "shape": [1.0]}]}, "give the file's 'channels'"),
        ({"channels": ["N1.uz"], "modes": [{"frequency": 2.0, "shape": [1.0, 2.0]}]}, "2 values for 1 channels"),
        ({"modes": [{"frequency": 2.0, "shape": {"N1.uw": 1.0}}]}, "channel 'N1.uw' does not name a DOF"),
        ({"modes": [{"frequency": 2.0, "shape": {"N1.uz": 0.0}}]}, "zero at every channel"),
        ({"modes": [{"frequency": 2.0, "shape": {"N1.uz": 1.0}}, {"frequency": 3.0, "shape": {"N2.uz": 1.0}}]},
         r"mode 2: field 'shape' has other channels .* \(missing \['N1.uz'\], extra \['N2.uz'\]\)"),
        ({"channels": ["N1.uz", "N2.uz"], "modes": [{"frequency": 2.0, "shape": {"N1.uz": 1.0}}]},
         r"missing \['N2.uz'\]"),
        ({"modes": [{"frequency": 2.0, "label": "vertical 1"}, {"frequency": 3.0, "shape": {"N1.uz": 1.0}}]},
         "'vertical 1' have no shape and 'mode 2' no label"),
        ({"modes": [{"frequency": 2.0, "label": "vertical 1"}, {"frequency": 3.0, "label": "vertical 1"}]},
         "share the name"),
        ({"channels": ["N1.uz", "N1.uz"], "modes": [{"frequency": 2.0, "label": "vertical 1"}]}, "twice"),
        # two names, one label: both would pair with one computed mode
        ({"modes": [{"frequency": 2.5, "label": "vertical 1", "name": "a"},
                    {"frequency": 2.6, "label": "vertical 1", "name": "b"}]},
         r"need distinct labels.*\('vertical 1': 'a', 'b'\)"),
        ({"modes": [{"frequency": 2.0, "label": "vertical 1", "damping": 2.0}]},
         r"'damping' is a damping ratio, 0 <= damping < 1 \(2 % is 0.02\), got 2.0"),
        ({"modes": [{"frequency": 2.0, "label": "vertical 1", "damping": -0.02}]}, "0 <= damping < 1"),
    ],
)
def test_bad_files_are_named(data, message):
    with pytest.raises(ParameterError, match=message):
        measured_modes(data, where="m.json")


def test_unreadable_files(tmp_path):
    with pytest.raises(ParameterError, match="cannot read"):
        read_measured(tmp_path / "missing.toml")
    (tmp_path / "bad.toml").write_text("[[modes]\n")
    with pytest.raises(ParameterError, match="not TOML"):
        read_measured(tmp_path / "bad.toml")
    (tmp_path / "bad.txt").write_text("frequency = 1")
    with pytest.raises(ParameterError, match="not JSON .* must end in .toml"):
        read_measured(tmp_path / "bad.txt")


def test_a_label_shared_by_modes_paired_by_shape_is_no_matter():
    """By MAC the labels are not used: two modes may carry the same (e.g. as first guessed)."""
    modes = measured_modes({"modes": [{"frequency": 2.5, "label": "vertical 1", "name": "a", "shape": {"N1.uz": 1.0}},
                                      {"frequency": 2.6, "label": "vertical 1", "name": "b", "shape": {"N1.uz": 0.5}}]})
    assert modes.pair_by == "mac"


def test_identified_modes_are_measured_modes_and_select_the_same_way():
    identified = IdentifiedModes(("N1.uz", "N2.uy"), [IdentifiedMode(1.5, 0.02, [1.0, -0.3]),
                                                      IdentifiedMode(2.5, 0.03, [0.2, 1.0], name="sway")],
                                 {"synthetic": True, "source": "simulated", "dt": 0.02})
    modes = from_identified(identified)
    assert modes.pair_by == "mac" and modes.channels == ("N1.uz", "N2.uy") and modes.names == ("mode 1", "sway")
    assert modes.damping == {"mode 1": 0.02, "sway": 0.03}
    assert modes.metadata == {"synthetic": True, "source": "simulated"}
    measurements, channels = identified_measurements(identified, ["sway", 1])
    assert [m.name for m in measurements] == ["sway", "mode 1"] and channels == ("N1.uz", "N2.uy")
    with pytest.raises(ParameterError, match=r"^identified_measurements: a mode is chosen twice"):
        identified_measurements(identified, [1, "mode 1"])
    with pytest.raises(ParameterError, match=r"^--modes: no measured mode 'sways'; modes: 1 \(mode 1, 1.500 Hz\)"):
        modes.select(["sways"])
