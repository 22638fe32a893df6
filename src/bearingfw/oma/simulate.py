"""Simulated ambient vibration tests of a linear model: plan the sensors, check the method.

The model's response to broadband excitation is built by modal superposition, mode by mode
exactly: each retained mode ``j`` (natural circular frequency ``w_j``, damping ratio ``z_j``,
mass-normalised shape ``phi_j``) obeys ``q'' + 2 z w q' + w^2 q = u_j(t)`` with the modal load

    u_j = - sum_d Gamma_jd a_g,d(t) + sum_k phi_j(k) f_k(t)

(``Gamma_jd = phi_j^T M r_d``: support acceleration ``a_g,d`` in direction ``d``, the same at
every support, as in the transient analysis; ``f_k``: forces at DOFs ``k``, e.g. traffic on the
deck). The inputs are sampled white noise held constant over each step (zero-order hold), and
for that input the sampled response is exact: the discrete transfer function of each mode comes
from the matrix exponential of its 2 x 2 state matrix (:func:`modal_filters`) and is applied by
``scipy.signal.lfilter``. No time-stepping error, so an identification is checked against the
model itself, not against an integrator's period elongation (HHT with alpha = -0.05 and
dt = 0.02 s lengthens the period of a 14 Hz mode by 24 %: its frequency comes out 19 % low; a
test checks this module against the transient solver run at a fine step instead).

Sensors measure absolute acceleration: ``a = sum_j phi_j(s) q_j'' + r(s) a_g``. Modes above the
Nyquist frequency are left out (an ideal anti-alias filter on the structural response); with
them every retained mode's quasi-static part of ``r a_g`` stays in the ``r a_g`` term, so a
sensor over a support reads the ground. Measurement noise is white, ``noise`` times each
channel's RMS.

The damping of each mode is given: one ratio for all, one per mode, or the model's Rayleigh
damping as the transient analysis applies it, ``C = alpha M + beta K_free``
(:func:`modal_damping`; ``K_free`` leaves out the bearing laws, so a mode stiffened by bearing
springs gets less than ``Rayleigh.ratio(f)``). Neglecting the coupling of modes through a
non-proportional ``C`` is the one approximation; at a few per cent damping it is small.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import scipy.linalg as sla
from scipy import signal

from bearingfw.analysis import ModalResult, Rayleigh
from bearingfw.oma.io import Channels, channel_dofs, parse_channel
from bearingfw.parameters import ParameterError

__all__ = ["modal_damping", "modal_filters", "modal_response", "simulate_ambient"]

_DIRECTIONS = ("x", "y", "z")


def modal_filters(omega: np.ndarray, zeta: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Discrete transfer functions ``(b, a)``, each (modes, 3), from a held modal load to the modal acceleration.

    Exact zero-order-hold discretisation of ``x' = F x + g u``, ``q'' = h x + u`` with
    ``x = (q, q')``, ``F = [[0, 1], [-w^2, -2 z w]]``, ``g = (0, 1)``, ``h = (-w^2, -2 z w)``:
    ``F_d = exp(F dt)``, ``g_d = F^-1 (F_d - I) g``, and
    ``H(z) = h (z I - F_d)^-1 g_d + 1 = b(z) / a(z)`` with ``a = z^2 - tr(F_d) z + det(F_d)``.
    """
    omega = np.asarray(omega, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    b = np.empty((omega.size, 3))
    a = np.empty((omega.size, 3))
    for j, (w, z) in enumerate(zip(omega, zeta, strict=True)):
        F = np.array([[0.0, 1.0], [-w * w, -2.0 * z * w]])
        Fd = sla.expm(F * dt)
        gd = np.linalg.solve(F, (Fd - np.eye(2)) @ np.array([0.0, 1.0]))
        h = F[1]
        trace, det = np.trace(Fd), np.linalg.det(Fd)
        adjugate = np.array([[-Fd[1, 1], Fd[0, 1]], [Fd[1, 0], -Fd[0, 0]]])  # adj(z I - Fd) = z I + this
        a[j] = (1.0, -trace, det)
        b[j] = (1.0, h @ gd - trace, h @ adjugate @ gd + det)
    return b, a


def modal_response(omega, zeta, loads: np.ndarray, dt: float) -> np.ndarray:
    """Modal accelerations ``q''`` (samples, modes) under held modal ``loads`` (samples, modes), from rest."""
    loads = np.asarray(loads, dtype=float)
    b, a = modal_filters(omega, zeta, dt)
    return np.column_stack([signal.lfilter(b[j], a[j], loads[:, j]) for j in range(loads.shape[1])])


def modal_damping(modal: ModalResult, rayleigh: Rayleigh) -> np.ndarray:
    """Each mode's ratio ``phi^T C phi / (2 w)`` with ``C = alpha M + beta K_free`` (module docstring)."""
    system = modal.system
    phi = modal.shapes_free
    stiffness = np.einsum("ij,ij->j", phi, system.K_free @ phi)
    mass = np.einsum("ij,ij->j", phi, system.M_free @ phi)
    omega = np.where(modal.omega > 0, modal.omega, np.inf)
    return (rayleigh.alpha * mass + rayleigh.beta * stiffness) / (2.0 * omega)


def _ratios(modal: ModalResult, damping) -> np.ndarray:
    if isinstance(damping, Rayleigh):
        return modal_damping(modal, damping)
    ratios = np.broadcast_to(np.asarray(damping, dtype=float), (modal.n_modes,)).copy()
    if not np.all((ratios > 0) & (ratios < 1)):
        raise ParameterError(f"simulate_ambient: damping ratios must be in 0 < zeta < 1, got {damping!r}")
    return ratios


def simulate_ambient(
    modal: ModalResult,
    channels: Sequence[str],
    duration: float,
    dt: float,
    *,
    damping=0.02,
    ground: Sequence[float] = (0.01, 0.01, 0.01),
    loads: Mapping[str, float] | None = None,
    noise: float = 0.05,
    seed: int = 0,
    ground_acceleration: np.ndarray | None = None,
) -> Channels:
    """Absolute accelerations at ``channels`` (``"<node>.<component>"``) under white-noise excitation.

    ``ground``: RMS (m/s^2) of the support acceleration in x, y, z; ``loads``: RMS force (N) at
    DOFs named like channels (``{"GA20.uz": 1e3}``), independent of each other. ``damping``: a
    ratio, one per computed mode, or a :class:`~bearingfw.analysis.Rayleigh` (:func:`modal_damping`).
    Modes of ``modal`` up to the Nyquist frequency ``0.5 / dt`` are superposed (compute enough of
    them). ``noise`` is the measurement noise's RMS relative to each channel's. Seeded.
    ``ground_acceleration``: the support acceleration itself, (samples, 3) held over each step,
    instead of the white noise of RMS ``ground`` (e.g. to run the same input through another solver).
    """
    if not (dt > 0 and duration > 2 * dt):
        raise ParameterError(
            f"simulate_ambient: need dt > 0 and duration > 2 dt, got dt = {dt!r}, duration = {duration!r}"
        )
    if len(ground) != 3 or any(g < 0 for g in ground):
        raise ParameterError(f"simulate_ambient: 'ground' must be three RMS values >= 0 (x, y, z), got {ground!r}")
    if not 0 <= noise < 10:
        raise ParameterError(f"simulate_ambient: 'noise' = {noise!r} must be in 0 <= noise < 10")
    loads = dict(loads or {})
    ratios = _ratios(modal, damping)
    kept = np.flatnonzero((modal.frequencies > 0) & (modal.frequencies < 0.5 / dt))
    if kept.size == 0:
        raise ParameterError("simulate_ambient: no computed mode lies below the Nyquist frequency")
    sensors = channel_dofs(modal.system, channels)
    at = channel_dofs(modal.system, list(loads))
    n = int(round(duration / dt)) + 1
    rng = np.random.default_rng(seed)
    ground_acc = rng.standard_normal((n, 3)) * np.asarray(ground, dtype=float)
    if ground_acceleration is not None:
        ground_acc = np.asarray(ground_acceleration, dtype=float)
        if ground_acc.shape != (n, 3) or not np.all(np.isfinite(ground_acc)):
            raise ParameterError(
                f"simulate_ambient: 'ground_acceleration' must be finite, shape ({n}, 3) for duration = {duration:g} s "
                f"at dt = {dt:g} s, got shape {ground_acc.shape}"
            )
    forces = rng.standard_normal((n, len(loads))) * np.array(list(loads.values()), dtype=float)
    gamma = np.column_stack([modal.participation[d][kept] for d in _DIRECTIONS])  # (modes, 3)
    modal_loads = -ground_acc @ gamma.T + forces @ modal.shapes[np.ix_(at, kept)]
    accel = modal_response(modal.omega[kept], ratios[kept], modal_loads, dt)
    rigid = np.array([[float(parse_channel(c)[1] == f"u{d}") for d in _DIRECTIONS] for c in channels])
    data = accel @ modal.shapes[np.ix_(sensors, kept)].T + ground_acc @ rigid.T
    data = data + noise * data.std(axis=0) * rng.standard_normal(data.shape)
    meta = {
        "seed": seed,
        "ground_rms": list(map(float, ground)) if ground_acceleration is None else "given",
        "loads_rms": {k: float(v) for k, v in loads.items()},
        "noise": noise,
        "modes": int(kept.size),
        "frequencies": modal.frequencies[kept].tolist(),
        "damping": ratios[kept].tolist(),
    }
    model = modal.system.model.name or "model"
    return Channels(data, dt, tuple(channels), "m/s^2", f"SYNTHETIC ambient vibration of {model}", True, meta)
