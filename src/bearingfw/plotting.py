"""Figures without a window: matplotlib's object API on the Agg canvas, never pyplot.

One place for how every layer makes and writes a figure. pyplot is avoided because it keeps
global state and may try to open a window.

Two layouts: ``new_figure(w, h)`` uses matplotlib's constrained layout (the commands' few
figures, whose labels vary); ``new_figure(w, h, margins=Margins(...))`` places the axes at fixed
margins given in inches (the experiment's many figures: the layout engine costs more than
drawing them, and their text is known in advance). :func:`save` writes each file atomically
(a temporary file in the same folder, then ``os.replace``): an interrupted or killed run never
leaves a half-written figure under the final name, and the temporary's name is the one the
results store (:mod:`bearingfw.experiment.store`) removes after a killed run.
"""

from __future__ import annotations

import os
import platform
import re
import textwrap
import uuid
from collections.abc import Sequence
from pathlib import Path

import attrs
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

__all__ = ["FIGURE_FORMATS", "FORMATS", "Margins", "fit_suptitle", "new_figure", "save", "synthetic_title"]

#: The formats the commands' figures (modal, oma, record) are written in.
FORMATS = ("png", "svg")
#: The formats a figure can be written in (``[figures] formats`` of an experiment).
FIGURE_FORMATS = ("png", "svg", "pdf")

#: savefig's options per format: PNG at zlib's level 1 (the pixels are the same; the file is about
#: 13 % larger and written in half the time of the default level 6)
_OPTIONS = {"png": {"pil_kwargs": {"compress_level": 1}}}
# The temporary's name, as the results store writes and cleans them: .partial-<name>.<host>-<pid>.<12 hex>
_TEMPORARY = ".partial-"
_HOST = re.sub(r"[^A-Za-z0-9]+", "_", platform.node() or "localhost")


@attrs.frozen
class Margins:
    """Fixed space around and between the axes, inches: ``left``, ``right``, ``top`` (title lines
    included), ``bottom``; ``wspace``, ``hspace`` between columns and rows of subplots."""

    left: float = 0.8
    right: float = 0.2
    top: float = 0.6
    bottom: float = 0.5
    wspace: float = 0.7
    hspace: float = 0.5

    def apply(self, figure: Figure) -> None:
        """Place ``figure``'s subplots (call after :meth:`~matplotlib.figure.Figure.subplots`)."""
        width, height = figure.get_size_inches()
        grids = {ax.get_subplotspec().get_gridspec() for ax in figure.axes if ax.get_subplotspec() is not None}
        columns = max((g.ncols for g in grids), default=1)
        rows = max((g.nrows for g in grids), default=1)
        inner_w = max(1e-3, width - self.left - self.right)
        inner_h = max(1e-3, height - self.top - self.bottom)
        # subplots_adjust's wspace/hspace are fractions of the mean axes width/height
        axes_w = max(1e-3, (inner_w - (columns - 1) * self.wspace) / columns)
        axes_h = max(1e-3, (inner_h - (rows - 1) * self.hspace) / rows)
        figure.subplots_adjust(left=self.left / width, right=1 - self.right / width, bottom=self.bottom / height,
                               top=1 - self.top / height, wspace=self.wspace / axes_w, hspace=self.hspace / axes_h)


def new_figure(width: float, height: float, margins: Margins | None = None) -> Figure:
    """A figure of ``width`` x ``height`` inches on the Agg canvas: with constrained layout, or, given
    ``margins``, with no layout engine (apply them with ``margins.apply(figure)`` once the axes exist)."""
    figure = Figure(figsize=(width, height), layout=None if margins is not None else "constrained")
    FigureCanvasAgg(figure)
    return figure


def fit_suptitle(figure: Figure) -> None:
    """Wrap each line of the figure's suptitle to the figure's width, so that no title is cut at the edges."""
    title = getattr(figure, "_suptitle", None)
    if title is None or not title.get_text():
        return
    width_pt = figure.get_size_inches()[0] * 72.0 - 12.0
    # An average character of DejaVu Sans is about 0.55 em wide.
    per_line = max(20, int(width_pt / (0.55 * title.get_fontsize())))
    lines = [wrapped for line in title.get_text().split("\n")
             for wrapped in (textwrap.wrap(line, per_line) or [""])]
    title.set_text("\n".join(lines))


def save(figure: Figure, directory, stem: str, formats: Sequence[str] = FORMATS, dpi: int = 150) -> list[Path]:
    """Write ``figure`` as ``stem.<format>`` in ``directory`` (created if needed); return the paths.

    Each file is written to a temporary in the same folder and renamed over its name: an
    interruption (Ctrl-C, an error, a full disk) leaves the previous file or none, never a part,
    and no temporary behind."""
    unknown = [f for f in formats if f not in FIGURE_FORMATS]
    if unknown:
        raise ValueError(f"figure format {unknown[0]!r}: the formats are {', '.join(FIGURE_FORMATS)}")
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    fit_suptitle(figure)
    paths = []
    for suffix in formats:
        path = folder / f"{stem}.{suffix}"
        if path.exists() and not path.is_file():  # a device or a pipe (e.g. a link to one): written in place
            with open(path, "wb") as handle:
                figure.savefig(handle, format=suffix, dpi=dpi, **_OPTIONS.get(suffix, {}))
            paths.append(path)
            continue
        temporary = folder / f"{_TEMPORARY}{path.name}.{_HOST}-{os.getpid()}.{uuid.uuid4().hex[:12]}"
        try:
            with open(temporary, "wb") as handle:
                figure.savefig(handle, format=suffix, dpi=dpi, **_OPTIONS.get(suffix, {}))
            os.replace(temporary, path)
        except BaseException as exc:  # interrupted or failed: no partial file, no temporary
            temporary.unlink(missing_ok=True)
            if isinstance(exc, OSError) and exc.filename is not None and _TEMPORARY in Path(exc.filename).name:
                raise type(exc)(exc.errno, exc.strerror or str(exc), str(path)) from None  # the file meant, not ours
            raise
        paths.append(path)
    return paths


def synthetic_title(text: str, synthetic: bool, what: str = "data", instead: str = "a measurement") -> str:
    """``text``, and for synthetic input a second line: ``SYNTHETIC <what>: generated by bearingfw, not <instead>``.

    A second title line rather than a free-floating note: the layout keeps it clear.
    """
    return f"{text}\nSYNTHETIC {what}: generated by bearingfw, not {instead}" if synthetic else text
