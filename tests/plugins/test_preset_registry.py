"""Bearing presets come from the plugin hook: the built-in ones, a third party's, broken ones reported."""

import importlib.metadata as metadata
import textwrap

import pytest

from bearingfw import BearingPreset, PresetBearing
from bearingfw.plugins import UnknownPresetError, get_registry, load_registry

PLUGINS = {
    "damped_presets": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_presets():
    def law(bearing):
        return ("linear-spring", {"k": 2 * bearing.ks})
    return [bearingfw.BearingPreset("stiff", "springs of twice K_s", law)]
''',
    "half_broken_presets": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_presets():
    good = bearingfw.BearingPreset("soft", "springs of half K_s", lambda b: ("linear-spring", {"k": b.ks / 2}))
    return [("M9", "not a preset"), good]
''',
    "raising_presets": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_presets():
    return [bearingfw.BearingPreset("", "an empty name", lambda b: None)]
''',
    "impostor_presets": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_presets():
    return [bearingfw.BearingPreset("M1", "not the paper's M1", lambda b: ("frictionless", {}))]
''',
}


@pytest.fixture
def plugin_dir(tmp_path, monkeypatch):
    for module, source in PLUGINS.items():
        (tmp_path / f"{module}.py").write_text(textwrap.dedent(source))
    monkeypatch.syspath_prepend(str(tmp_path))
    return tmp_path


def entry_points(*modules):
    builtin = [*metadata.entry_points(group="bearingfw", name="builtin-laws"),
               *metadata.entry_points(group="bearingfw", name="builtin-presets")]
    return [*builtin, *(metadata.EntryPoint(m.replace("_", "-"), m, "bearingfw") for m in modules)]


def test_the_built_in_presets_are_registered_by_bearingfw():
    registry = get_registry()
    for name in ("M0", "M1", "M2", "fixed"):
        assert registry.presets[name].origin.plugin == "builtin-presets"
        assert registry.presets[name].origin.distribution == "bearingfw"
    bearing = PresetBearing("1B", ks=4e8, friction=0.04, dead_load=None)
    assert registry.preset("M0").law(bearing) == ("frictionless", {})
    assert registry.preset("M1").law(bearing) == ("linear-spring", {"k": 4e8})
    assert registry.preset("M2").law(bearing) == ("regularized-coulomb", {"k": 4e8, "mu": 0.04})
    assert registry.preset("fixed").law(bearing) is None
    assert not any(registry.preset(name).needs_dead_load for name in ("M0", "M1", "M2", "fixed"))


def test_the_bouc_wen_package_registers_its_preset():
    entry = get_registry().presets["bouc-wen"]
    assert (entry.origin.distribution, entry.value.needs_dead_load) == ("bearingfw-boucwen", True)
    law, params = entry.value.law(PresetBearing("1B", ks=4e8, friction=0.04, dead_load=2e6))
    assert law == "bouc-wen"
    assert params["k"] * params["uy"] == pytest.approx(0.04 * 2e6, rel=1e-12)  # saturates at mu N_dead
    assert (params["alpha"], params["A"], params["beta"], params["gamma"], params["n"]) == (0.0, 1.0, 0.5, 0.5, 2.0)


def test_a_third_party_preset_loads_next_to_the_built_in_ones(plugin_dir):
    registry = load_registry(entry_points("damped_presets"))
    assert registry.broken == ()
    assert registry.presets["stiff"].origin.plugin == "damped-presets"
    assert registry.preset("stiff").law(PresetBearing("1B", 4e8, 0.04)) == ("linear-spring", {"k": 8e8})
    assert {"M0", "M1", "M2", "fixed", "stiff"} <= set(registry.presets)


@pytest.mark.parametrize(
    "module, message",
    [
        ("half_broken_presets", "bearingfw_register_presets must return bearingfw.BearingPreset objects, got ('M9'"),
        ("raising_presets", "bearingfw_register_presets raised bearingfw.parameters.ParameterError: BearingPreset: 'name' must be a non-empty"),
        ("impostor_presets", "name 'M1' is already registered by plugin 'builtin-presets'; this one is ignored"),
    ],
)
def test_a_broken_preset_contribution_is_reported_and_the_rest_loads(plugin_dir, module, message):
    registry = load_registry(entry_points(module, "damped_presets"))
    assert [b.plugin for b in registry.broken] == [module.replace("_", "-")]
    assert message in registry.broken[0].error
    assert {"M0", "M1", "M2", "fixed", "stiff"} <= set(registry.presets)
    assert registry.presets["M1"].origin.plugin == "builtin-presets"
    if module == "half_broken_presets":  # the good preset next to the bad one still loads
        assert registry.presets["soft"].origin.plugin == "half-broken-presets"


def test_an_unknown_preset_names_the_known_ones(plugin_dir):
    registry = load_registry(entry_points("damped_presets"))
    with pytest.raises(UnknownPresetError, match=r"unknown bearing preset 'M3'; known presets: M0, M1, M2, fixed, stiff"):
        registry.preset("M3")


def test_a_preset_checks_its_own_fields():
    with pytest.raises(ValueError, match="'name' must be a non-empty string"):
        BearingPreset(" ", "blank", lambda b: None)
    with pytest.raises(ValueError, match="'law' must be callable"):
        BearingPreset("x", "not callable", "linear-spring")


@pytest.mark.parametrize("first", ["bearingfw.experiment.spec", "bearingfw.cli.main"])
def test_a_registry_loaded_while_a_module_imports_loads_every_plugin(first):
    """Listing the presets loads the registry, possibly while a module is half imported (a class
    body that lists ``bearingfw.bridges.PRESETS``); a built-in plugin that imports that module
    would then fail to load, and the registry would keep the failure."""
    import subprocess
    import sys

    script = f"import {first}\nfrom bearingfw.plugins import get_registry\nprint(get_registry().broken)"
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "()"
