"""Experiments: bearing models x records x intensities on one structure -> cells -> results store ->
comparison matrices, figures, report.

The top layer of bearingfw (it uses every other; nothing imports it but the CLI). An experiment
is a TOML file (:mod:`~bearingfw.experiment.spec`; the built-in one, the paper's study, is
:data:`~bearingfw.experiment.default.DEFAULT_TOML`). Each (model, record, intensity) *cell* is an
independent transient analysis (:mod:`~bearingfw.experiment.cells`,
:mod:`~bearingfw.experiment.execute`), run by an executor (:mod:`~bearingfw.experiment.executors`:
serial, local processes, Dask) and committed atomically to the results store
(:mod:`~bearingfw.experiment.store`) with a hash of its inputs, so that a rerun computes only
what is missing or changed. From the store: matrices (:mod:`~bearingfw.experiment.matrices`),
the paper's findings (:mod:`~bearingfw.experiment.findings`), figures
(:mod:`~bearingfw.experiment.figures`) and ``report.md`` (:mod:`~bearingfw.experiment.report`).
:func:`run_experiment` does it all; ``bearingfw run`` is its command line.

Example::

    from bearingfw.experiment import load_experiment, run_experiment, SerialExecutor

    summary = run_experiment(load_experiment("examples/paper-study.toml"), "results/paper",
                             executor=SerialExecutor())
    summary.exit_code, summary.files["matrices.json"]
"""

from bearingfw.experiment.cells import CellJob, cell_id, plan_cells, recording
from bearingfw.experiment.default import DEFAULT_TOML, default_experiment
from bearingfw.experiment.execute import CellOutcome, CellSummary, compute_cell
from bearingfw.experiment.executors import (
    EXECUTORS,
    DaskExecutor,
    ExecutorError,
    ProcessExecutor,
    SerialExecutor,
    make_executor,
)
from bearingfw.experiment.findings import Finding, paper_findings
from bearingfw.experiment.matrices import Matrices, collect_matrices, format_tables
from bearingfw.experiment.metrics import FAMILIES
from bearingfw.experiment.progress import Progress
from bearingfw.experiment.runner import (
    RunSummary,
    check_experiment,
    default_output,
    run_experiment,
)
from bearingfw.experiment.spec import (
    DampingSpec,
    Experiment,
    FigureSpec,
    Intensity,
    IntensitySpec,
    ModelSpec,
    OutputSpec,
    RecordSpec,
    SpecError,
    StructureSpec,
    load_experiment,
    parse_experiment,
)
from bearingfw.experiment.store import Store, StoreError

__all__ = [
    "DEFAULT_TOML",
    "EXECUTORS",
    "FAMILIES",
    "CellJob",
    "CellOutcome",
    "CellSummary",
    "DampingSpec",
    "DaskExecutor",
    "ExecutorError",
    "Experiment",
    "FigureSpec",
    "Finding",
    "Intensity",
    "IntensitySpec",
    "Matrices",
    "ModelSpec",
    "OutputSpec",
    "ProcessExecutor",
    "Progress",
    "RecordSpec",
    "RunSummary",
    "SerialExecutor",
    "SpecError",
    "Store",
    "StoreError",
    "StructureSpec",
    "cell_id",
    "check_experiment",
    "collect_matrices",
    "compute_cell",
    "default_experiment",
    "default_output",
    "format_tables",
    "load_experiment",
    "make_executor",
    "paper_findings",
    "parse_experiment",
    "plan_cells",
    "recording",
    "run_experiment",
]
