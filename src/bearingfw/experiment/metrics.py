"""What a cell records, and its reduction to time histories and peak metrics.

Recorded (every integration step): section forces of the response elements, every connector's
response, and the absolute acceleration of the deck nodes. Metrics are named
``<family>.<item>``; the families (:data:`FAMILIES`):

======================  =====  ==========================================================================
family                  unit   value
======================  =====  ==========================================================================
stress.<element>        Pa     peak maximum principal stress, total (dead load + tremor), over the
                               element's recovery points at both ends: what a design check compares
                               with the material's strength
stress_dynamic.<el.>    Pa     peak maximum principal stress of the tremor's own stress state: sigma1
                               of the section forces F(t) - F_dead (module notes). The family the
                               models are compared on (the paper's findings)
stress_increase.<el.>   Pa     peak rise of the total maximum principal stress above its dead-load
                               value at the same point: max over t and points of sigma1(F(t)) -
                               sigma1(F_dead), what one reads off a total stress history (module notes)
bearing_force.<b>       N      peak force magnitude in the bearing's sliding directions (PLANAR: x and
                               y; AXIAL: the guided one; NaN for JOIN, where nothing slides); with the
                               rigid ``fixed`` law it is the restraint force there
bearing_shear.<b>       N      peak horizontal force magnitude the bearing transmits, guide and tie
                               reactions included (a JOIN bearing's too)
bearing_displacement.   m      peak relative displacement in the sliding directions, from the dead-load
<b>                            position (the girder's movement on the bearing)
slip.<b>                m      peak magnitude of the irreversible slip the law reports (NaN when the
                               law keeps none: frictionless, springs, JOIN)
friction_ratio.<b>      -      maximum abs(F)/N in the sliding directions over the instants the bearing
                               is pressed with more than :data:`MIN_NORMAL_FRACTION` of its dead-load
                               N (NaN for JOIN and rigid laws, and if it never is)
deck_acceleration.<d>   m/s^2  peak absolute acceleration over the deck nodes in global d = x, y, z
======================  =====  ==========================================================================

Each metric keeps the time of its peak and where it occurred (element end and recovery point,
node). Metrics always use every integration step; ``[output] every`` only thins the saved
histories.

Dynamic stress. The paper compares "maximum principal stresses" of models M0, M1, M2 (its
figures 18, 20) and argues that the linear models' responses are "proportional to applied loads".
The stress tensor at a point is linear in the section forces, its maximum principal value is not:
``sigma1(F_dead + F_dyn)`` is not ``sigma1(F_dead) + sigma1(F_dyn)``. Of the two ways to take
the tremor's part, ``stress_dynamic`` = ``sigma1(F_dyn)`` is the maximum principal stress of a real
stress state (the tremor's, which adds to the dead load's tensor by superposition) and is
positively homogeneous in the response: a linear model's value scales exactly with the record,
so ratios between models do not depend on the intensity, as the paper states. ``stress_increase``
= ``sigma1(F) - sigma1(F_dead)`` is the change of one principal value, not a principal stress of
anything: it depends on how the dead-load stress is oriented (a point in dead-load compression
hardly rises until the tremor turns it into tension), is not proportional to the intensity even
for linear models, and can be negative. So model comparisons of "the peak maximum principal
stress" use ``stress_dynamic``; ``stress`` (the total) is the one for strength checks; and
``stress_increase`` is kept because it is what a total stress-time history plotted from the
dead-load level shows.

Friction ratio. ``abs(F)/N`` divides by the bearing's normal force, which the vertical motion
changes; as N approaches zero (a bearing about to lift off) the ratio grows without bound while
the force is tiny, and a peak taken there says nothing about friction. The ratio is therefore
defined only while N exceeds :data:`MIN_NORMAL_FRACTION` (10 %) of the bearing's dead-load
normal force (its value at the start, sample 0); elsewhere it is NaN, in the histories too.
"""

from __future__ import annotations

import math

import numpy as np

from bearingfw.analysis import (
    ConnectorResponse,
    ElementForces,
    NodalResponse,
    TransientResult,
    section_stresses,
)
from bearingfw.model import ConnectorKind, Model

__all__ = [
    "FAMILIES",
    "MIN_NORMAL_FRACTION",
    "NOTES",
    "STRESS_FAMILIES",
    "display_scale",
    "friction_ratio",
    "metric_family",
    "recorders",
    "reduce_result",
]

#: The friction ratio abs(F)/N counts only while N exceeds this fraction of the dead-load N (module notes).
MIN_NORMAL_FRACTION = 0.1

#: Metric families in display order: (unit, description).
FAMILIES = {
    "stress": ("Pa", "peak maximum principal stress, dead load + tremor"),
    "stress_dynamic": ("Pa", "peak maximum principal stress of the tremor's own stress state, sigma1(F - F_dead)"),
    "stress_increase": ("Pa", ("peak rise of the total maximum principal stress above its dead-load value, "
                               "sigma1(F) - sigma1(F_dead)")),
    "bearing_force": ("N", "peak force in the bearing's sliding directions"),
    "bearing_shear": ("N", "peak horizontal force transmitted (guides and ties included)"),
    "bearing_displacement": ("m", "peak relative displacement in the sliding directions"),
    "slip": ("m", "peak irreversible slip reported by the law"),
    "friction_ratio": ("-", (f"maximum abs(F)/N in the sliding directions while N > {MIN_NORMAL_FRACTION:.0%} "
                             "of its dead-load value")),
    "deck_acceleration": ("m/s^2", "peak absolute deck acceleration"),
}

#: Display units for tables and figures: unit -> (factor, label).
_DISPLAY = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm"), "m/s^2": (1.0, "m/s²"), "-": (1.0, "-")}

#: What the report says of the families whose definition is a choice (module notes).
NOTES = {
    "stress": "the total maximum principal stress (dead load + tremor), the one to compare with a strength",
    "stress_dynamic": (
        "sigma1 of the stress state of the tremor's own section forces F(t) - F_dead: a real stress state that adds "
        "to the dead load's by superposition, and proportional to the intensity for a linear model, so that ratios "
        "between models do not depend on the intensity (the paper's argument). The models are compared on it"
    ),
    "stress_increase": (
        "sigma1(F(t)) - sigma1(F_dead) at the same point: how far the total maximum principal stress rises above its "
        "dead-load value (what a total stress history plotted from the dead-load level shows); not a principal "
        "stress of any state, not proportional to the intensity, and at most stress_dynamic (sigma1 is subadditive)"
    ),
    "friction_ratio": (
        f"abs(F)/N only while the bearing is pressed with more than {MIN_NORMAL_FRACTION:.0%} of its dead-load normal "
        "force: near uplift the ratio grows without bound while the force is tiny (NaN there, in the histories too)"
    ),
}

#: The families whose items are response elements.
STRESS_FAMILIES = ("stress", "stress_dynamic", "stress_increase")

_SECTIONS, _BEARINGS, _DECK = "sections", "bearings", "deck"


def metric_family(metric: str) -> str:
    """``"stress_dynamic.S1"`` -> ``"stress_dynamic"``."""
    return metric.partition(".")[0]


def display_scale(metric: str) -> tuple[float, str]:
    """(factor, unit label) to show a metric's SI value in (MPa, kN, mm, ...)."""
    return _DISPLAY[FAMILIES[metric_family(metric)][0]]


def recorders(elements: tuple[str, ...], deck_nodes: tuple[str, ...], model: Model) -> list:
    """The recorders of a cell (every integration step)."""
    chosen = []
    if elements:
        chosen.append(ElementForces(elements, name=_SECTIONS))
    if model.connectors:
        chosen.append(ConnectorResponse(name=_BEARINGS))
    if deck_nodes:
        chosen.append(NodalResponse(deck_nodes, quantity="acceleration", total=True, name=_DECK))
    return chosen


def _peak(values: np.ndarray, time: np.ndarray) -> tuple[float, float | None, tuple | None]:
    """Largest value of ``values`` (time first axis), its time and index; NaN if all are NaN."""
    if values.size == 0 or np.all(np.isnan(values)):
        return math.nan, None, None
    k = np.unravel_index(int(np.nanargmax(values)), values.shape)
    return float(values[k]), float(time[k[0]]), tuple(int(i) for i in k)


def _entry(value: float, time: float | None, at: str | None) -> dict:
    return {"value": value, "time": time, "at": at}


def _stresses(result: TransientResult, model: Model, elements, histories: dict, metrics: dict) -> None:
    forces = result[_SECTIONS]  # (t, elements, 2 ends, 6); sample 0 is the dead-load state
    time = result[f"{_SECTIONS}.time"]
    for k, name in enumerate(elements):
        section = model.element(name).section
        total = section_stresses(forces[:, k], section)
        dynamic = section_stresses(forces[:, k] - forces[0, k], section)
        # sigma1 arrays: (t, 2 ends, points)
        for family, st, sigma1 in (("stress", total, total.sigma1), ("stress_dynamic", dynamic, dynamic.sigma1),
                                   ("stress_increase", total, total.sigma1 - total.sigma1[:1])):
            value, t, where = _peak(sigma1, time)
            at = None if where is None else f"end {'ij'[where[1]]}, point {st.points[where[2]]}"
            metrics[f"{family}.{name}"] = _entry(value, t, at)
            histories[f"{family}.{name}"] = sigma1.max(axis=(1, 2))


def _norm(values: np.ndarray, directions: tuple[int, ...]) -> np.ndarray:
    """Magnitude over the given local directions, (t,); NaN if there are none."""
    if not directions:
        return np.full(values.shape[0], np.nan)
    return np.sqrt(np.sum(values[:, list(directions)] ** 2, axis=1))


def friction_ratio(ratio: np.ndarray, normal_force: np.ndarray) -> np.ndarray:
    """``ratio`` (t, connectors) with NaN wherever the normal force (t, connectors) is not above
    :data:`MIN_NORMAL_FRACTION` of its dead-load value (sample 0), or the dead load presses nothing."""
    dead = normal_force[:1]
    counted = (dead > 0) & (normal_force > MIN_NORMAL_FRACTION * dead)
    return np.where(counted, ratio, np.nan)


def _bearings(result: TransientResult, model: Model, histories: dict, metrics: dict) -> None:
    time = result[f"{_BEARINGS}.time"]
    force = result[f"{_BEARINGS}.force"]
    moved = result[f"{_BEARINGS}.displacement"] - result[f"{_BEARINGS}.displacement"][:1]
    slip = result[f"{_BEARINGS}.slip"]
    ratio = friction_ratio(result[f"{_BEARINGS}.friction_ratio"], result[f"{_BEARINGS}.normal_force"])
    for c, connector in enumerate(model.connectors):
        sliding = connector.law_directions if connector.kind is not ConnectorKind.JOIN else ()
        series = {
            "bearing_force": _norm(force[:, c], sliding),
            "bearing_shear": _norm(force[:, c], (0, 1)),
            "bearing_displacement": _norm(moved[:, c], sliding),
            "slip": _norm(slip[:, c], sliding),
            "friction_ratio": ratio[:, c],
        }
        for family, values in series.items():
            value, t, _ = _peak(values, time)
            metrics[f"{family}.{connector.name}"] = _entry(value, t, None)
    for key in ("force", "displacement", "normal_force", "slip"):
        histories[f"bearings.{key}"] = result[f"{_BEARINGS}.{key}"]
    histories["bearings.friction_ratio"] = ratio


def _deck(result: TransientResult, deck_nodes, histories: dict, metrics: dict) -> None:
    time = result[f"{_DECK}.time"]
    acceleration = result[_DECK]  # (t, nodes, 3), absolute
    for d, direction in enumerate("xyz"):
        value, t, where = _peak(np.abs(acceleration[:, :, d]), time)
        metrics[f"deck_acceleration.{direction}"] = _entry(value, t, None if where is None else deck_nodes[where[1]])
    histories["deck.acceleration"] = acceleration


def reduce_result(
    result: TransientResult, model: Model, elements: tuple[str, ...], deck_nodes: tuple[str, ...]
) -> tuple[dict[str, np.ndarray], dict[str, dict]]:
    """``(histories, metrics)`` of a transient result recorded with :func:`recorders`.

    ``histories``: ``time``; ``stress.<e>``, ``stress_dynamic.<e>`` and ``stress_increase.<e>`` (the
    maximum over the element's points and ends at each instant, Pa); ``bearings.force``,
    ``.displacement``, ``.slip`` (t, connectors, 3 local directions), ``.normal_force``,
    ``.friction_ratio`` (t, connectors; NaN where it is not defined); ``deck.acceleration`` (t, nodes, 3). ``metrics``: ``{name: {"value", "time",
    "at"}}`` in family order (module docstring); NaN where a metric does not apply.
    """
    histories: dict[str, np.ndarray] = {"time": result.time}
    metrics: dict[str, dict] = {}
    if elements:
        _stresses(result, model, elements, histories, metrics)
        histories["time"] = result[f"{_SECTIONS}.time"]
    if model.connectors:
        _bearings(result, model, histories, metrics)
        histories["time"] = result[f"{_BEARINGS}.time"]
    if deck_nodes:
        _deck(result, deck_nodes, histories, metrics)
    order = {family: i for i, family in enumerate(FAMILIES)}
    ordered = sorted(metrics, key=lambda m: order[metric_family(m)])  # stable: items keep their order
    return histories, {m: metrics[m] for m in ordered}
