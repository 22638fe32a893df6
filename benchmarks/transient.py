"""Cost of a transient step against one sparse back-substitution, for growing models.

Usage::

    python benchmarks/transient.py            # 2000 steps per model, ~1e2 .. 1e4 DOF
    python benchmarks/transient.py --quick    # 200 steps, the smaller models

Each model is a grid deck: ``lines`` girders along x (frame elements) joined by crossbeams at
every node, resting on 2-D regularized-Coulomb bearings (PLANAR connectors, stick stiffness
``k``) over short piers (frame elements on fixed supports). The excitation is a seeded random
3-component acceleration, strong enough for the bearings to slip. Two extra rows: a stiff stick
(``k = 4e10`` N/m, stick/slip switches in most steps: the line search's case) and recorders on
(every connector, with fixed bearings whose tie forces need the multipliers; stresses along a
girder; a few nodal accelerations). Every case runs in a fresh process so that its peak resident
memory is its own.

Columns: free DOFs, bearings (and governed law directions m), stick stiffness, recorders (y/n);
``setup s``: ``solve_transient``'s setup (excitation, recorders, the first factorisation and
condensation; the gravity preload is not included); ``s/step``: the time loop per step (fast
path; energy balance always on); ``backsub s``: one bare back-substitution with the same
effective matrix factorised the same way (:func:`bearingfw.analysis.hht.factor`); their ratio;
``it/step``: Newton iterations per step of the converged sub-steps, ``failed it``: iterations
spent in attempts that were then halved, ``halvings``: step subdivisions, ``ls/step``: line-search
halvings per step (extra law calls); ``balance``: the energy balance error without HHT's
numerical dissipation; the process's peak resident memory (``resource.getrusage``, includes the
Python runtime).

BLAS runs single-threaded (``--threads``, default 1): the step's dense work is a few matrix-vector
products that threads do not speed up, and on a loaded machine OpenBLAS's thread synchronisation
can make them many times slower. Timings are wall-clock: run on a quiet machine.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import resource
import sys
import time

import attrs
import numpy as np


@attrs.frozen
class Case:
    """A grid deck: ``lines`` girders of ``per_line`` nodes, bearings under the two outer girders
    at ``axes`` axes (the first ``fixed`` axes fixed: JOIN), stick stiffness ``k``; ``recorders``
    on or off."""

    lines: int
    per_line: int
    axes: int
    fixed: int = 0
    k: float = 4e8
    recorders: bool = False


CASES = [
    Case(2, 9, 2, 1),  # ~1e2 DOF, 2 sliding bearings (+ 2 fixed)
    Case(2, 40, 4),  # ~5e2 DOF, 8 bearings
    Case(4, 45, 8),  # ~1e3 DOF, 16 bearings
    Case(4, 90, 16),  # ~2e3 DOF, 32 bearings
    Case(8, 110, 16),  # ~5e3 DOF, 32 bearings
    Case(8, 210, 16),  # ~1e4 DOF, 32 bearings
    Case(8, 210, 32),  # ~1e4 DOF, 64 bearings
    Case(4, 90, 16, k=4e10),  # ~2e3 DOF, stiff stick
    Case(4, 90, 16, fixed=1, recorders=True),  # ~2e3 DOF, recorders on
]
QUICK = [*CASES[:4], Case(4, 45, 8, k=4e10), Case(4, 45, 8, fixed=1, recorders=True)]


def build_model(lines: int, per_line: int, axes: int, fixed: int = 0, k_stick: float = 4e8):
    from bearingfw.model import Connector, FrameElement, Material, Model, Node, Section, Support

    concrete = Material("C40/50", 35e9, density=2500.0, nu=0.2)
    girder = Section.rectangle("girder", 1.0, 1.6)
    crossbeam = Section.rectangle("crossbeam", 0.4, 1.0)
    pier = Section.rectangle("pier", 1.4, 1.4)
    spacing, width = 5.0, 2.5
    nodes, elements, connectors, supports = [], [], [], []
    for li in range(lines):
        y = li * width
        for k in range(per_line):
            nodes.append(Node(f"G{li}_{k}", k * spacing, y, 0.0))
            if k:
                elements.append(
                    FrameElement(f"G{li}_{k}", f"G{li}_{k - 1}", f"G{li}_{k}", girder, concrete, added_mass=1500.0)
                )
            if li:
                elements.append(FrameElement(f"X{li}_{k}", f"G{li - 1}_{k}", f"G{li}_{k}", crossbeam, concrete))
    # Bearings under the two outer girders at ``axes`` evenly spaced axes (both ends included).
    positions = np.unique(np.linspace(0, per_line - 1, axes).round().astype(int))
    for a, k in enumerate(positions):
        for li in (0, lines - 1):
            top, base = f"P{li}_{k}", f"F{li}_{k}"
            nodes += [Node(top, k * spacing, li * width, 0.0), Node(base, k * spacing, li * width, -6.0)]
            elements.append(FrameElement(f"pier{li}_{k}", base, top, pier, concrete))
            supports.append(Support(base))
            if a < fixed:
                connectors.append(Connector(f"B{li}_{k}", top, f"G{li}_{k}", "join"))
            else:
                connectors.append(
                    Connector(
                        f"B{li}_{k}", top, f"G{li}_{k}", "planar", law="regularized-coulomb",
                        law_params={"k": k_stick, "mu": 0.04}, vertical_stiffness=5e9,
                    )
                )
    return Model(nodes, elements, connectors, supports=supports, name=f"grid {lines}x{per_line}")


def excitation(steps: int, dt: float, seed: int = 7) -> np.ndarray:
    """Seeded random ground acceleration, smoothed (a 5-point moving average), m/s^2."""
    rng = np.random.default_rng(seed)
    raw = rng.normal(size=(steps + 4, 3)) * np.array([3.0, 3.0, 1.5])
    kernel = np.ones(5) / 5
    return np.column_stack([np.convolve(raw[:, c], kernel, mode="valid") for c in range(3)])


def recorders(case: Case, model) -> list:
    """Every connector, the stresses along the first girder, the accelerations at three nodes."""
    from bearingfw.analysis import ConnectorResponse, ElementStress, NodalResponse

    if not case.recorders:
        return []
    girder = [e.name for e in model.elements if e.name.startswith("G0_")]
    nodes = [f"G0_{case.per_line // 4}", f"G0_{case.per_line // 2}", f"G{case.lines - 1}_{case.per_line // 2}"]
    return [ConnectorResponse(), ElementStress(girder), NodalResponse(nodes, "acceleration", total=True)]


def run_case(case: Case, steps: int, dt: float, queue) -> None:
    try:
        queue.put(_run_case(case, steps, dt))
    except Exception as exc:  # report instead of leaving the parent waiting
        queue.put({"error": f"{type(exc).__name__}: {exc}", "case": case})


def _run_case(case: Case, steps: int, dt: float) -> dict:
    from bearingfw.analysis import Rayleigh, TransientSettings, gravity, solve_transient
    from bearingfw.analysis.hht import Scheme, effective_matrix, factor

    model = build_model(case.lines, case.per_line, case.axes, case.fixed, case.k)
    pre = gravity(model)
    system = pre.system
    damping = Rayleigh(0.21, 0.00208)
    settings = TransientSettings()
    ag = excitation(steps + 1, dt)
    result = solve_transient(system, ag, dt, preload=pre, damping=damping, settings=settings, recorders=recorders(case, model))
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux; before the extra factors below
    stats = result.stats
    per_step = stats["loop_time"] / steps
    # One bare back-substitution of the same effective matrix (factorised the same way as the run).
    A = effective_matrix(system.M_free, system.K_free, damping.alpha, damping.beta, Scheme(settings.alpha), dt)
    solve = factor(A).solve
    r = np.random.default_rng(0).normal(size=system.n_free)
    repeats = max(20, min(2000, int(0.5 / max(per_step, 1e-6))))
    solve(r)
    t0 = time.perf_counter()
    for _ in range(repeats):
        solve(r)
    backsub = (time.perf_counter() - t0) / repeats
    return {
        "case": case,
        "dof": system.n_free,
        "bearings": sum(g.n for g in system.connectors.groups),
        "m": system.connectors.n_governed,
        "setup": stats["setup_time"],
        "per_step": per_step,
        "backsub": backsub,
        "iterations": stats["iterations"] / steps,
        "failed": stats["failed_iterations"],
        "subdivisions": stats["subdivisions"],
        "backtracks": stats["backtracks"] / steps,
        "peak_mb": rss,
        "balance": result.balance_error,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="200 steps and the smaller models only")
    parser.add_argument("--steps", type=int, default=None, help="integration steps per model (default 2000)")
    parser.add_argument("--dt", type=float, default=0.01, help="time step, s")
    parser.add_argument("--threads", type=int, default=1, help="BLAS threads in the benchmark processes")
    args = parser.parse_args(argv)
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = str(args.threads)  # inherited by the spawned processes before numpy loads
    steps = args.steps or (200 if args.quick else 2000)
    cases = QUICK if args.quick else CASES
    ctx = mp.get_context("spawn")
    print(
        f"transient benchmark: {steps} steps of {args.dt} s, fast path, HHT alpha = -0.05, Rayleigh damping, "
        f"{args.threads} BLAS thread(s), load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs"
    )
    header = (
        f"{'DOF':>6} {'bearings':>8} {'m':>4} {'k':>6} {'rec':>3} {'setup s':>8} {'s/step':>9} {'backsub s':>9} "
        f"{'ratio':>5} {'it/step':>7} {'failed it':>9} {'halvings':>8} {'ls/step':>7} {'balance':>8} {'peak MB':>7}"
    )
    print(header)
    print("-" * len(header))
    for case in cases:
        queue = ctx.Queue()
        proc = ctx.Process(target=run_case, args=(case, steps, args.dt, queue))
        proc.start()
        row = queue.get()
        proc.join()
        if "error" in row:
            print(f"case {row['case']} failed: {row['error']}", flush=True)
            continue
        print(
            f"{row['dof']:>6d} {row['bearings']:>8d} {row['m']:>4d} {case.k:>6.0e} {'y' if case.recorders else 'n':>3} "
            f"{row['setup']:>8.3f} {row['per_step']:>9.2e} {row['backsub']:>9.2e} {row['per_step'] / row['backsub']:>5.1f} "
            f"{row['iterations']:>7.2f} {row['failed']:>9d} {row['subdivisions']:>8d} {row['backtracks']:>7.2f} "
            f"{row['balance']:>8.1e} {row['peak_mb']:>7.0f}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
