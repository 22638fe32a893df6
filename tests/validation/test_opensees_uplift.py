"""Uplift against OpenSees: a girder on compression-only bearings (ENT) under a scaled real record
(validation/uplift.py, its quick window; a few seconds).

Skipped when OpenSeesPy is not installed (the optional extra ``validation``) or cannot be loaded.
"""

import numpy as np
import pytest
from opensees_scripts import load_script, require_opensees

require_opensees()

uplift = load_script("uplift")

QUICK = (7.5, 10.5)


@pytest.fixture(scope="module")
def same_equations():
    return uplift.compare(QUICK, alpha=0.0)


def test_lift_offs_and_landings_match_opensees_to_round_off_at_alpha_0(same_equations):
    c = same_equations
    assert c.horizon == c.samples  # no chaotic departure within this window
    assert all(n >= 3 for n in c.lift_offs_compared)  # both bearings lift off, several times
    assert all(v["lift_offs"] >= 5 for v in c.uplift.values())
    for row in c.rows:
        assert max(row.max, row.rms) < 1e-6, (row.quantity, row.max, row.rms)
    # the same samples lifted (N = 0) in both codes, and never tension
    np.testing.assert_array_equal(c.ours.normal_force <= 0.0, c.theirs.normal_force <= 0.0)
    assert np.all(c.ours.normal_force >= 0.0)


def test_with_hht_dissipation_uplift_is_within_one_percent_of_opensees():
    c = uplift.compare(QUICK, alpha=-0.05)
    assert all(n >= 3 for n in c.lift_offs_compared)
    assert all(r.within for r in c.rows), [(r.quantity, r.max, r.rms) for r in c.rows]
