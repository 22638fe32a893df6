"""Ground-motion measures: peaks, PGA_H10, Arias intensity, t_Ha, Fourier and response spectra.

Pure functions over numpy arrays (accelerations in m/s^2, time step ``dt`` in s); the
``record_*`` helpers apply them to a :class:`~bearingfw.motion.Record`.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from scipy import linalg, signal
from scipy.integrate import cumulative_trapezoid, trapezoid

from bearingfw.motion.record import G, Record
from bearingfw.parameters import ParameterError

__all__ = [
    "H10_CUTOFF",
    "ResponseSpectrum",
    "arias_intensity",
    "band_energy_fraction",
    "dominant_frequency",
    "fourier_spectrum",
    "husid",
    "lowpass",
    "peak",
    "pga_h10",
    "response_spectrum",
    "significant_duration",
    "t_ha",
]

#: The cut-off of PGA_H10 (Hz): the "10" in H10.
H10_CUTOFF = 10.0


def _signal(a, name: str = "acceleration") -> np.ndarray:
    a = np.asarray(a, dtype=float)
    if a.ndim != 1 or a.size < 2:
        raise ParameterError(f"{name} must be a 1-D array of at least 2 samples, got shape {a.shape}")
    return a


def _dt(dt) -> float:
    dt = float(dt)
    if not math.isfinite(dt) or dt <= 0:
        raise ParameterError(f"time step dt must be finite and > 0 s, got {dt!r}")
    return dt


def peak(a) -> float:
    """Peak absolute value, ``max_k |a_k|``."""
    return float(np.max(np.abs(_signal(a))))


def lowpass(a, dt: float, cutoff: float = H10_CUTOFF, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth low-pass of ``order`` at ``cutoff`` Hz.

    The filter runs forward and backward (``sosfiltfilt``): no phase shift, so peaks stay where
    they are; the magnitude response is ``1 / (1 + (f/cutoff)^(2 order))`` (the square of the
    one-pass filter's). If the cut-off is at or above the Nyquist frequency the signal has no
    content to remove and is returned unchanged.
    """
    a, dt = _signal(a), _dt(dt)
    nyquist = 0.5 / dt
    if cutoff >= nyquist:
        return a.copy()
    sos = signal.butter(order, cutoff, btype="lowpass", fs=1.0 / dt, output="sos")
    # Pad (odd reflection) by three periods of the cut-off, not scipy's few samples: the start-up
    # transient then dies out in the padding instead of overshooting the record's first peaks.
    padlen = min(a.size - 1, math.ceil(3.0 / (cutoff * dt)))
    return signal.sosfiltfilt(sos, a, padlen=padlen)


def pga_h10(h1, h2, dt: float) -> float:
    """PGA_H10 (m/s^2): the peak of the resultant of both horizontals, each low-passed to 10 Hz.

    ``max_k sqrt(h1f_k^2 + h2f_k^2)`` with ``h1f, h2f`` the zero-phase 4th-order Butterworth
    low-passes of the two horizontal components at 10 Hz (:func:`lowpass`).
    """
    f1, f2 = lowpass(h1, dt), lowpass(h2, dt)
    if f1.size != f2.size:
        raise ParameterError(f"the horizontal components differ in length ({f1.size} and {f2.size})")
    return float(np.max(np.hypot(f1, f2)))


def husid(a, dt: float) -> np.ndarray:
    """Cumulative Arias intensity ``I(t_k) = pi/(2g) int_0^t_k a^2 dt`` (m/s), trapezoidal rule.

    ``a`` may be ``(n,)`` or ``(m, n)``; several rows (e.g. both horizontals) are summed, which
    is the Arias intensity of the vector motion.
    """
    a, dt = np.atleast_2d(np.asarray(a, dtype=float)), _dt(dt)
    if a.shape[-1] < 2:
        raise ParameterError("acceleration must have at least 2 samples")
    return math.pi / (2.0 * G) * cumulative_trapezoid(np.sum(a * a, axis=0), dx=dt, initial=0.0)


def arias_intensity(a, dt: float) -> float:
    """Arias intensity ``I_a = pi/(2g) int a(t)^2 dt`` (m/s); rows of a 2-D ``a`` are summed."""
    a, dt = np.atleast_2d(np.asarray(a, dtype=float)), _dt(dt)
    return float(math.pi / (2.0 * G) * trapezoid(np.sum(a * a, axis=0), dx=dt))


def _crossing(cumulative: np.ndarray, level: float, dt: float) -> float:
    # First sample at or above the level; linear interpolation inside the step before it.
    k = int(np.searchsorted(cumulative, level, side="left"))
    if k == 0:
        return 0.0
    low, high = cumulative[k - 1], cumulative[k]
    return (k - 1 + (level - low) / (high - low)) * dt


def significant_duration(a, dt: float, start: float = 0.05, end: float = 0.95) -> float:
    """Time between ``start`` and ``end`` fractions of the Arias intensity (s).

    With the defaults this is the 5-95 % significant duration; for both horizontals (a 2-D
    ``a``) it is the paper's t_Ha. Crossing times are interpolated linearly between samples.
    """
    if not 0.0 <= start < end <= 1.0:
        raise ParameterError(f"fractions must satisfy 0 <= start < end <= 1, got start={start!r}, end={end!r}")
    cumulative = husid(a, dt)
    total = cumulative[-1]
    if total <= 0.0:
        raise ParameterError("the acceleration is zero everywhere: its Arias intensity and duration are undefined")
    return float(_crossing(cumulative, end * total, dt) - _crossing(cumulative, start * total, dt))


def t_ha(h1, h2, dt: float) -> float:
    """t_Ha (s): 5-95 % significant duration of the Arias intensity of both horizontals."""
    return significant_duration(np.vstack([_signal(h1), _signal(h2)]), dt)


def fourier_spectrum(a, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Fourier amplitude spectrum ``|A(f)| = |dt sum_k a_k exp(-2 pi i f t_k)|`` (m/s).

    Returns ``(f, |A|)`` at ``f = j / (n dt)``, ``j = 0 .. n//2`` (the continuous Fourier
    transform of the sampled signal, so amplitudes do not depend on ``dt``).
    """
    a, dt = _signal(a), _dt(dt)
    return np.fft.rfftfreq(a.size, dt), np.abs(np.fft.rfft(a)) * dt


def dominant_frequency(a, dt: float, smoothing: float = 0.2, fmin: float = 0.1) -> float:
    """Frequency (Hz) of the largest Fourier amplitude above ``fmin``.

    The amplitude is first averaged over a running window ``smoothing`` Hz wide (at least one
    frequency step) so that one spike of a short, noisy spectrum does not decide.
    """
    f, amplitude = fourier_spectrum(a, dt)
    df = f[1] - f[0]
    width = max(1, int(round(smoothing / df)) | 1)  # odd: a centred window
    smooth = np.convolve(amplitude, np.ones(width) / width, mode="same")
    mask = f >= fmin
    if not mask.any():
        raise ParameterError(f"no frequency above fmin = {fmin} Hz (record too short)")
    return float(f[mask][np.argmax(smooth[mask])])


def band_energy_fraction(a, dt: float, fmin: float, fmax: float) -> float:
    """Share of the Fourier energy ``sum |A(f)|^2`` between ``fmin`` and ``fmax`` Hz (inclusive).

    Rows of a 2-D ``a`` (e.g. both horizontals) are pooled. By Parseval's theorem this is the
    share of ``int a^2 dt`` carried by that band.
    """
    rows = np.atleast_2d(np.asarray(a, dtype=float))
    energy = None
    for row in rows:
        f, amplitude = fourier_spectrum(row, dt)
        energy = amplitude**2 if energy is None else energy + amplitude**2
    total = float(energy.sum())
    if total <= 0.0:
        raise ParameterError("the acceleration is zero everywhere: no Fourier energy")
    band = (f >= fmin) & (f <= fmax)
    return float(energy[band].sum() / total)


@attrs.frozen(eq=False)
class ResponseSpectrum:
    """Peak responses of linear oscillators (damping ratio ``damping``) to a ground acceleration.

    ``sd`` relative displacement (m), ``psv = omega sd`` pseudo-velocity (m/s),
    ``psa = omega^2 sd`` pseudo-acceleration (m/s^2), one value per period (s).
    """

    periods: np.ndarray
    damping: float
    sd: np.ndarray

    @property
    def omega(self) -> np.ndarray:
        return 2.0 * np.pi / self.periods

    @property
    def psv(self) -> np.ndarray:
        return self.omega * self.sd

    @property
    def psa(self) -> np.ndarray:
        return self.omega**2 * self.sd


def _oscillator_filter(omega: float, zeta: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """IIR coefficients ``(b, a)`` mapping the load ``p_k`` to the displacement ``u_k`` of
    ``u'' + 2 zeta omega u' + omega^2 u = p``, exact for ``p`` linear between samples.

    With ``x = [u, u']`` and ``x' = A x + e p`` the step is
    ``x_{k+1} = Phi x_k + G0 p_k + G1 p_{k+1}``: ``Phi = exp(A dt)`` and ``G0``, ``G1`` come
    from one matrix exponential of the system augmented with the ramp ``p(tau) = p_k + q tau``
    (the blocks of ``exp(M dt)`` that multiply ``p_k`` and ``q``). Eliminating ``u'`` gives
    ``U/P = (b0 z^2 + b1 z + b2) / (z^2 - tr(Phi) z + det(Phi))``.
    """
    A = np.array([[0.0, 1.0], [-(omega**2), -2.0 * zeta * omega]])
    M = np.zeros((4, 4))
    M[:2, :2] = A
    M[1, 2] = 1.0  # the load enters the velocity equation
    M[2, 3] = 1.0  # p' = q
    E = linalg.expm(M * dt)
    phi, e_p, e_q = E[:2, :2], E[:2, 2], E[:2, 3]
    g1 = e_q / dt
    g0 = e_p - g1
    # c adj(zI - Phi) (G0 + z G1) with c = [1, 0]: adj row 0 is [z - Phi11, Phi01].
    b0 = g1[0]
    b1 = g0[0] - phi[1, 1] * g1[0] + phi[0, 1] * g1[1]
    b2 = -phi[1, 1] * g0[0] + phi[0, 1] * g0[1]
    a = np.array([1.0, -np.trace(phi), np.linalg.det(phi)])
    return np.array([b0, b1, b2]), a


def response_spectrum(a, dt: float, periods=None, damping: float = 0.05) -> ResponseSpectrum:
    """Elastic response spectrum of ground acceleration ``a`` (m/s^2), default 5 % damping.

    For each period ``T`` the oscillator ``u'' + 2 zeta omega u' + omega^2 u = -a_g`` (omega =
    2 pi / T) starts at rest; the ground acceleration is taken linear between samples and the
    response is exact for that input (a Nigam-Jennings-type recursion, run as an IIR filter).
    The oscillator is at rest before the first sample and the acceleration ramps from zero to
    ``a_0`` during the step before it (exact when the record starts at zero, as records do).
    Default periods: 100 values from 0.02 s to 5 s, logarithmically spaced.
    """
    a, dt = _signal(a), _dt(dt)
    if not 0.0 <= damping < 1.0:
        raise ParameterError(f"damping ratio must satisfy 0 <= damping < 1, got {damping!r}")
    periods = np.geomspace(0.02, 5.0, 100) if periods is None else np.atleast_1d(np.asarray(periods, dtype=float))
    if np.any(~np.isfinite(periods)) or np.any(periods <= 0):
        raise ParameterError("periods must be finite and > 0 s")
    sd = np.empty(periods.size)
    for i, T in enumerate(periods):
        b, den = _oscillator_filter(2.0 * np.pi / T, damping, dt)
        sd[i] = np.max(np.abs(signal.lfilter(b, den, -a)))
    return ResponseSpectrum(periods=periods, damping=float(damping), sd=sd)


# -- the same measures for a Record -----------------------------------------------------------


def record_pga_h10(record: Record) -> float:
    return pga_h10(record.h1, record.h2, record.dt)


def record_t_ha(record: Record) -> float:
    return t_ha(record.h1, record.h2, record.dt)


def record_summary(record: Record) -> dict:
    """Every measure of :mod:`bearingfw.motion.metrics` for a record, as plain data (SI units)."""
    components = []
    for role, name, values, length in zip(("h1", "h2", "v"), record.names, record.components, record.original_lengths):
        components.append(
            {
                "role": role,
                "name": name,
                "pga": peak(values),
                "pga_g": peak(values) / G,
                "arias": arias_intensity(values, record.dt),
                "dominant_frequency": dominant_frequency(values, record.dt) if np.any(values) else None,
                "samples": int(length),
                "padded": bool(length < record.n),
            }
        )
    return {
        "pga_h10": record_pga_h10(record),
        "t_ha": record_t_ha(record),
        "arias": arias_intensity(record.horizontal, record.dt),
        "pga": {c["role"]: c["pga"] for c in components},
        "components": components,
    }
