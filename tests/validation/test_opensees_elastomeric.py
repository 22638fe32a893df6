"""The lead-rubber law against OpenSees's elastomericBearingPlasticity (a small version of
validation/elastomeric.py, about 20 s).

Skipped when OpenSeesPy is not installed (the optional extra ``validation``) or cannot be loaded,
or when the plugin bearingfw-elastomeric is not installed.
"""

import numpy as np
import pytest
from opensees_scripts import load_script, require_opensees

require_opensees()
pytest.importorskip("bearingfw_elastomeric", reason="the plugin plugins/bearingfw-elastomeric is not installed")

elastomeric = load_script("elastomeric")


@pytest.fixture(scope="module")
def law_rows():
    return [elastomeric.law_row(case) for case in elastomeric.law_cases(quick=True)]


def test_the_law_matches_the_opensees_element_to_round_off_on_random_paths(law_rows):
    """Same radial return, same parameters (kInit = k, qd, alpha1 = alpha, alpha2 = 0): round-off."""
    assert {r.case.u.shape[1] for r in law_rows} == {1, 2}
    for r in law_rows:
        assert r.peak_ratio > 2.9, r.case.name  # every path yields
        assert max(r.force) < 1e-10, (r.case.name, r.force)
        assert r.bfw_ref < 1e-12 and r.os_ref < 1e-10, r.case.name  # the kinematic-hardening form agrees


def test_opensees_saw_the_imposed_displacement_velocity_and_normal_force(law_rows):
    for r in law_rows:
        assert r.seen < 1e-9, r.case.name
        # the transient gives the element a velocity (Newmark's), which the law was given too
        assert np.abs(r.case.opensees["velocity"]).max() > 0.01
        np.testing.assert_allclose(r.case.opensees["velocity"], r.case.velocity, rtol=0,
                                   atol=1e-9 * np.abs(r.case.velocity).max())  # fmt: skip


def test_velocity_and_normal_force_play_no_part_in_either_code(law_rows):
    """OpenSees static (no velocity) = transient; the law's force does not vanish in tension."""
    for r in law_rows:
        assert r.static < 1e-10, r.case.name
    tension = [r for r in law_rows if r.case.normal.min() < 0]
    assert tension, "a case with N < 0 is expected"
    for r in tension:
        lifted = r.case.normal < 0
        assert np.linalg.norm(r.case.opensees["force"][lifted], axis=1).min() > 0
        assert np.linalg.norm(r.case.bearingfw[lifted], axis=1).min() > 0


def test_the_left_out_alpha2_hardening_of_opensees_is_not_isotropic():
    """The evidence for leaving alpha2/mu out: OpenSees applies it per axis, so |F| along 45
    degrees differs from |F| along an axis; without it OpenSees is isotropic like the law."""
    evidence = elastomeric.hardening_anisotropy(steps=60)
    without, with_hardening = evidence.values()
    assert without < 1e-12
    assert with_hardening > 0.02


def test_a_small_isolated_bridge_under_a_real_record_matches_opensees():
    ag, dt = elastomeric.models.record_window(20.0, 22.0)
    rows = elastomeric.bridge_rows("isolated", ag, dt, 0.0, 2)
    force = next(r for r in rows if r.quantity == "bearing force")
    assert float(force.note.split("= ")[-1]) > 1.0  # every bearing yields
    for row in rows:
        assert max(row.max, row.rms) < 1e-6, (row.quantity, row.worst, row.max, row.rms)


def test_the_parameter_mapping_and_the_bearings_are_as_documented():
    p = elastomeric.BEARINGS["D650"]
    assert elastomeric.opensees_args(p) == (p["k"], p["qd"], p["alpha"], 0.0, 2.0)
    # 650 mm bearing, 125 mm lead core (10 MPa), 150 mm rubber, G = 0.8 MPa, K_u = 10 K_d
    lead = np.pi / 4 * 0.125**2
    assert p["qd"] == pytest.approx(10e6 * lead)
    assert p["k"] == pytest.approx(10 * 0.8e6 * (np.pi / 4 * 0.65**2 - lead) / 0.15)
    assert elastomeric.yield_displacement(p) == pytest.approx(8.0e-3, rel=0.01)
