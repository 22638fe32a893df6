#!/usr/bin/env python
"""Validation of the friction-pendulum laws (plugins/bearingfw-pendulum) against OpenSees's ``singleFPBearing``.

    python validation/pendulum.py          # (a) every element case and (b) the deck, about 2 minutes
    python validation/pendulum.py --quick  # what tests/validation/test_opensees_pendulum.py runs

(a) ``friction-pendulum`` (``frictionModel Coulomb``) and ``friction-pendulum-vel``
    (``frictionModel VelDependent``) against ``singleFPBearing``, element by element:
    ``SingleFPSimple2d`` (1-D) and ``SingleFPSimple3d`` (2-D), driven through seeded random smooth
    paths with imposed normal-force histories in a transient analysis with ``Newmark 0.5 0.25``
    (as validation/ptfe.py: both sides get the same Newmark velocities, read back from OpenSees).
    OpenSees's element is the *large-displacement* form of the law: it takes the friction force
    and the pendulum stiffness from the force normal to the surface,
    ``N_s = N + (F_y u_y / R_y + F_z u_z / R_z)`` (a fixed-point iteration), uses the radii
    ``R_y = sqrt(R^2 - u_z^2)``, ``R_z = sqrt(R^2 - u_y^2)`` per axis (so its hysteretic stiffness and
    its plastic flow differ between the axes) and the speed along the surface
    ``sqrt(v . v + (v_y u_y / R_y + v_z u_z / R_z)^2)``. bearingfw's law is the small-displacement form
    (``N_s = N``, ``R_y = R_z = R``, speed ``|v|``). So the two differ by terms of order
    ``mu u / R`` and ``(u / R)^2``. Evidence, per case: ``transcription`` is a scalar Python
    transcription of OpenSees's update (its large-displacement terms switchable); with them it
    must equal OpenSees to round-off ("OS vs LD"), without them bearingfw ("bfw vs SD"). A
    row above 1 % is then EXPLAINED LARGE-DISPLACEMENT if both hold and the same case with the
    radius 10 times larger (u / R ten times smaller) is within 1 %.
(b) A rigid deck (2000 t, rotations held) isolated on four friction pendulums (R = 2.24 m,
    T = 3 s; different vertical stiffnesses, so different N) under the three components of the
    Chuetsu-oki record, built in bearingfw and by hand in OpenSees (four singleFPBearing,
    Newmark 0.5 0.25 both sides, mass-proportional damping), with the same explanation rule: a
    row above 1 % is run again with R ten times larger (u / R about ten times smaller).

Measures as validation/ptfe.py. Exit code 1 if a row exceeds 1 % without a valid explanation.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _opensees  # noqa: E402
from _reference import relative_difference  # noqa: E402

import bearingfw  # noqa: E402


def _load_ptfe():
    """validation/ptfe.py (its paths, Newmark velocities, deck record and measures), loaded by path
    under the name the tests give it: a plain ``import ptfe`` could find another module first."""
    import importlib.util

    name = "bearingfw_validation_ptfe"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, Path(__file__).resolve().parent / "ptfe.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


_ptfe = _load_ptfe()
BETA, GAMMA = _ptfe.BETA, _ptfe.GAMMA
DECK_DAMPING_A0, DECK_MASS = _ptfe.DECK_DAMPING_A0, _ptfe.DECK_MASS
_compare, _path_series, _pct = _ptfe._compare, _ptfe._path_series, _ptfe._pct
deck_record, newmark_velocity, smooth_path = _ptfe.deck_record, _ptfe.newmark_velocity, _ptfe.smooth_path

TOLERANCE = 0.01
SEED = 20240611

K = 2.0e8
NORMAL_FORCE = 2.0e6
RADIUS = 2.0
#: the law parameters of the two sets (bearingfw's names; R is set per case)
PARAMS = {
    "coulomb": ("friction-pendulum", {"k": K, "mu": 0.05}),
    "vel": ("friction-pendulum-vel", {"k": K, "f_min": 0.03, "f_max": 0.08, "a": 20.0}),
}
#: OpenSees's inner iteration: enough iterations, and a tolerance (N) above round-off of the forces.
OS_ITER = ("-iter", 100, 1e-8)


def friction_model_args(law: str, p: dict) -> tuple:
    """``frictionModel Coulomb mu`` or ``frictionModel VelDependent muSlow muFast transRate``."""
    if law == "friction-pendulum":
        return ("Coulomb", p["mu"])
    return ("VelDependent", p["f_min"], p["f_max"], p["a"])


def coefficient(law: str, p: dict, speed: float) -> float:
    if law == "friction-pendulum":
        return p["mu"]
    return p["f_max"] - (p["f_max"] - p["f_min"]) * math.exp(-p["a"] * abs(speed))


# --------------------------------------------------------------------------------------------
# OpenSees: singleFPBearing driven through imposed displacements in a transient analysis


def drive_single_fp(friction: tuple, radius: float, k: float, u, normal_force, h: float, axial_stiffness=1e13):
    """As validation/ptfe.py's ``drive_flat_slider``, with ``singleFPBearing frnTag Reff kInit``.

    Returns the shear force (steps, dims), the axial force's compression ``-(q_axial)`` (steps,),
    node 2's shear displacement and velocity (steps, dims).
    """
    ops = _opensees.import_opensees()
    u = np.asarray(u, dtype=float)
    steps, dims = u.shape
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), (steps,))
    shear = np.vstack([np.zeros((1, dims)), u])
    axial = np.concatenate([normal[:1], normal]) * (-1.0 / axial_stiffness)
    ops.wipe()
    orient = ("-orient", 1.0, 0.0, 0.0, 0.0, 1.0, 0.0)
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
    if dims == 1:
        ops.element("singleFPBearing", 1, 1, 2, 1, radius, k, "-P", 1, "-Mz", 2, *orient, *OS_ITER)
    else:
        ops.element("singleFPBearing", 1, 1, 2, 1, radius, k, "-P", 1, "-T", 2, "-My", 2, "-Mz", 2, *orient,
                    *OS_ITER)  # fmt: skip
    for dof, values in [(1, axial)] + [(2 + j, shear[:, j]) for j in range(dims)]:
        _path_series(ops, dof, values, h)
        ops.sp(2, dof, 1.0)
    ops.constraints("Lagrange")
    ops.numberer("Plain")
    ops.system("FullGeneral")
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
# bearingfw's side and the transcription of OpenSees's update


def drive_law(law, u, normal_force, velocity, dt: float) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    normal = np.broadcast_to(np.asarray(normal_force, dtype=float), u.shape[:1])
    velocity_kw = getattr(law, "uses_velocity", False)
    state = law.initial_state(1)
    out = np.empty_like(u)
    for i in range(len(u)):
        kwargs = {"velocity": velocity[i][None]} if velocity_kw else {}
        r = law.respond(state, u[i][None], normal[i : i + 1], dt, **kwargs)
        out[i] = r.force[0]
        state = r.state
    return out


def transcription(law: str, p: dict, radius: float, u, axial, velocity, large: bool = True) -> np.ndarray:
    """SingleFPSimple2d/3d::update written out in scalars (``axial``: the compression from the axial
    spring). ``large=False`` drops the large-displacement terms: N_s = N, R_y = R_z = R, speed |v|."""
    u = np.asarray(u, dtype=float)
    steps, dims = u.shape
    slip = np.zeros(dims)
    q = np.zeros(dims)  # the element keeps its last shear force as the iteration's start
    out = np.empty_like(u)
    for i in range(steps):
        ui, vi, p_axial = u[i], velocity[i], float(axial[i])
        if p_axial <= 0.0:  # uplift: no forces, the slip follows
            slip, q = ui.copy(), np.zeros(dims)
            out[i] = q
            continue
        if dims == 1:
            radii = np.array([radius])
        else:
            radii = np.array([math.sqrt(radius**2 - ui[1] ** 2), math.sqrt(radius**2 - ui[0] ** 2)]) if large else \
                np.array([radius, radius])  # fmt: skip
        if not large:
            radii = np.full(dims, radius)
        vertical = float(np.sum(vi * ui / radii)) if large else 0.0
        speed = math.sqrt(float(vi @ vi) + vertical**2)
        trial_slip = slip
        for _ in range(200):
            previous = q.copy()
            normal = p_axial + (float(np.sum(q * ui / radii)) if large else 0.0)
            normal = max(normal, 0.0)
            q_yield = coefficient(law, p, speed) * normal
            k2 = normal / radii
            k0 = p["k"] - k2
            trial = k0 * (ui - slip)
            size = float(np.sqrt(trial @ trial))
            if size - q_yield <= 0.0:
                q = trial + k2 * ui
                trial_slip = slip
            else:
                trial_slip = slip + (size - q_yield) / k0 * trial / size
                q = q_yield * trial / size + k2 * ui
            if np.sqrt(np.sum((q - previous) ** 2)) < 1e-9:
                break
        slip = trial_slip
        out[i] = q
    return out


# --------------------------------------------------------------------------------------------
# (a) cases


@dataclass
class ElementCase:
    name: str
    key: str
    radius: float
    u: np.ndarray
    normal: np.ndarray
    h: float

    @property
    def dims(self) -> int:
        return self.u.shape[1]

    @property
    def law_name(self) -> str:
        return PARAMS[self.key][0]

    @property
    def params(self) -> dict:
        return PARAMS[self.key][1]

    def scaled(self, factor: float) -> "ElementCase":
        """The same case with R times ``factor`` (u / R smaller by it)."""
        return ElementCase(f"{self.name} R x{factor:g}", self.key, self.radius * factor, self.u, self.normal, self.h)

    def run(self, evidence: bool = True) -> "ElementRow":
        velocity = newmark_velocity(self.u, self.h)
        law = bearingfw.create_law(self.law_name, **self.params, R=self.radius, dims=self.dims)
        ours = drive_law(law, self.u, self.normal, velocity, self.h)
        force, axial, disp, os_velocity = drive_single_fp(friction_model_args(self.law_name, self.params),
                                                          self.radius, self.params["k"], self.u, self.normal,
                                                          self.h)  # fmt: skip
        row = ElementRow(
            case=self,
            force=relative_difference(ours, force),
            inputs=max(relative_difference(disp, self.u)[0], relative_difference(os_velocity, velocity)[0],
                       float(np.abs(axial - np.maximum(self.normal, 0)).max() / np.abs(self.normal).max())),
            u_over_r=float(np.linalg.norm(self.u, axis=1).max() / self.radius),
        )  # fmt: skip
        if evidence:
            peak = np.linalg.norm(force, axis=1).max()
            large = transcription(self.law_name, self.params, self.radius, self.u, self.normal, velocity, True)
            small = transcription(self.law_name, self.params, self.radius, self.u, self.normal, velocity, False)
            row.os_vs_large = relative_difference(force, large, scale=peak)[0]
            row.bfw_vs_small = relative_difference(ours, small, scale=peak)[0]
            if max(row.force) > TOLERANCE:
                row.scaled = max(self.scaled(10.0).run(evidence=False).force)
        return row


@dataclass
class ElementRow:
    case: ElementCase
    force: tuple
    inputs: float
    u_over_r: float
    os_vs_large: float | None = None
    bfw_vs_small: float | None = None
    scaled: float | None = None

    @property
    def status(self) -> str:
        if self.inputs > 1e-9:
            return "FAIL (inputs)"
        if max(self.force) <= TOLERANCE:
            return "PASS"
        if self.explained:
            return "EXPLAINED LARGE-DISPLACEMENT"
        return "FAIL"

    @property
    def explained(self) -> bool:
        """OpenSees = its large-displacement transcription, bearingfw = the small-displacement one,
        and with u / R ten times smaller the two codes agree within 1 %."""
        return (
            self.os_vs_large is not None and self.os_vs_large < 1e-6 and self.bfw_vs_small < 1e-9
            and self.scaled is not None and self.scaled <= TOLERANCE
        )  # fmt: skip

    @property
    def ok(self) -> bool:
        return self.status in ("PASS", "EXPLAINED LARGE-DISPLACEMENT")


def element_cases(quick: bool = False, seed: int = SEED) -> list[ElementCase]:
    """The (a) cases: amplitudes as fractions of R (the measure of the geometric difference)."""
    rng = np.random.default_rng(seed)
    steps, h = (150, 0.02) if quick else (400, 0.01)
    t = h * np.arange(1, steps + 1)
    constant = np.full(steps, NORMAL_FORCE)
    varying = NORMAL_FORCE * (1.0 + 0.4 * np.sin(2 * np.pi * 0.7 * t + rng.uniform(0, 2 * np.pi)))
    lifting = NORMAL_FORCE * (0.35 + 0.8 * np.sin(2 * np.pi * 0.5 * t))
    slide = 0.05 * NORMAL_FORCE / (K - NORMAL_FORCE / RADIUS)  # stick range, 0.5 mm
    plan = [
        ("coulomb", 1, 0.6 * slide / RADIUS, constant, "1-D coulomb stick"),
        ("coulomb", 1, 0.005, constant, "1-D coulomb u/R 0.005"),
        ("coulomb", 1, 0.05, varying, "1-D coulomb u/R 0.05 N(t)"),
        ("vel", 1, 0.05, varying, "1-D vel u/R 0.05 N(t)"),
        ("coulomb", 2, 0.6 * slide / RADIUS, constant, "2-D coulomb stick"),
        ("coulomb", 2, 0.005, constant, "2-D coulomb u/R 0.005"),
        ("coulomb", 2, 0.05, constant, "2-D coulomb u/R 0.05"),
        ("vel", 2, 0.02, varying, "2-D vel u/R 0.02 N(t)"),
        ("vel", 2, 0.1, varying, "2-D vel u/R 0.1 N(t)"),
        ("vel", 2, 0.05, lifting, "2-D vel u/R 0.05 lift-off"),
    ]
    if quick:
        plan = [plan[i] for i in (1, 3, 6, 8, 9)]
    return [ElementCase(name, key, RADIUS, smooth_path(rng, amp * RADIUS, steps, h, dims), normal, h)
            for key, dims, amp, normal, name in plan]  # fmt: skip


def run_elements(quick: bool = False, seed: int = SEED) -> list[ElementRow]:
    return [case.run() for case in element_cases(quick, seed)]


def _opt(x) -> str:
    return "" if x is None else _pct(x)


def print_element_rows(rows: list[ElementRow], out=sys.stdout) -> None:
    print("(a) friction-pendulum(-vel) vs singleFPBearing (Coulomb / VelDependent), imposed paths, Newmark", file=out)
    print(f"{'case':30s} {'u/R':>6s} {'vs OpenSees max / RMS':>24s} {'OS vs LD':>9s} {'bfw vs SD':>9s} "
          f"{'R x10':>8s} {'inputs':>8s}  status", file=out)  # fmt: skip
    for r in rows:
        print(f"{r.case.name:30s} {r.u_over_r:6.3f} {_pct(r.force[0]):>11s} / {_pct(r.force[1]):>10s} "
              f"{_opt(r.os_vs_large):>9s} {_opt(r.bfw_vs_small):>9s} {_opt(r.scaled):>8s} {r.inputs:8.0e}  "
              f"{r.status}", file=out)  # fmt: skip


# --------------------------------------------------------------------------------------------
# (b) a rigid deck isolated on four friction pendulums

FP_RADIUS = 9.81 * (3.0 / (2 * math.pi)) ** 2  # T = 3 s: 2.24 m
FP_PARAMS = {"k": 4.0e8, "mu": 0.04}
FP_VERTICAL = {"b1": 3.0e9, "b2": 4.0e9, "b3": 5.0e9, "b4": 6.0e9}


def fp_deck_model(radius: float):
    from bearingfw.model import Connector, Model, NodalMass, Node, Support

    nodes = [Node("deck", 0.0, 0.0, 0.0)]
    connectors, supports = [], [Support("deck", ("rx", "ry", "rz"))]
    for name, kv in FP_VERTICAL.items():
        nodes.append(Node(f"{name}.seat", 0.0, 0.0, 0.0))
        supports.append(Support(f"{name}.seat"))
        connectors.append(Connector(name, f"{name}.seat", "deck", "planar", law="friction-pendulum",
                                    law_params={**FP_PARAMS, "R": radius}, vertical_stiffness=kv))  # fmt: skip
    return Model(nodes, connectors=connectors, supports=supports, masses=[NodalMass("deck", DECK_MASS)],
                 name="rigid deck on friction pendulums")  # fmt: skip


def fp_deck_bearingfw(ag, dt, radius: float, substeps: int = 2):
    from bearingfw.analysis import ConnectorResponse, NodalResponse, Rayleigh, TransientSettings, gravity
    from bearingfw.analysis import solve_transient

    model = fp_deck_model(radius)
    preload = gravity(model)
    settings = TransientSettings(alpha=0.0, dt_integration=dt / substeps)
    recorders = [NodalResponse(["deck"], "displacement", name="deck", every=substeps),
                 ConnectorResponse(list(FP_VERTICAL), name="bearings", every=substeps)]  # fmt: skip
    result = solve_transient(preload.system, ag, dt, settings=settings, damping=Rayleigh(DECK_DAMPING_A0, 0.0),
                             recorders=recorders, preload=preload)  # fmt: skip
    force, normal = result.data["bearings.force"], result.data["bearings.normal_force"]
    names = list(FP_VERTICAL)
    return ({b: force[:, k, :2] for k, b in enumerate(names)}, {b: normal[:, k] for k, b in enumerate(names)},
            result.data["deck"][:, 0] - result.data["deck"][0, 0])  # fmt: skip


def fp_deck_opensees(ag, dt, radius: float, substeps: int = 2, g: float = 9.81):
    """The deck of (b) in OpenSees: four ``singleFPBearing`` (Coulomb) from fixed seats to the deck
    node (rotations fixed: no P-Delta terms), ``-orient 0 0 1 1 0 0`` (axis vertical, shear X, Y)."""
    ops = _opensees.import_opensees()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.fix(1, 0, 0, 0, 1, 1, 1)
    ops.mass(1, DECK_MASS, DECK_MASS, DECK_MASS, 0.0, 0.0, 0.0)
    ops.uniaxialMaterial("Elastic", 100, 1e12)
    ops.frictionModel("Coulomb", 1, FP_PARAMS["mu"])
    tags = []
    for k, kv in enumerate(FP_VERTICAL.values()):
        seat, tag = 2 + k, 2 + k
        ops.node(seat, 0.0, 0.0, 0.0)
        ops.fix(seat, 1, 1, 1, 1, 1, 1)
        ops.uniaxialMaterial("Elastic", tag, kv)
        ops.element("singleFPBearing", tag, seat, 1, 1, radius, FP_PARAMS["k"], "-P", tag, "-T", 100, "-My", 100,
                    "-Mz", 100, "-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, *OS_ITER)  # fmt: skip
        tags.append(tag)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(1, 0.0, 0.0, -DECK_MASS * g, 0.0, 0.0, 0.0)
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

    def sample():
        q = [ops.eleResponse(t, "basicForce") for t in tags]
        return [*(v for qi in q for v in (qi[1], qi[2], -qi[0])), *ops.nodeDisp(1)[:3]]

    rows = [sample()]
    for step in range(len(ag) - 1):
        for _ in range(substeps):
            if ops.analyze(1, dt / substeps) != 0:
                raise RuntimeError(f"OpenSees deck model failed at step {step + 1}")
        rows.append(sample())
    ops.wipe()
    rows = np.array(rows)
    names = list(FP_VERTICAL)
    return ({b: rows[:, [3 * k, 3 * k + 1]] for k, b in enumerate(names)},
            {b: rows[:, 3 * k + 2] for k, b in enumerate(names)}, rows[:, -3:] - rows[0, -3:])  # fmt: skip


@dataclass
class DeckCase:
    rows: list
    u_over_r: float
    scaled_rows: list | None = None


def run_deck(quick: bool = False) -> DeckCase:
    """(b) at R = 2.24 m; if a row exceeds 1 %, again with R ten times larger (module docstring)."""
    ag, dt = deck_record(quick)

    def compare(radius, accel):
        force, normal, deck = fp_deck_bearingfw(accel, dt, radius)
        os_force, os_normal, os_deck = fp_deck_opensees(accel, dt, radius)
        u_over_r = float(np.linalg.norm(os_deck[:, :2], axis=1).max() / radius)
        rows = [_compare("bearing law force", force, os_force), _compare("bearing normal force", normal, os_normal),
                _compare("deck displacement", {"deck": deck}, {"deck": os_deck})]  # fmt: skip
        return rows, u_over_r

    rows, u_over_r = compare(FP_RADIUS, ag)
    case = DeckCase(rows, u_over_r)
    if not all(r.ok for r in rows):
        case.scaled_rows, _ = compare(10.0 * FP_RADIUS, ag)
    return case


def print_deck(case: DeckCase, out=sys.stdout) -> None:
    print(f"\n(b) rigid deck on four friction pendulums (R = {FP_RADIUS:.2f} m), Chuetsu-oki x/y/z, Newmark h = dt/2; "
          f"max |u|/R = {case.u_over_r:.3f}", file=out)  # fmt: skip
    print(f"{'quantity':22s} {'worst':6s} {'history max / RMS':>22s} {'peak, RMS values':>20s}  status", file=out)
    for k, r in enumerate(case.rows):
        status = "PASS" if r.ok else "FAIL"
        if not r.ok and case.scaled_rows is not None and case.scaled_rows[k].ok:
            status = f"EXPLAINED LARGE-DISPLACEMENT (R x10: {_pct(case.scaled_rows[k].max)})"
        print(f"{r.quantity:22s} {r.worst:6s} {_pct(r.max):>10s} / {_pct(r.rms):>9s} {_pct(r.peak):>9s}, "
              f"{_pct(r.level):>9s}  {status}", file=out)  # fmt: skip


def deck_ok(case: DeckCase) -> bool:
    return all(r.ok or (case.scaled_rows is not None and s.ok)
               for r, s in zip(case.rows, case.scaled_rows or case.rows, strict=True))  # fmt: skip


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
    print_deck(deck)
    ok = all(r.ok for r in rows) and deck_ok(deck)
    print(f"\n{time.perf_counter() - start:.1f} s; {'all within 1 % or explained' if ok else 'FAILED'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
