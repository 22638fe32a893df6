"""Whole models against OpenSeesPy (a small version of validation/models.py, a few seconds).

Skipped when OpenSeesPy is not installed (the optional extra ``validation``) or cannot be loaded.
"""

import numpy as np
import pytest
from opensees_scripts import load_script, require_opensees

require_opensees()

import _multispan  # noqa: E402 - validation/, on the path once OpenSees is known to load
import _translate  # noqa: E402

models = load_script("models")


@pytest.fixture(scope="module")
def record():
    """2 s of the Chuetsu-oki record around its strongest part (tapered, from rest)."""
    return models.record_window(20.0, 22.0)


def test_sdof_on_a_friction_bearing_matches_opensees_to_round_off_at_alpha_0(record):
    ag, dt = record
    displacement, force = models.case_sdof(ag, dt, 0.0, 2)
    assert "|F|max/(mu N) = 1.000" in force.note  # the bearing slides: the comparison covers stick and slip
    assert max(displacement.max, displacement.rms, force.max, force.rms) < 1e-8


def test_sdof_with_hht_dissipation_is_within_one_percent(record):
    ag, dt = record
    rows = models.case_sdof(ag, dt, -0.05, 2)
    assert all(r.within for r in rows), [(r.quantity, r.max, r.rms) for r in rows]


def test_frame_on_fixed_guided_and_free_friction_bearings_matches_opensees(record):
    ag, dt = record
    ag = ag[:101]  # 1 s
    frame = _multispan.Frame(per_span=3)
    model = _multispan.frame_model(frame)
    bearings = _multispan.sliding_bearings(model)
    assert {model.connector(b).kind.value for b in bearings} == {"axial", "planar"}
    rows = models.case_model("frame", model, _multispan.response_nodes(frame), bearings, ag, dt, 0.0, 2,
                             friction=(4e8, 0.04))  # fmt: skip
    for row in rows:
        assert max(row.max, row.rms) < 1e-5, (row.quantity, row.worst, row.max, row.rms)


def test_modal_frequencies_of_a_frame_with_rigid_offsets_match_opensees_eigen():
    model = _multispan.frame_model(_multispan.Frame(per_span=3, offset=0.8, law="linear-spring", params=(("k", 4e8),)))
    row = models.case_modal("frame", model, count=8)
    assert row.max < 1e-6, row


def test_hht_alpha_maps_to_the_opensees_convention():
    assert _translate.opensees_alpha(-0.05) == pytest.approx(0.95)
    assert _translate.opensees_alpha(0.0) == 1.0


def test_differences_are_relative_to_the_opensees_history():
    b = np.array([[1.0, 0.0], [0.0, -2.0], [0.0, 0.0]])
    a = b + np.array([[0.0, 0.1], [0.0, 0.0], [0.0, 0.0]])
    peak, rms = models.differences(a, b)
    assert peak == pytest.approx(0.1 / 2.0)
    assert rms == pytest.approx(np.sqrt(0.01 / 3) / np.sqrt(5.0 / 3))
