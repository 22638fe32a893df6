"""Real packages, installed with pip, extend bearingfw through the entry-point group alone.

Each package is pip-installed into its own target folder (no change to the environment the
tests run in) and used from a fresh interpreter that has that folder on its path.
"""

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

THROWAWAY_LAW = '''
import numpy as np
from bearingfw import LawResponse, hookimpl


class TanhSpring:
    """F = F_max tanh(k u / F_max): smooth saturation. A plain class."""

    name = "tanh-spring"
    dims = 1
    rigid = False

    def __init__(self, k, f_max):
        self.k, self.f_max = float(k), float(f_max)

    def initial_state(self, n):
        return {}

    def force_bound(self, normal_force):
        return np.full(np.shape(normal_force), self.f_max)

    def respond(self, state, u, normal_force, dt):
        x = self.k * np.asarray(u, dtype=float) / self.f_max
        return LawResponse(self.f_max * np.tanh(x), (self.k / np.cosh(x) ** 2)[:, :, None], state)


@hookimpl
def bearingfw_register_laws():
    return [TanhSpring]
'''


def pip_install_into(target: Path, package: Path) -> None:
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation", "--target", str(target), str(package)],
        check=True,
        capture_output=True,
    )


def run_python(target: Path, *args: str, returncode: int = 0) -> str:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(target), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True)
    assert done.returncode == returncode, done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def throwaway_site(tmp_path_factory):
    root = tmp_path_factory.mktemp("throwaway")
    package = root / "package"
    (package / "tanh_spring_plugin").mkdir(parents=True)
    (package / "tanh_spring_plugin" / "__init__.py").write_text(THROWAWAY_LAW)
    (package / "pyproject.toml").write_text(
        textwrap.dedent(
            """
            [build-system]
            requires = ["setuptools>=68"]
            build-backend = "setuptools.build_meta"

            [project]
            name = "throwaway-tanh-spring"
            version = "0.0.1"

            [project.entry-points.bearingfw]
            tanh = "tanh_spring_plugin"

            [tool.setuptools]
            packages = ["tanh_spring_plugin"]
            """
        )
    )
    site = root / "site"
    pip_install_into(site, package)
    return site


def listed_laws(site: Path) -> dict:
    listing = json.loads(run_python(site, "-m", "bearingfw", "plugins", "--json"))
    return {law["name"]: law for law in listing["laws"]}, listing["broken"]


def test_a_pip_installed_law_appears_in_bearingfw_plugins(throwaway_site):
    laws, broken = listed_laws(throwaway_site)
    assert broken == []
    tanh = laws["tanh-spring"]
    assert (tanh["distribution"], tanh["version"], tanh["plugin"]) == ("throwaway-tanh-spring", "0.0.1", "tanh")
    assert [p["name"] for p in tanh["parameters"]] == ["k", "f_max"]
    assert {"frictionless", "fixed", "linear-spring", "regularized-coulomb"} <= set(laws)


def test_a_pip_installed_law_works_with_create_law_drive_and_the_conformance_suite(throwaway_site):
    script = """
import json, numpy as np
from bearingfw import create_law
from bearingfw.testing import check_law, drive
law = create_law("tanh-spring", k=1e6, f_max=1e3)
check_law(law)
print(json.dumps(drive(law, [1e-4, 5e-3, -5e-3]).tolist()))
"""
    forces = json.loads(run_python(throwaway_site, "-c", script))
    expected = [1e3 * __import__("math").tanh(1e6 * u / 1e3) for u in (1e-4, 5e-3, -5e-3)]
    assert forces == pytest.approx(expected, rel=1e-12)


def test_the_example_plugin_package_installs_and_passes_its_own_tests(tmp_path):
    # A copy: building in place would write build/ and *.egg-info into the repository (a race when two
    # test sessions install it at once), and the copy's tests run as in a user's clone of the example,
    # under no pytest configuration of this repository (its addopts, e.g. -n, stay out).
    example = shutil.copytree(REPO / "examples" / "custom-law-plugin", tmp_path / "custom-law-plugin",
                              ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    site = tmp_path / "site"
    pip_install_into(site, example)
    laws, broken = listed_laws(site)
    assert broken == []
    assert laws["viscous-damper"]["distribution"] == "bearingfw-viscous-damper"
    run_python(site, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(example / "tests"))


THROWAWAY_PRESET = '''
import numpy as np
from bearingfw import BearingPreset, LawResponse, hookimpl


class TanhFriction:
    """F = f_max tanh(k u / f_max): friction with a smooth knee. A plain class."""

    name = "tanh-friction"
    dims = 1
    rigid = False

    def __init__(self, k, f_max, dims=1):
        self.k, self.f_max, self.dims = float(k), float(f_max), dims

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        x = self.k * np.asarray(u, dtype=float) / self.f_max
        tangent = np.einsum("ij,jk->ijk", self.k / np.cosh(x) ** 2, np.eye(self.dims))
        return LawResponse(self.f_max * np.tanh(x), tangent, state)


def tanh_friction(bearing):
    return ("tanh-friction", {"k": bearing.ks, "f_max": bearing.friction * bearing.dead_load})


@hookimpl
def bearingfw_register_laws():
    return [TanhFriction]


@hookimpl
def bearingfw_register_presets():
    # the second contribution is broken on purpose: it is reported, the first one loads
    return [BearingPreset("tanh-friction", "tanh friction k = K_s up to mu N_dead", tanh_friction, needs_dead_load=True),
            {"name": "not-a-preset"}]
'''


@pytest.fixture(scope="module")
def preset_site(tmp_path_factory):
    root = tmp_path_factory.mktemp("throwaway-preset")
    package = root / "package"
    (package / "tanh_friction_plugin").mkdir(parents=True)
    (package / "tanh_friction_plugin" / "__init__.py").write_text(THROWAWAY_PRESET)
    (package / "pyproject.toml").write_text(
        textwrap.dedent(
            """
            [build-system]
            requires = ["setuptools>=68"]
            build-backend = "setuptools.build_meta"

            [project]
            name = "throwaway-tanh-friction"
            version = "0.0.2"

            [project.entry-points.bearingfw]
            tanh-friction = "tanh_friction_plugin"

            [tool.setuptools]
            packages = ["tanh_friction_plugin"]
            """
        )
    )
    site = root / "site"
    pip_install_into(site, package)
    return site


def test_a_pip_installed_package_contributes_a_preset_and_a_broken_one_is_reported(preset_site):
    # the broken contribution makes the listing exit 1 (it ran; a plugin failed to load), with the JSON complete
    listing = json.loads(run_python(preset_site, "-m", "bearingfw", "plugins", "--json", returncode=1))
    presets = {p["name"]: p for p in listing["presets"]}
    entry = presets["tanh-friction"]
    assert (entry["distribution"], entry["plugin"], entry["needs_dead_load"]) == ("throwaway-tanh-friction", "tanh-friction", True)
    assert entry["description"] == "tanh friction k = K_s up to mu N_dead"
    assert {"M0", "M1", "M2", "fixed"} <= set(presets)
    assert [(b["plugin"], b["distribution"]) for b in listing["broken"]] == [("tanh-friction", "throwaway-tanh-friction")]
    assert "must return bearingfw.BearingPreset objects, got {'name': 'not-a-preset'}" in listing["broken"][0]["error"]


def test_the_reference_bridge_runs_a_third_party_preset(preset_site):
    from bearingfw.bridges import DEFAULT_KS, dead_load_normal_forces

    script = """
import json
from bearingfw.bridges import PRESETS, reference_bridge
from bearingfw.model import ConnectorKind, as_system
model = reference_bridge("tanh-friction", friction=0.05)
as_system(model)  # the laws are built from the registry
laws = {c.name: [c.law, c.params] for c in model.connectors if c.kind is not ConnectorKind.JOIN}
print(json.dumps({"description": PRESETS["tanh-friction"], "laws": laws}))
"""
    out = json.loads(run_python(preset_site, "-c", script))
    assert out["description"] == "tanh friction k = K_s up to mu N_dead"
    dead_load = dead_load_normal_forces()
    assert len(out["laws"]) == 11
    for bearing, (law, params) in out["laws"].items():
        assert law == "tanh-friction"
        assert params["k"] == DEFAULT_KS
        assert params["f_max"] == pytest.approx(0.05 * dead_load[bearing], rel=1e-12)
