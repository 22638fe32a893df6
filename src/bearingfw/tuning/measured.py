"""The measured-modes file that ``bearingfw tune --measured`` reads, and sensor channels checked on a model.

A measured-modes file is TOML (``.toml``) or JSON (anything else), one table per mode::

    # measured modes of my bridge
    source = "ambient test, 3 May"           # optional, shown in the report
    channels = ["G4.uz", "G12.uz", "G4.ux"]  # optional: the order of shapes written as arrays

    [[modes]]
    name = "first bending"       # optional (default: the label, else "mode <k>")
    frequency = 2.55             # Hz, required, > 0
    label = "vertical 1"         # optional: "<label> <k>", the k-th mode of that label
    damping = 0.021              # optional damping ratio, 0 <= damping < 1 (reported, not fitted)
    shape = { "G4.uz" = 1.0, "G12.uz" = -0.98, "G4.ux" = 0.02 }   # optional

- ``label``: one of ``vertical``, ``lateral``, ``longitudinal``, ``torsional`` and a number k:
  the k-th computed mode with that label, as ``bearingfw modal --structure ...`` lists them
  (labels from the modal kinetic energy of the whole mode; x along the bridge, z up). Pairing by
  label, two modes cannot have the same label (both would pair with one computed mode).
- ``shape``: the mode's components at named DOFs, ``"<node>.<component>"`` with a component
  among ux, uy, uz, rx, ry, rz (any scale and sign), as an object or, with ``channels``, an
  array in that order. Every mode that has a shape must give it at the same channels.

The output of ``bearingfw oma --json`` / ``--output`` is such a file (JSON, with shapes and
damping, no labels); its ``synthetic`` flag and ``source`` are kept. Modes identified in memory
(:class:`~bearingfw.oma.IdentifiedModes`) become the same :class:`MeasuredModes` with
:func:`from_identified`.

Pairing (:attr:`MeasuredModes.pair_by`): by MAC at the channels when every mode has a shape,
else by label when every mode has a label; a file where some modes have neither a shape nor a
label, or that mixes modes with only a shape and modes with only a label, is refused. Modes are
never paired by their index.
"""

from __future__ import annotations

import difflib
import json
import math
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from bearingfw.oma.io import MAX_FREQUENCY, MAX_SHAPE, IdentifiedModes, channel_dofs, parse_channel
from bearingfw.parameters import ParameterError
from bearingfw.tuning.pairing import Measurement

__all__ = [
    "MeasuredModes",
    "check_channels",
    "from_identified",
    "identified_measurements",
    "measured_modes",
    "read_measured",
]

_MODE_KEYS = {"name", "frequency", "label", "damping", "shape",
              # written by bearingfw oma, read and ignored
              "frequency_std", "damping_std", "poles", "mpc"}


@attrs.frozen(eq=False)
class MeasuredModes:
    """Measured modes (:class:`~bearingfw.tuning.Measurement`), their channels, damping and how to pair them."""

    measurements: tuple[Measurement, ...]
    channels: tuple[str, ...] | None
    damping: Mapping[str, float | None]
    pair_by: str
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(m.name for m in self.measurements)

    def select(self, items: Sequence[int | str] | None, what: str = "--modes", kind: str = "measured") -> MeasuredModes:
        """The modes ``items`` (1-based numbers or names), in that order; None: all.

        An unknown or repeated item is an error that starts with ``what`` (who asked) and
        lists the ``kind`` modes there are."""
        if items is None:
            return self
        chosen = []
        by_name = {m.name: k for k, m in enumerate(self.measurements)}
        for item in items:
            k = item - 1 if isinstance(item, int) else by_name.get(str(item))
            if k is None or not 0 <= k < len(self.measurements):
                known = ", ".join(f"{j + 1} ({m.name}, {m.frequency:.3f} Hz)" for j, m in enumerate(self.measurements))
                raise ParameterError(f"{what}: no {kind} mode {item!r}; modes: {known}")
            chosen.append(self.measurements[k])
        if len({m.name for m in chosen}) != len(chosen):
            raise ParameterError(f"{what}: a mode is chosen twice in {list(items)}")
        if not chosen:
            raise ParameterError(f"{what}: no {kind} modes to use")
        return attrs.evolve(self, measurements=tuple(chosen))


def _number(value, where: str, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ParameterError(f"{where}: field {what!r} must be a finite number, got {value!r}")
    return float(value)


def _shape_value(value, where: str, what: str) -> float:
    number = _number(value, where, what)
    if abs(number) > MAX_SHAPE:  # a shape is scaled freely; beyond this MAC's products overflow
        raise ParameterError(f"{where}: field {what!r} must be at most {MAX_SHAPE:g} in size, got {value!r}")
    return number


def _channels(value, where: str) -> tuple[str, ...] | None:
    if value is None:
        return None
    if not isinstance(value, list) or not value or not all(isinstance(c, str) for c in value):
        raise ParameterError(f"{where}: field 'channels' must be a non-empty list of channel names, got {value!r}")
    if len(set(value)) != len(value):
        raise ParameterError(f"{where}: field 'channels' names a channel twice: {value}")
    for name in value:
        try:
            parse_channel(name)
        except ParameterError as exc:
            raise ParameterError(f"{where}: {exc}") from None
    return tuple(value)


def _shape(value, channels: tuple[str, ...] | None, where: str) -> tuple[tuple[str, ...], np.ndarray]:
    """(channels, values) of a mode's ``shape`` (object, or array in the file's ``channels`` order)."""
    if isinstance(value, Mapping):
        names = tuple(str(c) for c in value)
        if not names:
            raise ParameterError(f"{where}: field 'shape' is empty")
        for name in names:
            try:
                parse_channel(name)
            except ParameterError as exc:
                raise ParameterError(f"{where}: field 'shape': {exc}") from None
        values = [_shape_value(v, where, f"shape.{c}") for c, v in value.items()]
        if channels is not None:
            missing = [c for c in channels if c not in value]
            extra = [c for c in names if c not in channels]
            if missing or extra:
                raise ParameterError(
                    f"{where}: field 'shape' has other channels than the file's or the first shape's (missing "
                    f"{missing}, extra {extra}); every shape must be at the same channels"
                )
            return channels, np.array([float(value[c]) for c in channels])
        return names, np.array(values)
    if isinstance(value, list):
        if channels is None:
            raise ParameterError(
                f"{where}: field 'shape' is an array: give the file's 'channels' (their order), or write the shape "
                "as {channel = value, ...}"
            )
        if len(value) != len(channels):
            raise ParameterError(f"{where}: field 'shape' has {len(value)} values for {len(channels)} channels")
        return channels, np.array([_shape_value(v, where, f"shape[{k}]") for k, v in enumerate(value)])
    raise ParameterError(f"{where}: field 'shape' must be an object {{channel: value}} or an array, got {value!r}")


def measured_modes(data: Mapping[str, Any], where: str = "measured modes") -> MeasuredModes:
    """:class:`MeasuredModes` from the parsed file (module docstring); errors name ``where`` and the mode."""
    if not isinstance(data, Mapping) or not isinstance(data.get("modes"), list) or not data["modes"]:
        raise ParameterError(
            f"{where}: expected a non-empty list 'modes' of tables with 'frequency' (and 'label' or 'shape'); "
            "see 'bearingfw tune --help'"
        )
    channels = _channels(data.get("channels"), where)
    measurements, damping = [], {}
    for k, entry in enumerate(data["modes"]):
        here = f"{where}: mode {k + 1}"
        if not isinstance(entry, Mapping):
            raise ParameterError(f"{here}: expected a table, got {entry!r}")
        unknown = sorted(set(entry) - _MODE_KEYS)
        if unknown:
            near = [m for u in unknown for m in difflib.get_close_matches(u, sorted(_MODE_KEYS), n=1)]
            raise ParameterError(
                f"{here}: unknown field(s) {', '.join(map(repr, unknown))}"
                + (f" (did you mean {', '.join(near)}?)" if near else "")
                + "; fields: name, frequency, label, damping, shape"
            )
        if "frequency" not in entry:
            raise ParameterError(f"{here}: field 'frequency' (Hz) is required")
        frequency = _number(entry["frequency"], here, "frequency")
        if not 0 < frequency <= MAX_FREQUENCY:
            raise ParameterError(
                f"{here}: field 'frequency' must be > 0 Hz and at most {MAX_FREQUENCY:g} Hz, got {frequency!r}"
            )
        label = entry.get("label")
        shape = None
        if entry.get("shape") is not None:
            # the first shape sets the channels when the file does not; the others are checked against them
            channels, shape = _shape(entry["shape"], channels, here)
        name = entry.get("name")
        if name is not None and (not isinstance(name, str) or not name):
            raise ParameterError(f"{here}: field 'name' must be a non-empty string, got {name!r}")
        if label is None and shape is None:
            raise ParameterError(f"{here}: give a 'label' (e.g. 'vertical 1') or a 'shape' at named channels")
        try:
            measurement = Measurement(frequency, label=label, shape=shape, name=name or label or f"mode {k + 1}")
        except ParameterError as exc:
            raise ParameterError(f"{here}: {exc}") from None
        if measurement.shape is not None and not np.any(measurement.shape):
            raise ParameterError(f"{here}: field 'shape' is zero at every channel")
        measurements.append(measurement)
        ratio = entry.get("damping")
        if ratio is not None:
            ratio = _number(ratio, here, "damping")
            if not 0 <= ratio < 1:
                raise ParameterError(
                    f"{here}: field 'damping' is a damping ratio, 0 <= damping < 1 (2 % is 0.02), got {ratio!r}"
                )
        damping[measurement.name] = ratio
    names = [m.name for m in measurements]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ParameterError(f"{where}: two modes share the name(s) {twice}; name them apart ('name = ...')")
    shaped = [m.shape is not None for m in measurements]
    labelled = [m.label is not None for m in measurements]
    if all(shaped):
        by = "mac"
    elif all(labelled):
        by = "label"
        channels = None  # shapes of some modes only: pairing is by label, the shapes are not used
        labels = [m.label for m in measurements]
        repeated = {lab: [m.name for m in measurements if m.label == lab] for lab in labels if labels.count(lab) > 1}
        if repeated:
            listed = "; ".join(f"{lab!r}: {', '.join(map(repr, modes))}" for lab, modes in repeated.items())
            raise ParameterError(
                f"{where}: modes paired by label need distinct labels, and these share one ({listed}): both would "
                "pair with the same computed mode; number them apart ('vertical 1', 'vertical 2') or give shapes"
            )
    else:
        no_shape = [m.name for m, s in zip(measurements, shaped, strict=True) if not s]
        no_label = [m.name for m, lab in zip(measurements, labelled, strict=True) if not lab]
        raise ParameterError(
            f"{where}: give every mode a shape (pairing by MAC) or every mode a label (pairing by label); "
            f"{', '.join(map(repr, no_shape))} have no shape and {', '.join(map(repr, no_label))} no label"
        )
    meta = {k: v for k, v in data.items() if k not in ("modes", "channels")}
    return MeasuredModes(tuple(measurements), channels, damping, by, meta)


def read_measured(path) -> MeasuredModes:
    """Read a measured-modes file (module docstring): TOML if it ends in ``.toml``, else JSON."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")  # a leading BOM (Windows editors) is not content
    except UnicodeDecodeError as exc:
        line = path.read_bytes()[: exc.start].count(b"\n") + 1
        raise ParameterError(f"{path}: line {line} is not UTF-8 text (byte {exc.start}); save the file as UTF-8") from None
    except OSError as exc:
        raise ParameterError(f"{path}: cannot read the file ({exc.strerror or exc})") from None
    try:
        data = tomllib.loads(text) if path.suffix.lower() == ".toml" else json.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not TOML ({exc})") from None
    except json.JSONDecodeError as exc:
        raise ParameterError(f"{path}: not JSON ({exc}); a TOML file must end in .toml") from None
    out = measured_modes(data, where=str(path))
    return attrs.evolve(out, metadata={"file": str(path), **out.metadata})


def check_channels(model, channels: Sequence[str]) -> None:
    """Every channel names a DOF of ``model`` (a Model or System): :func:`bearingfw.oma.channel_dofs`,
    whose error names an unknown channel and the model's nearest channel names."""
    channel_dofs(model, channels)


def from_identified(modes: IdentifiedModes) -> MeasuredModes:
    """Modes identified by ``bearingfw oma`` as measured modes: shapes at their channels (paired by
    MAC), their damping, and the identification's ``source`` and ``synthetic`` flag."""
    if not modes.modes:
        raise ParameterError("identified modes: there are none to use")
    measurements = tuple(Measurement(m.frequency, shape=m.shape, name=m.name) for m in modes.modes)
    meta = {k: modes.metadata.get(k) for k in ("source", "synthetic") if k in modes.metadata}
    return MeasuredModes(measurements, tuple(modes.channels), {m.name: m.damping for m in modes.modes}, "mac", meta)


def identified_measurements(modes: IdentifiedModes, select=None) -> tuple[tuple[Measurement, ...], tuple[str, ...]]:
    """Measurements (frequency, shape at the channels, name) from identified modes, and the channels.

    ``select``: mode names or 1-based numbers to keep (default all). Pair them ``by="mac"``
    with an :class:`~bearingfw.tuning.Observation` whose ``sensors`` are the returned channels.
    """
    chosen = from_identified(modes).select(select, what="identified_measurements", kind="identified")
    return chosen.measurements, chosen.channels
