"""ptfe-friction against OpenSees's flatSliderBearing with VelDependent / VelPressureDep (validation/ptfe.py).

Skipped when OpenSeesPy is not installed or cannot be loaded, or without the bearingfw-ptfe plugin.
"""

import numpy as np
import pytest
from opensees_scripts import load_script, require_opensees

require_opensees()
pytest.importorskip("bearingfw_ptfe", reason="the ptfe plugin (plugins/bearingfw-ptfe) is not installed")

ptfe = load_script("ptfe")


@pytest.fixture(scope="module")
def element_rows():
    return ptfe.run_elements(quick=True)


@pytest.fixture(scope="module")
def deck_rows():
    return {r.quantity: r for r in ptfe.run_deck(quick=True)}


def test_the_element_agrees_with_opensees_to_round_off(element_rows):
    """The same radial return with the same mu(v, N): only round-off separates the two codes."""
    assert element_rows
    for r in element_rows:
        assert max(r.force) < 1e-9, r.case.name
        assert max(r.reference) < 1e-12, r.case.name  # and the independent scalar loop


def test_opensees_saw_the_imposed_displacement_velocity_and_normal_force(element_rows):
    for r in element_rows:
        assert max(r.displacement, r.velocity, r.normal) < 1e-9, r.case.name


def test_the_cases_exercise_the_velocity_and_the_pressure(element_rows):
    """Evidence that the comparison covers what the law adds to Coulomb friction."""
    for r in element_rows:
        assert r.slid == pytest.approx(1.0, rel=1e-9), f"{r.case.name}: it never slid"
        assert r.mu_range[1] - r.mu_range[0] > 0.015, f"{r.case.name}: mu hardly changed"
    pressure = [r for r in element_rows if r.case.params.get("area")]
    assert pressure and all(np.ptp(r.case.normal) > 0.5 * ptfe.NORMAL_FORCE for r in pressure)
    assert any(r.case.normal.min() < 0 for r in element_rows)  # a lift-off case


def test_the_comparison_fails_when_the_law_is_not_given_the_velocity():
    """A law that ignores the velocity (mu = f_min) is caught: the check can fail."""
    case = ptfe.element_cases(quick=True)[0]
    law = ptfe.bearingfw.create_law("ptfe-friction", **case.params, dims=case.dims)
    at_rest = ptfe.drive_law(law, case.u, case.normal, np.zeros_like(case.u), case.h)
    force, *_ = ptfe.drive_flat_slider(ptfe.friction_model_args(case.params), case.params["k"], case.u, case.normal,
                                       case.h)  # fmt: skip
    assert max(ptfe.relative_difference(at_rest, force)) > 0.1


def test_the_deck_model_agrees_with_opensees_within_one_percent(deck_rows):
    for r in deck_rows.values():
        assert r.ok, f"{r.quantity}: max {r.max:.2%}, RMS {r.rms:.2%}"
        assert r.peak < 0.01 and r.level < 0.01, r.quantity
    # measured: 2e-9 (law forces), 6e-13 (normal forces), 5e-10 (deck) on this window
    assert deck_rows["bearing law force"].max < 1e-6


def test_the_deck_bearings_slide_at_a_velocity_dependent_coefficient(deck_rows):
    """Peak |F| / N well above f_min = 0.03: the kernel passed the velocity, and the bearings slid fast."""
    assert 0.06 < deck_rows["bearing law force"].friction_ratio <= 0.11
