"""The experiment engine names no study: the paper's models, response points, friction coefficient
and findings live in the study definition (bearingfw.bridges.paper_study), not in bearingfw.experiment.

A grep over the engine's source, docstrings and comments included; the one thing it may name is the
study module itself (where the built-in experiment comes from).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import bearingfw.experiment

ENGINE = Path(bearingfw.experiment.__file__).parent
#: The study module, which the engine's default experiment comes from.
ALLOWED = "bearingfw.bridges.paper_study"

#: The paper's models, response points and bearings (whole words), its friction coefficient, the
#: former reference-bridge branches, and the paper itself.
WORDS = ["M0", "M1", "M2", "S1", "S2", "2A", "3A", "4A", "5A", "2B", "3B", "4B", "5B", "1A", "1B", "6A", "6B"]
PATTERNS = {
    **{word: re.compile(rf"(?<![A-Za-z0-9_]){word}(?![A-Za-z0-9_])") for word in WORDS},
    "0.04": re.compile(r"(?<![\d.])0\.040*(?!\d)"),
    "is_reference": re.compile(r"is_reference"),
    "paper": re.compile(r"paper", re.IGNORECASE),
    "bouc-wen": re.compile(r"bouc[-_ ]?wen", re.IGNORECASE),
    "Table 2": re.compile(r"table ?2|figures? 1[89]|figures? 2[01]", re.IGNORECASE),
}


def offences(text: str) -> list[str]:
    """``name: line`` for every study name in ``text`` (the study module's own name excepted)."""
    found = []
    for number, line in enumerate(text.replace(ALLOWED, "").splitlines(), start=1):
        for name, pattern in PATTERNS.items():
            if pattern.search(line):
                found.append(f"{number}: {name!r} in {line.strip()!r}")
    return found


@pytest.mark.parametrize("path", sorted(ENGINE.glob("*.py")), ids=lambda p: p.name)
def test_the_engine_names_no_paper_model_element_or_number(path):
    assert offences(path.read_text(encoding="utf-8")) == []


def test_the_grep_finds_what_it_looks_for():
    """The patterns match the names they are meant to (a grep that matches nothing proves nothing)."""
    text = 'x = "M2"\nif model == "3B":\nmu = 0.04\n# the Paper says\nif st.is_reference:\n"bouc-wen"\nTable 2\n'
    names = [o.split("'")[1] for o in offences(text)]
    assert names == ["M2", "3B", "0.04", "paper", "is_reference", "bouc-wen", "Table 2"]
    assert offences("DM2x = 0.045; from bearingfw.bridges.paper_study import STUDY_TOML; G3B; M20") == []
