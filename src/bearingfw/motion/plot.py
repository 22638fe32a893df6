"""Figures of a record, after the paper's figures 1-3: acceleration histories, Fourier spectra,
and the record's point on the intensity chart; and its elastic response spectra.

Built on :class:`matplotlib.figure.Figure` with the Agg canvas, never pyplot: no window, no
global backend switch, safe in scripts and tests. Synthetic records say so in every title.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from bearingfw.motion.intensity import DEFAULT_SCALE
from bearingfw.motion.metrics import (
    DEFAULT_DAMPING,
    dominant_frequency,
    fourier_spectrum,
    record_pga_h10,
    record_t_ha,
    response_spectrum,
)
from bearingfw.motion.record import Record
from bearingfw.motion.scaling import horizontal_spectrum
from bearingfw.plotting import FORMATS, new_figure, save, synthetic_title
from bearingfw.plugins.contracts import IntensityScale

__all__ = ["plot_accelerations", "plot_fourier", "plot_intensity_chart", "plot_response_spectrum", "write_figures"]

def _figure(height: float) -> Figure:
    return new_figure(8.0, height)


def _title(text: str, record: Record | None) -> str:
    return synthetic_title(text, record is not None and record.synthetic, "motion", "a recording")


def plot_accelerations(record: Record) -> Figure:
    """The three acceleration histories (m/s^2) with their peaks (the paper's figure 1)."""
    figure = _figure(7.0)
    axes = figure.subplots(3, 1, sharex=True)
    t = record.time
    for ax, name, values in zip(axes, record.names, record.components):
        k = int(np.argmax(np.abs(values)))
        ax.plot(t, values, lw=0.6, color="tab:blue")
        ax.plot(t[k], values[k], "o", ms=4, color="tab:red")
        ax.annotate(f"{values[k]:+.3g} m/s²", (t[k], values[k]), textcoords="offset points", xytext=(6, 4), fontsize=8)
        ax.set_ylabel(f"{name} [m/s²]")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    figure.suptitle(_title(f"Acceleration histories: {record.title}", record), fontsize=10)
    return figure


def plot_fourier(record: Record, fmax: float | None = None) -> Figure:
    """Fourier amplitude spectra (m/s) with the dominant frequency marked (the paper's figure 2)."""
    figure = _figure(7.0)
    axes = figure.subplots(3, 1, sharex=True)
    fmax = fmax or min(50.0, 0.5 / record.dt)
    for ax, name, values in zip(axes, record.names, record.components):
        f, amplitude = fourier_spectrum(values, record.dt)
        keep = f <= fmax
        ax.plot(f[keep], amplitude[keep], lw=0.7, color="tab:blue")
        if np.any(values):
            dominant = dominant_frequency(values, record.dt)
            ax.axvline(dominant, color="tab:red", lw=0.8, ls="--")
            ax.text(dominant, ax.get_ylim()[1] * 0.9, f" {dominant:.2f} Hz", color="tab:red", fontsize=8, va="top")
        ax.set_ylabel(f"{name} [m/s]")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("frequency [Hz]")
    axes[-1].set_xlim(0.0, fmax)
    figure.suptitle(_title(f"Fourier amplitude spectra: {record.title}", record), fontsize=10)
    return figure


def plot_response_spectrum(record: Record, damping: float = DEFAULT_DAMPING, periods=None, marks=()) -> Figure:
    """Pseudo-spectral acceleration (m/s^2) of the three components and of the horizontals (their
    geometric mean, what an Sa(T) target scales) against the period (s); ``marks``: periods (s)
    to mark with their horizontal Sa."""
    figure = _figure(4.5)
    ax = figure.subplots()
    periods = np.geomspace(max(0.02, 2.0 * record.dt), 5.0, 120) if periods is None else np.asarray(periods, dtype=float)
    for name, values, colour in zip(record.names, record.components, ("tab:blue", "tab:orange", "tab:green")):
        ax.plot(periods, response_spectrum(values, record.dt, periods, damping).psa, lw=1.0, color=colour, label=name)
    if np.any(record.h1) or np.any(record.h2):
        ax.plot(periods, horizontal_spectrum(record, periods, damping), lw=1.6, ls="--", color="k",
                label="horizontal (geometric mean)")
        marks = np.asarray(marks, dtype=float)
        if marks.size:
            sa = horizontal_spectrum(record, marks, damping)
            ax.plot(marks, sa, "o", color="tab:red", ms=5)
            for T, value in zip(marks, sa):
                ax.annotate(f"Sa({T:g} s) = {value:.3g} m/s²", (T, value), textcoords="offset points", xytext=(6, 6),
                            fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("period T [s]")
    ax.set_ylabel("pseudo-spectral acceleration [m/s²]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    figure.suptitle(_title(f"Response spectra ({damping:.0%} damping): {record.title}", record), fontsize=10)
    return figure


def plot_intensity_chart(
    points: Sequence[tuple[str, float, float]],
    scale: IntensityScale = DEFAULT_SCALE,
    t_max: float | None = None,
    record: Record | None = None,
) -> Figure:
    """The degrees of ``scale`` in the (t_Ha, PGA_H10) plane with labelled points (figure 3).

    ``points``: ``(label, t_Ha in s, PGA_H10 in m/s^2)``. ``record``, if given, only adds the
    synthetic note when the record is synthetic.
    """
    figure = _figure(5.0)
    ax = figure.subplots()
    t_top = t_max or max(6.0, 1.15 * max((p[1] for p in points), default=0.0), 1.5 * scale.durations[-1])
    t = np.linspace(0.0, t_top, 400)
    bounds = np.array([scale.upper_bounds(x) for x in t]).T  # (degrees, t)
    y_top = max(1.25 * bounds[-1].max(), 1.15 * max((p[2] for p in points), default=0.0))
    colours = ["#d8f0d2", "#f4f1c4", "#fbe0b6", "#f7c3a8", "#ef9f9f"]
    lower = np.zeros_like(t)
    for i, (label, upper) in enumerate(zip(scale.degrees, bounds)):
        ax.fill_between(t, lower, upper, color=colours[i % len(colours)], lw=0)
        ax.plot(t, upper, color="0.4", lw=0.8)
        for at in (len(t) // 10, len(t) * 9 // 10):  # label both ends: the bands bend in between
            ax.text(t[at], 0.5 * (lower[at] + upper[at]), label, fontsize=10, va="center", ha="center")
        lower = upper
    ax.fill_between(t, lower, y_top, color="#d9a0c8", lw=0)
    for at in (len(t) // 10, len(t) * 9 // 10):
        ax.text(t[at], 0.5 * (lower[at] + y_top), scale.above, fontsize=10, va="center", ha="center")
    for label, duration, pga in points:
        ax.plot(duration, pga, "o", color="k", ms=5)
        ax.annotate(label, (duration, pga), textcoords="offset points", xytext=(6, 6), fontsize=9)
    ax.set_xlim(0.0, t_top)
    ax.set_ylim(0.0, y_top)
    ax.set_xlabel("t_Ha [s]")
    ax.set_ylabel("PGA_H10 [m/s²]")
    ax.set_title(_title(f"Intensity scale {scale.name}", record), fontsize=10)
    return figure


def _stem(record: Record) -> str:
    if record.synthetic and "seed" in record.metadata:
        return f"synthetic-seed{record.metadata['seed']}"
    files = record.metadata.get("files") or []
    base = Path(files[0]).stem if files else (record.source or "record")
    return re.sub(r"[^A-Za-z0-9._-]+", "_", base).strip("_") or "record"


def _point_label(record: Record, stem: str) -> str:
    # From the record, not the file name: a real record may be called "synthetic-seed...".
    if record.synthetic and "seed" in record.metadata:
        return f"synthetic tremor, seed {record.metadata['seed']}"
    return stem


def write_figures(
    record: Record,
    directory: str | Path,
    scale: IntensityScale = DEFAULT_SCALE,
    stem: str | None = None,
    formats: Sequence[str] = FORMATS,
    marks: Sequence[float] = (),
) -> list[Path]:
    """Write the four figures of ``record`` into ``directory`` in each format; return the paths.

    Files: ``<stem>_acceleration``, ``<stem>_fourier``, ``<stem>_intensity``, ``<stem>_spectrum``
    (``.png``, ``.svg``). ``marks``: periods (s) marked on the response spectrum.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    stem = stem or _stem(record)
    point = (_point_label(record, stem), record_t_ha(record), record_pga_h10(record))
    figures = {
        "acceleration": plot_accelerations(record),
        "fourier": plot_fourier(record),
        "intensity": plot_intensity_chart([point], scale, record=record),
        "spectrum": plot_response_spectrum(record, marks=marks),
    }
    return [path for kind, figure in figures.items() for path in save(figure, directory, f"{stem}_{kind}", formats)]
