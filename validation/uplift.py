#!/usr/bin/env python
"""Validation of uplift: a girder on compression-only bearings, bearingfw against OpenSeesPy.

    python validation/uplift.py            # 12 s of the record (about a minute)
    python validation/uplift.py --quick    # 3 s around its strongest part (what tests/validation runs)

The model: a rigid girder (mass ``MASS``, rotary inertia ``INERTIA`` about y, centre of mass
``CG_X`` off the middle and ``CG_H`` above the bearings) on two bearings at ``x = -+HALF_SPAN``
(``Connector(uplift=True)``: compression-only vertical springs ``KV``), each with linear
horizontal springs ``K`` in x and y (PLANAR ``linear-spring``), moving in the x-z plane (its
centre of mass held in y, and in the rotations about x and z). Under the Manjil 1990
record (Abbar station, longitudinal and vertical components, examples/data/records/) scaled by
``SCALE`` (vertical peak about 1.6 g), both bearings lift off repeatedly, at different times
(the off-centre mass loads them unequally and the horizontal shaking rocks the girder).

OpenSees: the same five nodes, ``rigidLink beam`` from the centre of mass to the soffits (the
centre of mass held in y, rx and rz by ``zeroLength`` springs of stiffness ``HOLD`` to a fixed
node: with ``fix`` on the links' retained node, OpenSees's ``Transformation`` handler let the
girder fall through its bearings, and ``Lagrange`` stalls Newton at round-off), a
``zeroLength`` per bearing with ``Elastic K`` along x and ``ENT KV`` (elastic, no tension) along
z (and ``Elastic K`` along y), node mass and inertia, mass-proportional Rayleigh damping
(bearingfw: ``Rayleigh(A0, 0)``; the structure has no member stiffness, and neither code damps
the springs), a static gravity step
with the bearings active (bearingfw: ``gravity(bearings="active")``, the same state), then
``UniformExcitation`` in x and z, HHT (bearingfw ``alpha``, OpenSees ``1 + alpha``), the same
integration step, Newton with a line search.

Compared (the measures of validation/models.py: ``max_t |a - b| / max_t |b|`` and the RMS ratio,
``a`` bearingfw, ``b`` OpenSees): the centre of mass's displacement (x, z and the rotation about
y, each history), and each bearing's normal force ``N``, over the span in which the response is
predictable (:func:`compare`: a bouncing girder is chaotic; beyond that span bearingfw disagrees
with itself under a 1e-12 change of the record as much as with OpenSees). A row above 1 % fails.

What it shows (12 s, 4-16 s of the record; ``--quick``: 7.5-10.5 s): at ``alpha = 0`` the two
codes solve the same discrete equations and agree to about 1e-5 % over the predictable span
(the whole quick window, with a dozen lift-offs per bearing); at ``alpha = -0.05`` their HHT
forms differ for nonlinear elements (validation/models.py, ``HHT-FORM``: bearingfw weights the
forces, OpenSees interpolates the displacement) and agree within about 0.6 % at ``h = dt / 16``,
0.15 % at ``dt / 64``. The step matters: at ``h = dt / 4`` (0.005 s, ``omega h = 0.7`` for the
closed bearings' vertical mode) both codes chatter on contact, with three times the lift-offs.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import attrs
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _opensees  # noqa: E402

from bearingfw.analysis import (  # noqa: E402
    ConnectorResponse,
    NodalResponse,
    Rayleigh,
    TransientSettings,
    gravity,
    solve_transient,
)
from bearingfw.model import Connector, Model, NodalMass, Node, RigidLink, Support  # noqa: E402
from bearingfw.motion import read_record  # noqa: E402

TOLERANCE = 0.01
RECORDS = Path(__file__).resolve().parents[1] / "examples" / "data" / "records"  # the same PEER files as shared/records
MANJIL = ("RSN1633_MANJIL_ABBAR--L.AT2", "RSN1633_MANJIL_ABBAR--T.AT2", "RSN1633_MANJIL_ABBAR--V.AT2")
SCALE = 2.0  # vertical peak 0.54 g -> 1.08 g
G = 9.81

MASS = 2.0e5  # kg: a 20 m girder
INERTIA = MASS * 20.0**2 / 12  # kg m^2 about y
HALF_SPAN = 10.0  # bearings at x = -+10 m
CG_X, CG_H = 2.0, 1.5  # centre of mass off the middle (the right bearing carries 60 %) and above the bearings
K = 2.0e7  # N/m, horizontal spring of each bearing
KV = 2.0e9  # N/m, vertical stiffness of each bearing (closed)
A0 = 0.5  # 1/s, mass-proportional damping
HOLD = 1e15  # OpenSees: the springs that hold the girder's out-of-plane motion
#: integration steps per record step (0.02 s / 16): the bearings' vertical mode (about 21 Hz
#: closed) needs a fine step to resolve the contacts (module docstring)
SUBSTEPS = 16
BEARINGS = ("left", "right")


def record_window(start: float, stop: float, taper: float = 0.5) -> tuple[np.ndarray, float]:
    """Manjil 1990, Abbar: longitudinal -> global x, vertical -> z (transverse left out), times
    ``SCALE``, from ``start`` to ``stop`` s, cosine-tapered over ``taper`` s at both ends and
    starting from a zero sample (both codes start at rest). Returns ((n, 3) m/s^2, dt)."""
    record = read_record([RECORDS / f for f in MANJIL])
    t = record.time
    keep = (t >= start) & (t <= stop)
    ag = np.zeros((int(keep.sum()), 3))
    ag[:, 0], ag[:, 2] = record.components[0][keep], record.components[2][keep]
    ramp = np.minimum(1.0, np.minimum(t[keep] - start, stop - t[keep]) / taper)
    ag *= SCALE * (0.5 - 0.5 * np.cos(np.pi * np.clip(ramp, 0.0, 1.0)))[:, None]
    return np.vstack([np.zeros((1, 3)), ag]), record.dt


def girder_model() -> Model:
    """The rigid girder on two uplift bearings (module docstring)."""
    nodes = [Node("CG", CG_X, 0.0, CG_H)]
    links, connectors, supports = [], [], [Support("CG", ("uy", "rx", "rz"))]
    for name, x in zip(BEARINGS, (-HALF_SPAN, HALF_SPAN), strict=True):
        nodes += [Node(f"S{name}", x, 0.0, 0.0), Node(f"P{name}", x, 0.0, 0.0)]
        links.append(RigidLink(f"link {name}", "CG", f"S{name}"))
        connectors.append(Connector(name, f"P{name}", f"S{name}", "planar", law="linear-spring", law_params={"k": K},
                                    vertical_stiffness=KV, uplift=True))  # fmt: skip
        supports.append(Support(f"P{name}"))
    return Model(nodes, connectors=connectors, rigid_links=links, supports=supports,
                 masses=[NodalMass("CG", MASS, iyy=INERTIA)])  # fmt: skip


@attrs.frozen(eq=False)
class Histories:
    """Sampled at the record's steps: the centre of mass's (ux, uz, ry) (dynamic part) and each
    bearing's normal force."""

    displacement: np.ndarray  # (t, 3)
    normal_force: np.ndarray  # (t, 2)


def bearingfw_run(ag: np.ndarray, dt: float, alpha: float, substeps: int, path: str = "fast"):
    model = girder_model()
    preload = gravity(model, bearings="active")
    result = solve_transient(
        preload.system, ag, dt, preload=preload, damping=Rayleigh(A0, 0.0),
        settings=TransientSettings(alpha=alpha, dt_integration=dt / substeps, tol_force=1e-10, tol_displacement=1e-12,
                                   path=path),
        recorders=[NodalResponse(["CG"], "displacement", components=("ux", "uz", "ry"), name="cg", every=substeps),
                   ConnectorResponse(BEARINGS, name="bearings", every=substeps)],
    )  # fmt: skip
    return Histories(result["cg"][:, 0], result["bearings.normal_force"]), result


def opensees_run(ag: np.ndarray, dt: float, alpha: float, substeps: int) -> Histories:
    ops = _opensees.import_opensees()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, CG_X, 0.0, CG_H)
    ops.mass(1, MASS, MASS, MASS, 0.0, INERTIA, 0.0)
    # the centre of mass held in y, rx and rz by stiff springs to a fixed node (module docstring)
    ops.node(9, CG_X, 0.0, CG_H)
    ops.fix(9, 1, 1, 1, 1, 1, 1)
    ops.uniaxialMaterial("Elastic", 3, HOLD)
    ops.element("zeroLength", 9, 9, 1, "-mat", 3, 3, 3, "-dir", 2, 4, 6)
    ops.uniaxialMaterial("Elastic", 1, K)
    ops.uniaxialMaterial("ENT", 2, KV)  # elastic, no tension: compression-only
    for k, x in enumerate((-HALF_SPAN, HALF_SPAN)):
        soffit, seat = 2 + 2 * k, 3 + 2 * k
        ops.node(soffit, x, 0.0, 0.0)
        ops.node(seat, x, 0.0, 0.0)
        ops.fix(seat, 1, 1, 1, 1, 1, 1)
        ops.rigidLink("beam", 1, soffit)
        # zeroLength from the seat to the soffit: its deformation along z is u_soffit - u_seat (< 0 pressed)
        ops.element("zeroLength", 10 + k, seat, soffit, "-mat", 1, 1, 2, "-dir", 1, 2, 3)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(1, 0.0, 0.0, -MASS * G, 0.0, 0.0, 0.0)
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-13, 100)
    ops.algorithm("NewtonLineSearch")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees gravity step failed")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    start = np.array([ops.nodeDisp(1, d) for d in (1, 3, 5)])
    for tag, component in ((2, 0), (3, 2)):
        ops.timeSeries("Path", tag, "-dt", float(dt), "-values", *map(float, ag[:, component]))
        ops.pattern("UniformExcitation", tag, 1 if component == 0 else 3, "-accel", tag)
    ops.rayleigh(A0, 0.0, 0.0, 0.0)
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-13, 100)
    ops.algorithm("NewtonLineSearch")
    ops.integrator("HHT", 1.0 + alpha)
    ops.analysis("Transient")

    def sample():
        disp = np.array([ops.nodeDisp(1, d) for d in (1, 3, 5)]) - start
        # the zeroLength's basic force along z (second -dir): > 0 in tension, never for ENT
        normal = [-ops.eleResponse(10 + k, "basicForce")[2] for k in range(2)]
        return disp, normal

    rows = [sample()]
    for step in range(len(ag) - 1):
        for _ in range(substeps):
            if ops.analyze(1, dt / substeps) != 0:
                raise RuntimeError(f"OpenSees transient failed at step {step + 1}")
        rows.append(sample())
    ops.wipe()
    return Histories(np.array([r[0] for r in rows]), np.array([r[1] for r in rows]))


def differences(a, b) -> tuple[float, float]:
    """``(max_t |a - b| / max_t |b|, rms_t |a - b| / rms_t |b|)`` of one history."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    diff = np.abs(a - b)
    return float(diff.max() / np.abs(b).max()), float(np.sqrt(np.mean(diff**2) / np.mean(b**2)))


def departure(a: np.ndarray, b: np.ndarray, level: float) -> int | None:
    """The first sample at which two histories of normal forces (t, bearings) differ by more than
    ``level`` of their peak, or None."""
    d = np.max(np.abs(a - b), axis=1) / np.max(np.abs(b))
    later = np.flatnonzero(d > level)
    return int(later[0]) if later.size else None


@attrs.frozen
class Row:
    quantity: str
    max: float
    rms: float

    @property
    def within(self) -> bool:
        return max(self.max, self.rms) <= TOLERANCE


@attrs.frozen(eq=False)
class Comparison:
    """bearingfw against OpenSees up to ``horizon`` (record samples), the span over which the
    response is predictable (:func:`compare`); ``beyond``: the rows over the whole window."""

    rows: tuple[Row, ...]
    beyond: tuple[Row, ...]
    horizon: int
    samples: int
    ours: Histories
    theirs: Histories
    uplift: dict  # bearingfw's uplift summary
    lifted_steps: tuple[int, int]  # record samples with each bearing lifted in OpenSees (N = 0)

    @property
    def lift_offs_compared(self) -> tuple[int, ...]:
        """Lift-offs of each bearing within the compared span (bearingfw's samples: N falls to 0)."""
        lifted = self.ours.normal_force[: self.horizon] <= 0.0
        return tuple(int(n) for n in np.sum(~lifted[:-1] & lifted[1:], axis=0))


def _rows(ours: Histories, theirs: Histories, stop: int) -> tuple[Row, ...]:
    rows = [Row(f"centre of mass {c}", *differences(ours.displacement[:stop, k], theirs.displacement[:stop, k]))
            for k, c in enumerate(("ux", "uz", "ry"))]  # fmt: skip
    rows += [Row(f"N of bearing {b}", *differences(ours.normal_force[:stop, k], theirs.normal_force[:stop, k]))
             for k, b in enumerate(BEARINGS)]  # fmt: skip
    return tuple(rows)


#: Relative perturbation of the record that measures the response's sensitivity at alpha = 0 (:func:`compare`).
PERTURBATION = 1e-12
#: The predictable span ends where the perturbed run departs by this fraction of the peak N.
PREDICTABLE = 1e-3


def compare(window: tuple[float, float], alpha: float = 0.0, substeps: int = SUBSTEPS) -> Comparison:
    """Both codes under the record window; the rows over the predictable span.

    A girder bouncing on its bearings is sensitive to its initial conditions like a ball on a
    vibrating table: the gap at each impact depends on the previous flight, and an impact
    amplifies a difference. At ``alpha = 0`` both codes solve the same equations, and what
    separates them is round-off and Newton tolerances: bearingfw runs again with the record scaled
    by ``1 + PERTURBATION``, and the predictable span ends where that run departs from the first
    by ``PREDICTABLE`` of the peak normal force. Beyond it two correct codes need not agree, and
    the rows there (``beyond``) are evidence, not a criterion. At ``alpha != 0`` the codes' HHT
    forms differ by ``O(h)`` (module docstring): no such span is computed (``horizon`` is the
    whole window), so compare a window without chaotic bouncing (``--quick``'s).
    """
    ag, dt = record_window(*window)
    ours, result = bearingfw_run(ag, dt, alpha, substeps)
    theirs = opensees_run(ag, dt, alpha, substeps)
    gone = None
    if alpha == 0.0:
        perturbed, _ = bearingfw_run(ag * (1.0 + PERTURBATION), dt, alpha, substeps)
        gone = departure(perturbed.normal_force, ours.normal_force, PREDICTABLE)
    horizon = len(ag) if gone is None else gone
    lifted = tuple(int(np.sum(theirs.normal_force[:, k] <= 0.0)) for k in range(2))
    return Comparison(_rows(ours, theirs, horizon), _rows(ours, theirs, len(ag)), horizon, len(ag), ours, theirs,
                      result.uplift, lifted)  # fmt: skip


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="3 s around the strongest vertical shaking")
    args = parser.parse_args(argv)
    _opensees.ensure_opensees()
    start = time.perf_counter()
    quick, whole = (7.5, 10.5), (4.0, 16.0)
    cases = [(quick, 0.0), (quick, -0.05)] if args.quick else [(whole, 0.0), (quick, -0.05), (quick, 0.0)]
    failed = 0
    for window, alpha in cases:
        c = compare(window, alpha)
        _, dt = record_window(*window)
        print(f"Manjil 1990 (Abbar) x {SCALE:g}, {window[0]:g}-{window[1]:g} s, HHT alpha = {alpha:g}, "
              f"h = {dt / SUBSTEPS:g} s")  # fmt: skip
        print(f"  bearingfw's uplift summary: {c.uplift}")
        print(f"  record samples with N = 0 in OpenSees: {dict(zip(BEARINGS, c.lifted_steps, strict=True))}")
        span = window[0] + dt * (c.horizon - 1)
        where = "the whole window" if c.horizon == c.samples else f"up to t = {span:.2f} s, where it is predictable"
        print(f"  compared over {where} ({c.horizon} of {c.samples} samples); lift-offs there (sampled): "
              f"{dict(zip(BEARINGS, c.lift_offs_compared, strict=True))}")  # fmt: skip
        for r, whole in zip(c.rows, c.beyond, strict=True):
            print(f"  {r.quantity:<22} max {100 * r.max:8.4f} %   RMS {100 * r.rms:8.4f} %   "
                  f"{'PASS' if r.within else 'FAIL'}   (whole window: max {100 * whole.max:.2f} %)")  # fmt: skip
        failed += sum(not r.within for r in c.rows)
    print(f"{failed} failed, {time.perf_counter() - start:.1f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
