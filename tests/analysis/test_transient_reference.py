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
from kernel_models import (
    BLOCK_HALF_BASE,
    BLOCK_HEIGHT,
    BLOCK_INERTIA,
    BLOCK_MASS,
    G,
    band_limited_noise,
    connector_chain,
    rel_err,
    rocking_block,
)

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
    # energy: exact at alpha = 0; at alpha < 0 the imbalance is the scheme's numerical
    # dissipation (energy removed, not created, and little of it), and nothing else
    imbalance, top = res.energy["imbalance"], np.max(np.abs(res.energy["input"]))
    if alpha == 0:
        assert res.energy_error < 1e-8
    else:
        assert 0 < imbalance[-1] < 0.01 * top and np.min(imbalance) > -1e-4 * top
    assert res.balance_error < 1e-8


# ---- N coupled to the friction forces: a rigid block rocking on two friction bearings ----------
BLOCK_K, BLOCK_MU, BLOCK_KV = 1.0e8, 0.2, 1.0e9
BLOCK_DAMPING = Rayleigh(0.2, 0.0005)


def block_reference(ag: np.ndarray, dt: float, alpha: float, tol: float = 1e-13):
    """Dense HHT of the rigid block of :func:`transient_models.rocking_block` in its own
    coordinates ``q = (x, z, theta_y)`` of the centre of mass, relative to the ground and measured
    from the dead-load state.

    Bearing ``i`` sits at ``r_i = (x_i, 0, -e)`` from the centre of mass; a rotation ``theta``
    about y moves it by ``theta x r_i = (-e theta, 0, -x_i theta)``, so its relative displacement
    is ``J_i q`` with ``J_i = [[1, 0, -e], [0, 1, -x_i]]`` (x, z). Forces on the block: the friction
    law (EPP with yield force ``mu N_i``, ``N_i = -kv (z_0 + u_z,i)`` from the vertical spring, the
    block's dead-load sag ``z_0``) and the spring's dynamic force ``kv u_z,i``, both resisting:
    ``f_int = sum_i J_i^T (F_i, kv u_z,i)``. Newton uses the exact tangent, including
    ``dF_i / du_z,i = -mu kv sign(F_i)`` while sliding: the coupling the solver lags.
    """
    e, m, inertia = BLOCK_HEIGHT, BLOCK_MASS, BLOCK_INERTIA
    gamma, beta = 0.5 - alpha, (1 - alpha) ** 2 / 4
    c1 = 1 + alpha
    xs = (-BLOCK_HALF_BASE, BLOCK_HALF_BASE)
    J = [np.array([[1.0, 0.0, -e], [0.0, 1.0, -x]]) for x in xs]
    M = np.diag([m, m, inertia])
    K_lin = sum(Ji.T @ np.diag([0.0, BLOCK_KV]) @ Ji for Ji in J)  # the vertical springs (K_free)
    C = BLOCK_DAMPING.alpha * M + BLOCK_DAMPING.beta * K_lin
    z0 = -m * G / (2 * BLOCK_KV)

    def internal(q, slip):
        """(f_int, tangent, F, N, new slip)."""
        f, kt = np.zeros(3), np.zeros((3, 3))
        F, N, new = np.zeros(2), np.zeros(2), np.zeros(2)
        for i, Ji in enumerate(J):
            ux, uz = Ji @ q
            N[i] = -BLOCK_KV * (z0 + uz)
            trial = BLOCK_K * (ux - slip[i])
            limit = BLOCK_MU * max(N[i], 0.0)
            if abs(trial) > limit:  # sliding: F = mu N sign, d F / d uz = -mu kv sign (N > 0)
                F[i] = np.copysign(limit, trial)
                new[i] = ux - F[i] / BLOCK_K
                local = np.array([[0.0, -BLOCK_MU * BLOCK_KV * np.sign(trial) * (N[i] > 0)], [0.0, BLOCK_KV]])
            else:
                F[i], new[i] = trial, slip[i]
                local = np.array([[BLOCK_K, 0.0], [0.0, BLOCK_KV]])
            f += Ji.T @ np.array([F[i], BLOCK_KV * uz])
            kt += Ji.T @ local @ Ji
        return f, kt, F, N, new

    n = ag.shape[0]
    q, v, a = np.zeros((n, 3)), np.zeros(3), np.zeros(3)
    F, N = np.zeros((n, 2)), np.zeros((n, 2))
    N[0] = -BLOCK_KV * z0
    slip = np.zeros(2)
    load = lambda i: -m * np.array([ag[i, 0], ag[i, 2], 0.0])  # noqa: E731
    f_old = np.zeros(3)
    for i in range(n - 1):
        qt = q[i] + dt * v + (0.5 - beta) * dt**2 * a
        vt = v + (1 - gamma) * dt * a
        g_old = C @ v + f_old - load(i)
        qi = q[i].copy()
        for _ in range(100):
            f, kt, *_ = internal(qi, slip)
            acc = (qi - qt) / (beta * dt**2)
            vel = vt + gamma * dt * acc
            R = M @ acc + c1 * (C @ vel + f - load(i + 1)) - alpha * g_old
            step = np.linalg.solve(M / (beta * dt**2) + c1 * gamma / (beta * dt) * C + c1 * kt, -R)
            lam = 1.0  # backtracking, as for any nonsmooth Newton
            while lam > 1e-4:
                trial_q = qi + lam * step
                f_t = internal(trial_q, slip)[0]
                acc_t = (trial_q - qt) / (beta * dt**2)
                R_t = M @ acc_t + c1 * (C @ (vt + gamma * dt * acc_t) + f_t - load(i + 1)) - alpha * g_old
                if np.linalg.norm(R_t) < (1 - 1e-4 * lam) * np.linalg.norm(R):
                    break
                lam /= 2
            qi = qi + lam * step
            if np.max(np.abs(lam * step)) <= tol * max(np.max(np.abs(qi)), 1e-12):
                break
        else:
            raise AssertionError(f"block reference: no convergence at step {i}")
        f_old, _, F[i + 1], N[i + 1], slip = internal(qi, slip)
        a = (qi - qt) / (beta * dt**2)
        v = vt + gamma * dt * a
        q[i + 1] = qi
    return q, F, N


@pytest.mark.parametrize("path", ["fast", "general"])
def test_rocking_block_with_normal_forces_coupled_to_friction_matches_the_dense_reference(path):
    """The friction forces act below the centre of mass, so their moment moves the normal force
    from one bearing to the other: N depends on the horizontal response within the step (the fast
    path lags that dependence one Newton iteration, the general one too; the reference does not)."""
    model = rocking_block(BLOCK_K, BLOCK_MU, BLOCK_KV)
    pre = gravity(model, g=G)
    ag = band_limited_noise(301, DT, seed=5, amplitude=[4.0, 0.0, 2.0])
    res = solve_transient(
        model, ag, DT, preload=pre, damping=BLOCK_DAMPING, settings=TransientSettings(path=path),
        recorders=[ConnectorResponse(), NodalResponse(["CG"], components=["ux", "uz", "ry"])],
    )
    q, F, N = block_reference(ag, DT, TransientSettings().alpha)
    disp = res["displacement"][:, 0]
    for k in range(3):
        assert rel_err(disp[:, k], q[:, k]) < 1e-6, k
    assert rel_err(res["connectors.force"][:, :, 0], F) < 1e-6
    assert rel_err(res["connectors.normal_force"], N) < 1e-6
    # the case is what it claims: both bearings slide, and their N swing far beyond the vertical
    # shaking's share because of the friction moment
    ratio = res["connectors.friction_ratio"]
    assert np.all(np.mean(ratio > (1 - 1e-9) * BLOCK_MU, axis=0) > 0.05)
    assert np.all(np.ptp(N, axis=0) > 1.2 * N[0])
    assert res.balance_error < 1e-8
