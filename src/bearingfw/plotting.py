"""Figures without a window: matplotlib's object API on the Agg canvas, never pyplot.

One place for how every layer makes and writes a figure, so that all of bearingfw's figures are
PNG and SVG files with the same resolution. pyplot is avoided because it keeps global state and
may try to open a window.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

__all__ = ["FORMATS", "new_figure", "save"]

#: The formats every figure is written in.
FORMATS = ("png", "svg")


def new_figure(width: float, height: float) -> Figure:
    """A figure of ``width`` x ``height`` inches with constrained layout, on the Agg canvas."""
    figure = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def save(figure: Figure, directory, stem: str, formats: Sequence[str] = FORMATS, dpi: int = 150) -> list[Path]:
    """Write ``figure`` as ``stem.<format>`` in ``directory`` (created if needed); return the paths."""
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for suffix in formats:
        path = folder / f"{stem}.{suffix}"
        figure.savefig(path, dpi=dpi)
        paths.append(path)
    return paths
