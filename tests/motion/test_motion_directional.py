"""Records of one, two or three components mapped to x, y, z; verticals refused on x and y."""

import json

import numpy as np
import pytest
from motion_records import CHUETSU, G, MANJIL, RECORDS, at2_values

from bearingfw.cli.main import main
from bearingfw.motion import (
    RecordFormatError,
    VerticalComponentError,
    load_directional,
    read_record,
    record_pga_h10,
    record_t_ha,
)
from bearingfw.motion.vertical import is_vertical_code, label_evidence, name_evidence
from bearingfw.parameters import ParameterError

EW, NS, UD = CHUETSU
L, T, V = MANJIL


def relabelled(source, target, new_label):
    """A copy of a real .AT2 file whose header line 2 names another component (CRLF kept)."""
    lines = source.read_bytes().split(b"\r\n")
    head, _, _ = lines[1].rpartition(b",")
    lines[1] = head + b", " + new_label.encode()
    target.write_bytes(b"\r\n".join(lines))
    return target


def test_one_component_drives_one_direction_and_the_others_are_zero():
    record = load_directional({"y": str(NS)})
    values = np.array(at2_values(NS)) * G
    assert np.array_equal(record.h2, values)
    assert not np.any(record.h1) and not np.any(record.v)
    assert record.directional and record.missing_directions == ("x", "z")
    assert record.names == ("x: none", "y: NS", "z: none")
    assert "no component is mapped to x: its ground acceleration is zero" in record.notes
    assert "no component is mapped to z: its ground acceleration is zero" in record.notes
    assert record.source_units == ("g", "g", "g")
    # PGA_H10 and t_Ha of a single horizontal: its own filtered peak and significant duration.
    from bearingfw.motion import lowpass, significant_duration

    assert record_pga_h10(record) == pytest.approx(np.max(np.abs(lowpass(values, 0.01))), rel=1e-12)
    assert record_t_ha(record) == pytest.approx(significant_duration(values, 0.01), rel=1e-12)


def test_three_components_any_order_with_a_flip(tmp_path):
    record = load_directional({"z": UD.name, "x": f"-{NS.name}", "y": EW.name}, base_dir=RECORDS)
    assert np.array_equal(record.h1, -np.array(at2_values(NS)) * G)
    assert np.array_equal(record.h2, np.array(at2_values(EW)) * G)
    assert np.array_equal(record.v, np.array(at2_values(UD)) * G)
    assert record.names == ("x: -NS", "y: EW", "z: UD") and record.missing_directions == ()
    assert record.metadata["directions"] == {"x": f"-{NS.name}", "y": EW.name, "z": UD.name}
    assert record.source == f"x=-{NS.name}, y={EW.name}, z={UD.name}"


def test_unequal_lengths_are_padded_and_said(tmp_path):
    record = load_directional({"x": str(L), "y": str(T)})
    assert record.n == 2676 and record.lengths == (2676, 2300, 2676)
    assert record.padded_components == ("y: T",)


def test_components_of_a_multi_column_file(tmp_path):
    path = tmp_path / "chuetsu.csv"
    columns = np.column_stack([at2_values(p) for p in CHUETSU])
    with open(path, "w") as handle:
        handle.write("# dt: 0.01\nEW [g], NS [g], UD [g]\n")
        np.savetxt(handle, columns, delimiter=",", fmt="%.9e")
    record = load_directional({"x": f"{path}#2", "z": f"-{path}#3"})
    assert record.h1 == pytest.approx(columns[:, 1] * G, rel=1e-9)
    assert record.v == pytest.approx(-columns[:, 2] * G, rel=1e-9)
    assert record.names == ("x: NS", "y: none", "z: -UD") and record.metadata["readers"] == ["columns"]
    with pytest.raises(ParameterError, match=r"holds 3 components; pick one with '#k'"):
        load_directional({"x": str(path)})
    with pytest.raises(ParameterError, match=r"holds 3 component\(s\); '#4' must be between 1 and 3"):
        load_directional({"x": f"{path}#4"})
    # The column name is the evidence: 'UD' on x is refused.
    with pytest.raises(VerticalComponentError, match=r"its column name 'UD' is a vertical component code"):
        load_directional({"x": f"{path}#3"})


def test_mapping_errors(tmp_path):
    with pytest.raises(ParameterError, match="at least one of x, y, z"):
        load_directional({})
    with pytest.raises(ParameterError, match="unknown direction\\(s\\) 'h1'; the directions are x, y, z"):
        load_directional({"h1": str(EW)})
    with pytest.raises(ParameterError, match="1-based"):
        load_directional({"x": f"{EW}#0"})
    with pytest.raises(ParameterError, match="expected a file path"):
        load_directional({"x": ""})
    with pytest.raises(RecordFormatError, match="nope.AT2: no such file"):
        load_directional({"x": "nope.AT2"}, base_dir=tmp_path)
    with pytest.raises(RecordFormatError, match="is a directory, not a record file"):
        load_directional({"x": str(tmp_path)})


# -- a vertical on a horizontal axis: each kind of evidence, on real files ---------------------


def test_vertical_refused_by_its_file_name(tmp_path):
    # The PEER header is made neutral ('C3'): only the name ...UD.AT2 tells.
    path = relabelled(UD, tmp_path / UD.name, "C3")
    with pytest.raises(VerticalComponentError) as caught:
        load_directional({"x": str(path)})
    error = caught.value
    assert [e.kind for e in error.evidence] == ["file name"] and error.axis == "x"
    assert str(error).startswith(f"{path}: x = ")
    assert f"its file name '{UD.name}' ends in 'UD', a vertical component code" in str(error)
    assert "Map it to z, or set vertical_as_horizontal = true" in str(error)


def test_vertical_refused_by_its_peer_header(tmp_path):
    path = tmp_path / "station-c3.AT2"  # a neutral name; the header says UD
    path.write_bytes(UD.read_bytes())
    with pytest.raises(VerticalComponentError) as caught:
        load_directional({"y": str(path)})
    assert [e.kind for e in caught.value.evidence] == ["header"]
    assert "its PEER header names the component 'UD' (line 2: 'Chuetsu-oki, 7/16/2007, Matsushiro Tokamachi, UD')" in str(
        caught.value
    )


def test_vertical_refused_by_its_amplitudes(tmp_path):
    # Neutral name and header: the Chuetsu-oki vertical is still 0.65 m/s^2 at 3.3 Hz against
    # 1.8 m/s^2 at 1.5 Hz for NS: the amplitudes tell, when the other component is given.
    path = relabelled(UD, tmp_path / "station-c3.AT2", "C3")
    assert load_directional({"x": str(path)}).n == 6000  # alone: nothing to compare with
    with pytest.raises(VerticalComponentError) as caught:
        load_directional({"x": str(path), "y": str(NS)})
    assert [e.kind for e in caught.value.evidence] == ["amplitudes"]
    message = str(caught.value)
    assert "its peak 0.653 m/s^2 is at most 0.6 of the other components'" in message
    assert "dominant frequency 3.32 Hz at least 1.5 times theirs (NS: 1.82 m/s^2 at 1.53 Hz)" in message


def test_amplitudes_say_nothing_about_a_near_source_vertical(tmp_path):
    # Manjil's vertical is as strong as its horizontals: with a neutral name and header it passes
    # (the limitation the docs state); its own name and header refuse it.
    path = relabelled(V, tmp_path / "abbar-c3.AT2", "C3")
    assert load_directional({"x": str(path), "y": str(T), "z": str(L)}).n == 2676
    with pytest.raises(VerticalComponentError) as caught:
        load_directional({"x": str(V), "y": str(T), "z": str(L)})
    assert [e.kind for e in caught.value.evidence] == ["file name", "header"]


@pytest.mark.parametrize("pair", [(EW, NS), (NS, EW), (L, T), (T, L), (EW, L), (T, NS)])
def test_real_horizontals_are_never_taken_for_verticals(pair):
    record = load_directional({"x": str(pair[0]), "y": str(pair[1]), "z": str(UD)})
    assert not any("vertical" in note for note in record.notes)


def test_vertical_as_horizontal_is_taken_with_a_note():
    record = load_directional({"x": str(UD), "y": str(NS)}, vertical_as_horizontal=True)
    assert np.array_equal(record.h1, np.array(at2_values(UD)) * G)
    note = next(n for n in record.notes if "looks vertical" in n)
    assert note.startswith(f"x: {UD.name} looks vertical (its file name") and "(vertical_as_horizontal)" in note


def test_a_vertical_on_z_is_fine_and_legacy_files_only_get_a_note():
    load_directional({"z": str(UD)})
    record = read_record([UD, NS, EW])  # h1, h2, v by position: taken as before, with a note
    assert any(n.startswith(f"{UD.name} is given as horizontal 1 but looks vertical") for n in record.notes)
    assert not any("looks vertical" in n for n in read_record(CHUETSU).notes)


@pytest.mark.parametrize(
    "name, vertical",
    [
        ("RSN1633_MANJIL_ABBAR--V.AT2", True), ("RSN4843_CHUETSU_65006UD.AT2", True), ("NORTHR_SYL-UP.AT2", True),
        ("IMPVALL_H-E06DWN.AT2", True), ("station_HNZ.csv", True), ("quake_z.txt", True), ("TCU068-VER.AT2", True),
        ("RSN1633_MANJIL_ABBAR--L.AT2", False), ("RSN4843_CHUETSU_65006EW.AT2", False), ("NORTHR_SYL360.AT2", False),
        ("station_HNE.csv", False), ("ZAGREB.AT2", False), ("abbar.AT2", False), ("X.AT2", False),
    ],
)
def test_file_name_codes(name, vertical):
    assert (name_evidence(name) is not None) == vertical


def test_label_codes():
    assert label_evidence("az") and label_evidence("acc_z") and label_evidence("VERTICAL ACC") and label_evidence("UP")
    assert not label_evidence("ax") and not label_evidence("EW") and not label_evidence("") and not label_evidence("L")
    assert is_vertical_code("hhz") and not is_vertical_code("HHE")


# -- bearingfw record info --x/--y/--z ---------------------------------------------------------


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_record_info_with_mapped_components(capsys):
    code, out, _ = run(capsys, "record", "info", "--x", str(EW), f"--y=-{NS}", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["directions"] == {"x": str(EW), "y": f"-{NS}"} and data["missing"] == ["z"]
    assert data["pga"]["v"] == 0.0 and data["names"] == ["x: EW", "y: -NS", "z: none"]
    code, out, _ = run(capsys, "record", "info", "--x", str(EW), f"--y=-{NS}")
    assert "components mapped to the axes:" in out and "z: zero" in out


def test_record_info_refuses_a_vertical_on_x(capsys):
    code, _, err = run(capsys, "record", "info", "--x", str(UD))
    assert code == 2 and str(UD) in err and "looks vertical" in err and "ends in 'UD'" in err
    code, _, _ = run(capsys, "record", "info", "--x", str(UD), "--vertical-as-horizontal", "--json")
    assert code == 0
    code, _, err = run(capsys, "record", "info", str(EW), "--x", str(NS))
    assert code == 2 and "not several" in err
    code, _, err = run(capsys, "record", "info", "--synthetic", "1", "--vertical-as-horizontal")
    assert code == 2 and "--vertical-as-horizontal goes with --x/--y/--z" in err
