"""Pairing computed modes with measured ones: by label or by mode shape (MAC), never by index.

A measured mode is a :class:`Measurement`: its frequency and either a label such as
``"lateral 1"`` (the first mode labelled lateral) or a shape at the observed DOFs.

Where the measurements were taken matters. An :class:`Observation` names the nodes and
components the sensors saw (the paper's: the deck). With one, a mode is labelled from its
kinetic energy *at the observed DOFs*: the kernel's energy shares
(:func:`bearingfw.analysis.energy_shares`) of the shape with every other DOF zeroed. Only modes
carrying at least ``min_share`` of their kinetic energy there take part, numbered among
themselves: a mode of the arches alone, which deck sensors barely see, is not "lateral 1" of
the deck, and a deck moving vertically under arches that swing in opposition is vertical for
the deck. The share of mode ``phi`` (mass-normalised) at the observed DOFs ``o`` is
``phi_o^T M_oo phi_o``. Without an observation the kernel's labels of the whole mode are used.

By MAC, each measured shape is paired with the computed mode of highest MAC (the paper's eq.
12) at the observed DOFs, one-to-one (an optimal assignment over the MAC table), so modes that
swap order between two models are still paired with the right measurement. The assignment pairs
every measurement, however poorly its shape matches: :meth:`Pairing.weak` names the pairs below
a least MAC (:data:`MIN_MAC`, 0.8: a measured mode that matches no computed one that well is a
noise mode or a mode the model lacks, and its frequency error would pull a calibration off).
A measured shape that is zero at every sensor, or sensors at supported DOFs (where every
computed shape is zero), make MAC undefined: an error names them.

Sensors. Measured shapes are often known at a few channels only, not at every node x component
of the observed region: an :class:`Observation` with ``sensors`` (channel names
``"<node>.<component>"``, as :mod:`bearingfw.oma` writes them) compares shapes at exactly those
DOFs, in that order, while the region (``nodes`` x ``components``) still decides which computed
modes count. :func:`~bearingfw.tuning.identified_measurements` turns modes identified by
``bearingfw oma`` into measurements and their sensors.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

import attrs
import numpy as np
from scipy.optimize import linear_sum_assignment

from bearingfw.analysis import LABELS, ModalResult, energy_shares, label_modes, mac
from bearingfw.model import COMPONENTS
from bearingfw.oma.io import channel_dofs, parse_channel
from bearingfw.parameters import ParameterError, parameter

__all__ = [
    "MIN_MAC",
    "PAIR_BY",
    "Measurement",
    "Observation",
    "ObservedModes",
    "Pairing",
    "PairingError",
    "as_measurements",
    "observed_modes",
    "pair_modes",
    "paired_shapes",
]

PAIR_BY = ("label", "mac")
#: The least MAC of a trustworthy pair by shape (:meth:`Pairing.weak`): the usual consistency
#: threshold between a test mode and its FE counterpart (0.8-0.9 in the updating literature);
#: the lower end, because a few sensors see neighbouring modes alike.
MIN_MAC = 0.8
_LABEL = re.compile(rf"^({'|'.join(LABELS)}) ([1-9][0-9]*)$")


class PairingError(ValueError):
    """A measurement has no computed counterpart (no such label, too few modes)."""


def _shape(value):
    if value is None:
        return None
    arr = np.asarray(value, dtype=float).reshape(-1)
    arr.setflags(write=False)
    return arr


@attrs.frozen(eq=False)
class Measurement:
    """A measured mode: ``frequency`` (Hz) and a ``label`` (``"<label> <k>"``) and/or a ``shape``.

    ``name`` defaults to the label (:func:`as_measurements` names unlabelled ones by position).
    ``shape`` holds the mode's components at the observed DOFs (node-major, the order of
    :meth:`Observation.dofs`), or at every DOF of the model when pairing without an observation.
    """

    frequency: float = parameter(low=0.0, low_open=True, unit="Hz", doc="measured natural frequency")
    label: str | None = attrs.field(default=None)
    shape: np.ndarray | None = attrs.field(default=None, converter=_shape)
    name: str | None = attrs.field(default=None)

    def __attrs_post_init__(self):
        if self.label is not None and not (isinstance(self.label, str) and _LABEL.match(self.label)):
            raise ParameterError(
                f"Measurement: field 'label' must read '<label> <k>' with a label among {', '.join(LABELS)} "
                f"and k >= 1 (e.g. 'lateral 1'), got {self.label!r}"
            )
        if self.label is None and self.shape is None:
            raise ParameterError("Measurement: give a 'label' or a 'shape' (or both)")
        if self.shape is not None and not np.all(np.isfinite(self.shape)):
            raise ParameterError("Measurement: field 'shape' must be finite")
        if self.name is None and self.label is not None:
            object.__setattr__(self, "name", self.label)


def as_measurements(measured) -> tuple[Measurement, ...]:
    """Measurements from ``Measurement`` objects, ``(label or shape, frequency)`` pairs or ``{label: frequency}``."""
    if isinstance(measured, Mapping):
        measured = list(measured.items())
    out = []
    for item in measured:
        if isinstance(item, Measurement):
            out.append(item)
            continue
        try:
            what, frequency = item
        except (TypeError, ValueError):
            raise ParameterError(
                f"measured: each item must be a Measurement or a (label or shape, frequency) pair, got {item!r}"
            ) from None
        if isinstance(what, str):
            out.append(Measurement(frequency, label=what))
        else:
            out.append(Measurement(frequency, shape=what))
    out = [m if m.name is not None else attrs.evolve(m, name=f"measured {k + 1}") for k, m in enumerate(out)]
    names = [m.name for m in out]
    if not out:
        raise ParameterError("measured: no measurements")
    if len(set(names)) != len(names):
        raise ParameterError(f"measured: two measurements share a name among {names}")
    return tuple(out)


def _nodes(value):
    return tuple(value) if not isinstance(value, str) else (value,)


def _components(value):
    return tuple(str(v).lower() for v in ((value,) if isinstance(value, str) else value))


def _sensors(value):
    if value is None:
        return None
    return (str(value),) if isinstance(value, str) else tuple(str(v) for v in value)


@attrs.frozen
class Observation:
    """The measured DOFs: ``nodes`` x ``components``, and the share a mode needs there to count."""

    nodes: tuple[str, ...] = attrs.field(converter=_nodes)
    components: tuple[str, ...] = attrs.field(default=COMPONENTS, converter=_components)
    min_share: float = parameter(
        low=0.0, high=1.0, high_open=True, default=0.5, doc="least kinetic-energy share at the observed DOFs"
    )
    sensors: tuple[str, ...] | None = attrs.field(default=None, converter=_sensors)

    def __attrs_post_init__(self):
        if not self.nodes:
            raise ParameterError("Observation: field 'nodes' is empty")
        bad = [c for c in self.components if c not in COMPONENTS]
        if bad or not self.components:
            raise ParameterError(f"Observation: field 'components' must be among {', '.join(COMPONENTS)}, got {bad}")
        if self.sensors is not None:
            if not self.sensors or len(set(self.sensors)) != len(self.sensors):
                raise ParameterError(f"Observation: field 'sensors' must be distinct channel names, got {self.sensors}")
            for name in self.sensors:
                parse_channel(name)

    def dofs(self, system) -> np.ndarray:
        """The observed DOFs of ``system``, node-major."""
        return system.dofmap.dofs(self.nodes, self.components)

    def shape_dofs(self, system) -> np.ndarray:
        """The DOFs at which shapes are compared: the ``sensors`` in order if given, else :meth:`dofs`."""
        return self.dofs(system) if self.sensors is None else channel_dofs(system, self.sensors)


@attrs.frozen(eq=False)
class ObservedModes:
    """Per computed mode: kinetic-energy share at the observed DOFs, label there, and whether it counts."""

    share: np.ndarray
    labels: tuple[str, ...]
    eligible: np.ndarray

    @property
    def numbered(self) -> dict[str, int]:
        """``"<label> <k>"`` of each eligible mode -> its index (frequency order)."""
        counts: dict[str, int] = {}
        out = {}
        for m in np.flatnonzero(self.eligible):
            lab = self.labels[m]
            counts[lab] = counts.get(lab, 0) + 1
            out[f"{lab} {counts[lab]}"] = int(m)
        return out


def observed_modes(modal: ModalResult, observation: Observation | None = None) -> ObservedModes:
    """Shares, labels and eligibility of ``modal``'s modes as seen at ``observation`` (all DOFs if None)."""
    if observation is None:
        return ObservedModes(np.ones(modal.n_modes), modal.labels, np.ones(modal.n_modes, dtype=bool))
    system = modal.system
    mask = np.zeros(system.n_dof)
    mask[observation.dofs(system)] = 1.0
    seen = modal.shapes * mask[:, None]
    share = np.einsum("ij,ij->j", seen, system.M @ seen)
    labels = label_modes(energy_shares(system, seen))
    return ObservedModes(share, labels, share >= observation.min_share)


@attrs.frozen(eq=False)
class Pairing:
    """Which computed mode answers each measurement."""

    measurements: tuple[Measurement, ...]
    modes: tuple[int, ...]
    frequencies: np.ndarray
    labels: tuple[str, ...]  # the paired modes' numbered labels (as observed)
    mac: np.ndarray | None  # MAC of each pair (by MAC), else None
    by: str

    @property
    def measured(self) -> np.ndarray:
        return np.array([m.frequency for m in self.measurements])

    @property
    def errors(self) -> np.ndarray:
        """Relative frequency errors ``(f - f_measured) / f_measured``."""
        return self.frequencies / self.measured - 1.0

    def weak(self, min_mac: float = MIN_MAC) -> tuple[str, ...]:
        """Names of the measurements paired by MAC below ``min_mac`` (none when paired by label)."""
        if self.mac is None:
            return ()
        return tuple(m.name for m, v in zip(self.measurements, self.mac, strict=True) if v < min_mac)


def _reverse(numbered: dict[str, int]) -> dict[int, str]:
    return {m: lab for lab, m in numbered.items()}


def pair_modes(
    modal: ModalResult,
    measured,
    by: str = "label",
    observation: Observation | None = None,
) -> Pairing:
    """Pair each measurement with a computed mode of ``modal`` (module docstring).

    ``by="label"`` needs every measurement's label; ``by="mac"`` its shape. Raises
    :class:`PairingError` when a label has no eligible mode (compute more modes) or there are
    fewer eligible modes than measured shapes.
    """
    if by not in PAIR_BY:
        raise ParameterError(f"pair_modes: 'by' must be one of {', '.join(PAIR_BY)}, got {by!r}")
    ms = as_measurements(measured)
    seen = observed_modes(modal, observation)
    numbered = seen.numbered
    names = _reverse(numbered)
    freq = modal.frequencies
    if by == "label":
        missing = [m.name for m in ms if m.label is None]
        if missing:
            raise ParameterError(f"pair_modes: by='label' needs a label on every measurement; {missing} have none")
        labels = [m.label for m in ms]
        repeated = sorted({lab for lab in labels if labels.count(lab) > 1})
        if repeated:
            raise ParameterError(
                f"pairing by label: two measured modes have the label {', '.join(map(repr, repeated))}; both would "
                "pair with the same computed mode: give each mode its own label"
            )
        absent = [m.label for m in ms if m.label not in numbered]
        if absent:
            have = ", ".join(f"{lab} ({freq[i]:.3g} Hz)" for lab, i in numbered.items())
            counted = "" if observation is None else " that the sensors see"
            raise PairingError(
                f"pairing by label: no computed mode labelled {', '.join(absent)} among the {modal.n_modes} computed"
                f"{counted} (they are: {have or 'none'}); compute more modes, or check the label"
            )
        modes = tuple(numbered[m.label] for m in ms)
        return Pairing(ms, modes, freq[list(modes)], tuple(m.label for m in ms), None, by)
    missing = [m.name for m in ms if m.shape is None]
    if missing:
        raise ParameterError(f"pair_modes: by='mac' needs a shape on every measurement; {missing} have none")
    candidates = np.flatnonzero(seen.eligible)
    if candidates.size < len(ms):
        raise PairingError(
            f"pairing by MAC: {len(ms)} measured shapes but only {candidates.size} computed modes to pair them with; "
            "compute more modes"
        )
    dofs = None if observation is None else observation.shape_dofs(modal.system)
    computed = modal.shapes[:, candidates] if dofs is None else modal.shapes[np.ix_(dofs, candidates)]
    size = {m.shape.size for m in ms}
    if size != {computed.shape[0]}:
        raise ParameterError(
            f"pairing by MAC: measured shapes have {sorted(size)} components; the computed ones are compared at "
            f"{computed.shape[0]} DOFs"
        )
    table = _mac_table(ms, computed, observation, modal.system)
    rows, cols = linear_sum_assignment(-table)
    chosen = np.empty(len(ms), dtype=int)
    chosen[rows] = cols
    modes = tuple(int(candidates[c]) for c in chosen)
    values = table[np.arange(len(ms)), chosen]
    return Pairing(ms, modes, freq[list(modes)], tuple(names[m] for m in modes), values, by)


def _mac_table(ms, computed: np.ndarray, observation: Observation | None, system) -> np.ndarray:
    """MAC of the measured shapes against the computed ones; a computed mode still at every sensor scores 0.

    ``mac`` refuses zero shapes; here a zero measured shape and sensors at supported DOFs are
    errors that name them, and a computed mode that happens not to move the sensors is no match.
    """
    measured = np.column_stack([m.shape for m in ms])
    zero = [m.name for m in ms if not np.any(m.shape)]
    if zero:
        raise ParameterError(
            f"pairing by MAC: measured mode(s) {', '.join(map(repr, zero))} have a zero shape at every sensor: "
            "MAC is undefined"
        )
    if observation is not None and observation.sensors is not None:
        # A supported DOF has an empty row in u = T q: it never moves, whatever the mode.
        still = system.T.getnnz(axis=1)[observation.shape_dofs(system)] == 0
        fixed = [c for c, s in zip(observation.sensors, still, strict=True) if s]
        if fixed:
            raise ParameterError(
                f"pairing by MAC: channel(s) {', '.join(fixed)} are at supported DOFs of the model, where every mode "
                "shape is zero (sensors on a support read the ground); leave them out of the modes file"
            )
    moving = np.any(computed != 0, axis=0)
    table = np.zeros((measured.shape[1], computed.shape[1]))
    if np.any(moving):
        table[:, moving] = mac(measured, computed[:, moving])
    return table


def paired_shapes(modal: ModalResult, pairing: Pairing, observation: Observation | None = None) -> np.ndarray:
    """The paired modes' shapes at the observed DOFs (all DOFs without an observation), one per column."""
    shapes = modal.shapes[:, list(pairing.modes)]
    return shapes if observation is None else shapes[observation.shape_dofs(modal.system)]
