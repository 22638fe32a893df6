"""Multichannel acceleration files in, identified modes out.

Channels. A measurement is a set of simultaneously sampled acceleration channels, one column (CSV)
or one array (NPZ) per channel. A channel named ``"<node>.<component>"`` (``"GA32.uz"``: node
``GA32``, component ``uz``; the form :meth:`bearingfw.model.DofMap.describe` writes) is a sensor
at that DOF of a model; :func:`channel_dofs` maps names to DOF indices. Other names are allowed
for identification, which does not need a model; pairing with a model's modes does.

Files are read by the record readers of :mod:`bearingfw.motion` (the same CSV and NPZ rules as
``bearingfw record``: a header row of names, a time column or ``# dt:``, units in brackets or a
``# units:`` comment; an NPZ with one 1-D array per channel, ``dt``, ``units`` and ``names``), so
one parser serves both. An NPZ archive without ``names`` names its channels by their array keys.
Units are optional here: frequencies, damping ratios and normalised shapes do not depend on
them, so a file that states none is taken as m/s^2 (and says so in :attr:`Channels.metadata`).

Identified modes are written as JSON (:func:`write_modes`): per mode its frequency, damping ratio
and real shape ``{channel: value}`` normalised to a largest component of +1. ``bearingfw tune
--measured`` reads that file (:func:`read_modes`).
"""

from __future__ import annotations

import difflib
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.model import COMPONENTS, ModelError
from bearingfw.motion import RecordFormatError, read_file
from bearingfw.parameters import ParameterError, parameter

__all__ = [
    "MODES_FORMAT",
    "Channels",
    "IdentifiedMode",
    "IdentifiedModes",
    "channel_dofs",
    "parse_channel",
    "read_channels",
    "read_modes",
    "write_modes",
]

#: The ``format`` key of a modes file, and its version.
MODES_FORMAT = "bearingfw-oma-modes"
MODES_VERSION = 1
#: The largest frequency (Hz) a modes file may give: far above any structure's modes that an
#: accelerometer samples, and a bound that keeps every later computation finite.
MAX_FREQUENCY = 1e5
#: The largest size of a shape value in a modes file: a shape's scale is free (MAC ignores it), but
#: the products MAC forms, ``(a . b)^2``, must stay finite.
MAX_SHAPE = 1e30


def parse_channel(name: str) -> tuple[str, str]:
    """``"GA32.uz"`` -> ``("GA32", "uz")``; the node name may itself contain dots (``"P2A.0.uy"``)."""
    node, dot, component = str(name).rpartition(".")
    if not dot or not node or component.lower() not in COMPONENTS:
        raise ParameterError(
            f"channel {name!r} does not name a DOF: expected '<node>.<component>' with a component among "
            f"{', '.join(COMPONENTS)} (e.g. 'GA32.uz')"
        )
    return node, component.lower()


def channel_dofs(system_or_model, channels: Sequence[str]) -> np.ndarray:
    """Full DOF indices of the sensor ``channels`` in a :class:`~bearingfw.model.System` or ``Model``.

    A channel at a node the model lacks is an error naming it, the model and its nearest channel
    names (a typo such as ``G44.uz`` for ``G4.uz`` is the usual cause)."""
    dofmap = getattr(system_or_model, "dofmap", None) or system_or_model.model.dofmap
    out = []
    for name in channels:
        node, component = parse_channel(name)
        try:
            out.append(dofmap.dof(node, component))
        except ModelError:
            model = getattr(system_or_model, "model", system_or_model)
            near = _near_channels(model, name)
            raise ParameterError(f"channel {name!r}: the model has no node {node!r}{near}") from None
    return np.array(out, dtype=int)


def _near_channels(model, name: str) -> str:
    """`` (in 'model'; near matches: ...)``: the model's channel names nearest ``name``."""
    nodes = sorted(n.name for n in getattr(model, "nodes", ()))
    if not nodes:
        return ""
    node, _, component = name.rpartition(".")
    near = difflib.get_close_matches(name, [f"{n}.{c}" for n in nodes for c in COMPONENTS], n=5, cutoff=0.5)
    if not near:  # a node name far from any: the nearest nodes, with the channel's component
        near = [f"{n}.{component.lower()}" for n in difflib.get_close_matches(node, nodes, n=5)]
    more = ", ..." if len(nodes) > 12 else ""
    listing = f"near matches: {', '.join(near)}" if near else f"its nodes: {', '.join(nodes[:12])}{more}"
    title = getattr(model, "name", "")
    return f" ({f'in {title!r}; ' if title else ''}{listing})"


def _data(value) -> np.ndarray:
    array = np.array(value, dtype=float)
    array.setflags(write=False)
    return array


def _names(value) -> tuple[str, ...]:
    return (value,) if isinstance(value, str) else tuple(str(v) for v in value)


@attrs.frozen(eq=False)
class Channels:
    """Simultaneous acceleration channels: ``data`` (samples, channels) in ``units``, every ``dt`` s."""

    data: np.ndarray = attrs.field(converter=_data)
    dt: float = parameter(low=0.0, low_open=True, unit="s", doc="sampling interval")
    names: tuple[str, ...] = attrs.field(converter=_names)
    units: str = "m/s^2"
    source: str = ""
    synthetic: bool = attrs.field(default=False, converter=bool)
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    def __attrs_post_init__(self):
        if self.data.ndim != 2 or self.data.shape[0] < 2 or self.data.shape[1] < 1:
            raise ParameterError(f"Channels: field 'data' must be (samples >= 2, channels >= 1), got {self.data.shape}")
        if len(self.names) != self.data.shape[1]:
            raise ParameterError(f"Channels: {len(self.names)} names for {self.data.shape[1]} channels")
        if len(set(self.names)) != len(self.names) or not all(self.names):
            raise ParameterError(f"Channels: field 'names' must be distinct and non-empty, got {list(self.names)}")
        if not np.all(np.isfinite(self.data)):
            raise ParameterError("Channels: field 'data' must be finite")

    @property
    def n_samples(self) -> int:
        return int(self.data.shape[0])

    @property
    def n_channels(self) -> int:
        return int(self.data.shape[1])

    @property
    def duration(self) -> float:
        return (self.n_samples - 1) * self.dt

    @property
    def time(self) -> np.ndarray:
        return np.arange(self.n_samples) * self.dt

    def select(self, names: Sequence[str]) -> Channels:
        """The channels ``names``, in that order (an unknown name is an error naming the known ones)."""
        names = _names(names)
        unknown = [n for n in names if n not in self.names]
        if unknown:
            raise ParameterError(
                f"Channels: no channel {', '.join(map(repr, unknown))}; channels: {', '.join(self.names)}"
            )
        index = [self.names.index(n) for n in names]
        return attrs.evolve(self, data=self.data[:, index], names=names)

    def to_npz(self, path) -> Path:
        """Write as an NPZ archive that :func:`read_channels` (and ``bearingfw record``'s reader) reads."""
        path = Path(path)
        arrays = {name: self.data[:, j] for j, name in enumerate(self.names)}
        np.savez(
            path,
            dt=self.dt,
            units=self.units,
            names=np.array(self.names),
            source=self.source,
            synthetic=self.synthetic,
            **arrays,
        )
        return path

    def to_csv(self, path) -> Path:
        """Write as CSV: a ``time`` column, one column per channel, the units and the source in comments.

        CSV has no field for the synthetic flag: read back, only an NPZ archive keeps it.
        """
        path = Path(path)
        header = "time," + ",".join(self.names)
        table = np.column_stack([self.time, self.data])
        comments = f"# units: {self.units}\n" + (f"# {self.source}\n" if self.source else "")
        np.savetxt(path, table, delimiter=",", header=header, comments="", fmt="%.10g")
        path.write_text(comments + path.read_text())
        return path


def _read_traces(path: Path, fmt, dt, units):
    """The traces of ``path`` and whether the file stated its units: through
    :func:`bearingfw.motion.read_file`, whose checks name the file (a directory, a value beyond 100 g)."""
    try:
        return read_file(path, format=fmt, dt=dt, units=units)[1], True
    except RecordFormatError as first:
        if units is not None:
            raise
        # Only the units differ between the two calls: if this one reads, they were what was missing;
        # if it fails too, its reason is the file's other fault (a value beyond 100 g ...).
        try:
            return read_file(path, format=fmt, dt=dt, units="m/s^2")[1], False
        except RecordFormatError as second:
            raise second from first


#: Arrays of an NPZ archive that describe the record rather than hold a channel (those the record
#: reader of :mod:`bearingfw.motion` sets aside).
_NPZ_DESCRIPTIVE = {
    "dt", "units", "names", "source", "synthetic", "lengths", "source_units", "scale_factor", "metadata", "time", "t",
}


def _npz_channel_keys(path: Path) -> list[str]:
    """The names of the channel arrays of an NPZ archive without a ``names`` array: its keys, in stored order."""
    with np.load(path, allow_pickle=False) as archive:
        return [k for k in archive.files if k not in _NPZ_DESCRIPTIVE and archive[k].dtype.kind not in "US"]


def read_channels(path, *, dt: float | None = None, units: str | None = None, fmt: str | None = None) -> Channels:
    """Read a multichannel CSV or NPZ file (module docstring) into :class:`Channels` in m/s^2.

    ``dt`` and ``units`` are used only where the file does not state them; ``fmt`` names a record
    reader (default: by suffix and content, as ``bearingfw record`` chooses). Every channel must
    have a name, the same length and the same time step.
    """
    path = Path(path)
    traces, stated = _read_traces(path, fmt, dt, units)
    names = [t.label for t in traces]
    if not all(names) and all(t.metadata.get("format") == "npz" for t in traces):
        keys = _npz_channel_keys(path)
        if len(keys) == len(names):
            names = [n or k for n, k in zip(names, keys, strict=True)]
    unnamed = [j + 1 for j, n in enumerate(names) if not n]
    if unnamed:
        raise RecordFormatError(
            path, None, f"channel(s) {unnamed} have no name; give a header row of names (CSV) or a 'names' array (NPZ)"
        )
    lengths = {t.values.size for t in traces}
    steps = {t.dt for t in traces}
    if len(lengths) != 1 or max(steps) - min(steps) > 1e-9 * max(steps):
        raise RecordFormatError(path, None, "the channels differ in length or time step; they must be sampled together")
    meta: dict[str, Any] = {"file": str(path), "units_stated": stated}
    if not stated:
        meta["note"] = "the file states no units; taken as m/s^2 (frequencies, damping and shapes do not depend on it)"
    synthetic = any(bool(t.metadata.get("synthetic", False)) for t in traces)
    source = next((t.metadata["source"] for t in traces if t.metadata.get("source")), str(path))
    return Channels(np.column_stack([t.in_si() for t in traces]), traces[0].dt, names, "m/s^2", source, synthetic, meta)


# -- identified modes ------------------------------------------------------------------------------


def _shape(value) -> np.ndarray:
    array = np.array(value, dtype=float).reshape(-1)
    array.setflags(write=False)
    return array


@attrs.frozen(eq=False)
class IdentifiedMode:
    """One identified mode: frequency (Hz), damping ratio, real ``shape`` at the channels (largest +1).

    ``frequency_std`` and ``damping_std`` are the spread over the poles that make it up (``poles``
    of them, one per model order); ``mpc`` the modal phase collinearity of its complex shape (1 for
    a real, classically damped mode).
    """

    frequency: float = parameter(low=0.0, low_open=True, unit="Hz", doc="natural frequency")
    damping: float = parameter(low=-1.0, high=1.0, doc="damping ratio")
    shape: np.ndarray = attrs.field(converter=_shape)
    frequency_std: float = 0.0
    damping_std: float = 0.0
    poles: int = 1
    mpc: float = 1.0
    name: str = ""


@attrs.frozen(eq=False)
class IdentifiedModes:
    """Modes identified at ``channels`` (shapes in that order), and how (``metadata``)."""

    channels: tuple[str, ...] = attrs.field(converter=_names)
    modes: tuple[IdentifiedMode, ...] = attrs.field(converter=tuple)
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    def __attrs_post_init__(self):
        bad = [m.name or k + 1 for k, m in enumerate(self.modes) if m.shape.size != len(self.channels)]
        if bad:
            raise ParameterError(
                f"IdentifiedModes: mode(s) {bad} have a shape of another size than the {len(self.channels)} channels"
            )
        named = [m if m.name else attrs.evolve(m, name=f"mode {k + 1}") for k, m in enumerate(self.modes)]
        object.__setattr__(self, "modes", tuple(named))

    @property
    def frequencies(self) -> np.ndarray:
        return np.array([m.frequency for m in self.modes])

    @property
    def damping(self) -> np.ndarray:
        return np.array([m.damping for m in self.modes])

    @property
    def shapes(self) -> np.ndarray:
        """(channels, modes)."""
        return np.column_stack([m.shape for m in self.modes]) if self.modes else np.zeros((len(self.channels), 0))

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": MODES_FORMAT,
            "version": MODES_VERSION,
            **{k: v for k, v in self.metadata.items() if k not in ("format", "version", "channels", "modes")},
            "channels": list(self.channels),
            "modes": [
                {
                    "name": m.name,
                    "frequency": m.frequency,
                    "damping": m.damping,
                    "frequency_std": m.frequency_std,
                    "damping_std": m.damping_std,
                    "poles": m.poles,
                    "mpc": m.mpc,
                    "shape": {c: float(v) for c, v in zip(self.channels, m.shape, strict=True)},
                }
                for m in self.modes
            ],
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], where: str = "modes") -> IdentifiedModes:
        """Back from :meth:`to_dict` (errors name ``where`` and the offending entry)."""
        if not isinstance(data, Mapping) or not isinstance(data.get("modes"), list):
            raise ParameterError(
                f"{where}: expected a JSON object with a 'modes' list (written by 'bearingfw oma --json')"
            )
        entries = data["modes"]
        channels = data.get("channels")
        if channels is None:  # a hand-written file: the channels of the first shape, in its order
            first = next((e.get("shape") for e in entries if isinstance(e, Mapping)), None)
            channels = list(first) if isinstance(first, Mapping) else []
        modes = []
        for k, entry in enumerate(entries):
            label = f"{where}: mode {k + 1}"
            if (
                not isinstance(entry, Mapping)
                or "frequency" not in entry
                or not isinstance(entry.get("shape"), Mapping)
            ):
                raise ParameterError(f"{label}: needs 'frequency' and a 'shape' object {{channel: value}}")
            shape = entry["shape"]
            missing = [c for c in channels if c not in shape]
            extra = [c for c in shape if c not in channels]
            if missing or extra:
                raise ParameterError(
                    f"{label}: shape channels differ from the file's (missing {missing}, extra {extra})"
                )
            try:
                values = [float(shape[c]) for c in channels]
                frequency = float(entry["frequency"])
                damping = float(entry.get("damping", 0.0))
            except (TypeError, ValueError):
                raise ParameterError(f"{label}: frequency, damping and shape values must be numbers") from None
            bad = next((c for c, v in zip(channels, values, strict=True) if not abs(v) <= MAX_SHAPE), None)
            if bad is not None:
                raise ParameterError(
                    f"{label}: shape value {shape[bad]!r} at channel {bad!r} is out of range: shape values must be "
                    f"finite, |value| <= {MAX_SHAPE:g} (write the shape normalised, largest component 1)"
                )
            if values and not any(values):
                raise ParameterError(f"{label}: the shape is zero at every channel; a mode shape needs a nonzero value")
            if not 0.0 < frequency <= MAX_FREQUENCY:
                raise ParameterError(
                    f"{label}: field 'frequency' = {entry['frequency']!r} is out of range: 0 < frequency <= "
                    f"{MAX_FREQUENCY:g} Hz"
                )
            try:
                modes.append(
                    IdentifiedMode(
                        frequency,
                        damping,
                        values,
                        frequency_std=_statistic(entry, "frequency_std", 0.0),
                        damping_std=_statistic(entry, "damping_std", 0.0),
                        poles=_count(entry.get("poles", 1)),
                        mpc=_statistic(entry, "mpc", 1.0, high=1.0),
                        name=str(entry.get("name", "")),
                    )
                )
            except (ParameterError, TypeError, ValueError) as exc:
                raise ParameterError(f"{label}: {exc}") from None
        meta = {k: v for k, v in data.items() if k not in ("channels", "modes")}
        return cls(channels, modes, meta)


def _statistic(entry: Mapping[str, Any], key: str, default: float, high: float = math.inf) -> float:
    """An optional number of a mode entry in ``0 <= value <= high`` (a spread, a collinearity)."""
    value = entry.get(key, default)
    number = float(value) if isinstance(value, int | float) and not isinstance(value, bool) else math.nan
    if not 0.0 <= number <= high:
        allowed = f"0 <= {key} <= {high:g}" if math.isfinite(high) else f"{key} >= 0, finite"
        raise ParameterError(f"field {key!r} = {value!r} is out of range: {allowed}")
    return number


def _count(value) -> int:
    """The ``poles`` of a mode entry: a whole number >= 1 (JSON may write it as 3.0)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not (1 <= value <= 2**31 and value == int(value)):
        raise ParameterError(f"field 'poles' = {value!r} must be a whole number >= 1")
    return int(value)


def write_modes(modes: IdentifiedModes, path) -> Path:
    """Write ``modes`` as JSON (:meth:`IdentifiedModes.to_dict`)."""
    path = Path(path)
    path.write_text(json.dumps(modes.to_dict(), indent=2) + "\n")
    return path


def read_modes(path) -> IdentifiedModes:
    """Read a modes file written by :func:`write_modes` or ``bearingfw oma --json``."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except IsADirectoryError:
        raise ParameterError(f"{path}: is a directory, not a modes file") from None
    except OSError as exc:
        raise ParameterError(f"{path}: cannot read the file ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8-sig")  # a leading BOM (Windows editors) is not content
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise ParameterError(
            f"{path}: not UTF-8 text (byte {raw[exc.start:exc.start + 1]!r} at offset {exc.start}) on line {line}; a "
            "modes file is JSON in UTF-8"
        ) from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ParameterError(f"{path}: not JSON ({exc})") from None
    except RecursionError:
        raise ParameterError(f"{path}: not a modes file (JSON nested too deeply)") from None
    return IdentifiedModes.from_dict(data, where=str(path))
