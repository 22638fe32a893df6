"""Figures of modal results: mode shapes (elevation and plan) and MAC tables.

Built on :class:`matplotlib.figure.Figure` with the Agg canvas, never pyplot: no window and no
global backend switch, so they are safe in scripts and tests. :func:`bearingfw.plotting.save` writes them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from bearingfw.analysis import ModalResult
from bearingfw.model import FrameElement, TrussElement
from bearingfw.plotting import new_figure

__all__ = ["plot_mac", "plot_mode"]

def _members(modal: ModalResult) -> np.ndarray:
    """Node index pairs of every frame and truss member, (n, 2)."""
    model = modal.system.model
    pairs = [
        (model.node_index(e.i), model.node_index(e.j))
        for e in model.elements
        if isinstance(e, (FrameElement, TrussElement))
    ]
    return np.array(pairs, dtype=int).reshape(-1, 2)


def plot_mode(modal: ModalResult, mode: int, title: str | None = None, scale: float | None = None) -> Figure:
    """Mode ``mode`` of ``modal``: undeformed (grey) and deformed members, elevation (x-z) and plan (x-y).

    The shape is scaled so that its largest translation is 5 % of the model's length (or by ``scale``).
    """
    model = modal.system.model
    xyz = model.coordinates
    u = modal.shapes[:, mode].reshape(-1, 6)[:, :3]
    size = float(np.ptp(xyz[:, 0])) or 1.0
    biggest = float(np.abs(u).max()) or 1.0
    k = scale if scale is not None else 0.05 * size / biggest
    moved = xyz + k * u
    pairs = _members(modal)
    figure = new_figure(9.0, 5.0)
    axes = figure.subplots(2, 1, sharex=True)
    for ax, (a, b), name in zip(axes, ((0, 2), (0, 1)), ("elevation: z [m]", "plan: y [m]"), strict=True):
        for points, style in ((xyz, {"color": "0.75", "lw": 0.6}), (moved, {"color": "tab:blue", "lw": 0.9})):
            # one collection of every member's segment (a line per member costs seconds on a real bridge)
            ax.add_collection(LineCollection(points[pairs][:, :, [a, b]], **style))
        ax.autoscale_view()
        ax.set_ylabel(name)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("x [m]")
    label = modal.numbered_labels[mode]
    figure.suptitle(title or f"mode {mode + 1}: {modal.frequencies[mode]:.3f} Hz ({label})", fontsize=10)
    return figure


def plot_mac(table, rows: Sequence[str], columns: Sequence[str] | None = None, title: str = "MAC") -> Figure:
    """A MAC (or AutoMAC) table as an annotated heatmap, 0 (white) to 1 (dark)."""
    table = np.asarray(table, dtype=float)
    columns = rows if columns is None else columns
    figure = new_figure(1.2 + 0.9 * table.shape[1], 1.0 + 0.8 * table.shape[0])
    ax = figure.subplots()
    image = ax.imshow(table, vmin=0.0, vmax=1.0, cmap="Blues")
    for (r, c), value in np.ndenumerate(table):
        ax.text(c, r, f"{value:.2f}", ha="center", va="center", fontsize=8, color="white" if value > 0.6 else "black")
    ax.set_xticks(range(table.shape[1]), labels=list(columns), rotation=30, ha="right", fontsize=8)
    ax.set_yticks(range(table.shape[0]), labels=list(rows), fontsize=8)
    figure.colorbar(image, ax=ax, shrink=0.8)
    ax.set_title(title, fontsize=10)
    return figure


