"""The kernel reaches laws only through the protocol and the registry."""

from __future__ import annotations

import ast
from pathlib import Path

from import_graph import imported_modules

import bearingfw
from bearingfw.plugins import get_registry

KERNEL = [Path(bearingfw.__file__).parent / sub for sub in ("model", "analysis")]
FORBIDDEN_IMPORTS = (
    "bearingfw.laws", "bearingfw.cli", "bearingfw.experiment", "bearingfw.motion", "bearingfw.oma", "bearingfw.tuning",
)


def kernel_files():
    files = [f for d in KERNEL for f in sorted(d.rglob("*.py"))]
    assert files
    return files


def test_no_kernel_module_imports_a_law_or_a_higher_layer():
    for path in kernel_files():
        for name in imported_modules(path):
            assert not name.startswith(FORBIDDEN_IMPORTS), f"{path.name} imports {name}"


def test_no_kernel_module_names_a_concrete_law():
    laws = set(get_registry().laws) | {"frictionless", "fixed", "linear-spring", "regularized-coulomb", "bouc-wen"}
    for path in kernel_files():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                assert node.value not in laws, f"{path.name} names the law {node.value!r}"
