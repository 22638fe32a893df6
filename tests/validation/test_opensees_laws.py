"""Cross-check of the bearing laws against OpenSeesPy (a small version of validation/laws.py).

Skipped when OpenSeesPy is not installed (it is the optional extra ``validation``) or cannot be
loaded, so the default test run does not need it.
"""

import numpy as np
import pytest
from opensees_scripts import load_script, require_opensees

require_opensees()
pytest.importorskip("bearingfw_boucwen", reason="the bouc-wen plugin (plugins/bearingfw-boucwen) is not installed")

laws = load_script("laws")


@pytest.fixture(scope="module")
def rows():
    return laws.run(quick=True)


def test_every_comparison_is_within_one_percent_or_explained(rows):
    failed = [f"{r.label}: force {r.force}, displacement {r.displacement}" for r in rows if not r.ok]
    assert not failed, "gaps above 1 % without a valid explanation:\n" + "\n".join(failed)


def test_the_prescribed_displacements_reach_the_opensees_element(rows):
    for r in rows:
        assert max(r.displacement) < 1e-12, r.label


def test_friction_laws_match_opensees_to_round_off(rows):
    """ElasticPP and flatSliderBearing use the same closed-form return map as regularized-coulomb."""
    friction = [r for r in rows if isinstance(r.case, (laws.EppCase, laws.FrictionCase))]
    assert friction
    for r in friction:
        assert max(r.force) < 1e-12, r.label


def test_bouc_wen_mappings_are_exact_when_both_codes_take_one_step(rows):
    """Increments shorter than bearingfw's substep: both solve the same backward-Euler equation."""
    single = [r for r in rows if "1 BE step" in r.case.name]
    assert {r.case.dims for r in single} == {1, 2}
    for r in single:
        assert max(r.force) < 1e-9, r.label


def test_flat_slider_follows_a_varying_normal_force():
    rng = np.random.default_rng(7)
    u = laws.random_path(rng, 5e-3, 60, dims=2)
    normal = laws.NORMAL_FORCE * (1.0 + 0.5 * np.sin(np.linspace(0.0, 6.0, 60)))
    case = laws.FrictionCase("N(t)", u, normal_force=normal)
    row = laws.Row(case, "native")
    assert max(row.force) < 1e-12
    np.testing.assert_allclose(case.bearingfw_force, case.reference_force, rtol=0, atol=1e-9 * np.abs(normal).max())
