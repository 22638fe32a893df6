"""The averaged spectrum under a stabilisation diagram: singular values of the spectral density matrix.

Welch's estimate of the cross spectral density matrix ``G(f)`` of all channels (Hann windows,
half overlap, each segment's mean removed, one-sided density: the conventions of
:func:`scipy.signal.csd`) and its singular values at each frequency. The first singular value is
the complex mode indicator function (CMIF) the paper plots under its diagram: every mode any
channel sees peaks there, whatever the channel, and the next singular values show closely spaced
modes. Each channel is scaled to unit variance first, so that no channel dominates by its units
or level (an averaged, not a summed, spectrum).

Why not :func:`scipy.signal.csd` itself: it transforms both signals of every pair, ``l^2`` sets
of FFTs for ``l`` channels (784 for the bridge's 28); here each channel is transformed once and
the matrix is formed from the segment spectra (a test checks the two agree).

:func:`peak_ratio` is the spectral check of the automatic selection
(:mod:`bearingfw.oma.stabilisation`): the paper accepted as modes only stable poles that the
CMIF confirms with a peak (its stable poles near 12 Hz without one were rejected).
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from scipy import signal

__all__ = ["Spectrum", "half_width", "least_peak", "peak_ratio", "singular_spectrum", "spectral_matrix"]

#: Welch segments: a sixteenth of the record by default (about 30 half-overlapping averages, a
#: relative scatter of about 20 % per bin), at most this many samples.
MAX_SEGMENT = 4096


def _segment_length(n: int, dt: float, segment: float | None) -> int:
    if segment is None:
        return min(MAX_SEGMENT, max(16, n // 16))
    return max(16, min(n, int(round(segment / dt))))


def spectral_matrix(y: np.ndarray, dt: float, segment: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(f, G)``: Welch's one-sided cross spectral density matrix of the columns of ``y``, ``G`` (len(f), l, l).

    ``G[k, i, j]`` is :func:`scipy.signal.csd` of channels ``i`` and ``j`` (Hann window,
    ``segment`` seconds long, half overlap, constant detrend). ``segment`` defaults to a sixteenth
    of the record, at most :data:`MAX_SEGMENT` samples.
    """
    y = np.asarray(y, dtype=float)
    n = y.shape[0]
    length = _segment_length(n, dt, segment)
    window = signal.get_window("hann", length)
    starts = range(0, n - length + 1, length - length // 2)  # csd: noverlap = length // 2
    segments = np.stack([y[s : s + length] for s in starts])  # (segments, samples, channels)
    segments = segments - segments.mean(axis=1, keepdims=True)
    spectra = np.fft.rfft(window[None, :, None] * segments, axis=1)  # (segments, f, channels)
    # csd's convention: G_ij = conj(X_i) X_j, averaged, density scaling, one-sided (interior bins doubled).
    G = np.einsum("sfi,sfj->fij", spectra.conj(), spectra) * dt / (len(starts) * float(window @ window))
    interior = slice(1, None) if length % 2 else slice(1, -1)
    G[interior] *= 2.0
    return np.fft.rfftfreq(length, dt), G


#: Singular values kept per frequency (the CMIF curves): enough for the floors of a few directly
#: measured support components and a pair of close modes.
CURVES = 6


@attrs.frozen(eq=False)
class Spectrum:
    """The spectral density matrix of the channels scaled to unit variance, and its singular values.

    ``matrix``: ``G(f)``, (len(frequency), l, l); ``values``: its largest singular values,
    descending, one column each (the first is the CMIF); ``scale``: each channel's standard
    deviation (the scaling undone by :meth:`along`); ``duration``: of the record (s).
    """

    frequency: np.ndarray
    matrix: np.ndarray
    values: np.ndarray
    scale: np.ndarray
    duration: float

    @property
    def resolution(self) -> float:
        return float(self.frequency[1] - self.frequency[0])

    def along(self, shape) -> np.ndarray:
        """The spectral density along ``shape`` (channel units, real or complex): ``phi^H G phi / phi^H phi``."""
        phi = np.asarray(shape) / self.scale
        norm = float(np.real(np.vdot(phi, phi)))
        if norm == 0:
            return np.zeros(self.frequency.size)
        return np.real(np.einsum("i,fij,j->f", phi.conj(), self.matrix, phi)) / norm


def singular_spectrum(y: np.ndarray, dt: float, segment: float | None = None) -> Spectrum:
    """:class:`Spectrum` of the channels ``y`` (samples, l) scaled to unit variance (module docstring)."""
    y = np.asarray(y, dtype=float)
    std = y.std(axis=0)
    scale = np.where(std > 0, std, 1.0)
    f, G = spectral_matrix((y - y.mean(axis=0)) / scale, dt, segment)
    values = np.linalg.svd(G, compute_uv=False)[:, :CURVES]
    return Spectrum(f, G, values, scale, float(y.shape[0] * dt))


#: The peak check looks for the spectrum's peak within PEAK_BAND half-widths of a pole and for
#: the valleys on either side within SEARCH half-widths (:func:`peak_ratio`).
PEAK_BAND = 1.0
SEARCH = 6.0
#: A peak must stand this many standard deviations of a band mean clear of the valley
#: (:func:`least_peak`).
SIGNIFICANCE = 5.0


def _band_mean(values: np.ndarray, half: int) -> np.ndarray:
    """The mean of ``values`` over ``+-half`` bins around each bin (fewer at the ends)."""
    total = np.concatenate([[0.0], np.cumsum(values)])
    k = np.arange(values.size)
    low, high = np.maximum(k - half, 0), np.minimum(k + half + 1, values.size)
    return (total[high] - total[low]) / (high - low)


def half_width(spectrum: Spectrum, frequency: float, damping: float) -> float:
    """The band of a pole: its half-power half-width ``zeta f``, at least two bins (a Hann window's main lobe)."""
    return max(abs(damping) * frequency, 2.0 * spectrum.resolution)


def _valley(side: np.ndarray) -> float:
    """The lowest value of ``side`` (from the peak outwards) before it first rises above the peak."""
    higher = np.flatnonzero(side > side[0])
    return float(side[: higher[0] if higher.size else side.size].min())


def _prominence(values: np.ndarray, f: np.ndarray, frequency: float, w: float, half: int) -> float:
    smooth = _band_mean(values, half)
    centre = np.flatnonzero(np.abs(f - frequency) <= PEAK_BAND * w)
    span = np.flatnonzero(np.abs(f - frequency) <= SEARCH * w)
    top = centre[np.argmax(smooth[centre])]
    valley = max(_valley(smooth[span[0] : top + 1][::-1]), _valley(smooth[top : span[-1] + 1]))
    return float(smooth[top]) / max(valley, np.finfo(float).tiny)


def peak_ratio(spectrum: Spectrum, frequency: float, damping: float, shape=None) -> float:
    """How clearly the spectrum peaks at a pole: the prominence of its peak, as a ratio.

    The spectrum is first averaged over the pole's band, ``+- w`` (:func:`half_width`); that
    removes most of the estimate's scatter from bin to bin. The peak is the largest band mean
    within ``w`` of ``frequency``; the ratio is the peak over the higher of the two valleys (on
    either side, the least band mean between the peak and ``6 w`` away or the first higher
    value, whichever is nearer: the topographic prominence). On a flank that rises towards a
    stronger neighbour, or on a falling spectrum, the largest band mean lies at the edge next to
    the higher values: the valley there is the peak itself, and the ratio 1.

    The ratio is the largest over the CMIF curves (the :data:`CURVES` largest singular values:
    a weaker mode next to a stronger one peaks in the second; where every sensor reads the same
    support motion directly, a white floor of rank two or three hides weak modes from the first
    curves) and, given the pole's ``shape`` at the channels, the spectrum along it
    (:meth:`Spectrum.along`), which leaves out most of what other modes and the floor put on the
    other channels. A lightly damped mode alone gives 10-100; one among close neighbours 1.7-3;
    noise 1-1.5 (:func:`least_peak`). NaN when ``frequency`` lies outside the spectrum.
    """
    f = spectrum.frequency
    w = half_width(spectrum, frequency, damping)
    if not np.any(np.abs(f - frequency) <= PEAK_BAND * w):
        return math.nan
    half = max(1, int(round(w / spectrum.resolution)))
    curves = list(spectrum.values.T)
    if shape is not None:
        curves.append(spectrum.along(shape))
    return max(_prominence(values, f, frequency, w, half) for values in curves)


def least_peak(spectrum: Spectrum, frequency: float, damping: float, floor: float) -> float:
    """The least :func:`peak_ratio` that counts as a peak: ``floor``, or more where the estimate scatters.

    A band mean over ``2 w`` Hz of a Welch estimate from ``T`` seconds scatters by about
    ``1 / sqrt(2 w T)`` (relative); among the several band means a search looks at, noise makes
    bumps of three to four times that. A peak must stand :data:`SIGNIFICANCE` (5) times clear:
    on a 30 s record with its coarse bins, noise bumps reach ratios of 1.5, on 10 minutes 1.3.
    """
    w = half_width(spectrum, frequency, damping)
    return max(floor, 1.0 + SIGNIFICANCE / math.sqrt(2.0 * w * spectrum.duration))
