"""Channel files in (CSV, NPZ), identified modes out (JSON), channel names as model DOFs."""

from __future__ import annotations

import json

import numpy as np
import pytest
from oma_systems import column_model

from bearingfw.motion import G, RecordFormatError
from bearingfw.oma import (
    Channels,
    IdentifiedMode,
    IdentifiedModes,
    channel_dofs,
    parse_channel,
    read_channels,
    read_modes,
    write_modes,
)
from bearingfw.parameters import ParameterError


def sample(n: int = 50) -> Channels:
    rng = np.random.default_rng(2)
    return Channels(rng.standard_normal((n, 3)), 0.01, ("GA4.uz", "GB4.uz", "P2A.0.uy"), source="test")


def test_channel_names_are_node_dot_component():
    assert parse_channel("GA32.uz") == ("GA32", "uz")
    assert parse_channel("P2A.0.UY") == ("P2A.0", "uy")
    for bad in ("GA32", "GA32.z", ".uz", "GA32.uz."):
        with pytest.raises(ParameterError, match="does not name a DOF"):
            parse_channel(bad)


def test_channel_dofs_in_a_model():
    model = column_model()
    dofs = channel_dofs(model, ["C3.uy", "C6.ux"])
    assert [model.dofmap.describe(d) for d in dofs] == ["C3.uy", "C6.ux"]
    with pytest.raises(ParameterError, match="channel 'X1.uz': the model has no node 'X1'"):
        channel_dofs(model, ["X1.uz"])


@pytest.mark.parametrize("writer", ["to_npz", "to_csv"])
def test_channels_round_trip(tmp_path, writer):
    data = sample()
    path = getattr(data, writer)(tmp_path / f"record.{writer[3:]}")
    back = read_channels(path)
    assert back.names == data.names and back.dt == pytest.approx(data.dt)
    np.testing.assert_allclose(back.data, data.data, rtol=1e-9)
    assert back.metadata["units_stated"] is True and back.units == "m/s^2"


def test_units_are_converted_and_optional(tmp_path):
    csv = tmp_path / "g.csv"
    csv.write_text("# units: g\ntime,A.uz,B.uz\n0,0.1,0.2\n0.01,0.3,0.4\n0.02,0.5,0.6\n")
    back = read_channels(csv)
    np.testing.assert_allclose(back.data[0], [0.1 * G, 0.2 * G])
    bare = tmp_path / "bare.csv"
    bare.write_text("time,A.uz,B.uz\n0,0.1,0.2\n0.01,0.3,0.4\n0.02,0.5,0.6\n")
    back = read_channels(bare)
    np.testing.assert_allclose(back.data[0], [0.1, 0.2])
    assert back.metadata["units_stated"] is False and "m/s^2" in back.metadata["note"]


def test_a_file_without_time_step_or_names_is_an_error(tmp_path):
    nodt = tmp_path / "nodt.csv"
    nodt.write_text("A.uz,B.uz\n0.1,0.2\n0.3,0.4\n0.5,0.6\n")
    with pytest.raises(RecordFormatError, match="dt"):
        read_channels(nodt)
    assert read_channels(nodt, dt=0.02).dt == 0.02
    nameless = tmp_path / "nameless.csv"
    nameless.write_text("# dt: 0.01\n# units: m/s^2\n0.1,0.2\n-0.3,0.4\n0.5,0.6\n")
    with pytest.raises(RecordFormatError, match="no name"):
        read_channels(nameless)


def test_select_and_validation():
    data = sample()
    assert data.select(["P2A.0.uy", "GA4.uz"]).names == ("P2A.0.uy", "GA4.uz")
    with pytest.raises(ParameterError, match="no channel 'nope'"):
        data.select(["nope"])
    with pytest.raises(ParameterError, match="distinct"):
        Channels(np.zeros((5, 2)), 0.01, ("a.ux", "a.ux"))
    with pytest.raises(ParameterError, match="2 names for 3 channels"):
        Channels(np.zeros((5, 3)), 0.01, ("a.ux", "b.ux"))


def identified() -> IdentifiedModes:
    modes = [IdentifiedMode(1.5, 0.02, [1.0, -0.5, 0.1], poles=9), IdentifiedMode(3.4, 0.03, [0.2, 1.0, -0.3])]
    return IdentifiedModes(("GA4.uz", "GB4.uz", "GA8.uy"), modes, {"source": "test"})


def test_modes_round_trip_through_json(tmp_path):
    path = write_modes(identified(), tmp_path / "modes.json")
    data = json.loads(path.read_text())
    assert data["format"] == "bearingfw-oma-modes" and data["source"] == "test"
    assert data["modes"][0]["shape"] == {"GA4.uz": 1.0, "GB4.uz": -0.5, "GA8.uy": 0.1}
    back = read_modes(path)
    assert [m.name for m in back.modes] == ["mode 1", "mode 2"]
    np.testing.assert_allclose(back.shapes, identified().shapes)
    np.testing.assert_allclose(back.frequencies, [1.5, 3.4])
    assert back.modes[0].poles == 9


def test_a_hand_written_modes_file_needs_only_frequencies_and_shapes(tmp_path):
    path = tmp_path / "hand.json"
    path.write_text(json.dumps({"modes": [{"frequency": 2.3, "shape": {"GA32.uy": 1.0, "GA32.uz": 0.1}}]}))
    back = read_modes(path)
    assert back.channels == ("GA32.uy", "GA32.uz") and back.modes[0].damping == 0.0


@pytest.mark.parametrize(
    "content, message",
    [
        ("not json", "not JSON"),
        (json.dumps({"mode": []}), "'modes' list"),
        (json.dumps({"channels": ["a.uz"], "modes": [{"frequency": 1.0, "shape": {"b.uz": 1.0}}]}), "missing"),
        (json.dumps({"modes": [{"shape": {"a.uz": 1.0}}]}), "needs 'frequency'"),
        (json.dumps({"modes": [{"frequency": "x", "shape": {"a.uz": 1.0}}]}), "must be numbers"),
    ],
)
def test_bad_modes_files_are_named(tmp_path, content, message):
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(ParameterError, match=message):
        read_modes(path)


def test_an_npz_without_names_names_its_channels_by_their_arrays(tmp_path):
    rng = np.random.default_rng(3)
    path = tmp_path / "bare.npz"
    np.savez(path, dt=0.01, **{"GA4.uz": rng.standard_normal(50), "GB4.uz": rng.standard_normal(50)})
    back = read_channels(path)
    assert back.names == ("GA4.uz", "GB4.uz") and back.dt == 0.01
