"""The paper's tuning study on the reference bridge: observation, step 1, step 2, damping.

This module joins :mod:`bearingfw.bridges` (the model) and :mod:`bearingfw.tuning` (the
method); it and the defaults script :mod:`bearingfw.bridges.calibrate_defaults` are the only
bridge modules that import tuning, and nothing in tuning imports bridges.

- :func:`deck_observation`: the paper's sensors saw the deck's vertical and transverse motion,
  so its modes are the deck's (``DECK_COMPONENTS``, ``DECK_SHARE``); :func:`modes` pairs a
  model's modes with Table 2's that way.
- :func:`ks_estimate`: eq. (11) with the pillars' K_c, the untuned model's lateral frequency
  f_a and the measured one f_b.
- :func:`calibrate_ks` (step 1): least squares on K_s of the M1 model (linear springs on the
  sliding directions) against the measured frequencies of Table 2.
- :func:`calibrate_ks_as_paper` (step 1 as the paper did it, ``bearingfw tune``): the same least
  squares with K_s bounded above by the paper's stop (400 MN/m, where its first vertical frequency
  rose too much), and without the bound for comparison. On this frame model the first vertical
  frequency hardly depends on K_s (1.603 Hz at 400 MN/m, 1.604 Hz at the unbounded 7.3 GN/m), so
  the unbounded fit follows the lateral mode alone; the bound is the paper's constraint made
  explicit, and its value is the K_s of the presets (:data:`~bearingfw.bridges.DEFAULT_KS`,
  :data:`~bearingfw.bridges.KS_SOURCE`) and so of the default study.
- :func:`tuned_bridge` (step 2): the M2 model, regularized Coulomb with the stick stiffness
  K_s and ``mu = 0.04``, for time histories.
- :func:`measured_damping`: the measured decrements as damping ratios and Rayleigh coefficients.
- :func:`paper_sensors`: the paper's measurement points P1..P7 as deck channels (``"GA12.uz"``),
  for simulated ambient tests and for pairing modes identified by ``bearingfw oma`` by MAC.
- :func:`calibrate_ks_to_identified` (step 1 with identified modes, ``bearingfw tune
  --measured``): :func:`bearingfw.tuning.fit_parameters` on K_s of the M1 model, its modes seen by
  the deck sensors, starting from eq. 11; modes identified by ``bearingfw oma`` paired by MAC at
  their channels; those that pair with no computed mode well enough are dropped and named; a scan
  of K_s starts the least squares; each mode's sensitivity to K_s and the damping follow.

Identified modes, step by step. A few deck sensors see several modes alike (on half the
bridge, as the paper placed them, MAC 0.85-0.9 between neighbouring vertical modes), so pairing
by MAC can switch between trial values of K_s and the sum of squares has local minima: from
eq. 11's estimate, which is rough (its SDOF frame ignores the deck), the fit can stop in one.
So the fit starts from the best of eq. 11 and a scan of K_s over its bounds
(:attr:`IdentifiedTuning.scan_points` log-spaced values, one modal analysis each). Before
that, each identified mode's best MAC with its partner over the scan (and eq. 11's K_s)
decides whether it takes part: below :attr:`IdentifiedTuning.min_mac` it is a noise mode or
one the model lacks, and its frequency error alone would drive K_s (a spurious mode at MAC 0.13
pulls the fit to the bound of 10 MN/m). After the fit, pairs below the least MAC at the fitted
K_s are warned about. The sensitivity ``d ln f / d ln K_s`` of each mode at the fitted K_s says
how much it tells about K_s: a frequency error ``e`` moves K_s by about ``e / s``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

import attrs
import numpy as np

from bearingfw.analysis import ModalResult, solve_modal
from bearingfw.analysis.damping import damping_ratio_from_log_decrement, rayleigh_from_ratios
from bearingfw.bridges.layout import SIDES
from bearingfw.bridges.paper import DAMPING_RATIOS, FRICTION, KS_FIT, LOG_DECREMENTS, MODES, TABLE2_OMA
from bearingfw.bridges.parameters import BridgeParameters
from bearingfw.bridges.presets import DEFAULT_KS, KS_SOURCE, reference_bridge
from bearingfw.bridges.reference import DECK_COMPONENTS, DECK_SHARE, deck_nodes, grid
from bearingfw.model import Model
from bearingfw.parameters import ParameterError, integer_parameter, parameter
from bearingfw.tuning import (
    MIN_MAC,
    CalibrationReport,
    FitOptions,
    Measurement,
    Observation,
    Pairing,
    PairingError,
    calibrate,
    channel_warnings,
    evaluate,
    fit_parameters,
    from_identified,
    ks_eq11,
    observed_modes,
    pair_modes,
    screen_by_mac,
)

__all__ = [
    "KS_BOUNDS",
    "KS_PAPER_BOUND",
    "N_MODES",
    "IdentifiedFit",
    "IdentifiedTuning",
    "PaperKs",
    "calibrate_ks",
    "calibrate_ks_as_paper",
    "calibrate_ks_to_identified",
    "channel_warnings",  # from bearingfw.tuning, where the fit of identified modes lives
    "deck_observation",
    "ks_estimate",
    "measured_damping",
    "mode_labels",
    "modes",
    "paper_measurements",
    "paper_sensors",
    "part_shares",
    "screen_by_mac",  # from bearingfw.tuning
    "tuned_bridge",
]

#: Search range of K_s in step 1 (N/m): from nearly free to nearly rigid sliding bearings.
KS_BOUNDS = (1e7, 1e11)
#: Modes computed per trial: enough to reach the torsional mode near 14 Hz.
N_MODES = 40


def deck_observation(params: BridgeParameters = BridgeParameters(), sensors=None) -> Observation:
    """The paper's sensors: the deck's vertical and transverse motion (``DECK_COMPONENTS``, ``DECK_SHARE``).

    ``sensors``: channel names at which measured shapes are given (e.g. :func:`paper_sensors`).
    """
    return Observation(deck_nodes(params), components=DECK_COMPONENTS, min_share=DECK_SHARE, sensors=sensors)


#: Section 2.3: the measurement points, each on both outer edges of the deck (a, b), as
#: ``("span", k, fraction of span k)`` or ``("axis", k, metres past axis k)``: P1 in the middle
#: of the first span, P2 over the second support, P3 and P4 at 1/3 and 2/3 of the second span,
#: P5 over the third support, P6 18.22 m from the third support into the central span, P7 at the
#: middle of the central span (figure 8 is missing; the text gives these positions).
PAPER_POINTS = {
    "P1": ("span", 1, 0.5), "P2": ("axis", 2, 0.0), "P3": ("span", 2, 1 / 3), "P4": ("span", 2, 2 / 3),
    "P5": ("axis", 3, 0.0), "P6": ("axis", 3, 18.22), "P7": ("span", 3, 0.5),
}


def paper_sensors(
    params: BridgeParameters = BridgeParameters(), components=DECK_COMPONENTS
) -> dict[str, tuple[str, ...]]:
    """The channels of P1..P7: ``{point: ("GA<k>.uy", "GA<k>.uz", "GB<k>.uy", "GB<k>.uz")}``.

    Each point is the girder station nearest its position; the sensors' a and b sides are the
    girders A and B (the model's deck edges), with ``components`` (default: the vertical and
    transverse channels the paper analysed, figure 11).
    """
    stations = grid(params)
    x = params.axis_positions

    def station(kind, number, where):
        at = x[number - 1] + where if kind == "axis" else x[number - 1] + where * (x[number] - x[number - 1])
        return int(round(at / stations.step))

    return {
        point: tuple(f"G{side}{station(*spec)}.{c}" for side in SIDES for c in components)
        for point, spec in PAPER_POINTS.items()
    }


def paper_measurements(column: Mapping[str, float] = TABLE2_OMA) -> list[tuple[str, float]]:
    """Table 2's modes in the paper's order as ``(label, frequency)`` (default: the measured column)."""
    return [(mode, column[mode]) for mode in MODES]


def modes(
    preset: str = "M0", params: BridgeParameters = BridgeParameters(), measured=None, ks: float = DEFAULT_KS
) -> tuple[ModalResult, Pairing]:
    """The modal analysis of the bridge with ``preset`` and its pairing with ``measured`` (default: Table 2 OMA)."""
    measured = paper_measurements() if measured is None else measured
    model = reference_bridge(preset, ks=ks, params=params)
    return evaluate(model, measured, observation=deck_observation(params), n_modes=N_MODES)


#: The parts of the reference bridge a mode can belong to, by node name: the girders (with the
#: bearings' girder-side nodes), the arches, the pillars. The abutment seats carry no mass.
PARTS = {"deck": re.compile(r"^G[AB]\d+$|\.girder$"), "arches": re.compile(r"^R[AB]\d+$"),
         "pillars": re.compile(r"^P\d[AB]\.")}


def part_shares(modal: ModalResult) -> dict[str, np.ndarray]:
    """Each part's share of each mode's kinetic energy (:data:`PARTS`), ``{part: (n_modes,)}``."""
    system = modal.system
    energy = modal.shapes * (system.M @ modal.shapes)
    per_node = energy.reshape(len(system.model.nodes), -1, modal.n_modes).sum(axis=1)
    total = per_node.sum(axis=0)
    total = np.where(np.abs(total) > 0, total, 1.0)
    names = [n.name for n in system.model.nodes]
    return {part: per_node[[i for i, n in enumerate(names) if rule.search(n)]].sum(axis=0) / total
            for part, rule in PARTS.items()}


def mode_labels(modal: ModalResult, params: BridgeParameters = BridgeParameters()) -> tuple[str, ...]:
    """Whose mode each is, with its label: ``"deck lateral 1"``, ``"arches lateral 1"``, ...

    A mode the deck sensors see (:func:`deck_observation`: at least ``DECK_SHARE`` of its kinetic
    energy in the deck's vertical and transverse motion) is the deck's, numbered among those as
    Table 2 and ``bearingfw tune`` number them (``"deck lateral 1"`` is Table 2's ``"lateral 1"``);
    any other mode belongs to the part with the largest share of its kinetic energy
    (:func:`part_shares`) and is numbered among that part's modes of its label. The kernel's own
    labels (:attr:`~bearingfw.analysis.ModalResult.numbered_labels`) number all modes together:
    there the arches' sway at 0.94 Hz is "lateral 1" and the deck's is "lateral 2".
    """
    seen = observed_modes(modal, deck_observation(params))
    deck = {m: f"deck {label}" for label, m in seen.numbered.items()}
    shares = part_shares(modal)
    parts = list(shares)
    owner = np.argmax(np.array([shares[p] for p in parts]), axis=0)
    counts: dict[tuple[str, str], int] = {}
    out = []
    for m, label in enumerate(modal.labels):
        if m in deck:
            out.append(deck[m])
            continue
        key = (parts[owner[m]], label)
        counts[key] = counts.get(key, 0) + 1
        out.append(f"{key[0]} {label} {counts[key]}")
    return tuple(out)


def ks_estimate(
    params: BridgeParameters = BridgeParameters(), f_b: float = TABLE2_OMA["lateral 1"]
) -> tuple[float, float]:
    """Eq. (11) for this model: ``(K_s, f_a)`` with f_a the untuned model's first lateral frequency."""
    f_a = float(modes("M0", params, [("lateral 1", f_b)])[1].frequencies[0])
    return ks_eq11(params.pillar_stiffness, f_a, f_b), f_a


def calibrate_ks(
    params: BridgeParameters = BridgeParameters(),
    measured=None,
    initial: float | None = None,
    by: str = "label",
    n_modes: int = N_MODES,
    sensors=None,
) -> CalibrationReport:
    """Step 1: fit K_s of the M1 model to ``measured`` (default: Table 2's OMA column).

    Starts from ``initial`` (default: the eq. 11 estimate) within :data:`KS_BOUNDS`; the
    variable is named ``"ks"``. ``sensors``: the channels of measured shapes (``by="mac"``).
    """
    measured = paper_measurements() if measured is None else measured
    start = ks_estimate(params)[0] if initial is None else float(initial)
    return calibrate(
        lambda ks: reference_bridge("M1", ks=ks, params=params),
        measured,
        {"ks": (start, *KS_BOUNDS)},
        by=by,
        observation=deck_observation(params, sensors),
        n_modes=n_modes,
    )


#: The upper bound of K_s in step 1 as the paper did it (:func:`calibrate_ks_as_paper`): its least-squares value.
KS_PAPER_BOUND = KS_FIT


@attrs.frozen(eq=False)
class PaperKs:
    """Step 1 as the paper did it (:func:`calibrate_ks_as_paper`): the bounded fit, the unbounded one, the evidence."""

    bound: float
    constrained: CalibrationReport
    unconstrained: CalibrationReport
    source: str = KS_SOURCE

    @property
    def ks(self) -> float:
        """The K_s step 2 (and the default study) uses."""
        return self.constrained.values["ks"]

    @property
    def active(self) -> bool:
        """Whether the bound ends the fit (the unbounded least squares would go above it)."""
        return self.ks >= self.bound * (1 - 1e-9) and self.unconstrained.values["ks"] > self.bound

    def evidence(self) -> dict[str, Any]:
        """Each Table 2 mode's frequency at the bounded and the unbounded K_s, and the sum of squared errors."""
        names = [m.name for m in self.constrained.measurements]
        at = dict(zip(names, self.constrained.after.frequencies, strict=True))
        free = dict(zip(names, self.unconstrained.after.frequencies, strict=True))
        return {
            "frequencies_bounded": {n: float(at[n]) for n in names},
            "frequencies_unbounded": {n: float(free[n]) for n in names},
            "change": {n: float(free[n] / at[n] - 1.0) for n in names},
            "sum_squares_bounded": float(np.sum(self.constrained.errors_after ** 2)),
            "sum_squares_unbounded": float(np.sum(self.unconstrained.errors_after ** 2)),
        }

    def to_dict(self) -> dict[str, Any]:
        return {
            "ks": self.ks,
            "source": self.source,
            "kind": "upper bound",
            "bound": self.bound,
            "active": self.active,
            "ks_unbounded": self.unconstrained.values["ks"],
            "reason": ("the paper's least squares stopped at 400 MN/m because a stiffer K_s raised its first vertical "
                       "frequency too much (section 3.3); this model's first vertical frequency hardly moves with "
                       "K_s, so without the bound only the lateral mode decides the fit"),
            **self.evidence(),
        }


def calibrate_ks_as_paper(
    params: BridgeParameters = BridgeParameters(), bound: float = KS_PAPER_BOUND, initial: float | None = None
) -> PaperKs:
    """Step 1 as the paper did it: :func:`calibrate_ks` against Table 2 with K_s at most ``bound``, and without it.

    The paper's fit stopped at 400 MN/m: "raising the spring stiffness above this value led to an
    excessive increase of the first vertical frequency". That stop came from its model's first
    vertical mode, which this frame model does not have (it moves by about 0.1 % between 400 MN/m
    and the unbounded optimum; see the package docstring's fixed-bearing comparison), so it is made
    explicit here as an upper bound of the least squares. Both fits start from eq. 11 (within the
    bounds); :meth:`PaperKs.evidence` gives each mode at both values.
    """
    if not (isinstance(bound, (int, float)) and KS_BOUNDS[0] < bound <= KS_BOUNDS[1]):
        raise ParameterError(
            f"calibrate_ks_as_paper: 'bound' must be within ({KS_BOUNDS[0]:g}, {KS_BOUNDS[1]:g}] N/m, got {bound!r}")
    start = ks_estimate(params)[0] if initial is None else float(initial)
    unconstrained = calibrate_ks(params, initial=start)
    constrained = calibrate(
        lambda ks: reference_bridge("M1", ks=ks, params=params),
        paper_measurements(),
        {"ks": (min(start, bound), KS_BOUNDS[0], bound)},
        observation=deck_observation(params),
        n_modes=N_MODES,
    )
    return PaperKs(bound=float(bound), constrained=constrained, unconstrained=unconstrained)


def tuned_bridge(ks: float, params: BridgeParameters = BridgeParameters(), friction: float = FRICTION) -> Model:
    """Step 2: the M2 model, regularized Coulomb with stick stiffness ``ks`` and ``friction``."""
    return reference_bridge("M2", ks=ks, params=params, friction=friction)


def measured_damping(decrements=LOG_DECREMENTS, stated=DAMPING_RATIOS) -> dict:
    """Damping ratios from the measured ``(frequency, log decrement)`` pairs and Rayleigh through the first two.

    ``rayleigh`` uses the ratios computed from the decrements (2.07 % and 2.70 %);
    ``rayleigh_paper_ratios`` the ratios as the paper states them (``stated``: 2.1 % and 2.7 %),
    which give its alpha = 0.21 1/s and beta = 0.00208 s.
    """
    ratios = [(f, damping_ratio_from_log_decrement(d)) for f, d in decrements]

    def rayleigh(pairs):
        (f1, z1), (f2, z2) = pairs[:2]
        alpha, beta = rayleigh_from_ratios(f1, z1, f2, z2)
        return {"alpha": alpha, "beta": beta}

    return {
        "decrements": [{"frequency": f, "decrement": d} for f, d in decrements],
        "ratios": [{"frequency": f, "ratio": z} for f, z in ratios],
        "rayleigh": rayleigh(ratios),
        "rayleigh_paper_ratios": rayleigh(list(stated)),
    }


# -- step 1 with identified modes ------------------------------------------------------------------


@attrs.frozen
class IdentifiedTuning:
    """Options of :func:`calibrate_ks_to_identified` (module docstring)."""

    min_mac: float = parameter(
        low=0.0, high=1.0, default=MIN_MAC, doc="least MAC of an identified mode with its computed partner"
    )
    scan_points: int = integer_parameter(
        low=2, high=200, default=17, doc="log-spaced values of K_s over its bounds whose fit starts the least squares"
    )
    sensitivity_step: float = parameter(
        low=0.0, low_open=True, high=0.5, default=0.05, doc="relative step of d ln f / d ln K_s (central difference)"
    )


@attrs.frozen(eq=False)
class IdentifiedFit:
    """What :func:`calibrate_ks_to_identified` found; :meth:`to_dict` is ``bearingfw tune --measured --json``."""

    options: IdentifiedTuning
    sensors: tuple[str, ...]
    used: tuple[Measurement, ...]
    dropped: tuple[dict, ...]
    untuned: Pairing
    eq11: dict | None
    ks_eq11: float | None
    scan: tuple[tuple[float, float], ...]
    ks_start: float
    report: CalibrationReport
    sensitivity: np.ndarray
    damping: dict
    warnings: tuple[str, ...]
    metadata: Mapping[str, Any] = attrs.field(factory=dict)

    @property
    def ks(self) -> float:
        return self.report.values["ks"]

    def to_dict(self) -> dict[str, Any]:
        names = [m.name for m in self.used]

        def by_name(values):
            return {n: float(v) for n, v in zip(names, values, strict=True)}

        after = self.report.after
        return {
            "source": self.metadata.get("source"),
            "synthetic": bool(self.metadata.get("synthetic", False)),
            "sensors": list(self.sensors),
            "min_mac": self.options.min_mac,
            "dropped": [dict(d) for d in self.dropped],
            "warnings": list(self.warnings),
            "ks_eq11": self.ks_eq11,
            "ks_start": self.ks_start,
            "ks_fit": self.ks,
            "eq11": self.eq11,
            "scan": [{"ks": v, "cost": c if math.isfinite(c) else None} for v, c in self.scan],  # None: unpaired
            "measured": by_name(after.measured),
            "before": by_name(self.untuned.frequencies),
            "after": by_name(after.frequencies),
            "error_before": by_name(self.untuned.errors),
            "error_after": by_name(self.report.errors_after),
            "label_after": dict(zip(names, after.labels, strict=True)),
            "mac_after": by_name(after.mac),
            "sensitivity": by_name(self.sensitivity),
            "calibration": self.report.to_dict(),
            "damping": self.damping,
        }


def _identified_damping(damping: Mapping[str, float | None], used: Sequence[Measurement], report) -> dict:
    """The identified damping ratios, and Rayleigh through vertical 1 and 2 when both are paired (section 3.2)."""
    out: dict[str, Any] = {"identified": {m.name: damping.get(m.name) for m in used}}
    paired = dict(zip(report.after.labels, used, strict=True))
    if "vertical 1" in paired and "vertical 2" in paired:
        (f1, z1), (f2, z2) = ((paired[k].frequency, damping.get(paired[k].name)) for k in ("vertical 1", "vertical 2"))
        try:
            alpha, beta = rayleigh_from_ratios(f1, z1, f2, z2)
            out["rayleigh"] = {"alpha": alpha, "beta": beta, "through": ["vertical 1", "vertical 2"]}
        except ParameterError as exc:
            out["rayleigh"] = {"error": str(exc)}
    return out


def calibrate_ks_to_identified(
    identified,
    options: IdentifiedTuning = IdentifiedTuning(),
    select=None,
    params: BridgeParameters = BridgeParameters(),
) -> IdentifiedFit:
    """Step 1 with modes identified by ``bearingfw oma`` (:class:`~bearingfw.oma.IdentifiedModes`), module docstring.

    ``select``: mode names or 1-based numbers to use (default all). Raises
    :class:`~bearingfw.parameters.ParameterError` when no mode pairs with a computed one at
    ``options.min_mac`` or better, or the channels are not deck DOFs of the model.
    """
    measured = from_identified(identified).select(select, what="identified modes", kind="identified")
    observation = deck_observation(params, measured.channels)
    untuned_modal = solve_modal(reference_bridge("M0", params=params), N_MODES)
    # eq. 11 needs the measured first lateral mode: the identified mode that pairs with the untuned
    # model's (as the deck sensors see it) at the least MAC or better
    try:
        untuned_all = pair_modes(untuned_modal, measured.measurements, by="mac", observation=observation)
        lateral = [m for m, label, value in zip(measured.measurements, untuned_all.labels, untuned_all.mac, strict=True)
                   if label == "lateral 1" and value >= options.min_mac]
    except PairingError:  # more identified modes than the deck's computed ones: eq. 11 is skipped
        lateral = []
    if lateral:
        f_b = lateral[0].frequency
        f_a = float(untuned_modal.frequencies[observed_modes(untuned_modal, deck_observation(params)).numbered[
            "lateral 1"]])
        ks0 = ks_eq11(params.pillar_stiffness, f_a, f_b)
        eq11 = {"k_c": params.pillar_stiffness, "f_a": f_a, "f_b": f_b, "mode": lateral[0].name}
    else:  # no identified mode is the untuned model's first lateral one: the paper's value joins the scan
        ks0, eq11 = DEFAULT_KS, None
    fit = fit_parameters(
        lambda values: reference_bridge("M1", ks=values["ks"], params=params),
        measured,
        {"ks": (min(max(ks0, KS_BOUNDS[0]), KS_BOUNDS[1]), *KS_BOUNDS)},
        FitOptions(min_mac=options.min_mac, scan_points=options.scan_points,
                   sensitivity_step=options.sensitivity_step, n_modes=N_MODES),
        observation=observation,
        describe=lambda name: "K_s",
    )
    untuned = pair_modes(untuned_modal, fit.used, by="mac", observation=observation)
    at_start = (fit.start["ks"], float(np.sum(fit.before.errors**2)))
    scan = (*((values["ks"], cost) for values, cost in fit.scan), at_start)
    return IdentifiedFit(
        options=options,
        sensors=tuple(measured.channels),
        used=fit.used,
        dropped=fit.dropped,
        untuned=untuned,
        eq11=eq11,
        ks_eq11=ks0 if eq11 else None,
        scan=scan,
        ks_start=fit.scan_start["ks"],
        report=fit.report,
        sensitivity=fit.sensitivity[:, 0],
        damping=_identified_damping(fit.damping, fit.used, fit.report),
        warnings=fit.warnings,
        metadata={k: identified.metadata.get(k) for k in ("source", "synthetic")},
    )
