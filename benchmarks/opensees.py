#!/usr/bin/env python
"""The same time-history analyses timed in bearingfw and in OpenSeesPy, for growing models.

Usage::

    python benchmarks/opensees.py                  # every case, 3 repetitions, about 20 minutes
    python benchmarks/opensees.py --quick          # the small cases, 1 repetition (development)
    python benchmarks/opensees.py --reps 5 --steps 400 --out benchmarks/results

Models: the parametric multi-span frame of ``validation/_multispan.py`` (twin girders with
crossbeams, piers, regularized-Coulomb bearings: fixed, guided 1-D and free 2-D, ``k = 4e8 N/m``,
``mu = 0.04``), grown in two ways: more elements per span at 8 bearings (about 200 to 10,000 free
DOFs) and more spans at about 2,000 DOFs (8 to 64 bearings); plus the paper's reference bridge
(``bearingfw.bridges.reference_bridge("M2")``) and a frame of its reported size (1,488 DOFs, 20
bearings). OpenSees gets each model through ``validation/_translate.py`` (elasticBeamColumn,
Truss, rigidLink, flatSliderBearing with Coulomb friction between rotation-fixed nodes, penalty
ties): the same structure, mass, damping and gravity preload; ``validation/models.py`` shows the
two agree to round-off at alpha = 0.

Run: the Chuetsu-oki record (EW, NS, UD on x, y, z; from 19.5 s, tapered in over 0.5 s),
``--steps`` integration steps of ``--dt`` (default 0.005 s: the record's 0.01 s halved, as the
paper's study integrates), HHT alpha = -0.05 (OpenSees ``HHT 0.95``), the paper's Rayleigh
damping; both record every step the displacement of the girders' mid-span nodes and the force of
every sliding bearing (the same work: ``nodeDisp``/``eleResponse`` calls against bearingfw's
recorders). Each case runs in a fresh process; in it the two tools alternate (``--reps`` times,
the order swapped every repetition) and the medians are reported. Timed: the transient analysis
alone, its setup included (bearingfw: ``solve_transient`` from a computed preload, which
factorises and condenses; OpenSees: defining the excitation and the analysis and every
``analyze``); model building and the gravity step are not timed on either side. BLAS runs on
one thread (``--threads``) in both.

Columns: free DOFs (bearingfw's; OpenSees's model has 6 more per friction bearing, the two
rotation-fixed nodes of each flatSliderBearing), bearings (law-governed), bearingfw and OpenSees
time per step (median, ms), their ratio OpenSees / bearingfw (how many times faster bearingfw
is), bearingfw's time per step over one bare back-substitution (scipy ``splu`` solve of the same
effective matrix, ordered the same way), Newton iterations per step, and the agreement of the
two histories: the largest ``max |a - b| / max |b|`` over the recorded displacements, and over the
bearing forces (at alpha = -0.05 the two codes' HHT forms differ by O(h) at stick-slip
transitions, and OpenSees's flat slider can commit a stale slip: validation/README.md). The JSON
and the figures (cost per step against DOFs and against bearings, PNG and SVG) go to ``--out``.

OpenSees settings (the fastest of ``--sweep`` on the 3x60 frame, all with equal results):
``constraints Transformation``, ``numberer RCM``, ``system ProfileSPD`` (the effective tangent is
symmetric: the flat sliders' P-Delta terms act on fixed rotations), ``test NormDispIncr 1e-10 50``,
``algorithm KrylovNewton``; ``--system``, ``--numberer`` and ``--algorithm`` change them.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import attrs
import numpy as np

HERE = Path(__file__).resolve().parent
VALIDATION = HERE.parent / "validation"


@attrs.frozen
class Case:
    """A multi-span frame (``spans`` of ``span`` m, ``per_span`` elements, 2 girders), or the
    reference bridge (``reference=True``); ``group``: which series of the figures it belongs to."""

    label: str
    spans: int = 3
    per_span: int = 6
    span: float = 30.0
    reference: bool = False
    group: str = "dof"


CASES = [
    Case("frame 3x4", 3, 4),
    Case("frame 3x20", 3, 20),
    Case("frame 3x60", 3, 60, group="both"),
    Case("frame 3x140", 3, 140),
    Case("frame 3x280", 3, 280),
    Case("frame 7x24", 7, 24, group="bearings"),
    Case("frame 15x10", 15, 10, group="bearings"),
    Case("frame 31x4", 31, 4, group="bearings"),
    Case("frame 9x11 (1488 DOF, 20 bearings)", 9, 11, group="reference"),
    Case("reference bridge M2", reference=True, group="reference"),
]
QUICK = [CASES[0], CASES[1], Case("frame 7x4", 7, 4, group="bearings"), CASES[-1]]


# --------------------------------------------------------------------------------------------
# One case (in its own process)


def _imports():
    sys.path.insert(0, str(VALIDATION))
    import _multispan
    import _translate

    return _multispan, _translate


def build_case(case: Case):
    """``(model, response nodes, sliding bearings)``."""
    _multispan, _ = _imports()
    if case.reference:
        from bearingfw.bridges import BridgeParameters, reference_bridge
        from bearingfw.bridges.reference import deck_nodes

        model = reference_bridge("M2")
        deck = deck_nodes(BridgeParameters())
        nodes = list(deck[:: max(1, len(deck) // 6)])  # six girder nodes along both girders
        return model, nodes, _multispan.sliding_bearings(model)
    frame = _multispan.Frame(spans=(case.span,) * case.spans, per_span=case.per_span)
    model = _multispan.frame_model(frame)
    return model, _multispan.response_nodes(frame), _multispan.sliding_bearings(model)


def validation_preload(model):
    """The gravity preload in the state OpenSees reaches (``validation/models.py``)."""
    import models as validation_models

    return validation_models.comparable_preload(model)


def excitation(steps: int, dt: float) -> np.ndarray:
    """``steps + 1`` samples every ``dt`` of the Chuetsu-oki record from 19.5 s (x, y, z)."""
    import models as validation_models  # validation/models.py: the record window

    record, record_dt = validation_models.record_window(19.5, 19.5 + steps * dt + 1.0)
    t = np.arange(steps + 1) * dt
    return np.column_stack([np.interp(t, np.arange(len(record)) * record_dt, record[:, c]) for c in range(3)])


def _bearingfw(system, preload, ag, dt, alpha, nodes, bearings):
    from bearingfw.analysis import ConnectorResponse, NodalResponse, Rayleigh, TransientSettings, solve_transient

    recorders = [NodalResponse(nodes, "displacement", name="disp"), ConnectorResponse(bearings, name="bearings")]
    start = time.perf_counter()
    result = solve_transient(system, ag, dt, settings=TransientSettings(alpha=alpha), damping=Rayleigh(0.21, 0.00208),
                             recorders=recorders, preload=preload)  # fmt: skip
    seconds = time.perf_counter() - start
    model = system.model
    disp = {n: result.data["disp"][:, k] for k, n in enumerate(nodes)}
    force = result.data["bearings.force"]
    forces = {b: force[:, k, list(model.connector(b).law_directions)] for k, b in enumerate(bearings)}
    return seconds, disp, forces, result.stats


def _opensees(model, ag, dt, alpha, nodes, bearings, settings):
    _, _translate = _imports()
    ops = _translate.opensees()
    built = _translate.build(ops, model, a1=0.00208)
    _translate.gravity(ops, model, built)
    start = time.perf_counter()
    run = _translate.transient(ops, built, ag, dt, alpha=alpha, rayleigh=(0.21, 0.00208), nodes=nodes,
                               bearings=bearings, settings=settings)  # fmt: skip
    seconds = time.perf_counter() - start
    n_eq = ops.systemSize()
    ops.wipe()
    return seconds, run.displacement, run.force, n_eq


def _agreement(ours: dict, theirs: dict) -> float:
    worst = 0.0
    for key, a in ours.items():
        b = np.asarray(theirs[key]).reshape(len(a), -1)
        a = np.asarray(a).reshape(len(a), -1)
        peak = np.linalg.norm(b, axis=1).max()
        if peak > 0:
            worst = max(worst, float(np.linalg.norm(a - b, axis=1).max() / peak))
    return worst


def _backsubstitution(system, dt: float, alpha: float, seconds: float = 0.3) -> float:
    """One bare ``splu`` solve of the effective matrix, factorised as the run factorises it (s)."""
    from bearingfw.analysis.hht import Scheme, effective_matrix, factor

    A = effective_matrix(system.M_free, system.K_free, 0.21, 0.00208, Scheme(alpha), dt)
    solve = factor(A).solve
    r = np.random.default_rng(0).normal(size=system.n_free)
    solve(r)
    repeats, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds or repeats < 20:
        solve(r)
        repeats += 1
    return (time.perf_counter() - start) / repeats


def run_case(case: Case, steps: int, dt: float, alpha: float, reps: int, settings: dict) -> dict:
    _, _translate = _imports()
    model, nodes, bearings = build_case(case)
    preload, _ = validation_preload(model)
    system = preload.system
    ag = excitation(steps, dt)
    os_settings = _translate.Settings(**settings)
    times = {"bearingfw": [], "opensees": []}
    agreement = stats = n_eq = None  # (displacements, bearing forces)
    for rep in range(reps):
        order = ("bearingfw", "opensees") if rep % 2 == 0 else ("opensees", "bearingfw")
        for tool in order:
            if tool == "bearingfw":
                seconds, disp, forces, stats = _bearingfw(system, preload, ag, dt, alpha, nodes, bearings)
                ours = (disp, forces)
            else:
                seconds, os_disp, os_forces, n_eq = _opensees(model, ag, dt, alpha, nodes, bearings, os_settings)
                theirs = (os_disp, os_forces)
            times[tool].append(seconds)
        if agreement is None:
            agreement = (_agreement(ours[0], theirs[0]), _agreement(ours[1], theirs[1]))
    per_step = {tool: statistics.median(t) / steps for tool, t in times.items()}
    backsub = _backsubstitution(system, dt, alpha)
    return {
        "case": case.label,
        "group": case.group,
        "dof": int(system.n_free),
        "opensees_equations": int(n_eq),
        "bearings": len(bearings),
        "governed_directions": int(system.connectors.n_governed),
        "steps": steps,
        "bearingfw_s_per_step": per_step["bearingfw"],
        "opensees_s_per_step": per_step["opensees"],
        "speedup": per_step["opensees"] / per_step["bearingfw"],
        "backsubstitution_s": backsub,
        "bearingfw_per_backsubstitution": per_step["bearingfw"] / backsub,
        "iterations_per_step": stats["iterations"] / stats["steps"],
        "agreement_displacement": agreement[0],
        "agreement_force": agreement[1],
        "times": times,
    }


def _child(case, steps, dt, alpha, reps, settings, queue):
    try:
        queue.put(run_case(case, steps, dt, alpha, reps, settings))
    except Exception as exc:  # noqa: BLE001 - report instead of leaving the parent waiting
        queue.put({"case": case.label, "error": f"{type(exc).__name__}: {exc}"})


def in_process(case: Case, steps: int, dt: float, alpha: float, reps: int, settings: dict) -> dict:
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_child, args=(case, steps, dt, alpha, reps, settings, queue))
    proc.start()
    row = queue.get()
    proc.join()
    return row


# --------------------------------------------------------------------------------------------
# Machine, table, figures


def machine() -> dict:
    import numpy
    import scipy

    _, _translate = _imports()
    try:
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True, check=False).stdout
        cpu = next((line.split(":", 1)[1].strip() for line in lscpu.splitlines() if line.startswith("Model name")), "")
    except OSError:
        cpu = ""
    import bearingfw

    return {
        "cpu": cpu or platform.processor(),
        "cpus": os.cpu_count(),
        "load_average": os.getloadavg()[0],
        "python": platform.python_version(),
        "platform": platform.platform(),
        "bearingfw": bearingfw.__version__,
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "openseespy": _translate.opensees().version(),
    }


def table(rows: list[dict]) -> str:
    head = ("| model | free DOFs | bearings | bearingfw ms/step | OpenSees ms/step | OpenSees / bearingfw | "
            "bearingfw / back-substitution | it/step | agreement: displacement, force |")  # fmt: skip
    lines = [head, "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['case']} | failed: {r['error']} | | | | | | | |")
            continue
        lines.append(
            f"| {r['case']} | {r['dof']} | {r['bearings']} | {1e3 * r['bearingfw_s_per_step']:.3g} | "
            f"{1e3 * r['opensees_s_per_step']:.3g} | {r['speedup']:.1f} | {r['bearingfw_per_backsubstitution']:.1f} | "
            f"{r['iterations_per_step']:.2f} | {r['agreement_displacement']:.0e}, {r['agreement_force']:.0e} |"
        )
    return "\n".join(lines)


def figures(rows: list[dict], out: Path) -> list[Path]:
    """Time per step against free DOFs (frames at 8 bearings) and against bearings (frames at about
    2,000 DOFs), both tools and one back-substitution; the reference-size cases as labelled points."""
    from bearingfw.plotting import new_figure, save

    ok = [r for r in rows if "error" not in r]
    paths = []
    for key, label, series in (("dof", "free DOFs", ("dof", "both")), ("bearings", "bearings", ("bearings", "both"))):
        line = sorted((r for r in ok if r["group"] in series), key=lambda r: r[key])
        points = [r for r in ok if r["group"] == "reference"]
        if not line and not points:
            continue
        fig = new_figure(6.0, 4.0)
        ax = fig.add_subplot()
        for tool, marker, colour in (("opensees", "s", "C0"), ("bearingfw", "o", "C1")):
            name = "OpenSeesPy" if tool == "opensees" else "bearingfw"
            x = [r[key] for r in line]
            ax.loglog(x, [1e3 * r[f"{tool}_s_per_step"] for r in line], marker + "-", color=colour, label=name)
            for r in points:
                ax.loglog(r[key], 1e3 * r[f"{tool}_s_per_step"], marker, color=colour, mfc="none", ms=9)
        ax.loglog([r[key] for r in line], [1e3 * r["backsubstitution_s"] for r in line], ":", color="grey",
                  label="one back-substitution")  # fmt: skip
        for r in points:
            ax.annotate(r["case"].split(" (")[0], (r[key], 1e3 * r["opensees_s_per_step"]), textcoords="offset points",
                        xytext=(6, -12), fontsize=7)  # fmt: skip
        if key == "bearings":  # 8 .. 64: a log axis would print its ticks as powers of ten
            ax.set_xscale("linear")
        ax.set_xlabel(label)
        ax.set_ylabel("time per step [ms]")
        ax.set_title(f"transient cost against {label} (open markers: reference-size models)", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        paths += save(fig, out, f"cost_vs_{key}")
    return paths


def sweep(case: Case, steps: int, dt: float, alpha: float, algorithms=None) -> None:
    """Time OpenSees alone with each candidate setting on ``case`` (the choice of Settings)."""
    _, _translate = _imports()
    model, nodes, bearings = build_case(case)
    preload, _ = validation_preload(model)
    ag = excitation(steps, dt)
    reference = _bearingfw(preload.system, preload, ag, dt, alpha, nodes, bearings)
    algorithms = [tuple(a.split()) for a in algorithms] if algorithms else [
        ("Newton",),
        ("KrylovNewton",),
        ("KrylovNewton", "-iterate", "initial", "-increment", "initial"),
        ("ModifiedNewton", "-initial"),
    ]
    candidates = [
        {"system": s, "numberer": n, "algorithm": a}
        for s in ("UmfPack", "SparseGeneral", "ProfileSPD")
        for n in ("RCM", "AMD")
        for a in algorithms
    ]
    for c in candidates:
        try:
            seconds, disp, forces, _ = _opensees(model, ag, dt, alpha, nodes, bearings, _translate.Settings(**c))
        except Exception as exc:  # noqa: BLE001 - a setting that does not work is reported
            print(f"{c}: failed ({exc})", flush=True)
            continue
        agree = max(_agreement(reference[1], disp), _agreement(reference[2], forces))
        print(f"{c}: {1e3 * seconds / steps:.2f} ms/step, agreement {agree:.1e}", flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small cases, 100 steps, 1 repetition")
    parser.add_argument("--steps", type=int, default=None, help="integration steps per run (default 400)")
    parser.add_argument("--dt", type=float, default=0.005, help="integration step, s")
    parser.add_argument("--alpha", type=float, default=-0.05, help="HHT alpha (bearingfw's convention)")
    parser.add_argument("--reps", type=int, default=None, help="repetitions per case (default 3)")
    parser.add_argument("--threads", type=int, default=1, help="BLAS threads")
    parser.add_argument("--only", action="append", default=None, help="run only the cases whose label has this text")
    parser.add_argument("--system", default="ProfileSPD", help="OpenSees system")
    parser.add_argument("--numberer", default="RCM", help="OpenSees numberer")
    parser.add_argument("--algorithm", default="KrylovNewton", help="OpenSees algorithm and its options, e.g. 'Newton'")
    parser.add_argument("--sweep", action="store_true",
                        help="time OpenSees's settings on the 3x60 frame (or the first --only case) and exit")
    parser.add_argument("--sweep-algorithms", action="append", default=None, help="algorithms the sweep tries")
    parser.add_argument("--out", type=Path, default=HERE / "results", help="folder for the JSON and the figures")
    args = parser.parse_args(argv)
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = str(args.threads)  # inherited by the spawned processes before numpy loads
    sys.path.insert(0, str(VALIDATION))
    import _translate

    _translate.ensure()
    steps = args.steps or (100 if args.quick else 400)
    reps = args.reps or (1 if args.quick else 3)
    if args.sweep:  # on the 3x60 frame, or the first case --only names
        chosen = [c for c in CASES if args.only and any(text in c.label for text in args.only)]
        sweep((chosen or [CASES[2]])[0], steps, args.dt, args.alpha, args.sweep_algorithms)
        return 0
    cases = QUICK if args.quick else CASES
    if args.only:
        cases = [c for c in CASES if any(text in c.label for text in args.only)]
    settings = {"system": args.system, "numberer": args.numberer, "algorithm": tuple(args.algorithm.split())}
    info = machine()
    print(f"bearingfw {info['bearingfw']} vs OpenSeesPy {info['openseespy']}; {info['cpu']} ({info['cpus']} CPUs, "
          f"load {info['load_average']:.1f}); numpy {info['numpy']}, scipy {info['scipy']}, "
          f"Python {info['python']}")  # fmt: skip
    print(f"{steps} steps of {args.dt} s, HHT alpha = {args.alpha}, {reps} repetitions, OpenSees {settings}",
          flush=True)  # fmt: skip
    rows = []
    for case in cases:
        row = in_process(case, steps, args.dt, args.alpha, reps, settings)
        rows.append(row)
        print(table([row]).splitlines()[-1], flush=True)
    print()
    print(table(rows))
    args.out.mkdir(parents=True, exist_ok=True)
    report = {"machine": info, "steps": steps, "dt": args.dt, "alpha": args.alpha, "reps": reps,
              "opensees_settings": settings, "command": " ".join(["python", *sys.argv]), "rows": rows}  # fmt: skip
    (args.out / "opensees.json").write_text(json.dumps(report, indent=2))
    for path in figures(rows, args.out):
        print(f"wrote {path}")
    return 1 if any("error" in r for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
