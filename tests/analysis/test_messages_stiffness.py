"""Truthful kernel messages: a law's tangent that is not finite, or so stiff that the factors lose the
structure beside it, is named (law, bearing, value, allowed range) instead of being reported as a
mechanism; a real mechanism still is one.

Before: each case below said "the stiffness matrix is singular ... the model is a mechanism; check
supports", and ``bearingfw modal --ks 1e300`` said "the model has only 0 with mass".
"""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from typing import ClassVar

import attrs
import numpy as np
import pytest
from kernel_models import elastic_tangent, registry_with, sdof_frame_model

import bearingfw
from bearingfw.analysis import gravity, solve_modal, solve_static
from bearingfw.analysis.static import ACCURATE_CONTRAST, OUT_OF_RANGE, StiffnessRangeError, check_law_tangents
from bearingfw.model import ModelError, NodalLoad, build_system


@attrs.frozen
class BrokenTangent:
    """A test-only law: F = k u with the tangent ``tangent`` (NaN or infinite) instead of k."""

    name: ClassVar[str] = "test-broken-tangent"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    tangent: float = attrs.field(default=float("inf"))  # deliberately unchecked
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        tangent = np.zeros((u.shape[0], self.dims, self.dims))
        tangent[:, range(self.dims), range(self.dims)] = self.tangent
        return bearingfw.LawResponse(self.k * u, tangent, state)


@attrs.frozen
class AnisotropicSpring:
    """A test-only 2-D law: F = diag(kx, ky) u (ky = 0 leaves the y direction free)."""

    name: ClassVar[str] = "test-anisotropic-spring"
    rigid: ClassVar[bool] = False
    dims: ClassVar[int] = 2
    kx: float = attrs.field(default=1e6)
    ky: float = attrs.field(default=0.0)

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        k = np.array([self.kx, self.ky])
        return bearingfw.LawResponse(u * k, np.broadcast_to(np.diag(k), (u.shape[0], 2, 2)).copy(), state)


@pytest.fixture(scope="module")
def broken_registry():
    with registry_with([BrokenTangent, AnisotropicSpring], "broken-tangent-laws", "bearingfw_broken_tangent_plugin") as registry:
        yield registry


def spring_frame(k: float):
    """The SDOF frame whose right bearing is a linear spring ``k`` in both horizontal directions."""
    return sdof_frame_model("linear-spring", {"k": k})


@pytest.mark.parametrize("tangent", [np.inf, -np.inf, np.nan])
@pytest.mark.parametrize("bearings", ["set-after-dead-load", "active"])
def test_a_non_finite_tangent_names_the_law_the_bearing_and_the_value(broken_registry, tangent, bearings):
    model = sdof_frame_model("test-broken-tangent", {"k": 1e6, "tangent": tangent})
    with pytest.raises(StiffnessRangeError) as caught:
        gravity(model, registry=broken_registry, bearings=bearings)
    message = str(caught.value)
    assert "law 'test-broken-tangent' of the bearing 'sliding'" in message
    assert f"tangent stiffness {float(tangent)} (not finite)" in message and "mechanism" not in message
    assert caught.value.connector == "sliding" and caught.value.law == "test-broken-tangent"


def test_a_non_finite_tangent_in_modal_is_named(broken_registry):
    model = sdof_frame_model("test-broken-tangent", {"k": 1e6})
    with pytest.raises(StiffnessRangeError, match="law 'test-broken-tangent' of the bearing 'sliding'"):
        solve_modal(model, 1, registry=broken_registry)


def test_the_stated_limit_is_truthful():
    """A spring beyond the stated limit fails naming it; one a little below it solves in both modes."""
    with pytest.raises(StiffnessRangeError) as caught:
        gravity(spring_frame(1e25))
    error = caught.value
    message = str(error)
    assert error.law == "linear-spring" and error.connector == "sliding" and error.value == 1e25
    assert "law 'linear-spring' of the bearing 'sliding' has a tangent stiffness 1e+25 N/m" in message
    assert "this is not a mechanism" in message and f"at most about {error.limit:.2g} N/m" in message
    stiffest = float(abs(build_system(spring_frame(1.0)).K_free.diagonal()).max())
    assert stiffest < error.limit <= ACCURATE_CONTRAST * stiffest
    for bearings in ("set-after-dead-load", "active"):
        gravity(spring_frame(error.limit / 3), bearings=bearings)  # resolved and converged: no error


def test_a_stiff_but_resolved_spring_still_solves_correctly():
    """Stiffer than every member but within the limit: accepted, and the answer is the rigid one."""
    load = NodalLoad("DL", fy=1e5)
    stiff = solve_static(spring_frame(1e14), [load])
    both_columns = 1e5 / (2 * 147e6)  # the right column then works as hard as the left one
    assert stiff.displacement("DL", "uy") == pytest.approx(both_columns, rel=1e-4)


@pytest.mark.parametrize("k", [1e300, OUT_OF_RANGE * 1e20])
def test_an_absurd_stiffness_is_refused_before_factorising(k):
    system = build_system(spring_frame(k))
    group = system.connectors.groups[0]
    blocks = [elastic_tangent(k, group.n, group.dims)]
    with pytest.raises(StiffnessRangeError, match=r"law 'linear-spring' of the bearing 'sliding' has a tangent stiffness"):
        check_law_tangents(system, blocks)
    check_law_tangents(system, [elastic_tangent(1e6, group.n, group.dims)])  # an ordinary one passes


def test_modal_with_an_absurd_stiffness_says_so_not_only_zero_modes_with_mass():
    with pytest.raises(StiffnessRangeError, match=r"'sliding' has a tangent stiffness 1e\+300 N/m"):
        solve_modal(spring_frame(1e300), 1)


def test_a_real_mechanism_still_says_mechanism_beside_a_huge_stiffness(broken_registry):
    """Bearings absurdly stiff along the girder but free across it: the girder's lateral motion is a
    mechanism whatever the stiffness along it, and is reported as one."""
    from test_analysis_static import simply_supported_girder

    model = simply_supported_girder("test-anisotropic-spring", {"kx": 1e25, "ky": 0.0})
    with pytest.raises(ModelError, match=r"mechanism; the free motion moves most G\d\.uy") as caught:
        gravity(model, registry=broken_registry)
    assert not isinstance(caught.value, StiffnessRangeError)
    held = simply_supported_girder("test-anisotropic-spring", {"kx": 1e25, "ky": 1e8})
    with pytest.raises(StiffnessRangeError, match="'test-anisotropic-spring' of the bearing 'C0'"):
        gravity(held, registry=broken_registry)


def run_cli(*argv) -> tuple[int, str]:
    from bearingfw.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(list(argv))
    return status, err.getvalue()


@pytest.mark.parametrize("ks", ["1e300", "1e20"])
def test_cli_modal_names_ks_and_its_allowed_range(ks):
    status, err = run_cli("modal", "--model", "M1", "--ks", ks, "--modes", "2")
    assert status == 2, err
    assert f"--ks = {float(ks):g} N/m is out of range: allowed 0 < ks <= " in err
    assert "N/m for this bridge" in err and "only 0 with mass" not in err and "check supports" not in err


@pytest.mark.parametrize("bearings", ["set-after-dead-load", "active"])
@pytest.mark.parametrize("kv", [1e24, 1e300])
def test_a_huge_vertical_stiffness_names_the_connector_and_the_field(kv, bearings):
    """Before: 'the stiffness matrix is singular ... mechanism; check supports'."""
    with pytest.raises(StiffnessRangeError) as caught:
        gravity(sdof_frame_model("linear-spring", {"k": 1e6}, vertical_stiffness=kv), bearings=bearings)
    error = caught.value
    assert str(error).startswith(f"connector 'sliding': field 'vertical_stiffness' = {kv:.3g} N/m is ")
    assert "this is not a mechanism" in str(error) and error.law is None and 1e11 < error.limit < kv
    gravity(sdof_frame_model("linear-spring", {"k": 1e6}, vertical_stiffness=error.limit / 1e3), bearings=bearings)
