"""Three-component acceleration records, the traces readers return, units and resampling.

A :class:`Record` holds the two orthogonal horizontal components ``h1``, ``h2`` and the vertical
``v`` on one time grid ``t_k = k dt`` (``k = 0 .. n-1``), always in m/s^2. Readers return
:class:`Trace` objects in the file's own units and time step; :func:`assemble` converts the units,
resamples every trace to the finest time step among them and pads shorter traces with trailing
zeros, and the record keeps the original lengths so that it can say which components were padded.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from fractions import Fraction
from pathlib import Path
from typing import Any, ClassVar

import attrs
import numpy as np

from bearingfw.parameters import ParameterError, parameter

__all__ = [
    "AXIS_ROLES",
    "DEFAULT_NAMES",
    "G",
    "MAX_REFINEMENT",
    "MAX_SAMPLES",
    "ROLES",
    "UNIT_FACTORS",
    "Record",
    "Trace",
    "assemble",
    "normalize_units",
    "resample",
]

#: Standard gravity (m/s^2): PEER and most strong-motion files give accelerations in g.
G = 9.80665

#: Canonical acceleration units and their factor to m/s^2.
UNIT_FACTORS = {"g": G, "m/s^2": 1.0, "cm/s^2": 0.01}

_UNIT_ALIASES = {
    "g": "g",
    "m/s^2": "m/s^2", "m/s2": "m/s^2", "m/s/s": "m/s^2", "m/s**2": "m/s^2", "m/sec/sec": "m/s^2",
    "m/sec^2": "m/s^2", "m/sec2": "m/s^2", "ms-2": "m/s^2", "m s-2": "m/s^2", "mps2": "m/s^2",
    "cm/s^2": "cm/s^2", "cm/s2": "cm/s^2", "cm/s/s": "cm/s^2", "cm/s**2": "cm/s^2", "cm/sec/sec": "cm/s^2",
    "cm/sec^2": "cm/s^2", "cm/sec2": "cm/s^2", "cms-2": "cm/s^2", "cm s-2": "cm/s^2", "gal": "cm/s^2",
}

#: The component roles of a record, in the order files and columns are assigned to them.
ROLES = ("h1", "h2", "v")

#: Component labels when the files give none, one per role.
DEFAULT_NAMES = ("H1", "H2", "V")

#: The global axes and the role that holds each in a directional record (see :class:`Record`).
AXIS_ROLES = {"x": "h1", "y": "h2", "z": "v"}

# Punctuation around a unit in free text: "G.", "(G)", "[cm/s^2]", "g;".
_UNIT_PUNCTUATION = " \t.,;:()[]{}'\""


def normalize_units(text: Any) -> str:
    """The canonical name (``g``, ``m/s^2`` or ``cm/s^2``) of an acceleration unit spelling.

    Surrounding punctuation is ignored, so ``G.``, ``(G)`` and ``[cm/s^2]`` are understood.
    """
    key = str(text).strip().strip(_UNIT_PUNCTUATION).lower().replace("²", "^2")
    if key in _UNIT_ALIASES:
        return _UNIT_ALIASES[key]
    raise ParameterError(f"unknown acceleration unit {text!r}; allowed: g, m/s^2, cm/s^2 (or gal)")


def _float_vector(value: Any) -> Any:
    try:
        array = np.array(value, dtype=float)  # a private copy: the caller's array stays theirs
    except (TypeError, ValueError):
        return value
    array.setflags(write=False)
    return array


def _check_vector(instance, attribute, value):
    owner = type(instance).__name__
    if not isinstance(value, np.ndarray) or value.ndim != 1 or value.size < 2:
        raise ParameterError(f"{owner}: {attribute.name!r} must be a 1-D array of at least 2 numbers, got {value!r}")
    bad = np.flatnonzero(~np.isfinite(value))
    if bad.size:
        raise ParameterError(f"{owner}: {attribute.name!r} has a non-finite value {value[bad[0]]} at index {bad[0]}")


@attrs.frozen(eq=False)
class Trace:
    """One acceleration component as a reader found it: values in ``units``, sampled every ``dt`` s.

    ``metadata`` is free-form; two keys have a meaning for :func:`assemble`: ``source_units``,
    the units of the original recording when the values were converted before (an archive
    bearingfw wrote holds m/s^2 but remembers that the files were in g), and ``record``, a
    mapping of record-level metadata that such an archive stored (seed, scale factor, ...).
    """

    values: np.ndarray = attrs.field(converter=_float_vector, validator=_check_vector)
    dt: float = parameter(low=0.0, low_open=True, unit="s", doc="time step")
    units: str = attrs.field(converter=normalize_units)
    label: str = ""
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    def in_si(self) -> np.ndarray:
        """The values in m/s^2."""
        return self.values * UNIT_FACTORS[self.units]


def _check_names(instance, attribute, value):
    if not (isinstance(value, tuple) and len(value) == 3 and all(isinstance(n, str) and n for n in value)):
        raise ParameterError(f"Record: 'names' must be three non-empty labels (h1, h2, v), got {value!r}")


def _check_lengths(instance, attribute, value):
    if value is None:
        return
    n = instance.h1.size
    if not (isinstance(value, tuple) and len(value) == 3 and all(isinstance(k, int) and 1 <= k <= n for k in value)):
        raise ParameterError(f"Record: 'lengths' must be three sample counts between 1 and n = {n}, got {value!r}")


def _check_source_units(instance, attribute, value):
    if not (isinstance(value, tuple) and len(value) == 3):
        raise ParameterError(f"Record: 'source_units' must be three units (h1, h2, v), got {value!r}")


@attrs.frozen(eq=False)
class Record:
    """A three-component ground acceleration record in m/s^2.

    ``h1`` and ``h2`` are orthogonal horizontal components, ``v`` the vertical (up); all have the
    same length ``n``. ``lengths`` are the components' sample counts before zero padding (None:
    nothing was padded). ``source`` says where the record came from; ``synthetic`` is True for
    generated motion, which every printout and plot then labels as synthetic.

    ``metadata`` keys bearingfw sets: ``scale_factor`` (product of all scalings),
    ``resampled_from`` (each component's time step before resampling),
    ``peaks_before_resampling`` (each component's peak in m/s^2 before resampling, times any
    later scale factor: band-limited resampling changes peaks), ``notes`` (sentences a printout
    should show; :attr:`notes` adds one per resampled component), ``seed`` (synthetic motion),
    ``level``/``degree``/``scale`` (after :func:`~bearingfw.motion.scale_to_level`),
    ``target`` (the :class:`~bearingfw.motion.ScaleTarget` label after
    :func:`~bearingfw.motion.scale_record`), ``files``/``readers`` (records read from files),
    ``directions`` and ``missing`` (records of :func:`~bearingfw.motion.load_directional`).

    Directions: a record read by :func:`~bearingfw.motion.load_directional` is *directional*: its
    roles are the global axes, ``h1`` = x, ``h2`` = y, ``v`` = z (:data:`AXIS_ROLES`);
    ``metadata['directions']`` maps each given axis to its component (``"file.AT2"``,
    ``"-file.csv#2"``) and ``metadata['missing']`` lists the axes given no component, whose
    values are zero (the notes say so). Every 3-role caller works on it unchanged.
    """

    units: ClassVar[str] = "m/s^2"

    h1: np.ndarray = attrs.field(converter=_float_vector, validator=_check_vector)
    h2: np.ndarray = attrs.field(converter=_float_vector, validator=_check_vector)
    v: np.ndarray = attrs.field(converter=_float_vector, validator=_check_vector)
    dt: float = parameter(low=0.0, low_open=True, unit="s", doc="time step")
    names: tuple[str, str, str] = attrs.field(default=DEFAULT_NAMES, converter=tuple, validator=_check_names)
    source: str = ""
    synthetic: bool = attrs.field(default=False, converter=bool)
    lengths: tuple[int, int, int] | None = attrs.field(
        default=None, converter=attrs.converters.optional(lambda v: tuple(int(k) for k in v)), validator=_check_lengths
    )
    source_units: tuple[str, str, str] = attrs.field(
        default=("m/s^2",) * 3, converter=lambda v: tuple(normalize_units(u) for u in v), validator=_check_source_units
    )
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    def __attrs_post_init__(self):
        sizes = (self.h1.size, self.h2.size, self.v.size)
        if len(set(sizes)) != 1:
            raise ParameterError(
                f"Record: components must have equal lengths (got h1={sizes[0]}, h2={sizes[1]}, v={sizes[2]}); "
                "use bearingfw.motion.assemble to pad them"
            )

    # -- shape and time ------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return int(self.h1.size)

    @property
    def duration(self) -> float:
        """``(n - 1) dt``, s."""
        return (self.n - 1) * self.dt

    @property
    def time(self) -> np.ndarray:
        return np.arange(self.n) * self.dt

    @property
    def components(self) -> np.ndarray:
        """``(3, n)``: h1, h2, v."""
        return np.vstack([self.h1, self.h2, self.v])

    @property
    def horizontal(self) -> np.ndarray:
        """``(2, n)``: h1, h2."""
        return np.vstack([self.h1, self.h2])

    def component(self, role: str) -> np.ndarray:
        if role not in ROLES:
            raise ParameterError(f"Record: component must be one of {', '.join(ROLES)}, got {role!r}")
        return getattr(self, role)

    # -- padding and resampling ----------------------------------------------------------------
    @property
    def original_lengths(self) -> tuple[int, int, int]:
        return self.lengths if self.lengths is not None else (self.n,) * 3

    @property
    def padded(self) -> bool:
        """True if any component was shorter than the record and was padded with zeros."""
        return any(k < self.n for k in self.original_lengths)

    @property
    def padded_components(self) -> tuple[str, ...]:
        """The names of the components padded with trailing zeros."""
        return tuple(name for name, k in zip(self.names, self.original_lengths) if k < self.n)

    @property
    def was_resampled(self) -> tuple[bool, bool, bool]:
        """For each component (h1, h2, v): was it resampled from another time step (its peak changed)?"""
        steps = self.metadata.get("resampled_from") or (self.dt,) * 3
        return tuple(not math.isclose(step, self.dt, rel_tol=1e-12) for step in steps)

    @property
    def resampled_components(self) -> tuple[str, ...]:
        """The names of the resampled components."""
        return tuple(name for name, flag in zip(self.names, self.was_resampled) if flag)

    @property
    def peak_ratios(self) -> tuple[float | None, float | None, float | None]:
        """For each component (h1, h2, v): its peak after resampling over its peak before (None if
        it was not resampled or is zero). A ratio well below 1 means the new step lost the peak
        (a 0.5 s step cuts a 5.28 m/s^2 peak to 0.40): :attr:`min_peak_ratio` lets a caller refuse it."""
        before = self.metadata.get("peaks_before_resampling") or [_peak(c) for c in self.components]
        return tuple(
            _peak(values) / p0 if flag and p0 > 0 else None
            for flag, values, p0 in zip(self.was_resampled, self.components, before)
        )

    @property
    def min_peak_ratio(self) -> float:
        """The smallest of :attr:`peak_ratios` (1.0 if no component was resampled)."""
        return min((r for r in self.peak_ratios if r is not None), default=1.0)

    @property
    def directional(self) -> bool:
        """True for a record of :func:`~bearingfw.motion.load_directional` (roles are x, y, z)."""
        return "directions" in self.metadata

    @property
    def missing_directions(self) -> tuple[str, ...]:
        """The axes of a directional record that no component drives (their values are zero)."""
        return tuple(self.metadata.get("missing", ()))

    @property
    def notes(self) -> tuple[str, ...]:
        """What a printout of this record should say besides its numbers: ``metadata['notes']`` and,
        for each resampled component, its peak after and before resampling and their ratio."""
        notes = list(self.metadata.get("notes", ()))
        steps = self.metadata.get("resampled_from") or (self.dt,) * 3
        before = self.metadata.get("peaks_before_resampling") or [_peak(c) for c in self.components]
        for name, flag, step, values, p0 in zip(self.names, self.was_resampled, steps, self.components, before):
            if flag:
                ratio = f" (ratio {_peak(values) / p0:.3g})" if p0 > 0 else ""
                notes.append(
                    f"{name} resampled from dt = {step:g} s to {self.dt:g} s (band-limited interpolation): its peak "
                    f"is {_peak(values):.4g} m/s^2 after resampling, {p0:.4g} m/s^2 before{ratio}"
                )
        return tuple(notes)

    # -- labels --------------------------------------------------------------------------------
    @property
    def title(self) -> str:
        """A one-line label for printouts and plots; synthetic motion always says so."""
        text = self.source or "record"
        if self.synthetic and "synthetic" not in text.lower():
            text = f"SYNTHETIC {text}"
        factor = self.metadata.get("scale_factor")
        if factor is not None and factor != 1.0:
            text += f", scaled x{factor:.4g}"
        return text

    # -- derived records -----------------------------------------------------------------------
    def scaled(self, factor: float, **metadata: Any) -> Record:
        """All three components times ``factor`` (> 0); ``metadata['scale_factor']`` accumulates."""
        factor = float(factor)
        if not math.isfinite(factor) or factor <= 0:
            raise ParameterError(f"Record.scaled: factor must be finite and > 0, got {factor!r}")
        meta = dict(self.metadata)
        meta["scale_factor"] = meta.get("scale_factor", 1.0) * factor
        if "peaks_before_resampling" in meta:
            meta["peaks_before_resampling"] = [p * factor for p in meta["peaks_before_resampling"]]
        meta.update(metadata)
        return attrs.evolve(self, h1=self.h1 * factor, h2=self.h2 * factor, v=self.v * factor, metadata=meta)

    def resampled(self, dt: float) -> Record:
        """The record on the grid ``k dt`` (band-limited polyphase resampling, see :func:`resample`).

        Each component is resampled at its own (unpadded) length and padded afterwards, so that
        the filter's ringing at the end of a short component does not spill into its padding.
        The time steps and peaks before the first resampling stay in the metadata.
        """
        if math.isclose(dt, self.dt, rel_tol=1e-12):
            return self
        series = [resample(c[:k], self.dt, dt) for c, k in zip(self.components, self.original_lengths)]
        (h1, h2, v), lengths = _pad_to_longest(series)
        meta = dict(self.metadata)
        meta.setdefault("peaks_before_resampling", [_peak(c) for c in self.components])
        meta.setdefault("resampled_from", [self.dt] * 3)
        return attrs.evolve(self, h1=h1, h2=h2, v=v, dt=dt, lengths=lengths, metadata=meta)

    def to_npz(self, path: str | Path) -> Path:
        """Write the record as an ``.npz`` archive that the ``npz`` reader reads back unchanged.

        Besides the components (padded, as in the record) the archive keeps ``dt``, ``units``,
        ``names``, ``source``, ``synthetic``, ``lengths`` (the unpadded sample counts),
        ``source_units``, ``scale_factor`` and the rest of the JSON-able metadata as the string
        ``metadata``.
        """
        path = Path(path)
        meta = {k: v for k, v in self.metadata.items() if k != "scale_factor"}
        np.savez(
            path,
            h1=self.h1, h2=self.h2, v=self.v, dt=np.float64(self.dt), units=np.str_(self.units),
            names=np.array(self.names), source=np.str_(self.source), synthetic=np.bool_(self.synthetic),
            lengths=np.array(self.original_lengths, dtype=np.int64), source_units=np.array(self.source_units),
            scale_factor=np.float64(self.metadata.get("scale_factor", 1.0)),
            metadata=np.str_(json.dumps(meta, default=_json_value)),
        )
        return path if path.suffix == ".npz" else path.with_name(path.name + ".npz")


def _json_value(value: Any) -> Any:
    # numpy scalars and arrays in metadata become plain numbers and lists; anything else its text.
    if isinstance(value, (np.generic, np.ndarray)):
        return value.tolist()
    return str(value)


def _peak(values: np.ndarray) -> float:
    return float(np.max(np.abs(values)))


def _pad_to_longest(series: Sequence[np.ndarray]) -> tuple[list[np.ndarray], tuple[int, ...] | None]:
    """Pad every series with trailing zeros to the longest; also the unpadded lengths (None if all equal)."""
    lengths = tuple(s.size for s in series)
    n = max(lengths)
    padded = [np.concatenate([s, np.zeros(n - s.size)]) for s in series]
    return padded, (lengths if min(lengths) < n else None)


def _checked_step(value: Any, what: str) -> float:
    try:
        step = float(value)
    except (TypeError, ValueError):
        step = math.nan
    if not math.isfinite(step) or step <= 0:
        raise ParameterError(f"resample: {what} = {value!r} s is outside the allowed range {what} > 0 (finite)")
    return step


#: Most samples a record or a resampled component may have (100 million: 11.6 days at 100 Hz).
MAX_SAMPLES = 100_000_000
#: Largest refinement of a time step by resampling: a component sampled 1000 times more coarsely
#: than another holds nothing at the finer one's frequencies, and the filter would grow with it.
MAX_REFINEMENT = 1000


def resample(values: np.ndarray, dt_from: float, dt_to: float) -> np.ndarray:
    """Resample a signal from step ``dt_from`` to ``dt_to`` (band-limited, zero phase).

    ``dt_from / dt_to`` is written as a fraction ``up / down`` (denominator <= 1000) and the
    signal goes through a polyphase filter (``scipy.signal.resample_poly``): interpolation by
    ``up``, a linear-phase Kaiser-window low-pass at the lower Nyquist frequency (the
    anti-aliasing filter when coarsening), decimation by ``down``. The output has
    ``ceil(n up / down)`` samples: one at every ``k dt_to`` before ``n dt_from``, i.e. up to the
    input's last sample plus one input step (so ``(n_out - 1) dt_to`` may differ from
    ``(n - 1) dt_from`` by less than one step). Band-limited interpolation does not keep the
    peaks: the reconstructed signal between samples can exceed the sampled peak.
    """
    dt_from, dt_to = _checked_step(dt_from, "dt_from"), _checked_step(dt_to, "dt_to")
    ratio = Fraction(dt_from / dt_to).limit_denominator(1000)
    if ratio <= 0 or not math.isclose(float(ratio), dt_from / dt_to, rel_tol=1e-9):
        raise ParameterError(
            f"cannot resample from dt = {dt_from:g} s to dt = {dt_to:g} s: the ratio is not a fraction with a "
            "denominator up to 1000; choose a time step that divides the record's"
        )
    if ratio == 1:
        return np.array(values, dtype=float)
    if ratio.numerator > MAX_REFINEMENT:
        raise ParameterError(
            f"cannot resample from dt = {dt_from:g} s to dt = {dt_to:g} s: a time step is refined at most "
            f"{MAX_REFINEMENT} times (here {dt_from / dt_to:.4g}); are the time steps of the components right?"
        )
    values = np.asarray(values, dtype=float)
    size = math.ceil(values.size * ratio.numerator / ratio.denominator)
    if size > MAX_SAMPLES:
        raise ParameterError(
            f"resampling {values.size} samples from dt = {dt_from:g} s to dt = {dt_to:g} s gives {size} samples, "
            f"outside the allowed range samples <= {MAX_SAMPLES}"
        )
    from scipy import signal  # here, not at the top: its import costs a second of CPU in every process

    return signal.resample_poly(values, ratio.numerator, ratio.denominator)


def assemble(
    traces: Sequence[Trace],
    *,
    source: str = "",
    synthetic: bool = False,
    names: Sequence[str] | None = None,
    metadata: Mapping[str, Any] | None = None,
    dt: float | None = None,
) -> Record:
    """One :class:`Record` from three traces given as horizontal 1, horizontal 2, vertical.

    Units are converted to m/s^2. Every trace is resampled to ``dt`` (default: the finest time
    step among the traces, so that no trace loses content) and shorter traces are padded with
    trailing zeros to the longest; the record's ``lengths`` keep the unpadded counts. When a trace
    is resampled, the metadata keep every trace's time step and peak as read (``resampled_from``,
    ``peaks_before_resampling``), because band-limited resampling changes peaks; the record's
    :attr:`~Record.notes` then say so.
    """
    traces = list(traces)
    if len(traces) != 3:
        raise ParameterError(
            f"a record needs 3 components (horizontal 1, horizontal 2, vertical), got {len(traces)}"
        )
    for trace in traces:
        if not isinstance(trace, Trace):
            raise TypeError(f"expected bearingfw.motion.Trace objects, got {trace!r}")
    target = min(t.dt for t in traces) if dt is None else _checked_step(dt, "dt")
    series = []
    for k, t in enumerate(traces):
        try:
            series.append(resample(t.in_si(), t.dt, target))
        except ParameterError as exc:  # say which component: the time steps come from its file
            raise ParameterError(f"component {k + 1} ({t.label or DEFAULT_NAMES[k]}): {exc}") from None
    padded, lengths = _pad_to_longest(series)
    if names is None:
        names = tuple(t.label or default for t, default in zip(traces, DEFAULT_NAMES))
    meta = dict(metadata or {})
    if any(not math.isclose(t.dt, target, rel_tol=1e-12) for t in traces):
        meta.update(resampled_from=[t.dt for t in traces], peaks_before_resampling=[_peak(t.in_si()) for t in traces])
    return Record(
        h1=padded[0], h2=padded[1], v=padded[2], dt=target, names=tuple(names), source=source,
        synthetic=synthetic, lengths=lengths,
        source_units=tuple(t.metadata.get("source_units") or t.units for t in traces), metadata=meta,
    )
