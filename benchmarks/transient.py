"""Cost of a transient step against one sparse back-substitution, for growing models.

Usage::

    python benchmarks/transient.py            # 2000 steps per model, ~1e2 .. 1e4 DOF
    python benchmarks/transient.py --quick    # 200 steps, the smaller models

Each model is a grid deck: ``lines`` girders along x (frame elements) joined by crossbeams at
every node, resting on 2-D regularized-Coulomb bearings (PLANAR connectors) over short piers
(frame elements on fixed supports). The excitation is a seeded random 3-component acceleration,
strong enough for the bearings to slip. Every case runs in a fresh process so that its peak
resident memory is its own.

Columns: free DOFs, bearings (and governed law directions m), wall time per step of
``solve_transient`` (fast path, no recorders; energy balance always on), the time of one bare
``splu(A).solve(r)`` with the same effective matrix ``A``, their ratio, Newton iterations per step,
and the process's peak resident memory (``resource.getrusage``, includes the Python runtime).

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

import numpy as np

#: (girder lines, nodes per line, bearing axes, fixed axes): two bearings (the outer girders) per
#: axis; the bearings of the first ``fixed`` axes are fixed (JOIN), the others regularized Coulomb.
CASES = [
    (2, 9, 2, 1),  # ~1e2 DOF, 2 sliding bearings (+ 2 fixed)
    (2, 40, 4, 0),  # ~5e2 DOF, 8 bearings
    (4, 45, 8, 0),  # ~1e3 DOF, 16 bearings
    (4, 90, 16, 0),  # ~2e3 DOF, 32 bearings
    (8, 110, 16, 0),  # ~5e3 DOF, 32 bearings
    (8, 210, 16, 0),  # ~1e4 DOF, 32 bearings
    (8, 210, 32, 0),  # ~1e4 DOF, 64 bearings
]
QUICK = CASES[:4]


def build_model(lines: int, per_line: int, axes: int, fixed: int = 0):
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
                        law_params={"k": 4e8, "mu": 0.04}, vertical_stiffness=5e9,
                    )
                )
    return Model(nodes, elements, connectors, supports=supports, name=f"grid {lines}x{per_line}")


def excitation(steps: int, dt: float, seed: int = 7) -> np.ndarray:
    """Seeded random ground acceleration, smoothed (a 5-point moving average), m/s^2."""
    rng = np.random.default_rng(seed)
    raw = rng.normal(size=(steps + 4, 3)) * np.array([3.0, 3.0, 1.5])
    kernel = np.ones(5) / 5
    return np.column_stack([np.convolve(raw[:, c], kernel, mode="valid") for c in range(3)])


def run_case(case, steps: int, dt: float, queue) -> None:
    try:
        queue.put(_run_case(case, steps, dt))
    except Exception as exc:  # report instead of leaving the parent waiting
        queue.put({"error": f"{type(exc).__name__}: {exc}", "case": case})


def _run_case(case, steps: int, dt: float) -> dict:
    from bearingfw.analysis import TransientSettings, gravity, solve_transient
    from bearingfw.analysis.hht import build_operator
    from bearingfw.analysis.transient import _problem  # the same effective matrix the run factorised
    from bearingfw.analysis.damping import Rayleigh

    model = build_model(*case)
    pre = gravity(model)
    system = pre.system
    damping = Rayleigh(0.21, 0.00208)
    settings = TransientSettings()
    ag = excitation(steps + 1, dt)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.perf_counter()
    result = solve_transient(system, ag, dt, preload=pre, damping=damping, settings=settings)
    per_step = (time.perf_counter() - start) / steps
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux; before the extra factors below
    # One bare back-substitution of the same effective matrix (factors built the same way).
    op = build_operator(_problem(system, pre, damping, settings), dt)
    r = np.random.default_rng(0).normal(size=system.n_free)
    repeats = max(20, min(2000, int(0.5 / max(per_step, 1e-6))))
    op.solve(r)
    t0 = time.perf_counter()
    for _ in range(repeats):
        op.solve(r)
    backsub = (time.perf_counter() - t0) / repeats
    return {
        "dof": system.n_free,
        "bearings": sum(g.n for g in system.connectors.groups),
        "m": system.connectors.n_governed,
        "per_step": per_step,
        "backsub": backsub,
        "iterations": result.stats["iterations"] / result.stats["substeps"],
        "subdivisions": result.stats["subdivisions"],
        "peak_mb": rss,
        "rss_before_mb": rss0 / 1024.0,
        "energy_error": result.energy_error,
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
        f"{'DOF':>7} {'bearings':>8} {'m':>4} {'s/step':>10} {'backsub s':>10} {'ratio':>6} "
        f"{'it/step':>7} {'peak MB':>8}"
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
            f"{row['dof']:>7d} {row['bearings']:>8d} {row['m']:>4d} {row['per_step']:>10.2e} {row['backsub']:>10.2e} "
            f"{row['per_step'] / row['backsub']:>6.1f} {row['iterations']:>7.2f} {row['peak_mb']:>8.0f}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
