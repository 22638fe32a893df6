"""What the OpenSees comparison tests share: skipping without OpenSeesPy, and loading the scripts
of validation/ (imported by the test modules of this folder)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

VALIDATION = Path(__file__).resolve().parents[2] / "validation"


def require_opensees() -> None:
    """Skip the calling test module unless OpenSeesPy is installed and loads; put validation/ on the path."""
    pytest.importorskip("openseespy", reason="OpenSeesPy is the optional extra: pip install -e '.[validation]'")
    if str(VALIDATION) not in sys.path:
        sys.path.insert(0, str(VALIDATION))
    import _opensees

    try:
        _opensees.import_opensees()
    except _opensees.OpenSeesUnavailable as exc:  # installed but its bundled libraries do not load
        pytest.skip(str(exc), allow_module_level=True)


def load_script(name: str):
    """validation/<name>.py as a module (registered in sys.modules: attrs classes look it up there)."""
    spec = importlib.util.spec_from_file_location(f"bearingfw_validation_{name}", VALIDATION / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module
