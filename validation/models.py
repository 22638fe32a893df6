#!/usr/bin/env python
"""Validation (b) and (c): whole models in bearingfw and in OpenSeesPy under a real record.

    python validation/models.py            # every case (a few minutes)
    python validation/models.py --quick    # short record windows (what tests/validation runs)

Cases:

(b1) SDOF: a mass on a massless elastic column (the paper's pillar, K_c = 147 MN/m, f = 1.87 Hz)
     and, in parallel, a regularized-Coulomb bearing to the ground (AXIAL, guided along x) under
     the x component of a real record. OpenSees: a hand-written 2-D model, ``elasticBeamColumn``
     plus ``zeroLength`` with ``ElasticPP(E = k, epsyP = mu N / k)``, N the bearing's dead-load
     normal force from bearingfw's preload (constant: the record has no vertical component here).
(b2) a three-span, twin-girder 3-D frame on piers and abutments with fixed, guided (1-D) and
     multidirectional (2-D) regularized-Coulomb bearings under all three components of the record;
     OpenSees gets the same model through ``_translate.build`` (flatSliderBearing, N(t) from its
     axial spring). Also with linear-spring bearings (a linear check of the whole chain: mass,
     damping, gravity, excitation, HHT).
(c)  modal frequencies: the (b2) frame with rigid offsets (bearings at the girder soffit) and
     linear-spring / frictionless bearings, and the reference bridge (M0, M1, fixed), against
     OpenSees ``eigen``.

Both sides: the same HHT (bearingfw alpha, OpenSees ``HHT 1 + alpha``), the same step, the same
Rayleigh damping (``C = a0 M + a1 K`` of the linear structure: members and the bearings'
vertical springs, not the laws), consistent member mass, the gravity preload first. Each
time-history row compares a node's displacement (the dynamic part, the translation vector) or a
bearing's law force (vector in its law directions) and prints

    max  = max_t |a - b| / max_t |b|      RMS = rms_t |a - b| / rms_t |b|

with ``a`` bearingfw, ``b`` OpenSees and ``|.|`` the Euclidean norm at each step; the case's
row is the largest over its nodes and bearings. Modal rows: ``|f_a / f_b - 1|``, largest over
the modes. A row above 1 % fails (exit code 1) unless the refinement evidence (``--evidence``:
both codes with the step cut by 4) shows which side is right; see validation/README.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import attrs
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _multispan  # noqa: E402
import _translate  # noqa: E402

import bearingfw  # noqa: E402
from bearingfw.analysis import (  # noqa: E402
    ConnectorResponse,
    NodalResponse,
    Rayleigh,
    TransientSettings,
    gravity,
    solve_modal,
    solve_transient,
)
from bearingfw.model import (  # noqa: E402
    Connector,
    FrameElement,
    Material,
    Model,
    NodalMass,
    Node,
    Section,
    Support,
)
from bearingfw.motion import read_record  # noqa: E402

TOLERANCE = 0.01
RECORDS = Path(__file__).resolve().parents[1] / "examples" / "data" / "records"
CHUETSU = ("RSN4843_CHUETSU_65006EW.AT2", "RSN4843_CHUETSU_65006NS.AT2", "RSN4843_CHUETSU_65006UD.AT2")
#: The paper's damping (Rayleigh from 2.1 % at 1.50 Hz and 2.7 % at 3.36 Hz).
DAMPING = Rayleigh(0.21, 0.00208)


# --------------------------------------------------------------------------------------------
# The record


def record_window(start: float, stop: float, taper: float = 0.5) -> tuple[np.ndarray, float]:
    """Chuetsu-oki 2007, Matsushiro Tokamachi (EW, NS, UD -> global x, y, z), from ``start`` to
    ``stop`` s, cosine-tapered over ``taper`` s at both ends and starting from a zero sample, so
    that both codes start at rest. Returns (samples (n, 3) in m/s^2, dt)."""
    record = read_record([RECORDS / f for f in CHUETSU])
    t = record.time
    keep = (t >= start) & (t <= stop)
    ag = record.components.T[keep].copy()
    ramp = np.minimum(1.0, np.minimum(t[keep] - start, stop - t[keep]) / taper)
    ag *= (0.5 - 0.5 * np.cos(np.pi * np.clip(ramp, 0.0, 1.0)))[:, None]
    return np.vstack([np.zeros((1, 3)), ag]), record.dt


# --------------------------------------------------------------------------------------------
# Difference measures


def differences(a, b) -> tuple[float, float]:
    """``(max_t |a - b| / max_t |b|, rms_t |a - b| / rms_t |b|)``, rows are vectors (module docstring)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    a, b = a.reshape(len(a), -1), b.reshape(len(b), -1)
    diff = np.linalg.norm(a - b, axis=1)
    size = np.linalg.norm(b, axis=1)
    if size.max() == 0.0:
        return (0.0, 0.0) if diff.max() == 0.0 else (np.inf, np.inf)
    return float(diff.max() / size.max()), float(np.sqrt(np.mean(diff**2) / np.mean(size**2)))


@attrs.frozen
class Row:
    case: str
    quantity: str
    worst: str  # which history gave the largest difference
    max: float
    rms: float
    note: str = ""
    #: an explanation (a key of EXPLANATIONS) whose evidence held in this run, for a row above 1 %
    explained: str = ""
    #: (max, RMS) outside the windows after OpenSees's stale slips, where they were looked for
    outside: tuple | None = None

    @property
    def within(self) -> bool:
        return max(self.max, self.rms) <= TOLERANCE

    @property
    def passed(self) -> bool:
        return self.within or bool(self.explained)

    @property
    def status(self) -> str:
        return "PASS" if self.within else f"EXPLAINED {self.explained}" if self.explained else "FAIL"


#: Why a row may exceed 1 %; each is accepted only where its evidence is computed and holds.
EXPLANATIONS = {
    "OS-STALE-SLIP": (
        "OpenSees's flatSliderBearing (FlatSliderSimple3d::update) does not reset its trial slip in the "
        "elastic branch: a step whose Newton iterates pass through sliding and end in stick commits the "
        "slip of the sliding iterate, so the next step starts from a slip the converged state never had "
        "(a force jump k0 * dslip with no motion). Evidence: such jumps found in the OpenSees histories "
        "(the implied slip u - q/k0 changes between two stick steps); outside the intervals from each one "
        "until that bearing slides again (which resets its force to mu N), plus 0.4 s, both codes agree "
        "within 1 %; and at rest after gravity (no ground motion) OpenSees's model moves while "
        "bearingfw's stays still."
    ),
    "HHT-FORM": (
        "With alpha != 0 the two codes' HHT differ for nonlinear elements: bearingfw weights the law forces, "
        "(1 + alpha) f(u_n+1) - alpha f(u_n) (Hilber, Hughes and Taylor's form); OpenSees evaluates the "
        "element at the interpolated displacement u_n+1+alpha (its HHT::update). Both are consistent and "
        "differ by O(h) at stick-slip transitions. Evidence: with the step halved on both sides the "
        "difference falls within 1 % (and at alpha = 0 the codes agree to round-off)."
    ),
}


def compare(case: str, quantity: str, ours: dict, theirs: dict) -> Row:
    """The largest differences over the histories of ``ours`` and ``theirs`` (same keys)."""
    pairs = {k: differences(ours[k], theirs[k]) for k in ours}
    worst = max(pairs, key=lambda k: max(pairs[k]))
    return Row(case, quantity, worst, max(p[0] for p in pairs.values()), max(p[1] for p in pairs.values()))


# --------------------------------------------------------------------------------------------
# (b1) SDOF

SDOF_H = 5.9  # pillar height (m)
SDOF_KC = 147e6  # its bending stiffness (N/m), 3 E I / h^3
SDOF_I = 1.4**4 / 12
SDOF_E = SDOF_KC * SDOF_H**3 / (3 * SDOF_I)
SDOF_MASS = SDOF_KC / (2 * np.pi * 1.87) ** 2
SDOF_A, SDOF_J = 1.96, 0.2
SDOF_BEARING = {"k": 4e8, "mu": 0.04}
SDOF_KV = 5e9


def sdof_model() -> Model:
    column = Section("pillar", A=SDOF_A, Iy=SDOF_I, Iz=SDOF_I, J=SDOF_J)
    massless = Material("massless concrete", SDOF_E, density=0.0)
    return Model(
        [Node("base", 0, 0, 0), Node("top", 0, 0, SDOF_H), Node("ground", 0, 0, SDOF_H)],
        [FrameElement("column", "base", "top", column, massless)],
        [Connector("bearing", "ground", "top", "axial", guided="x", law="regularized-coulomb",
                   law_params=SDOF_BEARING, vertical_stiffness=SDOF_KV)],
        supports=[Support("base"), Support("ground"), Support("top", ("uy", "rx", "rz"))],
        masses=[NodalMass("top", SDOF_MASS)],
    )  # fmt: skip


def _bearingfw_run(model, ag, dt, alpha, substeps, nodes, bearings, preload=None):
    preload = gravity(model) if preload is None else preload
    settings = TransientSettings(alpha=alpha, dt_integration=dt / substeps)
    # record at the record's samples only (every ``substeps``-th integration step), as OpenSees does
    recorders = [NodalResponse(nodes, "displacement", name="disp", every=substeps)]
    if bearings:
        recorders.append(ConnectorResponse(bearings, name="bearings", every=substeps))
    result = solve_transient(preload.system, ag, dt, settings=settings, damping=DAMPING, recorders=recorders,
                             preload=preload)  # fmt: skip
    model_ = preload.system.model
    disp = {n: result.data["disp"][:, k] for k, n in enumerate(nodes)}
    force = result.data.get("bearings.force")
    law_force = {b: force[:, k, list(model_.connector(b).law_directions)] for k, b in enumerate(bearings)}
    return disp, law_force, result, preload


def sdof_opensees(ag_x, dt, alpha, substeps, normal_force):
    """The hand-written OpenSees SDOF (2-D): column + zeroLength ElasticPP; returns (disp, force)."""
    ops = _translate.opensees()
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, SDOF_H)
    ops.node(3, 0.0, SDOF_H)
    ops.fix(1, 1, 1, 1)
    ops.fix(3, 1, 1, 1)
    ops.mass(2, SDOF_MASS, SDOF_MASS, 0.0)
    ops.geomTransf("Linear", 1)
    ops.element("elasticBeamColumn", 1, 1, 2, SDOF_A, SDOF_E, SDOF_I, 1)
    k, mu = SDOF_BEARING["k"], SDOF_BEARING["mu"]
    ops.uniaxialMaterial("ElasticPP", 1, k, mu * normal_force / k)
    ops.element("zeroLength", 2, 3, 2, "-mat", 1, "-dir", 1)
    ops.timeSeries("Path", 1, "-dt", float(dt), "-values", *_translate.path_values(ag_x))
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.rayleigh(DAMPING.alpha, 0.0, DAMPING.beta, 0.0)  # the column only: zeroLength takes none
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("HHT", _translate.opensees_alpha(alpha))
    ops.analysis("Transient")
    rows = [(0.0, 0.0)]
    for step in range(len(ag_x) - 1):
        for _ in range(substeps):
            if ops.analyze(1, dt / substeps) != 0:
                raise RuntimeError(f"OpenSees SDOF failed at step {step + 1}")
        # element forces on (node 3, node 2), x y rz each: on node 2 it is the force resisting u_2 - u_3
        rows.append((ops.nodeDisp(2, 1), ops.eleResponse(2, "force")[3]))
    ops.wipe()
    rows = np.array(rows)
    return rows[:, 0], rows[:, 1]


def case_sdof(ag, dt, alpha, substeps) -> list[Row]:
    model = sdof_model()
    x_only = np.column_stack([ag[:, 0], np.zeros(len(ag)), np.zeros(len(ag))])
    disp, force, _, preload = _bearingfw_run(model, x_only, dt, alpha, substeps, ["top"], ["bearing"])
    normal = preload.normal_force("bearing")
    os_disp, os_force = sdof_opensees(ag[:, 0], dt, alpha, substeps, normal)
    name = f"(b1) SDOF alpha={alpha:g} h=dt/{substeps}"
    slid = float(np.max(np.abs(force["bearing"])) / (SDOF_BEARING["mu"] * normal))
    return [
        compare(name, "displacement", {"top": disp["top"][:, 0]}, {"top": os_disp}),
        attrs.evolve(compare(name, "bearing force", force, {"bearing": os_force}), note=f"|F|max/(mu N) = {slid:.3f}"),
    ]


# --------------------------------------------------------------------------------------------
# (b2) multi-span frame


def comparable_preload(model):
    """bearingfw's gravity preload in the state OpenSees's gravity step reaches.

    bearingfw sets the bearings after the dead load by default (zero law force there); OpenSees's
    bearings act during its gravity step. The two coincide when the dead load moves no bearing
    horizontally (bearings on the girder axis of a straight symmetric frame); otherwise (rigid
    offsets: the girder's rotation moves the soffit) bearingfw's ``bearings="active"`` is the same
    analysis as OpenSees's: the laws from their virgin state, one load step. Returns the preload
    and which option it used."""
    preload = gravity(model)
    if np.abs(preload.law_reference).max(initial=0.0) < 1e-9:
        return preload, "set-after-dead-load"
    return gravity(model, bearings="active"), "active"


def stale_slips(run, k0: float, mu: float) -> tuple[list[tuple[int, int]], float]:
    """Where an OpenSees flat slider starts from a slip its last step never had, and how long that lasts.

    In a stick step the force is ``k0 (u - s)`` with ``s`` the slip committed by the step before, so
    ``s = u - q / k0`` (per slider, basic shear directions). Two consecutive stick steps must show
    the same ``s``; a change means the first of them committed a slip from a sliding Newton iterate
    (EXPLANATIONS["OS-STALE-SLIP"]). The wrong slip stays until the slider slides again, which
    sets its force back to ``mu N``. Returns the intervals ``(first step with the wrong slip, next
    sliding step)`` in integration steps (``run.sliders`` has every one) and the largest force jump
    ``k0 |ds|`` (N).
    """
    intervals, largest = [], 0.0
    for q, u in run.sliders.values():
        shear = q[:, 1:3]
        stick = np.linalg.norm(shear, axis=1) < (1.0 - 1e-9) * mu * -q[:, 0]
        slip = u[:, 1:3] - shear / k0
        jump = k0 * np.linalg.norm(np.diff(slip, axis=0), axis=1)
        found = np.flatnonzero(stick[1:] & stick[:-1] & (jump > 1e-6 * k0 * np.abs(slip).max(initial=1e-3) + 1.0))
        sliding = np.flatnonzero(~stick)
        for k in found + 1:
            later = sliding[sliding > k]
            intervals.append((int(k), int(later[0]) if later.size else len(stick)))
        largest = max(largest, float(jump[found].max(initial=0.0)))
    return sorted(intervals), largest


def _outside(histories: dict, intervals, span: int) -> dict:
    """The histories without the samples of ``intervals`` (record samples) and ``span`` more after each."""
    keep = np.ones(len(next(iter(histories.values()))), dtype=bool)
    for first, last in intervals:
        keep[first : last + span] = False
    return {name: np.asarray(h)[keep] for name, h in histories.items()}


def case_model(name, model, nodes, bearings, ag, dt, alpha, substeps, friction=None) -> list[Row]:
    """A 3-D model under all three components, bearingfw against ``_translate``'s OpenSees model.

    ``friction``: ``(k0, mu)`` of its regularized-Coulomb bearings, to look for OpenSees's stale
    slips (:func:`stale_slips`) when a row exceeds 1 %. A row of ``alpha != 0`` still above
    1 % is run again with the step halved (EXPLANATIONS["HHT-FORM"]).
    """
    rows = _case_model(name, model, nodes, bearings, ag, dt, alpha, substeps, friction)
    if alpha == 0.0 or all(r.passed for r in rows):
        return rows
    finer = _case_model(name, model, nodes, bearings, ag, dt, alpha, 2 * substeps, friction)
    out = []
    for row, fine in zip(rows, finer, strict=True):
        if row.passed:
            out.append(row)
            continue
        # the difference left outside OpenSees's stale-slip windows, at this step and at half of it
        now, then = _rest(row), _rest(fine)
        note = f"{row.note}; with h/2: max {fine.max:.2%}, RMS {fine.rms:.2%}" + (
            f" (outside stale slips {then[0]:.2%} / {then[1]:.2%})" if fine.outside is not None else ""
        )
        stale_mattered = row.outside is not None and row.outside[0] < 0.9 * row.max
        reasons = ("OS-STALE-SLIP", "HHT-FORM") if stale_mattered else ("HHT-FORM",)
        explained = "+".join(reasons) if max(then) <= TOLERANCE and max(then) < max(now) else ""
        out.append(attrs.evolve(row, note=note, explained=explained))
    return out


def _rest(row: Row) -> tuple[float, float]:
    """The row's (max, RMS) outside OpenSees's stale-slip windows if it has them, else its own."""
    return row.outside if row.outside is not None else (row.max, row.rms)


def _case_model(name, model, nodes, bearings, ag, dt, alpha, substeps, friction=None) -> list[Row]:
    preload, mode = comparable_preload(model)
    disp, force, _, _ = _bearingfw_run(model, ag, dt, alpha, substeps, nodes, bearings, preload)
    ops = _translate.opensees()
    built = _translate.build(ops, model, a1=DAMPING.beta)
    _translate.gravity(ops, model, built)
    run = _translate.transient(ops, built, ag, dt, alpha=alpha, rayleigh=(DAMPING.alpha, DAMPING.beta), nodes=nodes,
                               bearings=bearings, substeps=substeps, record_sliders=friction is not None)  # fmt: skip
    ops.wipe()
    name = f"{name} alpha={alpha:g} h=dt/{substeps}"
    rows = [
        attrs.evolve(compare(name, "displacement", disp, run.displacement), note=f"gravity: bearings {mode}"),
        compare(name, "bearing force", force, run.force),
    ]
    if friction is None or all(r.within for r in rows):
        return rows
    stale, jump = stale_slips(run, *friction)
    if not stale:
        return rows
    # integration steps -> the record samples they end in; then 0.4 s for the structure to settle
    stale = [(-(-first // substeps), -(-last // substeps)) for first, last in stale]
    span = round(0.4 / dt)
    ours = (_outside(disp, stale, span), _outside(force, stale, span))
    theirs = (_outside(run.displacement, stale, span), _outside(run.force, stale, span))
    kept = len(next(iter(ours[0].values()))) / len(ag)
    out = []
    for row, a, b in zip(rows, ours, theirs, strict=True):
        rest = compare(row.case, row.quantity, a, b)
        note = f"{row.note + '; ' if row.note else ''}{len(stale)} OpenSees stale slips (up to {jump / 1e3:.2f} kN); " \
               f"outside them ({kept:.0%} of the record) max {rest.max:.2%}, RMS {rest.rms:.2%}"  # fmt: skip
        explained = "OS-STALE-SLIP" if not row.within and rest.within else ""
        out.append(attrs.evolve(row, note=note, explained=explained, outside=(rest.max, rest.rms)))
    return out


def at_rest(model, seconds: float = 0.3, dt: float = 0.005) -> Row:
    """Evidence for OS-STALE-SLIP: both models after gravity, no ground motion: the largest motion
    (m) of any node. A consistent rest state does not move."""
    preload, _ = comparable_preload(model)
    nodes = [n.name for n in model.nodes]
    still = np.zeros((round(seconds / dt) + 1, 3))
    disp, _, _, _ = _bearingfw_run(model, still, dt, 0.0, 1, nodes, [], preload)
    ops = _translate.opensees()
    built = _translate.build(ops, model, a1=DAMPING.beta)
    _translate.gravity(ops, model, built)
    run = _translate.transient(ops, built, still, dt, alpha=0.0, rayleigh=(DAMPING.alpha, DAMPING.beta), nodes=nodes)
    ops.wipe()
    ours = max(float(np.abs(d).max()) for d in disp.values())
    theirs = max(float(np.abs(d).max()) for d in run.displacement.values())
    return Row(f"(evidence) {model.name} at rest after gravity", "largest motion (m)", "bearingfw / OpenSees",
               ours, theirs, note="not a comparison: OpenSees should stay at 0 too")  # fmt: skip


def case_frame(
    ag, dt, alpha, substeps, law="regularized-coulomb", params=(("k", 4e8), ("mu", 0.04)), **frame
) -> list[Row]:
    """(b2): the multi-span frame of ``_multispan`` (bearings on the girder axis)."""
    frame = _multispan.Frame(law=law, params=params, **frame)
    model = _multispan.frame_model(frame)
    nodes = _multispan.response_nodes(frame)
    friction = (dict(params)["k"], dict(params)["mu"]) if law == "regularized-coulomb" else None
    return case_model(f"(b2) frame {law}", model, nodes, _multispan.sliding_bearings(model), ag, dt, alpha, substeps,
                      friction)  # fmt: skip


def case_reference_bridge(ag, dt, alpha, substeps) -> list[Row]:
    """(b2) on the paper's bridge, M2 (bearings at the soffit, on rigid offsets; arches, hangers)."""
    from bearingfw.bridges import BridgeParameters, reference_bridge
    from bearingfw.bridges.reference import deck_nodes

    from bearingfw.bridges import DEFAULT_KS
    from bearingfw.bridges.paper import FRICTION

    model = reference_bridge("M2")
    deck = deck_nodes(BridgeParameters())
    nodes = list(deck[:: max(1, len(deck) // 8)])
    return case_model("(b2) reference bridge M2", model, nodes, _multispan.sliding_bearings(model), ag, dt, alpha,
                      substeps, friction=(DEFAULT_KS, FRICTION))  # fmt: skip


# --------------------------------------------------------------------------------------------
# (c) modal


def case_modal(name: str, model: Model, count: int = 12) -> Row:
    preload = gravity(model)
    ours = np.sort(solve_modal(preload.system, count, preload=preload).frequencies)
    ops = _translate.opensees()
    _translate.build(ops, model)
    theirs = _translate.eigen(ops, count)
    ops.wipe()
    rel = np.abs(ours / theirs - 1.0)
    k = int(np.argmax(rel))
    return Row(f"(c) modal {name}", f"{count} frequencies", f"mode {k + 1}: {ours[k]:.4f} Hz", float(rel.max()),
               float(np.sqrt(np.mean(rel**2))), note=f"f1 = {ours[0]:.4f} Hz")  # fmt: skip


def modal_cases(quick: bool) -> list[Row]:
    rows = []
    for law, params in (("linear-spring", (("k", 4e8),)), ("frictionless", ())):
        frame = _multispan.Frame(offset=0.8, law=law, params=params)
        rows.append(case_modal(f"frame with offsets, {law}", _multispan.frame_model(frame)))
    if not quick:
        from bearingfw.bridges import reference_bridge

        for preset in ("M0", "M1", "fixed"):
            rows.append(case_modal(f"reference bridge {preset}", reference_bridge(preset)))
    return rows


# --------------------------------------------------------------------------------------------


def run(quick: bool = False) -> list[Row]:
    window = (19.5, 23.5) if quick else (15.0, 35.0)
    ag, dt = record_window(*window)
    rows = []
    for alpha in (0.0, -0.05):
        rows += case_sdof(ag, dt, alpha, 2)
    for alpha in (0.0,) if quick else (0.0, -0.05):
        rows += case_frame(ag, dt, alpha, 2, law="linear-spring", params=(("k", 4e8),))
        rows += case_frame(ag, dt, alpha, 2)
        if not quick:
            rows += case_reference_bridge(ag, dt, alpha, 2)
    if not quick:
        from bearingfw.bridges import reference_bridge

        rows.append(at_rest(reference_bridge("M2")))
    return rows + modal_cases(quick)


def _pct(x: float) -> str:
    return f"{100 * x:.3f}%" if 100 * x >= 0.0005 or x == 0.0 else f"{100 * x:.0e}%"


def print_rows(rows: list[Row], out=sys.stdout) -> None:
    width = max(len(r.case) + len(r.quantity) + 3 for r in rows)
    print(f"{'case':<{width}}  {'max':>9} {'RMS':>9}  {'status':<24}  worst", file=out)
    for r in rows:
        label = f"{r.case} - {r.quantity}"
        extra = f"{r.worst}" + (f"; {r.note}" if r.note else "")
        if r.case.startswith("(evidence)"):
            print(f"{label:<{width}}  {r.max:>9.1e} {r.rms:>9.1e}  {'':<24}  {extra}", file=out)
            continue
        print(f"{label:<{width}}  {_pct(r.max):>9} {_pct(r.rms):>9}  {r.status:<24}  {extra}", file=out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="4 s of the record, the frame at alpha = 0 only")
    args = parser.parse_args(argv)
    _translate.ensure()
    start = time.perf_counter()
    print(f"bearingfw {bearingfw.__version__} vs OpenSeesPy {_translate.opensees().version()}")
    rows = run(args.quick)
    print_rows(rows)
    compared = [r for r in rows if not r.case.startswith("(evidence)")]
    failed = [r for r in compared if not r.passed]
    explained = sorted({key for r in compared if r.explained and not r.within for key in r.explained.split("+")})
    n_explained = sum(1 for r in compared if r.explained and not r.within)
    print(f"\n{len(compared)} comparisons, {len(failed)} failed, {n_explained} explained, "
          f"{time.perf_counter() - start:.1f} s")  # fmt: skip
    for key in explained:
        print(f"  {key}: {EXPLANATIONS[key]}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
