"""A 3-DOF chain with closed-form modes, its exact ambient response, and the reference bridge's ambient test.

The chain: three equal masses ``m`` on equal springs ``k``, fixed at the ground, free at the top.
``K = k [[2, -1, 0], [-1, 2, -1], [0, -1, 1]]`` has the eigenvalues ``k/m (2 - 2 cos((2j - 1) pi / 7))``,
``j = 1, 2, 3``, and the eigenvectors ``sin(i (2j - 1) pi / 7)`` at mass ``i``. Rayleigh damping
``C = alpha M + beta K`` is classical: mode ``j`` has ``zeta_j = alpha / (2 w_j) + beta w_j / 2``.

Its response to a white-noise ground acceleration is computed here with the *full* state-space
model, discretised exactly for an input held over each step (the matrix exponential of the
augmented ``[[A, B], [0, 0]] dt``), independently of :mod:`bearingfw.oma.simulate`'s modal
superposition.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from bearingfw.analysis import Rayleigh

MASS = 1000.0  # kg
STIFFNESS = 287.0 * MASS  # N/m: f = 1.20, 3.36, 4.86 Hz
CHANNELS = ("m1.ux", "m2.ux", "m3.ux")
RAYLEIGH = Rayleigh.from_ratios(1.2, 0.02, 4.86, 0.03)


def chain_matrices(rayleigh: Rayleigh = RAYLEIGH) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    M = MASS * np.eye(3)
    K = STIFFNESS * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return M, rayleigh.alpha * M + rayleigh.beta * K, K


def chain_modes(rayleigh: Rayleigh = RAYLEIGH) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closed form: frequencies (Hz), damping ratios, shapes (3, 3) one per column, lowest first."""
    j = np.arange(1, 4)
    omega = np.sqrt(STIFFNESS / MASS * (2 - 2 * np.cos((2 * j - 1) * np.pi / 7)))
    shapes = np.sin(np.outer(np.arange(1, 4), (2 * j - 1) * np.pi / 7))
    return omega / (2 * np.pi), rayleigh.alpha / (2 * omega) + rayleigh.beta * omega / 2, shapes


def state_space_response(M, C, K, ground: np.ndarray, dt: float) -> np.ndarray:
    """Absolute accelerations (samples, n) of ``M u'' + C u' + K u = -M 1 a_g`` under held ``ground`` samples."""
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    B = np.concatenate([np.zeros(n), -np.ones(n)])[:, None]
    augmented = np.zeros((2 * n + 1, 2 * n + 1))
    augmented[: 2 * n, : 2 * n] = A
    augmented[: 2 * n, 2 * n :] = B
    E = sla.expm(augmented * dt)
    Ad, Bd = E[: 2 * n, : 2 * n], E[: 2 * n, 2 * n]
    out = np.hstack([-Minv @ K, -Minv @ C])  # absolute acceleration: u'' + a_g = -M^-1 (C u' + K u)
    x = np.zeros(2 * n)
    states = np.empty((ground.size, 2 * n))
    for k, a in enumerate(ground):
        states[k] = x
        x = Ad @ x + Bd * a
    return states @ out.T


def chain_record(duration: float = 600.0, dt: float = 0.02, noise: float = 0.05, seed: int = 3):
    """The chain's ambient record as :class:`~bearingfw.oma.Channels` (5 % measurement noise)."""
    from bearingfw.oma import Channels

    rng = np.random.default_rng(seed)
    ground = 0.05 * rng.standard_normal(int(round(duration / dt)) + 1)
    y = state_space_response(*chain_matrices(), ground, dt)
    y = y + noise * y.std(axis=0) * rng.standard_normal(y.shape)
    return Channels(y, dt, CHANNELS, source="SYNTHETIC 3-DOF chain", synthetic=True)


# -- the reference bridge ----------------------------------------------------------------------

#: Ambient test of the bridge: 20 minutes at 40 Hz, sensors at the paper's P1..P7 (vertical and
#: transverse on both girders), excited as the issue asks by a white-noise support acceleration
#: alone, the same at every support (as the transient analysis applies a tremor), 0.01 m/s^2 RMS
#: in each direction, with 5 % measurement noise.
BRIDGE_DT = 0.025
BRIDGE_DURATION = 1200.0
BRIDGE_GROUND = (0.01, 0.01, 0.01)  # m/s^2 RMS
#: The band a user would choose from the averaged spectrum to hold the paper's three deck modes
#: (its peaks at 1.5-3.4 Hz) with margin, as the paper analysed 0-15 Hz; not taken from the model.
BRIDGE_FMAX = 5.0


# -- a small bearingfw model -------------------------------------------------------------------


def column_model(n: int = 6, height: float = 12.0, modulus: float = 210e9):
    """A steel cantilever column along z, clamped at ``C0``; bending in x stiffer than in y."""
    from bearingfw.model import FrameElement, Material, Model, Node, Section, Support

    steel = Material("steel", modulus, density=7850.0, nu=0.3)
    section = Section("column", A=0.02, Iy=4e-4, Iz=1e-4, J=2e-4)
    nodes = [Node(f"C{k}", 0.0, 0.0, height * k / n) for k in range(n + 1)]
    elements = [FrameElement(f"E{k}", f"C{k}", f"C{k + 1}", section, steel) for k in range(n)]
    return Model(nodes, elements, supports=[Support("C0")], name="column")


# -- a jumping test ----------------------------------------------------------------------------

JUMP_DT = 0.01
JUMP_STOP = 20.0  # the jumping stops
#: Three modes: the paper's two vertical ones with its measured damping, and a third.
JUMP_FREQUENCIES = np.array([1.50, 3.36, 5.0])
JUMP_RATIOS = np.array([0.021, 0.027, 0.02])


def jumping_test(seed: int = 0, duration: float = 120.0) -> np.ndarray:
    """People jump at 1.50 and (weaker) 3.36 Hz until JUMP_STOP; ambient loads all along; 5 % measurement noise.

    The modal accelerations of three unit-mass modes, summed (exact for held loads).
    """
    from bearingfw.oma.simulate import modal_response

    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration, JUMP_DT)
    on = t < JUMP_STOP
    loads = np.column_stack(
        [
            np.where(on, np.sin(2 * np.pi * 1.50 * t), 0.0),
            0.3 * np.where(on, np.sin(2 * np.pi * 3.36 * t), 0.0),
            0 * t,
        ]
    ) + 0.01 * rng.standard_normal((t.size, 3))
    y = modal_response(2 * np.pi * JUMP_FREQUENCIES, JUMP_RATIOS, loads, JUMP_DT).sum(axis=1)
    return y + 0.05 * y.std() * rng.standard_normal(y.size)


# -- records without modes ---------------------------------------------------------------------


def white_noise(channels: int, duration: float = 600.0, dt: float = 0.01, seed: int = 0):
    """Independent white noise on every channel: no structure, nothing to identify."""
    from bearingfw.oma import Channels

    y = np.random.default_rng(seed).standard_normal((int(round(duration / dt)), channels))
    return Channels(y, dt, tuple(f"N{k}.uz" for k in range(channels)), source="white noise")
