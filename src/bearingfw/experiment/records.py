"""The ground motion of a cell: read or generate the record, scale it, map it onto the model's axes.

Order: the record is read (files), mapped (``x``/``y``/``z``: :func:`bearingfw.motion.load_directional`)
or generated (synthetic tremor); resampled to the integration step if that step does not divide
the record's (the transient solver needs whole sub-steps; band-limited resampling, and the
record's notes say so; a resampling that loses more than half of a component's peak is refused,
see :data:`MIN_PEAK_RATIO`); scaled to the cell's target (:class:`bearingfw.motion.ScaleTarget`:
an intensity level's PGA_H10, whose degree is checked, a PGA_H10, PGA or Sa(T) value, or the
record as recorded: :func:`bearingfw.motion.scale_record`); and its components are put on
global x, y, z (a directional record is already on them; a ``files`` record as ``[records.<name>]
components`` says). The same acceleration acts at every support.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import attrs
import numpy as np

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
from bearingfw.motion.metrics import arias_intensity, dominant_frequency, peak
from bearingfw.parameters import ParameterError
from bearingfw.plugins import Registry

__all__ = [
    "MIN_PEAK_RATIO",
    "ground_acceleration",
    "load_record",
    "record_info",
    "record_inputs",
    "record_mapping",
    "record_readers",
    "scale_target",
    "scaled_record",
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
    """The record as read, mapped or generated, before any resampling and scaling."""
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
        filter=lambda a, v: a.name not in ("name", "files", *AXES)
        and not (a.name == "vertical_as_horizontal" and mapping is None and not v),
    )
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
        return list(dict.fromkeys(parse_component(a, t, experiment.base_dir).path for a, t in mapping.items()))
    return [experiment.resolve_path(f) for f in spec.files or ()]


def record_readers(experiment: Experiment, spec: RecordSpec, registry: Registry | None = None) -> tuple[str, ...]:
    """The names of the readers that read the record's files (none for the synthetic tremor)."""
    return tuple(find_reader(path, spec.format, registry).name for path in _record_files(experiment, spec))


def record_info(record: Record, components: tuple[str, str, str] | None = None, scale=None) -> dict:
    """A record's measures for the report: PGA_H10, t_Ha, Arias intensity, degree,
    peaks, dominant frequencies, which component goes where and, after scaling, the target."""
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
