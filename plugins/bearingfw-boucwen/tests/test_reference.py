"""``respond`` against frozen answers of the pure-numpy implementation it replaced (issue 16).

``reference_respond.npz`` (written by ``make_reference.py`` before the arithmetic moved to the
compiled kernels of ``bearingfw_boucwen._kernels``) holds 156 calls: 1-D and 2-D, n = 2 (closed
form), n = 1, 1.5, 3, 6 (substeps) and per-bearing mixtures of both, random admissible
parameters shared or one value per connector, 1, 2 or 5 connectors, committed states of random
walks, increments from 1e-4 to 60 yield lengths (reversals, sign changes of z's components,
components and connectors that do not move, increments below STILL uy). The compiled law must
give the same forces, tangents and states to 1e-12 relative (of each array's largest entry per
connector: a tangent's entries that nearly cancel carry the round-off of the larger ones).
"""

from pathlib import Path

import numpy as np
import pytest

import bearingfw
from bearingfw_boucwen import BoucWen

NAMES = ("k", "alpha", "uy", "A", "beta", "gamma", "n")
REFERENCE = np.load(Path(__file__).with_name("reference_respond.npz"))
RTOL = 1e-12


def law_of(values, dims):
    """The law of ``(m, 7)`` parameter rows, as ``make_reference.py`` built it."""
    if (values == values[0]).all():
        return BoucWen(**{name: float(v) for name, v in zip(NAMES, values[0], strict=True)}, dims=dims)
    return BoucWen(**{name: values[:, i].copy() for i, name in enumerate(NAMES)}, dims=dims)


def calls():
    group, dims = REFERENCE["group"], REFERENCE["dims"]
    for g in np.unique(group):
        rows = np.flatnonzero(group == g)
        d = int(dims[rows[0]])
        exponents = "/".join(f"{n:g}" for n in np.unique(REFERENCE["params"][rows, 6]))
        yield pytest.param(rows, d, id=f"call{g}-{d}D-n{exponents}")


def close(actual, expected, what):
    """Equal within RTOL of each connector's largest entry of ``expected`` (exactly where it is 0)."""
    actual, expected = actual.reshape(len(actual), -1), expected.reshape(len(expected), -1)
    scale = np.max(np.abs(expected), axis=1, keepdims=True)
    bound = np.broadcast_to(RTOL * scale + (scale == 0), actual.shape)
    np.testing.assert_array_less(np.abs(actual - expected), bound, err_msg=what)
    assert np.all(actual[scale[:, 0] == 0] == 0), what


@pytest.mark.parametrize(("rows", "dims"), list(calls()))
def test_respond_equals_the_numpy_implementation(rows, dims):
    law = law_of(REFERENCE["params"][rows], dims)
    state = {"z": REFERENCE["z0"][rows, :dims].copy(), "u": REFERENCE["u0"][rows, :dims].copy()}
    u = REFERENCE["u"][rows, :dims]
    response = law.respond(state, u, np.ones(len(rows)), 0.01)
    assert response.tangent.shape == (len(rows), dims, dims)
    close(response.force, REFERENCE["force"][rows, :dims], "force")
    close(response.tangent, REFERENCE["tangent"][rows, : dims * dims], "tangent")
    close(response.state["z"], REFERENCE["z"][rows, :dims], "z")
    np.testing.assert_array_equal(response.state["u"], u)


def test_the_reference_covers_both_integrations_and_both_dims():
    n, dims = REFERENCE["params"][:, 6], REFERENCE["dims"]
    for d in (1, 2):
        assert np.any((dims == d) & (n == 2.0)) and np.any((dims == d) & (n != 2.0))
    assert len(np.unique(REFERENCE["group"])) == 156


# --- the compiled kernels: imported lazily, one signature, checked inputs --------------------


def test_registering_and_importing_the_plugin_does_not_import_numba():
    """Every bearingfw process loads the entry points: numba (a few tenths of a second to import)
    waits for the first call of respond."""
    import subprocess
    import sys

    code = (
        "import sys, bearingfw, bearingfw_boucwen, bearingfw_boucwen.plugin\n"
        "assert 'bouc-wen' in bearingfw.get_registry().laws\n"
        "law = bearingfw.create_law('bouc-wen', k=4e8, alpha=0.0, uy=1e-3, n=2.0)\n"
        "print('numba' in sys.modules, end=' ')\n"
        "law.respond(law.initial_state(1), [[1e-3]], [1.0], 0.01)\n"
        "print('numba' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "True"]


def test_any_array_layout_answers_alike_through_one_compiled_signature():
    """Fortran-ordered, strided, read-only, integer and list states answer as C-contiguous float64
    ones, and compile nothing new (the kernels have one signature each)."""
    from bearingfw_boucwen import _kernels

    law = BoucWen(k=4e8, alpha=0.05, uy=2e-4, n=2.0, dims=2)
    rng = np.random.default_rng(3)
    state = law.respond(law.initial_state(4), rng.normal(size=(4, 2)) * 1e-3, np.ones(4), 0.01).state
    u = state["u"] + rng.normal(size=(4, 2)) * 1e-4
    reference = law.respond(state, u, np.ones(4), 0.01)
    wide = {key: np.repeat(value, 2, axis=0) for key, value in state.items()}
    read_only = {key: value.copy() for key, value in state.items()}
    for value in read_only.values():
        value.flags.writeable = False
    variants = [
        {key: np.asfortranarray(value) for key, value in state.items()},
        {key: value[::2] for key, value in wide.items()},
        read_only,
        {key: value.tolist() for key, value in state.items()},
    ]
    for variant in variants:
        for trial in (u, np.asfortranarray(u), u.tolist()):
            response = law.respond(variant, trial, np.ones(4), 0.01)
            np.testing.assert_array_equal(response.force, reference.force)
            np.testing.assert_array_equal(response.tangent, reference.tangent)
            np.testing.assert_array_equal(response.state["z"], reference.state["z"])
    integer = BoucWen(k=4e8, alpha=0.05, uy=2e-4, n=2.0, dims=1)
    zeros = np.zeros((2, 1), dtype=int)
    integer.respond({"z": zeros, "u": zeros}, np.ones((2, 1), dtype=int), [1, 1], 0)
    assert len(_kernels.respond_1d.signatures) == 1 and len(_kernels.respond_2d.signatures) == 1


@pytest.mark.parametrize("key", ["z", "u"])
def test_a_state_of_the_wrong_shape_is_named(key):
    law = BoucWen(k=4e8, alpha=0.05, uy=2e-4, dims=2)
    state = law.initial_state(3)
    state[key] = np.zeros((2, 2))
    message = rf"'state'\['{key}'\] must have the shape of 'u', \(3, 2\), got shape \(2, 2\)"
    with pytest.raises(bearingfw.ParameterError, match=message):
        law.respond(state, np.zeros((3, 2)), np.ones(3), 0.01)
