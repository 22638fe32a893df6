"""Multi-support excitation (bearingfw.analysis.excitation.SupportMotion): uniform motion through the
new path is today's run bit for bit; the pseudo-static influence is exact in closed-form cases; a
rigid-body motion of a statically determinate structure strains nothing; errors name the field."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import STEEL, deck_model

from bearingfw.analysis import ConnectorResponse, ElementForces, NodalResponse, Rayleigh, gravity, solve_transient
from bearingfw.analysis.excitation import (
    SupportMotion,
    build_excitation,
    integrate_motion,
    pseudo_static_influence,
    support_groups,
)
from bearingfw.analysis.recorders import SupportResponse
from bearingfw.model import FrameElement, Material, Model, NodalMass, Node, Section, Support, build_system
from bearingfw.parameters import ParameterError

DT = 0.01


def _pulse(steps: int = 200) -> np.ndarray:
    t = np.arange(steps) * DT
    a = np.zeros((steps, 3))
    a[:, 0] = 2.0 * np.sin(2 * np.pi * 2.0 * t) * np.exp(-2.0 * t)
    a[:, 1] = 1.0 * np.sin(2 * np.pi * 3.0 * t) * np.exp(-2.0 * t)
    a[:, 2] = 0.5 * np.sin(2 * np.pi * 5.0 * t) * np.exp(-2.0 * t)
    return a


def _delayed(a: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros_like(a)
    out[n:] = a[: a.shape[0] - n]
    return out


@pytest.fixture(scope="module")
def deck():
    system = build_system(deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.05}))
    return system, gravity(system)


def _recorders():
    return [ConnectorResponse(name="b"), NodalResponse(["GA2"], quantity="acceleration", total=True, name="acc")]


def test_support_groups_by_position(deck):
    system, _ = deck
    groups = support_groups(system)
    xs = [{round(float(system.model.coordinates[system.model.node_index(n), 0]), 6) for n in g} for g in groups.values()]
    assert all(len(x) == 1 for x in xs)  # one position per group
    positions = [min(x) for x in xs]
    assert positions == sorted(positions) and len(set(positions)) == len(positions)  # support1, support2, ... along x
    assert sorted(n for g in groups.values() for n in g) == sorted(s.node for s in system.model.supports)


def test_uniform_support_motion_is_the_uniform_run_bit_for_bit(deck):
    system, preload = deck
    a = _pulse()
    groups = support_groups(system)
    damping = Rayleigh(0.3, 1e-3)
    ref = solve_transient(system, a, DT, recorders=_recorders(), preload=preload, damping=damping)
    new = solve_transient(system, SupportMotion(groups, {g: a for g in groups}), DT, recorders=_recorders(),
                          preload=preload, damping=damping)
    for key in ("b.force", "b.displacement", "acc"):
        assert np.max(np.abs(new[key] - ref[key])) <= 1e-12 * np.max(np.abs(ref[key]))


def test_influence_of_a_common_translation_is_the_rigid_body_motion(deck):
    system, preload = deck
    psi = pseudo_static_influence(system, [tuple(s.node for s in system.model.supports)], preload.normal_forces)
    rigid = np.column_stack([system.rigid_body(d) for d in "xyz"])
    active = np.abs(system.T).sum(axis=1).A1 > 0
    assert np.max(np.abs(psi[active] - rigid[active])) < 1e-9


def test_result_does_not_depend_on_the_reference_group(deck):
    """x + Psi delta is the same motion whichever group is the reference (only round-off differs)."""
    system, preload = deck
    a = _pulse()
    groups = support_groups(system)
    motions = {g: _delayed(a, 3 * k) for k, g in enumerate(groups)}
    names = list(groups)
    r1 = solve_transient(system, SupportMotion(groups, motions, reference=names[0], baseline="none"), DT,
                         recorders=_recorders(), preload=preload)
    r2 = solve_transient(system, SupportMotion(groups, motions, reference=names[-1], baseline="none"), DT,
                         recorders=_recorders(), preload=preload)
    scale = np.max(np.abs(r1["b.force"] - r1["b.force"][:1]))
    assert scale > 0
    assert np.max(np.abs(r1["b.force"] - r2["b.force"])) <= 1e-6 * scale
    assert r1.stats["balance_error"] < 1e-8  # the energy balance in x still closes


def _two_span_beam(L: float = 10.0, n: int = 10, mass: float = 0.0):
    """A continuous beam over three supports (pin, roller, roller): two spans ``L``; optional end masses."""
    sec = Section("s", A=0.02, Iy=2e-4, Iz=1e-4, J=1e-4)
    nodes = [Node(f"N{k}", 2 * L * k / (2 * n), 0.0, 0.0) for k in range(2 * n + 1)]
    els = [FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", sec, STEEL, mass="lumped") for k in range(2 * n)]
    supports = [Support("N0", ("ux", "uy", "uz", "rx")), Support(f"N{n}", ("uy", "uz")), Support(f"N{2 * n}", ("uy", "uz"))]
    return Model(nodes, els, supports=supports), sec


def test_middle_support_settlement_gives_the_closed_form_moment():
    """Two equal spans, the middle support moving down by delta slowly: M_mid = 3 E I delta / L^2."""
    L, n = 10.0, 10
    model, sec = _two_span_beam(L, n)
    system = build_system(model)
    steps = 400
    t = np.arange(steps) * 0.05
    settle = np.zeros((steps, 3))
    settle[:, 2] = -0.01 * (1 - np.cos(np.pi * np.minimum(t / t[-1], 1.0))) / 2  # slow: quasi-static
    acc = np.gradient(np.gradient(settle, 0.05, axis=0), 0.05, axis=0)
    zero = np.zeros_like(acc)
    groups = {"ends": ("N0", f"N{2 * n}"), "middle": (f"N{n}",)}
    motion = SupportMotion(groups, {"ends": zero, "middle": acc}, displacement={"ends": zero, "middle": settle})
    res = solve_transient(system, motion, 0.05, recorders=[ElementForces([f"E{n - 1}"], name="f")])
    My = res["f"][:, 0, 1, 4] - res["f"][0, 0, 1, 4]  # end j of the element left of the middle support, minus dead load
    expected = 3 * STEEL.E * sec.Iy * settle[:, 2] / L**2
    assert np.max(np.abs(np.abs(My) - np.abs(expected))) <= 2e-3 * np.max(np.abs(expected))
    assert abs(My[-1]) > 0.99 * abs(expected[-1])


def test_rigid_body_delay_on_a_determinate_structure_strains_nothing():
    """A simply supported beam whose two supports move differently (a delayed record at the roller):
    the motion is a rigid-body one, so the section forces stay at zero even with mass on the beam."""
    L, n = 10.0, 10
    sec = Section("s", A=0.02, Iy=2e-4, Iz=1e-4, J=1e-4)
    nodes = [Node(f"N{k}", L * k / n, 0.0, 0.0) for k in range(n + 1)]
    massless = Material("massless steel", STEEL.E, density=0.0, nu=0.3)
    els = [FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", sec, massless) for k in range(n)]
    model = Model(nodes, els, supports=[Support("N0", ("ux", "uy", "uz", "rx")), Support(f"N{n}", ("uy", "uz"))])
    system = build_system(model)
    a = _pulse()
    a[:, 0] = 0.0  # along the beam the roller is free: only the pin carries x
    motion = SupportMotion({"pin": ("N0",), "roller": (f"N{n}",)}, {"pin": a, "roller": _delayed(a, 5)},
                           baseline="none")
    # massless beam: the quasi-static motion is the whole motion; a rigid-body one
    res = solve_transient(system, motion, DT, recorders=[ElementForces([e.name for e in els], name="f"),
                                                         NodalResponse([f"N{n // 2}"], total=True, name="mid")])
    assert np.max(np.abs(res["f"])) < 1e-6  # no dead load either: massless
    u_pin, _ = integrate_motion(a, DT)
    u_roller, _ = integrate_motion(_delayed(a, 5), DT)
    # the midspan follows the supports rigidly: half of the roller's difference from the pin (total: relative to the pin)
    assert np.allclose(res["mid"][:, 0, 2], (u_roller[:, 2] - u_pin[:, 2]) / 2, atol=1e-12)
    assert np.max(np.abs(u_roller[:, 2] - u_pin[:, 2])) > 1e-4


def test_support_motion_errors_name_the_field(deck):
    system, _ = deck
    a = _pulse()
    groups = support_groups(system)
    first = next(iter(groups))
    with pytest.raises(ParameterError, match="'acceleration' of group"):
        SupportMotion(groups, {g: a[:, :2] for g in groups})
    with pytest.raises(ParameterError, match="field 'acceleration' must give one"):
        SupportMotion(groups, {first: a})
    with pytest.raises(ParameterError, match="puts node"):
        SupportMotion({"a": ("X",), "b": ("X",)}, {"a": a, "b": a})
    with pytest.raises(ParameterError, match="'reference'"):
        SupportMotion(groups, {g: a for g in groups}, reference="nope")
    partial = {first: groups[first]}
    with pytest.raises(ParameterError, match="in no group"):
        build_excitation(system, SupportMotion(partial, {first: a}), DT)
    with pytest.raises(ParameterError, match="without a support"):
        build_excitation(system, SupportMotion({**groups, "deck": ("GA2",)}, {g: a for g in [*groups, "deck"]}), DT)


def test_integrated_displacement_is_exact_for_piecewise_linear_acceleration():
    a = np.column_stack([np.linspace(0.0, 1.0, 11)] * 3)  # a = t on [0, 1]
    u, v = integrate_motion(a, 0.1)
    t = np.linspace(0.0, 1.0, 11)
    assert np.allclose(v[:, 0], t**2 / 2, atol=1e-14)
    assert np.allclose(u[:, 0], t**3 / 6, atol=1e-14)


def test_baseline_correction_removes_a_drift_of_the_difference():
    steps = 1000
    a = _pulse(steps)
    b = a.copy()
    b[:, 0] += 0.01  # an offset: a quadratic displacement drift of the difference
    groups = {"a": ("N0",), "b": ("N1",)}
    _, u_raw, _, _ = SupportMotion(groups, {"a": a, "b": b}, baseline="none").differences(DT)
    _, u_fix, _, _ = SupportMotion(groups, {"a": a, "b": b}).differences(DT)
    assert np.max(np.abs(u_raw[:, 0])) > 0.4
    assert np.max(np.abs(u_fix[:, 0])) < 1e-3 * np.max(np.abs(u_raw[:, 0]))


def test_support_response_records_differences_and_quasi_static_share(deck):
    system, preload = deck
    a = _pulse()
    groups = support_groups(system)
    motions = {g: _delayed(a, 3 * k) for k, g in enumerate(groups)}
    res = solve_transient(system, SupportMotion(groups, motions, baseline="none"), DT,
                          recorders=[SupportResponse()], preload=preload)
    disp = res["supports.displacement"]
    assert disp.shape[1:] == (len(groups), 3)
    assert np.all(disp[:, 0] == 0.0)  # the reference group
    u_ref, _ = integrate_motion(motions[list(groups)[0]], DT)
    u_last, _ = integrate_motion(motions[list(groups)[-1]], DT)
    assert np.allclose(disp[:, -1], u_last - u_ref, atol=1e-12)
    uniform = solve_transient(system, a, DT, recorders=[SupportResponse()], preload=preload)
    assert np.all(np.nan_to_num(uniform["supports.quasi_static"]) == 0.0)
    assert np.nanmax(np.abs(res["supports.quasi_static"])) > 0
