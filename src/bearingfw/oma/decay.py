"""Damping from a free decay: the logarithmic decrement of a band-pass filtered record.

The paper's jumping test (section 3.2): people jump at a natural frequency, stop, and the
deck's acceleration decays freely. A 3rd-order Butterworth band-pass (the paper: 0.04 Hz wide;
here by default 20 % of the centre frequency) centred on the mode's frequency isolates that
mode; the decay of its half-cycle peaks gives the logarithmic decrement
``delta = ln(x_k / x_(k+1))`` per cycle and the damping ratio ``zeta = delta / sqrt(4 pi^2 + delta^2)``
(:func:`bearingfw.analysis.damping_ratio_from_log_decrement`).

Why the filter runs backward in time only. A band-pass as narrow as the paper's rings longer than the mode
decays (a 0.04 Hz band decays at about ``pi 0.04 / 2 = 0.06 1/s``, a 2 % mode at 1.5 Hz at
``0.19 1/s``): run forward (causally), its output after the excitation stops is the filter's own
ringing, and the decrement would be the filter's. Run backward (anti-causally), the output at
time ``t`` depends only on the record after ``t``. During a free decay that is a sum of damped
modes ``a e^(lambda s)``, and each passes as ``a H(-lambda) e^(lambda t)``: scaled, with its own
decay rate unchanged, however narrow the band. (A forward-backward zero-phase pass has the
forward pass's bias.) The record must go on after the decay has died out, so that the backward
pass starts from noise.

Where the decay starts. Before the excitation stops, the backward filter's output already
mixes the forced motion with the decay to come (over the filter's memory), so its peaks start
falling early, at the filter's rate. The same band run forward does the opposite: its output
stays at the forced level until the excitation stops and falls from then on. So the default
``start`` is the first peak of the longest run of decreasing half-cycle peaks of the *forward*
filtered record (a free decay decreases peak after peak; forced motion and noise do not for
long), and the decrement is fitted on the *backward* filtered one from there.

The band. The backward pass keeps the decay rate for any band, but its output is the decay
times ``|H(-lambda)|``, about ``pi B / (2 sigma)`` for a band ``B`` much narrower than the mode
(decay rate ``sigma``): with the paper's 0.04 Hz on a 2.7 % mode at 3.36 Hz that is a tenth,
while noise in the band falls only as ``sqrt(B)``. And a band that narrow rings for longer
than the mode decays (its time constant, about ``2 / (pi B)`` = 16 s, against the mode's 2-5 s),
so its forward-filtered record would be the filter's own ringing: the start is always found
with a band at least the default relative width. Hence the default band of 20 % of the centre
frequency, several times the mode's own half-power band ``2 zeta f``: its time constant (2 s at
1.5 Hz) is shorter than the decay's, and the decay stands out of the noise.

The end. The backward pass starts from rest at the end of the record and needs a few of its
time constants ``tau`` (the slowest pole of the band-pass) to forget that start: peaks within
``settle`` time constants of the record's end are not used (default 4, a residue of e^-4 = 2 %).

The fit: the half-cycle peaks (largest ``|y|`` between zero crossings) from ``start`` until
they fall below ``floor`` times the first (or ``end``) give ``ln |peak|`` against time, a
straight line of slope ``-sigma``; the damped frequency ``f_d`` is half the inverse of the mean
peak spacing, and ``delta = sigma / f_d``. A fit that does not decay (slope >= 0) or is not a
straight line (``r^2 < min_r2``, default 0.95: the peaks are forced motion, beats of two modes
or noise) is an error, not a damping ratio.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from scipy import signal

from bearingfw.analysis.damping import damping_ratio_from_log_decrement
from bearingfw.parameters import ParameterError, integer_parameter, parameter

__all__ = [
    "Decay",
    "DecayFilter",
    "backward_band_pass",
    "decay_start",
    "filter_time_constant",
    "half_cycle_peaks",
    "log_decrement",
    "longest_decrease",
]


@attrs.frozen
class DecayFilter:
    """The band-pass of a decay: Butterworth of ``order`` (scipy's band-pass order), ``bandwidth`` Hz wide.

    ``bandwidth`` defaults to ``relative_bandwidth`` times the centre frequency.
    """

    bandwidth: float | None = parameter(
        optional=True,
        low=0.0,
        low_open=True,
        unit="Hz",
        doc="band width (the paper's: 0.04 Hz; default relative_bandwidth x centre)",
    )
    relative_bandwidth: float = parameter(
        low=0.0,
        low_open=True,
        high=1.0,
        default=0.2,
        doc="band width over the centre frequency, when no bandwidth is given",
    )
    order: int = integer_parameter(low=1, high=8, default=3, doc="Butterworth order (the paper's: 3)")
    floor: float = parameter(
        low=0.0,
        low_open=True,
        high=1.0,
        high_open=True,
        default=0.1,
        doc="the fit ends where the peaks fall below this share of the first",
    )
    min_r2: float = parameter(
        low=0.0, high=1.0, default=0.95, doc="least r^2 of the straight line through ln(peak) against time"
    )
    settle: float = parameter(
        low=0.0, high=50.0, default=4.0, doc="filter time constants between the last peak used and the record's end"
    )


def _band_limits(centre: float, spec: DecayFilter) -> tuple[float, float]:
    width = spec.bandwidth if spec.bandwidth is not None else spec.relative_bandwidth * centre
    return centre - width / 2, centre + width / 2


def _band(dt: float, centre: float, spec: DecayFilter) -> np.ndarray:
    low, high = _band_limits(centre, spec)
    nyquist = 0.5 / dt
    if not 0 < low < high < nyquist:
        raise ParameterError(
            f"log_decrement: the band {low:g}..{high:g} Hz must lie within 0 < f < {nyquist:g} Hz "
            "(the Nyquist frequency)"
        )
    return signal.butter(spec.order, [low, high], btype="bandpass", fs=1.0 / dt, output="sos")


def backward_band_pass(y: np.ndarray, dt: float, centre: float, spec: DecayFilter = DecayFilter()) -> np.ndarray:
    """``y`` band-passed around ``centre`` Hz, anti-causally (module docstring)."""
    return signal.sosfilt(_band(dt, centre, spec), np.asarray(y, dtype=float)[::-1])[::-1]


def decay_start(y: np.ndarray, dt: float, centre: float, spec: DecayFilter = DecayFilter()) -> float:
    """When the free decay near ``centre`` Hz starts: where the forward-filtered peaks start their longest fall.

    The forward filter is ``spec``'s band, but never narrower than its default relative band: a
    narrower one rings for longer than the mode decays (module docstring).
    """
    wide = max(spec.bandwidth or 0.0, spec.relative_bandwidth * centre)
    index, amplitude = half_cycle_peaks(
        signal.sosfilt(_band(dt, centre, attrs.evolve(spec, bandwidth=wide)), np.asarray(y, dtype=float))
    )
    return float(index[longest_decrease(amplitude)] * dt) if index.size else 0.0


def filter_time_constant(dt: float, centre: float, spec: DecayFilter = DecayFilter()) -> float:
    """The band-pass's longest time constant (s): one over the decay rate of its slowest pole."""
    poles = np.concatenate([np.roots(section[3:]) for section in _band(dt, centre, spec)])  # each denominator
    rates = -np.log(np.abs(poles)) / dt
    return float(1.0 / rates.min())


def half_cycle_peaks(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indices and absolute values of the largest ``|y|`` between consecutive zero crossings."""
    crossings = np.flatnonzero(np.signbit(y[1:]) != np.signbit(y[:-1])) + 1
    index = np.array(
        [a + int(np.argmax(np.abs(y[a:b]))) for a, b in zip(crossings[:-1], crossings[1:]) if b > a], dtype=int
    )
    return index, np.abs(y[index]) if index.size else np.zeros(0)


def longest_decrease(amplitudes: np.ndarray) -> int:
    """Index of the first peak of the longest run of strictly decreasing ``amplitudes``."""
    falls = np.diff(amplitudes) < 0
    best, best_length, begin = 0, 0, 0
    for k, fall in enumerate(np.append(falls, False)):
        if not fall:
            if k - begin > best_length:
                best, best_length = begin, k - begin
            begin = k + 1
    return best


@attrs.frozen(eq=False)
class Decay:
    """A fitted decay: the band's ``centre``, the ``damped_frequency`` from the peak spacing, the decrement per
    cycle, the damping ratio, the peaks used and the line's ``r2``."""

    centre: float
    damped_frequency: float
    decrement: float
    damping: float
    times: np.ndarray
    amplitudes: np.ndarray
    filtered: np.ndarray
    r2: float

    def to_dict(self) -> dict:
        return {
            "centre": self.centre,
            "damped_frequency": self.damped_frequency,
            "decrement": self.decrement,
            "damping": self.damping,
            "peaks": int(self.times.size),
            "start": float(self.times[0]),
            "end": float(self.times[-1]),
            "r2": self.r2,
        }


def _fit_range(t: np.ndarray, amplitude: np.ndarray, start: float, end: float, floor: float) -> tuple[int, int]:
    """Indices ``[first, last)`` of the peaks from ``start`` until they fall below ``floor`` x the first, or ``end``."""
    after = np.flatnonzero(t >= start)
    first = int(after[0]) if after.size else amplitude.size
    last = int(np.searchsorted(t, end, side="right"))
    if first < last:
        below = np.flatnonzero(amplitude[first:last] < floor * amplitude[first])
        if below.size:
            last = first + int(below[0])
    return first, max(last, first)


def log_decrement(
    y,
    dt: float,
    frequency: float,
    spec: DecayFilter = DecayFilter(),
    *,
    start: float | None = None,
    end: float | None = None,
) -> Decay:
    """The logarithmic decrement of the mode near ``frequency`` Hz in the free decay ``y`` (module docstring).

    Raises :class:`~bearingfw.parameters.ParameterError` when fewer than 4 peaks are usable, the
    peaks do not decay, or they do not lie on a straight line (``spec.min_r2``).
    """
    y = np.asarray(y, dtype=float)
    if y.ndim != 1 or y.size < 8:
        raise ParameterError(f"log_decrement: y must be a 1-D record of at least 8 samples, got shape {y.shape}")
    if not (math.isfinite(dt) and dt > 0):
        raise ParameterError(f"log_decrement: dt = {dt!r} must be > 0 s")
    filtered = backward_band_pass(y, dt, frequency, spec)
    index, amplitude = half_cycle_peaks(filtered)
    t = index * dt
    start = decay_start(y, dt, frequency, spec) if start is None else start
    tau = filter_time_constant(dt, frequency, spec)
    settled = (y.size - 1) * dt - spec.settle * tau  # later peaks still carry the backward pass's start
    first, last = _fit_range(t, amplitude, start, settled if end is None else min(end, settled), spec.floor)
    where = f"log_decrement at {frequency:g} Hz"
    if last - first < 4:
        raise ParameterError(
            f"{where}: only {last - first} half-cycle peaks between the start ({start:.2f} s) and where they fall "
            f"below floor = {spec.floor:g} of the first or reach {settled:.2f} s (settle = {spec.settle:g} filter time "
            f"constants of {tau:.2f} s before the record's end); need at least 4 (a longer record after the decay, "
            "another start, a lower floor, or a wider band)"
        )
    tt, ln_a = t[first:last], np.log(amplitude[first:last])
    slope, intercept = np.polyfit(tt, ln_a, 1)
    residual = ln_a - (slope * tt + intercept)
    r2 = 1.0 - float(residual @ residual) / float(np.sum((ln_a - ln_a.mean()) ** 2))
    span = f"{last - first} peaks from {tt[0]:.2f} to {tt[-1]:.2f} s"
    if slope >= 0:
        raise ParameterError(
            f"{where}: the peaks do not decay ({span}, slope {slope:+.4f} 1/s): no free decay there "
            "(check the frequency and the start)"
        )
    if r2 < spec.min_r2:
        raise ParameterError(
            f"{where}: ln(peak) against time is not a straight line ({span}, r2 = {r2:.3f} < min_r2 = "
            f"{spec.min_r2:g}): forced motion, beating modes or noise (check the start, narrow the band)"
        )
    f_d = 1.0 / (2.0 * float(np.mean(np.diff(tt))))
    low, high = _band_limits(frequency, spec)
    if not low <= f_d <= high:
        # The peaks are another mode leaking through the band's skirts (a strong mode nearby):
        # their decrement is that mode's, not this one's.
        raise ParameterError(
            f"{where}: the fitted decay oscillates at {f_d:.4g} Hz, outside the band {low:.4g}..{high:.4g} Hz "
            f"({span}): another mode leaks through the filter; no free decay of this mode was found "
            "(check the frequency, narrow the band or choose another start)"
        )
    delta = -slope / f_d
    return Decay(
        float(frequency), f_d, delta, damping_ratio_from_log_decrement(delta), tt, amplitude[first:last], filtered, r2
    )
