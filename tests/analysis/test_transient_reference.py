"""Two masses on elastic-perfectly-plastic bearings, 10 s of random 3-component ground motion,
against an independent dense HHT solver written here.

Model: ``m1`` on bearing ``c1`` over the ground, ``m2`` on ``c2`` over ``m1`` (AXIAL connectors
along x: x governed by regularized Coulomb, y tied, z a vertical spring). With ``N`` held
constant regularized Coulomb is an elastic-perfectly-plastic spring of yield force ``mu N``;
here the vertical ground motion makes ``N`` vary (about +-40 %), so the yield force follows the
vertical response every step, which the reference reproduces by solving the (linear, uncoupled)
vertical motion first and the horizontal one with that ``N``.

The reference knows nothing of bearingfw beyond the numbers: masses, stiffnesses, Rayleigh
coefficients (``C = a0 M + a1 K_lin``, ``K_lin`` the vertical springs only: the laws are not in
the stiffness-proportional part), HHT's three equations, and a closed-form EPP return map.
"""

from __future__ import annotations

import numpy as np
import pytest
from transient_models import G, band_limited_noise, connector_chain, rel_err

from bearingfw.analysis import ConnectorResponse, NodalResponse, Rayleigh, TransientSettings, gravity, solve_transient

M1, M2 = 3.0e4, 2.0e4
K1, K2 = 6.0e7, 3.0e7  # stick stiffnesses
MU1, MU2 = 0.05, 0.08
KV1, KV2 = 2.0e9, 1.5e9
DAMPING = Rayleigh(0.3, 0.002)
DT = 0.01
SECONDS = 10.0


def epp(k: float, mu: float, d: float, slip: float, N: float) -> tuple[float, float, float]:
    """Elastic-perfectly-plastic spring with yield force ``mu N``: (force, tangent, new slip)."""
    trial = k * (d - slip)
    limit = mu * max(N, 0.0)
    if abs(trial) > limit:
        force = np.copysign(limit, trial)
        return force, 0.0, d - force / k
    return trial, k, slip


def reference(ag: np.ndarray, dt: float, alpha: float, tol: float = 1e-12):
    """Dense HHT of the 4-DOF model (x1, x2 horizontal; z1, z2 vertical), relative to the ground.

    Returns x (steps, 2), z (steps, 2, total incl. the dead-load sag), F (steps, 2), N (steps, 2).
    """
    gamma, beta = 0.5 - alpha, (1 - alpha) ** 2 / 4
    c1 = 1 + alpha
    a0, a1 = DAMPING.alpha, DAMPING.beta
    m = np.diag([M1, M2])
    # vertical: linear springs kv1 (ground - m1), kv2 (m1 - m2); dynamic part from the dead-load state
    kz = np.array([[KV1 + KV2, -KV2], [-KV2, KV2]])
    cz, cx = a0 * m + a1 * kz, a0 * m
    z0 = np.array([-(M1 + M2) * G / KV1, -(M1 + M2) * G / KV1 - M2 * G / KV2])
    n = ag.shape[0]
    x, vx, ax = np.zeros((n, 2)), np.zeros(2), np.zeros(2)
    z, vz, az = np.zeros((n, 2)), np.zeros(2), np.zeros(2)
    F, N = np.zeros((n, 2)), np.zeros((n, 2))
    N[0] = [(M1 + M2) * G, M2 * G]
    slip = np.zeros(2)
    Az = m / (beta * dt**2) + c1 * gamma / (beta * dt) * cz + c1 * kz
    for i in range(n - 1):
        px0, px1 = -np.diag(m) * ag[i, 0], -np.diag(m) * ag[i + 1, 0]
        pz0, pz1 = -np.diag(m) * ag[i, 2], -np.diag(m) * ag[i + 1, 2]
        # vertical (linear)
        zt = z[i] + dt * vz + (0.5 - beta) * dt**2 * az
        vt = vz + (1 - gamma) * dt * az
        rhs = m @ zt / (beta * dt**2) + c1 * cz @ (gamma / (beta * dt) * zt - vt) + c1 * pz1
        rhs += alpha * (cz @ vz + kz @ z[i] - pz0)
        z[i + 1] = np.linalg.solve(Az, rhs)
        az = (z[i + 1] - zt) / (beta * dt**2)
        vz = vt + gamma * dt * az
        zt_total = z0 + z[i + 1]
        N[i + 1] = [-KV1 * zt_total[0], -KV2 * (zt_total[1] - zt_total[0])]
        # horizontal (EPP bearings), Newton on x
        xt = x[i] + dt * vx + (0.5 - beta) * dt**2 * ax
        vtx = vx + (1 - gamma) * dt * ax
        g_old = cx @ vx + np.array([F[i, 0] - F[i, 1], F[i, 1]]) - px0
        xi = x[i].copy()
        for _ in range(50):
            f1, k1, s1 = epp(K1, MU1, xi[0], slip[0], N[i + 1, 0])
            f2, k2, s2 = epp(K2, MU2, xi[1] - xi[0], slip[1], N[i + 1, 1])
            acc = (xi - xt) / (beta * dt**2)
            vel = vtx + gamma * dt * acc
            fint = np.array([f1 - f2, f2])
            R = m @ acc + c1 * (cx @ vel + fint - px1) - alpha * g_old
            kt = np.array([[k1 + k2, -k2], [-k2, k2]])
            J = m / (beta * dt**2) + c1 * gamma / (beta * dt) * cx + c1 * kt
            step = np.linalg.solve(J, -R)
            xi = xi + step
            if np.max(np.abs(step)) <= tol * max(np.max(np.abs(xi)), 1e-12):
                break
        else:
            raise AssertionError(f"reference Newton did not converge at step {i}")
        f1, _, s1 = epp(K1, MU1, xi[0], slip[0], N[i + 1, 0])
        f2, _, s2 = epp(K2, MU2, xi[1] - xi[0], slip[1], N[i + 1, 1])
        slip = np.array([s1, s2])
        ax = (xi - xt) / (beta * dt**2)
        vx = vtx + gamma * dt * ax
        x[i + 1], F[i + 1] = xi, (f1, f2)
    return x, z0 + z, F, N


@pytest.fixture(scope="module")
def problem():
    model = connector_chain(
        [M1, M2],
        [("regularized-coulomb", {"k": K1, "mu": MU1}), ("regularized-coulomb", {"k": K2, "mu": MU2})],
        [KV1, KV2],
    )
    ag = band_limited_noise(int(SECONDS / DT) + 1, DT, seed=2024, amplitude=[3.0, 1.0, 4.0])
    return model, gravity(model, g=G), ag


@pytest.mark.parametrize("alpha", [-0.05, 0.0])
@pytest.mark.parametrize("path", ["fast", "general"])
def test_two_masses_on_epp_bearings_match_the_dense_reference(problem, path, alpha):
    model, pre, ag = problem
    res = solve_transient(
        model, ag, DT, preload=pre, damping=DAMPING, settings=TransientSettings(alpha=alpha, path=path),
        recorders=[ConnectorResponse(), NodalResponse(["m1", "m2"], components=["ux", "uz"], total=True)],
    )
    x, z, F, N = reference(ag, DT, alpha)
    disp = res["displacement"]
    assert rel_err(disp[:, :, 0], x) < 1e-6
    assert rel_err(disp[:, :, 1], z) < 1e-6
    assert rel_err(res["connectors.force"][:, :, 0], F) < 1e-6
    assert rel_err(res["connectors.normal_force"], N) < 1e-6
    # the case is what it claims: both bearings yield, repeatedly, under a varying N
    ratio = res["connectors.friction_ratio"]
    for c, mu in enumerate((MU1, MU2)):
        assert np.mean(ratio[:, c] > (1 - 1e-9) * mu) > 0.1
        assert np.nanmax(ratio[:, c]) <= mu * (1 + 1e-9)
    assert np.ptp(N[:, 0]) > 0.5 * N[0, 0]
    assert res.energy_error < 0.01
