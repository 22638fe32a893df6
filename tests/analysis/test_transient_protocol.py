"""Protocol v2 in the kernel: one law call per group and iteration, the trial velocity, dF/dN."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import (
    LAW_CALLS,
    band_limited_noise,
    deck_model,
    registry_with_protocol_laws,
    rel_err,
)

from bearingfw.analysis import ConnectorResponse, NodalResponse, Rayleigh, TransientSettings, gravity, solve_transient
from bearingfw.model import Connector, Model, NodalMass, Node, Support, build_system


@pytest.fixture(scope="module")
def laws():
    with registry_with_protocol_laws() as registry:
        yield registry


# --- one law object, one call per Newton iteration, for all its bearings --------------------------
def bearing_field(n: int, law: str = "test-counting-spring", scale: float = 1.0) -> Model:
    """``n`` masses, each on its own bearing over a support, every bearing with its own stiffness
    ``scale * 1e6 (1 + k)``: PLANAR and AXIAL (guided along x) alternately."""
    nodes, connectors, supports, masses = [], [], [], []
    for k in range(n):
        nodes += [Node(f"g{k}", 2.0 * k, 0, 0), Node(f"m{k}", 2.0 * k, 0, 0)]
        kind = "planar" if k % 2 else "axial"
        params = {"k": scale * 1e6 * (1 + k)}
        connectors.append(Connector(f"b{k}", f"g{k}", f"m{k}", kind, law=law, law_params=params, vertical_stiffness=1e9))
        supports.append(Support(f"g{k}"))
        masses.append(NodalMass(f"m{k}", 1e3 * (1 + 0.1 * k)))
    return Model(nodes, connectors=connectors, supports=supports, masses=masses)


@pytest.mark.parametrize("n", [4, 40])
def test_each_law_is_called_once_per_newton_iteration_whatever_the_number_of_bearings(laws, n):
    system = build_system(bearing_field(n), laws)
    groups = system.connectors.groups
    # one object per (law, dims): its stiffness an array over its bearings, in connector order
    assert [(g.dims, g.n) for g in groups] == [(1, n // 2), (2, n // 2)]
    np.testing.assert_array_equal(groups[0].law.k, 1e6 * (1 + np.arange(0, n, 2)))
    np.testing.assert_array_equal(groups[1].law.k, 1e6 * (1 + np.arange(1, n, 2)))
    pre = gravity(system)
    ag = band_limited_noise(201, 0.01, seed=3, amplitude=[2.0, 2.0, 1.0])
    for path in ("fast", "general"):
        LAW_CALLS.clear()
        res = solve_transient(system, ag, 0.01, preload=pre, settings=TransientSettings(path=path))
        st = res.stats
        assert st["subdivisions"] == 0 and st["failed_iterations"] == 0
        # a law call per trial: the Newton iterations (one trial each) and the line search's halvings
        calls = st["iterations"] + st["backtracks"]
        assert calls >= 200
        assert LAW_CALLS == {1: calls, 2: calls}, path


def test_per_bearing_group_answers_like_one_law_object_per_bearing(laws):
    """Grouped (arrays of k) or not (the same springs as a law without per_bearing, F = 2 (k / 2) u,
    one object per bearing), the response is the same."""
    grouped_system = build_system(bearing_field(6), laws)
    single_system = build_system(bearing_field(6, law="test-doubled-spring", scale=0.5), laws)
    assert len(grouped_system.connectors.groups) == 2 and len(single_system.connectors.groups) == 6
    ag = band_limited_noise(101, 0.01, seed=4, amplitude=[2.0, 2.0, 1.0])
    recorders = [ConnectorResponse(), NodalResponse([f"m{k}" for k in range(6)], "displacement")]
    grouped = solve_transient(grouped_system, ag, 0.01, recorders=recorders)
    single = solve_transient(single_system, ag, 0.01, recorders=recorders)
    assert np.max(np.abs(single["displacement"])) > 1e-3
    for key in ("displacement", "connectors.force", "connectors.law_displacement", "connectors.normal_force"):
        assert rel_err(grouped[key], single[key]) < 1e-12, key


# --- the trial velocity ------------------------------------------------------------------------------
SDOF_MASS = 2.0e4
SDOF_K = 8.0e6  # omega = 20 rad/s
SDOF_C = 0.05 * 2 * SDOF_MASS * 20.0  # 5 % of critical


def sdof(dashpot: bool) -> Model:
    """A mass on an AXIAL linear spring (guided along x) and, with ``dashpot``, an AXIAL linear
    dashpot beside it: the vertical springs carry the weight either way (same total ``kv``)."""
    spring = Connector(
        "spring", "g", "m", "axial", law="linear-spring", law_params={"k": SDOF_K},
        vertical_stiffness=1e9 if dashpot else 2e9,
    )
    connectors = [spring]
    if dashpot:
        connectors.append(
            Connector("dashpot", "g", "m", "axial", law="test-linear-dashpot", law_params={"c": SDOF_C},
                      vertical_stiffness=1e9)
        )
    return Model([Node("g", 0, 0, 0), Node("m", 0, 0, 0)], connectors=connectors, supports=[Support("g")],
                 masses=[NodalMass("m", SDOF_MASS)])


@pytest.mark.parametrize("path", ["fast", "general"])
@pytest.mark.parametrize("alpha", [0.0, -0.05])
def test_a_viscous_law_on_the_trial_velocity_is_a_linear_dashpot(laws, path, alpha):
    """``F = c v`` from the kernel's trial velocity is HHT's damping force ``C v`` of the same ``c``
    (Rayleigh ``a0 = c / m``): the same discrete equations, so the same response to round-off; a
    linear law whose force moves with the velocity still converges at once."""
    dt = 0.01
    ag = np.zeros((301, 3))
    ag[:, 0] = band_limited_noise(301, dt, seed=7, amplitude=[3.0, 0, 0])[:, 0]
    settings = TransientSettings(path=path, alpha=alpha)
    rec = [NodalResponse(["m"], "displacement", components=("ux",)), ConnectorResponse(["spring"], name="c")]
    viscous = solve_transient(build_system(sdof(True), laws), ag, dt, settings=settings, recorders=rec)
    rayleigh = solve_transient(build_system(sdof(False), laws), ag, dt, settings=settings, recorders=rec,
                               damping=Rayleigh(SDOF_C / SDOF_MASS, 0.0))
    assert np.max(np.abs(rayleigh["displacement"])) > 1e-3
    assert rel_err(viscous["displacement"], rayleigh["displacement"]) < 1e-11
    assert rel_err(viscous["c.force"][..., 0], rayleigh["c.force"][..., 0]) < 1e-11
    # the dashpot's work is in the bearings' column (with the spring's), Rayleigh's in the damping column
    assert rel_err(viscous.energy["bearings"], rayleigh.energy["bearings"] + rayleigh.energy["damping"]) < 1e-9
    assert viscous.balance_error < 1e-10
    assert viscous.stats["max_iterations"] <= 2


def test_the_viscous_law_matches_the_closed_form_of_a_damped_oscillator(laws):
    """A step ground acceleration ``A`` from t = 0: ``x(t) = -(A / w^2) (1 - e^{-z w t} (cos w_d t +
    z / sqrt(1 - z^2) sin w_d t))``; HHT (alpha = 0) with a fine step follows it to its period error."""
    dt, A = 0.001, 1.5
    ag = np.zeros((1501, 3))
    ag[:, 0] = A
    res = solve_transient(build_system(sdof(True), laws), ag, dt, settings=TransientSettings(alpha=0.0),
                          recorders=[NodalResponse(["m"], "displacement", components=("ux",))])
    w = np.sqrt(SDOF_K / SDOF_MASS)
    z = SDOF_C / (2 * SDOF_MASS * w)
    wd = w * np.sqrt(1 - z * z)
    t = res.time
    exact = -(A / w**2) * (1 - np.exp(-z * w * t) * (np.cos(wd * t) + z / np.sqrt(1 - z * z) * np.sin(wd * t)))
    assert rel_err(res["displacement"][:, 0, 0], exact) < 2e-4  # (w dt)^2 / 12 of phase per radian
    assert res.stats["max_iterations"] <= 2


def test_static_analyses_give_a_velocity_law_zero_velocity(laws):
    """The preload and the modal linearisation call laws with velocity zeros: a dashpot carries
    nothing at rest and adds no stiffness."""
    pre = gravity(build_system(sdof(True), laws))
    np.testing.assert_array_equal(pre.connector_force("dashpot")[:2], 0.0)


# --- dF/dN in Newton -----------------------------------------------------------------------------------
@pytest.mark.parametrize("path", ["fast", "general"])
def test_normal_coupling_cuts_newton_iterations_and_keeps_the_answer(laws, path):
    """Friction bearings under strong vertical shaking: N changes in every step. With dF/dN in
    Newton (the same law, ``normal_coupling``), fewer iterations, the same converged response."""
    ag = band_limited_noise(301, 0.01, seed=11, amplitude=[3.0, 2.5, 6.0])
    runs = {}
    for law in ("test-lagged-coulomb", "test-coupled-coulomb"):
        system = build_system(deck_model(law, {"k": 4e8, "mu": 0.04}), laws)
        runs[law] = solve_transient(
            system, ag, 0.01, settings=TransientSettings(path=path, tol_force=1e-10, tol_displacement=1e-12),
            damping=Rayleigh(0.21, 0.00208), recorders=[ConnectorResponse()],
        )
    lagged, coupled = runs["test-lagged-coulomb"], runs["test-coupled-coulomb"]
    N = coupled["connectors.normal_force"][:, 3:]
    assert np.all(np.ptp(N, axis=0) > 0.5 * N[0])  # the vertical response moves N a lot
    assert np.nanmax(np.abs(coupled["connectors.slip"])) > 1e-4  # and the bearings slip
    assert coupled.stats["iterations"] < 0.85 * lagged.stats["iterations"]
    for key in coupled.keys():
        assert rel_err(coupled[key], lagged[key]) < 1e-7, key
    assert coupled.balance_error < 1e-8
