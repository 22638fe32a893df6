"""The reference bridge's bearing models come from the preset registry."""

from __future__ import annotations

import importlib.metadata as metadata

import numpy as np
import pytest

from bearingfw import BearingPreset, ParameterError
from bearingfw.bridges import BEARINGS, DEFAULT_KS, PRESETS, BridgeParameters, bearing_laws, preset_laws, reference_bridge
from bearingfw.bridges import presets as presets_module
from bearingfw.bridges.paper import FRICTION
from bearingfw.model import ConnectorKind, ModelError, as_system
from bearingfw.plugins import load_registry
from bearingfw.protocol import law_flag

SLIDING = [name for name, spec in BEARINGS.items() if spec.kind is not ConnectorKind.JOIN]


def law_groups(model):
    """The kernel's law groups of ``model`` (the internal uplift gap group left out)."""
    return [g for g in as_system(model).connectors.groups if not g.gap]


def test_presets_is_a_read_only_view_of_names_and_descriptions_in_registry_order():
    assert list(PRESETS)[:4] == ["M0", "M1", "M2", "fixed"]
    assert PRESETS["M2"] == "regularized Coulomb k = K_s, mu (step 2)"
    assert "bouc-wen" in PRESETS and "M9" not in PRESETS
    with pytest.raises(TypeError):
        PRESETS["M9"] = "a new model"  # type: ignore[index]


@pytest.mark.parametrize("build", [reference_bridge, bearing_laws])
def test_an_unknown_preset_is_a_parameter_error_naming_the_known_ones(build):
    with pytest.raises(ParameterError, match=r"unknown bearing preset 'M9'; known presets: M0, M1, M2, bouc-wen, fixed"):
        build("M9")


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"ks": 0.0}, r"ks = 0.0 must be a finite number > 0 N/m"),
        ({"ks": float("inf")}, r"ks = inf must be a finite number > 0 N/m"),
        ({"ks": "4e8"}, r"ks = '4e8' must be a finite number > 0 N/m"),
        ({"friction": 1.0}, r"friction = 1.0 must be in 0 <= friction < 1"),
        ({"friction": True}, r"friction = True must be in 0 <= friction < 1"),
    ],
)
def test_bad_stiffness_or_friction_names_the_field_and_range(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        reference_bridge("M2", **kwargs)


def test_the_registry_argument_is_the_one_asked():
    builtin_only = load_registry(
        [*metadata.entry_points(group="bearingfw", name="builtin-laws"),
         *metadata.entry_points(group="bearingfw", name="builtin-presets")]
    )
    assert bearing_laws("M1", registry=builtin_only)["1B"] == ("linear-spring", {"k": DEFAULT_KS})
    with pytest.raises(ParameterError, match="unknown bearing preset 'bouc-wen'; known presets: M0, M1, M2, fixed$"):
        reference_bridge("bouc-wen", registry=builtin_only)


def test_a_preset_object_may_be_given_in_place_of_a_name():
    stiff = BearingPreset("stiff", "springs of 3 K_s on the free bearings only",
                          lambda b: ("linear-spring", {"k": 3 * b.ks}) if b.name.endswith("B") else None)
    model = reference_bridge(stiff, ks=1e8)
    assert model.name == "reference bridge (stiff)"
    for name in SLIDING:
        connector = model.connector(name)
        if name.endswith("B"):
            assert (connector.law, connector.params) == ("linear-spring", {"k": 3e8})
        else:  # None: the bearing is fixed (JOIN)
            assert (connector.kind, connector.law) == (ConnectorKind.JOIN, None)


def test_preset_laws_serve_any_bearings_and_ask_for_the_dead_load_only_when_needed():
    assert preset_laws("M2", ["a", "b"], ks=1e8, friction=0.1) == {
        "a": ("regularized-coulomb", {"k": 1e8, "mu": 0.1}),
        "b": ("regularized-coulomb", {"k": 1e8, "mu": 0.1}),
    }
    with pytest.raises(ParameterError, match=r"preset 'bouc-wen' needs each bearing's dead-load normal force"):
        preset_laws("bouc-wen", ["a"])
    with pytest.raises(ParameterError, match=r"no dead-load normal force for bearing\(s\) b"):
        preset_laws("bouc-wen", ["a", "b"], normal_forces={"a": 1e6})
    law, params = preset_laws("bouc-wen", ["a"], ks=4e8, friction=0.05, normal_forces={"a": 2e6})["a"]
    assert (law, params["uy"]) == ("bouc-wen", pytest.approx(0.05 * 2e6 / 4e8, rel=1e-15))
    with pytest.raises(ParameterError, match=r"bouc-wen preset: bearing 'a' carries N = -5.0 N at dead load"):
        preset_laws("bouc-wen", ["a"], normal_forces={"a": -5.0})


@pytest.mark.parametrize(
    "law, message",
    [
        (lambda b: "linear-spring", r"preset 'broken' gave 'linear-spring' for bearing 'x'; a preset's law must return"),
        (lambda b: ("linear-spring", 4e8), r"preset 'broken' gave \('linear-spring', 400000000.0\) for bearing 'x'"),
        (lambda b: 1 / 0, r"preset 'broken' failed on bearing 'x': ZeroDivisionError"),
    ],
)
def test_a_broken_preset_is_a_model_error_naming_the_preset_and_the_bearing(law, message):
    with pytest.raises(ModelError, match=message):
        preset_laws(BearingPreset("broken", "a third party's mistake", law), ["x"])


def test_the_bouc_wen_exponent_is_the_presets_not_the_bridges():
    with pytest.raises(ParameterError, match=r"boucwen_exponent = 4 is no longer used: pass preset=bearingfw_boucwen"):
        reference_bridge("bouc-wen", params=BridgeParameters(boucwen_exponent=4.0))


@pytest.mark.parametrize("preset", ["M1", "M2"])
def test_the_per_bearing_presets_give_the_kernel_one_law_object_per_law_and_dims(preset):
    groups = law_groups(reference_bridge(preset))
    assert sorted((g.law.dims, g.n) for g in groups) == [(1, 6), (2, 5)]
    for g in groups:
        assert g.law.k == DEFAULT_KS and isinstance(g.law.k, float)  # equal values stay scalars
        if preset == "M2":
            assert g.law.mu == FRICTION


@pytest.fixture(scope="module")
def bouc_wen_bridge():
    """The bouc-wen bridge with n = 4, and how often the dead load was computed for it."""
    from bearingfw_boucwen.plugin import bouc_wen_preset

    calls = []
    original = presets_module.dead_load_normal_forces

    def counting(*args, **kwargs):
        calls.append(args)
        return original(*args, **kwargs)

    presets_module.dead_load_normal_forces = counting
    try:
        model = reference_bridge(bouc_wen_preset(exponent=4.0), friction=0.05)
    finally:
        presets_module.dead_load_normal_forces = original
    return model, len(calls), original()


def test_a_preset_built_with_another_exponent_reaches_every_bearing(bouc_wen_bridge):
    model, dead_load_runs, normal = bouc_wen_bridge
    assert dead_load_runs == 1  # one gravity analysis for all the bearings
    for name in SLIDING:
        params = model.connector(name).params
        assert params["n"] == 4.0
        assert params["k"] * params["uy"] == pytest.approx(0.05 * normal[name], rel=1e-12)


def test_a_bad_exponent_is_refused_when_the_preset_is_made():
    from bearingfw_boucwen.plugin import bouc_wen_preset

    with pytest.raises(ParameterError, match=r"'n' = 0.5 is outside the allowed range n >= 1"):
        bouc_wen_preset(exponent=0.5)


def test_the_bouc_wen_bearings_share_one_law_object_per_dims_once_the_law_is_per_bearing(bouc_wen_bridge):
    model, _, _ = bouc_wen_bridge
    from bearingfw_boucwen.law import BoucWen

    if not law_flag(BoucWen, "per_bearing"):
        pytest.skip("the bouc-wen law does not declare per_bearing (yet): the kernel builds one object per bearing")
    groups = law_groups(model)
    assert sorted((g.law.dims, g.n) for g in groups) == [(1, 6), (2, 5)]
    for g in groups:
        assert np.shape(g.law.uy) == (g.n,)  # each bearing its own uy, in one object
