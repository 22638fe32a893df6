"""Metric families: what a cell records, and how each family reduces the response to peak metrics.

A metric is named ``<family>.<item>``: the family says what is measured, the item where (a
response element, a connector, a direction). Each family is one :class:`MetricFamily` record:
its name, SI unit, a one-line description, which recorded response it reads (``reads``), which
items it has (``items``), the function that reduces a cell's response to one peak per item
(``reduce``), and its note in the report. The records drive everything after a cell is computed:
the metrics, the matrices, their units, the default table and the report. Families are
registered through the plugin hook ``bearingfw_register_metrics`` (the built-in ones below by
:mod:`bearingfw.experiment.builtin`), so a new metric is one module with a family and a
registration.

The built-in families (:data:`BUILTIN`):

======================  =====  ==========================================================================
family                  unit   value
======================  =====  ==========================================================================
stress.<element>        Pa     peak maximum principal stress, total (dead load + ground motion), over the
                               element's recovery points at both ends: what a design check compares
                               with the material's strength
stress_dynamic.<el.>    Pa     peak maximum principal stress of the ground motion's own stress state:
                               sigma1 of the section forces F(t) - F_dead (notes below); the family on
                               which models are compared
stress_increase.<el.>   Pa     peak rise of the total maximum principal stress above its dead-load
                               value at the same point: max over t and points of sigma1(F(t)) -
                               sigma1(F_dead), what one reads off a total stress history (notes below)
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

Under ground motion given per support (a record entry with ``spatial``,
:mod:`bearingfw.experiment.records`) a cell also records the support groups' motion
(:class:`~bearingfw.analysis.SupportResponse`) and :data:`SUPPORT_FAMILIES` measure it (cells of
uniform records have neither):

=========================  =====  =======================================================================
family                     unit   value
=========================  =====  =======================================================================
differential_displacement  m      peak over time and over every pair of support groups of the
.<d>                              difference of their ground displacements in global d = x, y, z (the
                                  pair and the time of the peak kept)
quasi_static_share.<b>     -      peak of the deformation the quasi-static support motion imposes on the
                                  bearing (``Psi delta``, the laws at their initial tangent) over the
                                  peak of its total displacement, both in the sliding directions:
                                  how much of the bearing's movement the differential support motion
                                  explains by itself (0 under uniform motion; NaN for JOIN)
=========================  =====  =======================================================================

Each metric keeps the time of its peak and where it occurred (element end and recovery point,
node). Metrics always use every integration step; ``[output] every`` only thins the saved
histories.

Dynamic stress. The stress tensor at a point is linear in the section forces, its maximum
principal value is not: ``sigma1(F_dead + F_dyn)`` is not ``sigma1(F_dead) + sigma1(F_dyn)``. Of
the two ways to take the ground motion's part, ``stress_dynamic`` = ``sigma1(F_dyn)`` is the
maximum principal stress of a real stress state (the motion's, which adds to the dead load's
tensor by superposition) and is positively homogeneous in the response: a linear model's value
scales exactly with the record, so ratios between models do not depend on the intensity.
``stress_increase`` = ``sigma1(F) - sigma1(F_dead)`` is the change of one principal value, not a
principal stress of anything: it depends on how the dead-load stress is oriented (a point in
dead-load compression hardly rises until the motion turns it into tension), is not proportional
to the intensity even for linear models, and can be negative. So model comparisons of "the peak
maximum principal stress" use ``stress_dynamic``; ``stress`` (the total) is the one for strength
checks; and ``stress_increase`` is kept because it is what a total stress-time history plotted
from the dead-load level shows.

Friction ratio. ``abs(F)/N`` divides by the bearing's normal force, which the vertical motion
changes; as N approaches zero (a bearing about to lift off) the ratio grows without bound while
the force is tiny, and a peak taken there says nothing about friction. The ratio is therefore
defined only while N exceeds :data:`MIN_NORMAL_FRACTION` (10 %) of the bearing's dead-load
normal force (its value at the start, sample 0); elsewhere it is NaN, in the histories too.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping

import attrs
import numpy as np

from bearingfw.analysis import (
    ConnectorResponse,
    ElementForces,
    NodalResponse,
    SupportResponse,
    TransientResult,
    section_stresses,
)
from bearingfw.model import ConnectorKind, Model
from bearingfw.plugins import Registry, get_registry

__all__ = [
    "BUILTIN",
    "DIRECTIONS",
    "MIN_NORMAL_FRACTION",
    "READS",
    "SUPPORTS",
    "SUPPORT_FAMILIES",
    "CellResponse",
    "MetricFamily",
    "Peak",
    "display_scale",
    "friction_ratio",
    "metric_families",
    "metric_family",
    "recorders",
    "reduce_result",
]

#: The friction ratio abs(F)/N counts only while N exceeds this fraction of the dead-load N (module notes).
MIN_NORMAL_FRACTION = 0.1
#: The items of a family over global directions.
DIRECTIONS = ("x", "y", "z")

#: The recorded responses a family can read (``MetricFamily.reads``) and the items each has.
SECTIONS, BEARINGS, DECK = "sections", "bearings", "deck"
READS = {
    SECTIONS: "section forces of the response elements ([structure] elements), every step; items: the elements",
    BEARINGS: "every connector's force, displacement, slip, normal force and friction ratio; items: the connectors",
    DECK: "absolute acceleration of the deck nodes ([structure] deck_nodes); items: the directions x, y, z",
}

#: The name of the support-motion recorder (cells with ground motion per support only). Not a key of
#: :data:`READS`: its families read it together with the bearings' response.
SUPPORTS = "supports"

#: Display units for tables and figures: SI unit -> (factor, label).
_DISPLAY = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm"), "m/s^2": (1.0, "m/s²"), "-": (1.0, "-")}


@attrs.frozen
class Peak:
    """One metric of one cell: its value (SI units, NaN where it does not apply), the time of the
    peak (s) and where it occurred; ``history``: the value's time history if the family keeps one."""

    value: float
    time: float | None = None
    at: str | None = None
    history: np.ndarray | None = attrs.field(default=None, eq=False, repr=False)

    def entry(self, unit: str) -> dict:
        """The metric as a cell's JSON document keeps it."""
        return {"value": self.value, "unit": unit, "time": self.time, "at": self.at}


@attrs.frozen
class MetricFamily:
    """A family of metrics ``<name>.<item>`` (module docstring).

    ``reads``: the recorded response it needs (a key of :data:`READS`); the family is measured in
    a cell only when the structure records it. ``reduce(response)``: a :class:`CellResponse` ->
    ``{item: Peak}`` for every item of the family. ``note``: what the report says of its
    definition (empty: nothing beyond ``description``). ``table``: shown in the default table.
    ``items``: the family's items when they are its own (e.g. the directions x, y, z of a ground
    motion), not those of the response it reads (None: the elements, connectors or directions of
    :data:`READS`); what ``[output] table`` may name.
    """

    name: str
    unit: str
    description: str
    reads: str = attrs.field(validator=attrs.validators.in_(tuple(READS)))
    reduce: Callable[[CellResponse], dict[str, Peak]] = attrs.field(repr=False)
    note: str = ""
    table: bool = True
    items: tuple[str, ...] | None = None

    @property
    def display(self) -> tuple[float, str]:
        """(factor, label) of the unit values are shown in (MPa, kN, mm, ...)."""
        return display_scale(self.unit)


def display_scale(unit: str) -> tuple[float, str]:
    """(factor, label) to show a value in SI ``unit`` in (Pa -> MPa, N -> kN, m -> mm, ...)."""
    return _DISPLAY.get(unit, (1.0, unit))


def metric_family(metric: str) -> str:
    """``"stress_dynamic.G4"`` -> ``"stress_dynamic"``."""
    return metric.partition(".")[0]


def metric_families(registry: Registry | None = None) -> dict[str, MetricFamily]:
    """The registered metric families by name, in registration order (default: the installed plugins)."""
    registry = registry or get_registry()
    return {name: entry.value for name, entry in registry.metrics.items()}


# ---- a cell's recorded response ------------------------------------------------------------------------
def recorders(elements: tuple[str, ...], deck_nodes: tuple[str, ...], model: Model) -> list:
    """The recorders of a cell (every integration step): what the families can read (:data:`READS`)."""
    chosen = []
    if elements:
        chosen.append(ElementForces(elements, name=SECTIONS))
    if model.connectors:
        chosen.append(ConnectorResponse(name=BEARINGS))
    if deck_nodes:
        chosen.append(NodalResponse(deck_nodes, quantity="acceleration", total=True, name=DECK))
    chosen.append(_PerSupportMotion())
    return chosen


@attrs.frozen
class _PerSupportMotion:
    """:class:`~bearingfw.analysis.SupportResponse` in a run whose ground motion is given per support;
    in a run of uniform motion (a plain array) it records nothing, so that such cells stay as they were."""

    name: str = SUPPORTS
    every: int = 1

    @property
    def label(self) -> str:
        return self.name

    def bind(self, ctx):
        if ctx.excitation.support is None:
            return _Idle(self.name)
        return SupportResponse(name=self.name).bind(ctx)


class _Idle:
    """A probe that keeps only the sample times it is asked for (the run needs them) and returns nothing."""

    every = 1

    def __init__(self, label: str):
        self.label = label
        self.times: list[float] = []

    def sample(self, snapshot) -> None:
        self.times.append(snapshot.t)

    def sample_many(self, samples) -> None:
        self.times.extend(samples.t.tolist())

    def finish(self) -> tuple[dict, dict]:
        return {}, {"kind": "support response", "recorded": False, "why": "uniform ground motion"}


def friction_ratio(ratio: np.ndarray, normal_force: np.ndarray) -> np.ndarray:
    """``ratio`` (t, connectors) with NaN wherever the normal force (t, connectors) is not above
    :data:`MIN_NORMAL_FRACTION` of its dead-load value (sample 0), or the dead load presses nothing."""
    dead = normal_force[:1]
    counted = (dead > 0) & (normal_force > MIN_NORMAL_FRACTION * dead)
    return np.where(counted, ratio, np.nan)


class CellResponse:
    """A cell's recorded response (:func:`recorders`), as the families read it.

    ``result`` is a :class:`~bearingfw.analysis.TransientResult` or any mapping with its keys
    (``sections``, ``sections.time``, ``bearings.<quantity>``, ``deck``, ...). What several
    families share (the stress states of an element, the masked friction ratio) is computed once.
    """

    def __init__(self, result: TransientResult | Mapping, model: Model, elements: tuple[str, ...] = (),
                 deck_nodes: tuple[str, ...] = ()):
        self.result = result
        self.model = model
        self.elements = tuple(elements)
        self.deck_nodes = tuple(deck_nodes)

    def records(self, reads: str) -> bool:
        """True if the response has what a family reading ``reads`` needs."""
        return {SECTIONS: bool(self.elements), BEARINGS: bool(self.model.connectors), DECK: bool(self.deck_nodes)}[reads]

    def time(self, reads: str) -> np.ndarray:
        return self.result[f"{reads}.time"]

    def __getitem__(self, key: str) -> np.ndarray:
        return self.result[key]

    @functools.cache  # noqa: B019 - one response object per cell; the cache dies with it
    def stress_states(self, element: str):
        """``(total, dynamic)`` :func:`~bearingfw.analysis.section_stresses` of ``element``: of the section
        forces F(t), and of F(t) - F_dead (sample 0 is the dead-load state); sigma1 arrays (t, 2 ends, points)."""
        k = self.elements.index(element)
        forces = self.result[SECTIONS][:, k]
        section = self.model.element(element).section
        return section_stresses(forces, section), section_stresses(forces - forces[0], section)

    @functools.cached_property
    def friction_ratio(self) -> np.ndarray:
        """abs(F)/N (t, connectors), NaN where the bearing is not pressed enough (module notes)."""
        return friction_ratio(self.result[f"{BEARINGS}.friction_ratio"], self.result[f"{BEARINGS}.normal_force"])

    @functools.cached_property
    def moved(self) -> np.ndarray:
        """Connector displacements from the dead-load position (t, connectors, 3)."""
        displacement = self.result[f"{BEARINGS}.displacement"]
        return displacement - displacement[:1]

    @functools.cached_property
    def per_support(self) -> bool:
        """True if the cell's ground motion was given per support (the support response is recorded)."""
        try:
            self.result[f"{SUPPORTS}.displacement"]
        except KeyError:
            return False
        return True

    @property
    def support_groups(self) -> list[str]:
        """The support groups' names in the order of ``supports.displacement`` (``G1``, ... if unknown)."""
        described = getattr(self.result, "recorders", {}).get(SUPPORTS, {})
        count = self.result[f"{SUPPORTS}.displacement"].shape[1]
        return list(described.get("groups") or [f"G{k + 1}" for k in range(count)])

    def histories(self) -> dict[str, np.ndarray]:
        """The raw response kept with a cell besides the families' own histories (module ``execute``):
        bearings.force, .displacement, .normal_force, .slip, .friction_ratio (masked); deck.acceleration;
        under ground motion per support, supports.displacement (t, groups, 3) and .quasi_static (t, c, 3;
        0 outside the laws' directions)."""
        out = {}
        if self.records(BEARINGS):
            for key in ("force", "displacement", "normal_force", "slip"):
                out[f"{BEARINGS}.{key}"] = self.result[f"{BEARINGS}.{key}"]
            out[f"{BEARINGS}.friction_ratio"] = self.friction_ratio
        if self.records(DECK):
            out[f"{DECK}.acceleration"] = self.result[DECK]
        if self.per_support:
            out[f"{SUPPORTS}.displacement"] = self.result[f"{SUPPORTS}.displacement"]
            # 0 outside the laws' directions (NaN in the recorder): nothing is imposed on a law there
            out[f"{SUPPORTS}.quasi_static"] = np.nan_to_num(self.result[f"{SUPPORTS}.quasi_static"], nan=0.0)
        return out

    @property
    def sample_time(self) -> np.ndarray:
        """The time of every kept sample (the recorders all record every step from the dead-load state)."""
        for reads in (BEARINGS, SECTIONS, DECK):
            if self.records(reads):
                return self.time(reads)
        return self.result.time


#: Values within this fraction of the peak count as reaching it, for the peak's time and place.
PLATEAU = 1e-12


def _peak(values: np.ndarray, time: np.ndarray) -> tuple[float, float | None, tuple | None]:
    """Largest value of ``values`` (time first axis), the first instant (and index) it is reached;
    NaN if all are NaN.

    "Reached" means within :data:`PLATEAU` of the peak: a force that saturates (a friction force at
    ``mu N``, a smooth hysteretic force at its yield level) stays at its peak over a plateau, where the
    largest sample is decided by round-off; its first instant is not."""
    if values.size == 0 or np.all(np.isnan(values)):
        return math.nan, None, None
    peak = float(np.nanmax(values))
    if math.isfinite(peak):
        with np.errstate(invalid="ignore"):  # NaN samples compare False: never the peak
            first = int(np.argmax(values >= peak - PLATEAU * abs(peak)))  # C order: the earliest instant
    else:
        first = int(np.nanargmax(values))
    k = np.unravel_index(first, values.shape)
    return peak, float(time[k[0]]), tuple(int(i) for i in k)


# ---- the built-in families' reductions -------------------------------------------------------------------
def _stress_family(pick: Callable) -> Callable[[CellResponse], dict[str, Peak]]:
    """A reduction over the response elements of ``pick(total, dynamic) -> (stress state, sigma1)``."""

    def reduce(response: CellResponse) -> dict[str, Peak]:
        time = response.time(SECTIONS)
        out = {}
        for name in response.elements:
            state, sigma1 = pick(*response.stress_states(name))
            value, t, where = _peak(sigma1, time)
            at = None if where is None else f"end {'ij'[where[1]]}, point {state.points[where[2]]}"
            out[name] = Peak(value, t, at, history=sigma1.max(axis=(1, 2)))
        return out

    return reduce


def _norm(values: np.ndarray, directions: tuple[int, ...]) -> np.ndarray:
    """Magnitude over the given local directions, (t,); NaN if there are none."""
    if not directions:
        return np.full(values.shape[0], np.nan)
    return np.sqrt(np.sum(values[:, list(directions)] ** 2, axis=1))


def _sliding(connector) -> tuple[int, ...]:
    return connector.law_directions if connector.kind is not ConnectorKind.JOIN else ()


def _bearing_family(series: Callable) -> Callable[[CellResponse], dict[str, Peak]]:
    """A reduction over every connector of ``series(response, c, connector) -> (t,) values``."""

    def reduce(response: CellResponse) -> dict[str, Peak]:
        time = response.time(BEARINGS)
        out = {}
        for c, connector in enumerate(response.model.connectors):
            value, t, _ = _peak(series(response, c, connector), time)
            out[connector.name] = Peak(value, t, None)
        return out

    return reduce


def _deck_acceleration(response: CellResponse) -> dict[str, Peak]:
    time = response.time(DECK)
    acceleration = response[DECK]  # (t, nodes, 3), absolute
    out = {}
    for d, direction in enumerate(DIRECTIONS):
        value, t, where = _peak(np.abs(acceleration[:, :, d]), time)
        out[direction] = Peak(value, t, None if where is None else response.deck_nodes[where[1]])
    return out


#: The built-in families, in display order (registered by :mod:`bearingfw.experiment.builtin`).
BUILTIN = (
    MetricFamily(
        "stress", "Pa", "peak maximum principal stress, dead load + ground motion", SECTIONS,
        _stress_family(lambda total, dynamic: (total, total.sigma1)),
        note="the total maximum principal stress (dead load + ground motion), the one to compare with a strength",
    ),
    MetricFamily(
        "stress_dynamic", "Pa",
        "peak maximum principal stress of the ground motion's own stress state, sigma1(F - F_dead)", SECTIONS,
        _stress_family(lambda total, dynamic: (dynamic, dynamic.sigma1)),
        note=("sigma1 of the stress state of the ground motion's own section forces F(t) - F_dead: a real stress "
              "state that adds to the dead load's by superposition, and proportional to the intensity for a linear "
              "model, so that ratios between models do not depend on the intensity. The models are compared on it"),
    ),
    MetricFamily(
        "stress_increase", "Pa",
        "peak rise of the total maximum principal stress above its dead-load value, sigma1(F) - sigma1(F_dead)",
        SECTIONS, _stress_family(lambda total, dynamic: (total, total.sigma1 - total.sigma1[:1])),
        note=("sigma1(F(t)) - sigma1(F_dead) at the same point: how far the total maximum principal stress rises "
              "above its dead-load value (what a total stress history plotted from the dead-load level shows); not a "
              "principal stress of any state, not proportional to the intensity, and at most stress_dynamic (sigma1 "
              "is subadditive)"),
        table=False,
    ),
    MetricFamily(
        "bearing_force", "N", "peak force in the bearing's sliding directions", BEARINGS,
        _bearing_family(lambda r, c, conn: _norm(r[f"{BEARINGS}.force"][:, c], _sliding(conn))),
    ),
    MetricFamily(
        "bearing_shear", "N", "peak horizontal force transmitted (guides and ties included)", BEARINGS,
        _bearing_family(lambda r, c, conn: _norm(r[f"{BEARINGS}.force"][:, c], (0, 1))), table=False,
    ),
    MetricFamily(
        "bearing_displacement", "m", "peak relative displacement in the sliding directions", BEARINGS,
        _bearing_family(lambda r, c, conn: _norm(r.moved[:, c], _sliding(conn))), table=False,
    ),
    MetricFamily(
        "slip", "m", "peak irreversible slip reported by the law", BEARINGS,
        _bearing_family(lambda r, c, conn: _norm(r[f"{BEARINGS}.slip"][:, c], _sliding(conn))),
    ),
    MetricFamily(
        "friction_ratio", "-",
        f"maximum abs(F)/N in the sliding directions while N > {MIN_NORMAL_FRACTION:.0%} of its dead-load value",
        BEARINGS, _bearing_family(lambda r, c, conn: r.friction_ratio[:, c]),
        note=(f"abs(F)/N only while the bearing is pressed with more than {MIN_NORMAL_FRACTION:.0%} of its dead-load "
              "normal force: near uplift the ratio grows without bound while the force is tiny (NaN there, in the "
              "histories too)"),
    ),
    MetricFamily(
        "deck_acceleration", "m/s^2", "peak absolute deck acceleration", DECK, _deck_acceleration,
    ),
)


def _differential_displacement(response: CellResponse) -> dict[str, Peak]:
    if not response.per_support:
        return {}
    time = response.time(SUPPORTS)
    displacement = response[f"{SUPPORTS}.displacement"]  # (t, groups, 3), relative to the reference group
    groups = response.support_groups
    first, second = np.triu_indices(len(groups), 1)
    out = {}
    for d, direction in enumerate(DIRECTIONS):
        if first.size == 0:  # one group: nothing moves differentially
            out[direction] = Peak(0.0, None, None, history=np.zeros(time.size))
            continue
        apart = np.abs(displacement[:, first, d] - displacement[:, second, d])  # (t, pairs)
        value, t, where = _peak(apart, time)
        if value == 0.0:  # no differential motion in this direction: no pair or time to name
            out[direction] = Peak(0.0, None, None, history=apart.max(axis=1))
            continue
        at = None if where is None else f"{groups[first[where[1]]]}-{groups[second[where[1]]]}"
        out[direction] = Peak(value, t, at, history=apart.max(axis=1))
    return out


def _quasi_static_share(response: CellResponse) -> dict[str, Peak]:
    if not response.per_support:
        return {}
    time = response.time(SUPPORTS)
    imposed = response[f"{SUPPORTS}.quasi_static"]  # (t, c, 3), NaN outside the laws' directions
    out = {}
    for c, connector in enumerate(response.model.connectors):
        directions = _sliding(connector)
        quasi, t, _ = _peak(_norm(np.nan_to_num(imposed[:, c]), directions), time)
        total, _, _ = _peak(_norm(response.moved[:, c], directions), response.time(BEARINGS))
        share = quasi / total if math.isfinite(quasi) and math.isfinite(total) and total > 0 else math.nan
        out[connector.name] = Peak(share, t if math.isfinite(share) else None, None)
    return out


#: The families of ground motion per support (module docstring), registered with :data:`BUILTIN`.
SUPPORT_FAMILIES = (
    MetricFamily(
        "differential_displacement", "m",
        "peak differential ground displacement between two support groups in global x, y, z", BEARINGS,
        _differential_displacement,
        items=DIRECTIONS,
        note=("the largest difference of two support groups' ground displacements over time and every pair of groups "
              "(the pair and time in cells.csv); measured in cells whose ground motion is given per support "
              "([records.<name>.spatial]) only"),
        table=False,
    ),
    MetricFamily(
        "quasi_static_share", "-",
        "peak bearing deformation imposed by the quasi-static support motion over the peak bearing displacement",
        BEARINGS, _quasi_static_share,
        note=("peak of the deformation Psi delta(t) the differential support motion imposes quasi-statically (laws at "
              "their initial tangent) over the peak of the bearing's displacement from its dead-load position, both "
              "in the sliding directions; cells with ground motion per support only"),
        table=False,
    ),
)


def reduce_result(
    result: TransientResult | Mapping, model: Model, elements: tuple[str, ...], deck_nodes: tuple[str, ...],
    families: Mapping[str, MetricFamily] | None = None,
) -> tuple[dict[str, np.ndarray], dict[str, dict]]:
    """``(histories, metrics)`` of a transient result recorded with :func:`recorders`.

    ``families``: the metric families to measure (default: the registered ones), each where the
    structure records what it reads. ``histories``: ``time``; each family's own histories
    (``stress.<e>``, ... the maximum over the element's points and ends at each instant, Pa);
    :meth:`CellResponse.histories`. ``metrics``: ``{name: {"value", "unit", "time", "at"}}``
    in family order, items in their order; NaN where a metric does not apply.
    """
    families = metric_families() if families is None else families
    response = CellResponse(result, model, elements, deck_nodes)
    histories: dict[str, np.ndarray] = {"time": response.sample_time}
    metrics: dict[str, dict] = {}
    for family in families.values():
        if not response.records(family.reads):
            continue
        for item, peak in family.reduce(response).items():
            metrics[f"{family.name}.{item}"] = peak.entry(family.unit)
            if peak.history is not None:
                histories[f"{family.name}.{item}"] = peak.history
    histories.update(response.histories())
    return histories, metrics
