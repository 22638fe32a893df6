"""Every package of bearingfw imports only the layers below it (DESIGN.md, "Layers").

The per-package layering tests (model, oma, bridges) say why a particular boundary matters; this
one holds the whole order, so that a new module or package cannot slip an upward import past
them. Side packages are reached by no other package: ``laws`` (a plugin, found through its entry
point) and ``testing`` (the conformance kit, for a plugin author's tests).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from import_graph import imported_modules

import bearingfw

ROOT = Path(bearingfw.__file__).parent

#: Lowest first; a package may import its own rank and below.
RANK = {
    "protocol": 0, "parameters": 0, "jit": 0,
    "plugins": 1, "plotting": 1,
    "laws": 2, "testing": 2,
    "model": 3,
    "analysis": 4,
    "motion": 5,
    "oma": 6,
    "tuning": 7,
    "bridges": 8,  # beside tuning: only its glue modules (the paper's tuning steps) use tuning
    "structures": 9,
    "experiment": 10,
    "cli": 11,
}
SIDE = {"laws", "testing"}


def _package(path: Path) -> str:
    rel = path.relative_to(ROOT)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _sources():
    return [p for p in sorted(ROOT.rglob("*.py")) if _package(p) in RANK]


def test_every_package_has_a_rank():
    packages = {_package(p) for p in ROOT.rglob("*.py")} - {"__init__", "__main__"}
    assert packages <= set(RANK), f"packages without a layer: {sorted(packages - set(RANK))}"


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(ROOT)))
def test_imports_go_down_only(path):
    own = _package(path)
    for name in imported_modules(path):
        if not name.startswith("bearingfw."):
            continue
        target = name.split(".")[1]
        if target not in RANK or target == own:
            continue  # a name re-exported by bearingfw/__init__ (e.g. __version__)
        assert target not in SIDE, f"{path.relative_to(ROOT)} imports the side package {name}"
        assert RANK[target] <= RANK[own], f"{path.relative_to(ROOT)} ({own}) imports the higher layer {name}"
