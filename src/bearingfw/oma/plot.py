"""Figures of an operational modal analysis: the stabilisation diagram over the averaged spectrum, a decay.

Built on :func:`bearingfw.plotting.new_figure` (Agg canvas, no pyplot); synthetic data say so in
the title.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from bearingfw.oma.decay import Decay
from bearingfw.oma.identify import Identification
from bearingfw.oma.stabilisation import STATUS
from bearingfw.plotting import new_figure, synthetic_title

__all__ = ["plot_decay", "plot_stabilisation"]

#: Marker of each pole status in the diagram, worst first (``STATUS``); unphysical and new poles are not drawn.
_STYLE = {
    "unstable": {"marker": ".", "color": "0.7", "ms": 2.5},
    "frequency": {"marker": "x", "color": "tab:orange", "ms": 3.5},
    "frequency+shape": {"marker": "^", "color": "tab:olive", "ms": 3.5, "mfc": "none"},
    "stable": {"marker": "o", "color": "tab:blue", "ms": 3.5, "mfc": "none"},
}


def plot_stabilisation(result: Identification, title: str | None = None) -> Figure:
    """Poles by order and frequency, marked by status; the CMIF (first singular values) behind; the selected modes."""
    poles, state = result.poles, result.stability
    criteria = result.criteria
    fmax = criteria.fmax if criteria.fmax is not None else 0.5 / result.channels.dt
    figure = new_figure(9.0, 5.5)
    ax = figure.subplots()
    spectrum_ax = ax.twinx()
    f, s = result.spectrum.frequency, result.spectrum.values[:, :3]
    band = (f >= criteria.fmin) & (f <= fmax)
    for k in range(s.shape[1]):
        spectrum_ax.semilogy(f[band], s[band, k], color="0.55" if k == 0 else "0.8", lw=0.8 if k == 0 else 0.6)
    spectrum_ax.set_ylabel("singular values of the spectral density matrix (CMIF)", fontsize=8, color="0.4")
    spectrum_ax.tick_params(axis="y", labelsize=7, colors="0.4")
    ax.set_zorder(spectrum_ax.get_zorder() + 1)
    ax.patch.set_visible(False)
    for name, style in _STYLE.items():
        at = state.status == STATUS.index(name)
        ax.plot(poles.frequency[at], poles.order[at], ls="none", label=f"{name} ({int(at.sum())})", **style)
    for mode in result.modes.modes:
        ax.axvline(mode.frequency, color="tab:red", lw=0.8, alpha=0.7)
        ax.annotate(
            f"{mode.frequency:.3f} Hz\n{mode.damping:.1%}",
            (mode.frequency, poles.orders[-1]),
            xytext=(2, 2),
            textcoords="offset points",
            fontsize=7,
            color="tab:red",
            rotation=90,
            va="top",
        )
    ax.set_xlim(criteria.fmin, fmax)
    ax.set_ylim(0, poles.orders[-1] + 2)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=7, framealpha=0.9)
    crit = (
        f"SSI-COV, orders 2..{poles.orders[-1]}, {poles.block_rows} block rows; "
        f"stable: df <= {criteria.frequency:.0%}, dzeta <= {criteria.damping:.0%}, MAC >= {criteria.mac:.0%}; "
        f"{len(result.modes.modes)} modes selected"
    )
    figure.suptitle(
        synthetic_title(title or f"Stabilisation diagram: {result.channels.source}\n{crit}", result.channels.synthetic),
        fontsize=9,
    )
    return figure


def plot_decay(decay: Decay, dt: float, channel: str = "", synthetic: bool = False) -> Figure:
    """The filtered record, the half-cycle peaks used and the fitted exponential envelope."""
    figure = new_figure(8.0, 3.5)
    ax = figure.subplots()
    t = np.arange(decay.filtered.size) * dt
    ax.plot(t, decay.filtered, lw=0.6, color="tab:blue", label="band-passed (backward)")
    sign = np.sign(decay.filtered[np.round(decay.times / dt).astype(int)])
    ax.plot(decay.times, sign * decay.amplitudes, "o", ms=3, color="tab:red", label="half-cycle peaks used")
    sigma = decay.decrement * decay.damped_frequency
    envelope = decay.amplitudes[0] * np.exp(-sigma * (decay.times - decay.times[0]))
    ax.plot(decay.times, envelope, "--", color="tab:red", lw=0.8)
    ax.plot(
        decay.times,
        -envelope,
        "--",
        color="tab:red",
        lw=0.8,
        label=f"delta = {decay.decrement:.3f}, zeta = {decay.damping:.2%}",
    )
    period = 1.0 / decay.damped_frequency
    ax.set_xlim(max(0.0, decay.times[0] - 5.0 * period), decay.times[-1] + 5.0 * period)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("acceleration [m/s²]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    what = f"Free decay at {decay.centre:g} Hz" + (f", channel {channel}" if channel else "")
    figure.suptitle(synthetic_title(what, synthetic), fontsize=9)
    return figure
