"""The experiment file: the built-in default, and errors that name the key's path and what is allowed."""

from __future__ import annotations

import tomllib

import pytest
from tiny_experiment import tiny_toml

from bearingfw.experiment import (
    DEFAULT_TOML,
    SpecError,
    check_experiment,
    default_experiment,
    load_experiment,
    parse_experiment,
)
from bearingfw.motion import LEVEL_NAMES


def test_the_default_is_the_papers_study():
    e = default_experiment()
    assert e.model_names == ("M0", "M1", "M2", "fixed", "bouc-wen")
    assert [m.preset for m in e.models] == ["M0", "M1", "M2", "fixed", "bouc-wen"]
    assert [i.name for i in e.intensity_list] == list(LEVEL_NAMES)
    assert [i.pga_h10 for i in e.intensity_list] == [0.10, 0.23, 0.46, 0.75, 1.10]
    assert e.reference_model == "M2"
    assert e.records[0].seed == 0 and e.records[0].components == ("h1", "h2", "v")
    rayleigh = e.damping.rayleigh()
    assert rayleigh.alpha == pytest.approx(0.21, abs=0.005) and rayleigh.beta == pytest.approx(0.00208, rel=0.01)
    assert e.integration.alpha == -0.05 and e.integration.dt_integration == 0.005
    # every key the default file writes out is what the classes default to anyway (it documents them)
    assert tomllib.loads(DEFAULT_TOML)["name"] == e.name == "paper-study"


def test_a_file_loads_with_paths_relative_to_it(tmp_path):
    path = tmp_path / "sub" / "x.toml"
    path.parent.mkdir()
    path.write_text('name = "x"\n[models.a]\npreset = "M0"\n[records.r]\nfiles = ["a.AT2", "b.AT2", "c.AT2"]\n')
    e = load_experiment(path)
    assert e.base_dir == path.parent.resolve()
    assert e.resolve_path("a.AT2") == path.parent.resolve() / "a.AT2"
    assert e.reference_model == "a"  # no reference given: the first model


def _error(text: str) -> str:
    with pytest.raises(SpecError) as caught:
        parse_experiment(text, origin="exp.toml")
    return str(caught.value)


BASE = 'name = "x"\n[models.M2]\npreset = "M2"\n[records.r]\nseed = 0\n'


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ('colour = "red"\n' + BASE, "exp.toml: colour: unknown key; allowed in the top level: name, description"),
        (BASE + "mu = 0.05\n", "exp.toml: records.r.mu: unknown key; allowed in [records.r]: seed, tremor, files"),
        ('name = "x"\n[models.M2]\npreset = "M2"\nmu = 0.05\n[records.r]\nseed = 0\n',
         "models.M2.mu: unknown key; allowed in [models.M2]: preset, ks, friction, law, params"),
        (BASE + "[integration]\nalpha = 'big'\n", "integration.alpha: parameter 'alpha' must be a real number"),
        (BASE + "[integration]\nalpha = 0.5\n",
         "integration.alpha: parameter 'alpha' = 0.5 is outside the allowed range"),
        (BASE + "[integration]\nmax_iterations = 2.5\n",
         "integration.max_iterations: parameter 'max_iterations' must be an integer"),
        (BASE + "[intensities]\nlevels = 'D_0'\n",
         "intensities.levels: field 'levels' must be a list of levels among D_0"),
        (BASE + "[intensities]\nlevels = ['D_9']\n", "intensities.levels"),
        (BASE + "[intensities]\nsa = [1.0]\n", "intensities: 'sa' and 'period' go together"),
        (BASE + "[intensities]\npga = [1.0, 1.0]\n", "intensities.pga: field 'pga' gives a value twice"),
        (BASE + "[intensities]\nsa = [1.0]\nperiod = -1\n", "intensities.period: field 'period' must be a period"),
        (BASE + "[intensities]\nlevels = ['D_0', 'as-recorded', 'as_recorded']\n", "names a level twice"),
        (BASE + "[intensities]\nvalues = { D_II = 0.05 }\n",
         "intensities.values: IntensityLevels: the levels must increase"),
        (BASE.replace('seed = 0', 'seed = -1'), "records.r.seed: field 'seed' must be an integer >= 0"),
        (BASE.replace('seed = 0', 'seed = 0\nfiles = ["a", "b", "c"]'),
         "records.r: give one of 'seed' (synthetic tremor), 'files' or 'x'/'y'/'z' (files per direction), not seed "
         "and files"),
        (BASE.replace('seed = 0', 'x = "a.AT2"\ncomponents = ["h2", "h1", "v"]'), "records.r: 'components' goes with"),
        (BASE.replace('seed = 0', 'files = ["a", "b", "c"]\nvertical_as_horizontal = true'),
         "records.r: 'vertical_as_horizontal' goes with 'x'/'y'/'z'"),
        (BASE.replace('seed = 0', 'x = 3'), "records.r.x: field 'x' must be a record file"),
        (BASE.replace('seed = 0', 'seed = 0\ncomponents = ["h1", "x", "v"]'),
         "records.r.components: field 'components' must be 3 entries"),
        (BASE.replace('[models.M2]\npreset = "M2"', '[models."M2.5"]\npreset = 9'), 'models."M2.5".preset: field'),
        (BASE.replace('preset = "M2"', 'preset = "M2"\nparams = { k = 1.0 }'), "models.M2: 'params' go with 'law'"),
        (BASE.replace('preset = "M2"', 'law = "linear-spring"\nks = 1e8'),
         "models.M2: 'ks' and 'friction' go with 'preset'"),
        (BASE.replace('preset = "M2"', 'preset = "M2"\nfriction = 1.5'),
         "models.M2.friction: parameter 'friction' = 1.5"),
        (BASE + "[damping]\nratios = [[1.5, 0.02]]\n",
         "damping.ratios: field 'ratios' must be two [frequency Hz, damping ratio] pairs"),
        (BASE + "[damping]\nalpha = 0.2\n", "damping: give both 'alpha' and 'beta'"),
        (BASE + "[damping]\nratios = [[1.0, 0.10], [3.0, 0.001]]\n", "damping.ratios: rayleigh_from_ratios"),
        (BASE + "[structure]\nbuilder = ''\n", "structure.builder: field 'builder' must be 'package.module:function'"),
        (BASE + "[damping]\nratio = 0.02\nalpha = 0.1\nbeta = 0.0\n", "damping: give alpha and beta or ratio"),
        (BASE + "[output]\naggregate = 'median'\n",
         "output.aggregate: parameter 'aggregate' must be one of 'ec8', 'max', 'mean'"),
        (BASE + "[figures]\nintensities = ['D_V']\n", "figures.intensities: 'D_V' is not among D_0"),
        (BASE + "[figures]\ndraw = 1\n", "figures.draw: field 'draw' must be true or false"),
        ('reference = "M7"\n' + BASE, "reference: 'M7' is not a model; models: M2"),
        ('name = "a b"\n' + BASE[len('name = "x"\n'):], "name: field 'name' must be a name of at most 64 letters"),
        (BASE.replace('name = "x"\n', ""), "name: missing"),
        ('name = "x"\n[records.r]\nseed = 0\n', "models: the experiment needs at least one [models.<name>] table"),
        ('name = "x"\nmodels = 3\n[records.r]\nseed = 0\n', "models: must be tables [models.<name>]"),
        (BASE + "[output\n", "exp.toml: not valid TOML"),
    ],
)
def test_errors_name_the_key_path_and_what_is_allowed(text, expected):
    assert expected in _error(text)


def test_unknown_keys_list_every_allowed_key():
    message = _error(BASE + "[output]\ntabel = []\n")
    assert message.startswith("exp.toml: output.tabel: unknown key; allowed in [output]: ")
    for key in ("table", "aggregate", "histories", "every", "report"):
        assert key in message


def test_what_needs_the_plugins_or_the_users_code_is_checked_before_running(tmp_path):
    def checked(text):
        path = tmp_path / "e.toml"
        path.write_text(text)
        with pytest.raises(SpecError) as caught:
            check_experiment(load_experiment(path))
        return str(caught.value)

    message = checked(BASE.replace('preset = "M2"', 'law = "no-such-law"'))
    assert message.startswith("models.M2.law: unknown bearing law 'no-such-law'; known laws: ")
    assert "regularized-coulomb" in message
    message = checked(BASE.replace('preset = "M2"', 'law = "regularized-coulomb"\nparams = { k = 4e8 }'))
    assert message.startswith("models.M2.params: ") and "missing parameter(s) 'mu'" in message
    message = checked(BASE.replace('preset = "M2"', 'law = "linear-spring"\nparams = { k = -1.0 }'))
    assert message.startswith("models.M2.params: linear-spring: parameter 'k' = -1.0 is outside the allowed range k > 0")
    message = checked(BASE.replace('preset = "M2"', 'law = "linear-spring"\nparams = { k = 1e8, c = 2 }'))
    assert message.startswith("models.M2.params: linear-spring: unknown parameter(s) 'c'; parameters of linear-spring: k")
    message = checked(BASE + "[intensities]\nscale = 'no-such-scale'\n")
    assert message.startswith("intensities.scale: unknown intensity scale 'no-such-scale'; known scales: usb-pga-h10")
    # the option that is out of range is named first (structures.py's message)
    assert "structure.options: option element_length = 99.0: structure 'reference': BridgeParameters: parameter " \
           "'element_length' = 99.0 is outside" in checked(BASE + "[structure]\noptions = { element_length = 99.0 }\n")
    assert "structure.options: structure 'reference': unknown option 'spam' (did you mean spans?)" in checked(
        BASE + "[structure]\noptions = { spam = 1 }\n")
    assert "structure.builder: structure 'no_such_module_xyz:build': module 'no_such_module_xyz' not found" in checked(
        BASE + "[structure]\nbuilder = 'no_such_module_xyz:build'\n")
    assert "structure.builder: structure 'not a function': expected 'reference', 'package.module:function'" in checked(
        BASE + "[structure]\nbuilder = 'not a function'\n")
    message = checked(BASE + "[structure]\nelements = ['Z9']\n")
    assert message.startswith("structure.elements: the model has no element 'Z9'; its frame elements with stress "
                              "recovery points: GA0, GA1,") and "(225 in all)" in message  # what exists, not all
    assert "figures.bearing: the model has no connector '9Z'; it has 1A, 1B, 2A" in checked(
        BASE + "[figures]\nbearing = '9Z'\n")
    assert "figures.elements: 'S1' is not a response element; they are none ([structure] elements)" in checked(
        BASE + "[figures]\nelements = ['S1']\n")
    assert "structure.bearings: the model has no connector '9Z'; it has 1A, 1B, 2A, 2B" in checked(
        BASE + "[structure]\nbearings = ['9Z']\n")
    assert checked(BASE.replace('"M2"', '"M9"')).startswith(
        "models.M2.preset: unknown bearing preset 'M9'; known presets: M0, M1, M2")
    assert "output.table: 'stress.9Z': '9Z' is not recorded" in checked(BASE + "[output]\ntable = ['stress.9Z']\n")
    assert "output.table: 'strain.S1': unknown metric family 'strain'" in checked(
        BASE + "[output]\ntable = ['strain.S1']\n")
    assert "records.r:" in checked(BASE.replace("seed = 0", 'files = ["a.AT2", "b.AT2", "c.AT2"]'))
    assert "plugins: module 'no_such_plugin_xyz'" in checked('plugins = ["no_such_plugin_xyz"]\n' + BASE)


def test_the_tiny_experiment_of_these_tests_is_valid(tiny):
    e = load_experiment(tiny)
    checked = check_experiment(e)
    assert checked.elements == ("G2", "G4") and checked.nodes == ("G2", "G6")
    assert checked.bearings == ("1A", "1B", "2B", "3A", "3B")  # every connector that is not JOIN
    assert "slow" not in e.model_names and tiny_toml().count("[models.") == 3


def test_intensities_of_every_kind_resolve_to_scale_targets_in_order():
    e = parse_experiment(BASE + "[intensities]\nlevels = ['D_II', 'As_Recorded']\nvalues = { D_II = 0.5 }\n"
                                "pga_h10 = [0.1]\npga = [2]\nsa = [3.0, 4.5]\nperiod = 0.5\n")
    assert [i.name for i in e.intensity_list] == ["D_II", "as-recorded", "PGA_H10=0.1", "pga=2", "sa=3@0.5s",
                                                  "sa=4.5@0.5s"]
    kinds = [(i.target.kind, i.target.value, i.target.period, i.level) for i in e.intensity_list]
    assert kinds == [("pga_h10", 0.5, None, "D_II"), ("as-recorded", None, None, None), ("pga_h10", 0.1, None, None),
                     ("pga", 2.0, None, None), ("sa", 3.0, 0.5, None), ("sa", 4.5, 0.5, None)]
    assert [i.pga_h10 for i in e.intensity_list][:3] == [0.5, None, 0.1]
    # a level keeps the digest data it always had; another kind adds its whole target
    assert e.intensity_list[0].inputs() == {"name": "D_II", "pga_h10": 0.5, "level": "D_II"}
    assert e.intensity_list[4].inputs()["target"] == {"kind": "sa", "value": 3.0, "period": 0.5, "label": "sa=3@0.5s",
                                                      "level": None}
    t1 = parse_experiment(BASE + "[intensities]\nsa = [2.0]\nperiod = 'T1'\n").intensities
    assert t1.needs_first_period and t1.resolve()[0].target.period is None
    assert t1.resolve(0.8)[0].target.period == 0.8 and t1.resolve(0.8)[0].name == "sa=2@T1"


def test_a_file_that_is_not_utf8_gets_a_clear_error_naming_the_path_and_offset(tmp_path, capsys):
    from bearingfw.cli.main import main

    path = tmp_path / "latin1.toml"
    path.write_bytes('name = "x"\n# Widerstandsmoment f\u00fcr Tr\u00e4ger\n'.encode("latin-1"))
    with pytest.raises(SpecError) as caught:
        load_experiment(path)
    assert str(caught.value) == (f"{path}: not UTF-8 text (TOML files are UTF-8): byte 0xfc at byte offset 32 "
                                 "(line 2) cannot be decoded; save the file as UTF-8")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "byte offset 32 (line 2)" in err and not (tmp_path / "out").exists()
