#!/usr/bin/env python
"""What one transient step costs, counted in sparse back-substitutions (issue 16).

Usage::

    python benchmarks/step_cost.py              # 8 cases, 1000 steps each (a few minutes)
    python benchmarks/step_cost.py --quick      # 300 DOFs (3 and 20 bearings), 3,000 DOFs / 20; 200 steps
    python benchmarks/step_cost.py --json       # the same as one JSON document on stdout
    python benchmarks/step_cost.py --repeats 3  # the timings the best of 3 runs (a busy machine)

Models: the grid decks of ``benchmarks/transient.py`` (its ``build_model``: girders and
crossbeams on piers, 2-D regularized-Coulomb bearings, PLANAR, ``k = 4e8`` N/m, ``mu = 0.04``)
at about 300, 3,000 and 15,000 free DOFs with 3, 20 and 80 sliding bearings (the builder puts
bearings in pairs, so for an odd count the first bearing is made fixed, JOIN). Excitation: that
script's seeded random 3-component ground acceleration (strong enough for every bearing to slip:
the ``slipping`` column counts the bearings whose law reports a slip above 0.1 mm), ``--steps``
steps of ``--dt`` (default 0.005 s, the default study's integration step), HHT alpha = -0.05,
Rayleigh damping (0.21 1/s, 0.00208 s), the fast path, no recorders. Every case runs in a fresh
process, twice: a counted run, then a timed one with nothing patched.

Counted run: the factors :func:`bearingfw.analysis.hht.factor` returns get a ``solve`` that
counts its right-hand sides, and every law class's ``respond`` counts its calls (one call serves
all connectors of a law). Since the Newton iteration runs compiled with compiled laws
(:mod:`bearingfw.analysis.hht_newton`), ``respond`` is not called in a step; ``laws/step`` is
then the compiled laws' calls, one per group for every iterate (iterations plus line-search
halvings), and the JSON keeps both counts. What is solved inside :func:`bearingfw.analysis.hht.step` is per step;
what is solved outside it (``hht.build_operator``: the condensation ``W = A^-1 B^T``, one column
per governed bearing direction, once per step size) is setup.

Columns: free DOFs; sliding bearings and governed law directions ``m``; ``setup bs``: columns
back-substituted in the setup (``calls``: solve calls); ``bs/step``: back-substitutions inside
steps per step (a multi-column solve there would count once per call, ``cols/step`` shows its
columns); ``it/step``: Newton iterations, ``ls/step``: line-search halvings, ``laws/step``: law
calls, per step; ``halvings``: step subdivisions; ``ms/step`` and ``CPU ms``: wall-clock and
CPU time per step of the timed runs, a run of all the steps less one of a quarter of them over
the steps between (:func:`per_step_of`: the setup and the first calls cancel; the time loop runs
many steps in one compiled call, so a clock read between steps would not see a step's cost);
``bs CPU ms``: the CPU time of one bare back-substitution of the same
effective matrix factorised the same way (as ``benchmarks/opensees.py`` measures it);
``step/bs``: ``CPU ms`` over ``bs CPU ms``, what a step costs in back-substitutions (the issue's
measure: "a step costs 7.7 sparse back-substitutions"), next to the issue's ``target`` (at most
3 at 3,000 DOFs with 20 bearings, at most 10 at 300 DOFs); ``load``: the load average after
the case. Since issue 16 a step back-substitutes with bearingfw's compiled forward and backward
substitution on SuperLU's factors (``hht.Factors``), about three times cheaper than SuperLU's
own ``solve``; ``bs CPU ms`` times that one, ``SuperLU ms`` SuperLU's ``solve`` on the same
factors (the unit of the issue's first measurements), and ``step/SLU`` the step in that unit. The JSON has the wall-clock ratio too. The script reports; it asserts nothing.
``--repeats R`` times the run and the bare back-substitution R times each and keeps the fastest
of each (wall and CPU separately): on a busy machine the least disturbed run is the closest to
the cost itself.

BLAS runs on ``--threads`` threads (default 1): through threadpoolctl when it is installed,
else by ``OPENBLAS_NUM_THREADS``/``OMP_NUM_THREADS``/``MKL_NUM_THREADS``, set before any case
process imports numpy. On a loaded machine the wall-clock timings grow with the load, the CPU
times much less (other processes still share the caches), the counts not at all.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path

import attrs

HERE = Path(__file__).resolve().parent
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
#: a bearing slips when its law reports more than this slip (m)
SLIP = 1e-4


@attrs.frozen
class Case:
    """A grid deck of ``benchmarks/transient.py`` of about ``dofs`` free DOFs with ``sliding``
    sliding bearings: ``lines`` girders of ``per_line`` nodes."""

    dofs: int
    sliding: int
    lines: int
    per_line: int

    @property
    def axes(self) -> int:
        return (self.sliding + 1) // 2  # the builder sets a bearing under each outer girder per axis

    @property
    def target(self) -> float | None:
        """The issue's bound on a step's cost in back-substitutions (None: no target)."""
        if self.dofs == 300:
            return 10.0
        if (self.dofs, self.sliding) == (3000, 20):
            return 3.0
        return None


CASES = [
    Case(300, 3, 2, 23),
    Case(300, 20, 2, 15),
    Case(3000, 3, 4, 124),
    Case(3000, 20, 4, 120),
    Case(3000, 80, 4, 105),
    Case(15000, 3, 8, 312),
    Case(15000, 20, 8, 310),
    Case(15000, 80, 8, 302),
]
QUICK = [CASES[0], CASES[1], CASES[3]]


# --------------------------------------------------------------------------------------------
# One case (in its own process)


def transient_script():
    """``benchmarks/transient.py``: its model builder and excitation."""
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    import transient

    return transient


def build_model(case: Case):
    """``transient.build_model``'s grid deck; for an odd bearing count its first bearing fixed."""
    transient = transient_script()
    model = transient.build_model(case.lines, case.per_line, case.axes)
    extra = 2 * case.axes - case.sliding
    connectors = [
        attrs.evolve(c, kind="join", law=None, law_params=(), vertical_stiffness=None) if k < extra else c
        for k, c in enumerate(model.connectors)
    ]
    return attrs.evolve(model, connectors=connectors)


class Counts:
    """Back-substitutions (calls and columns) and law calls, inside steps and outside them."""

    def __init__(self):
        self.phase = "setup"
        self.calls = {"setup": 0, "step": 0}
        self.columns = {"setup": 0, "step": 0}
        self.laws = {"setup": 0, "step": 0}

    def solved(self, rhs) -> None:
        self.calls[self.phase] += 1
        self.columns[self.phase] += 1 if rhs.ndim == 1 else rhs.shape[1]


class CountingFactors:
    """Sparse factors whose ``solve`` counts its right-hand sides; everything else is theirs."""

    def __init__(self, factors, counts: Counts):
        self._factors = factors
        self._counts = counts

    def solve(self, rhs, *args, **kwargs):
        self._counts.solved(rhs)
        return self._factors.solve(rhs, *args, **kwargs)

    def __getattr__(self, name):
        return getattr(self._factors, name)


def counting(system) -> tuple[Counts, Callable[[], None]]:
    """Patch ``hht.factor``, ``hht.step`` and the laws' ``respond`` to count; returns the counts
    and a function that undoes the patches."""
    from bearingfw.analysis import hht

    counts = Counts()
    factor, step = hht.factor, hht.step

    def counted_factor(*args, **kwargs):
        return CountingFactors(factor(*args, **kwargs), counts)

    def counted_step(*args, **kwargs):
        counts.phase = "step"
        try:
            return step(*args, **kwargs)
        finally:
            counts.phase = "setup"

    def counted_law(respond):
        def respond_counted(*args, **kwargs):
            counts.laws[counts.phase] += 1
            return respond(*args, **kwargs)

        return respond_counted

    # (the class's own respond or None: inherited, the respond it has)
    law_classes = {type(g.law) for g in system.connectors.groups}
    originals = {cls: (cls.__dict__.get("respond"), cls.respond) for cls in law_classes}
    hht.factor, hht.step = counted_factor, counted_step
    for cls, (_, respond) in originals.items():
        cls.respond = counted_law(respond)

    def undo() -> None:
        hht.factor, hht.step = factor, step
        for cls, (own, _) in originals.items():
            if own is None:
                del cls.respond
            else:
                cls.respond = own

    return counts, undo


def timed_run(solve, steps: int) -> tuple[float, float]:
    """``(wall, CPU)`` seconds of ``solve(steps)``, a whole run of ``steps`` steps."""
    wall, cpu = time.perf_counter(), time.process_time()
    solve(steps)
    return time.perf_counter() - wall, time.process_time() - cpu


def per_step_of(solve, steps: int) -> tuple[float, float]:
    """``(wall, CPU)`` seconds per step: a run of ``steps`` steps less one of a quarter of them, over
    the steps between, so that the setup and the first calls (the first compiled run of steps
    loads its kernels) cancel; the time loop runs steps in compiled runs of many at once, so a
    clock read between steps would not see each step's own cost."""
    short = max(1, steps // 4)
    full_wall, full_cpu = timed_run(solve, steps)
    short_wall, short_cpu = timed_run(solve, short)
    return (full_wall - short_wall) / (steps - short), (full_cpu - short_cpu) / (steps - short)


def bare_backsubstitution(
    system, damping, dt: float, alpha: float, seconds: float = 0.3, superlu: bool = False
) -> tuple[float, float]:
    """``(wall, CPU)`` seconds of one back-substitution of the run's effective matrix, factorised as
    the run factorises it (``benchmarks/opensees.py``'s ``_backsubstitution``, with the CPU clock:
    on a loaded machine the wall clock counts the waits for a core): bearingfw's compiled one, which
    a step makes, or with ``superlu`` SuperLU's own ``solve`` on the same factors (the unit the
    issue's first measurements used)."""
    import numpy as np

    from bearingfw.analysis.hht import Scheme, effective_matrix, factor

    A = effective_matrix(system.M_free, system.K_free, damping.alpha, damping.beta, Scheme(alpha), dt)
    factors = factor(A)
    solve = factors.lu.solve if superlu else factors.solve
    rhs = np.random.default_rng(0).normal(size=system.n_free)
    solve(rhs)
    repeats, wall, cpu = 0, time.perf_counter(), time.process_time()
    while time.process_time() - cpu < seconds or repeats < 20:
        solve(rhs)
        repeats += 1
    return (time.perf_counter() - wall) / repeats, (time.process_time() - cpu) / repeats


def run_case(case: Case, steps: int, dt: float, threads: int, repeats: int = 1) -> dict:
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(threads)
    except ImportError:
        pass  # the environment variables the parent set hold
    import numpy as np

    from bearingfw.analysis import ConnectorResponse, Rayleigh, TransientSettings, gravity, solve_transient

    transient = transient_script()
    model = build_model(case)
    preload = gravity(model)
    system = preload.system
    damping = Rayleigh(0.21, 0.00208)
    settings = TransientSettings()
    ag = transient.excitation(steps + 1, dt)
    sliding = [c.name for c in model.connectors if c.law]

    from bearingfw.analysis.transient import build_problem

    compiled = build_problem(system, preload, damping, settings).compiled is not None
    counts, undo = counting(system)
    try:
        counted = solve_transient(system, ag, dt, preload=preload, damping=damping, settings=settings,
                                  recorders=[ConnectorResponse(sliding, name="bearings")])  # fmt: skip
    finally:
        undo()
    slip = counted.data["bearings.slip"]  # (t, bearings, 3)
    slipping = int((np.nanmax(np.linalg.norm(np.nan_to_num(slip), axis=2), axis=0) > SLIP).sum())

    per_step = cpu_per_step = backsub = cpu_backsub = cpu_superlu = float("inf")
    runs = []

    def solve(n: int) -> None:
        runs.append(solve_transient(system, ag[: n + 1], dt, preload=preload, damping=damping, settings=settings))

    for _ in range(repeats):
        wall, cpu = per_step_of(solve, steps)
        per_step, cpu_per_step = min(per_step, wall), min(cpu_per_step, cpu)
        wall, cpu = bare_backsubstitution(system, damping, dt, settings.alpha)
        backsub, cpu_backsub = min(backsub, wall), min(cpu_backsub, cpu)
        cpu_superlu = min(cpu_superlu, bare_backsubstitution(system, damping, dt, settings.alpha, superlu=True)[1])
    stats = runs[0].stats  # a run of all the steps
    return {
        "dofs_asked": case.dofs,
        "dof": int(system.n_free),
        "sliding": case.sliding,
        "m": int(system.connectors.n_governed),
        "steps": steps,
        "slipping": slipping,
        "setup_columns": counts.columns["setup"],
        "setup_calls": counts.calls["setup"],
        "backsubs_per_step": counts.calls["step"] / steps,
        "columns_per_step": counts.columns["step"] / steps,
        "law_calls_per_step": counts.laws["step"] / steps,
        # compiled laws (hht_newton): every Newton iterate calls each law group once, the predictor's
        # and each line-search trial's; that is iterations + halvings per step and group
        "compiled_laws": compiled,
        "compiled_law_calls_per_step": len(system.connectors.groups) * (stats["iterations"] + stats["backtracks"]) / steps,
        "iterations_per_step": stats["iterations"] / steps,
        "counted_iterations_per_step": counted.stats["iterations"] / steps,  # equal unless counting changed a run
        "backtracks_per_step": stats["backtracks"] / steps,
        "halvings": stats["subdivisions"],
        "setup_s": stats["setup_time"],
        "ms_per_step": 1e3 * per_step,
        "cpu_ms_per_step": 1e3 * cpu_per_step,
        "backsub_ms": 1e3 * backsub,
        "cpu_backsub_ms": 1e3 * cpu_backsub,
        "cpu_superlu_ms": 1e3 * cpu_superlu,
        "step_over_backsub": cpu_per_step / cpu_backsub,
        "step_over_superlu": cpu_per_step / cpu_superlu,
        "wall_step_over_backsub": per_step / backsub,
        "target": case.target,
        "repeats": repeats,
    }


def _child(case, steps, dt, threads, repeats, queue) -> None:
    try:
        queue.put(run_case(case, steps, dt, threads, repeats))
    except Exception as exc:  # noqa: BLE001 - report instead of leaving the parent waiting
        queue.put({"case": attrs.asdict(case), "error": f"{type(exc).__name__}: {exc}"})


def in_fresh_process(case: Case, steps: int, dt: float, threads: int, repeats: int = 1) -> dict:
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_child, args=(case, steps, dt, threads, repeats, queue))
    proc.start()
    row = queue.get()
    proc.join()
    row["load_average"] = os.getloadavg()[0]
    return row


# --------------------------------------------------------------------------------------------
# Machine and table


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def machine(threads: int | None = None) -> dict:
    """CPU, cores, load, Python, numpy, scipy and numpy's BLAS (and how its threads are set)."""
    import numpy
    import scipy

    import bearingfw

    try:
        blas = numpy.show_config(mode="dicts")["Build Dependencies"]["blas"]
        blas = f"{blas.get('name', '?')} {blas.get('version', '')}".strip()
    except Exception:  # noqa: BLE001 - older numpy: no dict form
        blas = "unknown"
    info = {
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "load_average": os.getloadavg()[0],
        "python": platform.python_version(),
        "bearingfw": bearingfw.__version__,
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "blas": blas,
    }
    if threads is not None:
        try:
            import threadpoolctl  # noqa: F401

            how = "threadpoolctl"
        except ImportError:
            how = "/".join(THREAD_VARIABLES)
        info["blas_threads"] = f"{threads} ({how})"
    return info


def describe(info: dict) -> str:
    text = (f"{info['cpu']}, {info['cores']} cores, load average {info['load_average']:.1f}; Python {info['python']}, "
            f"bearingfw {info['bearingfw']}, numpy {info['numpy']}, scipy {info['scipy']}, BLAS {info['blas']}")  # fmt: skip
    if "blas_threads" in info:
        text += f" on {info['blas_threads']} thread(s)"
    return text


COLUMNS = (  # header, width, format of a row's value
    ("DOFs", 6, lambda r: f"{r['dof']}"),
    ("sliding", 7, lambda r: f"{r['sliding']}"),
    ("m", 4, lambda r: f"{r['m']}"),
    ("slipping", 8, lambda r: f"{r['slipping']}"),
    ("setup bs", 8, lambda r: f"{r['setup_columns']}"),
    ("calls", 5, lambda r: f"{r['setup_calls']}"),
    ("bs/step", 7, lambda r: f"{r['backsubs_per_step']:.2f}"),
    ("cols/step", 9, lambda r: f"{r['columns_per_step']:.2f}"),
    ("it/step", 7, lambda r: f"{r['iterations_per_step']:.2f}"),
    ("ls/step", 7, lambda r: f"{r['backtracks_per_step']:.2f}"),
    ("laws/step", 9, lambda r: f"{r['compiled_law_calls_per_step' if r.get('compiled_laws') else 'law_calls_per_step']:.2f}"),
    ("halvings", 8, lambda r: f"{r['halvings']}"),
    ("ms/step", 8, lambda r: f"{r['ms_per_step']:.3f}"),
    ("CPU ms", 7, lambda r: f"{r['cpu_ms_per_step']:.3f}"),
    ("bs CPU ms", 9, lambda r: f"{r['cpu_backsub_ms']:.4f}"),
    ("step/bs", 7, lambda r: f"{r['step_over_backsub']:.1f}"),
    ("SuperLU ms", 10, lambda r: f"{r['cpu_superlu_ms']:.4f}"),
    ("step/SLU", 8, lambda r: f"{r['step_over_superlu']:.1f}"),
    ("target", 6, lambda r: "-" if r["target"] is None else f"<= {r['target']:.0f}"),
    ("load", 4, lambda r: f"{r['load_average']:.1f}"),
)


def header() -> str:
    return " ".join(f"{name:>{width}}" for name, width, _ in COLUMNS)


def line(row: dict) -> str:
    if "error" in row:
        return f"case {row['case']} failed: {row['error']}"
    text = " ".join(f"{fmt(row):>{width}}" for _, width, fmt in COLUMNS)
    if abs(row["counted_iterations_per_step"] - row["iterations_per_step"]) > 1e-12:
        text += "  (the counted run iterated differently)"
    if row.get("compiled_laws"):
        text += "  (compiled laws: laws/step counts their calls, iterations + halvings per group)"
    elif not row["backsubs_per_step"] or not row["law_calls_per_step"]:
        text += "  (a count is zero: the kernel no longer calls hht.factor's solve or the laws' respond)"
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="200 steps, 300 DOFs (3, 20 bearings) and 3,000 DOFs / 20")
    parser.add_argument("--steps", type=int, default=None, help="integration steps per case (default 1000; quick 200)")
    parser.add_argument("--dt", type=float, default=0.005, help="integration step, s")
    parser.add_argument("--threads", type=int, default=1, help="BLAS threads in the case processes")
    parser.add_argument("--json", action="store_true", help="print one JSON document instead of the table")
    parser.add_argument("--repeats", type=int, default=1, help="timed runs per case, the fastest kept (default 1)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be at least 1, got {args.repeats}")
    for var in THREAD_VARIABLES:
        os.environ[var] = str(args.threads)  # before numpy loads here or in a case process
    steps = args.steps or (200 if args.quick else 1000)
    cases = QUICK if args.quick else CASES
    info = machine(args.threads)
    if not args.json:
        best = f", timings the best of {args.repeats} runs" if args.repeats > 1 else ""
        print(f"step cost: {steps} steps of {args.dt} s, HHT alpha = -0.05, fast path, no recorders, each case in a "
              f"fresh process{best}\nmachine: {describe(info)}", flush=True)  # fmt: skip
        print(header())
        print("-" * len(header()), flush=True)
    rows = []
    for case in cases:
        row = in_fresh_process(case, steps, args.dt, args.threads, args.repeats)
        rows.append(row)
        if not args.json:
            print(line(row), flush=True)
    info["load_average_after"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps({"machine": info, "steps": steps, "dt": args.dt, "rows": rows}, indent=2))
    else:
        print(f"load average at the end: {info['load_average_after']:.1f} on {info['cores']} cores")
    return 1 if any("error" in r for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
