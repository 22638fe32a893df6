"""The ground motion of a cell: read or generate the record, scale it, map it onto the model's axes.

Order: the record is read (files), mapped (``x``/``y``/``z``: :func:`bearingfw.motion.load_directional`)
or generated (synthetic tremor); resampled to the integration step if that step does not divide
the record's (the transient solver needs whole sub-steps; band-limited resampling, and the
record's notes say so; a resampling that loses more than half of a component's peak is refused,
see :data:`MIN_PEAK_RATIO`); scaled to the cell's target (:class:`bearingfw.motion.ScaleTarget`:
an intensity level's PGA_H10, whose degree is checked, a PGA_H10, PGA or Sa(T) value, or the
record as recorded: :func:`bearingfw.motion.scale_record`); and its components are put on
global x, y, z (a directional record is already on them; a ``files`` record as ``[records.<name>]
components`` says). The same acceleration acts at every support, unless the entry has a
``spatial`` table (:class:`SpatialSpec`, below).

Spatially varying records (``[records.<name>.spatial]``). The supported nodes are put in groups:
``groups = "auto"`` (default) by their position along ``axis`` (nodes within ``tolerance`` m of
the previous one form a group, named support1, support2, ... in increasing position:
:func:`bearingfw.analysis.excitation.support_groups`), or ``groups = { west = ["N1", "N2"], ... }``
by node names (every supported node in exactly one group). Each group then moves in one of two ways:

- per-group records: ``[records.<name>.spatial.motions.<group>]`` holds a record of its own (the
  keys of a record entry: ``files``, ``x``/``y``/``z``, ``components``, ...); groups without one
  move with the entry's own record, which is the reference group's. Every group's record is
  resampled like the entry's and multiplied by the entry's scale factor (the intensity scales the
  ground motion field as a whole, so the supports keep their recorded ratios); shorter records
  are padded with zeros at the end;
- generated (:mod:`bearingfw.motion.spatial`): ``apparent_velocity`` (m/s) and ``azimuth`` (deg,
  from x towards y) for wave passage, ``coherency`` (``"harichandran-vanmarcke"``, ``"luco-wong"``)
  with its ``params`` for loss of coherency, ``seed``. The scaled record is what the first
  support reached receives; the others' motions are generated from it for the cell (seeded, so a
  rerun gives the same motions), from the groups' plan positions (the mean of their nodes').

The reference group (``reference``; default: the first group moving with the entry's record, for a
generator the first group reached) carries the record itself; the others' differences from it are
integrated to displacements with ``baseline`` correction (:class:`~bearingfw.analysis.excitation.SupportMotion`).
A cell of such a record is run with :class:`SpatialGround` in place of the (steps, 3) array: its
support motion is made for the cell's system when the run starts, and as an array it is the
reference group's acceleration (what the cell keeps as ``ground.acceleration``). Without
``spatial`` nothing changes: the entry's cells keep their digests.
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.analysis.excitation import SupportMotion, support_groups
from bearingfw.experiment.spec import (
    Experiment,
    Intensity,
    IntensitySpec,
    RecordSpec,
    SpecError,
    from_table,
    key_path,
)
from bearingfw.motion import (
    AXES,
    ROLES,
    Record,
    ScaleTarget,
    TremorParameters,
    find_reader,
    get_scale,
    load_directional,
    parse_component,
    read_record,
    record_degree,
    record_pga_h10,
    record_t_ha,
    scale_record,
    synthetic_tremor,
)
from bearingfw.motion.metrics import arias_intensity, dominant_frequency, has_horizontal_motion, peak
from bearingfw.motion.spatial import COHERENCY_MODELS, SpatialVariation, delays, spatial_motions
from bearingfw.parameters import ParameterError, choice, integer_parameter, parameter
from bearingfw.plugins import Registry

__all__ = [
    "MIN_PEAK_RATIO",
    "SpatialGround",
    "SpatialSpec",
    "ground_acceleration",
    "check_length",
    "ground_motion",
    "load_record",
    "record_info",
    "record_inputs",
    "record_mapping",
    "record_readers",
    "scale_target",
    "scaled_record",
    "spatial_spec",
    "target_inputs",
]

#: Smallest peak ratio (after / before) that resampling to the integration step may leave a
#: component: a coarser step that keeps less than half of a peak does not carry the record
#: (a 0.5 s step cuts a 5.28 m/s^2 peak to 0.40 m/s^2).
MIN_PEAK_RATIO = 0.5


def record_mapping(spec: RecordSpec) -> dict[str, str] | None:
    """The ``{axis: "[-]FILE[#k]"}`` of a ``[records.<name>]`` with ``x``/``y``/``z`` keys, else None."""
    mapping = {axis: getattr(spec, axis, None) for axis in AXES}
    return {axis: text for axis, text in mapping.items() if text is not None} or None


def load_record(experiment: Experiment, spec: RecordSpec, registry: Registry | None = None) -> Record:
    """The record as read, mapped or generated, before any resampling and scaling. For an entry with
    ``spatial``, the table is checked and its per-group records read (errors name the key), and the
    record's notes say how the motion varies between supports.

    Refused (:class:`SpecError` naming ``records.<name>``), so that no cell runs to fail: a record
    with fewer than 2 samples at ``[integration] dt_integration``, and a record with no horizontal
    motion (only ``z``) in a study with an intensity other than ``as-recorded`` (every scaling
    measure is of the horizontals)."""
    record = _loaded(experiment, spec, registry)
    where = key_path("records", spec.name)
    dt_integration = experiment.integration.dt_integration
    try:
        check_length(record, dt_integration)
    except ParameterError as exc:
        raise SpecError(f"{where}: {exc}") from None
    _check_scalable(experiment, record, where)
    return record


def check_length(record: Record, dt_integration: float | None) -> None:
    """Refuse a record that gives fewer than 2 samples when resampled to ``dt_integration`` (s): it
    lasts less than one integration step (ParameterError naming ``integration.dt_integration``)."""
    if dt_integration is None or _divides(dt_integration, record.dt):
        return  # no resampling: the record keeps its own samples (at least 2)
    # Resampling gives ceil(n dt / dt_integration) samples (bearingfw.motion.record.resample).
    samples = math.ceil(round(record.n * record.dt / dt_integration, 9))
    if samples < 2:
        raise ParameterError(
            f"the record lasts {record.duration:.4g} s ({record.n} samples at dt = {record.dt:g} s), which gives "
            f"{samples} sample(s) at integration.dt_integration = {dt_integration:g} s, fewer than the 2 a time "
            f"history needs; use a dt_integration below {record.n * record.dt:g} s (one that divides the record's "
            f"dt = {record.dt:g} s keeps every sample) or a longer record"
        )


def _check_scalable(experiment: Experiment, record: Record, where: str) -> None:
    """A record without horizontal motion can only be used as recorded (module docstring of
    :mod:`bearingfw.motion.scaling`: PGA_H10, PGA and Sa all measure the horizontals)."""
    if has_horizontal_motion(record):
        return
    scaled = [i for i in experiment.intensity_list if i.target.kind != "as-recorded"]
    if not scaled:
        return
    names = ", ".join(i.name for i in scaled)
    raise SpecError(
        f"{where}: the record has no horizontal motion (x and y are zero everywhere{_only_vertical(record)}), so its "
        f"PGA_H10, PGA, Sa and t_Ha are zero or undefined and it cannot be scaled to the intensities {names}: a "
        "level (D_0 .. D_IV) and pga_h10, pga and sa targets all measure the horizontal motion. Use "
        '[intensities] levels = ["as-recorded"] for a vertical-only record, or give it a horizontal component '
        "(x or y)"
    )


def _only_vertical(record: Record) -> str:
    return ": only z is given" if record.directional and record.missing_directions == ("x", "y") else ""


def _loaded(experiment: Experiment, spec: RecordSpec, registry: Registry | None) -> Record:
    record = _read_record(experiment, spec, registry)
    sp = spatial_spec(spec)
    if sp is None:
        return record
    for group in sp.motions:
        _group_record(experiment, spec, group, registry)
    notes = [*record.metadata.get("notes", ()), sp.describe()]
    return attrs.evolve(record, metadata={**record.metadata, "notes": notes})


def _read_record(experiment: Experiment, spec: RecordSpec, registry: Registry | None) -> Record:
    if spec.synthetic:
        parameters = from_table(TremorParameters, spec.tremor, key_path("records", spec.name, "tremor"))
        return synthetic_tremor(spec.seed, parameters)
    mapping = record_mapping(spec)
    if mapping is not None:
        return load_directional(
            mapping, base_dir=experiment.base_dir, format=spec.format, dt=spec.dt, units=spec.units,
            vertical_as_horizontal=bool(getattr(spec, "vertical_as_horizontal", False)), registry=registry,
        )
    paths = [experiment.resolve_path(f) for f in spec.files]
    return read_record(paths, format=spec.format, dt=spec.dt, units=spec.units, registry=registry)


def _divides(step: float, dt: float) -> bool:
    ratio = dt / step
    return round(ratio) >= 1 and abs(round(ratio) - ratio) <= 1e-9 * ratio


def scale_target(intensity: Any, intensities: IntensitySpec | None = None) -> ScaleTarget:
    """The :class:`~bearingfw.motion.ScaleTarget` of a cell's intensity: a ScaleTarget itself, an
    object with a ``target`` attribute holding one, or an :class:`Intensity` (a level: its PGA_H10
    with the degree check; else a plain PGA_H10, named as the intensity)."""
    if isinstance(intensity, ScaleTarget):
        return intensity
    target = getattr(intensity, "target", None)
    if isinstance(target, ScaleTarget):
        return target
    if isinstance(intensity, Intensity):
        if intensity.level is not None:
            return ScaleTarget(kind="pga_h10", value=intensity.pga_h10, label=intensity.name, level=intensity.level)
        return ScaleTarget(kind="pga_h10", value=intensity.pga_h10, label=intensity.name)
    raise TypeError(f"expected a ScaleTarget or an Intensity, got {intensity!r}")


def scaled_record(
    record: Record,
    intensity: Any,
    intensities: IntensitySpec | None = None,
    dt_integration: float | None = None,
    registry: Registry | None = None,
    *,
    period: float | None = None,
    min_peak_ratio: float | None = MIN_PEAK_RATIO,
) -> Record:
    """``record`` on a grid the integration step divides, scaled to ``intensity``.

    ``intensity``: a :class:`~bearingfw.motion.ScaleTarget` or anything :func:`scale_target`
    takes. ``period``: the structure's first-mode period (s), for an Sa target whose period is
    "T1". A level is checked on ``intensities.scale`` (default: the default scale). A resampling
    that leaves a component less than ``min_peak_ratio`` of its peak is refused (None: never).
    """
    if dt_integration is not None and not _divides(dt_integration, record.dt):
        check_length(record, dt_integration)
        before = record.dt
        record = record.resampled(dt_integration)
        if min_peak_ratio is not None and record.min_peak_ratio < min_peak_ratio:
            lost = ", ".join(
                f"{name} to {ratio:.3g} of its peak" for name, ratio in zip(record.names, record.peak_ratios)
                if ratio is not None and ratio < min_peak_ratio
            )
            raise ParameterError(
                f"{record.title}: resampling from dt = {before:g} s to the integration step dt_integration = "
                f"{dt_integration:g} s cuts {lost} (allowed: at least {min_peak_ratio:g}); choose an integration "
                f"step that divides {before:g} s"
            )
    target = scale_target(intensity, intensities)
    if target.needs_period and period is not None:
        target = target.with_period(period)
    scale = None
    if target.level is not None and intensities is not None and intensities.scale:
        scale = get_scale(intensities.scale, registry)
    return scale_record(record, target, scale)


def ground_acceleration(record: Record, components: tuple[str, str, str] | None = None) -> np.ndarray:
    """(steps, 3) support acceleration in global x, y, z from the record's components (m/s^2).

    A directional record (:func:`~bearingfw.motion.load_directional`) is on x, y, z already:
    ``components`` must then be None or ``("h1", "h2", "v")``. Otherwise ``components`` names
    the role for each axis (``"-h2"`` flips it, ``"0"`` leaves the axis at rest); None means
    h1 -> x, h2 -> y, v -> z.
    """
    if components is None or tuple(components) == ROLES:
        return np.column_stack([record.h1, record.h2, record.v])
    if record.directional:
        raise ParameterError(
            f"{record.title}: the record maps its components to x, y, z itself ({record.metadata['directions']}); "
            f"'components' = {list(components)} cannot remap it"
        )
    columns = []
    for role in components:
        if role == "0":
            columns.append(np.zeros(record.n))
        else:
            sign = -1.0 if role.startswith("-") else 1.0
            columns.append(sign * record.component(role.lstrip("-")))
    return np.column_stack(columns)


# ---- spatially varying records -------------------------------------------------------------------------
#: The generator's keys of ``[records.<name>.spatial]`` (the rest of SpatialVariation's fields go in ``params``).
GENERATOR_KEYS = ("apparent_velocity", "azimuth", "coherency", "seed")
_GROUP_NAME = re.compile(r"^[A-Za-z0-9_.+-]+$")


def _groups_value(value):
    if isinstance(value, Mapping):
        return {k: ((v,) if isinstance(v, str) else tuple(v) if isinstance(v, (list, tuple)) else v)
                for k, v in value.items()}
    return value


def _check_groups(instance, attribute, value):
    if value == "auto":
        return
    hint = ('"auto" (by position along \'axis\') or a table {group = ["node", ...]} naming every supported node '
            "once")
    if not isinstance(value, dict) or not value:
        raise SpecError(f"SpatialSpec: field 'groups' must be {hint}, got {value!r}")
    seen: dict[str, str] = {}
    for name, nodes in value.items():
        if not _GROUP_NAME.match(name):
            raise SpecError(f"SpatialSpec: field 'groups' has a group name {name!r}; use letters, digits and . _ + -")
        if not isinstance(nodes, tuple) or not nodes or not all(isinstance(n, str) and n for n in nodes):
            raise SpecError(f"SpatialSpec: field 'groups' entry {name!r} must be a non-empty list of node names, "
                            f"got {nodes!r}")
        for n in nodes:
            if n in seen:
                raise SpecError(f"SpatialSpec: field 'groups' puts node {n!r} in both {seen[n]!r} and {name!r}")
            seen[n] = name


def _check_reference(instance, attribute, value):
    if value is not None and not (isinstance(value, str) and _GROUP_NAME.match(value)):
        raise SpecError(f"SpatialSpec: field 'reference' must be a group name, got {value!r}")


@attrs.frozen
class SpatialSpec:
    """``[records.<name>.spatial]``, checked (module docstring).

    ``groups``: ``"auto"`` or ``{group: (node, ...)}``; ``axis`` and ``tolerance`` (m): the automatic
    grouping; ``reference``: the group carrying the entry's record; ``baseline`` and
    ``baseline_degree``: the correction of the integrated differential displacements;
    ``variation``: the generator (wave passage, coherency), None without one; ``motions``:
    ``{group: RecordSpec}`` per-group records (exclusive with a generator).
    """

    groups: Any = attrs.field(default="auto", converter=_groups_value, validator=_check_groups,
                              metadata={"doc": 'support groups: "auto" (by position) or {group = [nodes]}'})
    axis: str = choice(("x", "y"), default="x", doc="axis along which 'auto' groups the supports")
    tolerance: float = parameter(low=0.0, high=1e4, default=1.0, unit="m",
                                 doc="'auto': supports within this distance of the previous one share a group")
    reference: str | None = attrs.field(default=None, validator=_check_reference,
                                        metadata={"doc": "the group that carries the entry's record"})
    baseline: str = choice(("polynomial", "none"), default="polynomial",
                           doc="baseline correction of the integrated differential displacements")
    baseline_degree: int = integer_parameter(low=2, high=8, default=3, doc="highest power of the baseline polynomial")
    variation: SpatialVariation | None = attrs.field(default=None)
    motions: dict = attrs.field(factory=dict)

    def __attrs_post_init__(self):
        if self.motions and self.variation is not None:
            raise SpecError("SpatialSpec: give per-group records ('motions') or a generator ('apparent_velocity', "
                            "'coherency'), not both")
        if isinstance(self.groups, dict):
            names = list(self.groups)
            for where, group in [("reference", self.reference), *(("motions", g) for g in self.motions)]:
                if group is not None and group not in names:
                    raise SpecError(f"SpatialSpec: field {where!r} names group {group!r}; the groups are {names}")
        if self.reference is not None and self.reference in self.motions:
            raise SpecError(f"SpatialSpec: field 'reference' = {self.reference!r} has a record of its own in "
                            "'motions'; the reference group carries the entry's record")

    def describe(self) -> str:
        """One sentence for the report."""
        if isinstance(self.groups, dict):
            grouping = "support groups " + ", ".join(f"{g} ({', '.join(n)})" for g, n in self.groups.items())
        else:
            grouping = f"support groups by position along {self.axis} (within {self.tolerance:g} m: support1, support2, ...)"
        if self.motions:
            how = ("per-group records for " + ", ".join(self.motions)
                   + "; the other groups move with this record (scaled alike)")
        elif self.variation is None:
            how = "every group moves with this record (uniform motion, through the per-support formulation)"
        else:
            v = self.variation
            parts = []
            if v.apparent_velocity is not None:
                parts.append(f"wave passage at an apparent velocity of {v.apparent_velocity:g} m/s towards azimuth "
                             f"{v.azimuth:g} deg")
            if v.coherency != "none":
                parts.append(f"loss of coherency ({v.coherency}, seed {v.seed})")
            how = " and ".join(parts) or "no variation generated (uniform motion)"
            how += "; generated per cell from this record, which the first support reached receives"
        return f"spatially varying: {grouping}; {how}"


def spatial_spec(spec: RecordSpec) -> SpatialSpec | None:
    """The checked ``[records.<name>.spatial]`` of ``spec`` (None without one); errors name the key."""
    if not spec.spatial:
        return None
    path = key_path("records", spec.name, "spatial")
    table = dict(spec.spatial)
    generator = {k: table.pop(k) for k in GENERATOR_KEYS if k in table}
    params = table.pop("params", None)
    motions = table.pop("motions", None)
    allowed = [f.name for f in attrs.fields(SpatialSpec) if f.name not in ("variation", "motions")]
    allowed += [*GENERATOR_KEYS, "params", "motions"]
    for key in table:
        if key not in allowed:
            raise SpecError(f"{path}.{key}: unknown key; allowed in [{path}]: {', '.join(allowed)}")
    variation = None
    if generator or params is not None:
        from_table(SpatialVariation, generator, path)  # each generator key checked at its own path
        model = [f.name for f in attrs.fields(SpatialVariation) if f.name not in GENERATOR_KEYS]
        if params is not None and not isinstance(params, Mapping):
            raise SpecError(f"{path}.params: must be a table of the coherency model's parameters "
                            f"({', '.join(model)}), got {params!r}")
        variation = from_table(SpatialVariation, dict(params or {}), f"{path}.params", **generator)
    records = {}
    if motions is not None:
        if not isinstance(motions, Mapping) or not motions:
            raise SpecError(f"{path}.motions: must be a table {{group = {{files = [...]}} or {{x = ..., y = ...}}}}, "
                            f"got {motions!r}")
        for group, entry in motions.items():
            where = f"{path}.motions.{key_path(group)}"
            if not _GROUP_NAME.match(group):
                raise SpecError(f"{where}: a group name has letters, digits and . _ + - only")
            if not isinstance(entry, Mapping):
                raise SpecError(f"{where}: must be a table with the group's record (files = [...], or x/y/z)")
            if "spatial" in entry or "name" in entry:
                bad = "spatial" if "spatial" in entry else "name"
                raise SpecError(f"{where}.{bad}: not allowed in a group's record")
            records[group] = from_table(RecordSpec, dict(entry), where, name=spec.name)
    return from_table(SpatialSpec, table, path, variation=variation, motions=records)


def _group_record(experiment: Experiment, spec: RecordSpec, group: str, registry: Registry | None) -> Record:
    sub = spatial_spec(spec).motions[group]
    where = key_path("records", spec.name, "spatial", "motions", group)
    try:
        return _loaded(experiment, sub, registry)
    except SpecError:
        raise
    except (ValueError, KeyError, OSError, RuntimeError) as exc:
        raise SpecError(f"{where}: {exc}") from None


def _padded_rows(a: np.ndarray, n: int) -> np.ndarray:
    return a if a.shape[0] == n else np.vstack([a, np.zeros((n - a.shape[0], a.shape[1]))])


@attrs.frozen(eq=False)
class SpatialGround:
    """A cell's spatially varying ground motion, made into a :class:`SupportMotion` for the cell's
    system when the run starts (``support_motion``, what :func:`~bearingfw.analysis.solve_transient`
    calls); as an array, the reference group's acceleration (the entry's record, scaled).

    ``acceleration``: (steps, 3) the entry's record in global x, y, z (m/s^2), every ``dt`` s;
    ``motions``: ``{group: (steps_g, 3)}`` per-group records, scaled and resampled alike.
    """

    acceleration: np.ndarray
    dt: float
    spatial: SpatialSpec
    motions: dict = attrs.field(factory=dict)
    record: str = ""

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self.acceleration, dtype=dtype)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.acceleration.shape

    def groups(self, model) -> dict[str, tuple[str, ...]]:
        """The support groups on ``model`` (a Model or System)."""
        sp = self.spatial
        if sp.groups == "auto":
            return support_groups(model, axis=sp.axis, tolerance=sp.tolerance)
        return dict(sp.groups)

    def positions(self, model, groups: Mapping[str, tuple[str, ...]]) -> dict[str, np.ndarray]:
        """Each group's plan position: the mean of its nodes' (x, y), m."""
        model = getattr(model, "model", model)
        coords = model.coordinates
        return {g: np.mean([coords[model.node_index(n), :2] for n in nodes], axis=0) for g, nodes in groups.items()}

    def support_motion(self, system, dt: float) -> SupportMotion:
        where = key_path("records", self.record, "spatial") if self.record else "spatial"
        if not math.isclose(dt, self.dt, rel_tol=1e-9):
            raise ParameterError(f"{where}: the support motion is sampled every {self.dt:g} s, the run asks {dt:g} s")
        sp = self.spatial
        groups = self.groups(system)
        names = list(groups)
        unknown = [g for g in [*self.motions, *([sp.reference] if sp.reference else [])] if g not in groups]
        if unknown:
            raise ParameterError(f"{where}: names group(s) {unknown} that the structure does not have; its support "
                                 f"groups are {names} ({'by position along ' + sp.axis if sp.groups == 'auto' else 'as given'})")
        reference = sp.reference
        if self.motions:
            free = [g for g in names if g not in self.motions]
            if not free:
                raise ParameterError(f"{where}.motions: every group {names} has a record of its own; leave the "
                                     "reference group to the entry's record")
            n = max(a.shape[0] for a in [self.acceleration, *self.motions.values()])
            acceleration = {g: _padded_rows(self.motions.get(g, self.acceleration), n) for g in names}
            reference = reference or free[0]
        elif sp.variation is None:
            acceleration = dict.fromkeys(names, self.acceleration)
        else:
            positions = self.positions(system, groups)
            acceleration = spatial_motions(self.acceleration, dt, positions, sp.variation)
            if reference is None:
                tau = delays(positions, sp.variation)
                reference = min(names, key=lambda g: (tau[g], names.index(g)))
        return SupportMotion(groups, acceleration, reference=reference, baseline=sp.baseline,
                             baseline_degree=sp.baseline_degree)


def ground_motion(experiment: Experiment, spec: RecordSpec, record: Record, registry: Registry | None = None):
    """The cell's ground motion from its scaled ``record``: the (steps, 3) array of :func:`ground_acceleration`,
    or, for an entry with ``spatial``, a :class:`SpatialGround` (the per-group records read, resampled
    to ``record.dt`` and scaled by ``record``'s scale factor)."""
    ag = ground_acceleration(record, spec.components)
    sp = spatial_spec(spec)
    if sp is None:
        return ag
    factor = float(record.metadata.get("scale_factor", 1.0))
    motions = {}
    for group, sub in sp.motions.items():
        raw = _group_record(experiment, spec, group, registry)
        if not math.isclose(raw.dt, record.dt, rel_tol=1e-9):
            raw = raw.resampled(record.dt)
        motions[group] = ground_acceleration(raw, sub.components) * factor
    return SpatialGround(ag, record.dt, sp, motions, spec.name)


def _sha256(path: Path, key: str) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError as exc:
        raise SpecError(f"{key}: cannot read {path}: {exc.strerror or exc}") from None


def record_inputs(experiment: Experiment, spec: RecordSpec) -> dict:
    """What identifies the record in a cell's input hash: the files' contents (not their paths), or the
    seed and tremor parameters; for ``x``/``y``/``z`` records each axis's file content, component
    number and sign (``mapping``) and ``vertical_as_horizontal``.

    A ``files`` or ``seed`` record gives the same data as before the mapping existed (its new
    fields are at their defaults and left out), so its cells keep their digests.
    """
    mapping = record_mapping(spec)
    data = attrs.asdict(
        spec,
        filter=lambda a, v: a.name not in ("name", "files", "spatial", *AXES)
        and not (a.name == "vertical_as_horizontal" and mapping is None and not v),
    )
    sp = spatial_spec(spec)
    if sp is not None:  # only then: an entry without it keeps the digest it always had
        spatial = attrs.asdict(sp, recurse=False, filter=lambda a, v: a.name not in ("variation", "motions"))
        spatial["groups"] = sp.groups if sp.groups == "auto" else {g: list(n) for g, n in sp.groups.items()}
        spatial["variation"] = None if sp.variation is None else sp.variation.to_dict()
        spatial["motions"] = {g: record_inputs(experiment, sub) for g, sub in sp.motions.items()}
        data["spatial"] = spatial
    if spec.files is not None:
        data["file_sha256"] = [_sha256(experiment.resolve_path(f), key_path("records", spec.name, "files")) for f in spec.files]
    if mapping is not None:
        entries = {}
        for axis, text in mapping.items():
            try:
                ref = parse_component(axis, text, experiment.base_dir)
            except ParameterError as exc:
                raise SpecError(f"{key_path('records', spec.name, axis)}: {exc}") from None
            entries[axis] = {
                "file_sha256": _sha256(ref.path, key_path("records", spec.name, axis)),
                "component": ref.index,
                "flip": ref.flip,
            }
        data["mapping"] = entries
    return data


def target_inputs(target: ScaleTarget) -> dict:
    """What identifies a cell's scale target in its input hash (kind, value, period, label, level)."""
    return target.to_dict()


def _record_files(experiment: Experiment, spec: RecordSpec) -> list[Path]:
    mapping = record_mapping(spec)
    if mapping is not None:
        files = list(dict.fromkeys(parse_component(a, t, experiment.base_dir).path for a, t in mapping.items()))
    else:
        files = [experiment.resolve_path(f) for f in spec.files or ()]
    return files


def record_readers(experiment: Experiment, spec: RecordSpec, registry: Registry | None = None) -> tuple[str, ...]:
    """The names of the readers that read the record's files (none for the synthetic tremor), per-group
    records' included."""
    names = [find_reader(path, spec.format, registry).name for path in _record_files(experiment, spec)]
    sp = spatial_spec(spec)
    for sub in sp.motions.values() if sp is not None else ():
        names += [n for n in record_readers(experiment, sub, registry) if n not in names]
    return tuple(names)


def record_info(record: Record, components: tuple[str, str, str] | None = None, scale=None) -> dict:
    """A record's measures for the report: PGA_H10, t_Ha, Arias intensity, degree,
    peaks, dominant frequencies, which component goes where and, after scaling, the target.
    For a record with no horizontal motion t_Ha is NaN and the degree None (undefined)."""
    scale = scale or get_scale()
    if record.directional or components is None:
        axes = {axis: role for axis, role in zip(AXES, ROLES)}
    else:
        axes = dict(zip(AXES, components))
    info = {
        "source": record.title,
        "synthetic": record.synthetic,
        "dt": record.dt,
        "samples": record.n,
        "duration": record.duration,
        "pga_h10": record_pga_h10(record),
        "t_ha": record_t_ha(record),
        "arias": arias_intensity(record.horizontal, record.dt),
        "degree": record_degree(record, scale),
        "scale": scale.name,
        "scale_factor": record.metadata.get("scale_factor", 1.0),
        "components": [
            {"name": name, "role": role, "pga": peak(values),
             "dominant_frequency": dominant_frequency(values, record.dt) if np.any(values) else None}
            for name, role, values in zip(record.names, ROLES, record.components)
        ],
        "axes": axes,
        "notes": list(record.notes),
    }
    if record.directional:
        info["directions"] = dict(record.metadata["directions"])
        info["missing"] = list(record.missing_directions)
    if "target" in record.metadata:
        info["target"] = record.metadata["target"]
    return info
