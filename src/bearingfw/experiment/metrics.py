"""What a cell records, and its reduction to time histories and peak metrics.

Recorded (every integration step): section forces of the response elements, every connector's
response, and the absolute acceleration of the deck nodes. Metrics are named
``<family>.<item>``; the families (:data:`FAMILIES`):

======================  =====  ==========================================================================
family                  unit   value
======================  =====  ==========================================================================
stress.<element>        Pa     peak maximum principal stress, total (dead load + tremor) as in the
                               paper's figures, over the element's recovery points at both ends
stress_dynamic.<el.>    Pa     the same for the tremor's part of the section forces alone (total minus
                               dead load): the dynamic stress the paper compares. Positively
                               homogeneous in the response, so a linear model's value scales exactly
                               with the record
bearing_force.<b>       N      peak force magnitude in the bearing's sliding directions (PLANAR: x and
                               y; AXIAL: the guided one; NaN for JOIN, where nothing slides); with the
                               rigid ``fixed`` law it is the restraint force there
bearing_shear.<b>       N      peak horizontal force magnitude the bearing transmits, guide and tie
                               reactions included (a JOIN bearing's too)
bearing_displacement.   m      peak relative displacement in the sliding directions, from the dead-load
<b>                            position (the girder's movement on the bearing)
slip.<b>                m      peak magnitude of the irreversible slip the law reports (NaN when the
                               law keeps none: frictionless, springs, JOIN)
friction_ratio.<b>      -      maximum abs(F)/N in the sliding directions (NaN for JOIN and rigid laws)
deck_acceleration.<d>   m/s^2  peak absolute acceleration over the deck nodes in global d = x, y, z
======================  =====  ==========================================================================

Each metric keeps the time of its peak and where it occurred (element end and recovery point,
node). Metrics always use every integration step; ``[output] every`` only thins the saved
histories.
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

__all__ = ["FAMILIES", "display_scale", "metric_family", "recorders", "reduce_result"]

#: Metric families in display order: (unit, description).
FAMILIES = {
    "stress": ("Pa", "peak maximum principal stress, dead load + tremor"),
    "stress_dynamic": ("Pa", "peak maximum principal stress of the tremor's section forces"),
    "bearing_force": ("N", "peak force in the bearing's sliding directions"),
    "bearing_shear": ("N", "peak horizontal force transmitted (guides and ties included)"),
    "bearing_displacement": ("m", "peak relative displacement in the sliding directions"),
    "slip": ("m", "peak irreversible slip reported by the law"),
    "friction_ratio": ("-", "maximum abs(F)/N in the sliding directions"),
    "deck_acceleration": ("m/s^2", "peak absolute deck acceleration"),
}

#: Display units for tables and figures: unit -> (factor, label).
_DISPLAY = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm"), "m/s^2": (1.0, "m/s²"), "-": (1.0, "-")}

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
    for family, dynamic in (("stress", False), ("stress_dynamic", True)):
        for k, name in enumerate(elements):
            section = model.element(name).section
            f = forces[:, k] - forces[0, k] if dynamic else forces[:, k]
            st = section_stresses(f, section)
            value, t, where = _peak(st.sigma1, time)
            at = None if where is None else f"end {'ij'[where[1]]}, point {st.points[where[2]]}"
            metrics[f"{family}.{name}"] = _entry(value, t, at)
            histories[f"{family}.{name}"] = st.sigma1.max(axis=(1, 2))


def _norm(values: np.ndarray, directions: tuple[int, ...]) -> np.ndarray:
    """Magnitude over the given local directions, (t,); NaN if there are none."""
    if not directions:
        return np.full(values.shape[0], np.nan)
    return np.sqrt(np.sum(values[:, list(directions)] ** 2, axis=1))


def _bearings(result: TransientResult, model: Model, histories: dict, metrics: dict) -> None:
    time = result[f"{_BEARINGS}.time"]
    force = result[f"{_BEARINGS}.force"]
    moved = result[f"{_BEARINGS}.displacement"] - result[f"{_BEARINGS}.displacement"][:1]
    slip = result[f"{_BEARINGS}.slip"]
    ratio = result[f"{_BEARINGS}.friction_ratio"]
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
    for key in ("force", "displacement", "normal_force", "slip", "friction_ratio"):
        histories[f"bearings.{key}"] = result[f"{_BEARINGS}.{key}"]


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

    ``histories``: ``time``; ``stress.<e>`` and ``stress_dynamic.<e>`` (the maximum over the
    element's points and ends at each instant, Pa); ``bearings.force``, ``.displacement``,
    ``.slip`` (t, connectors, 3 local directions), ``.normal_force``, ``.friction_ratio`` (t,
    connectors); ``deck.acceleration`` (t, nodes, 3). ``metrics``: ``{name: {"value", "time",
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
