"""`bearingfw plugins` on the environment the README's install command sets up."""

import json

from bearingfw.cli.main import main

EXPECTED = {
    "frictionless": "bearingfw",
    "fixed": "bearingfw",
    "linear-spring": "bearingfw",
    "regularized-coulomb": "bearingfw",
    "bouc-wen": "bearingfw-boucwen",
}


def test_json_lists_the_five_laws_with_their_distributions(capsys):
    assert main(["plugins", "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    laws = {law["name"]: law for law in listing["laws"]}
    missing = set(EXPECTED) - set(laws)
    assert not missing, f"not registered: {missing} (the README's install command installs plugins/bearingfw-boucwen)"
    assert {name: laws[name]["distribution"] for name in EXPECTED} == EXPECTED
    assert listing["broken"] == []
    coulomb = laws["regularized-coulomb"]
    assert {key for key in coulomb} >= {"name", "plugin", "distribution", "version", "parameters"}
    mu = next(p for p in coulomb["parameters"] if p["name"] == "mu")
    assert (mu["required"], mu["range"]) == (True, "0 <= mu < 1")


def test_the_table_shows_each_law_and_its_parameters(capsys):
    assert main(["plugins"]) == 0
    out = capsys.readouterr().out
    for name in EXPECTED:
        assert name in out
    assert "k (k > 0, N/m); mu (0 <= mu < 1); dims (1 or 2) = 1" in out


def test_no_command_prints_help_and_fails(capsys):
    assert main([]) == 2
    assert "plugins" in capsys.readouterr().out


def test_json_lists_each_laws_protocol_flags_and_per_bearing_parameters(capsys):
    assert main(["plugins", "--json"]) == 0
    laws = {law["name"]: law for law in json.loads(capsys.readouterr().out)["laws"]}
    assert laws["regularized-coulomb"]["flags"] == {
        "uses_velocity": False, "normal_coupling": True, "per_bearing": True, "friction": True, "rate_dependent": False,
        "linear": False,
    }
    assert laws["linear-spring"]["flags"]["per_bearing"] is True and laws["linear-spring"]["flags"]["linear"] is True
    assert laws["fixed"]["flags"] == dict.fromkeys(laws["fixed"]["flags"], False)
    k = next(p for p in laws["linear-spring"]["parameters"] if p["name"] == "k")
    assert (k["per_bearing"], k["unit"], k["range"]) == (True, "N/m", "k > 0")


def test_json_lists_the_presets_with_their_plugins(capsys):
    assert main(["plugins", "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    presets = {p["name"]: p for p in listing["presets"]}
    for name in ("M0", "M1", "M2", "fixed"):
        assert (presets[name]["plugin"], presets[name]["distribution"]) == ("builtin-presets", "bearingfw")
    assert presets["M2"]["description"] == "regularized Coulomb k = K_s, mu (step 2)"
    assert (presets["bouc-wen"]["distribution"], presets["bouc-wen"]["needs_dead_load"]) == ("bearingfw-boucwen", True)
    assert isinstance(listing["metrics"], list) and isinstance(listing["executors"], list)


def test_the_table_shows_flags_presets_metrics_and_executors(capsys):
    assert main(["plugins"]) == 0
    out = capsys.readouterr().out
    coulomb = next(line for line in out.splitlines() if line.strip().startswith("regularized-coulomb "))
    assert "normal coupling, per-bearing, friction" in coulomb
    spring = next(line for line in out.splitlines() if line.strip().startswith("linear-spring "))
    assert "friction" not in spring and "per-bearing" in spring
    presets = out[out.index("Bearing presets:"):out.index("Record readers:")]
    assert "builtin-presets" in presets and "regularized Coulomb k = K_s, mu (step 2)" in presets
    assert "(uses the dead load)" in presets.split("bouc-wen", 1)[1].splitlines()[0]
    assert "Metric families:" in out and "Executors:" in out


def test_the_listing_says_which_laws_offer_a_compiled_function(capsys):
    assert main(["plugins", "--json"]) == 0
    laws = {law["name"]: law for law in json.loads(capsys.readouterr().out)["laws"]}
    assert laws["regularized-coulomb"]["compiled"] and laws["linear-spring"]["compiled"]
    assert not laws["fixed"]["compiled"]
    assert main(["plugins"]) == 0
    out = capsys.readouterr().out
    assert "compiled" in next(line for line in out.splitlines() if line.strip().startswith("regularized-coulomb "))
    assert "compiled" not in next(line for line in out.splitlines() if line.strip().startswith("fixed "))


EXTRAS = '''
import numpy as np
import bearingfw


class Dashpot:
    name = "test-dashpot"
    dims = 1
    rigid = False
    uses_velocity = True

    def __init__(self, c=1.0):
        self.c = c

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt, velocity=None):
        v = np.zeros_like(u) if velocity is None else velocity
        return bearingfw.LawResponse(self.c * v, np.zeros((len(u), 1, 1)), state)


class PeakMetric:
    name = "test-peak"
    description = "the peak of something, for a test"


class InlineExecutor:
    name = "test-inline"


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [Dashpot]


@bearingfw.hookimpl
def bearingfw_register_metrics():
    return [PeakMetric()]


@bearingfw.hookimpl
def bearingfw_register_executors():
    return [InlineExecutor()]
'''


def test_metric_families_executors_and_velocity_laws_are_listed(tmp_path, monkeypatch, capsys):
    import importlib.metadata as metadata

    import bearingfw.cli.plugins as command
    from bearingfw.plugins import load_registry

    (tmp_path / "cli_extras_plugin.py").write_text(EXTRAS)
    monkeypatch.syspath_prepend(str(tmp_path))
    registry = load_registry([
        *metadata.entry_points(group="bearingfw", name="builtin-laws"),
        metadata.EntryPoint("cli-extras", "cli_extras_plugin", "bearingfw"),
    ])
    assert registry.broken == ()
    monkeypatch.setattr(command, "get_registry", lambda: registry)
    assert main(["plugins", "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    assert [(m["name"], m["plugin"], m["description"]) for m in listing["metrics"]] == [
        ("test-peak", "cli-extras", "the peak of something, for a test")
    ]
    assert [(e["name"], e["plugin"], e["description"]) for e in listing["executors"]] == [("test-inline", "cli-extras", "")]
    assert listing["presets"] == []
    assert main(["plugins"]) == 0
    out = capsys.readouterr().out
    dashpot = next(line for line in out.splitlines() if line.strip().startswith("test-dashpot "))
    assert "velocity, rate-dependent" in dashpot  # uses_velocity implies rate dependence
    metrics = out[out.index("Metric families:"):out.index("Executors:")]
    assert "test-peak" in metrics and "the peak of something, for a test" in metrics
    assert "test-inline" in out[out.index("Executors:"):]
    assert "Bearing presets:\n  (none)" in out
