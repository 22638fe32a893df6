"""[structure] mode_labels: a study names its modes (whose mode it is) in the report's modal table;
the engine falls back to the kernel's labels, saying why, when that function fails."""

import attrs
import pytest

from bearingfw.analysis import solve_modal
from bearingfw.bridges import reference_bridge
from bearingfw.bridges.study import mode_labels
from bearingfw.experiment.default import default_experiment
from bearingfw.experiment.runner import _labels
from bearingfw.experiment.spec import SpecError, StructureSpec
from bearingfw.experiment.structure import mode_labeller


@pytest.fixture(scope="module")
def modal():
    return solve_modal(reference_bridge("M0"), 8)


def test_the_default_study_labels_modes_by_whose_they_are(modal):
    labeller = mode_labeller(default_experiment())
    assert labeller is mode_labels
    labels, problem = _labels(modal, labeller)
    assert problem is None
    # the arches' sway at 0.94 Hz is not the deck's lateral mode (the kernel calls both "lateral n")
    assert labels[0] == "arches lateral 1" and modal.numbered_labels[0] == "lateral 1"
    assert "deck lateral 1" in labels and abs(modal.frequencies[labels.index("deck lateral 1")] - 1.87) < 0.05


def test_without_the_key_the_kernels_labels_are_used(modal):
    experiment = attrs.evolve(default_experiment(), structure=StructureSpec())
    assert mode_labeller(experiment) is None
    assert _labels(modal, None) == (tuple(modal.numbered_labels), None)


def test_a_failing_or_wrong_length_labeller_falls_back_with_the_reason(modal):
    def broken(_):
        raise RuntimeError("no parts")

    labels, problem = _labels(modal, broken)
    assert labels == tuple(modal.numbered_labels) and "RuntimeError: no parts" in problem
    labels, problem = _labels(modal, lambda m: ["x"])
    assert labels == tuple(modal.numbered_labels) and f"1 labels for {modal.n_modes} modes" in problem


def test_an_unknown_function_is_a_spec_error_naming_the_key():
    experiment = attrs.evolve(default_experiment(),
                              structure=StructureSpec(mode_labels="bearingfw.bridges.study:no_such_function"))
    with pytest.raises(SpecError, match=r"structure\.mode_labels: .*no function 'no_such_function'"):
        mode_labeller(experiment)
