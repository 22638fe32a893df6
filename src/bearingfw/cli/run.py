"""``bearingfw run``: run an experiment (models x records x intensities) and write matrices, figures, report."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
import textwrap

from bearingfw.parameters import ParameterError

#: Exit codes (the convention of every command, :mod:`bearingfw.cli.main`): every cell finished and
#: passed its checks; a cell failed or is suspect (the rest completed); the experiment could not run
#: for bad input (a bad file or option, a directory in use or holding another experiment); the
#: environment refused (an executor that cannot be reached, an output that cannot be written:
#: main turns an OSError into 2 or 3 naming the path); interrupted (128 + SIGINT).
OK, CELLS_FAILED, ERROR, ENVIRONMENT, INTERRUPTED = 0, 1, 2, 3, 130


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "run",
        help="run an experiment: bearing models x ground motions x intensities -> matrices, figures, report",
        description=textwrap.fill(
            "Run an experiment described by a TOML file; without one, the built-in experiment: the paper's "
            "comparative study (bearing models M0, M1, M2, fixed and Bouc-Wen on the reference bridge, under the "
            "synthetic mining tremor scaled to D_0 .. D_IV). Each (model, record, intensity) cell is a time-history "
            "analysis, stored as soon as it finishes with a hash of its inputs: a rerun computes only the cells that "
            "are missing, failed, or whose inputs changed, so an interrupted run just continues. Then the comparison "
            "matrices (matrices.json, CSVs), figures (PNG; [figures] formats adds SVG, PDF; the figures of an "
            "intensity are drawn as soon as its cells are done) and report.md are written to the output directory, "
            "which one run at a time writes into (a lock) and which belongs to one experiment (see --take-over).",
            width=88,
        ),
        epilog="exit status: 0 every cell finished and passed its acceptance checks, 1 some cell failed or is "
        "suspect (the others completed; see report.md), 2 the experiment could not run (a bad file or option, or "
        "DIR is in use by another run or holds another experiment), 3 the environment refused (an executor that "
        "cannot be reached, an output that cannot be written), 130 interrupted\n\n"
        "examples:\n"
        "  bearingfw run                                  the paper's study into bearingfw-results/paper-study\n"
        "  bearingfw run --print-default > my.toml        a starting point for your own experiment\n"
        "  bearingfw run my.toml --out results/my --workers 4\n"
        "  bearingfw run my.toml --executor dask --scheduler tcp://10.0.0.5:8786\n"
        "  bearingfw run my.toml --structure bridge.py:build --option spans=3 --out results/mine\n"
        "  bearingfw run --only M2 --levels D_II --quiet --json",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("experiment", nargs="?", metavar="EXPERIMENT.toml",
                        help="the experiment file (default: the built-in paper study)")
    parser.add_argument("--print-default", action="store_true",
                        help="print the built-in experiment's TOML (every option, commented) and exit")
    parser.add_argument("--out", metavar="DIR",
                        help="results directory (default: bearingfw-results/<experiment name> here)")
    parser.add_argument("--executor", metavar="NAME",
                        help="who computes the cells: serial (this process), processes (local worker processes, the "
                        "default), dask (Dask distributed, the 'dask' extra), or a plugin's executor "
                        "(`bearingfw plugins` lists them)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="worker processes (default: one per core; for dask without --scheduler, the local "
                        "cluster's workers)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="Dask scheduler to use (implies --executor dask; default: a local cluster)")
    parser.add_argument("--reference", metavar="MODEL",
                        help="model the ratios divide by (default: the file's, or the first model)")
    parser.add_argument("--structure", metavar="SPEC",
                        help="your structure: 'package.module:function' or 'path/to/file.py:function' (relative to "
                        "here), a function returning a bearingfw Model; replaces the experiment's [structure] builder "
                        "and options. What names items of the file's structure is left out: [structure] elements, "
                        "deck_nodes, bearings, [output] table, [figures] elements and bearing, [[findings]]")
    parser.add_argument("--option", action="append", metavar="KEY=VALUE",
                        help="a keyword argument of the structure's function, repeatable (added to [structure] "
                        "options, or the only ones with --structure); VALUE is read as a TOML value (4e8, true, "
                        "[1, 2], \"text\"), a bare word as text")
    parser.add_argument("--force", action="store_true", help="recompute every cell, finished or not")
    parser.add_argument("--take-over", action="store_true",
                        help="run even if DIR holds another experiment's results (or other files): cells with the "
                        "same inputs are reused, the others are left on disk, outside the new results")
    parser.add_argument("--only", action="append", metavar="MODEL",
                        help="run only this model's cells (repeat for several); the matrices show all finished cells")
    parser.add_argument("--levels", action="append", metavar="INTENSITY",
                        help="run only this intensity's cells, e.g. D_II (repeat for several)")
    parser.add_argument("--figures", choices=("none", "report", "all"), metavar="{none,report,all}",
                        help="which figures to draw, overriding the file's [figures] draw: none, report (those "
                        "report.md shows: the default) or all (with every model's bearing hysteresis sheets)")
    parser.add_argument("--no-figures", action="store_true", help="the same as --figures none")
    parser.add_argument("--quiet", action="store_true", help="no progress and no tables (errors only)")
    parser.add_argument("--json", action="store_true", help="print a JSON summary at the end")
    parser.set_defaults(func=run)


def _own_structure(experiment, spec: str | None, pairs: list[str] | None) -> dict:
    """The changes of ``--structure SPEC`` and ``--option key=value`` to the experiment."""
    import re
    from pathlib import Path

    import attrs

    from bearingfw.experiment import StructureSpec
    from bearingfw.structures import parse_options

    options = parse_options(pairs)
    if spec is None:
        structure = experiment.structure
        return {"structure": attrs.evolve(structure, options={**structure.options, **options})}
    target, _, function = spec.rpartition(":")
    python_path = experiment.python_path
    if target.endswith(".py"):  # a file named from here, not from the experiment file's folder
        spec = f"{Path(target).expanduser().resolve()}:{function}"
    else:  # a module importable from here too
        python_path = (*python_path, str(Path.cwd()))
    slug = re.sub(r"[^A-Za-z0-9._+-]+", "_", f"{Path(target).stem}.{function}")
    return {
        "name": f"{experiment.name}+{slug}",  # not the results of the file's own structure
        "python_path": tuple(dict.fromkeys(python_path)),
        "structure": StructureSpec(builder=spec, options=options),
        "output": attrs.evolve(experiment.output, table=()),
        "figures": attrs.evolve(experiment.figures, elements=None, bearing=None),
        "findings": (),
    }


def _experiment(args):
    import attrs

    from bearingfw.experiment import default_experiment, load_experiment

    experiment = load_experiment(args.experiment) if args.experiment else default_experiment()
    changes = {}
    if args.structure is not None or args.option:
        changes.update(_own_structure(experiment, args.structure, args.option))
    if args.reference:
        changes["reference"] = args.reference
    if args.no_figures and args.figures not in (None, "none"):
        raise ParameterError(f"--no-figures and --figures {args.figures} contradict each other; give one")
    draw = "none" if args.no_figures else args.figures
    if draw is not None:
        changes["figures"] = attrs.evolve(changes.get("figures", experiment.figures), draw=draw)
    if changes:
        try:
            experiment = attrs.evolve(experiment, **changes)
        except ParameterError as exc:
            given = "--reference" if args.reference else "--structure"
            raise ParameterError(f"{given}: {exc}") from None
    return experiment


@contextlib.contextmanager
def _stdout_to_stderr():
    """While the study runs, what its code prints (a structure builder's or a law's print) goes to
    stderr, so that ``--json`` leaves the JSON alone on stdout: at the file descriptor too, which
    the worker processes inherit, where stdout is a real file."""
    sys.stdout.flush()
    try:
        out, err = sys.stdout.fileno(), sys.stderr.fileno()
    except (AttributeError, OSError, ValueError):  # not a file (e.g. captured): the Python level only
        with contextlib.redirect_stdout(sys.stderr):
            yield
        return
    saved = os.dup(out)
    try:
        os.dup2(err, out)
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        sys.stderr.flush()
        os.dup2(saved, out)
        os.close(saved)


def _print_results(summary, out) -> None:
    from bearingfw.experiment import format_tables

    print(format_tables(summary.matrices, summary.table), file=out)
    groups: dict = {}
    for f in summary.findings:
        groups.setdefault(f.group, []).append(f)
    for group, findings in groups.items():
        print(f"\n{group}:", file=out)
        for f in findings:
            mark = {True: "yes", False: "NO ", None: "n/a"}[f.holds]
            print(f"  [{mark}] {f.statement}: {f.measured}", file=out)
    if summary.failed:
        print(f"\n{len(summary.failed)} cell(s) failed:", file=out)
        for cell, error in summary.failed:
            print(f"  {cell}: {error}", file=out)
    if summary.suspect:
        print(f"\n{len(summary.suspect)} cell(s) SUSPECT (ran, but failed an acceptance check; left out of the "
              "matrices):", file=out)
        for cell, reasons in summary.suspect:
            print(f"  {cell}: {reasons}", file=out)
    print(f"\nresults: {summary.out} (matrices.json, matrices/, figures/, report.md)", file=out)


def run(args) -> int:
    from bearingfw.experiment import (
        DEFAULT_TOML,
        ExecutorError,
        ExecutorUnavailable,
        Progress,
        StoreError,
        make_executor,
        run_experiment,
    )
    from bearingfw.experiment.structure import import_paths, registry_for

    if args.print_default:
        sys.stdout.write(DEFAULT_TOML)
        return OK
    # what the study's code prints (a builder's print) must not mix into --json's stdout
    with _stdout_to_stderr() if args.json else contextlib.nullcontext():
        try:
            experiment = _experiment(args)
            name = args.executor or ("dask" if args.scheduler else "processes")
            registry = registry_for(experiment.plugins, import_paths(experiment))  # the experiment's plugins too
            executor = make_executor(name, args.workers, args.scheduler, registry)
            progress = Progress(quiet=args.quiet)
            summary = run_experiment(
                experiment, args.out, executor, force=args.force, models=tuple(args.only or ()),
                intensities=tuple(args.levels or ()), progress=progress, take_over=args.take_over,
            )
        except KeyboardInterrupt:
            print("\nbearingfw run: interrupted; finished cells are kept, run again to continue", file=sys.stderr)
            return INTERRUPTED
        except ExecutorUnavailable as exc:
            print(f"bearingfw run: error: {exc}", file=sys.stderr)
            return ENVIRONMENT
        except (ParameterError, ExecutorError, StoreError) as exc:
            print(f"bearingfw run: error: {exc}", file=sys.stderr)
            return ERROR
    if not args.quiet:
        _print_results(summary, sys.stderr if args.json else sys.stdout)
    if args.json:
        from bearingfw.experiment.store import jsonable

        print(json.dumps(jsonable(summary.to_dict()), indent=2))
    return CELLS_FAILED if summary.exit_code else OK
