"""A parametric multi-span bridge frame on bearings, described once in bearingfw.

Used by the model validation (``validation/models.py``) and by the OpenSees benchmark
(``benchmarks/opensees.py``); OpenSees gets the same model through ``_translate.build``.

The deck: ``lines`` continuous girders along x (frame elements, ``per_span`` per span), joined by
crossbeams at every girder node. Axes ``0 .. spans`` sit at the span ends: the two end axes on
abutments (a fully supported node under each bearing), the inner axes on one pier per girder
(``pier_elements`` frame elements, clamped at the base). One bearing per girder and axis, named
``B<axis>.<line>``, on the pier top or abutment node, joined to the girder directly or, with
``offset > 0``, through a rigid link down to a soffit node ``offset`` below the girder axis (the
eccentricity that makes restrained bearings stiffen the vertical modes).

Bearing layout (as on the paper's bridge): at the middle axis girder 0's bearing is fixed (JOIN)
and the others are guided transversally (AXIAL along y); at every other axis girder 0's bearing
is guided longitudinally (AXIAL along x) and the others slide freely (PLANAR). Sliding bearings
take ``law`` with ``params``.
"""

from __future__ import annotations

import itertools

import attrs
import numpy as np

from bearingfw.model import (
    Connector,
    FrameElement,
    Material,
    Model,
    NodalMass,
    Node,
    RigidLink,
    Section,
    Support,
)

__all__ = ["Frame", "frame_model", "response_nodes", "sliding_bearings"]

CONCRETE = Material("C40/50", 35e9, density=2500.0, nu=0.2)
GIRDER = Section.rectangle("girder", 1.0, 1.6)
CROSSBEAM = Section.rectangle("crossbeam", 0.4, 1.0)
PIER = Section.rectangle("pier", 1.4, 1.4)


@attrs.frozen
class Frame:
    """The parameters of :func:`frame_model` (SI units)."""

    spans: tuple[float, ...] = (20.0, 30.0, 20.0)
    per_span: int = 6
    lines: int = 2
    line_spacing: float = 5.0
    pier_height: float = 6.0
    pier_elements: int = 3
    offset: float = 0.0
    added_mass: float = 2000.0  # kg/m on each girder: deck slab and finishes
    vertical_stiffness: float = 5e9
    law: str = "regularized-coulomb"
    params: tuple = (("k", 4e8), ("mu", 0.04))
    lamp_mass: float = 5000.0  # a nodal mass at each mid-span of girder 0

    @property
    def axes(self) -> int:
        return len(self.spans) + 1


def _girder_x(frame: Frame) -> np.ndarray:
    """x of every girder node, span by span (the axes are at the span ends)."""
    ends = np.concatenate([[0.0], np.cumsum(frame.spans)])
    pieces = [np.linspace(a, b, frame.per_span + 1)[:-1] for a, b in itertools.pairwise(ends)]
    return np.concatenate([*pieces, ends[-1:]])


def _bearing(frame: Frame, axis: int, line: int, top: str, girder_side: str) -> Connector:
    name = f"B{axis}.{line}"
    middle = frame.axes // 2
    sliding = {"law": frame.law, "law_params": dict(frame.params), "vertical_stiffness": frame.vertical_stiffness}
    if axis == middle:
        if line == 0:
            return Connector(name, top, girder_side, "join")
        return Connector(name, top, girder_side, "axial", guided="y", **sliding)
    if line == 0:
        return Connector(name, top, girder_side, "axial", guided="x", **sliding)
    return Connector(name, top, girder_side, "planar", **sliding)


def frame_model(frame: Frame = Frame()) -> Model:
    """The model (module docstring)."""
    xs = _girder_x(frame)
    axis_nodes = [k * frame.per_span for k in range(frame.axes)]
    nodes, elements, links, connectors, supports, masses = [], [], [], [], [], []
    for line in range(frame.lines):
        y = line * frame.line_spacing
        for k, x in enumerate(xs):
            nodes.append(Node(f"G{line}_{k}", x, y, 0.0))
            if k:
                elements.append(
                    FrameElement(f"G{line}_{k}", f"G{line}_{k - 1}", f"G{line}_{k}", GIRDER, CONCRETE,
                                 added_mass=frame.added_mass)
                )  # fmt: skip
            if line:
                elements.append(FrameElement(f"X{line}_{k}", f"G{line - 1}_{k}", f"G{line}_{k}", CROSSBEAM, CONCRETE))
        for axis, k in enumerate(axis_nodes):
            x, z = xs[k], -frame.offset
            girder_side = f"G{line}_{k}"
            if frame.offset > 0:
                girder_side = f"S{axis}.{line}"
                nodes.append(Node(girder_side, x, y, z))
                links.append(RigidLink(f"L{axis}.{line}", f"G{line}_{k}", girder_side))
            top = f"P{axis}.{line}_{frame.pier_elements}"
            if axis in (0, frame.axes - 1):  # abutment: a supported node under the bearing
                top = f"A{axis}.{line}"
                nodes.append(Node(top, x, y, z))
                supports.append(Support(top))
            else:
                for j in range(frame.pier_elements + 1):
                    height = frame.pier_height * (1 - j / frame.pier_elements)  # below the bearing
                    nodes.append(Node(f"P{axis}.{line}_{j}", x, y, z - height))
                    if j:
                        elements.append(
                            FrameElement(f"P{axis}.{line}_{j}", f"P{axis}.{line}_{j - 1}", f"P{axis}.{line}_{j}", PIER,
                                         CONCRETE)
                        )  # fmt: skip
                supports.append(Support(f"P{axis}.{line}_0"))
            connectors.append(_bearing(frame, axis, line, top, girder_side))
    if frame.lamp_mass:
        for s in range(len(frame.spans)):
            masses.append(NodalMass(f"G0_{s * frame.per_span + frame.per_span // 2}", frame.lamp_mass))
    name = f"{len(frame.spans)}-span frame, {frame.lines} girders, {frame.per_span} elements per span"
    return Model(nodes, elements, connectors, links, supports, masses, name=name)


def response_nodes(frame: Frame) -> list[str]:
    """Girder nodes at every mid-span of the first and last girder."""
    mids = [s * frame.per_span + frame.per_span // 2 for s in range(len(frame.spans))]
    return [f"G{line}_{k}" for line in sorted({0, frame.lines - 1}) for k in mids]


def sliding_bearings(model: Model) -> list[str]:
    """The connectors a law governs (not JOIN)."""
    return [c.name for c in model.connectors if c.law_directions]
