"""Plugin discovery: good plugins load, broken ones are reported and never stop the others."""

import importlib.metadata as metadata
import textwrap

import pytest

from bearingfw import ParameterError, create_law
from bearingfw.plugins import UnknownLawError, load_registry

GOOD = '''
import numpy as np
import bearingfw


class Stiffening:
    """F = k u (1 + (u / u0)^2): a plain class, no bearingfw base."""

    name = "stiffening-spring"
    dims = 1
    rigid = False

    def __init__(self, k, u0=0.01):
        if not k > 0:
            raise ValueError(f"k must be > 0, got {k}")
        self.k, self.u0 = k, u0

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        r = u / self.u0
        force = self.k * u * (1 + r**2)
        tangent = self.k * (1 + 3 * r**2)
        return bearingfw.LawResponse(force, tangent[:, :, None], state)


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [Stiffening]
'''

PLUGINS = {
    "good_plugin": GOOD,
    "import_error_plugin": "import numpy\nimport no_such_module_anywhere\n",
    "missing_member_plugin": '''
import bearingfw

class NoRespond:
    name = "no-respond"
    dims = 1
    rigid = False
    def initial_state(self, n):
        return {}

@bearingfw.hookimpl
def bearingfw_register_laws():
    return [NoRespond]
''',
    "duplicate_plugin": '''
import bearingfw
from good_plugin import Stiffening

class Impostor(Stiffening):
    name = "linear-spring"

@bearingfw.hookimpl
def bearingfw_register_laws():
    return [Impostor]
''',
    "raising_plugin": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_laws():
    raise RuntimeError("database of laws is offline")
''',
    "not_a_class_plugin": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_laws():
    return ["regularized-coulomb"]
''',
    "typo_plugin": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_law():
    return []
''',
    "bad_signature_plugin": '''
import bearingfw

@bearingfw.hookimpl
def bearingfw_register_laws(config):
    return []
''',
}


@pytest.fixture
def plugin_dir(tmp_path, monkeypatch):
    for module, source in PLUGINS.items():
        (tmp_path / f"{module}.py").write_text(textwrap.dedent(source))
    monkeypatch.syspath_prepend(str(tmp_path))
    return tmp_path


def entry_points(*modules):
    builtin = metadata.entry_points(group="bearingfw", name="builtin-laws")
    return [*builtin, *(metadata.EntryPoint(m.replace("_", "-"), m, "bearingfw") for m in modules)]


def test_a_third_party_law_loads_next_to_the_built_in_ones(plugin_dir):
    registry = load_registry(entry_points("good_plugin"))
    assert {"frictionless", "fixed", "linear-spring", "regularized-coulomb", "stiffening-spring"} <= set(registry.laws)
    assert registry.laws["stiffening-spring"].origin.plugin == "good-plugin"
    assert registry.laws["linear-spring"].origin.distribution == "bearingfw"
    assert registry.broken == ()
    law = create_law("stiffening-spring", registry=registry, k=2.0, u0=1.0)
    force = law.respond({}, __import__("numpy").array([[2.0]]), [0.0], 0.01).force
    assert force[0, 0] == pytest.approx(2.0 * 2.0 * 5.0)


@pytest.mark.parametrize(
    "module, message",
    [
        ("import_error_plugin", "ModuleNotFoundError: No module named 'no_such_module_anywhere'"),
        ("missing_member_plugin", "lacks protocol member(s) respond"),
        ("duplicate_plugin", "name 'linear-spring' is already registered by plugin 'builtin-laws'"),
        ("raising_plugin", "bearingfw_register_laws raised RuntimeError: database of laws is offline"),
        ("not_a_class_plugin", "must return classes"),
        ("typo_plugin", "implements unknown hook 'bearingfw_register_law'"),
        ("bad_signature_plugin", "config"),
    ],
)
def test_a_broken_plugin_is_reported_by_name_and_the_others_still_load(plugin_dir, module, message):
    registry = load_registry(entry_points(module, "good_plugin"))
    assert [b.plugin for b in registry.broken] == [module.replace("_", "-")]
    assert message in registry.broken[0].error
    assert {"linear-spring", "regularized-coulomb", "stiffening-spring"} <= set(registry.laws)
    # The built-in linear spring survives an impostor of the same name.
    assert registry.laws["linear-spring"].origin.plugin == "builtin-laws"


def test_unknown_law_lists_the_known_ones(plugin_dir):
    registry = load_registry(entry_points("good_plugin"))
    with pytest.raises(UnknownLawError, match="unknown bearing law 'coulomb'; known laws: fixed, frictionless, "):
        create_law("coulomb", registry=registry)


def test_a_plain_class_constructor_error_names_the_law(plugin_dir):
    registry = load_registry(entry_points("good_plugin"))
    with pytest.raises(ParameterError, match="stiffening-spring: k must be > 0"):
        create_law("stiffening-spring", registry=registry, k=-1.0)
    with pytest.raises(ParameterError, match=r"stiffening-spring: missing parameter\(s\) 'k'"):
        create_law("stiffening-spring", registry=registry)
    with pytest.raises(ParameterError, match=r"unknown parameter\(s\) 'mu'"):
        create_law("stiffening-spring", registry=registry, k=1.0, mu=0.1)
