"""The experiment description: validated attrs classes, loaded from a TOML file.

An experiment is a TOML file (see :data:`bearingfw.experiment.default.DEFAULT_TOML`, printed
by ``bearingfw run --print-default``, for every table with comments). Its tables map onto the
classes below: ``[structure]`` :class:`StructureSpec`, ``[models.<name>]`` :class:`ModelSpec`,
``[records.<name>]`` :class:`RecordSpec`, ``[intensities]`` :class:`IntensitySpec`,
``[integration]`` :class:`bearingfw.analysis.TransientSettings` (the transient solver's own
settings, field for field), ``[damping]`` :class:`DampingSpec`, ``[output]`` :class:`OutputSpec`
and ``[figures]`` :class:`FigureSpec`.

Loading checks the *form* of the file, with the key's path in every message: an unknown key
(``models.M2.mu: unknown key; allowed here: preset, ks, friction, law, params``), a wrong type or
a value out of range (``integration.alpha: ...``). What needs the installed plugins or the user's
code (does the law exist, does the builder import, do the record files exist) is checked when the
experiment runs (:func:`bearingfw.experiment.structure.check_experiment`).
"""

from __future__ import annotations

import math
import numbers
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import attrs

from bearingfw.analysis import TransientSettings
from bearingfw.bridges import PRESETS
from bearingfw.bridges.paper import DAMPING_RATIOS
from bearingfw.motion import LEVEL_NAMES, ROLES, IntensityLevels, level_name
from bearingfw.parameters import ParameterError, choice, integer_parameter, parameter

__all__ = [
    "AGGREGATES",
    "COMPONENT_CHOICES",
    "REFERENCE_BUILDER",
    "DampingSpec",
    "Experiment",
    "FigureSpec",
    "Intensity",
    "IntensitySpec",
    "ModelSpec",
    "OutputSpec",
    "RecordSpec",
    "SpecError",
    "StructureSpec",
    "from_table",
    "key_path",
    "load_experiment",
    "parse_experiment",
]

#: ``[structure] builder`` of the paper's reference bridge (:mod:`bearingfw.bridges`).
REFERENCE_BUILDER = "reference"
#: What a record component can be mapped to (``-`` flips the sign, ``0`` drops the direction).
COMPONENT_CHOICES = (*ROLES, *(f"-{r}" for r in ROLES), "0")
#: How the matrices combine several records: EN 1998-1 4.3.3.4.3 takes the mean of at least seven
#: records and the most unfavourable value of fewer ("ec8"); or always "max" or "mean".
AGGREGATES = ("ec8", "max", "mean")

# Models, records and intensities name files of the results store: keep them portable.
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._+-]*$")
_MODULE_FUNCTION = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$")


class SpecError(ParameterError):
    """The experiment file is malformed; the message starts with the key's path."""


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def key_path(*parts: str) -> str:
    """A key's path as TOML writes it: ``models."M2.5".law`` (a part that is not a bare key is quoted)."""
    return ".".join(p if _BARE_KEY.match(p) else '"' + p.replace("\\", "\\\\").replace('"', '\\"') + '"'
                    for p in parts)


# ---- field helpers ------------------------------------------------------------------------------
def _listish(value: Any) -> Any:
    return tuple(value) if isinstance(value, list) else value


def _owner(instance) -> str:
    return type(instance).__name__


def names_field(*, default: Any = (), optional: bool = False, allowed: tuple[str, ...] | None = None, doc: str = ""):
    """A list of distinct non-empty strings (stored as a tuple); ``None`` if optional and not given."""

    def check(instance, attribute, value):
        if value is None and optional:
            return
        ok = isinstance(value, tuple) and all(isinstance(v, str) and v for v in value)
        if not ok:
            raise SpecError(f"{_owner(instance)}: field {attribute.name!r} must be a list of names, got {value!r}")
        if len(set(value)) != len(value):
            raise SpecError(f"{_owner(instance)}: field {attribute.name!r} names an item twice: {list(value)!r}")
        if allowed is not None:
            bad = [v for v in value if v not in allowed]
            if bad:
                raise SpecError(
                    f"{_owner(instance)}: field {attribute.name!r} has {bad[0]!r}; allowed: {', '.join(allowed)}"
                )

    return attrs.field(default=default, converter=_listish, validator=check, metadata={"doc": doc})


def text_field(*, default: Any = attrs.NOTHING, optional: bool = False, pattern: re.Pattern | None = None,
               hint: str = "", doc: str = ""):
    """A string (matching ``pattern`` if given); ``None`` if optional and not given."""

    def check(instance, attribute, value):
        if value is None and optional:
            return
        if not isinstance(value, str) or (pattern is not None and not pattern.match(value)):
            raise SpecError(
                f"{_owner(instance)}: field {attribute.name!r} must be {hint or 'a string'}, "
                f"got {type(value).__name__} {value!r}"
            )

    if optional and default is attrs.NOTHING:
        default = None
    return attrs.field(default=default, validator=check, metadata={"doc": doc})


def flag_field(default: bool, doc: str = ""):
    """A boolean (TOML true/false; not 0/1)."""

    def check(instance, attribute, value):
        if not isinstance(value, bool):
            raise SpecError(f"{_owner(instance)}: field {attribute.name!r} must be true or false, got {value!r}")

    return attrs.field(default=default, validator=check, metadata={"doc": doc})


def table_field(doc: str = ""):
    """A table of keyword arguments (string keys), stored as a plain dict."""

    def check(instance, attribute, value):
        if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
            raise SpecError(f"{_owner(instance)}: field {attribute.name!r} must be a table, got {value!r}")

    return attrs.field(factory=dict, converter=lambda v: dict(v) if isinstance(v, Mapping) else v, validator=check,
                       metadata={"doc": doc})


def _reals(value: Any) -> Any:
    if isinstance(value, list):
        return tuple(float(v) if isinstance(v, numbers.Real) and not isinstance(v, bool) else v for v in value)
    return value


# ---- the tables -----------------------------------------------------------------------------------
@attrs.frozen
class StructureSpec:
    """``[structure]``: the bridge model and what is recorded on it.

    ``builder``: ``"reference"`` (the paper's bridge; ``options`` are fields of
    :class:`bearingfw.bridges.BridgeParameters`) or ``"package.module:function"``, a function
    returning a :class:`bearingfw.model.Model` when called with ``options`` as keyword arguments.
    The module is imported with ``python_path`` (top level) and the experiment file's folder on
    ``sys.path``. ``elements``: frame elements whose stresses are metrics (reference default: the
    paper's S1, S2, 2A..5A, 2B..5B; otherwise none). ``bearings``: the connectors the bearing
    models govern (user builders only; default every connector with a law, i.e. not JOIN).
    ``deck_nodes``: nodes whose absolute acceleration is a metric (reference default: both girders
    at the middle of every span; otherwise none).
    """

    builder: str = text_field(
        default=REFERENCE_BUILDER,
        pattern=re.compile(rf"^({REFERENCE_BUILDER}|{_MODULE_FUNCTION.pattern[1:-1]})$"),
        hint=f"{REFERENCE_BUILDER!r} or 'package.module:function'",
        doc="the reference bridge or a function building the model",
    )
    options: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "keyword arguments of the builder (reference: BridgeParameters fields)"
    )
    elements: tuple[str, ...] | None = names_field(default=None, optional=True, doc="response elements")
    bearings: tuple[str, ...] | None = names_field(default=None, optional=True, doc="connectors the models govern")
    deck_nodes: tuple[str, ...] | None = names_field(default=None, optional=True, doc="nodes for deck accelerations")

    @property
    def is_reference(self) -> bool:
        return self.builder == REFERENCE_BUILDER

    def __attrs_post_init__(self):
        if self.is_reference and self.bearings is not None:
            raise SpecError(
                "field 'bearings': only for user builders; on the reference bridge the models govern every "
                "sliding bearing (the presets of bearingfw.bridges)"
            )


@attrs.frozen
class ModelSpec:
    """``[models.<name>]``: a bearing model, the law of the sliding directions.

    Either ``preset`` (one of :data:`bearingfw.bridges.PRESETS`: M0, M1, M2, fixed, bouc-wen)
    with the optional ``ks`` (stick stiffness K_s, N/m) and ``friction`` (mu), or ``law`` (a
    registered law name, see ``bearingfw plugins``) with its ``params``.
    """

    name: str = text_field(pattern=_NAME, hint="a name of letters, digits and . _ + - (it names files)")
    preset: str | None = text_field(
        optional=True, pattern=re.compile(f"^({'|'.join(map(re.escape, PRESETS))})$"),
        hint=f"one of {', '.join(PRESETS)}", doc="a preset of bearingfw.bridges (the names are case-sensitive)",
    )
    ks: float | None = parameter(optional=True, low=0.0, low_open=True, unit="N/m", doc="stick stiffness K_s")
    friction: float | None = parameter(optional=True, low=0.0, high=1.0, high_open=True, doc="friction coefficient")
    law: str | None = text_field(optional=True, hint="a registered law name", doc="bearing law")
    params: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "the law's parameters (SI units)"
    )

    def __attrs_post_init__(self):
        if (self.preset is None) == (self.law is None):
            raise SpecError(f"ModelSpec {self.name!r}: give either 'preset' ({', '.join(PRESETS)}) or 'law', not "
                            f"{'both' if self.preset else 'neither'}")
        if self.preset is not None and self.params:
            raise SpecError(f"ModelSpec {self.name!r}: 'params' go with 'law'; a preset takes 'ks' and 'friction'")
        if self.law is not None and (self.ks is not None or self.friction is not None):
            raise SpecError(f"ModelSpec {self.name!r}: 'ks' and 'friction' go with 'preset'; a law takes 'params'")

    @property
    def friction_coefficient(self) -> float | None:
        """The mu of this model's friction law, if it has one (the friction figure's line)."""
        if self.preset in ("M2", "bouc-wen"):
            from bearingfw.bridges.paper import FRICTION

            return FRICTION if self.friction is None else self.friction
        value = self.params.get("mu")
        return float(value) if isinstance(value, numbers.Real) else None

    def describe(self) -> str:
        if self.preset is not None:
            given = (("ks", self.ks), ("friction", self.friction))
            extra = ", ".join(f"{k} = {v:g}" for k, v in given if v is not None)
            return f"preset {self.preset}" + (f" ({extra})" if extra else "")
        params = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in self.params.items())
        return f"{self.law}" + (f" ({params})" if params else "")


def _check_components(instance, attribute, value):
    ok = isinstance(value, tuple) and len(value) == 3 and all(v in COMPONENT_CHOICES for v in value)
    if not ok:
        raise SpecError(
            f"RecordSpec: field 'components' must be 3 entries for global x, y, z, each one of "
            f"{', '.join(COMPONENT_CHOICES)}; got {value!r}"
        )


@attrs.frozen
class RecordSpec:
    """``[records.<name>]``: a three-component ground motion.

    Either ``seed`` (the synthetic mining tremor of :func:`bearingfw.motion.synthetic_tremor`;
    ``tremor`` holds fields of :class:`bearingfw.motion.TremorParameters`) or ``files``
    (horizontal 1, horizontal 2, vertical, relative to the experiment file; ``format``, ``dt`` and
    ``units`` as in ``bearingfw record info``). ``components``: the record component applied in
    global x, y and z, the same at every support (default h1 -> x along the bridge, h2 -> y
    across, v -> z).
    """

    name: str = text_field(pattern=_NAME, hint="a name of letters, digits and . _ + - (it names files)")
    seed: int | None = attrs.field(default=None, validator=lambda i, a, v: _check_seed(v))
    tremor: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "TremorParameters fields of the synthetic tremor"
    )
    files: tuple[str, ...] | None = names_field(default=None, optional=True, doc="record files h1, h2, v")
    format: str | None = text_field(optional=True, hint="a reader name", doc="reader (default: by file suffix)")
    dt: float | None = parameter(optional=True, low=0.0, low_open=True, unit="s", doc="time step of files without one")
    units: str | None = text_field(optional=True, hint="g, m/s^2 or cm/s^2", doc="units of files without them")
    components: tuple[str, str, str] = attrs.field(
        default=tuple(ROLES), converter=_listish, validator=_check_components,
        metadata={"doc": "record component applied in global x, y, z"},
    )

    def __attrs_post_init__(self):
        if (self.seed is None) == (self.files is None):
            raise SpecError(f"RecordSpec {self.name!r}: give either 'seed' (synthetic tremor) or 'files', not "
                            f"{'both' if self.seed is not None else 'neither'}")
        if self.files is not None and self.tremor:
            raise SpecError(f"RecordSpec {self.name!r}: 'tremor' parameters go with 'seed', not with 'files'")
        if self.seed is not None and any(v is not None for v in (self.format, self.dt, self.units)):
            raise SpecError(f"RecordSpec {self.name!r}: 'format', 'dt' and 'units' describe files; not with 'seed'")

    @property
    def synthetic(self) -> bool:
        return self.seed is not None


def _check_seed(value):
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
        raise SpecError(f"RecordSpec: field 'seed' must be an integer >= 0, got {value!r}")


@attrs.frozen
class Intensity:
    """One intensity of the study: its name, PGA_H10 (m/s^2), and the level it stands for (or None)."""

    name: str
    pga_h10: float
    level: str | None = None


def _level_names(value: Any) -> Any:
    value = _listish(value)
    if isinstance(value, tuple):
        try:
            return tuple(level_name(v) for v in value)
        except ParameterError:
            return value
    return value


def _check_levels(instance, attribute, value):
    if value is None:
        return
    if not isinstance(value, tuple) or not value or not all(v in LEVEL_NAMES for v in value):
        raise SpecError(f"IntensitySpec: field 'levels' must be a list of levels among {', '.join(LEVEL_NAMES)}, "
                        f"got {value!r}")
    if len(set(value)) != len(value):
        raise SpecError(f"IntensitySpec: field 'levels' names a level twice: {list(value)!r}")


def _check_pga(instance, attribute, value):
    if value is None:
        return
    ok = isinstance(value, tuple) and value and all(isinstance(v, float) and math.isfinite(v) and v > 0 for v in value)
    if not ok:
        raise SpecError(f"IntensitySpec: field 'pga_h10' must be a list of PGA_H10 values > 0 (m/s^2), got {value!r}")
    if len(set(value)) != len(value):
        raise SpecError(f"IntensitySpec: field 'pga_h10' gives a value twice: {list(value)!r}")


@attrs.frozen
class IntensitySpec:
    """``[intensities]``: the intensities every record is scaled to.

    ``levels`` (default D_0 .. D_IV) at the PGA_H10 of :class:`bearingfw.motion.IntensityLevels`,
    with ``values`` overriding some (``{ D_II = 0.5 }``); a record scaled to a level must then be
    of that level's degree on ``scale`` (default: the default scale), else the cell fails and says
    why. Or ``pga_h10``: plain PGA_H10 values (m/s^2), named ``PGA_H10=<value>``.
    """

    levels: tuple[str, ...] | None = attrs.field(default=None, converter=_level_names, validator=_check_levels)
    values: dict = table_field(  # noqa: RUF009 - an attrs field with a factory, not a shared default
        "PGA_H10 (m/s^2) of some levels, replacing the defaults"
    )
    pga_h10: tuple[float, ...] | None = attrs.field(default=None, converter=_reals, validator=_check_pga)
    scale: str | None = text_field(optional=True, hint="a registered intensity scale name", doc="intensity scale")

    def __attrs_post_init__(self):
        if self.pga_h10 is not None and (self.levels is not None or self.values):
            raise SpecError("IntensitySpec: give 'levels' (and 'values') or 'pga_h10', not both")
        self.table()  # the level values must make a valid IntensityLevels

    def table(self) -> IntensityLevels:
        """The PGA_H10 of each level, defaults with ``values`` applied."""
        try:
            return IntensityLevels.with_overrides(self.values)
        except ParameterError as exc:
            raise SpecError(f"field 'values': {exc}") from None

    @property
    def default_levels(self) -> bool:
        """True when the intensities are levels D_x (named so in the matrices)."""
        return self.pga_h10 is None

    def resolve(self) -> tuple[Intensity, ...]:
        """The intensities in order."""
        if self.pga_h10 is not None:
            return tuple(Intensity(f"PGA_H10={v:g}", v) for v in self.pga_h10)
        table = self.table()
        return tuple(Intensity(name, table[name], name) for name in (self.levels or LEVEL_NAMES))


def _pairs(value: Any) -> Any:
    if isinstance(value, list):
        return tuple(_reals(v) if isinstance(v, list) else v for v in value)
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
            f"DampingSpec: field 'ratios' must be two [frequency Hz, damping ratio] pairs, e.g. [[1.5, 0.021], "
            f"[3.36, 0.027]]; got {value!r}"
        )


@attrs.frozen
class DampingSpec:
    """``[damping]``: Rayleigh damping ``C = alpha M + beta K`` of the linear structure.

    Through two ``ratios`` ``[[f1, zeta1], [f2, zeta2]]`` (Hz, -), default the paper's measured
    2.1 % at 1.50 Hz and 2.7 % at 3.36 Hz, or directly ``alpha`` (1/s) and ``beta`` (s).
    """

    ratios: tuple[tuple[float, float], ...] | None = attrs.field(
        default=None, converter=_pairs, validator=_check_ratios
    )
    alpha: float | None = parameter(optional=True, low=0.0, unit="1/s", doc="mass-proportional coefficient")
    beta: float | None = parameter(optional=True, low=0.0, unit="s", doc="stiffness-proportional coefficient")

    def __attrs_post_init__(self):
        direct = (self.alpha is not None, self.beta is not None)
        if any(direct) and self.ratios is not None:
            raise SpecError("DampingSpec: give 'ratios' or 'alpha' and 'beta', not both")
        if any(direct) and not all(direct):
            raise SpecError("DampingSpec: give both 'alpha' and 'beta' (0 for none)")
        self.rayleigh()  # ratios that give a negative coefficient fail here, with the loader's path

    def rayleigh(self):
        """The :class:`bearingfw.analysis.Rayleigh` object."""
        from bearingfw.analysis import Rayleigh

        if self.alpha is not None:
            return Rayleigh(self.alpha, self.beta)
        (f1, z1), (f2, z2) = self.ratios or DAMPING_RATIOS
        try:
            return Rayleigh.from_ratios(f1, z1, f2, z2)
        except ParameterError as exc:
            raise SpecError(f"field 'ratios': {exc}") from None


@attrs.frozen
class OutputSpec:
    """``[output]``: what the run writes besides the matrices of every metric.

    ``table``: the metrics printed and shown in the report (all are in ``matrices.json`` and the
    CSVs); ``aggregate``: how several records combine (:data:`AGGREGATES`); ``histories``: keep
    each cell's time histories (NPZ; figures need them); ``every``: keep every k-th integration
    step in them; ``report``: write ``report.md``.
    """

    table: tuple[str, ...] = names_field(default=(), doc="metrics to print (default: a selection)")
    aggregate: str = choice(AGGREGATES, default="ec8", doc="combination of several records")
    histories: bool = flag_field(True, "keep each cell's histories (NPZ)")
    every: int = integer_parameter(low=1, high=10_000, default=1, doc="keep every k-th integration step")
    report: bool = flag_field(True, "write report.md")


@attrs.frozen
class FigureSpec:
    """``[figures]``: which figures the run draws (PNG and SVG in ``figures/``).

    For every record and every intensity in ``intensities`` (default all): the stress histories
    of all models at ``elements`` (the paper's figures 18 and 20; default S1 and 3B on the
    reference bridge, else the first two response elements), the force in ``bearing`` (default 3B,
    else the first governed bearing) for the models ``compare`` (default M1 and M2; figures 19a,
    21a), its friction ratio for the models with a friction coefficient, with the mu line
    (figures 19b, 21b), and with ``hysteresis`` the force-displacement loops of every bearing of
    every model. Also a heatmap per metric of the table, and the records' intensity chart.
    """

    draw: bool = flag_field(True, "draw figures at all")
    intensities: tuple[str, ...] | None = names_field(default=None, optional=True, doc="intensities to draw")
    elements: tuple[str, ...] | None = names_field(default=None, optional=True, doc="elements of the stress figure")
    bearing: str | None = text_field(optional=True, doc="bearing of the force and friction figures")
    compare: tuple[str, ...] | None = names_field(default=None, optional=True, doc="models in the force figure")
    hysteresis: bool = flag_field(True, "draw every bearing's force-displacement loops")


def _check_module_names(instance, attribute, value):
    if not isinstance(value, tuple) or not all(isinstance(v, str) and re.match(r"^[A-Za-z_][\w.]*$", v) for v in value):
        raise SpecError(f"Experiment: field 'plugins' must be a list of module names, got {value!r}")


@attrs.frozen
class Experiment:
    """A whole experiment: models x records x intensities on one structure (module docstring).

    ``base_dir`` is the folder relative paths start from (the TOML file's); ``source`` the TOML
    text the experiment was read from (copied into the results store).
    """

    name: str = text_field(pattern=_NAME, hint="a name of letters, digits and . _ + - (it names the output folder)")
    description: str = text_field(default="")
    reference: str | None = text_field(optional=True, doc="the model the ratios divide by (default M2 or the first)")
    plugins: tuple[str, ...] = attrs.field(default=(), converter=_listish, validator=_check_module_names)
    python_path: tuple[str, ...] = names_field(default=(), doc="folders (relative to the file) put on sys.path")
    structure: StructureSpec = attrs.field(factory=StructureSpec)
    models: tuple[ModelSpec, ...] = ()
    records: tuple[RecordSpec, ...] = ()
    intensities: IntensitySpec = attrs.field(factory=IntensitySpec)
    integration: TransientSettings = attrs.field(factory=TransientSettings)
    damping: DampingSpec = attrs.field(factory=DampingSpec)
    output: OutputSpec = attrs.field(factory=OutputSpec)
    figures: FigureSpec = attrs.field(factory=FigureSpec)
    base_dir: Path = attrs.field(factory=Path.cwd, converter=Path)
    source: str = ""

    def __attrs_post_init__(self):
        if not self.models:
            raise SpecError("models: the experiment needs at least one [models.<name>] table")
        if not self.records:
            raise SpecError("records: the experiment needs at least one [records.<name>] table")
        names = [m.name for m in self.models]
        if self.reference is not None and self.reference not in names:
            raise SpecError(f"reference: {self.reference!r} is not a model; models: {', '.join(names)}")
        intensities = [i.name for i in self.intensity_list]
        for field, given, known in (("figures.intensities", self.figures.intensities, intensities),
                                    ("figures.compare", self.figures.compare, names)):
            bad = [g for g in (given or ()) if g not in known]
            if bad:
                raise SpecError(f"{field}: {bad[0]!r} is not among {', '.join(known)}")

    @property
    def model_names(self) -> tuple[str, ...]:
        return tuple(m.name for m in self.models)

    @property
    def record_names(self) -> tuple[str, ...]:
        return tuple(r.name for r in self.records)

    @property
    def intensity_list(self) -> tuple[Intensity, ...]:
        return self.intensities.resolve()

    @property
    def reference_model(self) -> str:
        """The model the ratio matrices divide by: ``reference``, else M2 if present, else the first."""
        if self.reference is not None:
            return self.reference
        return "M2" if "M2" in self.model_names else self.model_names[0]

    def model(self, name: str) -> ModelSpec:
        return next(m for m in self.models if m.name == name)

    def record(self, name: str) -> RecordSpec:
        return next(r for r in self.records if r.name == name)

    def resolve_path(self, path: str) -> Path:
        """A path of the file (a record file, a python_path folder), relative to :attr:`base_dir`."""
        p = Path(path).expanduser()
        return p if p.is_absolute() else self.base_dir / p


# ---- loading ----------------------------------------------------------------------------------------
#: The top-level keys and the class (or kind) of each table.
_TABLES = {
    "structure": StructureSpec,
    "intensities": IntensitySpec,
    "integration": TransientSettings,
    "damping": DampingSpec,
    "output": OutputSpec,
    "figures": FigureSpec,
}
_NAMED = {"models": ModelSpec, "records": RecordSpec}
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
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SpecError(f"{path}: cannot read the experiment file: {exc.strerror or exc}") from None
    return parse_experiment(text, path.resolve().parent, str(path))


def _experiment(data: dict, base_dir: Path, text: str) -> Experiment:
    _unknown("", data, (*_SCALARS, *_TABLES, *_NAMED))
    kwargs: dict[str, Any] = {key: from_table(cls, data[key], key) for key, cls in _TABLES.items() if key in data}
    for key, cls in _NAMED.items():
        tables = data.get(key, {})
        if not isinstance(tables, Mapping):
            raise SpecError(f"{key}: must be tables [{key}.<name>], got {type(tables).__name__} {tables!r}")
        kwargs[key] = tuple(from_table(cls, table, key_path(key, name), name=name) for name, table in tables.items())
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
