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
