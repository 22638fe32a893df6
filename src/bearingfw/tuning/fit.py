"""Calibrating any named parameters of a model against measured modes (``bearingfw tune --structure``).

:func:`fit_parameters` takes a ``build({name: value}) -> Model`` (e.g. a user's builder called
with its keyword arguments), the measured modes (:class:`~bearingfw.tuning.MeasuredModes`: a
measured-modes file or ``bearingfw oma`` output) and the variables with their bounds, and does
what the paper's step 1 does for its K_s, for any parameter:

1. pairing: by MAC at the measured channels when the modes have shapes (every computed mode a
   candidate, unless an ``observation`` says which count), else by label (the kernel's labels of
   the whole mode, or as the ``observation`` sees them); never by index, and again at every
   trial, so modes that change order are still paired right;
2. screening (by MAC, :func:`screen_by_mac`): a measured mode whose best MAC with its partner, at
   the start and over the scan, stays below ``min_mac`` is a noise mode or one the model lacks;
   it is left out and named (its frequency error alone would drive the fit);
3. a scan: ``scan_points`` values of each variable over its bounds (log-spaced for a positive
   range, as the least squares searches it; several variables one at a time, the others at their
   start) whose best sum of squared errors, or the start, begins
4. the least squares of :func:`~bearingfw.tuning.calibrate` (``r_i = f_i / f_i^measured - 1``;
   a variable with a positive lower bound is searched in ``log p``, so a range spanning decades
   is searched evenly);
5. the sensitivities ``d ln f_i / d ln p_j`` at the optimum (differences over a relative step
   ``sensitivity_step`` on each side, one-sided at a bound: no trial leaves the bounds): a
   frequency error ``e`` moves ``p_j`` by about ``e / s_ij``, and a variable that no measured mode
   is sensitive to is not determined by them (a warning says so), nor is one that ends at a bound.
   A fit whose largest frequency error stays above :data:`POOR_MATCH` is warned about too.

Every trial (the start, the scan, the least squares, the sensitivities) builds and analyses the
model; a :class:`~bearingfw.parameters.ParameterError` there (the builder or the model refusing a
value) names the values tried and which trial it was (``START``, ``LOW``, ``HIGH``, a scan point,
...), each variable as ``describe(name)`` says (``bearingfw tune``: ``--param NAME``).

The :class:`ParameterFit` holds the frequencies and errors before (at the start values) and
after, the MAC table of the measured against the paired computed shapes, and what was left out;
:meth:`ParameterFit.to_dict` is ``bearingfw tune --structure ... --json``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import attrs
import numpy as np

from bearingfw.analysis import ModalResult, mac, solve_modal
from bearingfw.model import COMPONENTS, Model
from bearingfw.oma.io import parse_channel
from bearingfw.parameters import ParameterError, integer_parameter, parameter
from bearingfw.tuning.calibration import CalibrationReport, Variable, _variables, calibrate
from bearingfw.tuning.measured import MeasuredModes, check_channels
from bearingfw.tuning.pairing import MIN_MAC, Measurement, Observation, Pairing, PairingError, pair_modes

__all__ = ["POOR_MATCH", "WEAK_SENSITIVITY", "FitOptions", "ParameterFit", "channel_warnings", "fit_parameters",
           "screen_by_mac"]

#: Below this |d ln f / d ln p| for every mode a variable is "not determined" by the measurements.
WEAK_SENSITIVITY = 0.01
#: Above this largest |relative frequency error| after the fit, the model does not match the
#: measurements (frequencies in rad/s instead of Hz are 6.28 times too high; a missing mass or
#: restraint moves modes by tens of percent): a warning says so.
POOR_MATCH = 0.10


@attrs.frozen
class FitOptions:
    """Options of :func:`fit_parameters` (module docstring)."""

    min_mac: float = parameter(
        low=0.0, high=1.0, default=MIN_MAC, doc="least MAC of a measured mode with its computed partner"
    )
    scan_points: int = integer_parameter(
        low=0, high=200, default=9, doc="values of each variable over its bounds scanned for a start (0: none)"
    )
    sensitivity_step: float = parameter(
        low=0.0, low_open=True, high=0.5, default=0.05, doc="relative step of d ln f / d ln p (each side)"
    )
    n_modes: int = integer_parameter(low=1, high=1000, default=20, doc="modes computed per trial")
    max_evaluations: int = integer_parameter(low=1, high=10_000, default=100, doc="modal analyses of the least squares")


@attrs.frozen(eq=False)
class ParameterFit:
    """What :func:`fit_parameters` found (module docstring)."""

    options: FitOptions
    variables: tuple[Variable, ...]
    start: dict[str, float]
    scan_start: dict[str, float]
    by: str
    sensors: tuple[str, ...] | None
    used: tuple[Measurement, ...]
    dropped: tuple[dict, ...]
    before: Pairing
    scan: tuple[tuple[dict, float], ...]
    report: CalibrationReport
    sensitivity: np.ndarray  # (modes, variables) d ln f / d ln p; NaN where p <= 0 or a mode did not pair
    mac_table: np.ndarray | None  # measured x paired computed shapes, after
    damping: Mapping[str, float | None]
    warnings: tuple[str, ...]
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    @property
    def values(self) -> dict[str, float]:
        return dict(self.report.values)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form. Everywhere in it, ``before`` is at the start values (``start``) and ``after``
        at the fitted ones; the least squares began at ``scan_start`` (``calibration.from``)."""
        names = [m.name for m in self.used]
        after = self.report.after

        def by_name(values):
            return {n: float(v) for n, v in zip(names, values, strict=True)}

        def finite(v):
            return float(v) if v is not None and math.isfinite(v) else None

        parameters = {}
        for j, v in enumerate(self.variables):
            parameters[v.name] = {
                "start": self.start[v.name], "scan_start": self.scan_start[v.name], "fitted": self.values[v.name],
                "low": v.low, "high": v.high, "scale": "log" if v.logarithmic else "linear",
                "sensitivity": {n: finite(s) for n, s in zip(names, self.sensitivity[:, j], strict=True)},
            }
        report = self.report
        return {
            "source": self.metadata.get("source"),
            "synthetic": bool(self.metadata.get("synthetic", False)),
            "pairing": self.by,
            "sensors": None if self.sensors is None else list(self.sensors),
            "min_mac": self.options.min_mac if self.by == "mac" else None,
            "parameters": parameters,
            "fitted": self.values,
            "dropped": [dict(d) for d in self.dropped],
            "warnings": list(self.warnings),
            "scan": [{"values": dict(values), "cost": finite(cost)} for values, cost in self.scan],  # None: unpaired
            "modes": [
                {
                    "name": m.name,
                    "measured": m.frequency,
                    "before": float(self.before.frequencies[i]),
                    "after": float(after.frequencies[i]),
                    "error_before": float(self.before.errors[i]),
                    "error_after": float(after.errors[i]),
                    "label_before": self.before.labels[i],
                    "label_after": after.labels[i],
                    "mode_after": int(after.modes[i]) + 1,
                    "mac_before": None if self.before.mac is None else float(self.before.mac[i]),
                    "mac_after": None if after.mac is None else float(after.mac[i]),
                    "damping": self.damping.get(m.name),
                    "sensitivity": {v.name: finite(self.sensitivity[i, j]) for j, v in enumerate(self.variables)},
                }
                for i, m in enumerate(self.used)
            ],
            "measured": by_name(after.measured),
            "before": by_name(self.before.frequencies),
            "after": by_name(after.frequencies),
            "error_before": by_name(self.before.errors),
            "error_after": by_name(after.errors),
            "mac": None if self.mac_table is None else np.round(self.mac_table, 6).tolist(),
            "calibration": {
                "from": dict(self.scan_start),
                "cost": report.cost,
                "evaluations": report.evaluations,
                "success": report.success,
                "message": report.message,
                "automac_after": np.round(report.automac_after, 6).tolist(),
            },
        }


def _observation(channels: Sequence[str]) -> Observation:
    """Shapes compared at ``channels``; every computed mode a candidate (no region decides)."""
    nodes = tuple(dict.fromkeys(parse_channel(c)[0] for c in channels))
    return Observation(nodes, components=COMPONENTS, min_share=0.0, sensors=tuple(channels))


def _grid(variable: Variable, points: int) -> list[float]:
    if points == 0:
        return []
    if variable.logarithmic:
        return [float(v) for v in np.geomspace(variable.low, variable.high, points)]
    return [float(v) for v in np.linspace(variable.low, variable.high, points)]


def _scan_role(k: int, points: int) -> str:
    return "LOW" if k == 0 else "HIGH" if k == points - 1 else "a scan point"


def _cost(pairing: Pairing | None) -> float:
    return math.inf if pairing is None else float(np.sum(pairing.errors**2))


def screen_by_mac(
    measured: Sequence[Measurement], pairings: Sequence[Pairing | None], min_mac: float
) -> tuple[tuple[Measurement, ...], tuple[dict, ...]]:
    """Keep the measurements whose best pair MAC over ``pairings`` reaches ``min_mac``; the others, named
    (``{"name", "frequency", "best_mac"}``). A None pairing (nothing paired at that trial) counts for none."""
    best = np.zeros(len(measured))
    for pairing in pairings:
        if pairing is not None:
            best = np.maximum(best, pairing.mac)
    kept = tuple(m for m, b in zip(measured, best, strict=True) if b >= min_mac)
    dropped = tuple(
        {"name": m.name, "frequency": m.frequency, "best_mac": float(b)}
        for m, b in zip(measured, best, strict=True)
        if b < min_mac
    )
    return kept, dropped


def channel_warnings(sensors: Sequence[str]) -> list[str]:
    """What the channels of measured shapes leave in doubt: with one, every MAC is 1."""
    if len(sensors) == 1:
        return [
            f"the shapes have a single channel ({sensors[0]}): every MAC is 1, so modes are paired by the "
            "assignment alone and the screening by MAC cannot reject anything"
        ]
    return []


def fit_parameters(
    build: Callable[[dict[str, float]], Model],
    measured: MeasuredModes,
    variables: Mapping[str, Sequence[float]],
    options: FitOptions = FitOptions(),
    *,
    observation: Observation | None = None,
    describe: Callable[[str], str] | None = None,
    **modal_options,
) -> ParameterFit:
    """Fit ``variables`` (``{name: (start, low, high)}``) of ``build`` to ``measured`` (module docstring).

    ``build`` gets ``{name: value}`` for every variable. ``observation``: which computed modes
    count and how they are labelled (default: all, labelled as whole modes); by MAC, its sensors
    become the measured channels. ``describe(name)``: how messages name a variable (default: its
    name). Raises :class:`ParameterError` for a channel that is not a DOF of the model, a trial
    value the builder or the model refuses (naming it and the trial), and when no measured mode
    pairs with a computed one at ``options.min_mac`` or better;
    :class:`~bearingfw.tuning.PairingError` when a label has no computed mode (compute more:
    ``options.n_modes``). Extra keywords go to :func:`~bearingfw.analysis.solve_modal`.
    """
    vs = _variables(variables)
    describe = describe or str
    start = {v.name: v.initial for v in vs}
    by = measured.pair_by
    sensors = measured.channels if by == "mac" else None
    if sensors is not None:
        observation = _observation(sensors) if observation is None else attrs.evolve(observation, sensors=sensors)
    warnings: list[str] = [] if sensors is None else channel_warnings(sensors)
    tried: list[dict[str, float]] = []  # the values of the latest trial (the least squares calls build itself)

    def model_at(values: Mapping[str, float]) -> Model:
        tried[:] = [dict(values)]
        model = build(dict(values))
        if not isinstance(model, Model):
            raise ParameterError(f"fit_parameters: 'build' must return a Model, got {type(model).__name__}")
        return model

    def refused(values: Mapping[str, float], varied: Sequence[str], role: str, exc: ParameterError) -> ParameterError:
        named = ", ".join(f"{describe(n)} = {values[n]:g}" for n in varied)
        return ParameterError(f"{named} ({role}): {exc}")

    def modal_at(values: Mapping[str, float], varied: Sequence[str], role: str) -> ModalResult:
        try:
            return solve_modal(model_at(values), options.n_modes, **modal_options)
        except ParameterError as exc:  # the builder or the model refusing a trial value
            raise refused(values, varied, role, exc) from None

    def pairing(modal: ModalResult, ms) -> Pairing | None:
        try:
            return pair_modes(modal, ms, by=by, observation=observation)
        except PairingError:
            return None

    names = [v.name for v in vs]
    start_modal = modal_at(start, names, "START")
    if sensors is not None:
        check_channels(start_modal.system, sensors)
    scanned = []
    for v in vs:
        grid = _grid(v, options.scan_points)
        for k, value in enumerate(grid):
            point = {**start, v.name: value}
            scanned.append((point, modal_at(point, [v.name], _scan_role(k, len(grid)))))
    ms = measured.measurements
    dropped: tuple[dict, ...] = ()
    if by == "mac":
        used, dropped = screen_by_mac(ms, [pairing(m, ms) for m in [start_modal] + [m for _, m in scanned]],
                                      options.min_mac)
        listed = ", ".join(f"{d['name']} ({d['frequency']:.3f} Hz, best MAC {d['best_mac']:.2f})" for d in dropped)
        if not used:
            raise ParameterError(
                f"no measured mode pairs with a computed one at MAC >= {options.min_mac:g} (at the start or over the "
                f"scan): {listed}"
            )
        if dropped:
            warnings.append(f"left out, paired at MAC below {options.min_mac:g} with every computed mode: {listed}")
    else:
        used = ms
    before = pair_modes(start_modal, used, by=by, observation=observation)  # raises the PairingError with its message
    scan = tuple((p, _cost(pairing(modal, used))) for p, modal in scanned)
    begin = min([(start, _cost(before)), *scan], key=lambda item: item[1])[0]
    fitted_vs = {v.name: (begin[v.name], v.low, v.high) for v in vs}

    def build_one(value_or_values):
        values = value_or_values if isinstance(value_or_values, dict) else {vs[0].name: value_or_values}
        return model_at(values)

    try:
        report = calibrate(build_one, used, fitted_vs, by=by, observation=observation, n_modes=options.n_modes,
                           max_evaluations=options.max_evaluations, **modal_options)
    except PairingError:
        raise
    except ParameterError as exc:
        raise refused(tried[0], names, "a least-squares trial", exc) from None
    values = report.values
    after = report.after
    weak = after.weak(options.min_mac)
    if weak:
        macs = dict(zip((m.name for m in used), after.mac, strict=True))
        warnings.append(f"at the fitted values these modes pair below MAC {options.min_mac:g}: "
                        + ", ".join(f"{n} (MAC {macs[n]:.3f})" for n in weak))
    worst = int(np.argmax(np.abs(after.errors)))
    if abs(after.errors[worst]) > POOR_MATCH:
        warnings.append(
            f"after the fit, {used[worst].name} is still {after.errors[worst]:+.1%} off its measured frequency: check "
            "that the measured frequencies are in Hz (not rad/s) and the model (a mass, a restraint, or a parameter "
            "that these modes do not answer)"
        )

    sensitivity = np.full((len(used), len(vs)), np.nan)
    step = options.sensitivity_step
    fitted_logs = np.log(after.frequencies)
    for j, v in enumerate(vs):
        p = values[v.name]
        if not p > 0:
            continue
        # a relative step each side, one-sided at a bound: every trial within the bounds
        low, high = max(p * (1 - step), v.low), min(p * (1 + step), v.high)
        logs = []
        for q in (low, high):
            if q == p:
                logs.append(fitted_logs)
                continue
            found = pairing(modal_at({**values, v.name: q}, [v.name], "a sensitivity step"), used)
            logs.append(None if found is None else np.log(found.frequencies))
        if logs[0] is not None and logs[1] is not None and high > low:
            sensitivity[:, j] = (logs[1] - logs[0]) / math.log(high / low)
    for j, v in enumerate(vs):
        column = sensitivity[:, j]
        if np.all(np.isfinite(column)) and np.max(np.abs(column)) < WEAK_SENSITIVITY:
            warnings.append(f"no measured mode is sensitive to {describe(v.name)} (|d ln f / d ln {v.name}| < "
                            f"{WEAK_SENSITIVITY:g}): its fitted value is not determined by these modes")
        x = v.to_x(values[v.name])
        if min(x - v.to_x(v.low), v.to_x(v.high) - x) < 1e-3 * (v.to_x(v.high) - v.to_x(v.low)):
            warnings.append(f"{describe(v.name)} = {values[v.name]:.6g} ends at a bound of [{v.low:g}, {v.high:g}]: "
                            "widen it, or the model cannot match these modes by this parameter")

    mac_table = None
    if by == "mac":
        measured_shapes = np.column_stack([m.shape for m in used])
        computed = report.modal_after.shapes[np.ix_(observation.shape_dofs(report.modal_after.system), after.modes)]
        moving = np.any(computed != 0, axis=0)
        mac_table = np.zeros((len(used), len(used)))
        if np.any(moving):
            mac_table[:, moving] = mac(measured_shapes, computed[:, moving])
    return ParameterFit(
        options=options,
        variables=vs,
        start=start,
        scan_start=dict(begin),
        by=by,
        sensors=sensors,
        used=used,
        dropped=dropped,
        before=before,
        scan=scan,
        report=report,
        sensitivity=sensitivity,
        mac_table=mac_table,
        damping={m.name: measured.damping.get(m.name) for m in used},
        warnings=tuple(warnings),
        metadata=dict(measured.metadata),
    )
