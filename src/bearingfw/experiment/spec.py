"""The experiment description: validated attrs classes, loaded from a TOML file.

An experiment is a TOML file (the built-in one, printed by ``bearingfw run --print-default``,
shows every table with comments). Its tables map onto the classes below: ``[structure]``
:class:`StructureSpec`, ``[models.<name>]`` :class:`ModelSpec`, ``[records.<name>]``
:class:`RecordSpec`, ``[intensities]`` :class:`IntensitySpec`, ``[integration]``
:class:`bearingfw.analysis.TransientSettings` (the transient solver's own settings, field for
field), ``[damping]`` :class:`DampingSpec`, ``[output]`` :class:`OutputSpec`, ``[figures]``
:class:`FigureSpec` and each ``[[findings]]`` a :class:`FindingSpec`.

Loading checks the *form* of the file, with the key's path in every message: an unknown key
(``models.A.mu: unknown key; allowed here: preset, ks, friction, law, params``), a wrong type or
a value out of range (``integration.alpha: ...``), a name that is not in the file (a finding's
model). What needs the installed plugins or the user's code (does the law or the preset exist,
does the builder import, do the record files and the named elements exist) is checked when the
experiment runs (:func:`bearingfw.experiment.runner.check_experiment`).
"""

from __future__ import annotations

import numbers
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import attrs

from bearingfw.analysis import TransientSettings
from bearingfw.experiment.fields import (
    NAME,
    NAME_LENGTH,
    SpecError,
    flag_field,
    listish,
    names_field,
    reals,
    reals_field,
    table_field,
    text_field,
)
from bearingfw.motion import AXES, LEVEL_NAMES, ROLES, IntensityLevels, ScaleTarget, level_name
from bearingfw.parameters import ParameterError, choice, integer_parameter, parameter
from bearingfw.structures import REFERENCE

__all__ = [
    "AGGREGATES",
    "AS_RECORDED",
    "COMPONENT_CHOICES",
    "FINDING_TESTS",
    "DampingSpec",
    "Experiment",
    "FigureSpec",
    "FindingSpec",
    "Intensity",
    "IntensitySpec",
    "ModelSpec",
    "OutputSpec",
    "RecordSpec",
    "RunSpec",
    "SpecError",
    "StructureSpec",
    "from_table",
    "key_path",
    "load_experiment",
    "parse_experiment",
]

#: What a record component can be mapped to (``-`` flips the sign, ``0`` drops the direction).
COMPONENT_CHOICES = (*ROLES, *(f"-{r}" for r in ROLES), "0")
#: How the matrices combine several records: EN 1998-1 4.3.3.4.3 takes the mean of at least seven
#: records and the most unfavourable value of fewer ("ec8"); or always "max" or "mean".
AGGREGATES = ("ec8", "max", "mean")
#: The intensity "the record as it is" (``[intensities] levels = ["as-recorded"]``).
AS_RECORDED = "as-recorded"
#: The tests a finding can make (:class:`FindingSpec`).
FINDING_TESTS = ("within", "below", "above", "equals", "same")

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def key_path(*parts: str) -> str:
    """A key's path as TOML writes it: ``models."A.5".law`` (a part that is not a bare key is quoted)."""
    return ".".join(p if _BARE_KEY.match(p) else '"' + p.replace("\\", "\\\\").replace('"', '\\"') + '"'
                    for p in parts)


# ---- [structure] ------------------------------------------------------------------------------------
@attrs.frozen
class StructureSpec:
    """``[structure]``: the model of the structure and what is recorded on it.

    ``builder``: a structure spec of :mod:`bearingfw.structures`: ``"reference"`` (bearingfw's
    built-in bridge), ``"package.module:function"`` or ``"path/to/file.py:function"`` (relative to
    the experiment file), a function returning a :class:`bearingfw.model.Model` when called with
    ``options`` as keyword arguments (the same as ``--structure`` and ``--option`` on the
    commands). Modules are imported with ``python_path`` and the experiment file's folder on
    ``sys.path``. ``elements``: frame elements whose stresses are metrics (default none).
    ``deck_nodes``: nodes whose absolute acceleration is a metric (default none). ``bearings``: the
    connectors the bearing models govern (default: every connector that is not JOIN).
    ``mode_labels``: a function (named like ``builder``) called with a
    :class:`~bearingfw.analysis.ModalResult` that returns one label per mode for the report's modal
    table, e.g. saying which part of the structure a mode belongs to (default: the kernel's labels).

    A builder that takes a ``preset`` keyword applies a preset bearing model itself (with ``ks``
    and ``friction`` if it takes them), unless ``bearings`` is given; otherwise the preset's laws
    are put on the governed connectors (:mod:`bearingfw.experiment.structure`).
    """

    builder: str = text_field(default=REFERENCE, pattern=re.compile(r"^\S.*$"),
                              hint="'package.module:function', 'path/to/file.py:function' or 'reference'",
                              doc="the function building the model")
    options: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "keyword arguments of the builder"
    )
    elements: tuple[str, ...] | None = names_field(default=None, optional=True, doc="response elements")
    bearings: tuple[str, ...] | None = names_field(default=None, optional=True, doc="connectors the models govern")
    deck_nodes: tuple[str, ...] | None = names_field(default=None, optional=True, doc="nodes for deck accelerations")
    mode_labels: str | None = text_field(
        optional=True, pattern=re.compile(r"^\S.*:\S+$"),
        hint="'package.module:function' or 'path/to/file.py:function'",
        doc="a function naming each mode of a ModalResult, e.g. whose mode it is (default: the kernel's labels)",
    )


# ---- [models.<name>] ----------------------------------------------------------------------------------
@attrs.frozen
class ModelSpec:
    """``[models.<name>]``: a bearing model, the law of the sliding directions.

    Either ``preset`` (a registered bearing preset, see ``bearingfw plugins``) with the optional
    ``ks`` (stick stiffness K_s, N/m) and ``friction`` (mu) it may use, or ``law`` (a registered law
    name) with its ``params``.
    """

    name: str = text_field(pattern=NAME, hint=f"a name of at most {NAME_LENGTH} letters, digits and . _ + - (it names files)")
    preset: str | None = text_field(optional=True, hint="a registered preset name", doc="a bearing preset")
    ks: float | None = parameter(optional=True, low=0.0, low_open=True, unit="N/m", doc="stick stiffness K_s")
    friction: float | None = parameter(optional=True, low=0.0, high=1.0, high_open=True, doc="friction coefficient")
    law: str | None = text_field(optional=True, hint="a registered law name", doc="bearing law")
    params: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "the law's parameters (SI units)"
    )

    def __attrs_post_init__(self):
        if (self.preset is None) == (self.law is None):
            raise SpecError(f"ModelSpec {self.name!r}: give either 'preset' or 'law', not "
                            f"{'both' if self.preset else 'neither'}")
        if self.preset is not None and self.params:
            raise SpecError(f"ModelSpec {self.name!r}: 'params' go with 'law'; a preset takes 'ks' and 'friction'")
        if self.law is not None and (self.ks is not None or self.friction is not None):
            raise SpecError(f"ModelSpec {self.name!r}: 'ks' and 'friction' go with 'preset'; a law takes 'params'")

    def describe(self) -> str:
        if self.preset is not None:
            given = (("ks", self.ks), ("friction", self.friction))
            extra = ", ".join(f"{k} = {v:g}" for k, v in given if v is not None)
            return f"preset {self.preset}" + (f" ({extra})" if extra else "")
        params = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in self.params.items())
        return f"{self.law}" + (f" ({params})" if params else "")


# ---- [records.<name>] ---------------------------------------------------------------------------------
def _check_components(instance, attribute, value):
    ok = isinstance(value, tuple) and len(value) == 3 and all(v in COMPONENT_CHOICES for v in value)
    if not ok:
        raise SpecError(
            f"RecordSpec: field 'components' must be 3 entries for global x, y, z, each one of "
            f"{', '.join(COMPONENT_CHOICES)}; got {value!r}"
        )


def _check_seed(value):
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
        raise SpecError(f"RecordSpec: field 'seed' must be an integer >= 0, got {value!r}")


def _axis_field(axis: str):
    return text_field(optional=True, pattern=re.compile(r"^-?\s*\S.*$"),
                      hint="a record file, optionally '-FILE' (flipped) or 'FILE#k' (its k-th component)",
                      doc=f"the file whose motion acts in global {axis}")


@attrs.frozen
class RecordSpec:
    """``[records.<name>]``: a ground motion, the same at every support unless ``spatial`` says otherwise.

    One of: ``seed`` (the synthetic mining tremor of :func:`bearingfw.motion.synthetic_tremor`;
    ``tremor`` holds fields of :class:`bearingfw.motion.TremorParameters`); ``x``, ``y``, ``z``
    (any subset: the file acting in each global direction, relative to the experiment file,
    ``"FILE#k"`` for the k-th component of a multi-component file, ``"-FILE"`` flipped; a file
    judged vertical may drive x or y only with ``vertical_as_horizontal = true``,
    :func:`bearingfw.motion.load_directional`); or ``files`` (horizontal 1, horizontal 2,
    vertical) with ``components``, the record component applied in global x, y and z (default
    h1 -> x, h2 -> y, v -> z). ``format``, ``dt`` and ``units`` describe files that do not state
    them, as in ``bearingfw record info``. ``spatial``: a table making the motion vary from
    support to support (per-group records or wave passage and loss of coherency generated from
    this one; :class:`bearingfw.experiment.records.SpatialSpec`); empty (default): the same
    motion at every support.
    """

    name: str = text_field(pattern=NAME, hint=f"a name of at most {NAME_LENGTH} letters, digits and . _ + - (it names files)")
    seed: int | None = attrs.field(default=None, validator=lambda i, a, v: _check_seed(v))
    tremor: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "TremorParameters fields of the synthetic tremor"
    )
    files: tuple[str, ...] | None = names_field(default=None, optional=True, doc="record files h1, h2, v")
    format: str | None = text_field(optional=True, hint="a reader name", doc="reader (default: by file suffix)")
    dt: float | None = parameter(optional=True, low=0.0, low_open=True, unit="s", doc="time step of files without one")
    units: str | None = text_field(optional=True, hint="g, m/s^2 or cm/s^2", doc="units of files without them")
    components: tuple[str, str, str] = attrs.field(
        default=tuple(ROLES), converter=listish, validator=_check_components,
        metadata={"doc": "record component applied in global x, y, z"},
    )
    x: str | None = _axis_field("x (along)")
    y: str | None = _axis_field("y (across)")
    z: str | None = _axis_field("z (up)")
    vertical_as_horizontal: bool = flag_field(False, "let a file judged vertical drive x or y")
    spatial: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "ground motion varying from support to support (bearingfw.experiment.records.SpatialSpec); empty: uniform"
    )

    def __attrs_post_init__(self):
        sources = {"seed": self.seed is not None, "files": self.files is not None, "x/y/z": self.mapped}
        given = [k for k, v in sources.items() if v]
        if len(given) != 1:
            raise SpecError(f"RecordSpec {self.name!r}: give one of 'seed' (synthetic tremor), 'files' or 'x'/'y'/'z' "
                            f"(files per direction), not {' and '.join(given) if given else 'none'}")
        if self.seed is None and self.tremor:
            raise SpecError(f"RecordSpec {self.name!r}: 'tremor' parameters go with 'seed', not with files")
        if self.seed is not None and any(v is not None for v in (self.format, self.dt, self.units)):
            raise SpecError(f"RecordSpec {self.name!r}: 'format', 'dt' and 'units' describe files; not with 'seed'")
        if self.mapped and self.components != tuple(ROLES):
            raise SpecError(f"RecordSpec {self.name!r}: 'components' goes with 'files'; with 'x'/'y'/'z' each file "
                            "names its direction already")
        if self.vertical_as_horizontal and not self.mapped:
            raise SpecError(f"RecordSpec {self.name!r}: 'vertical_as_horizontal' goes with 'x'/'y'/'z'")

    @property
    def mapped(self) -> bool:
        """True for a record given by direction (``x``, ``y``, ``z``)."""
        return any(getattr(self, axis) is not None for axis in AXES)

    @property
    def synthetic(self) -> bool:
        return self.seed is not None


# ---- [intensities] ------------------------------------------------------------------------------------
@attrs.frozen
class Intensity:
    """One intensity of the experiment: its name (the cells' and the matrices' column) and the
    :class:`~bearingfw.motion.ScaleTarget` every record is scaled to."""

    name: str
    target: ScaleTarget

    @property
    def pga_h10(self) -> float | None:
        """The target PGA_H10 (m/s^2) of a level or a PGA_H10 value; None for the other kinds."""
        return self.target.value if self.target.kind == "pga_h10" else None

    @property
    def level(self) -> str | None:
        """The level D_0 .. D_IV the intensity stands for (its degree is checked), or None."""
        return self.target.level

    def inputs(self) -> dict:
        """What identifies the intensity in a cell's digest (a level or PGA_H10 as it always was)."""
        if self.target.kind == "pga_h10":
            return {"name": self.name, "pga_h10": self.target.value, "level": self.target.level}
        return {"name": self.name, "target": self.target.to_dict()}


def _level_names(value: Any) -> Any:
    value = listish(value)
    if not isinstance(value, tuple):
        return value
    out = []
    for v in value:
        if isinstance(v, str) and v.strip().lower().replace("_", "-") == AS_RECORDED:
            out.append(AS_RECORDED)
            continue
        try:
            out.append(level_name(v))
        except ParameterError:
            out.append(v)
    return tuple(out)


def _check_levels(instance, attribute, value):
    if value is None:
        return
    allowed = (*LEVEL_NAMES, AS_RECORDED)
    if not isinstance(value, tuple) or not value or not all(v in allowed for v in value):
        raise SpecError(f"IntensitySpec: field 'levels' must be a list of levels among {', '.join(allowed)}, "
                        f"got {value!r}")
    if len(set(value)) != len(value):
        raise SpecError(f"IntensitySpec: field 'levels' names a level twice: {list(value)!r}")


def _check_period(instance, attribute, value):
    if value is None or value == "T1":
        return
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not value > 0:
        raise SpecError(f"IntensitySpec: field 'period' must be a period > 0 (s) or \"T1\" (the structure's first "
                        f"mode), got {value!r}")


#: The largest acceleration an intensity may ask for (m/s^2): 100 g, far beyond any ground motion; a
#: larger target only overflows the scaled record (and its measures) into meaningless numbers.
MAX_ACCELERATION = 1000.0
_WHY_MAX = "100 g, far beyond any ground motion"


@attrs.frozen
class IntensitySpec:
    """``[intensities]``: what every record is scaled to, one intensity per entry, in this order.

    ``levels``: intensity levels D_0 .. D_IV at the PGA_H10 of
    :class:`bearingfw.motion.IntensityLevels` (``values`` overrides some: ``{ D_II = 0.5 }``; a
    record scaled to a level must be of that level's degree on ``scale``, else the cell fails and
    says why), and ``"as-recorded"`` (the record unscaled); ``pga_h10``: PGA_H10 values (m/s^2,
    named ``PGA_H10=<value>``); ``pga``: peak horizontal ground accelerations (m/s^2, the
    horizontal resultant, named ``pga=<value>``); ``sa``: pseudo-spectral accelerations Sa(T, 5 %)
    (m/s^2) at ``period`` T (s, or ``"T1"``: the first mode of the structure as its builder
    returns it; named ``sa=<value>@<T>s`` or ``sa=<value>@T1``). :mod:`bearingfw.motion.scaling` defines each measure.
    Without any of them: the five levels D_0 .. D_IV.
    """

    levels: tuple[str, ...] | None = attrs.field(default=None, converter=_level_names, validator=_check_levels)
    values: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "PGA_H10 (m/s^2) of some levels, replacing the defaults"
    )
    pga_h10: tuple[float, ...] | None = reals_field(what="PGA_H10", unit="m/s^2", high=MAX_ACCELERATION, why=_WHY_MAX)
    pga: tuple[float, ...] | None = reals_field(what="PGA", unit="m/s^2", high=MAX_ACCELERATION, why=_WHY_MAX)
    sa: tuple[float, ...] | None = reals_field(what="Sa(T, 5 %)", unit="m/s^2", high=MAX_ACCELERATION, why=_WHY_MAX)
    period: float | str | None = attrs.field(
        default=None, converter=lambda v: float(v) if isinstance(v, int) and not isinstance(v, bool) else v,
        validator=_check_period, metadata={"doc": "period of Sa (s) or 'T1'", "unit": "s"},
    )
    scale: str | None = text_field(optional=True, hint="a registered intensity scale name", doc="intensity scale")

    def __attrs_post_init__(self):
        if (self.sa is None) != (self.period is None):
            raise SpecError("IntensitySpec: 'sa' and 'period' go together (period: seconds, or \"T1\" for the "
                            "structure's first mode)")
        self.table()  # the level values must make a valid IntensityLevels
        names = [i.name for i in self.resolve()]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise SpecError(f"IntensitySpec: the intensity {twice[0]!r} is given twice")

    def table(self) -> IntensityLevels:
        """The PGA_H10 of each level, defaults with ``values`` applied."""
        try:
            return IntensityLevels.with_overrides(self.values)
        except ParameterError as exc:
            raise SpecError(f"field 'values': {exc}") from None

    @property
    def needs_first_period(self) -> bool:
        """True when an Sa intensity is at the structure's first-mode period (resolved when the run starts)."""
        return self.sa is not None and self.period == "T1"

    def resolve(self, first_period: float | None = None) -> tuple[Intensity, ...]:
        """The intensities in order; an Sa target at "T1" gets ``first_period`` (s) if given."""
        given = any(v is not None for v in (self.levels, self.pga_h10, self.pga, self.sa))
        levels = self.levels if self.levels is not None else (() if given else LEVEL_NAMES)
        table = self.table()
        out = []
        for level in levels:
            target = (ScaleTarget(kind=AS_RECORDED) if level == AS_RECORDED
                      else ScaleTarget.for_level(level, table))
            out.append(target)
        out += [ScaleTarget(kind="pga_h10", value=v) for v in self.pga_h10 or ()]
        out += [ScaleTarget(kind="pga", value=v) for v in self.pga or ()]
        period = None if self.period == "T1" else self.period
        for v in self.sa or ():
            target = ScaleTarget(kind="sa", value=v, period=period)
            if period is None and first_period is not None:
                target = target.with_period(first_period)
            out.append(target)
        return tuple(Intensity(t.label, t) for t in out)


# ---- [damping] ------------------------------------------------------------------------------------------
def _pairs(value: Any) -> Any:
    if isinstance(value, list):
        return tuple(reals(v) if isinstance(v, list) else v for v in value)
    return value


def _check_ratios(instance, attribute, value):
    if value is None:
        return
    ok = (
        isinstance(value, tuple) and len(value) == 2
        and all(isinstance(p, tuple) and len(p) == 2 and all(isinstance(x, float) for x in p) for p in value)
    )
    if not ok:
        raise SpecError(
            f"DampingSpec: field 'ratios' must be two [frequency Hz, damping ratio] pairs, e.g. [[1.5, 0.02], "
            f"[3.5, 0.03]]; got {value!r}"
        )


@attrs.frozen
class DampingSpec:
    """``[damping]``: Rayleigh damping ``C = alpha M + beta K`` of the linear structure.

    Through two ``ratios`` ``[[f1, zeta1], [f2, zeta2]]`` (Hz, -); or directly ``alpha`` (1/s) and
    ``beta`` (s); or ``ratio`` (default 0.02) at the first two natural frequencies of the structure
    as its builder returns it (computed when the run starts).
    """

    ratios: tuple[tuple[float, float], ...] | None = attrs.field(
        default=None, converter=_pairs, validator=_check_ratios
    )
    alpha: float | None = parameter(optional=True, low=0.0, unit="1/s", doc="mass-proportional coefficient")
    beta: float | None = parameter(optional=True, low=0.0, unit="s", doc="stiffness-proportional coefficient")
    ratio: float | None = parameter(optional=True, low=0.0, high=1.0, low_open=True, high_open=True,
                                    doc="damping ratio at the first two natural frequencies (default 0.02)")

    def __attrs_post_init__(self):
        direct = (self.alpha is not None, self.beta is not None)
        ways = [w for w, given in (("ratios", self.ratios is not None), ("alpha and beta", any(direct)),
                                   ("ratio", self.ratio is not None)) if given]
        if len(ways) > 1:
            raise SpecError(f"DampingSpec: give {' or '.join(ways)}, not both")
        if any(direct) and not all(direct):
            raise SpecError("DampingSpec: give both 'alpha' and 'beta' (0 for none)")
        if self.ratios is not None:
            self.rayleigh()  # ratios that give a negative coefficient fail here, with the loader's path

    @property
    def needs_frequencies(self) -> bool:
        """True when the damping is set at the structure's first two frequencies (resolved when the run starts)."""
        return self.ratios is None and self.alpha is None

    @property
    def modal_ratio(self) -> float:
        """The damping ratio put at the first two natural frequencies when neither ratios nor coefficients are given."""
        return 0.02 if self.ratio is None else self.ratio

    def rayleigh(self, frequencies: tuple[float, float] | None = None):
        """The :class:`bearingfw.analysis.Rayleigh` object (``frequencies``: the structure's first two, Hz,
        when :attr:`needs_frequencies`)."""
        from bearingfw.analysis import Rayleigh

        if self.alpha is not None:
            return Rayleigh(self.alpha, self.beta)
        if self.ratios is not None:
            (f1, z1), (f2, z2) = self.ratios
        elif frequencies is not None:
            (f1, f2), z1, z2 = frequencies, self.modal_ratio, self.modal_ratio
        else:
            raise SpecError("damping: the Rayleigh coefficients need the structure's first two frequencies")
        try:
            return Rayleigh.from_ratios(f1, z1, f2, z2)
        except ParameterError as exc:
            raise SpecError(f"field 'ratios': {exc}") from None


# ---- [run] ---------------------------------------------------------------------------------------------------
@attrs.frozen
class RunSpec:
    """``[run]``: when a computed cell is accepted, and how long the run waits.

    Acceptance (a cell that fails a check is stored as ``suspect`` with the reasons, left out of
    the matrices, listed at the top of the report, and the run exits with status 1; see
    :mod:`bearingfw.experiment.acceptance`): ``energy_tolerance``, the largest energy balance
    error accepted (work no term of the balance accounts for, over the largest input work);
    ``dissipation_tolerance``, the largest share of the input work HHT's numerical dissipation may
    remove (an integration step too coarse for the motion shows there); ``min_peak_ratio``, the least
    fraction of each record component's peak that resampling to the integration step may keep
    (below it the cell fails). They are inputs of the cells: changing one computes them again.

    Time limits, not inputs: ``cell_timeout``, the wall time after which a cell still running is
    ended and recorded as failed (an alarm signal in the process computing it, POSIX only: the
    ``serial`` executor's main thread, each worker of ``processes``, whose run also kills a worker
    the alarm cannot reach, 10 s later at the least; Dask runs cells in worker threads, where no
    limit applies); ``dask_no_worker_timeout``, how long a Dask run waits with no live worker
    before it stops with a message.
    """

    energy_tolerance: float = parameter(low=0.0, low_open=True, high=1.0, default=0.01, unit="-",
                                        doc="largest accepted energy balance error (fraction of the input work)")
    dissipation_tolerance: float = parameter(low=0.0, low_open=True, high=1.0, default=0.05, unit="-",
                                             doc="largest accepted numerical dissipation (fraction of the input work)")
    min_peak_ratio: float = parameter(low=0.0, high=1.0, default=0.5, unit="-",
                                      doc="least fraction of a component's peak that resampling may keep")
    cell_timeout: float = parameter(low=0.0, low_open=True, default=3600.0, unit="s",
                                    doc="wall time after which a running cell is ended as failed")
    dask_no_worker_timeout: float = parameter(low=0.0, low_open=True, default=300.0, unit="s",
                                              doc="how long a Dask run waits with no live worker")


# ---- [output], [figures] ----------------------------------------------------------------------------------
@attrs.frozen
class OutputSpec:
    """``[output]``: what the run writes besides the matrices of every metric.

    ``table``: the metrics printed and shown in the report (all are in ``matrices.json`` and the
    CSVs; default: each family's items that the structure has, :func:`default_table`);
    ``aggregate``: how several records combine (:data:`AGGREGATES`); ``histories``: keep each
    cell's time histories (NPZ; figures need them); ``every``: keep every k-th integration step in
    them; ``report``: write ``report.md``.
    """

    table: tuple[str, ...] = names_field(default=(), doc="metrics to print (default: a selection)")
    aggregate: str = choice(AGGREGATES, default="ec8", doc="combination of several records")
    histories: bool = flag_field(True, "keep each cell's histories (NPZ)")
    every: int = integer_parameter(low=1, high=10_000, default=1, doc="keep every k-th integration step")
    report: bool = flag_field(True, "write report.md")


#: What ``[figures] draw`` can be: nothing, the figures report.md shows, or those and the hysteresis sheets.
FIGURE_DRAW = ("none", "report", "all")
#: The formats ``[figures] formats`` can name.
FIGURE_FORMATS = ("png", "svg", "pdf")


def _draw_choice(value: Any) -> Any:
    # true/false, the key's older form, mean the default set of figures and none
    if isinstance(value, bool):
        return "report" if value else "none"
    return value.lower() if isinstance(value, str) else value


def _check_draw(instance, attribute, value):
    if value not in FIGURE_DRAW:
        raise SpecError(f"FigureSpec: field 'draw' must be true or false, or one of "
                        f"{', '.join(map(repr, FIGURE_DRAW))}, got {value!r}")


def _formats(value: Any) -> Any:
    # one format may be given as a string; "PNG" is "png"
    value = (value,) if isinstance(value, str) else listish(value)
    return tuple(v.lower() if isinstance(v, str) else v for v in value) if isinstance(value, tuple) else value


def _check_formats(instance, attribute, value):
    if not isinstance(value, tuple):
        raise SpecError(f"FigureSpec: field 'formats' must be a list of figure formats among "
                        f"{', '.join(map(repr, FIGURE_FORMATS))}, got {value!r}")
    bad = [v for v in value if v not in FIGURE_FORMATS]
    if not value or bad:
        given = f"{bad[0]!r} is not one" if bad else "none given"
        raise SpecError(f"FigureSpec: field 'formats' must list figure formats among "
                        f"{', '.join(map(repr, FIGURE_FORMATS))}; {given}")
    if len(set(value)) != len(value):
        raise SpecError(f"FigureSpec: field 'formats' names a format twice: {list(value)!r}")


@attrs.frozen
class FigureSpec:
    """``[figures]``: which figures the run draws, into ``figures/``.

    ``draw``: ``"report"`` (the default; ``true`` means it too) the figures report.md shows: for
    every record and every intensity in ``intensities`` (default all) the stress histories at
    ``elements`` (default: the first two response elements), the force in ``bearing`` (default:
    the first governed bearing) and its friction ratio (the models whose law there has a
    friction coefficient, with the mu line), each of the models ``compare`` (default all; a
    study names the ones its comparison figures show), the experiment's reference model drawn on top; a
    heatmap per metric of the table, and the records' intensity chart. ``"all"``: those and,
    with ``hysteresis``, the force-displacement loops of every bearing of every model.
    ``"none"`` (or ``false``): no figure. ``formats``: the files of each figure
    (:data:`FIGURE_FORMATS`; default PNG only).
    """

    draw: str = attrs.field(default="report", converter=_draw_choice, validator=_check_draw,
                            metadata={"doc": "which figures: none, report or all", "range": " | ".join(FIGURE_DRAW)})
    formats: tuple[str, ...] = attrs.field(default=("png",), converter=_formats, validator=_check_formats,
                                           metadata={"doc": "files of each figure: png, svg, pdf"})
    intensities: tuple[str, ...] | None = names_field(default=None, optional=True, doc="intensities to draw")
    elements: tuple[str, ...] | None = names_field(default=None, optional=True, doc="elements of the stress figure")
    bearing: str | None = text_field(optional=True, doc="bearing of the force and friction figures")
    compare: tuple[str, ...] | None = names_field(default=None, optional=True, doc="models in the force figure")
    hysteresis: bool = flag_field(True, "draw every bearing's force-displacement loops")


# ---- [[findings]] -----------------------------------------------------------------------------------------
def _levels_list(value: Any) -> Any:
    if isinstance(value, str):
        return (value,)
    return listish(value)


def _check_finding_levels(instance, attribute, value):
    ok = isinstance(value, tuple) and value and all(isinstance(v, str) and v for v in value)
    if not ok:
        raise SpecError(f"FindingSpec: field 'level' must be an intensity name or a list of them, got {value!r}")
    if len(set(value)) != len(value):
        raise SpecError(f"FindingSpec: field 'level' names an intensity twice: {list(value)!r}")


def _check_metric(instance, attribute, value):
    if not isinstance(value, str) or not re.match(r"^[A-Za-z_][\w]*\.\S+$", value):
        raise SpecError(f"FindingSpec: field 'metric' must be 'family.item' (e.g. 'stress_dynamic.G4', "
                        f"'friction_ratio.B7'), got {value!r}")


def _check_pair(instance, attribute, value):
    if value is None:
        return
    ok = isinstance(value, tuple) and len(value) == 2 and all(isinstance(v, str) and v for v in value)
    if not ok or value[0] == value[1]:
        raise SpecError(f"FindingSpec: field 'models' must be two different model names [A, B] (the ratio A/B), "
                        f"got {value!r}")


@attrs.frozen
class FindingSpec:
    """``[[findings]]``: a statement the experiment checks on the matrices, reported with what it measured.

    ``metric`` (``family.item``) at ``level`` (an intensity name, or a list: the statement for
    each), of ``models = [A, B]`` (the ratio A/B at the same intensity) or of ``model = A`` (its
    value, SI units). Exactly one test: ``within = t`` (abs(x - 1) <= t), ``below = b`` (x < b),
    ``above = a`` (x > a), ``equals = e`` (abs(x - e) <= tolerance x abs(e); ``tolerance`` default
    1e-6, absolute when e = 0), or ``same = t`` (x is the same at every ``level`` of the list:
    abs(x_l / x_first - 1) <= t). ``name``: the statement as reported (``{level}`` stands for the
    level; default: written from the fields); ``group``: the heading it is reported under.
    """

    metric: str = attrs.field(validator=_check_metric)
    level: tuple[str, ...] = attrs.field(converter=_levels_list, validator=_check_finding_levels)
    models: tuple[str, str] | None = attrs.field(default=None, converter=listish, validator=_check_pair)
    model: str | None = text_field(optional=True, pattern=NAME, hint="a model name")
    within: float | None = parameter(optional=True, low=0.0, doc="abs(ratio - 1) at most this")
    below: float | None = parameter(optional=True, doc="strictly below this")
    above: float | None = parameter(optional=True, doc="strictly above this")
    equals: float | None = parameter(optional=True, doc="equal to this, within the tolerance")
    tolerance: float | None = parameter(optional=True, low=0.0, doc="relative tolerance of 'equals' (default 1e-6)")
    same: float | None = parameter(optional=True, low=0.0, doc="the same at every level, within this (relative)")
    name: str | None = text_field(optional=True, pattern=re.compile(r"^.*\S.*$"), hint="a non-empty text")
    group: str = text_field(default="Findings", pattern=re.compile(r"^.*\S.*$"), hint="a non-empty text")

    def __attrs_post_init__(self):
        if (self.models is None) == (self.model is None):
            raise SpecError("FindingSpec: give 'models' = [A, B] (the ratio A/B) or 'model' = A (its value), not "
                            f"{'both' if self.model else 'neither'}")
        tests = [t for t in FINDING_TESTS if getattr(self, t) is not None]
        if len(tests) != 1:
            raise SpecError(f"FindingSpec: give exactly one test of {', '.join(FINDING_TESTS)}; got "
                            f"{', '.join(tests) or 'none'}")
        if self.tolerance is not None and self.test != "equals":
            raise SpecError("FindingSpec: 'tolerance' goes with 'equals'")
        if self.test == "same" and len(self.level) < 2:
            raise SpecError("FindingSpec: 'same' compares levels: 'level' must list at least two")

    @property
    def test(self) -> str:
        return next(t for t in FINDING_TESTS if getattr(self, t) is not None)

    @property
    def bound(self) -> float:
        return getattr(self, self.test)

    @property
    def subject(self) -> str:
        """``A/B`` or ``A``."""
        return "/".join(self.models) if self.models else self.model

    @property
    def model_names(self) -> tuple[str, ...]:
        return self.models or (self.model,)


# ---- the experiment ---------------------------------------------------------------------------------------
def _check_module_names(instance, attribute, value):
    if not isinstance(value, tuple) or not all(isinstance(v, str) and re.match(r"^[A-Za-z_][\w.]*$", v) for v in value):
        raise SpecError(f"Experiment: field 'plugins' must be a list of module names, got {value!r}")


@attrs.frozen
class Experiment:
    """A whole experiment: models x records x intensities on one structure (module docstring).

    ``base_dir`` is the folder relative paths start from (the TOML file's); ``source`` the TOML
    text the experiment was read from (copied into the results store).
    """

    name: str = text_field(pattern=NAME, hint=f"a name of at most {NAME_LENGTH} letters, digits and . _ + - (it names the output folder)")
    description: str = text_field(default="")
    reference: str | None = text_field(optional=True, doc="the model the ratios divide by (default the first)")
    plugins: tuple[str, ...] = attrs.field(default=(), converter=listish, validator=_check_module_names)
    python_path: tuple[str, ...] = names_field(default=(), doc="folders (relative to the file) put on sys.path")
    structure: StructureSpec = attrs.field(factory=StructureSpec)
    models: tuple[ModelSpec, ...] = ()
    records: tuple[RecordSpec, ...] = ()
    intensities: IntensitySpec = attrs.field(factory=IntensitySpec)
    integration: TransientSettings = attrs.field(factory=TransientSettings)
    damping: DampingSpec = attrs.field(factory=DampingSpec)
    output: OutputSpec = attrs.field(factory=OutputSpec)
    figures: FigureSpec = attrs.field(factory=FigureSpec)
    findings: tuple[FindingSpec, ...] = ()
    run: RunSpec = attrs.field(factory=RunSpec)
    base_dir: Path = attrs.field(factory=Path.cwd, converter=Path)
    source: str = ""

    def __attrs_post_init__(self):
        if not self.models:
            raise SpecError("models: the experiment needs at least one [models.<name>] table")
        if not self.records:
            raise SpecError("records: the experiment needs at least one [records.<name>] table")
        names = list(self.model_names)
        if self.reference is not None and self.reference not in names:
            raise SpecError(f"reference: {self.reference!r} is not a model; models: {', '.join(names)}")
        intensities = [i.name for i in self.intensity_list]
        for field, given, known in (("figures.intensities", self.figures.intensities, intensities),
                                    ("figures.compare", self.figures.compare, names)):
            bad = [g for g in (given or ()) if g not in known]
            if bad:
                raise SpecError(f"{field}: {bad[0]!r} is not among {', '.join(known)}")
        for k, finding in enumerate(self.findings, start=1):
            for field, given, known in (("models" if finding.models else "model", finding.model_names, names),
                                        ("level", finding.level, intensities)):
                bad = [g for g in given if g not in known]
                if bad:
                    raise SpecError(f"findings[{k}].{field}: {bad[0]!r} is not in the experiment; it has "
                                    f"{', '.join(known)}")

    @property
    def model_names(self) -> tuple[str, ...]:
        return tuple(m.name for m in self.models)

    @property
    def record_names(self) -> tuple[str, ...]:
        return tuple(r.name for r in self.records)

    @property
    def intensity_list(self) -> tuple[Intensity, ...]:
        """The intensities as the file gives them (an Sa target at "T1" still without its period)."""
        return self.intensities.resolve()

    @property
    def reference_model(self) -> str:
        """The model the ratio matrices divide by: ``reference``, else the first model."""
        return self.reference if self.reference is not None else self.model_names[0]

    def model(self, name: str) -> ModelSpec:
        return next(m for m in self.models if m.name == name)

    def record(self, name: str) -> RecordSpec:
        return next(r for r in self.records if r.name == name)

    def resolve_path(self, path: str) -> Path:
        """A path of the file (a record file, a python_path folder), relative to :attr:`base_dir`."""
        p = Path(path).expanduser()
        return p if p.is_absolute() else self.base_dir / p


# ---- loading ----------------------------------------------------------------------------------------------
#: The top-level keys and the class (or kind) of each table.
_TABLES = {
    "structure": StructureSpec,
    "intensities": IntensitySpec,
    "integration": TransientSettings,
    "damping": DampingSpec,
    "output": OutputSpec,
    "figures": FigureSpec,
    "run": RunSpec,
}
_NAMED = {"models": ModelSpec, "records": RecordSpec}
_LISTS = {"findings": FindingSpec}
_SCALARS = ("name", "description", "reference", "plugins", "python_path")


def _fields(cls, exclude=()) -> list[str]:
    return [f.name for f in attrs.fields(cls) if f.name not in exclude and f.init]


def _unknown(path: str, keys, allowed) -> None:
    for key in keys:
        if key not in allowed:
            where = f"{path}.{key}" if path else key
            here = f"[{path}]" if path else "the top level"
            raise SpecError(f"{where}: unknown key; allowed in {here}: {', '.join(allowed)}")


def _message(exc: Exception) -> str:
    # Drop the class prefix of the attrs classes' own messages ("TransientSettings: parameter ..."):
    # the path says where.
    return re.sub(r"^[A-Z][A-Za-z]*( '[^']*')?: ", "", str(exc))


def _at(path: str, exc: Exception) -> str:
    """``path: message``, or ``path.field: rest`` when a check between fields blames one field."""
    text = _message(exc)
    found = re.match(r"^field '(\w+)': (.*)$", text, flags=re.DOTALL)
    return f"{path}.{found[1]}: {found[2]}" if found else f"{path}: {text}"


def from_table(cls, table: Any, path: str, **fixed):
    """An instance of the attrs class ``cls`` from a TOML table, errors prefixed with the key path.

    Each given key is first converted and validated on its own, so that a bad value is reported
    at its own path (``integration.alpha``); then the object is built, which adds the checks
    between fields (reported at the table's path).
    """
    if not isinstance(table, Mapping):
        raise SpecError(f"{path}: must be a table, got {type(table).__name__} {table!r}")
    _unknown(path, table, _fields(cls, exclude=fixed))
    blank = object.__new__(cls)  # for the validators' messages only
    for f in attrs.fields(cls):
        if f.name not in table:
            continue
        value = table[f.name]
        try:
            if f.converter is not None:
                value = f.converter(value)
            if f.validator is not None:
                f.validator(blank, f, value)
        except (ParameterError, TypeError, ValueError) as exc:
            raise SpecError(f"{path}.{f.name}: {_message(exc)}") from None
    try:
        return cls(**fixed, **table)
    except (ParameterError, TypeError, ValueError) as exc:
        raise SpecError(_at(path, exc)) from None


def parse_experiment(text: str, base_dir: str | Path | None = None, origin: str = "<string>") -> Experiment:
    """An :class:`Experiment` from TOML text; relative paths start at ``base_dir`` (default: cwd)."""
    # Windows editors (Notepad) save UTF-8 with a byte-order mark, which TOML does not allow.
    text = text.removeprefix("\ufeff")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{origin}: not valid TOML: {exc}") from None
    try:
        return _experiment(data, Path.cwd() if base_dir is None else Path(base_dir), text)
    except SpecError as exc:
        raise SpecError(f"{origin}: {exc}") from None


def load_experiment(path: str | Path) -> Experiment:
    """Read an experiment file (TOML, module docstring)."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise SpecError(f"{path}: cannot read the experiment file: {exc.strerror or exc}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise SpecError(
            f"{path}: not UTF-8 text (TOML files are UTF-8): byte 0x{data[exc.start]:02x} at byte offset "
            f"{exc.start} (line {line}) cannot be decoded; save the file as UTF-8"
        ) from None
    return parse_experiment(text, path.resolve().parent, str(path))


def _experiment(data: dict, base_dir: Path, text: str) -> Experiment:
    _unknown("", data, (*_SCALARS, *_TABLES, *_NAMED, *_LISTS))
    kwargs: dict[str, Any] = {key: from_table(cls, data[key], key) for key, cls in _TABLES.items() if key in data}
    for key, cls in _NAMED.items():
        tables = data.get(key, {})
        if not isinstance(tables, Mapping):
            raise SpecError(f"{key}: must be tables [{key}.<name>], got {type(tables).__name__} {tables!r}")
        kwargs[key] = tuple(from_table(cls, table, key_path(key, name), name=name) for name, table in tables.items())
    for key, cls in _LISTS.items():
        tables = data.get(key, [])
        if not isinstance(tables, list):
            raise SpecError(f"{key}: must be an array of tables [[{key}]], got {type(tables).__name__} {tables!r}")
        kwargs[key] = tuple(from_table(cls, table, f"{key}[{k}]") for k, table in enumerate(tables, start=1))
    scalars = {key: data[key] for key in _SCALARS if key in data}
    if "name" not in scalars:
        raise SpecError("name: missing; every experiment has a name (it names the output folder)")
    for key in _SCALARS:  # each scalar on its own first: a bad one is reported at its own key
        if key in scalars:
            field = attrs.fields_dict(Experiment)[key]
            try:
                value = field.converter(scalars[key]) if field.converter else scalars[key]
                field.validator(object.__new__(Experiment), field, value)
            except (ParameterError, TypeError, ValueError) as exc:
                raise SpecError(f"{key}: {_message(exc)}") from None
    try:
        return Experiment(**scalars, **kwargs, base_dir=base_dir, source=text)
    except SpecError:
        raise
    except (ParameterError, TypeError, ValueError) as exc:
        raise SpecError(_message(exc)) from None
