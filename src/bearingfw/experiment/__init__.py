"""Experiments: bearing models x records x intensities on one structure -> cells -> results store ->
comparison matrices, figures, report.

The top layer of bearingfw (it uses every other; nothing imports it but the CLI). An experiment
is a TOML file (:mod:`~bearingfw.experiment.spec`; the built-in one is
:data:`~bearingfw.experiment.default.DEFAULT_TOML`, a study definition held outside the engine).
Each (model, record, intensity) *cell* is an
independent transient analysis (:mod:`~bearingfw.experiment.cells`,
:mod:`~bearingfw.experiment.execute`), run by an executor (:mod:`~bearingfw.experiment.executors`:
serial, local processes, Dask, or a plugin's) and committed atomically to the results store
(:mod:`~bearingfw.experiment.store`) with a hash of its inputs, so that a rerun computes only
what is missing or changed. From the store: matrices of every metric family
(:mod:`~bearingfw.experiment.metrics`, :mod:`~bearingfw.experiment.matrices`), the experiment's
declared findings (:mod:`~bearingfw.experiment.findings`), figures
(:mod:`~bearingfw.experiment.figures`) and ``report.md`` (:mod:`~bearingfw.experiment.report`).
:func:`run_experiment` does it all; ``bearingfw run`` is its command line.

Example::

    from bearingfw.experiment import load_experiment, make_executor, run_experiment

    summary = run_experiment(load_experiment("examples/small-bridge/small-bridge.toml"), "results/small",
                             executor=make_executor("serial"))
    summary.exit_code, summary.files["matrices.json"]
"""

from bearingfw.experiment.cells import CellJob, cell_id, plan_cells, recording
from bearingfw.experiment.default import DEFAULT_TOML, default_experiment
from bearingfw.experiment.execute import CellOutcome, CellSummary, compute_cell
from bearingfw.experiment.executors import (
    EXECUTORS,
    DaskExecutor,
    Executor,
    ExecutorError,
    ExecutorUnavailable,
    ProcessExecutor,
    SerialExecutor,
    make_executor,
)
from bearingfw.experiment.findings import Finding, check_findings
from bearingfw.experiment.matrices import Matrices, collect_matrices, format_tables
from bearingfw.experiment.metrics import CellResponse, MetricFamily, Peak, metric_families
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
    FindingSpec,
    Intensity,
    IntensitySpec,
    ModelSpec,
    OutputSpec,
    RecordSpec,
    RunSpec,
    SpecError,
    StructureSpec,
    load_experiment,
    parse_experiment,
)
from bearingfw.experiment.store import Store, StoreError

__all__ = [
    "DEFAULT_TOML",
    "EXECUTORS",
    "CellJob",
    "CellOutcome",
    "CellResponse",
    "CellSummary",
    "DampingSpec",
    "DaskExecutor",
    "Executor",
    "ExecutorError",
    "ExecutorUnavailable",
    "Experiment",
    "FigureSpec",
    "Finding",
    "FindingSpec",
    "Intensity",
    "IntensitySpec",
    "Matrices",
    "MetricFamily",
    "ModelSpec",
    "OutputSpec",
    "Peak",
    "ProcessExecutor",
    "Progress",
    "RecordSpec",
    "RunSpec",
    "RunSummary",
    "SerialExecutor",
    "SpecError",
    "Store",
    "StoreError",
    "StructureSpec",
    "cell_id",
    "check_experiment",
    "check_findings",
    "collect_matrices",
    "compute_cell",
    "default_experiment",
    "default_output",
    "format_tables",
    "load_experiment",
    "make_executor",
    "metric_families",
    "parse_experiment",
    "plan_cells",
    "recording",
    "run_experiment",
]
