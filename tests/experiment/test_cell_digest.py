"""What a cell's digest covers besides the data: bearingfw's version, the versions of the plugin
distributions whose laws the cell uses, and the sources of the experiment's own code (the builder
and the modules it imports from the experiment's folders); and what it leaves out: the names, and
what is recorded (``[output] histories``, ``every``)."""

from __future__ import annotations

import textwrap

import attrs
import pytest
from tiny_experiment import EXAMPLE, tiny_toml, write_tiny

import bearingfw
from bearingfw.experiment import load_experiment, plan_cells
from bearingfw.experiment.structure import import_paths, local_sources, registry_for


def _digests(experiment, registry=None) -> dict[str, str]:
    return {j.id: j.digest for j in plan_cells(experiment, registry)}


def test_the_bearingfw_version_is_an_input(tmp_path, monkeypatch):
    experiment = load_experiment(write_tiny(tmp_path, models=("M1",), levels=("D_0",)))
    before = _digests(experiment)
    monkeypatch.setattr(bearingfw, "__version__", "99.0")
    after = _digests(experiment)
    assert before.keys() == after.keys() and all(before[c] != after[c] for c in before)


def _with_version(registry, law: str, version: str):
    entry = registry.laws[law]
    moved = attrs.evolve(entry, origin=attrs.evolve(entry.origin, distribution="some-plugin", version=version))
    return attrs.evolve(registry, laws={**registry.laws, law: moved})


def test_a_plugin_version_changes_only_the_cells_whose_laws_it_provides(tmp_path):
    experiment = load_experiment(write_tiny(tmp_path, models=("M0", "M1", "M2"), levels=("D_0",)))
    registry = registry_for(experiment.plugins, import_paths(experiment))
    old = _digests(experiment, _with_version(registry, "regularized-coulomb", "1.0"))
    new = _digests(experiment, _with_version(registry, "regularized-coulomb", "1.1"))
    assert [c for c in old if old[c] != new[c]] == ["M2/tremor/D_0"]  # only M2 uses regularized-coulomb
    assert old["M1/tremor/D_0"] == _digests(experiment, registry)["M1/tremor/D_0"]
    job = next(j for j in plan_cells(experiment, _with_version(registry, "regularized-coulomb", "1.1"))
               if j.model == "M2")
    assert job.inputs["code"]["distributions"]["some-plugin"] == "1.1"


def test_an_own_plugin_modules_source_counts_for_the_cells_that_use_its_laws(tmp_path):
    """``plugins = [...]`` modules of the experiment are hashed by source: the test laws' module here."""
    experiment = load_experiment(write_tiny(tmp_path, models=("M1", "slow"), levels=("D_0",)))
    jobs = {j.model: j for j in plan_cells(experiment)}
    assert "bfw_test_laws" in jobs["slow"].inputs["code"]["sources"]
    assert "bfw_test_laws" not in jobs["M1"].inputs["code"]["sources"]


PACKAGE = {
    "__init__.py": "",
    "builder.py": """\
        from small_bridge import build as _build

        from . import geometry

        def build(**options):
            from .loads import DEAD  # imported when called: still the builder's code
            return _build(span=geometry.SPAN, superimposed_dead_load=DEAD, **options)
        """,
    "geometry.py": "SPAN = 24.0\n",
    "loads.py": "DEAD = 3000.0\n",
    "unused.py": "X = 1\n",
}


def _package(folder):
    for name, text in PACKAGE.items():
        path = folder / "mybridge" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))


def test_the_builder_and_what_it_imports_from_the_experiments_folders_are_inputs(tmp_path):
    spec = tmp_path / "spec"
    _package(spec)
    path = spec / "tiny.toml"
    path.write_text(tiny_toml(models=("M1",), levels=("D_0",),
                              **{'builder = "small_bridge:build"': 'builder = "mybridge.builder:build"'}))
    base = _digests(load_experiment(path))
    sources = plan_cells(load_experiment(path))[0].inputs["code"]["sources"]["mybridge.builder"]
    # the package, its modules the builder imports (at the top or in a function), and small_bridge from
    # python_path; not the package's other modules, not bearingfw
    assert sorted(sources) == ["mybridge", "mybridge.builder", "mybridge.geometry", "mybridge.loads", "small_bridge"]
    for name, edit in (("geometry.py", "SPAN = 24.0  # checked\n"), ("loads.py", "DEAD = 3000.0\n\n"),
                       ("__init__.py", "# the package\n"), ("builder.py", None)):
        file = spec / "mybridge" / name
        old = file.read_text()
        file.write_text(edit if edit is not None else old + "\n# edited\n")
        assert _digests(load_experiment(path)) != base, name
        file.write_text(old)
    assert _digests(load_experiment(path)) == base
    (spec / "mybridge" / "unused.py").write_text("X = 2\n")
    assert _digests(load_experiment(path)) == base


def test_local_sources_resolve_relative_and_submodule_imports(tmp_path):
    _package(tmp_path)
    (tmp_path / "mybridge" / "sub").mkdir()
    (tmp_path / "mybridge" / "sub" / "__init__.py").write_text("from .. import geometry\nfrom ..sub import deep\n")
    (tmp_path / "mybridge" / "sub" / "deep.py").write_text("import mybridge.loads\nfrom mybridge import *\n")
    found = local_sources("mybridge.sub.deep", (str(tmp_path),))
    assert sorted(found) == ["mybridge", "mybridge.geometry", "mybridge.loads", "mybridge.sub", "mybridge.sub.deep"]
    assert local_sources("mybridge.nothing", (str(tmp_path),)) is None
    assert local_sources("small_bridge", (str(EXAMPLE),)).keys() == {"small_bridge"}


def test_recording_settings_are_not_inputs(tmp_path):
    """What is kept of the histories changes no physics: the same digests (the store tells the rest)."""
    base = _digests(load_experiment(write_tiny(tmp_path / "a", models=("M1",), levels=("D_0",))))
    for setting in ("histories = false", "every = 5"):
        path = write_tiny(tmp_path / setting.split()[0], models=("M1",), levels=("D_0",),
                          **{"[output]\n": f"[output]\n{setting}\n"})
        assert _digests(load_experiment(path)) == base, setting


@pytest.mark.parametrize("change", ["[integration]\ndt_integration = 0.005", "[damping]\nalpha = 0.1\nbeta = 0.001"])
def test_physics_settings_are_inputs(tmp_path, change):
    base = _digests(load_experiment(write_tiny(tmp_path / "a", models=("M1",), levels=("D_0",))))
    table = change.split("\n")[0]
    text = tiny_toml(models=("M1",), levels=("D_0",))
    text = text.replace("[integration]\ndt_integration = 0.01", "") + "\n" + change + "\n"
    path = tmp_path / "b" / "tiny.toml"
    path.parent.mkdir()
    path.write_text(text)
    assert _digests(load_experiment(path)) != base, table
