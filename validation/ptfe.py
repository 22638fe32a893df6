#!/usr/bin/env python
"""Validation of ``ptfe-friction`` (plugins/bearingfw-ptfe) against OpenSees's ``flatSliderBearing``.

    python validation/ptfe.py             # (a) every element case and (b) the deck, about 1 minute
    python validation/ptfe.py --quick     # what tests/validation/test_opensees_ptfe.py runs

(a) The law against ``flatSliderBearing`` with ``frictionModel VelDependent`` and
    ``VelPressureDep``, element by element: ``FlatSliderSimple2d`` (1-D) and ``FlatSliderSimple3d``
    (2-D), driven through seeded random smooth displacement paths and normal-force histories.
    The element computes its friction coefficient from its nodes' trial *velocities*, so the
    paths are imposed in a *transient* analysis (``sp`` constraints following ``Path`` series,
    Lagrange multipliers, ``Newmark 0.5 0.25``): node 2's velocity is then the Newmark velocity
    of the imposed displacements. bearingfw's law is fed the same displacement, normal force and
    velocity histories, the velocity computed here by the Newmark recursion and checked against
    OpenSees's ``nodeVel`` (column "v"). N is imposed through the axial spring (N = -axial basic
    force) and read back (column "N"). An independent scalar return-map loop with OpenSees's
    coefficient formula (``reference``) is the third opinion.
(b) A small bridge: a rigid deck (one node with the deck mass, rotations held) on a massless
    elastic pier and four multidirectional PTFE bearings with different vertical stiffnesses
    (so different dead loads, and per-bearing areas: one ``ptfe-friction`` law object with array
    parameters in bearingfw) under the three components of the Chuetsu-oki record, built here
    in bearingfw and by hand in OpenSees (elasticBeamColumn, four flatSliderBearing with
    VelPressureDep, HHT alpha = 0 = Newmark 0.5 0.25 on both sides, the gravity preload first).

Measures: (a) as validation/laws.py, ``max_t |F_bfw - F_OS| / max_t |F_OS|`` and the RMS of the
difference over the same peak (Euclidean norm per step in 2-D); (b) as validation/models.py,
``max_t |a - b| / max_t |b|`` and ``rms_t |a - b| / rms_t |b|``, plus the relative differences of
the peak and RMS values themselves. The results and the mapping of parameters are in
plugins/bearingfw-ptfe/README.md. Exit code 1 if a row exceeds 1 %.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from dataclasses import replace as dataclass_replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _opensees  # noqa: E402
from _reference import relative_difference  # noqa: E402

import bearingfw  # noqa: E402

TOLERANCE = 0.01
SEED = 20240611

#: Stick stiffness and normal force of the element cases (yield displacement f_max N / k = 0.9 mm).
K = 2.0e8
NORMAL_FORCE = 2.0e6
#: Newmark's average-acceleration rule, on both sides.
GAMMA, BETA = 0.5, 0.25

#: The two parameter sets, in bearingfw's names. "vel" maps to VelDependent, "pressure" to
#: VelPressureDep (alpha N / area = 1 at NORMAL_FORCE: f_max falls from 0.11 to 0.087 there).
PARAMS = {
    "vel": {"k": K, "f_min": 0.03, "f_max": 0.09, "a": 20.0},
    "pressure": {"k": K, "f_min": 0.03, "f_max": 0.11, "a": 20.0, "area": 0.1, "delta_mu": 0.03, "alpha": 5e-8},
}


def friction_model_args(p: dict) -> tuple:
    """``frictionModel`` arguments after the tag.

    ``VelDependent muSlow muFast transRate`` = (f_min, f_max, a) and
    ``VelPressureDep muSlow muFast0 A deltaMu alpha transRate`` = (f_min, f_max, area, delta_mu,
    alpha, a). OpenSees requires muSlow > 0 and muFast > 0.
    """
    if p.get("area") is None:
        return ("VelDependent", p["f_min"], p["f_max"], p["a"])
    return ("VelPressureDep", p["f_min"], p["f_max"], p["area"], p["delta_mu"], p["alpha"], p["a"])


# --------------------------------------------------------------------------------------------
# Paths and the integrator's velocity


def smooth_path(rng: np.random.Generator, amplitude: float, steps: int, h: float, dims: int) -> np.ndarray:
    """A seeded random smooth displacement history (steps, dims) sampled at t = h, 2h, ...

    Each component is a sum of four sines (0.3 to 2 Hz, random phases and weights) times a
    ramp ``(1 - cos(pi t / 0.5 s)) / 2`` over the first half second, so it starts from rest with
    zero velocity (as the Newmark recursion does), then scaled so that its largest magnitude is
    ``amplitude``. Components are independent: in 2-D the direction of motion turns.
    """
    t = h * np.arange(1, steps + 1)
    ramp = np.where(t < 0.5, 0.5 - 0.5 * np.cos(np.pi * np.minimum(t, 0.5) / 0.5), 1.0)
    u = np.empty((steps, dims))
    for j in range(dims):
        freq = rng.uniform(0.3, 2.0, 4)
        phase = rng.uniform(0.0, 2 * np.pi, 4)
        weight = rng.uniform(0.3, 1.0, 4)
        u[:, j] = ramp * (np.sin(2 * np.pi * freq[None, :] * t[:, None] + phase) * weight).sum(axis=1)
    return u * (amplitude / np.linalg.norm(u, axis=1).max())


def newmark_velocity(u: np.ndarray, h: float, gamma: float = GAMMA, beta: float = BETA) -> np.ndarray:
    """The Newmark velocities of the displacement history ``u`` (steps, dims) from rest at u = 0.

    v1 = gamma/(beta h) du + (1 - gamma/beta) v0 + h (1 - gamma/(2 beta)) a0 and
    a1 = du/(beta h^2) - v0/(beta h) - (1/(2 beta) - 1) a0: what OpenSees's Newmark::update gives
    a node whose displacement is imposed, and what bearingfw's kernel passes a law.
    """
    v = np.zeros(u.shape[1])
    a = np.zeros(u.shape[1])
    previous = np.zeros(u.shape[1])
    out = np.empty_like(u)
    for i, ui in enumerate(u):
        du = ui - previous
        v, a = (
            gamma / (beta * h) * du + (1 - gamma / beta) * v + h * (1 - gamma / (2 * beta)) * a,
            du / (beta * h * h) - v / (beta * h) - (1 / (2 * beta) - 1) * a,
        )
        out[i] = v
        previous = ui
    return out


# --------------------------------------------------------------------------------------------
# OpenSees: flatSliderBearing driven through imposed displacements in a transient analysis


def _path_series(ops, tag: int, values, h: float) -> None:
    """A ``Path`` series through ``values`` at t = 0, h, 2h, ... and a ``Plain`` pattern using it
    (the last value repeated: a Path series is zero after its last point)."""
    values = [*map(float, values), float(values[-1])]
    ops.timeSeries("Path", tag, "-dt", float(h), "-values", *values)
    ops.pattern("Plain", tag, tag)


def drive_flat_slider(friction: tuple, k: float, u, normal_force, h: float, axial_stiffness: float = 1e13):
    """Drive a ``flatSliderBearing`` (``frictionModel(*friction)``, ``kInit = k``) through ``u`` (steps, dims).

    dims = 1: the 2-D element (ndm 2: axial X, shear Y, rotation fixed); dims = 2: the 3-D element
    (axial X, shear Y and Z, rotations fixed). The compressive ``normal_force`` (scalar or (steps,))
    is imposed as the axial displacement ``-N / axial_stiffness``. Returns the shear force
    (steps, dims), the normal force the element used, ``-(axial basic force)`` (steps,), node 2's
    shear displacement and velocity (steps, dims).
    """
    ops = _opensees.import_opensees()
    u = np.asarray(u, dtype=float)
    steps, dims = u.shape
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), (steps,))
    shear = np.vstack([np.zeros((1, dims)), u])
    axial = np.concatenate([normal[:1], normal]) * (-1.0 / axial_stiffness)
    ops.wipe()
    if dims == 1:
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0)
        ops.node(2, 0.0, 0.0)
        ops.fix(1, 1, 1, 1)
        ops.fix(2, 0, 0, 1)
    else:
        ops.model("basic", "-ndm", 3, "-ndf", 6)
        ops.node(1, 0.0, 0.0, 0.0)
        ops.node(2, 0.0, 0.0, 0.0)
        ops.fix(1, 1, 1, 1, 1, 1, 1)
        ops.fix(2, 0, 0, 0, 1, 1, 1)
    ops.frictionModel(friction[0], 1, *friction[1:])
    ops.uniaxialMaterial("Elastic", 1, axial_stiffness)
    ops.uniaxialMaterial("Elastic", 2, 1e12)
    orient = ("-orient", 1.0, 0.0, 0.0, 0.0, 1.0, 0.0)
    if dims == 1:
        ops.element("flatSliderBearing", 1, 1, 2, 1, k, "-P", 1, "-Mz", 2, *orient, "-iter", 50, 1e-12)
    else:
        ops.element("flatSliderBearing", 1, 1, 2, 1, k, "-P", 1, "-T", 2, "-My", 2, "-Mz", 2, *orient,
                    "-iter", 50, 1e-12)  # fmt: skip
    # the shear DOFs of node 2 are 2 (and 3): the first is the axial one
    for dof, values in [(1, axial)] + [(2 + j, shear[:, j]) for j in range(dims)]:
        _path_series(ops, dof, values, h)
        ops.sp(2, dof, 1.0)
    ops.constraints("Lagrange")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    # Every degree of freedom is prescribed: the first iteration imposes the displacements (and so
    # the Newmark velocities) exactly, the second only updates the Lagrange multipliers.
    ops.test("FixedNumIter", 2)
    ops.algorithm("Newton")
    ops.integrator("Newmark", GAMMA, BETA)
    ops.analysis("Transient")
    rows = []
    for i in range(steps):
        if ops.analyze(1, float(h)) != 0:
            raise RuntimeError(f"OpenSees analysis failed at step {i + 1}")
        q = ops.eleResponse(1, "basicForce")
        d, v = ops.nodeDisp(2), ops.nodeVel(2)
        rows.append([*q[1 : 1 + dims], -q[0], *d[1 : 1 + dims], *v[1 : 1 + dims]])
    ops.wipe()
    rows = np.array(rows)
    return rows[:, :dims], rows[:, dims], rows[:, dims + 1 : 2 * dims + 1], rows[:, 2 * dims + 1 :]


# --------------------------------------------------------------------------------------------
# bearingfw's side and the independent reference


def drive_law(law, u, normal_force, velocity, dt: float) -> np.ndarray:
    """The law's force history (steps, dims) along ``u`` with the given normal forces and velocities."""
    u = np.asarray(u, dtype=float)
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), u.shape[:1])
    state = law.initial_state(1)
    out = np.empty_like(u)
    for i in range(len(u)):
        r = law.respond(state, u[i][None], normal[i : i + 1], dt, velocity=velocity[i][None])
        out[i] = r.force[0]
        state = r.state
    return out


def coefficient_reference(p: dict, speed: float, normal: float) -> float:
    """OpenSees's VelDependent / VelPressureDep coefficient, written out in scalars."""
    fast = p["f_max"]
    if p.get("area") is not None and normal > 0:
        fast -= p["delta_mu"] * math.tanh(p["alpha"] * normal / p["area"])
    return fast - (fast - p["f_min"]) * math.exp(-p["a"] * abs(speed))


def reference(p: dict, u, normal_force, velocity) -> np.ndarray:
    """A scalar radial-return loop (any dims) with the coefficient at each step's speed and N."""
    u = np.asarray(u, dtype=float)
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), u.shape[:1])
    slip = np.zeros(u.shape[1])
    out = np.empty_like(u)
    for i in range(len(u)):
        n = float(normal[i])
        trial = p["k"] * (u[i] - slip)
        size = float(np.sqrt(trial @ trial))
        capacity = coefficient_reference(p, float(np.sqrt(velocity[i] @ velocity[i])), n) * max(n, 0.0)
        if size > capacity or capacity <= 0.0:
            trial = trial * (capacity / size if size > 0 else 0.0)
            slip = u[i] - trial / p["k"]
        out[i] = trial
    return out


# --------------------------------------------------------------------------------------------
# (a) cases


@dataclass
class ElementCase:
    name: str
    params: dict
    u: np.ndarray
    normal: np.ndarray
    h: float

    @property
    def dims(self) -> int:
        return self.u.shape[1]

    def run(self) -> "ElementRow":
        velocity = newmark_velocity(self.u, self.h)
        law = bearingfw.create_law("ptfe-friction", **self.params, dims=self.dims)
        ours = drive_law(law, self.u, self.normal, velocity, self.h)
        force, normal, disp, os_velocity = drive_flat_slider(friction_model_args(self.params), self.params["k"],
                                                             self.u, self.normal, self.h)  # fmt: skip
        expected_normal = np.maximum(self.normal, 0.0)  # tension: the element reports no axial force
        speed = np.linalg.norm(velocity, axis=1)
        mu = np.array([coefficient_reference(self.params, s, n) for s, n in zip(speed, expected_normal)])
        return ElementRow(
            case=self,
            force=relative_difference(ours, force),
            reference=relative_difference(ours, reference(self.params, self.u, self.normal, velocity),
                                          scale=np.linalg.norm(force, axis=1).max()),  # fmt: skip
            os_reference=relative_difference(force, reference(self.params, self.u, self.normal, velocity)),
            displacement=relative_difference(disp, self.u)[0],
            velocity=relative_difference(os_velocity, velocity)[0],
            normal=float(np.abs(normal - expected_normal).max() / np.abs(expected_normal).max()),
            peak_speed=float(speed.max()),
            mu_range=(float(mu.min()), float(mu.max())),
            slid=float(np.max(np.linalg.norm(force, axis=1) / np.maximum(mu * expected_normal, 1e-300))),
        )


@dataclass
class ElementRow:
    case: ElementCase
    force: tuple
    reference: tuple
    os_reference: tuple
    displacement: float
    velocity: float
    normal: float
    peak_speed: float
    mu_range: tuple
    slid: float

    @property
    def ok(self) -> bool:
        inputs_agree = max(self.displacement, self.velocity, self.normal) <= 1e-9
        return inputs_agree and max(self.force) <= TOLERANCE

    @property
    def status(self) -> str:
        return "PASS" if self.ok else "FAIL"


def element_cases(quick: bool = False, seed: int = SEED) -> list[ElementCase]:
    """The (a) cases; amplitudes in yield displacements at rest, uy = f_min N / k (0.3 mm)."""
    rng = np.random.default_rng(seed)
    steps, h = (150, 0.02) if quick else (400, 0.01)
    uy = 0.03 * NORMAL_FORCE / K
    t = h * np.arange(1, steps + 1)
    varying = NORMAL_FORCE * (1.0 + 0.4 * np.sin(2 * np.pi * 0.7 * t + rng.uniform(0, 2 * np.pi)))
    lifting = NORMAL_FORCE * (0.35 + 0.8 * np.sin(2 * np.pi * 0.5 * t))  # tension in part of each cycle
    constant = np.full(steps, NORMAL_FORCE)
    plan = [
        ("vel", 1, 0.6, constant, "1-D vel 0.6 uy (stick)"),
        ("vel", 1, 10.0, constant, "1-D vel 10 uy"),
        ("vel", 1, 100.0, constant, "1-D vel 100 uy"),
        ("pressure", 1, 100.0, varying, "1-D pressure 100 uy N(t)"),
        ("vel", 2, 0.6, constant, "2-D vel 0.6 uy (stick)"),
        ("vel", 2, 10.0, constant, "2-D vel 10 uy"),
        ("vel", 2, 100.0, constant, "2-D vel 100 uy"),
        ("pressure", 2, 30.0, varying, "2-D pressure 30 uy N(t)"),
        ("pressure", 2, 100.0, varying, "2-D pressure 100 uy N(t)"),
        ("pressure", 2, 60.0, lifting, "2-D pressure 60 uy lift-off"),
    ]
    if quick:
        plan = [plan[i] for i in (1, 3, 6, 8, 9)]
    return [ElementCase(name, PARAMS[key], smooth_path(rng, amp * uy, steps, h, dims), normal, h)
            for key, dims, amp, normal, name in plan]  # fmt: skip


def run_elements(quick: bool = False, seed: int = SEED) -> list[ElementRow]:
    return [case.run() for case in element_cases(quick, seed)]


def _pct(x: float) -> str:
    return f"{100 * x:.2g} %" if x >= 1e-4 else f"{x:.0e}"


def print_element_rows(rows: list[ElementRow], out=sys.stdout) -> None:
    print("(a) ptfe-friction vs flatSliderBearing (VelDependent / VelPressureDep), imposed paths, Newmark", file=out)
    header = (f"{'case':30s} {'vs OpenSees max / RMS':>24s} {'bfw vs ref':>10s} {'OS vs ref':>10s} "
              f"{'|v|max m/s':>10s} {'mu range':>13s} {'|F|/muN':>7s} {'u, v, N read back':>20s}  status")  # fmt: skip
    print(header, file=out)
    for r in rows:
        inputs = max(r.displacement, r.velocity, r.normal)
        print(
            f"{r.case.name:30s} {_pct(r.force[0]):>11s} / {_pct(r.force[1]):>10s} {_pct(r.reference[0]):>10s} "
            f"{_pct(r.os_reference[0]):>10s} {r.peak_speed:10.3f} {r.mu_range[0]:6.3f}-{r.mu_range[1]:.3f} "
            f"{r.slid:7.3f} {inputs:20.1e}  {r.status}",
            file=out,
        )


# --------------------------------------------------------------------------------------------
# (b) a rigid deck on a pier and four PTFE bearings, under a real record

DECK_MASS = 2.0e6  # kg
PIER_HEIGHT = 8.0  # m
PIER_E = 3.4e10  # Pa
#: The pier: a massless column clamped at its base and (the deck's rotations are held) at its top,
#: lateral stiffness 12 E I / H^3 = 79 MN/m (1 Hz with the deck mass); a small area, so that the
#: bearings carry most of the weight.
PIER_SECTION = {"A": 0.05, "Iy": 0.1, "Iz": 0.1, "J": 0.15}
#: Four multidirectional bearings: vertical stiffnesses (N/m) and PTFE disc areas (m^2) differ, so
#: their normal forces and pressures differ (one law object with per-bearing arrays in bearingfw).
DECK_BEARINGS = {
    "b1": (3.0e9, 0.20),
    "b2": (4.0e9, 0.25),
    "b3": (5.0e9, 0.30),
    "b4": (6.0e9, 0.35),
}
DECK_PTFE = {"k": 4.0e8, "f_min": 0.03, "f_max": 0.11, "a": 20.0, "delta_mu": 0.03, "alpha": 5e-8}
#: Rayleigh damping, mass-proportional only (so that the two codes' damping matrices are the same
#: without dashpots: the flat sliders take no stiffness-proportional damping in OpenSees).
DECK_DAMPING_A0 = 0.21
DECK_RECORD = (15.0, 35.0)
DECK_RECORD_QUICK = (18.0, 23.0)


def deck_model():
    """The bearingfw model of (b): ``deck`` (mass, rotations held) on the pier and bearings b1..b4."""
    from bearingfw.model import Connector, FrameElement, Material, Model, NodalMass, Node, Section, Support

    pier = Section("pier", **PIER_SECTION)
    massless = Material("massless concrete", PIER_E, density=0.0)
    nodes = [Node("base", 0.0, 0.0, -PIER_HEIGHT), Node("deck", 0.0, 0.0, 0.0)]
    connectors, supports = [], [Support("base"), Support("deck", ("rx", "ry", "rz"))]
    for name, (kv, area) in DECK_BEARINGS.items():
        nodes.append(Node(f"{name}.seat", 0.0, 0.0, 0.0))
        supports.append(Support(f"{name}.seat"))
        connectors.append(Connector(name, f"{name}.seat", "deck", "planar", law="ptfe-friction",
                                    law_params={**DECK_PTFE, "area": area}, vertical_stiffness=kv))  # fmt: skip
    return Model(nodes, [FrameElement("pier", "base", "deck", pier, massless)], connectors, supports=supports,
                 masses=[NodalMass("deck", DECK_MASS)], name="rigid deck on PTFE bearings")  # fmt: skip


def deck_bearingfw(ag: np.ndarray, dt: float, substeps: int = 2):
    """bearingfw's run of (b): law forces {bearing: (t, 2)}, normal forces {bearing: (t,)}, deck (t, 3)."""
    from bearingfw.analysis import ConnectorResponse, NodalResponse, Rayleigh, TransientSettings, gravity
    from bearingfw.analysis import solve_transient

    model = deck_model()
    preload = gravity(model)
    settings = TransientSettings(alpha=0.0, dt_integration=dt / substeps)
    recorders = [NodalResponse(["deck"], "displacement", name="deck", every=substeps),
                 ConnectorResponse(list(DECK_BEARINGS), name="bearings", every=substeps)]  # fmt: skip
    result = solve_transient(preload.system, ag, dt, settings=settings, damping=Rayleigh(DECK_DAMPING_A0, 0.0),
                             recorders=recorders, preload=preload)  # fmt: skip
    force = result.data["bearings.force"]
    normal = result.data["bearings.normal_force"]
    names = list(DECK_BEARINGS)
    return ({b: force[:, k, :2] for k, b in enumerate(names)}, {b: normal[:, k] for k, b in enumerate(names)},
            result.data["deck"][:, 0] - result.data["deck"][0, 0])  # fmt: skip


def deck_opensees(ag: np.ndarray, dt: float, substeps: int = 2, g: float = 9.81):
    """The same structure written directly in OpenSees (3-D): returns what :func:`deck_bearingfw` does.

    Pier: ``elasticBeamColumn`` (massless), ``geomTransf Linear``. Bearings: ``flatSliderBearing``
    from each seat (fixed) to the deck node, ``frictionModel VelPressureDep`` with the bearing's
    area, ``kInit = k``, axial ``Elastic kv``; ``-orient 0 0 1 1 0 0`` makes the element's axis
    vertical and its shear directions global X and Y (basic forces 1, 2). The deck's rotations are
    fixed, so the sliders' P-Delta terms (N times a node rotation) vanish. Gravity in one load step,
    ``loadConst -time 0``, then ``UniformExcitation`` in X, Y, Z, ``rayleigh a0 0 0 0``,
    ``Newmark 0.5 0.25`` (bearingfw's HHT at alpha = 0), Newton with ``NormDispIncr 1e-12``.
    """
    ops = _opensees.import_opensees()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, -PIER_HEIGHT)
    ops.node(2, 0.0, 0.0, 0.0)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 0, 0, 1, 1, 1)
    ops.mass(2, DECK_MASS, DECK_MASS, DECK_MASS, 0.0, 0.0, 0.0)
    ops.geomTransf("Linear", 1, 1.0, 0.0, 0.0)
    s = PIER_SECTION
    shear_modulus = PIER_E / 2.4  # nu = 0.2, bearingfw's Material default
    ops.element("elasticBeamColumn", 1, 1, 2, s["A"], PIER_E, shear_modulus, s["J"], s["Iy"], s["Iz"], 1)
    ops.uniaxialMaterial("Elastic", 100, 1e12)  # the sliders' rotational springs (both nodes held)
    p = DECK_PTFE
    for k, (kv, area) in enumerate(DECK_BEARINGS.values()):
        seat, tag = 3 + k, 2 + k
        ops.node(seat, 0.0, 0.0, 0.0)
        ops.fix(seat, 1, 1, 1, 1, 1, 1)
        ops.frictionModel("VelPressureDep", tag, p["f_min"], p["f_max"], area, p["delta_mu"], p["alpha"], p["a"])
        ops.uniaxialMaterial("Elastic", tag, kv)
        ops.element("flatSliderBearing", tag, seat, 2, tag, p["k"], "-P", tag, "-T", 100, "-My", 100, "-Mz", 100,
                    "-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, "-iter", 50, 1e-12)  # fmt: skip
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -DECK_MASS * g, 0.0, 0.0, 0.0)
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees gravity step failed")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    for direction in (1, 2, 3):
        ops.timeSeries("Path", 10 + direction, "-dt", float(dt), "-values", *map(float, ag[:, direction - 1]),
                       float(ag[-1, direction - 1]))  # fmt: skip
        ops.pattern("UniformExcitation", 10 + direction, direction, "-accel", 10 + direction)
    ops.rayleigh(DECK_DAMPING_A0, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", GAMMA, BETA)
    ops.analysis("Transient")
    tags = [2 + k for k in range(len(DECK_BEARINGS))]

    def sample():
        q = [ops.eleResponse(t, "basicForce") for t in tags]
        return [*(v for qi in q for v in (qi[1], qi[2], -qi[0])), *ops.nodeDisp(2)[:3]]

    rows = [sample()]
    start = list(rows[0][-3:])
    for step in range(len(ag) - 1):
        for _ in range(substeps):
            if ops.analyze(1, dt / substeps) != 0:
                raise RuntimeError(f"OpenSees deck model failed at step {step + 1}")
        rows.append(sample())
    ops.wipe()
    rows = np.array(rows)
    names = list(DECK_BEARINGS)
    force = {b: rows[:, [3 * k, 3 * k + 1]] for k, b in enumerate(names)}
    normal = {b: rows[:, 3 * k + 2] for k, b in enumerate(names)}
    return force, normal, rows[:, -3:] - np.array(start)


def history_difference(a, b) -> tuple[float, float]:
    """``(max_t |a - b| / max_t |b|, rms_t |a - b| / rms_t |b|)`` (validation/models.py's measure)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    a, b = a.reshape(len(a), -1), b.reshape(len(b), -1)
    diff, size = np.linalg.norm(a - b, axis=1), np.linalg.norm(b, axis=1)
    return float(diff.max() / size.max()), float(np.sqrt(np.mean(diff**2) / np.mean(size**2)))


@dataclass
class DeckRow:
    quantity: str
    worst: str
    max: float
    rms: float
    #: the largest |peak_a / peak_b - 1| and |rms_a / rms_b - 1| over the histories
    peak: float = 0.0
    level: float = 0.0
    note: str = ""
    #: bearing force rows: the largest |F| / N any bearing reached in OpenSees
    friction_ratio: float | None = None

    @property
    def ok(self) -> bool:
        return max(self.max, self.rms) <= TOLERANCE


def _compare(quantity: str, ours: dict, theirs: dict, note: str = "") -> DeckRow:
    pairs = {k: history_difference(ours[k], theirs[k]) for k in ours}
    worst = max(pairs, key=lambda k: max(pairs[k]))

    def size(h):
        h = np.asarray(h, dtype=float).reshape(len(h), -1)
        return np.linalg.norm(h, axis=1)

    peak = max(abs(size(ours[k]).max() / size(theirs[k]).max() - 1) for k in ours)
    level = max(abs(np.sqrt(np.mean(size(ours[k]) ** 2) / np.mean(size(theirs[k]) ** 2)) - 1) for k in ours)
    return DeckRow(quantity, worst, max(p[0] for p in pairs.values()), max(p[1] for p in pairs.values()), peak, level,
                   note)  # fmt: skip


RECORDS = Path(__file__).resolve().parents[1] / "examples" / "data" / "records"
CHUETSU = ("RSN4843_CHUETSU_65006EW.AT2", "RSN4843_CHUETSU_65006NS.AT2", "RSN4843_CHUETSU_65006UD.AT2")


def deck_record(quick: bool = False, taper: float = 0.5) -> tuple[np.ndarray, float]:
    """The record of (b): Chuetsu-oki 2007, Matsushiro Tokamachi (PEER NGA-West2 RSN4843; EW, NS, UD
    on global x, y, z), the window ``DECK_RECORD`` (or ``DECK_RECORD_QUICK``), cosine-tapered over
    ``taper`` s at both ends and preceded by a zero sample, so that both codes start at rest (the
    window validation/models.py uses). Returns (samples (n, 3) in m/s^2, dt)."""
    from bearingfw.motion import read_record

    start, stop = DECK_RECORD_QUICK if quick else DECK_RECORD
    record = read_record([RECORDS / name for name in CHUETSU])
    t = record.time
    keep = (t >= start) & (t <= stop)
    ag = record.components.T[keep].copy()
    ramp = np.clip(np.minimum(t[keep] - start, stop - t[keep]) / taper, 0.0, 1.0)
    ag *= (0.5 - 0.5 * np.cos(np.pi * ramp))[:, None]
    return np.vstack([np.zeros((1, 3)), ag]), record.dt


def run_deck(quick: bool = False) -> list[DeckRow]:
    ag, dt = deck_record(quick)
    force, normal, deck = deck_bearingfw(ag, dt)
    os_force, os_normal, os_deck = deck_opensees(ag, dt)
    total_normal = sum(np.asarray(n) for n in os_normal.values())
    mu_slid = max(float(np.max(np.linalg.norm(os_force[b], axis=1) / np.maximum(os_normal[b], 1e-300)))
                  for b in os_force)  # fmt: skip
    speed = np.abs(np.diff(os_deck[:, :2], axis=0)).max() / dt
    bearing_row = _compare("bearing law force", force, os_force,
                           note=f"peak |F|/N {mu_slid:.3f}; N from {total_normal.min():.3g} to "
                                f"{total_normal.max():.3g} N (sum of the four)")  # fmt: skip
    return [
        dataclass_replace(bearing_row, friction_ratio=mu_slid),
        _compare("bearing normal force", normal, os_normal),
        _compare("deck displacement", {"deck": deck}, {"deck": os_deck}, note=f"about {speed:.2f} m/s at most"),
    ]


def print_deck_rows(rows: list[DeckRow], out=sys.stdout) -> None:
    print("\n(b) rigid deck on a pier and four ptfe-friction bearings, Chuetsu-oki x/y/z, Newmark h = dt/2", file=out)
    print(f"{'quantity':22s} {'worst':6s} {'history max / RMS':>22s} {'peak, RMS values':>20s}  status  note", file=out)
    for r in rows:
        print(f"{r.quantity:22s} {r.worst:6s} {_pct(r.max):>10s} / {_pct(r.rms):>9s} {_pct(r.peak):>9s}, "
              f"{_pct(r.level):>9s}  {'PASS' if r.ok else 'FAIL':6s}  {r.note}", file=out)  # fmt: skip


# --------------------------------------------------------------------------------------------


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the short set the test runs")
    parser.add_argument("--seed", type=int, default=SEED)
    args = parser.parse_args(argv)
    _opensees.ensure_opensees()
    start = time.perf_counter()
    rows = run_elements(args.quick, args.seed)
    print_element_rows(rows)
    deck = run_deck(args.quick)
    print_deck_rows(deck)
    ok = all(r.ok for r in rows) and all(r.ok for r in deck)
    print(f"\n{time.perf_counter() - start:.1f} s; {'all within 1 %' if ok else 'FAILED'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
