"""The ground motion of a cell: read or generate the record, scale it, map it onto the model's axes.

Order: the record is read (files) or generated (synthetic tremor); resampled to the integration
step if that step does not divide the record's (the transient solver needs whole sub-steps;
band-limited resampling, and the record's notes say so); scaled to the intensity (a level:
:func:`bearingfw.motion.scale_to_level`, which also checks the degree; a PGA_H10 value:
:func:`bearingfw.motion.scale_to_pga_h10`); and its components are put on global x, y, z as
``[records.<name>] components`` says. The same acceleration acts at every support.
"""

from __future__ import annotations

import hashlib

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
    Record,
    TremorParameters,
    find_reader,
    get_scale,
    read_record,
    record_degree,
    record_pga_h10,
    record_t_ha,
    scale_to_level,
    scale_to_pga_h10,
    synthetic_tremor,
)
from bearingfw.motion.metrics import arias_intensity, dominant_frequency, peak
from bearingfw.plugins import Registry

__all__ = ["ground_acceleration", "load_record", "record_info", "record_inputs", "record_readers", "scaled_record"]


def load_record(experiment: Experiment, spec: RecordSpec, registry: Registry | None = None) -> Record:
    """The record as read or generated, before any scaling."""
    if spec.synthetic:
        parameters = from_table(TremorParameters, spec.tremor, key_path("records", spec.name, "tremor"))
        return synthetic_tremor(spec.seed, parameters)
    paths = [experiment.resolve_path(f) for f in spec.files]
    return read_record(paths, format=spec.format, dt=spec.dt, units=spec.units, registry=registry)


def _divides(step: float, dt: float) -> bool:
    ratio = dt / step
    return round(ratio) >= 1 and abs(round(ratio) - ratio) <= 1e-9 * ratio


def scaled_record(
    record: Record, intensity: Intensity, intensities: IntensitySpec, dt_integration: float | None = None,
    registry: Registry | None = None,
) -> Record:
    """``record`` on a grid the integration step divides, scaled to ``intensity``."""
    if dt_integration is not None and not _divides(dt_integration, record.dt):
        record = record.resampled(dt_integration)
    if intensity.level is None:
        return scale_to_pga_h10(record, intensity.pga_h10)
    scale = get_scale(intensities.scale, registry) if intensities.scale else None
    return scale_to_level(record, intensity.level, levels=intensities.table(), scale=scale)


def ground_acceleration(record: Record, components: tuple[str, str, str]) -> np.ndarray:
    """(steps, 3) support acceleration in global x, y, z from the record's components (m/s^2)."""
    columns = []
    for role in components:
        if role == "0":
            columns.append(np.zeros(record.n))
        else:
            sign = -1.0 if role.startswith("-") else 1.0
            columns.append(sign * record.component(role.lstrip("-")))
    return np.column_stack(columns)


def record_inputs(experiment: Experiment, spec: RecordSpec) -> dict:
    """What identifies the record in a cell's input hash: the files' contents (not their paths), or the
    seed and tremor parameters."""
    data = attrs.asdict(spec, filter=lambda a, v: a.name not in ("name", "files"))
    if spec.files is not None:
        digests = []
        for f in spec.files:
            path = experiment.resolve_path(f)
            try:
                digests.append(hashlib.sha256(path.read_bytes()).hexdigest())
            except OSError as exc:
                raise SpecError(f"{key_path('records', spec.name, 'files')}: cannot read {path}: {exc.strerror or exc}") from None
        data["file_sha256"] = digests
    return data


def record_readers(experiment: Experiment, spec: RecordSpec, registry: Registry | None = None) -> tuple[str, ...]:
    """The names of the readers that read the record's files (none for the synthetic tremor)."""
    if spec.files is None:
        return ()
    return tuple(find_reader(experiment.resolve_path(f), spec.format, registry).name for f in spec.files)


def record_info(record: Record, components: tuple[str, str, str], scale=None) -> dict:
    """A record's measures for the report: PGA_H10, t_Ha, Arias intensity, degree, peaks, dominant
    frequencies, and which component goes where."""
    scale = scale or get_scale()
    return {
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
            for name, role, values in zip(record.names, ("h1", "h2", "v"), record.components)
        ],
        "axes": dict(zip(("x", "y", "z"), components)),
        "notes": list(record.notes),
    }
