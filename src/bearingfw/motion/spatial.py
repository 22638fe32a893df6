"""Spatially varying ground motion from one record: wave passage and loss of coherency.

Given one three-component acceleration record and the plan positions of the support groups
(:func:`bearingfw.analysis.excitation.support_groups`), :func:`spatial_motions` returns one
acceleration record per group:

Wave passage. A plane wave crossing the site with apparent velocity ``c`` (m/s) in the horizontal
direction ``azimuth`` (degrees from global x towards y) reaches a support at plan position ``p``
after ``tau = (p - p_first) . e / c`` (``e`` the unit direction; the first support reached has
``tau = 0`` and keeps the record). Delays are fractional in general; they are applied exactly in
the frequency domain, ``A(f) exp(-2 pi i f tau)``, on the record zero-padded to at least twice
its length plus the largest delay (so nothing wraps around); the output is the record's length
plus the largest delay, with the delayed supports' tails kept.

Loss of coherency (``coherency`` not ``"none"``). Conditional spectral simulation: at each
frequency the lagged coherency matrix ``Gamma_jk = |gamma(xi_jk, f)|`` (``xi_jk`` the plan
distance between supports ``j`` and ``k``) is factorised, ``Gamma = L L^T``, the first-reached
support keeps the record's Fourier coefficient ``X_1`` and support ``j`` gets
``X_j = L_j1 X_1 + sum_{k>1} L_jk |X_1| exp(i phi_jk)`` with independent uniform random phases
(each component of each support independently), seeded by ``seed``: ``E[X_j X_1*] = Gamma_j1 |X_1|^2``
and ``E|X_j|^2 = |X_1|^2``. The independent parts are not bare random phases (those spread a
motion evenly over the whole window): each is random-phase noise with the record's Fourier
amplitude, multiplied in time by the record's envelope (moving RMS over 1 s), whose Fourier
amplitude is then set back to the record's, keeping its phases; so the simulated motion is strong
where the record is and the expectations above hold exactly.

Response spectra. One realisation's 5 %-damped spectrum still differs from the record's (its peaks
depend on the phases). Each generated support is therefore corrected towards the record's spectrum,
after its wave-passage delay (a fractional delay alone moves the sampled peaks of the record by up
to ``1 - cos(pi f dt)``, 4.5 % at 4.8 Hz for ``dt`` = 0.02 s) and on the spectrum's own definition,
:func:`~bearingfw.motion.metrics.response_spectrum` (the motion linear between samples, the peak over
its sub-steps), in two steps:

1. ``amplitude_iterations`` passes of the classical ratio correction (Gasparini and Vanmarcke's
   SIMQKE scheme: the Fourier coefficients times target/simulated spectral acceleration at
   :data:`MATCH_FREQUENCIES`, interpolated in log frequency, a factor smooth in frequency that keeps
   the phases). It brings the spectrum to within some 17-37 % everywhere, not closer: a record's
   spectrum changes by up to 10-12 % over 1 % of frequency (where its peak moves from one cycle of the
   motion to another), which no factor smooth in frequency reproduces on other phases.
2. ``wavelet_iterations`` passes of time-domain wavelet adjustment (the approach of Lilhanand and
   Tseng 1988 and Abrahamson 1992, RspMatch; Hancock et al. 2006, J. Earthq. Eng. 10(S1)). Every
   oscillator of :data:`WAVELET_FREQUENCIES` whose peak misses the record's by more than
   :data:`WAVELET_TOLERANCE` gets a wavelet ``cos(omega (t - t_c)) exp(-((t - t_c) / s)^2 / 2)``
   (``s`` = 6 periods: a band 2.7 % wide, no mean) per peak to correct (the largest if the
   response is too weak; if too strong, each of the three largest above the target, peaks closer
   than ``s`` sharing one), placed so that the oscillator's response to it peaks at that peak's
   time. The amplitudes solve, by least squares with a small Tikhonov term (neighbouring oscillators
   peaking together make the system nearly singular), the linear system of those peaks' responses to
   all the wavelets, in closed form (a damped oscillator under a Gaussian-modulated cosine: complex
   error functions). Half of that correction is applied each pass, whatever it does to the worst
   misfit (a rule that refuses a step stalls where neighbouring oscillators want opposite changes);
   the best motion of the passes is returned. Wavelets cut by the ends of the record (the slow ones
   are longer than it) leave the generated motion with some drift, as the random phases do: a
   generated support's displacement, integrated without correction, ends up to 2 m from zero
   (Manjil, 160 m away; the matching of version 1 did the same). The baseline correction of
   :class:`~bearingfw.analysis.excitation.SupportMotion` removes it from the differences.

The oscillators are 1.5 % apart in frequency (229 over 0.4-12 Hz). The matched spectra end within
4-5.5 % of the record's at them and within 6-8 % between them (on 1000 frequencies): a 5 %-damped
oscillator's peak comes from the band +-5 % around it, so neighbours 1.5 % apart share most of their
input, but the record's spectrum still bends sharply between them (linear interpolation between
points 1.5 % apart misses it by up to 3.6 % for Manjil), and so does a generated one, elsewhere. A
grid 1 % apart lowered the largest misfit by about 1 % for 50 % more time; points added only where
the record's spectrum bends did not lower it.

Measured (``benchmarks/spatial_cost.py``; 4 supports up to 160 m apart, apparent velocity 600 m/s,
every component of the three generated supports, 1000 frequencies over 0.5-10 Hz): Manjil 1990 (dt
0.02 s), seeds 0-9, each coherency model: largest misfit 6.0-7.8 % per realisation (5-7 % on the
tests' 100 frequencies); Chuetsu 2007 (dt 0.01 s), seeds 0-2: 6.2-7.6 %. After the ratio passes alone
it is 17-37 %. Cost: one realisation of Manjil (3 generated supports x 3 components) 3-5 s of CPU,
Chuetsu 5.5-7.5 s (version 1: tens of seconds): the spectra of all oscillators of all signals are evaluated together
(:class:`_Oscillators`: the recursion's transfer function times the signal's spectrum, one batched
inverse FFT), once per pass.

The passes cost some coherency: what they add to a support is not coherent with the record. Over 40
seeds, supports 100 m apart, the ensemble coherency is 0.03-0.08 below the model's with them where the
model's is above 0.2 (0.80 against 0.87 at 1-2 Hz for Harichandran-Vanmarcke; without them 0.85), half
of it from the ratio passes; tests/motion/test_spatial.py checks both against the same tolerance.

Coherency models (``|gamma|``, lagged: without the wave-passage phase):

- Harichandran and Vanmarcke (1986), "Stochastic variation of earthquake ground motion in space
  and time", J. Eng. Mech. 112(2): ``|gamma| = A exp(-2 xi (1 - A + alpha A) / (alpha theta(f)))
  + (1 - A) exp(-2 xi (1 - A + alpha A) / theta(f))``, ``theta(f) = k [1 + (f / f0)^b]^(-1/2)``;
  defaults: their fit to SMART-1 event 20, ``A = 0.736``, ``alpha = 0.147``, ``k = 5210 m``,
  ``f0 = 1.09 Hz``, ``b = 2.78``.
- Luco and Wong (1986), "Response of a rigid foundation to a spatially random ground motion",
  Earthq. Eng. Struct. Dyn. 14(6): ``|gamma| = exp(-(a 2 pi f xi)^2)`` with ``a = alpha / v_s``
  (s/m); default ``2.5e-4 s/m``, within the ``2e-4 .. 3e-4 s/m`` range usually quoted for it
  (e.g. Zerva 2009, "Spatial variation of seismic ground motions", CRC Press).

Everything here is numbers: the analysis layer (:class:`bearingfw.analysis.excitation.SupportMotion`)
turns the records into support motion, the experiment layer wires both to a cell.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import attrs
import numpy as np

from scipy import fft as sp_fft
from scipy import special

from bearingfw.motion.metrics import SUBSTEPS_PER_PERIOD, _oscillator_filters
from bearingfw.parameters import ParameterError, choice, integer_parameter, parameter

__all__ = [
    "COHERENCY_MODELS",
    "SpatialVariation",
    "coherency",
    "delays",
    "delayed",
    "spatial_motions",
]

COHERENCY_MODELS = ("none", "harichandran-vanmarcke", "luco-wong")
#: The spectral matching's version (1: ratio passes and one wavelet per band 8 % apart, on the motion before its
#: delay; 2: every oscillator 1.5 % apart, on the delayed motion, the definition of response_spectrum).
MATCHING_VERSION = 2


@attrs.frozen
class SpatialVariation:
    """How the ground motion varies between supports (module docstring for the models and sources)."""

    apparent_velocity: float | None = parameter(
        optional=True, low=1.0, high=1e5, unit="m/s", doc="apparent wave velocity (None: no wave passage)"
    )
    azimuth: float = parameter(low=-360.0, high=360.0, default=0.0, unit="deg", doc="propagation direction from x to y")
    coherency: str = choice(COHERENCY_MODELS, default="none", doc="lagged coherency model")
    seed: int = integer_parameter(low=0, high=2**32 - 1, default=0, doc="random phases of the incoherent part")
    hv_a: float = parameter(low=0.0, high=1.0, default=0.736, doc="Harichandran-Vanmarcke A")
    hv_alpha: float = parameter(low=0.0, high=1.0, low_open=True, default=0.147, doc="Harichandran-Vanmarcke alpha")
    hv_k: float = parameter(low=0.0, low_open=True, default=5210.0, unit="m", doc="Harichandran-Vanmarcke k")
    hv_f0: float = parameter(low=0.0, low_open=True, default=1.09, unit="Hz", doc="Harichandran-Vanmarcke f0")
    hv_b: float = parameter(low=0.0, low_open=True, default=2.78, doc="Harichandran-Vanmarcke b")
    lw_a: float = parameter(low=0.0, high=1e-2, default=2.5e-4, unit="s/m", doc="Luco-Wong alpha / v_s")
    amplitude_iterations: int = integer_parameter(low=0, high=20, default=5,
                                                  doc="response-spectrum ratio passes (frequency domain)")
    wavelet_iterations: int = integer_parameter(low=0, high=100, default=25,
                                                doc="response-spectrum wavelet passes (time domain)")

    def to_dict(self) -> dict:
        """The fields, plus, with a coherency model, the version of the spectral matching (what the experiment's
        digest takes: cells generated by an older matching are computed again)."""
        data = attrs.asdict(self)
        if self.coherency != "none":
            data["matching"] = MATCHING_VERSION
        return data


def coherency(variation: SpatialVariation, distance, frequency) -> np.ndarray:
    """``|gamma|`` of ``variation``'s model at plan ``distance`` (m) and ``frequency`` (Hz), broadcast."""
    xi = np.abs(np.asarray(distance, dtype=float))
    f = np.abs(np.asarray(frequency, dtype=float))
    if variation.coherency == "none":
        return np.ones(np.broadcast_shapes(xi.shape, f.shape))
    if variation.coherency == "luco-wong":
        return np.exp(-((variation.lw_a * 2.0 * math.pi * f * xi) ** 2))
    a, alpha = variation.hv_a, variation.hv_alpha
    theta = variation.hv_k / np.sqrt(1.0 + (f / variation.hv_f0) ** variation.hv_b)
    c = 2.0 * xi * (1.0 - a + alpha * a)
    return a * np.exp(-c / (alpha * theta)) + (1.0 - a) * np.exp(-c / theta)


def _positions(positions) -> tuple[list[str], np.ndarray]:
    if not isinstance(positions, Mapping) or not positions:
        raise ParameterError("spatial_motions: 'positions' must be a non-empty mapping {group: (x, y[, z])} in m")
    names = list(positions)
    try:
        xy = np.array([np.asarray(positions[n], dtype=float).reshape(-1)[:2] for n in names])
    except (TypeError, ValueError):
        raise ParameterError("spatial_motions: 'positions' must give numbers (x, y[, z]) in m per group") from None
    if xy.shape != (len(names), 2) or not np.all(np.isfinite(xy)):
        raise ParameterError("spatial_motions: 'positions' must give finite (x, y[, z]) in m per group")
    return names, xy


def delays(positions, variation: SpatialVariation) -> dict[str, float]:
    """The wave-passage delay (s) of every group: 0 at the first reached, none without ``apparent_velocity``."""
    names, xy = _positions(positions)
    if variation.apparent_velocity is None:
        return dict.fromkeys(names, 0.0)
    angle = math.radians(variation.azimuth)
    along = xy @ np.array([math.cos(angle), math.sin(angle)])
    tau = (along - along.min()) / variation.apparent_velocity
    return {n: float(t) for n, t in zip(names, tau, strict=True)}


def _padded(n: int, extra: int) -> int:
    size = 2 * n + extra
    return 1 << (size - 1).bit_length()


def delayed(acceleration: np.ndarray, dt: float, tau: float, n_out: int | None = None) -> np.ndarray:
    """``acceleration`` (n, ...) delayed by ``tau`` s (fractional: in the frequency domain), ``n_out`` samples."""
    a = np.asarray(acceleration, dtype=float)
    n = a.shape[0]
    n_out = n + int(math.ceil(tau / dt)) if n_out is None else n_out
    size = _padded(max(n, n_out), int(math.ceil(tau / dt)))
    spectrum = np.fft.rfft(a, size, axis=0)
    f = np.fft.rfftfreq(size, dt)
    shift = np.exp(-2j * math.pi * f * tau).reshape((-1,) + (1,) * (a.ndim - 1))
    return np.fft.irfft(spectrum * shift, size, axis=0)[:n_out]


def _cholesky(matrix: np.ndarray) -> np.ndarray:
    """Lower factor of a coherency matrix (clipping round-off negative eigenvalues if needed)."""
    try:
        return np.linalg.cholesky(matrix)
    except np.linalg.LinAlgError:
        values, vectors = np.linalg.eigh(matrix)
        fixed = (vectors * np.clip(values, 1e-12, None)) @ vectors.T
        d = np.sqrt(np.diag(fixed))
        return np.linalg.cholesky(fixed / np.outer(d, d) + 1e-12 * np.eye(len(d)))


def _cholesky_stack(matrices: np.ndarray) -> np.ndarray:
    """:func:`_cholesky` of each of ``matrices`` (nf, g, g): one batched factorisation; only where it
    fails (a coherency of one makes the matrix singular) the clipped one, matrix by matrix."""
    try:
        return np.linalg.cholesky(matrices)
    except np.linalg.LinAlgError:
        pass
    # numpy refuses the whole stack if one matrix fails: then each alone, with the clipped fallback
    L = np.empty_like(matrices)
    for i in range(matrices.shape[0]):
        L[i] = _cholesky(matrices[i])
    return L


def _envelope(a: np.ndarray, dt: float, size: int, window: float = 1.0) -> np.ndarray:
    """(size, components): the record's moving RMS over ``window`` s, scaled so that a stationary
    signal of the record's mean square over ``size`` samples keeps its energy when multiplied by it."""
    n = a.shape[0]
    w = max(1, int(round(window / dt)))
    kernel = np.ones(w) / w
    mean_square = np.column_stack([np.convolve(a[:, c] ** 2, kernel, mode="same") for c in range(a.shape[1])])
    padded = np.zeros((size, a.shape[1]))
    padded[:n] = mean_square
    level = np.sum(a**2, axis=0) / size
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(level > 0, np.sqrt(padded / np.where(level > 0, level, 1.0)), 0.0)


#: Oscillators (Hz) of the ratio passes: their spectral accelerations set the smooth correction factor.
MATCH_FREQUENCIES = np.geomspace(0.2, 20.0, 200)
#: Oscillators (Hz) of the wavelet passes (those below 0.4 / dt), 1.5 % apart (module docstring: why that
#: spacing), their damping ratio and the relative misfit at which an oscillator is left alone.
WAVELET_FREQUENCIES = np.geomspace(0.4, 12.0, 229)
WAVELET_DAMPING = 0.05
WAVELET_TOLERANCE = 0.03
_WAVELET_PERIODS = 6.0  # the Gaussian's standard deviation, in periods
_WAVELET_PEAKS = 3  # peaks brought down per oscillator and pass
_WAVELET_RELAXATION = 0.5  # the share of the computed correction each pass applies
_DECAY = 30.0  # s of zeros after a signal in its FFT: the slowest oscillator's response decays to 2 % over them


def _substeps(frequencies: np.ndarray, dt: float) -> np.ndarray:
    """Sub-steps per sample of each oscillator, as :func:`~bearingfw.motion.metrics.response_spectrum` takes them."""
    return np.maximum(1, np.ceil(SUBSTEPS_PER_PERIOD * dt * frequencies - 1e-9)).astype(int)


class _Oscillators:
    """Oscillators at ``frequencies`` (Hz, damping ``zeta``) evaluated together on signals sampled every ``dt``,
    exactly as :func:`~bearingfw.motion.metrics.response_spectrum` defines their response: the signal linear
    between samples, the exact recursion on ``m`` sub-steps per sample, the peak over the sub-steps.

    That recursion is a linear filter, so it is evaluated in the frequency domain, all oscillators of one
    ``m`` at once (one batched inverse FFT instead of one ``lfilter`` per oscillator): on ``size * m``
    sub-steps, the signal's spectrum repeated ``m`` times (zeros between the samples) times the linear
    interpolation's kernel (a triangle of base ``2 m`` sub-steps: ``sin^2(m theta / 2) / (m sin^2(theta / 2))``)
    times the recursion's transfer function ``B(z) / A(z)``. The FFT is circular: ``size`` leaves
    :data:`_DECAY` s of zeros after the signal, so what wraps round is the response a 0.4 Hz oscillator
    still has 30 s after the signal's end (2 % of what it had at the end). Measured against
    ``response_spectrum`` at the wavelet passes' oscillators: peaks within 2e-4 (Manjil) and 2e-3
    (Chuetsu), 2e-7 with a long padding (single precision)."""

    def __init__(self, frequencies: np.ndarray, dt: float, size: int, zeta: float = WAVELET_DAMPING):
        self.frequencies = np.asarray(frequencies, dtype=float)
        self.omega = 2.0 * math.pi * self.frequencies
        self.dt, self.size = dt, size
        self.substeps = _substeps(self.frequencies, dt)
        self.groups = []  # (oscillators, m, gain (oscillators, bins), folded bin, conjugated)
        for m in np.unique(self.substeps):
            rows = np.flatnonzero(self.substeps == m)
            b, den = _oscillator_filters(self.omega[rows], zeta, np.full(rows.size, dt / m))
            bins = np.arange(size * m // 2 + 1)
            theta = 2.0 * math.pi * bins / (size * m)
            z = np.exp(-1j * theta)[None, :]
            gain = (b[:, :1] + b[:, 1:2] * z + b[:, 2:] * z**2) / (den[:, :1] + den[:, 1:2] * z + den[:, 2:] * z**2)
            if m > 1:
                half = np.sin(theta / 2.0)
                with np.errstate(divide="ignore", invalid="ignore"):
                    gain = gain * np.where(half == 0.0, m, np.sin(m * theta / 2.0) ** 2 / (m * half**2))
            # omega^2 u for the load -a: the pseudo-acceleration's history
            gain = (-(self.omega[rows] ** 2)[:, None] * gain).astype(np.complex64)
            fold = bins % size
            conjugated = fold > size // 2
            self.groups.append((rows, int(m), gain, np.where(conjugated, size - fold, fold), conjugated))
        #: oscillator -> (its group, its row there, its sub-steps per sample)
        self.where = {int(r): (g, k, group[1]) for g, group in enumerate(self.groups) for k, r in enumerate(group[0])}

    def histories(self, x: np.ndarray, n_keep: int) -> list[np.ndarray]:
        """Per group of :attr:`groups`: ``omega^2 u`` (signals, oscillators, sub-steps) over ``x`` (signals, n)'s
        first ``n_keep`` samples."""
        X = sp_fft.rfft(np.asarray(x, dtype=np.float32), self.size, axis=-1)
        out = []
        for _, m, gain, fold, conjugated in self.groups:
            Y = X if m == 1 else np.where(conjugated, np.conj(X[:, fold]), X[:, fold])
            out.append(sp_fft.irfft(Y[:, None, :] * gain, self.size * m, axis=-1)[..., : (n_keep - 1) * m + 1])
        return out

    def peaks(self, histories: list[np.ndarray]) -> np.ndarray:
        """(signals, oscillators) pseudo-accelerations from :meth:`histories`."""
        out = np.empty((histories[0].shape[0], self.frequencies.size))
        for (rows, *_), u in zip(self.groups, histories, strict=True):
            out[:, rows] = np.max(np.abs(u), axis=-1)
        return out

    def psa(self, x: np.ndarray, n_keep: int) -> np.ndarray:
        """(signals, oscillators) pseudo-spectral accelerations of ``x`` (signals, n), peaks over its first
        ``n_keep`` samples."""
        return self.peaks(self.histories(x, n_keep))


def _ratio_matched(x: np.ndarray, target: np.ndarray, bank: _Oscillators, iterations: int) -> np.ndarray:
    """``x`` (signals, n) rescaled by a factor smooth in frequency towards the pseudo-accelerations ``target``
    (signals, oscillators of ``bank``): ``iterations`` passes of the classical ratio correction, interpolated in
    log frequency (constant outside the bank), phases kept."""
    n = x.shape[1]
    f = np.fft.rfftfreq(bank.size, bank.dt)
    logf = np.log(bank.frequencies)
    inside = np.log(np.clip(f, bank.frequencies[0], bank.frequencies[-1]))
    for _ in range(iterations):
        own = bank.psa(x, n)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(own > 0, target / own, 1.0)
        factor = np.vstack([np.interp(inside, logf, r) for r in ratio])
        x = np.fft.irfft(np.fft.rfft(x, bank.size, axis=-1) * factor, bank.size, axis=-1)[:, :n]
    return x


def _wavelet(t, omega, centre, width):
    return np.cos(omega * (t - centre)) * np.exp(-0.5 * ((t - centre) / width) ** 2)


def _wavelet_lags(bank: _Oscillators) -> np.ndarray:
    """Per oscillator, the time (s) from the centre of its own wavelet to the peak of its response to it."""
    dt, m = bank.dt, bank.substeps
    from scipy import signal  # here, not at the top: its import costs a second of CPU in every process

    b, den = _oscillator_filters(bank.omega, WAVELET_DAMPING, dt / m)
    width = _WAVELET_PERIODS / bank.frequencies
    lag = np.empty(bank.frequencies.size)
    for i, f in enumerate(bank.frequencies):
        centre = 4.0 * width[i]
        fine = np.arange(int((2.0 * centre + 10.0 / f) / dt) * m[i] + 1) * dt / m[i]
        u = signal.lfilter(b[i], den[i], -_wavelet(fine, bank.omega[i], centre, width[i]))
        lag[i] = np.argmax(np.abs(u)) * dt / m[i] - centre
    return lag


def _wavelet_step(u: list[np.ndarray], misfit: np.ndarray, target: np.ndarray, bank: _Oscillators,
                  lag: np.ndarray, n: int, tolerance: float) -> np.ndarray:
    """One signal's correction (n,): wavelets on every oscillator out of ``tolerance`` (module docstring)."""
    from scipy import signal  # here, not at the top: its import costs a second of CPU in every process

    dt = bank.dt
    which, at, change, carries = [], [], [], []  # per row: oscillator, time of a peak, its wanted change, a wavelet?
    for i in np.flatnonzero(np.abs(misfit) > tolerance):
        g, k, m = bank.where[int(i)]
        history = u[g][k]
        a = np.abs(history)
        if misfit[i] > 0:  # every peak above the target comes down to it
            peaks = signal.find_peaks(a)[0]
            peaks = peaks[a[peaks] > target[i] * (1.0 + tolerance / 2.0)]
            peaks = peaks[np.argsort(-a[peaks])][:_WAVELET_PEAKS]
            if peaks.size == 0:
                peaks = np.array([int(np.argmax(a))])
        else:
            peaks = np.array([int(np.argmax(a))])
        # peaks closer than the wavelet's width share one wavelet (two would be nearly the same function)
        separation = _WAVELET_PERIODS / bank.frequencies[i]
        placed: list[float] = []
        for p in peaks:
            which.append(int(i))
            at.append(p * dt / m)
            change.append((target[i] - a[p]) * math.copysign(1.0, history[p]))
            carries.append(all(abs(at[-1] - s) >= separation for s in placed))
            if carries[-1]:
                placed.append(at[-1])
    which, at, change = np.array(which), np.array(at), np.array(change)
    q = np.flatnonzero(carries)
    wavelets = q.size
    omega = bank.omega[which]
    width = _WAVELET_PERIODS / bank.frequencies[which]
    centre = at - lag[which]
    # C[r, q]: the response of oscillator which[r] at time at[r] to wavelet q (closed form), where it matters:
    # an oscillator more than a factor 2 in frequency from a wavelet responds to it by a few per cent of its own
    # wavelet's effect, and not at all more than 5 widths before the wavelet
    C = np.zeros((which.size, wavelets))
    near = (np.abs(np.log(omega[:, None] / omega[None, q])) < math.log(2.0)) & (
        at[:, None] > centre[None, q] - 5.0 * width[None, q])
    r, k = np.nonzero(near)
    C[r, k] = _wavelet_response(omega[r], at[r], omega[q[k]], centre[q[k]], width[q[k]])
    # neighbouring oscillators' peaks at one time make C nearly singular: a Tikhonov-regularised solution, the
    # ridge 1e-4 times the largest column's square (about what lstsq's rcond = 1e-2 would cut, far cheaper)
    normal = C.T @ C
    ridge = 1e-4 * float(np.max(np.diag(normal)))
    amplitude = np.linalg.solve(normal + ridge * np.eye(wavelets), C.T @ change)
    step = np.zeros(n)
    start = np.clip(np.floor((centre - 5.0 * width) / dt).astype(int), 0, n)  # the Gaussian's +-5 widths
    stop = np.clip(np.ceil((centre + 5.0 * width) / dt).astype(int) + 1, 0, n)
    for k, j in enumerate(q):
        t = np.arange(start[j], stop[j]) * dt
        step[start[j]:stop[j]] += amplitude[k] * _wavelet(t, omega[j], centre[j], width[j])
    return step


def _wavelet_response(omega, t, wavelet_omega, centre, width, zeta=WAVELET_DAMPING):
    """``omega^2 u(t)`` of the oscillator ``u'' + 2 zeta omega u' + omega^2 u = -w(t)``, at rest at first, under
    the wavelet ``w = cos(Omega (t - c)) exp(-((t - c) / s)^2 / 2)`` (``Omega`` = ``wavelet_omega``, ``c`` =
    ``centre``, ``s`` = ``width``); arrays broadcast. Closed form: with the impulse response
    ``Im(exp(lambda t)) / omega_d``, ``lambda = -zeta omega + i omega_d``, each half ``exp(+-i Omega t) / 2`` of
    the cosine gives a Gaussian integral up to ``t``, an ``erfc`` of complex argument, written with the
    Faddeeva function ``wofz`` so that nothing overflows (the branch on the sign of its argument keeps it in
    the half-plane where ``wofz`` is bounded)."""
    wd = omega * math.sqrt(1.0 - zeta**2)
    lam = -zeta * omega + 1j * wd
    T = t - centre
    total = 0.0
    for mu in (1j * wavelet_omega, -1j * wavelet_omega):
        kappa = mu - lam
        z = (kappa * width**2 - T) / (width * math.sqrt(2.0))
        base = np.exp(mu * T - 0.5 * (T / width) ** 2)
        before = z.real >= 0.0  # the wavelet's bulk still ahead of t: exp(...) erfc(z) directly
        with np.errstate(over="ignore", invalid="ignore"):
            ahead = base * special.wofz(1j * z)
            # erfc(z) = 2 - erfc(-z): the free vibration after the wavelet minus what is still to come
            behind = 2.0 * np.exp(lam * T + 0.5 * (kappa * width) ** 2) - base * special.wofz(-1j * z)
        total = total + np.where(before, ahead, behind)
    return -(omega**2) / wd * np.imag(0.5 * width * math.sqrt(0.5 * math.pi) * total)


def _wavelet_matched(x: np.ndarray, target: np.ndarray, bank: _Oscillators, iterations: int,
                     tolerance: float = WAVELET_TOLERANCE) -> np.ndarray:
    """``x`` (signals, n) plus wavelets until each signal's pseudo-accelerations at ``bank``'s oscillators are
    ``target`` (signals, oscillators) within ``tolerance`` (module docstring, step 2): per signal, the best of
    at most ``iterations`` passes. The signals are evaluated together (one batched FFT per pass)."""
    x = np.array(x, dtype=float)
    n = x.shape[1]
    lag = _wavelet_lags(bank)
    u = bank.histories(x, n)
    misfit = bank.peaks(u) / target - 1.0
    worst = np.max(np.abs(misfit), axis=1)
    best, best_worst = x.copy(), worst.copy()
    for _ in range(iterations):
        active = np.flatnonzero(worst > tolerance)
        if active.size == 0:
            break
        # every pass is taken, even one that raises the worst misfit a little: a rule that refuses such steps
        # (on the worst or on the summed excess) stalls where neighbouring oscillators want opposite changes,
        # while half steps taken anyway keep moving; the best motion seen is what is returned
        for s in active:
            step = _wavelet_step([h[s] for h in u], misfit[s], target[s], bank, lag, n, tolerance)
            x[s] += _WAVELET_RELAXATION * step
        trial = bank.histories(x[active], n)
        for h, th in zip(u, trial, strict=True):
            h[active] = th
        misfit[active] = bank.peaks(trial) / target[active] - 1.0
        worst[active] = np.max(np.abs(misfit[active]), axis=1)
        improved = active[worst[active] < best_worst[active]]
        best[improved], best_worst[improved] = x[improved], worst[improved]
    return best


def spatial_motions(acceleration, dt: float, positions, variation: SpatialVariation) -> dict[str, np.ndarray]:
    """One acceleration (n_out, components) per group of ``positions`` from the record ``acceleration``
    (n, components), m/s^2, sampled every ``dt`` (module docstring). ``n_out`` is ``n`` plus the
    largest wave-passage delay in samples; the first-reached group keeps the record (zero-padded)."""
    if not isinstance(variation, SpatialVariation):
        raise ParameterError(f"spatial_motions: 'variation' must be a SpatialVariation, got {type(variation).__name__}")
    a = np.asarray(acceleration, dtype=float)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2 or a.shape[0] < 2 or not np.all(np.isfinite(a)):
        raise ParameterError(
            f"spatial_motions: 'acceleration' must be a finite (steps, components) array with steps >= 2, got {a.shape}"
        )
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
        raise ParameterError(f"spatial_motions: 'dt' = {dt!r} must be a time step > 0 s")
    names, xy = _positions(positions)
    tau = delays(positions, variation)
    n = a.shape[0]
    lag = int(math.ceil(max(tau.values()) / dt))
    n_out = n + lag
    size = _padded(n_out, lag)
    f = np.fft.rfftfreq(size, dt)
    X1 = np.fft.rfft(a, size, axis=0)  # (nf, components)
    first = min(names, key=lambda k: (tau[k], names.index(k)))
    order = [first] + [k for k in names if k != first]
    X = dict.fromkeys(names, X1)  # fully coherent unless a model says otherwise
    if variation.coherency != "none" and len(names) > 1:
        idx = [names.index(k) for k in order]
        P = xy[idx]
        distance = np.linalg.norm(P[:, None, :] - P[None, :, :], axis=-1)
        gamma = coherency(variation, distance[None, :, :], f[:, None, None])  # (nf, g, g)
        rng = np.random.default_rng(variation.seed)
        g = len(order)
        L = _cholesky_stack(gamma)
        amplitude = np.abs(X1)
        envelope = _envelope(a, dt, size)
        sources = []  # independent motions with the record's Fourier amplitude and (roughly) its envelope
        for _ in range(g - 1):
            noise = np.fft.irfft(amplitude * np.exp(2j * math.pi * rng.random(X1.shape)), size, axis=0) * envelope
            Z = np.fft.rfft(noise, size, axis=0)
            with np.errstate(divide="ignore", invalid="ignore"):
                sources.append(np.where(np.abs(Z) > 0, amplitude * Z / np.abs(Z), 0.0))
        for j in range(1, g):
            Xj = L[:, j, 0][:, None] * X1
            for k in range(1, j + 1):
                Xj = Xj + L[:, j, k][:, None] * sources[k - 1]
            X[order[j]] = Xj
    out = {}
    for name in names:
        shift = np.exp(-2j * math.pi * f * tau[name])[:, None]
        out[name] = np.fft.irfft(X[name] * shift, size, axis=0)[:n_out]
    generated = order[1:] if variation.coherency != "none" else []
    if generated and (variation.amplitude_iterations or variation.wavelet_iterations):
        # matched after the delay: a fractional delay alone moves a sampled peak by up to 1 - cos(pi f dt)
        x = np.concatenate([out[name].T for name in generated])  # (supports x components, n_out)
        components = a.shape[1]
        matched = _spectrum_matched(x, a.T, dt, variation)
        for k, name in enumerate(generated):
            out[name] = matched[k * components:(k + 1) * components].T.copy()
    return out


def _spectrum_matched(x: np.ndarray, record: np.ndarray, dt: float, variation: SpatialVariation) -> np.ndarray:
    """``x`` (supports x components, n_out) with the 5 %-damped response spectra of ``record``'s components
    (components, n), support after support: the ratio passes, then the wavelet passes (module docstring).
    A component without motion (a zero spectrum: nothing to match) is left as it is."""
    n, repeats = record.shape[1], x.shape[0] // record.shape[0]
    size = sp_fft.next_fast_len(x.shape[1] + int(math.ceil(_DECAY / dt)), real=True)
    x = np.array(x)
    passes = ((MATCH_FREQUENCIES[MATCH_FREQUENCIES < 0.5 / dt], variation.amplitude_iterations, _ratio_matched),
              (WAVELET_FREQUENCIES[WAVELET_FREQUENCIES < 0.4 / dt], variation.wavelet_iterations, _wavelet_matched))
    for frequencies, iterations, matched in passes:
        if not iterations or frequencies.size == 0:
            continue
        bank = _Oscillators(frequencies, dt, size)
        target = np.tile(bank.psa(record, n), (repeats, 1))
        moving = np.flatnonzero(np.all(target > 0.0, axis=1))
        if moving.size:
            x[moving] = matched(x[moving], target[moving], bank, iterations)
    return x
