"""Mode labels say whose mode it is: the deck's (numbered as the deck sensors and Table 2 number them) or the
arches' / pillars' (by the part with most of the mode's kinetic energy)."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw.bridges.paper import MODES
from bearingfw.bridges.study import N_MODES, mode_labels, modes, part_shares


@pytest.fixture(scope="module")
def tuned():
    return modes("M1")  # K_s = 400 MN/m, paired with Table 2


def test_the_arch_sway_and_the_deck_lateral_mode_are_told_apart(tuned):
    modal, pairing = tuned
    labels = mode_labels(modal)
    # the kernel numbers all modes together: the arches' sway at 0.94 Hz is its "lateral 1"
    assert modal.numbered_labels[0] == "lateral 1" and modal.frequencies[0] == pytest.approx(0.943, abs=0.002)
    assert labels[0] == "arches lateral 1"
    lateral = pairing.modes[MODES.index("lateral 1")]
    assert modal.frequencies[lateral] == pytest.approx(2.31, abs=0.01) and labels[lateral] == "deck lateral 1"
    assert modal.numbered_labels[lateral] == "lateral 2"  # the ambiguity the qualified labels remove


def test_every_table2_mode_is_the_deck_mode_of_the_same_name(tuned):
    modal, pairing = tuned
    labels = mode_labels(modal)
    assert [labels[m] for m in pairing.modes] == [f"deck {name}" for name in MODES]
    assert len(set(labels)) == len(labels) == N_MODES


def test_part_shares_split_each_modes_kinetic_energy(tuned):
    modal, _ = tuned
    shares = part_shares(modal)
    total = sum(shares.values())
    np.testing.assert_allclose(total, 1.0, atol=1e-9)  # the abutment seats carry no mass
    assert shares["arches"][0] > 0.99 and shares["deck"][0] < 0.01
