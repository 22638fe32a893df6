#!/usr/bin/env python
"""What the main job costs: the default study's CPU seconds, split into physics, figures, report and I/O.

Usage::

    python benchmarks/main_job.py             # the default study (several minutes of CPU, three times)
    python benchmarks/main_job.py --quick     # a reduced study: 2 models (M1, M2) x 2 levels (D_0, D_II)
    python benchmarks/main_job.py --json      # the same as one JSON document on stdout
    python benchmarks/main_job.py --figures all   # runs 1 and 3 with every figure (default: the study's own)

Measured, each into a new temporary results directory:

1. ``bearingfw run`` as a subprocess with the executor a user gets (``--executor``,
   ``--workers`` and ``--figures`` pass through; default: none given, so the study's own
   ``[figures]``: PNG files of the figures the report shows, drawn while the cells run): its wall
   time and CPU seconds in all, the
   ``bearingfw`` process and its worker processes (``resource.getrusage(RUSAGE_CHILDREN)``, which
   holds every descendant that was waited for), next to the issue's target (40 CPU s).
2. The same with the figures off: ``--figures none`` when the CLI offers it, else its older
   ``--no-figures`` (the output says which), else "n/a"; target 30 CPU s. The difference of the
   two runs is the figures' cost, measured without a profiler.
3. The split: the study once more with ``--executor serial``, in this process, under cProfile
   with its own clock (wall time: a CPU clock given to cProfile slows a step 2.6 times instead of
   1.3 and so weighs call-heavy code more; on a loaded machine the waits for a core fall on all
   code alike, and what the run waits for, e.g. a pool drawing figures, counts). Every
   function's own time goes to the category of its module, or, for a module outside the
   categories (numpy, the standard library, ...), is shared among its callers' categories in
   proportion to the time spent on their behalf (the nearest categorised ancestor: numpy under a
   law is physics, under matplotlib figures). Categories: physics =
   ``bearingfw.analysis``, ``bearingfw.model``, ``bearingfw.laws`` and the modules of the plugin
   laws; figures = matplotlib (with PIL, fontTools, kiwisolver, contourpy), ``bearingfw.plotting``
   and any bearingfw module named for figures or plots; report = ``bearingfw.experiment.report``;
   I/O = ``bearingfw.experiment.store``, json, numpy's npy/npz code, zipfile, csv, pickle,
   shutil, tempfile and the built-in file operations; the rest is "other" (its largest modules
   are listed). The profile's shares are also applied to run 1's CPU seconds (an estimate: the
   profiler slows call-heavy code more than array code, and a run with workers pays their
   start-up too).

``--quick`` runs a reduced study generated from ``bearingfw run --print-default``: models M1 and
M2, levels D_0 and D_II, the findings that use only those (the targets are the full study's).
Timings are CPU seconds, which a loaded machine inflates less than wall time (the load average is
printed with them).
"""

from __future__ import annotations

import argparse
import contextlib
import cProfile
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
BEARINGFW = Path(sys.executable).with_name("bearingfw")  # the console script of this environment
TARGET_ALL = 40.0  # CPU s, issue 16
TARGET_NO_FIGURES = 30.0
QUICK_MODELS = ("M1", "M2")
QUICK_LEVELS = ("D_0", "D_II")
CATEGORIES = ("physics", "figures", "report", "I/O", "other")

FIGURE_PACKAGES = ("matplotlib", "mpl_toolkits", "PIL", "fontTools", "kiwisolver", "contourpy", "bearingfw.plotting")
IO_MODULES = (
    "bearingfw.experiment.store", "json", "numpy.lib.npyio", "numpy.lib._npyio_impl", "numpy.lib.format",
    "numpy.lib._format_impl", "zipfile", "csv", "pickle", "shutil", "tempfile",
)  # fmt: skip
#: built-in functions that are file operations (cProfile names them ``<method 'write' of '_io...'>``)
IO_BUILTINS = re.compile(r"_io\.|<built-in method (io\.open|posix\.(replace|rename|fsync|open|unlink|mkdir|stat))")


# --------------------------------------------------------------------------------------------
# Running the study


def cli(*args: str) -> list[str]:
    command = [str(BEARINGFW)] if BEARINGFW.exists() else [sys.executable, "-m", "bearingfw"]
    return [*command, *args]


def figures_off() -> tuple[list[str], str] | None:
    """The run options that turn the figures off, and how to name them (None: the CLI has none)."""
    text = subprocess.run(cli("run", "--help"), capture_output=True, text=True, check=True).stdout
    if re.search(r"(?<![\w-])--figures\b(?!-)", text):
        return ["--figures", "none"], "--figures none"
    if "--no-figures" in text:
        return ["--no-figures"], "--no-figures (the CLI has no --figures option yet)"
    return None


def to_toml(data: dict) -> str:
    """TOML text of ``data`` (tables and arrays of tables written inline: one key per line)."""

    def value(v) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, int | float):
            return repr(v)
        if isinstance(v, str):
            return json.dumps(v)  # a JSON string is a TOML basic string
        if isinstance(v, list | tuple):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{json.dumps(k)} = {value(x)}" for k, x in v.items()) + "}"
        raise TypeError(f"no TOML form for {type(v).__name__}")

    return "".join(f"{json.dumps(k)} = {value(v)}\n" for k, v in data.items())


def quick_experiment(folder: Path) -> Path:
    """The default study cut to :data:`QUICK_MODELS` x :data:`QUICK_LEVELS`, written into ``folder``."""
    import tomllib

    text = subprocess.run(cli("run", "--print-default"), capture_output=True, text=True, check=True).stdout
    data = tomllib.loads(text)
    data["name"] = f"{data['name']}-quick"
    data["models"] = {name: data["models"][name] for name in QUICK_MODELS}
    data.setdefault("intensities", {})["levels"] = list(QUICK_LEVELS)
    data["intensities"].pop("values", None)
    if data.get("reference") not in QUICK_MODELS:
        data["reference"] = QUICK_MODELS[-1]
    figures = data.get("figures", {})
    for key in ("compare", "intensities"):
        allowed = QUICK_MODELS if key == "compare" else QUICK_LEVELS
        if key in figures:
            figures[key] = [x for x in figures[key] if x in allowed]

    def kept(finding: dict) -> bool:
        models = finding.get("models", [finding.get("model")])
        levels = finding["level"] if isinstance(finding["level"], list) else [finding["level"]]
        return set(models) <= set(QUICK_MODELS) and set(levels) <= set(QUICK_LEVELS)

    data["findings"] = [f for f in data.get("findings", []) if kept(f)]
    path = folder / "quick.toml"
    path.write_text(to_toml(data), encoding="utf-8")
    return path


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def self_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def timed_run(study: list[str], out: Path, extra: list[str]) -> dict:
    """``bearingfw run`` into ``out`` as a subprocess: wall and CPU seconds (it and its workers)."""
    log = out.with_suffix(".log")
    cpu, wall = children_cpu(), time.perf_counter()
    with open(log, "w") as f:
        code = subprocess.run(cli("run", *study, "--out", str(out), *extra), stdout=f, stderr=subprocess.STDOUT).returncode
    row = {"cpu_s": children_cpu() - cpu, "wall_s": time.perf_counter() - wall, "exit": code,
           "load_average": os.getloadavg()[0], "files": sum(1 for p in out.rglob("*") if p.is_file())}  # fmt: skip
    if code not in (0, 1):  # 1: some cell failed, the run completed
        row["error"] = log.read_text()[-2000:]
    return row


# --------------------------------------------------------------------------------------------
# The profile and its split


def module_names() -> dict[str, str]:
    """Source file -> module name, of every module imported so far."""
    names = {}
    for name, module in list(sys.modules.items()):
        path = getattr(module, "__file__", None)
        if path:
            names[os.path.realpath(path)] = name
    return names


def law_packages() -> tuple[str, ...]:
    """The top-level packages of the registered laws that are not part of bearingfw (plugins)."""
    from bearingfw.plugins import get_registry

    packages = {entry.value.__module__.split(".")[0] for entry in get_registry().laws.values()}
    return tuple(sorted(packages - {"bearingfw"}))


def _within(module: str, prefixes) -> bool:
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def classifier(plugin_laws: tuple[str, ...]):
    """``category(module, function name)``: the category a module's own time belongs to, or None
    (shared among the callers' categories)."""
    physics = ("bearingfw.analysis", "bearingfw.model", "bearingfw.laws", *plugin_laws)

    def category(module: str, name: str) -> str | None:
        if module == "~":  # a built-in function
            return "I/O" if IO_BUILTINS.search(name) else None
        if _within(module, physics):
            return "physics"
        last = module.rsplit(".", 1)[-1]
        if _within(module, FIGURE_PACKAGES) or (module.startswith("bearingfw.") and ("figure" in last or "plot" in last)):
            return "figures"
        if module.startswith("bearingfw.") and "report" in last:
            return "report"
        if _within(module, IO_MODULES):
            return "I/O"
        return None

    return category


def split(stats: dict, module_of, category) -> tuple[dict[str, float], dict[str, float]]:
    """Seconds per category of a cProfile ``stats`` table (``pstats.Stats(...).stats``), and the
    "other" seconds per module (by top-level package; bearingfw by module).

    A function's own time goes to its module's category; without one, it is shared among its
    callers' categories (resolved the same way) in proportion to the own time spent for each
    caller (by call count when that is zero); a function nobody categorised called is "other".
    """
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20000))
    memo: dict = {}

    def shares(func, visiting: set) -> dict[str, float]:
        own = category(module_of(func), func[2])
        if own:
            return {own: 1.0}
        if func in memo:
            return memo[func]
        callers = stats[func][4] if func in stats else {}
        weights = {c: edge[2] for c, edge in callers.items()}
        if sum(weights.values()) <= 0:
            weights = {c: edge[1] for c, edge in callers.items()}
        total = sum(weights.values())
        if func in visiting or total <= 0:
            return {"other": 1.0}  # a root, or a cycle back to a function being resolved
        visiting.add(func)
        out: dict[str, float] = defaultdict(float)
        for caller, weight in weights.items():
            for cat, share in shares(caller, visiting).items():
                out[cat] += share * weight / total
        visiting.discard(func)
        memo[func] = dict(out)
        return memo[func]

    seconds: dict[str, float] = dict.fromkeys(CATEGORIES, 0.0)
    other: dict[str, float] = defaultdict(float)
    for func, (_, _, own_time, _, _) in stats.items():
        for cat, share in shares(func, set()).items():
            seconds[cat] += own_time * share
            if cat == "other":
                module = module_of(func)
                other[module if module.startswith("bearingfw") else module.split(".")[0]] += own_time * share
    return seconds, dict(other)


def profiled_run(study: list[str], out: Path, extra: list[str]) -> dict:
    """The study with the serial executor in this process under cProfile (its own clock): its split."""
    import pstats

    from bearingfw.cli.main import main as bearingfw_main

    profiler = cProfile.Profile()
    cpu, children, wall = self_cpu(), children_cpu(), time.perf_counter()
    with open(out.with_suffix(".log"), "w") as log, contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
        try:
            code = profiler.runcall(bearingfw_main, ["run", *study, "--out", str(out), "--executor", "serial", *extra])
        except SystemExit as exc:
            code = exc.code
    cpu_s = self_cpu() - cpu + children_cpu() - children
    wall_s = time.perf_counter() - wall
    stats = pstats.Stats(profiler).stats
    files = module_names()

    def module_of(func) -> str:
        filename = func[0]
        if filename == "~":
            return "~"
        return files.get(os.path.realpath(filename), filename)

    seconds, other = split(stats, module_of, classifier(law_packages()))
    largest = dict(sorted(other.items(), key=lambda kv: -kv[1])[:6])
    return {"cpu_s": cpu_s, "wall_s": wall_s, "exit": code, "profiled_s": sum(seconds.values()), "seconds": seconds,
            "other_modules": largest, "load_average": os.getloadavg()[0]}  # fmt: skip


# --------------------------------------------------------------------------------------------
# Report


def report(result: dict) -> str:
    m, run, off, prof = result["machine"], result["run"], result["figures_off"], result["profile"]
    from step_cost import describe

    lines = [
        f"main job: bearingfw run, {result['study']}, into a new directory; executor: {result['executor']}; "
        f"figures: {result.get('figures', 'the study default')}",
        f"machine: {describe(m)}",
        "",
        f"{'':28} {'CPU s':>8} {'wall s':>8} {'target CPU s':>12} {'files':>6} {'load':>5}",
    ]

    def row(label: str, r: dict | None, target: float) -> str:
        if r is None:
            return f"{label:28} {'n/a':>8} {'n/a':>8} {f'<= {target:.0f}':>12}"
        text = (f"{label:28} {r['cpu_s']:8.1f} {r['wall_s']:8.1f} {f'<= {target:.0f}':>12} {r['files']:6d} "
                f"{r['load_average']:5.1f}")  # fmt: skip
        if r["exit"] not in (0,):
            text += f"  (exit status {r['exit']})"
        return text

    lines.append(row("all (process + workers)", run, TARGET_ALL))
    lines.append(row("figures off", off, TARGET_NO_FIGURES))
    lines.append(f"(figures off: {result['figures_off_label'] or 'the CLI has no option for it'})")
    if off is not None:
        lines.append(f"figures, as the difference of the two runs: {run['cpu_s'] - off['cpu_s']:.1f} CPU s")
    total = prof["profiled_s"]
    lines += [
        "",
        f"split: from the cProfile of a serial run in this process ({prof['cpu_s']:.1f} CPU s and {prof['wall_s']:.1f} s "
        "wall with the profiler);",
        "'profile s': its clock (wall time of this thread); 'run CPU s': the share applied to the run's CPU s above",
        f"{'':28} {'profile s':>9} {'share':>6} {'run CPU s':>9}",
    ]
    for cat in CATEGORIES:
        s = prof["seconds"][cat]
        share = s / total if total else 0.0
        lines.append(f"{cat:28} {s:9.1f} {100 * share:5.1f}% {share * run['cpu_s']:9.1f}")
    lines.append("largest in 'other' (profile s): "
                 + ", ".join(f"{'built-ins' if k == '~' else k} {v:.1f}" for k, v in prof["other_modules"].items()))
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help=f"a reduced study: models {', '.join(QUICK_MODELS)} x levels {', '.join(QUICK_LEVELS)}")
    parser.add_argument("--executor", default=None, help="passed to bearingfw run (default: its own default)")
    parser.add_argument("--workers", type=int, default=None, help="passed to bearingfw run (default: its own default)")
    parser.add_argument("--figures", choices=("none", "report", "all"), default=None,
                        help="passed to bearingfw run in runs 1 and 3 (default: the study's [figures] draw)")
    parser.add_argument("--json", action="store_true", help="print one JSON document instead of the tables")
    parser.add_argument("--keep", action="store_true", help="keep the temporary results directories (their path is printed)")
    args = parser.parse_args(argv)  # fmt: skip
    sys.path.insert(0, str(HERE))
    from step_cost import machine

    folder = Path(tempfile.mkdtemp(prefix="bearingfw-main-job-"))
    result: dict = {}
    try:
        study = [str(quick_experiment(folder))] if args.quick else []
        executor = [*(["--executor", args.executor] if args.executor else []),
                    *(["--workers", str(args.workers)] if args.workers else [])]  # fmt: skip
        off = figures_off()
        result.update({
            "machine": machine(),
            "study": (f"reduced study ({' x '.join(QUICK_MODELS)} models x {' x '.join(QUICK_LEVELS)} levels)"
                      if args.quick else "the default study"),  # fmt: skip
            "executor": " ".join(executor) or "bearingfw run's default",
            "figures_off_label": off[1] if off else None,
        })
        if not args.json:
            print(f"running {result['study']} three times (all, figures off, profiled); load average "
                  f"{result['machine']['load_average']:.1f} on {result['machine']['cores']} cores", flush=True)  # fmt: skip
        drawn = ["--figures", args.figures] if args.figures else []
        result["figures"] = args.figures or "the study's [figures] draw"
        result["run"] = timed_run(study, folder / "all", [*executor, *drawn])
        result["figures_off"] = timed_run(study, folder / "figures-off", [*executor, *off[0]]) if off else None
        result["profile"] = profiled_run(study, folder / "profiled", drawn)
        result["machine"]["load_average_after"] = os.getloadavg()[0]
        if args.json:
            print(json.dumps(result, indent=2, default=str))
        else:
            print(report(result))
        if args.keep:
            print(f"results kept in {folder}", file=sys.stderr)
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)
    failed = [r for r in (result.get("run"), result.get("figures_off")) if r and "error" in r]
    for r in failed:
        print(f"a run failed (exit status {r['exit']}):\n{r['error']}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
