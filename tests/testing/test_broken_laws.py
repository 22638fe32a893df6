"""The conformance kit catches every mutant of broken_laws.py (each a copy of a correct law with one
classic mistake) with the property aimed at it, and passes the correct laws.

The default run uses 10 examples per property (derandomized: the same examples every run, so
the verdicts never change); ``-m slow`` repeats both with the kit's default of 30.
"""

import pytest
from broken_laws import MUTANTS, REFERENCES

from bearingfw.testing import ConformanceError, check_law


def law_id(law):
    return f"{type(law).__name__}-dims{law.dims}"


MUTANT_IDS = [law_id(mutant) for mutant, _ in MUTANTS]


def test_there_are_enough_mutants_of_each_kind():
    kinds = [type(mutant).__mro__[1].__name__ for mutant, _ in MUTANTS]
    assert kinds.count("Coulomb") + kinds.count("BoxFriction") >= 20
    assert {"Spring", "VelocityFriction", "Damper"} <= set(kinds)
    assert len({type(mutant) for mutant, _ in MUTANTS}) == len(MUTANTS)


@pytest.mark.parametrize("law", REFERENCES, ids=law_id)
def test_the_correct_laws_pass(law):
    check_law(law, max_examples=10)


@pytest.mark.parametrize("mutant, expected", MUTANTS, ids=MUTANT_IDS)
def test_every_mutant_is_caught(mutant, expected):
    with pytest.raises(ConformanceError) as caught:
        check_law(mutant, max_examples=10, shrink=False)
    assert caught.value.prop in expected, str(caught.value)


@pytest.mark.slow
@pytest.mark.parametrize("law", REFERENCES, ids=law_id)
def test_the_correct_laws_pass_with_the_default_examples(law):
    check_law(law)


@pytest.mark.slow
@pytest.mark.parametrize("mutant, expected", MUTANTS, ids=MUTANT_IDS)
def test_every_mutant_is_caught_with_the_default_examples(mutant, expected):
    with pytest.raises(ConformanceError) as caught:
        check_law(mutant, shrink=False)
    assert caught.value.prop in expected, str(caught.value)
