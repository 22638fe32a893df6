"""The paper's SDOF reasoning (figure 15, eqs. 7-11) on a two-column frame, and law swapping."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import SDOF_KC, SDOF_M, sdof_frame_model

from bearingfw.analysis import gravity, solve_modal
from bearingfw.model import ModelError, build_system

TOL = 1e-3  # the tolerance; the measured errors are ~1e-12 (see the report)
KS = 462e6  # the paper's eq.-11 estimate for the bridge


def lateral_frequency(model, **kw):
    res = solve_modal(model, 2, **kw)
    mode = res.dominant("y")
    assert res.labels[mode] == "lateral"
    return res.frequencies[mode]


def f_a():
    return np.sqrt(SDOF_KC / SDOF_M) / (2 * np.pi)  # eq. 7


def f_b(ks):
    return np.sqrt(SDOF_KC / SDOF_M * (SDOF_KC + 2 * ks) / (SDOF_KC + ks)) / (2 * np.pi)  # eq. 9


def eq_11(kc, fa, fb):
    alpha2 = (fb / fa) ** 2  # eq. 10
    return kc * (alpha2 - 1) / (2 - alpha2)


@pytest.mark.parametrize("kind", ["planar", "axial"])
def test_paper_sdof_reasoning(kind):
    fa = lateral_frequency(sdof_frame_model("frictionless", kind=kind))
    fb = lateral_frequency(sdof_frame_model("linear-spring", {"k": KS}, kind=kind))
    assert fa == pytest.approx(f_a(), rel=TOL)
    assert fb == pytest.approx(f_b(KS), rel=TOL)
    assert eq_11(SDOF_KC, fa, fb) == pytest.approx(KS, rel=TOL)
    # the paper's numbers: f_a = 1.87 Hz by construction of m, and K_s = 462 MN/m lifts it to 2.48 Hz
    assert fa == pytest.approx(1.87, rel=TOL) and fb == pytest.approx(2.48, rel=TOL)


@pytest.mark.parametrize(
    "law, params, expected",
    [
        ("frictionless", {}, lambda: f_a()),
        ("linear-spring", {"k": KS}, lambda: f_b(KS)),
        ("regularized-coulomb", {"k": KS, "mu": 0.04}, lambda: f_b(KS)),  # its stick stiffness
        ("fixed", {}, lambda: np.sqrt(2 * SDOF_KC / SDOF_M) / (2 * np.pi)),  # tied: both columns
        ("test-doubled-spring", {"k": KS / 2}, lambda: f_b(KS)),  # a law from a test plugin: F = 2 k u
        ("test-doubled-spring", {"k": KS}, lambda: f_b(2 * KS)),
    ],
)
def test_swapping_the_law_changes_the_modal_result(plugin_registry, law, params, expected):
    model = sdof_frame_model(law, params)
    assert lateral_frequency(model, registry=plugin_registry) == pytest.approx(expected(), rel=TOL)


def test_a_plugin_law_with_fixed_dims_serves_a_guided_connector(plugin_registry):
    model = sdof_frame_model("test-guided-only", {"k": KS}, kind="axial")
    assert lateral_frequency(model, registry=plugin_registry) == pytest.approx(f_b(KS), rel=TOL)
    with pytest.raises(ModelError, match="governs 1 direction"):
        build_system(sdof_frame_model("test-guided-only", {"k": KS}, kind="planar"), plugin_registry)


def test_plugin_law_is_unknown_to_the_default_registry():
    with pytest.raises(
        ModelError, match=r"connector 'sliding': field 'law': unknown bearing law 'test-doubled-spring'"
    ):
        build_system(sdof_frame_model("test-doubled-spring", {"k": KS}))


def test_fixed_law_ties_instead_of_calling_respond():
    system = build_system(sdof_frame_model("fixed"))
    assert system.connectors.n_governed == 0 and not system.connectors.groups
    ties = {(system.model.connectors[c].name, k) for c, k in system.connectors.ties}
    assert {("sliding", 0), ("sliding", 1)} <= ties and ("sliding", 2) not in ties  # vertical stays a spring


def test_gravity_normal_forces_feed_the_modal_laws(plugin_registry):
    """A law whose initial tangent is c N: the lateral frequency follows the preload's N."""
    c = KS / 3e6  # N of the sliding bearing is ~3.4 MN: K_s ~ 1.1 KS
    model = sdof_frame_model("test-normal-spring", {"c": c})
    pre = gravity(build_system(model, plugin_registry))
    N = pre.normal_force("sliding")
    assert pre.normal_forces.sum() == pytest.approx(SDOF_M * 9.81, rel=1e-9)
    res = solve_modal(pre.system, 2, preload=pre)
    np.testing.assert_allclose(res.normal_forces, pre.normal_forces)
    assert lateral_frequency(pre.system, preload=pre) == pytest.approx(f_b(c * N), rel=TOL)
    # the automatic preload gives the same; a preload with twice the weight stiffens the law
    assert lateral_frequency(pre.system) == pytest.approx(f_b(c * N), rel=TOL)
    heavy = gravity(pre.system, g=2 * 9.81)
    assert lateral_frequency(pre.system, preload=heavy) == pytest.approx(f_b(2 * c * N), rel=TOL)


def test_a_plugin_law_without_parameters(plugin_registry):
    """A law class with no constructor parameters at all (dims a class attribute) works too."""
    model = sdof_frame_model("test-free-2d", kind="planar")
    assert lateral_frequency(model, registry=plugin_registry) == pytest.approx(f_a(), rel=TOL)
