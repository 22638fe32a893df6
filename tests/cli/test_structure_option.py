"""Your structure everywhere: ``bearingfw.structures`` and ``--structure``/``--option`` on modal, oma and tune.

The path of ``examples/small-bridge`` from the command line alone: modes of the user's bridge,
simulated ambient data at named channels -> ``oma`` -> ``tune`` recovering the bearing stiffness
the data were simulated with.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from import_graph import imported_modules

import bearingfw
from bearingfw.analysis import solve_modal
from bearingfw.cli.main import main
from bearingfw.model import Model
from bearingfw.oma import Channels
from bearingfw.parameters import ParameterError
from bearingfw.structures import (
    REFERENCE,
    StructureError,
    build_structure,
    builder_keywords,
    import_location,
    load_builder,
    parse_options,
    reference_ignores,
)

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "small-bridge"
BRIDGE = f"{EXAMPLE / 'small_bridge.py'}:build"
#: The stiffness of the sliding bearings the simulated data come from (simulate_ambient.py's default).
K_TRUE = 2e8

MAST = '''
"""A steel mast clamped at its base: a cantilever of n elements along z."""
from bearingfw.model import FrameElement, Material, Model, Node, Section, Support

I_SMALL, I_LARGE, AREA, DENSITY = 1e-4, 4e-4, 0.02, 7850.0


def build(height=10.0, n=20, modulus=210e9):
    steel = Material("steel", modulus, density=DENSITY, nu=0.3)
    section = Section("mast", A=AREA, Iy=I_SMALL, Iz=I_LARGE, J=1e-4)
    nodes = [Node(f"N{k}", 0.0, 0.0, height * k / n) for k in range(n + 1)]
    elements = [FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", section, steel) for k in range(n)]
    return Model(nodes, elements, supports=[Support("N0")], name="mast")


def not_a_model():
    return 42


def broken(height=1.0):
    return 1 / 0


def exits():
    raise SystemExit(3)


def build_any(height=10.0, n=20, modulus=210e9, **rest):
    return build(height, n, modulus)


VALUE = 3
'''


def _small_bridge(**options) -> Model:
    return build_structure(BRIDGE, options)


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def mast(tmp_path):
    (tmp_path / "mast.py").write_text(textwrap.dedent(MAST))
    return tmp_path


# -- bearingfw.structures ----------------------------------------------------------------------------


def test_a_file_and_a_module_spec_build_the_same_model(mast):
    by_file = build_structure("mast.py:build", {"n": 4}, base_dir=mast)
    by_module = build_structure("mast:build", {"n": 4}, base_dir=mast)
    assert isinstance(by_file, Model) and by_file.name == "mast" and len(by_file.nodes) == 5
    assert by_module.nodes == by_file.nodes
    assert build_structure(f"{mast / 'mast.py'}:build").nodes[-1].z == 10.0  # absolute path, defaults
    assert import_location("mast.py:build", base_dir=mast) == ("mast", (str(mast.resolve()),))
    assert import_location(REFERENCE) == ("bearingfw.bridges", ())
    assert builder_keywords(load_builder("mast:build", base_dir=mast)) == {"height": 10.0, "n": 20, "modulus": 210e9}


def test_a_file_whose_name_is_taken_by_another_module_is_still_that_file(tmp_path):
    (tmp_path / "json.py").write_text("from bearingfw.model import Model\n\ndef build():\n    return 'mine'\n")
    assert load_builder("json.py:build", base_dir=tmp_path)() == "mine"
    assert json.dumps([1]) == "[1]"  # the standard library's json is untouched


def test_python_path_finds_a_package_module(tmp_path):
    package = tmp_path / "lib" / "bridges_of_mine"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "mast.py").write_text(textwrap.dedent(MAST))
    model = build_structure("bridges_of_mine.mast:build", {"n": 2}, base_dir=tmp_path, python_path=["lib"])
    assert len(model.nodes) == 3


def test_the_reference_bridge_takes_its_preset_and_bridge_parameters():
    from bearingfw.bridges import BridgeParameters, reference_bridge

    def bearings(model):
        return [(c.name, c.law, c.law_params) for c in model.connectors]

    model = build_structure(REFERENCE, {"preset": "M1", "ks": 3e8, "girder_depth": 1.5})
    expected = reference_bridge("M1", ks=3e8, params=BridgeParameters(girder_depth=1.5))
    assert model.name == expected.name and bearings(model) == bearings(expected)
    assert ("k", 3e8) in bearings(model)[-1][2]
    def sections(model):
        return [getattr(e, "section", None) for e in model.elements]

    assert sections(model) == sections(expected) != sections(reference_bridge("M1", ks=3e8))
    assert "spans" in builder_keywords(load_builder(REFERENCE))


@pytest.mark.parametrize(
    "spec, options, message",
    [
        ("mast", {}, "expected 'reference', 'package.module:function' or 'path/to/file.py:function' "
                     r"\(the function is missing"),
        ("mast:", {}, "expected"),
        ("mast:1x", {}, r"'1x' is not a function name"),
        ("", {}, "structure spec must be"),
        ("nowhere_module:build", {}, "module 'nowhere_module' not found"),
        ("missing.py:build", {}, r"file '.*missing.py' not found"),
        ("mast:bild", {}, "has no function 'bild'; did you mean build"),
        ("mast:VALUE", {}, "'VALUE' is a int, not a function"),
        ("mast:build", {"heigth": 3.0}, r"unknown option 'heigth' \(did you mean height\?\); it takes height, n, modulus"),
        ("mast:build", {"n": "four"}, "calling the builder failed: TypeError"),
        ("mast:broken", {}, r"calling the builder failed: ZeroDivisionError: division by zero \(.*mast.py, line \d+\)"),
        ("mast:not_a_model", {}, "the builder returned int, not a bearingfw Model"),
        ("mast:build", {"modulus": -1.0}, "parameter 'E' = -1.0 is outside the allowed range"),
        (REFERENCE, {"preset": "M9"}, "option 'preset' must be one of M0, M1, M2"),
        (REFERENCE, {"kss": 1.0}, r"unknown option 'kss' \(did you mean ks\?\)"),
        (REFERENCE, {"spans": "long"}, "structure 'reference': "),
        (REFERENCE, {"ks": True}, "option 'ks' must be a number"),
        ("mast:exits", {}, r"calling the builder failed: it called sys.exit\(3\) \(.*mast.py, line \d+\)"),
    ],
)
def test_structure_errors_name_the_spec_and_the_problem(mast, spec, options, message):
    with pytest.raises(StructureError, match=message) as info:
        build_structure(spec, options, base_dir=mast)
    assert isinstance(info.value, ParameterError)
    if spec:
        assert f"structure {spec!r}" in str(info.value)


def test_errors_while_importing_the_users_module(tmp_path):
    (tmp_path / "syntax.py").write_text("def build(:\n")
    with pytest.raises(StructureError,
                       match=r"importing module 'syntax' failed: SyntaxError.*syntax.py, line 1") as info:
        load_builder("syntax:build", base_dir=tmp_path)
    assert str(info.value).count("line 1") == 1  # the location once
    (tmp_path / "needs.py").write_text("import not_installed_anywhere\n")
    with pytest.raises(StructureError, match="importing file .* failed: ModuleNotFoundError: No module named "
                                             "'not_installed_anywhere'"):
        load_builder("needs.py:build", base_dir=tmp_path)


def test_a_failure_is_put_on_the_option_that_causes_it(mast):
    """The builder refusing a value: the message starts with how the user gave the one option without
    which the model builds; with check, the bearing laws' refusals too (they check at assembly)."""
    with pytest.raises(StructureError, match=r"^--option modulus=-1: structure 'mast:build': .*'E' = -1.0") as info:
        build_structure("mast:build", {"n": 4, "modulus": -1.0}, base_dir=mast,
                        origins={"modulus": "--option modulus=-1"})
    assert info.value.option == "modulus"
    with pytest.raises(StructureError, match=r"^option modulus = -1.0: "):
        build_structure("mast:build", {"n": 4, "modulus": -1.0}, base_dir=mast)
    # a law parameter refused when the model is assembled: only with check
    assert isinstance(build_structure(BRIDGE, {"bearing_stiffness": -5.0, "span": 20.0}), Model)
    with pytest.raises(StructureError, match=r"^option bearing_stiffness = -5.0: .*'k' = -5.0 is outside") as info:
        build_structure(BRIDGE, {"bearing_stiffness": -5.0, "span": 20.0}, check=True)
    assert info.value.option == "bearing_stiffness"
    # the builder fails whatever the options: nothing to put it on
    with pytest.raises(StructureError, match=r"^structure 'mast:broken': calling the builder failed") as info:
        build_structure("mast:broken", {"height": 2.0}, base_dir=mast)
    assert info.value.option is None


def test_which_reference_bearing_models_use_ks_and_friction():
    """Asked of the presets' laws themselves: M0 slides freely (no K_s), M1 is springs K_s (no friction)."""
    assert reference_ignores({}, "ks") == "M0" and reference_ignores({"preset": "M1"}, "ks") is None
    assert reference_ignores({"preset": "M1"}, "friction") == "M1"
    assert reference_ignores({"preset": "M2"}, "friction") is None
    assert reference_ignores({"preset": "M0"}, "girder_depth") is None  # not a bearing option


def test_a_required_keyword_must_be_given(tmp_path):
    (tmp_path / "req.py").write_text("def build(span):\n    return span\n")
    with pytest.raises(StructureError, match="option\\(s\\) 'span' required"):
        build_structure("req.py:build", {}, base_dir=tmp_path)


def test_options_are_toml_values_and_bare_words_are_text():
    assert parse_options(["k=4e8", "n=3", "flag=true", "spans=[30, 40]", 'name="a b"', "law=frictionless",
                          "x=.5", "path=a/b.py", "table={a = 1}"]) == {
        "k": 4e8, "n": 3, "flag": True, "spans": [30, 40], "name": "a b", "law": "frictionless", "x": 0.5,
        "path": "a/b.py", "table": {"a": 1},
    }
    assert parse_options(None) == {} and isinstance(parse_options(["n=3"])["n"], int)


@pytest.mark.parametrize(
    "pairs, message",
    [(["k"], "expected key=value"), (["k=1", "k=2"], "'k' is given twice"), (["1k=2"], "not a keyword name"),
     (["k="], "the value is missing"), (["k=[1,"], "not a valid value"), (['k="open'], "not a valid value")],
)
def test_bad_options_name_the_pair(pairs, message):
    with pytest.raises(StructureError, match=message):
        parse_options(pairs)


def test_structures_imports_only_the_layers_below_it():
    allowed = ("bearingfw.plugins", "bearingfw.model", "bearingfw.parameters", "bearingfw.bridges")
    path = Path(bearingfw.__file__).parent / "structures.py"
    ours = [n for n in imported_modules(path) if n.startswith("bearingfw")]
    assert ours and all(n.startswith(allowed) for n in ours), ours


# -- bearingfw modal --structure ---------------------------------------------------------------------


def test_modal_of_a_users_mast_gives_the_cantilevers_closed_form(capsys, mast):
    """f_1 = 1.8751^2 / (2 pi L^2) sqrt(E I / (rho A)) in each bending plane (20 elements: within 0.1 %)."""
    code, out, _ = run(capsys, "modal", "--structure", f"{mast / 'mast.py'}:build", "--option", "height=12",
                       "--modes", "4", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["model"] == "mast" and data["options"] == {"height": 12}
    exact = [1.87510407**2 / (2 * math.pi * 12.0**2) * math.sqrt(210e9 * inertia / (7850.0 * 0.02))
             for inertia in (1e-4, 4e-4)]
    f = [m["frequency"] for m in data["modes"]]
    assert f[0] == pytest.approx(exact[0], rel=1e-3) and f[1] == pytest.approx(exact[1], rel=1e-3)
    # each swings in one horizontal plane: that translation dominates, with the effective mass of the
    # cantilever's first mode (0.613 of a uniform cantilever's mass, less the base node's lumped share)
    for mode in data["modes"][:2]:
        assert mode["dominant"] in ("ux", "uy")
        direction = mode["dominant"][1]
        assert mode["participation"][direction] == pytest.approx(0.613, abs=0.03)
    assert {data["modes"][0]["dominant"], data["modes"][1]["dominant"]} == {"ux", "uy"}


def test_modal_json_of_the_small_bridge(capsys):
    code, out, _ = run(capsys, "modal", "--structure", BRIDGE, "--option", f"bearing_stiffness={K_TRUE:g}",
                       "--modes", "6", "--json")
    assert code == 0
    data = json.loads(out)
    modal = solve_modal(_small_bridge(bearing_stiffness=K_TRUE), 6)
    np.testing.assert_allclose([m["frequency"] for m in data["modes"]], modal.frequencies, rtol=1e-9)
    assert [m["label"] for m in data["modes"]] == list(modal.numbered_labels)
    longitudinal = next(m for m in data["modes"] if m["label"] == "longitudinal 1")
    assert longitudinal["dominant"] == "ux" and longitudinal["participation"]["x"] > 0.9
    assert longitudinal["effective_mass"]["x"] == pytest.approx(
        longitudinal["participation"]["x"] * data["total_mass"]["x"])
    code, out, _ = run(capsys, "modal", "--structure", BRIDGE, "--modes", "3")
    assert code == 0 and "two-span girder" in out and "dominant" in out and "longitudinal 1" in out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--structure", BRIDGE, "--model", "M1"], "--model and --ks choose the reference bridge's"),
        (["--structure", BRIDGE, "--option", "spn=20"], "unknown option 'spn' (did you mean span?)"),
        (["--structure", BRIDGE, "--option", "span"], "--option 'span': expected key=value"),
        (["--structure", "nowhere:build"], "module 'nowhere' not found"),
        (["--model", "M1", "--option", "preset=M2"], "--model and --option preset=... both give the preset"),
        (["--option", "preset=M9"], "--option preset must be one of M0, M1, M2"),
        (["--structure", BRIDGE, "--option", "bearing_stiffness=-5"],
         "--option bearing_stiffness=-5: structure '"),
    ],
)
def test_modal_structure_errors(capsys, argv, message):
    code, out, err = run(capsys, "modal", *argv)
    assert code == 2 and message in err and "Traceback" not in err and out == ""


# -- bearingfw oma --structure: channel names against the model's DOFs ---------------------------------


def _record(path, names, samples=400):
    rng = np.random.default_rng(0)
    return Channels(rng.standard_normal((samples, len(names))), 0.02, names, source="noise").to_csv(path)


def test_oma_refuses_a_channel_the_structure_lacks_and_lists_near_matches(capsys, tmp_path):
    path = _record(tmp_path / "typo.csv", ("G4.uz", "G44.uz"))
    code, _, err = run(capsys, "oma", path, "--structure", BRIDGE)
    assert code == 2
    assert "channel 'G44.uz': the model has no node 'G44' (in 'two-span girder'; near matches: G4.uz," in err
    code, _, err = run(capsys, "oma", path, "--structure", BRIDGE, "--decay", "2.5")
    assert code == 2 and "no node 'G44'" in err
    code, _, err = run(capsys, "oma", path, "--option", "span=20")
    assert code == 2 and "give --structure SPEC too" in err
    code, _, err = run(capsys, "oma", _record(tmp_path / "plain.csv", ("acc1", "G4.uz")), "--structure", BRIDGE)
    assert code == 2 and "channel 'acc1' does not name a DOF: expected '<node>.<component>'" in err


def test_oma_warns_of_channels_at_supported_dofs(capsys, tmp_path):
    path = _record(tmp_path / "base.csv", ("G4.uz", "P0.ux"), samples=3000)
    code, out, _ = run(capsys, "oma", path, "--structure", BRIDGE, "--json", "--order", "10")
    assert code == 0
    data = json.loads(out)
    assert data["structure"]["spec"] == BRIDGE and data["structure"]["model"] == "two-span girder"
    assert any("P0.ux are at supported DOFs" in w for w in data["warnings"])


# -- the whole path: simulated ambient data -> oma -> tune ----------------------------------------


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """simulate_ambient.py's data (the bridge with K_TRUE), identified by ``bearingfw oma --structure``."""
    folder = tmp_path_factory.mktemp("small-bridge")
    subprocess.run([sys.executable, str(EXAMPLE / "simulate_ambient.py"), "--out", str(folder / "ambient.npz")],
                   check=True, capture_output=True)
    code = main(["oma", str(folder / "ambient.npz"), "--structure", BRIDGE, "--fmax", "8",
                 "--output", str(folder / "modes.json"), "--json"])
    assert code == 0
    return folder


def test_oma_identifies_the_small_bridges_modes_at_named_channels(capsys, identified):
    modes = json.loads((identified / "modes.json").read_text())
    assert modes["synthetic"] is True and "G4.ux" in modes["channels"] and "G12.uy" in modes["channels"]
    exact = solve_modal(_small_bridge(bearing_stiffness=K_TRUE), 6).frequencies[:4]
    np.testing.assert_allclose([m["frequency"] for m in modes["modes"]], exact, rtol=0.01)


def test_tune_recovers_the_bearing_stiffness_from_the_identified_modes(capsys, identified):
    code, out, err = run(capsys, "tune", "--structure", BRIDGE, "--param", "bearing_stiffness=1e7:1e10",
                         "--measured", identified / "modes.json", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["fitted"]["bearing_stiffness"] == pytest.approx(K_TRUE, rel=0.05)
    assert data["pairing"] == "mac" and data["synthetic"] is True and data["dropped"] == []
    by_label = {m["label_after"]: m for m in data["modes"]}
    assert by_label["longitudinal 1"]["mac_after"] > 0.95
    # the longitudinal mode carries the information: d ln f / d ln k = 0.44; the bending modes ~0
    assert by_label["longitudinal 1"]["sensitivity"]["bearing_stiffness"] == pytest.approx(0.44, abs=0.02)
    assert abs(by_label["vertical 1"]["sensitivity"]["bearing_stiffness"]) < 0.01
    assert abs(by_label["longitudinal 1"]["error_before"]) > 0.1 > 0.01 > abs(by_label["longitudinal 1"]["error_after"])
    assert np.allclose(np.diag(data["mac"]), [m["mac_after"] for m in data["modes"]])


def test_tune_against_hand_written_labelled_modes(capsys):
    code, out, _ = run(capsys, "tune", "--structure", BRIDGE, "--param", "bearing_stiffness=1e7:1e10",
                       "--measured", EXAMPLE / "measured-modes.toml")
    assert code == 0
    assert "pairing: by label" in out and "along the bridge" in out and "longitudinal 1 (4)" in out
    fitted = float(out.split("bearing_stiffness: ")[1].split()[0])
    assert fitted == pytest.approx(K_TRUE, rel=0.005)  # the frequencies are rounded to 1 mHz


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--structure", BRIDGE, "--measured", "{toml}"], "give the parameters to calibrate, --param"),
        (["--structure", BRIDGE, "--param", "bearing_stiffness=1e7:1e10"], "give the measured modes, --measured"),
        (["--structure", BRIDGE, "--param", "bearing_stifness=1e7:1e10", "--measured", "{toml}"],
         "has no parameter 'bearing_stifness' (did you mean bearing_stiffness,"),
        (["--structure", BRIDGE, "--param", "bearing_stiffness=1e10:1e7", "--measured", "{toml}"], "LOW < HIGH"),
        (["--structure", BRIDGE, "--param", "bearing_stiffness=1e7", "--measured", "{toml}"], "expected NAME=LOW:HIGH"),
        (["--structure", BRIDGE, "--param", "bearing_stiffness=1e7:1e9:5e9", "--measured", "{toml}"],
         "START = 5e+09 is outside"),
        (["--structure", BRIDGE, "--param", "span=10:30", "--param", "span=10:40", "--measured", "{toml}"],
         "given twice"),
        (["--structure", BRIDGE, "--param", "span=10:30", "--option", "span=20", "--measured", "{toml}"],
         "either fixed or calibrated"),
        (["--structure", BRIDGE, "--param", "span=10:30", "--measured", "missing.toml"], "cannot read"),
        (["--option", "span=20"], "apply to --structure"),
        (["--structure", BRIDGE, "--param", "span=10:30", "--measured", "{toml}", "--modes", "9"],
         "no measured mode 9"),
        # a value the model refuses: named with the --param or --option that gave it
        (["--structure", BRIDGE, "--param", "bearing_stiffness=-1e8:1e10", "--measured", "{toml}"],
         "--param bearing_stiffness = -1e+08 (LOW): connector '1A': field 'law_params'"),
        (["--structure", BRIDGE, "--param", "bearing_stiffness=-1e8:1e10:-5e7", "--measured", "{toml}"],
         "--param bearing_stiffness = -5e+07 (START): structure '"),
        (["--structure", BRIDGE, "--param", "bearing_stiffness=1e7:1e10", "--option", "concrete_modulus=abc",
          "--measured", "{toml}"], "--option concrete_modulus=abc: structure '"),
        (["--structure", BRIDGE, "--param", "elements_per_span=4:12", "--measured", "{toml}"],
         "--param elements_per_span: the structure's function declares elements_per_span an integer"),
        # the default bearing model of the reference bridge (M0, frictionless) has no K_s
        (["--param", "ks=1e7:1e10", "--measured", "{toml}"],
         "--param ks: the reference bridge's bearing model M0 does not use ks"),
    ],
)
def test_tune_structure_errors(capsys, argv, message):
    argv = [a.replace("{toml}", str(EXAMPLE / "measured-modes.toml")) for a in argv]
    code, out, err = run(capsys, "tune", *argv)
    assert code == 2 and message in err and "Traceback" not in err and out == ""


def test_tune_names_its_doubts_about_the_command_line(capsys, mast):
    """A --param that a **kwargs builder does not name (a typo it would silently take), --min-mac with modes
    paired by label, and the MAC printed to three decimals, by shape."""
    spec = f"{mast / 'mast.py'}:build_any"
    modal = solve_modal(build_structure(spec, {"n": 6}), 4)
    channels = ["N3.ux", "N6.ux", "N3.uy", "N6.uy"]
    dofs = [modal.system.dofmap.dof(*c.split(".")) for c in channels]
    shapes = mast / "shapes.json"
    shapes.write_text(json.dumps({"channels": channels, "modes": [
        {"frequency": float(modal.frequencies[m]), "shape": modal.shapes[dofs, m].tolist()} for m in (0, 1)]}))
    code, out, err = run(capsys, "tune", "--structure", spec, "--option", "n=6", "--param", "modulus=1e11:4e11",
                         "--param", "modulu=1:2", "--measured", shapes, "--scan", "3")
    assert code == 0, err
    assert "warning: --param modulu: the structure's function does not name a parameter 'modulu'" in out
    assert "(did you mean modulus?)" in out and "no measured mode is sensitive to --param modulu" in out
    assert float(out.split("modulus: ")[1].split()[0]) == pytest.approx(210e9, rel=1e-4)
    table = out.split("MAC table")[1].splitlines()[1]
    assert table.split()[-2:] == ["1.000", "0.000"]  # three decimals
    labels = mast / "labels.json"
    labels.write_text(json.dumps({"modes": [{"frequency": float(modal.frequencies[0]),
                                             "label": modal.numbered_labels[0]}]}))
    code, out, err = run(capsys, "tune", "--structure", spec, "--option", "n=6", "--param", "modulus=1e11:4e11",
                         "--measured", labels, "--min-mac", "0.9", "--scan", "0", "--json")
    assert code == 0, err
    assert any(w.startswith("--min-mac 0.9 does nothing here") for w in json.loads(out)["warnings"])


def test_one_modal_analysis_is_one():
    from bearingfw.cli.tune import _analyses

    assert (_analyses(1), _analyses(11)) == ("1 modal analysis", "11 modal analyses")
