"""Shared helpers of the OpenSeesPy validation scripts.

Two jobs:

1. Import OpenSeesPy on Linux. The ``openseespylinux`` wheel ships its own BLAS, LAPACK and
   Fortran run-time libraries in ``openseespylinux/lib`` but its extension module does not find
   them unless ``LD_LIBRARY_PATH`` points there. :func:`import_opensees` first tries a plain
   import, then loads those libraries by absolute path (``ctypes``, ``RTLD_GLOBAL``) and tries
   again, so neither the scripts nor pytest need the variable. :func:`ensure_opensees` adds a
   last resort for the scripts: re-execute the interpreter with ``LD_LIBRARY_PATH`` set.

2. Drive single OpenSees elements through prescribed displacement histories (a fixed node and
   a node whose degrees of freedom are all prescribed by ``sp`` constraints following ``Path``
   time series, imposed with Lagrange multipliers so that a zero tangent in sliding does not
   make the system singular) and return the element's basic forces.

Every driver accepts ``substeps``: each increment of the path is cut into that many equal
parts (linear interpolation, which is also what a ``Path`` series does), and only the
original points are returned. Rate-independent OpenSees elements integrate each increment in
one implicit step, so this is how the integration error on the OpenSees side is controlled.
"""

from __future__ import annotations

import ctypes
import importlib
import importlib.util
import os
import sys
from pathlib import Path

import numpy as np

__all__ = [
    "OpenSeesUnavailable",
    "opensees_lib_dir",
    "import_opensees",
    "ensure_opensees",
    "drive_zero_length",
    "drive_flat_slider",
    "drive_elastomeric_bouc_wen",
]

#: Load order of the bundled libraries (each after the ones it links against).
_BUNDLED = ("libquadmath.so.0", "libgfortran.so.4", "libgomp.so.1", "libblas.so.3", "liblapack.so.3")
_REEXEC_FLAG = "BEARINGFW_VALIDATION_REEXEC"


class OpenSeesUnavailable(ImportError):
    """OpenSeesPy is not installed or its extension module cannot be loaded."""


def opensees_lib_dir() -> Path | None:
    """The ``openseespylinux/lib`` folder of the installed wheel, or None (not installed / not Linux)."""
    try:
        spec = importlib.util.find_spec("openseespylinux")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    lib = Path(list(spec.submodule_search_locations)[0]) / "lib"
    return lib if lib.is_dir() else None


def _forget_failed_import():
    for name in [m for m in sys.modules if m == "openseespy" or m.startswith(("openseespy.", "openseespylinux"))]:
        del sys.modules[name]


def import_opensees():
    """Return ``openseespy.opensees``, preloading the wheel's bundled libraries if needed.

    Raises :class:`OpenSeesUnavailable` (an ``ImportError``, so ``pytest.importorskip`` treats it
    as "not available") when OpenSeesPy is not installed or still cannot be loaded.
    """
    if importlib.util.find_spec("openseespy") is None:
        raise OpenSeesUnavailable("openseespy is not installed (pip install -e '.[validation]')")
    try:
        return importlib.import_module("openseespy.opensees")
    except (ImportError, RuntimeError) as first_error:
        _forget_failed_import()
        lib = opensees_lib_dir()
        if lib is None:
            raise OpenSeesUnavailable(f"openseespy is installed but cannot be imported: {first_error}") from first_error
        try:
            for name in _BUNDLED:
                if (lib / name).exists():
                    ctypes.CDLL(str(lib / name), mode=ctypes.RTLD_GLOBAL)
            return importlib.import_module("openseespy.opensees")
        except (ImportError, RuntimeError, OSError) as second_error:
            _forget_failed_import()
            raise OpenSeesUnavailable(
                f"openseespy cannot be imported even with its bundled libraries preloaded ({second_error}); "
                f"try LD_LIBRARY_PATH={lib}"
            ) from second_error


def ensure_opensees():
    """:func:`import_opensees`, re-executing the script with ``LD_LIBRARY_PATH`` set if that fails.

    For command-line scripts only (it replaces the running process).
    """
    try:
        return import_opensees()
    except OpenSeesUnavailable:
        lib = opensees_lib_dir()
        if lib is None or os.environ.get(_REEXEC_FLAG):
            raise
        env = dict(os.environ)
        env["LD_LIBRARY_PATH"] = os.pathsep.join(filter(None, [str(lib), env.get("LD_LIBRARY_PATH")]))
        env[_REEXEC_FLAG] = "1"
        sys.stdout.flush()
        os.execve(sys.executable, [sys.executable, *sys.argv], env)


# --------------------------------------------------------------------------------------------
# Drivers


def _refine(values: np.ndarray, substeps: int) -> np.ndarray:
    """Insert ``substeps - 1`` equally spaced points in every increment of ``values`` (axis 0)."""
    if substeps == 1:
        return values
    fractions = np.arange(substeps) / substeps
    start, step = values[:-1], np.diff(values, axis=0)
    fine = start[:, None] + fractions.reshape((1, -1) + (1,) * (values.ndim - 1)) * step[:, None]
    return np.concatenate([fine.reshape(-1, *values.shape[1:]), values[-1:]], axis=0)


def _static_analysis(ops, steps: int, record):
    """Run ``steps`` load-control steps of size 1 (time = step number) and call ``record()`` after each."""
    ops.constraints("Lagrange")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    # Every degree of freedom is prescribed: the first Newton iteration imposes the displacements
    # exactly (Lagrange rows), the second only updates the multipliers (the reactions).
    ops.test("FixedNumIter", 2)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    out = []
    for i in range(steps):
        if ops.analyze(1) != 0:
            raise RuntimeError(f"OpenSees analysis failed at step {i + 1}")
        out.append(record())
    return out


def _path_series(ops, tag: int, values):
    """A ``Path`` time series through ``values`` at times 0, 1, 2, ... and a pattern using it.

    The last value is repeated once: a ``Path`` series is zero from its last time point on,
    which would otherwise zero the final step.
    """
    values = [*map(float, values), float(values[-1])]
    ops.timeSeries("Path", tag, "-dt", 1.0, "-values", *values)
    ops.pattern("Plain", tag, tag)


def drive_zero_length(material: tuple, u, substeps: int = 1):
    """Drive a 1-D ``zeroLength`` element made of ``uniaxialMaterial(*material)`` through ``u``.

    ``material`` is the argument tuple of ``ops.uniaxialMaterial`` after the tag, e.g.
    ``("ElasticPP", E, epsyP)``. ``u`` (steps,) are the displacements after steps 1..steps (the
    element starts undeformed at 0). Returns ``(force, displacement)`` histories, each (steps,),
    read back from the element and from node 2.
    """
    ops = import_opensees()
    u = np.asarray(u, dtype=float)
    path = _refine(np.concatenate([[0.0], u]), substeps)
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.uniaxialMaterial(material[0], 1, *material[1:])
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1)
    _path_series(ops, 1, path)
    ops.sp(2, 1, 1.0)
    rows = _static_analysis(ops, len(path) - 1, lambda: (ops.eleResponse(1, "force")[1], ops.nodeDisp(2, 1)))
    rows = np.array(rows)[substeps - 1 :: substeps]
    ops.wipe()
    return rows[:, 0], rows[:, 1]


def _bearing_model(ops, shear_path, axial_path, element_args):
    """3-D two-node bearing at the origin: local x (axial) = global X, shear y, z = global Y, Z.

    Node 1 is fixed; node 2 has its rotations fixed and its three translations prescribed:
    X by ``axial_path`` (steps + 1,), Y and Z by ``shear_path`` (steps + 1, 2).
    """
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.node(2, 0.0, 0.0, 0.0)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 0, 0, 1, 1, 1)
    element_args()
    for dof, values in ((1, axial_path), (2, shear_path[:, 0]), (3, shear_path[:, 1])):
        _path_series(ops, dof, values)
        ops.sp(2, dof, 1.0)


def _bearing_run(ops, steps: int, substeps: int):
    def record():
        q = ops.eleResponse(1, "basicForce")
        d = ops.nodeDisp(2)
        return q[0], q[1], q[2], d[1], d[2]

    rows = np.array(_static_analysis(ops, steps, record))[substeps - 1 :: substeps]
    ops.wipe()
    return rows


def drive_flat_slider(mu: float, k: float, u, normal_force, substeps: int = 1, axial_stiffness: float = 1e13):
    """Drive a ``flatSliderBearing`` (``frictionModel Coulomb mu``, ``kInit = k``) in two shear directions.

    ``u`` (steps, 2) are the shear displacements; ``normal_force`` (a scalar or (steps,)) the
    compressive normal force, imposed through the axial displacement ``-N / axial_stiffness`` of
    an elastic axial material (flatSliderBearing takes ``N = -(axial basic force)``). Returns
    ``(shear_force (steps, 2), normal_force (steps,), shear_displacement (steps, 2))``.
    """
    ops = import_opensees()
    u = np.asarray(u, dtype=float)
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), u.shape[:1])
    shear = _refine(np.vstack([np.zeros((1, 2)), u]), substeps)
    # Start from the first normal force so that the first shear step already sees it.
    axial = _refine(np.concatenate([normal[:1], normal]), substeps) * (-1.0 / axial_stiffness)

    def element():
        ops.frictionModel("Coulomb", 1, mu)
        ops.uniaxialMaterial("Elastic", 1, axial_stiffness)
        ops.uniaxialMaterial("Elastic", 2, 1e12)
        ops.element(
            "flatSliderBearing", 1, 1, 2, 1, k, "-P", 1, "-T", 2, "-My", 2, "-Mz", 2,
            "-orient", 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, "-iter", 50, 1e-12,
        )  # fmt: skip

    _bearing_model(ops, shear, axial, element)
    rows = _bearing_run(ops, len(shear) - 1, substeps)
    return rows[:, 1:3], -rows[:, 0], rows[:, 3:5]


def drive_elastomeric_bouc_wen(
    k_init: float, qd: float, alpha1: float, eta: float, beta: float, gamma: float, u, substeps: int = 1
):
    """Drive an ``elastomericBearingBoucWen`` (3-D: coupled shear) in two shear directions.

    OpenSees's arguments: ``kInit qd alpha1 alpha2 mu eta beta gamma`` (``alpha2 = 0``: no
    nonlinear hardening; its exponent ``mu`` then plays no part). Returns
    ``(shear_force (steps, 2), shear_displacement (steps, 2))``.
    """
    ops = import_opensees()
    u = np.asarray(u, dtype=float)
    shear = _refine(np.vstack([np.zeros((1, 2)), u]), substeps)

    def element():
        ops.uniaxialMaterial("Elastic", 1, 1e12)
        ops.uniaxialMaterial("Elastic", 2, 1e12)
        ops.element(
            "elastomericBearingBoucWen", 1, 1, 2, k_init, qd, alpha1, 0.0, 2.0, eta, beta, gamma,
            "-P", 1, "-T", 2, "-My", 2, "-Mz", 2, "-orient", 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, "-iter", 100, 1e-12,
        )  # fmt: skip

    _bearing_model(ops, shear, np.zeros(len(shear)), element)
    rows = _bearing_run(ops, len(shear) - 1, substeps)
    return rows[:, 1:3], rows[:, 3:5]
