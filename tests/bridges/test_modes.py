"""The untuned model against Table 2, the other bearing models, and the mode shapes' independence."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw.analysis import automac, solve_modal
from bearingfw.bridges import BEARINGS, DEFAULT_KS, PRESETS, reference_bridge
from bearingfw.bridges.paper import FIXED_F1, FRICTION, KS_FIT, MODES, TABLE2_FE, TABLE2_OMA
from bearingfw.bridges.presets import dead_load_normal_forces
from bearingfw.bridges.study import modes
from bearingfw.model import ConnectorKind
from bearingfw.tuning import evaluate, paired_shapes


def test_untuned_model_reproduces_table_2_in_the_papers_mode_order(untuned):
    modal, pairing = untuned
    assert pairing.labels == MODES
    np.testing.assert_array_less(np.abs(pairing.errors), 0.05)
    # 1st vertical, 1st lateral, 2nd vertical, 1st torsional: four distinct modes of the model, in the
    # paper's order (the labels are paired by shape, so this order is a result, not a sort)
    assert len(set(pairing.modes)) == 4 and np.all(np.diff(pairing.modes) > 0)
    assert np.all(np.diff(pairing.frequencies) > 0)
    # the kernel's own labels of those modes agree with the deck's
    assert [modal.labels[m] for m in pairing.modes] == [name.split()[0] for name in MODES]


def test_untuned_lateral_error_against_the_measurement_is_the_papers(untuned):
    _, pairing = untuned
    error = pairing.frequencies[MODES.index("lateral 1")] / TABLE2_OMA["lateral 1"] - 1
    assert error == pytest.approx(TABLE2_FE["lateral 1"] / TABLE2_OMA["lateral 1"] - 1, abs=0.01)  # -24.6 %


def test_automac_of_the_four_modes(untuned, observation):
    modal, pairing = untuned
    for shapes in (paired_shapes(modal, pairing, observation), paired_shapes(modal, pairing)):
        table = automac(shapes)
        np.testing.assert_allclose(np.diag(table), 1.0)
        assert np.max(table - np.diag(np.diag(table))) <= 0.2


@pytest.mark.xfail(
    strict=True,
    reason="no bearing restraint reaches the arch span's antisymmetric first mode in this layout: fixing every "
    "bearing moves it by about -1 %, not the paper's +21 % (the variants tried: bearingfw.bridges docstring)",
)
def test_fixing_every_bearing_lifts_the_first_vertical_frequency(untuned, observation):
    _, fixed = evaluate(reference_bridge("fixed"), [("vertical 1", FIXED_F1)], observation=observation, n_modes=12)
    assert fixed.frequencies[0] >= 1.15 * untuned[1].frequencies[0]


def test_fixing_every_bearing_brings_the_lateral_mode_to_the_measured_one(untuned, observation):
    """Section 3.3: all bearings fixed corrects the lateral frequency (within 2 % in the paper)."""
    _, fixed = evaluate(reference_bridge("fixed"), [("lateral 1", TABLE2_OMA["lateral 1"])], observation=observation,
                        n_modes=12)
    assert abs(fixed.errors[0]) < 0.05
    assert fixed.frequencies[0] > 1.3 * untuned[1].frequencies[1]


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_every_preset_builds_and_runs_a_modal_analysis(preset):
    modal = solve_modal(reference_bridge(preset), 6)
    assert np.all(modal.frequencies > 0.5) and np.all(np.diff(modal.frequencies) >= 0)


def test_presets_use_the_papers_laws():
    laws = {p: reference_bridge(p) for p in ("M0", "M1", "M2", "bouc-wen")}
    for name, spec in BEARINGS.items():
        if spec.kind is ConnectorKind.JOIN:
            continue
        assert laws["M0"].connector(name).law == "frictionless"
        assert laws["M1"].connector(name).params == {"k": DEFAULT_KS}
        assert laws["M2"].connector(name).params == {"k": DEFAULT_KS, "mu": FRICTION}
        assert laws["bouc-wen"].connector(name).law == "bouc-wen"
    assert DEFAULT_KS == KS_FIT


def test_bouc_wen_preset_saturates_at_the_dead_load_friction_force():
    normal = dead_load_normal_forces()
    model = reference_bridge("bouc-wen")
    for name, spec in BEARINGS.items():
        if spec.kind is ConnectorKind.JOIN:
            continue
        p = model.connector(name).params
        assert (p["alpha"], p["A"], p["beta"], p["gamma"]) == (0.0, 1.0, 0.5, 0.5) and p["n"] >= 2
        assert p["k"] * p["uy"] == pytest.approx(FRICTION * normal[name], rel=1e-9)  # saturation force mu N


def test_stick_laws_linearise_like_springs(observation):
    """M2 and bouc-wen start on their stick branch: their modes are M1's (the paper's step 1 = step 2's stick)."""
    results = {p: modes(p)[1] for p in ("M1", "M2", "bouc-wen")}
    np.testing.assert_allclose(results["M2"].frequencies, results["M1"].frequencies, rtol=1e-9)
    np.testing.assert_allclose(results["bouc-wen"].frequencies, results["M1"].frequencies, rtol=1e-6)


def test_with_the_papers_ks_every_frequency_is_within_8_percent_of_the_measured(observation):
    """Table 3's outcome with the paper's K_s = 400 MN/m: lateral -7.2 %, first vertical +6.6 % there."""
    _, pairing = modes("M1", ks=KS_FIT)
    assert np.max(np.abs(pairing.errors)) < 0.08
