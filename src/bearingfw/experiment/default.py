"""The built-in experiment, run by ``bearingfw run`` without a file: a study definition held as data
outside the engine (:mod:`bearingfw.bridges.paper_study`).

``bearingfw run --print-default`` prints it as a starting point for one's own experiment;
:func:`default_experiment` loads it.
"""

from __future__ import annotations

from pathlib import Path

from bearingfw.bridges.paper_study import STUDY_TOML

__all__ = ["DEFAULT_TOML", "default_experiment"]

#: The built-in experiment's TOML text.
DEFAULT_TOML = STUDY_TOML


def default_experiment(base_dir: str | Path | None = None):
    """The built-in experiment (:data:`DEFAULT_TOML`) as an :class:`~bearingfw.experiment.spec.Experiment`."""
    from bearingfw.experiment.spec import parse_experiment

    return parse_experiment(DEFAULT_TOML, base_dir, origin="<built-in experiment>")
