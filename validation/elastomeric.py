#!/usr/bin/env python
"""Validation of the lead-rubber law ``elastomeric-plasticity`` (plugin bearingfw-elastomeric)
against OpenSees's ``elastomericBearingPlasticity``.

    python validation/elastomeric.py            # every case (about 2.5 minutes of CPU)
    python validation/elastomeric.py --quick    # what tests/validation runs (about 20 s)

(a) The law alone, on seeded random displacement paths, against the OpenSees element
    (``ElastomericBearingPlasticity2d`` for dims = 1, ``...3d`` for dims = 2, two nodes at one
    point). OpenSees runs a *transient* analysis (Newmark, gamma = 1/2, beta = 1/4) in which node
    2's translations follow the path through ``sp`` constraints (Lagrange multipliers): the shear
    displacements are the path, the axial displacement imposes the normal force history N(t)
    through a stiff elastic axial material (compression negative in OpenSees). So OpenSees's
    element sees a velocity: the one its Newmark integrator derives from the displacements,
    ``v_n+1 = 2 (u_n+1 - u_n) / h - v_n``. bearingfw's law is driven with the same u, N and that
    same velocity (computed here and checked against OpenSees's ``nodeVel``), although neither
    code's shear force depends on N or velocity (the element passes velocity only to its
    axial/rotational materials). Each row prints the force difference (max and RMS over the
    history of ``|F_bfw - F_OS|`` over the peak ``|F_OS|``) and checks: the displacement, velocity
    and normal force OpenSees's element saw; the same OpenSees element in a static analysis
    (no velocity); and both codes against an independent reference, a scalar loop written in the
    *kinematic-hardening* form of the law (``F = k (u - u_p')``, ``|F - H u_p'| <= F_y``),
    which also checks the equivalence of the two forms the plugin's README states.
(b) A small isolated bridge: the 3-span twin-girder frame of ``_multispan`` (20 + 30 + 20 m,
    piers 6 m) with a lead-rubber bearing under each girder at each axis, under all three
    components of the Chuetsu-oki record (Matsushiro Tokamachi). "isolated": every bearing
    multidirectional (PLANAR), each designed for its own dead load (per-bearing parameters);
    "guided": the frame's usual layout (a fixed bearing at the middle axis, guided 1-D and free
    2-D ones) with one parameter set. bearingfw: ``solve_transient``; OpenSees: the same model
    built by ``_translate`` with the lead-rubber bearings' sliding directions left free and an
    ``elastomericBearingPlasticity`` element added at each (axial and rotational materials of
    zero stiffness: ``_translate``'s zeroLength carries the vertical spring, so the element's axial
    force, and with it its P-Delta moments, are zero). Peak and RMS bearing forces and deck
    displacements within 1 %, at HHT alpha = 0 and -0.05.

Parameter mapping (exact; see the plugin's README): OpenSees
``elastomericBearingPlasticity kInit qd alpha1 alpha2 mu`` with ``kInit = k``, ``qd = qd``,
``alpha1 = alpha``, ``alpha2 = 0`` (no nonlinear hardening, so ``mu`` plays no part; 2 is given
to keep ``|u|^(mu - 1)`` finite at u = 0).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from functools import cached_property
import importlib.util
from pathlib import Path

import attrs
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _multispan  # noqa: E402
import _opensees  # noqa: E402
import _translate  # noqa: E402
from _reference import proportional_path, random_path, relative_difference  # noqa: E402

import bearingfw  # noqa: E402


def _sibling(name: str):
    """This folder's ``name``.py by path: a plain ``import models`` could find another ``models``
    module first (the test suite has one) when this script runs inside pytest."""
    spec = importlib.util.spec_from_file_location(f"_validation_{name}", Path(__file__).resolve().parent / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses/attrs look the module up while it executes
    spec.loader.exec_module(module)
    return module


models = _sibling("models")
from bearingfw.analysis import gravity  # noqa: E402
from bearingfw.model import Connector, Model  # noqa: E402

TOLERANCE = 0.01
SEED = 20240614
LAW = "elastomeric-plasticity"
#: Newmark's constants of the OpenSees driver (trapezoidal rule).
NEWMARK = (0.5, 0.25)
#: Axial stiffness (N/m) through which the driver imposes N: N = -K_AXIAL * (axial displacement).
K_AXIAL = 1e13
#: Dead load (N) of the single-bearing cases: a pier bearing of a highway bridge.
DEAD_LOAD = 2.0e6


# --------------------------------------------------------------------------------------------
# Lead-rubber bearings of a highway bridge


def lrb_from_geometry(
    diameter: float, lead_diameter: float, rubber_thickness: float, shear_modulus: float,
    lead_yield_stress: float = 10e6, stiffness_ratio: float = 10.0,
) -> dict:  # fmt: skip
    """``{"k", "qd", "alpha"}`` of a circular lead-rubber bearing from its geometry (m) and materials (Pa).

    The textbook estimates (Naeim & Kelly 1999, ch. 4; Buckle et al. 2006, MCEER-06-SP07):
    ``Q_d = sigma_lead A_lead`` with an effective shear yield stress of lead of about 10 MPa,
    ``K_d = G A_rubber / T_rubber`` (the rubber's shear stiffness, G about 0.4-1.0 MPa), and an
    initial stiffness ``K_u`` about 10 ``K_d``.
    """
    lead_area = math.pi / 4 * lead_diameter**2
    rubber_area = math.pi / 4 * diameter**2 - lead_area
    post_yield = shear_modulus * rubber_area / rubber_thickness
    return {"k": stiffness_ratio * post_yield, "qd": lead_yield_stress * lead_area, "alpha": 1.0 / stiffness_ratio}


#: Two bearings: 650 mm with a 125 mm lead core, 150 mm of rubber, G = 0.8 MPa (K_u = 17.0 MN/m,
#: Q_d = 123 kN, u_y = 8.0 mm) and 900 mm with a 180 mm core, 200 mm of rubber, G = 0.55 MPa
#: (K_u = 16.8 MN/m, Q_d = 254 kN, u_y = 16.8 mm).
BEARINGS = {
    "D650": lrb_from_geometry(0.65, 0.125, 0.150, 0.8e6),
    "D900": lrb_from_geometry(0.90, 0.180, 0.200, 0.55e6),
}


def yield_displacement(p: dict) -> float:
    return p["qd"] / ((1.0 - p["alpha"]) * p["k"])


def opensees_args(p: dict, hardening: tuple[float, float] = (0.0, 2.0)) -> tuple:
    """``kInit qd alpha1 alpha2 mu`` of ``elastomericBearingPlasticity`` (module docstring);
    ``hardening`` = (alpha2, mu), OpenSees's nonlinear hardening, off for the comparisons."""
    return (float(p["k"]), float(p["qd"]), float(p["alpha"]), *map(float, hardening))


# --------------------------------------------------------------------------------------------
# (a) the law alone


def newmark_velocity(u: np.ndarray, h: float) -> np.ndarray:
    """The velocity Newmark's (gamma, beta) gives when the displacements ``u`` (steps, dims) are
    imposed from rest, as OpenSees's integrator computes it for a node under ``sp`` constraints."""
    gamma, beta = NEWMARK
    previous, v, a = np.zeros(u.shape[1]), np.zeros(u.shape[1]), np.zeros(u.shape[1])
    out = np.empty_like(u)
    for i, ui in enumerate(u):
        du = ui - previous
        a_next = du / (beta * h * h) - v / (beta * h) - (0.5 / beta - 1.0) * a
        v = v + h * ((1.0 - gamma) * a + gamma * a_next)
        a, previous = a_next, ui
        out[i] = v
    return out


def drive_opensees(
    p: dict, u: np.ndarray, normal: np.ndarray, h: float, transient: bool = True, hardening=(0.0, 2.0)
) -> dict:
    """Drive ``elastomericBearingPlasticity`` through the shear path ``u`` (steps, dims) with the
    normal force ``normal`` (steps,); returns its shear force, the normal force, displacement and
    velocity its node 2 had, each per step."""
    ops = _opensees.import_opensees()
    dims = u.shape[1]
    steps = len(u)
    axial = np.concatenate([[0.0], -normal / K_AXIAL])
    shear = np.vstack([np.zeros((1, dims)), u])
    ops.wipe()
    if dims == 1:
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0)
        ops.node(2, 0.0, 0.0)
        ops.fix(1, 1, 1, 1)
        ops.fix(2, 0, 0, 1)
        ops.uniaxialMaterial("Elastic", 1, K_AXIAL)
        ops.uniaxialMaterial("Elastic", 2, 0.0)
        # local x (axial) = global X, shear = global Y
        ops.element("elastomericBearingPlasticity", 1, 1, 2, *opensees_args(p, hardening), "-P", 1, "-Mz", 2,
                    "-orient", 1.0, 0.0, 0.0, 0.0, 1.0, 0.0)  # fmt: skip
        dofs = ((1, axial), (2, shear[:, 0]))
    else:
        ops.model("basic", "-ndm", 3, "-ndf", 6)
        ops.node(1, 0.0, 0.0, 0.0)
        ops.node(2, 0.0, 0.0, 0.0)
        ops.fix(1, 1, 1, 1, 1, 1, 1)
        ops.fix(2, 0, 0, 0, 1, 1, 1)
        ops.uniaxialMaterial("Elastic", 1, K_AXIAL)
        ops.uniaxialMaterial("Elastic", 2, 0.0)
        # local x (axial) = global X, shear y, z = global Y, Z
        ops.element("elastomericBearingPlasticity", 1, 1, 2, *opensees_args(p, hardening), "-P", 1, "-T", 2, "-My", 2,
                    "-Mz", 2, "-orient", 1.0, 0.0, 0.0, 0.0, 1.0, 0.0)  # fmt: skip
        dofs = ((1, axial), (2, shear[:, 0]), (3, shear[:, 1]))
    for dof, values in dofs:
        # a Path series is 0 after its last time: repeat the last value (see _opensees)
        ops.timeSeries("Path", dof, "-dt", h if transient else 1.0, "-values", *map(float, values), float(values[-1]))
        ops.pattern("Plain", dof, dof)
        ops.sp(2, dof, 1.0)
    ops.constraints("Lagrange")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    # Every translation is prescribed: the first iteration imposes it, the second the multipliers.
    ops.test("FixedNumIter", 2)
    ops.algorithm("Newton")
    if transient:
        ops.integrator("Newmark", *NEWMARK)
        ops.analysis("Transient")
    else:
        ops.integrator("LoadControl", 1.0)
        ops.analysis("Static")
    rows = []
    for i in range(steps):
        if (ops.analyze(1, h) if transient else ops.analyze(1)) != 0:
            raise RuntimeError(f"OpenSees failed at step {i + 1}")
        q = ops.eleResponse(1, "basicForce")
        d, v = ops.nodeDisp(2), ops.nodeVel(2)
        rows.append((q[1 : 1 + dims], -q[0], d[1 : 1 + dims], v[1 : 1 + dims]))
    ops.wipe()
    force, seen_normal, disp, vel = (np.array([r[k] for r in rows]) for k in range(4))
    return {"force": force, "normal": seen_normal, "displacement": disp, "velocity": vel}


def kinematic_hardening_reference(p: dict, u: np.ndarray) -> np.ndarray:
    """The force history of the law written as plasticity with linear kinematic hardening, one
    backward-Euler radial return per increment, as a plain scalar loop (module docstring):
    ``F = k (u - s)``, ``|F - H s| <= F_y``, ``H = alpha k / (1 - alpha)``, ``F_y = qd / (1 - alpha)``."""
    k, alpha = p["k"], p["alpha"]
    hardening, yield_force = alpha * k / (1.0 - alpha), p["qd"] / (1.0 - alpha)
    slip = [0.0] * u.shape[1]
    out = np.empty_like(u)
    for i, ui in enumerate(u):
        relative = [k * (x - s) - hardening * s for x, s in zip(ui, slip, strict=True)]
        size = math.sqrt(sum(r * r for r in relative))
        if size > yield_force:
            multiplier = (size - yield_force) / (k + hardening)
            slip = [s + multiplier * r / size for s, r in zip(slip, relative, strict=True)]
        out[i] = [k * (x - s) for x, s in zip(ui, slip, strict=True)]
    return out


@dataclass
class LawCase:
    """One bearing, one path, one normal-force history."""

    name: str
    bearing: str
    u: np.ndarray  # (steps, dims)
    normal: np.ndarray  # (steps,)
    h: float = 0.02

    @property
    def params(self) -> dict:
        return BEARINGS[self.bearing]

    @cached_property
    def velocity(self) -> np.ndarray:
        return newmark_velocity(self.u, self.h)

    @cached_property
    def bearingfw(self) -> np.ndarray:
        law = bearingfw.create_law(LAW, **self.params, dims=self.u.shape[1])
        state = law.initial_state(1)
        out = np.empty_like(self.u)
        for i in range(len(self.u)):
            step = slice(i, i + 1)
            response = law.respond(state, self.u[step], self.normal[step], self.h, velocity=self.velocity[step])
            out[i], state = response.force[0], response.state
        return out

    @cached_property
    def opensees(self) -> dict:
        return drive_opensees(self.params, self.u, self.normal, self.h)

    @cached_property
    def opensees_static(self) -> np.ndarray:
        return drive_opensees(self.params, self.u, self.normal, self.h, transient=False)["force"]

    @cached_property
    def reference(self) -> np.ndarray:
        return kinematic_hardening_reference(self.params, self.u)


@attrs.frozen
class LawRow:
    case: LawCase
    force: tuple  # (max, RMS) bearingfw vs OpenSees
    seen: float  # largest relative difference of the u, v, N that OpenSees's element saw from the imposed ones
    static: float  # OpenSees static vs transient (max)
    bfw_ref: float  # bearingfw vs the kinematic-hardening reference (max)
    os_ref: float  # OpenSees vs the reference (max)
    peak_ratio: float  # peak |u| / u_y

    @property
    def ok(self) -> bool:
        return max(self.force) <= TOLERANCE and self.seen <= 1e-9


def law_row(case: LawCase) -> LawRow:
    os = case.opensees
    scale = lambda a: max(float(np.abs(a).max()), 1e-300)  # noqa: E731
    seen = max(
        float(np.abs(os["displacement"] - case.u).max()) / scale(case.u),
        float(np.abs(os["velocity"] - case.velocity).max()) / scale(case.velocity),
        float(np.abs(os["normal"] - case.normal).max()) / scale(case.normal),
    )
    return LawRow(
        case,
        relative_difference(case.bearingfw, os["force"]),
        seen,
        relative_difference(case.opensees_static, os["force"])[0],
        relative_difference(case.bearingfw, case.reference)[0],
        relative_difference(os["force"], case.reference)[0],
        float(np.linalg.norm(case.u, axis=1).max() / yield_displacement(case.params)),
    )


def hardening_anisotropy(bearing: str = "D650", mu: float = 2.0, steps: int = 120) -> dict:
    """Evidence for leaving OpenSees's ``alpha2``/``mu`` hardening out: it acts per basic axis.

    The same random 1-D history of |u| (peak D = 10 u_y) driven along 0 and along 45 degrees; an
    isotropic bearing gives the same force magnitudes. ``alpha2 = alpha / D`` (with ``mu = 2``
    the hardening then doubles the post-yield stiffness at the peak along an axis). Returns the
    largest difference of the magnitudes over the peak, for OpenSees with (alpha2, mu) and
    without (alpha2 = 0)."""
    p = BEARINGS[bearing]
    rng = np.random.default_rng(SEED)
    peak = 10.0 * yield_displacement(p)
    alpha2 = p["alpha"] / peak
    s = random_path(rng, peak, steps)
    normal = np.full(steps, DEAD_LOAD)
    out = {}
    for label, hardening in (("alpha2 = 0", (0.0, 2.0)), (f"alpha2 = {alpha2:.3g}, mu = {mu:g}", (alpha2, mu))):
        size = []
        for angle in (0.0, 45.0):
            e = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
            force = drive_opensees(p, np.outer(s, e), normal, 0.02, transient=False, hardening=hardening)["force"]
            size.append(np.linalg.norm(force, axis=1))
        out[label] = relative_difference(size[1], size[0])[0]
    return out


def normal_history(rng, steps: int, kind: str) -> np.ndarray:
    """Constant dead load, a vertical tremor of +-40 %, or one whose dips reach tension (N < 0)."""
    if kind == "constant":
        return np.full(steps, DEAD_LOAD)
    t = np.arange(1, steps + 1) / steps
    swing = 0.4 if kind == "tremor" else 1.3
    return DEAD_LOAD * (1.0 + swing * np.sin(2.0 * np.pi * 5.0 * t + rng.uniform(0.0, 2.0 * np.pi)))


def law_cases(quick: bool = False, seed: int = SEED, steps: int | None = None) -> list[LawCase]:
    family = iter(np.random.SeedSequence(seed).spawn(3))
    steps = steps or (120 if quick else 300)
    cases = []
    rng = np.random.default_rng(next(family))
    for bearing in ("D650",) if quick else tuple(BEARINGS):
        uy = yield_displacement(BEARINGS[bearing])
        for amp in (3.0,) if quick else (0.5, 3.0, 20.0):
            u = random_path(rng, amp * uy, steps)[:, None]
            normal = normal_history(rng, steps, "tremor")
            cases.append(LawCase(f"1-D {bearing} {amp:g} uy, N(t) tremor", bearing, u, normal))
    rng = np.random.default_rng(next(family))
    paths = [("random", 3.0, "tremor"), ("random", 20.0, "tension")]
    if not quick:
        paths = [("random", 0.5, "constant"), ("random", 3.0, "tremor"), ("random", 20.0, "tremor"),
                 ("prop30", 10.0, "constant"), ("random", 10.0, "tension")]  # fmt: skip
    for bearing in ("D650",) if quick else tuple(BEARINGS):
        uy = yield_displacement(BEARINGS[bearing])
        for kind, amp, normal in paths:
            a = amp * uy
            u = random_path(rng, a, steps, dims=2) if kind == "random" else proportional_path(rng, a, steps, 30.0)
            name = f"2-D {bearing} {kind} {amp:g} uy, N(t) {normal}"
            cases.append(LawCase(name, bearing, u, normal_history(rng, steps, normal)))
    return cases


# --------------------------------------------------------------------------------------------
# (b) a small isolated bridge


def frame_dead_loads(frame: _multispan.Frame) -> dict[str, float]:
    """Each bearing's dead load (N) from a bearingfw gravity analysis with linear springs."""
    model = _multispan.frame_model(attrs.evolve(frame, law="linear-spring", params=(("k", 4e8),)))
    preload = gravity(model)
    return {c.name: preload.normal_force(c.name) for c in model.connectors}


def bridge_model(layout: str, per_span: int = 3) -> Model:
    """The ``_multispan`` frame on lead-rubber bearings (module docstring: "isolated" or "guided")."""
    from bearingfw_elastomeric import lead_rubber_parameters

    base = _multispan.Frame(per_span=per_span, law=LAW, params=tuple(BEARINGS["D650"].items()))
    model = _multispan.frame_model(base)
    if layout == "guided":
        return attrs.evolve(model, name=f"{model.name}, lead-rubber bearings (guided layout)")
    if layout != "isolated":
        raise ValueError(layout)
    dead = frame_dead_loads(base)
    connectors = []
    for c in model.connectors:
        # every bearing multidirectional, designed for its own dead load as the plugin's preset does
        params = lead_rubber_parameters(dead[c.name])
        connectors.append(Connector(c.name, c.node_i, c.node_j, "planar", law=LAW, law_params=params,
                                    vertical_stiffness=base.vertical_stiffness))  # fmt: skip
    return attrs.evolve(model, connectors=connectors, name=f"{model.name}, isolated on lead-rubber bearings")


def build_opensees(ops, model: Model, a1: float):
    """``_translate.build`` with the lead-rubber bearings' law directions free, then an
    ``elastomericBearingPlasticity`` element at each (module docstring). Returns the Built, whose
    ``bearings`` now name those elements (read like flat sliders: basic shear y, z = connector x, y)."""
    lrbs = {c.name: c for c in model.connectors if c.law == LAW}
    stand_in = [attrs.evolve(c, law="frictionless", law_params={}) if c.name in lrbs else c for c in model.connectors]
    built = _translate.build(ops, attrs.evolve(model, connectors=stand_in), a1=a1)
    zero = 10**6  # material tags of our own, clear of _translate's
    ops.uniaxialMaterial("Elastic", zero, 0.0)
    element = built.n_elements
    for name, c in lrbs.items():
        element += 1
        R = c.rotation
        ops.element("elastomericBearingPlasticity", element, built.nodes[c.node_i], built.nodes[c.node_j],
                    *opensees_args(dict(c.params)), "-P", zero, "-T", zero, "-My", zero, "-Mz", zero,
                    "-orient", *map(float, R[2]), *map(float, R[0]))  # fmt: skip
        built.bearings[name] = (element, "slider")
    return built


def bridge_rows(layout: str, ag: np.ndarray, dt: float, alpha: float, substeps: int, per_span: int = 3) -> list:
    """bearingfw and OpenSees on the same bridge under the same record: displacement and bearing-force rows."""
    model = bridge_model(layout, per_span)
    frame = _multispan.Frame(per_span=per_span)
    nodes = _multispan.response_nodes(frame)
    bearings = _multispan.sliding_bearings(model)
    preload, mode = models.comparable_preload(model)
    disp, force, _, _ = models._bearingfw_run(model, ag, dt, alpha, substeps, nodes, bearings, preload)
    ops = _translate.opensees()
    built = build_opensees(ops, model, a1=models.DAMPING.beta)
    _translate.gravity(ops, model, built)
    run = _translate.transient(ops, built, ag, dt, alpha=alpha, rayleigh=(models.DAMPING.alpha, models.DAMPING.beta),
                               nodes=nodes, bearings=bearings, substeps=substeps)  # fmt: skip
    ops.wipe()
    peak = {b: float(np.linalg.norm(force[b], axis=1).max()) for b in bearings}
    qd = {b: dict(model.connector(b).params)["qd"] for b in bearings}
    yielded = min(peak[b] / qd[b] for b in bearings)
    name = f"(b) bridge {layout} alpha={alpha:g} h=dt/{substeps}"
    return [
        attrs.evolve(models.compare(name, "displacement", disp, run.displacement), note=f"gravity: bearings {mode}"),
        attrs.evolve(models.compare(name, "bearing force", force, run.force),
                     note=f"min over bearings of |F|max/qd = {yielded:.2f}"),  # fmt: skip
    ]


def bridge_cases(quick: bool) -> list:
    window = (20.0, 23.0) if quick else (15.0, 35.0)
    ag, dt = models.record_window(*window)
    rows = []
    for layout in ("isolated",) if quick else ("isolated", "guided"):
        for alpha in (0.0,) if quick else (0.0, -0.05):
            rows += bridge_rows(layout, ag, dt, alpha, 2)
    return rows


# --------------------------------------------------------------------------------------------


def _pct(x):
    return f"{100 * x:.3f}%" if 100 * x >= 0.0005 or x == 0.0 else f"{100 * x:.0e}%"


def print_law_rows(rows: list[LawRow], out=sys.stdout) -> None:
    width = max(len(r.case.name) for r in rows)
    print("(a) elastomeric-plasticity vs elastomericBearingPlasticity on random paths (Newmark transient, N(t))\n"
          "    force: max / RMS of |F_bfw - F_OS| over peak |F_OS|;\n"
          "    seen: u, v, N of OpenSees's node vs the imposed ones; OS static: OpenSees static vs transient;\n"
          "    ref: the kinematic-hardening loop (max)\n", file=out)  # fmt: skip
    columns = f"{'force max':>9} {'force RMS':>9}  {'seen':>7}  {'OS static':>9}  {'bfw-ref':>8} {'OS-ref':>8}"
    header = f"{'case':<{width}}  {'|u|/uy':>6}  {columns}  status"
    print(header, file=out)
    for r in rows:
        values = f"{_pct(r.force[0]):>9} {_pct(r.force[1]):>9}  {r.seen:>7.0e}  {_pct(r.static):>9}  " \
                 f"{_pct(r.bfw_ref):>8} {_pct(r.os_ref):>8}"  # fmt: skip
        print(f"{r.case.name:<{width}}  {r.peak_ratio:>6.1f}  {values}  {'PASS' if r.ok else 'FAIL'}", file=out)


def run(quick: bool = False, seed: int = SEED, steps: int | None = None, bridge: bool = True):
    law_rows = [law_row(c) for c in law_cases(quick, seed, steps)]
    return law_rows, (bridge_cases(quick) if bridge else [])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a small subset of the cases")
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--steps", type=int, default=None, help="steps per path (default 300, quick 120)")
    parser.add_argument("--no-bridge", action="store_true", help="skip (b)")
    args = parser.parse_args(argv)
    _opensees.ensure_opensees()
    start = time.perf_counter()
    print(f"bearingfw {bearingfw.__version__} vs OpenSeesPy {_opensees.import_opensees().version()}")
    for key, p in BEARINGS.items():
        print(f"  {key}: k = {p['k'] / 1e6:.2f} MN/m, qd = {p['qd'] / 1e3:.1f} kN, alpha = {p['alpha']:g}, "
              f"uy = {1e3 * yield_displacement(p):.2f} mm")  # fmt: skip
    print()
    law_rows, bridge = run(args.quick, args.seed, args.steps, bridge=not args.no_bridge)
    print_law_rows(law_rows)
    if bridge:
        print("\n(b) the small bridge under the Chuetsu-oki record (max / RMS relative to the OpenSees history)")
        models.print_rows(bridge)
    print("\nEvidence for leaving OpenSees's alpha2/mu hardening out (it acts per axis):\n"
          "  largest difference of |F| along 45 and along 0 degrees, same |u| history")
    for label, value in hardening_anisotropy().items():
        print(f"  OpenSees {label}: {_pct(value)}")
    failed = [r.case.name for r in law_rows if not r.ok] + [f"{r.case} {r.quantity}" for r in bridge if not r.passed]
    print(f"\n{len(law_rows) + len(bridge)} comparisons, {len(failed)} failed, {time.perf_counter() - start:.1f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
