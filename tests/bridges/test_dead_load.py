"""Dead load: reactions against the bearing capacities, and equilibrium with the weight."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw.analysis import gravity
from bearingfw.bridges import BEARINGS, reference_bridge


@pytest.fixture(scope="module")
def dead_load():
    return gravity(reference_bridge("M0"))


def test_dead_load_reactions_stay_below_the_bearing_capacities(dead_load):
    for name, spec in BEARINGS.items():
        n = dead_load.normal_force(name)
        assert 0.0 < n < spec.capacity, f"bearing {name}: N = {n / 1e3:.0f} kN, capacity {spec.capacity / 1e3:.0f} kN"


def test_supports_carry_the_whole_weight(dead_load):
    weight = -dead_load.load[2::6].sum()  # every weight acts downward
    assert weight > 3e7  # a concrete bridge of some 4500 t
    resultant = dead_load.reaction_resultant()
    assert resultant[2] == pytest.approx(weight, rel=1e-8)
    np.testing.assert_allclose(resultant[:2], 0.0, atol=1e-6 * weight)


def test_the_arch_span_bypasses_bearings_3_and_4(dead_load):
    """The arches carry the deck of the arch span to their own foundations (as the capacities suggest)."""
    n = {b: dead_load.normal_force(b) for b in BEARINGS}
    assert n["3A"] + n["3B"] + n["4A"] + n["4B"] < n["2A"] + n["2B"] + n["5A"] + n["5B"]
