"""Models and test laws shared by the kernel tests (imported by the test modules)."""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

import bearingfw
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

STEEL = Material("steel", 210e9, density=7850.0, nu=0.3)
# A rectangle 0.3 (local y) x 0.5 (local z): Iy != Iz separates the two bending planes (and
# Avy != Avz the two shear areas).
RECT = Section("rect", A=0.15, Iy=0.3 * 0.5**3 / 12, Iz=0.5 * 0.3**3 / 12, J=2.82e-3, Avy=0.125, Avz=0.11)


def cantilever_model(
    n: int = 20,
    L: float = 10.0,
    section: Section = RECT,
    material: Material = STEEL,
    mass: str = "consistent",
    support: str = "cantilever",
    **element_options,
) -> Model:
    """A straight member along x from N0 to N{n}; clamped at N0 or simply supported (forks)."""
    nodes = [Node(f"N{k}", L * k / n, 0.0, 0.0) for k in range(n + 1)]
    elements = [
        FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", section, material, mass=mass, **element_options) for k in range(n)
    ]
    if support == "cantilever":
        supports = [Support("N0")]
    else:  # simply supported in both planes with fork supports (twist restrained at both ends)
        supports = [Support("N0", ("ux", "uy", "uz", "rx")), Support(f"N{n}", ("uy", "uz", "rx"))]
    return Model(nodes, elements, supports=supports)


# --- the paper's figure-15 SDOF frame --------------------------------------------------------
# Two columns (cantilevers fixed at the base, top pinned to the deck: K_c = 3 E I / h^3 each,
# as in the paper's eq. 7), a rigid deck of mass m in the transverse (y) plane, on a JOIN
# connector over the left column and a sliding connector over the right one. The paper's
# values: K_c = 147 MN/m, pillars 5.9 m high and 1.4 m square; m is chosen so that f_a = 1.87 Hz.
SDOF_H = 5.9
SDOF_B = 10.0
SDOF_KC = 147e6
SDOF_I = 1.4**4 / 12
SDOF_E = SDOF_KC * SDOF_H**3 / (3 * SDOF_I)
SDOF_M = SDOF_KC / (2 * np.pi * 1.87) ** 2


def sdof_frame_model(
    law: str = "frictionless",
    params: dict | None = None,
    kind: str = "planar",
    n_elements: int = 4,
    vertical_stiffness: float = 1e10,
) -> Model:
    column = Section("pillar", A=1.96, Iy=SDOF_I, Iz=SDOF_I, J=0.2)
    concrete = Material("massless concrete", SDOF_E, density=0.0)
    nodes = [Node("BL", 0.0, 0.0, 0.0), Node("BR", 0.0, SDOF_B, 0.0)]
    elements = []
    for side, y in (("L", 0.0), ("R", SDOF_B)):
        prev = f"B{side}"
        for k in range(1, n_elements + 1):
            nodes.append(Node(f"C{side}{k}", 0.0, y, SDOF_H * k / n_elements))
            elements.append(FrameElement(f"col{side}{k}", prev, f"C{side}{k}", column, concrete))
            prev = f"C{side}{k}"
    nodes += [Node("DL", 0.0, 0.0, SDOF_H), Node("DR", 0.0, SDOF_B, SDOF_H)]
    sliding = dict(law=law, law_params=params or {}, vertical_stiffness=vertical_stiffness)
    if kind == "axial":
        sliding["guided"] = "y"
    connectors = [
        Connector("pinned", f"CL{n_elements}", "DL", "join"),
        Connector("sliding", f"CR{n_elements}", "DR", kind, **sliding),
    ]
    # The deck translates as a rigid body in the frame's plane (figure 15): a rigid link
    # carries it from DL to DR, and DL's out-of-plane translation and rotations are held.
    return Model(
        nodes,
        elements,
        connectors,
        rigid_links=[RigidLink("deck", "DL", "DR")],
        supports=[Support("BL"), Support("BR"), Support("DL", ("ux", "rx", "ry", "rz"))],
        masses=[NodalMass("DL", SDOF_M)],
    )


# --- a registry with a law from a test plugin -------------------------------------------------
@attrs.frozen
class DoubledSpring:
    """A test-only law: F = 2 k u (a plain attrs class, no bearingfw base)."""

    name: ClassVar[str] = "test-doubled-spring"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        tangent = np.broadcast_to(2 * self.k * np.eye(self.dims), (u.shape[0], self.dims, self.dims)).copy()
        return bearingfw.LawResponse(2 * self.k * u, tangent, state)


class GuidedOnly:
    """A test-only 1-D law whose dims is a class attribute (not a parameter): F = k u."""

    name = "test-guided-only"
    rigid = False
    dims = 1

    def __init__(self, k: float):
        self.k = float(k)

    def initial_state(self, n):
        return None

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        return bearingfw.LawResponse(self.k * u, np.full((u.shape[0], 1, 1), self.k), state)


@attrs.frozen
class NormalSpring:
    """A test-only law whose stiffness is proportional to the normal force: F = c N u."""

    name: ClassVar[str] = "test-normal-spring"
    rigid: ClassVar[bool] = False
    c: float = bearingfw.parameter(low=0.0, low_open=True, unit="1/m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        k = self.c * np.asarray(normal_force, dtype=float)
        tangent = k[:, None, None] * np.eye(self.dims)[None]
        return bearingfw.LawResponse(k[:, None] * u, tangent, state)


class FreeSliding2D:
    """A test-only law without parameters: zero force in two directions."""

    name = "test-free-2d"
    rigid = False
    dims = 2

    def initial_state(self, n):
        return ()

    def respond(self, state, u, normal_force, dt):
        n = np.shape(u)[0]
        return bearingfw.LawResponse(np.zeros((n, 2)), np.zeros((n, 2, 2)), state)


# --- a small twin-girder deck on bearings ------------------------------------------------------
CONCRETE = Material("C40/50", 35e9, density=2500.0, nu=0.2)
GIRDER = Section.rectangle("girder", 1.0, 1.6)
CROSSBEAM = Section.rectangle("crossbeam", 0.4, 1.0)
PIER = Section.rectangle("pier", 1.4, 1.4)
DECK_SPAN = 20.0
DECK_HALF_WIDTH = 2.5
DECK_OFFSET = 0.8  # girder axis to bearing soffit (rigid offset)
PIER_HEIGHT = 6.0


def deck_model(
    law: str = "frictionless",
    params: dict | None = None,
    per_span: int = 4,
    added_mass: float = 1500.0,
    vertical_stiffness: float = 5e9,
) -> Model:
    """Two girders (A at y < 0, B at y > 0) over two spans, crossbeams at every girder node pair.

    Axes 1 and 3 (x = 0, 40 m) sit on supported abutment nodes, axis 2 on two piers. Bearings
    at the soffit, joined to the girder axis by rigid links: axis 2 A fixed (JOIN), 2 B guided
    transversally (AXIAL along y); axes 1 and 3: A guided longitudinally (AXIAL along x), B
    multidirectional (PLANAR). Sliding bearings use ``law``.
    """
    params = params or {}
    nodes, elements, links, connectors, supports = [], [], [], [], []
    n = 2 * per_span
    for side, y in (("A", -DECK_HALF_WIDTH), ("B", DECK_HALF_WIDTH)):
        for k in range(n + 1):
            nodes.append(Node(f"G{side}{k}", DECK_SPAN * k / per_span, y, 0.0))
        for k in range(n):
            elements.append(
                FrameElement(f"G{side}{k}", f"G{side}{k}", f"G{side}{k + 1}", GIRDER, CONCRETE, added_mass=added_mass)
            )
    for k in range(n + 1):
        elements.append(FrameElement(f"X{k}", f"GA{k}", f"GB{k}", CROSSBEAM, CONCRETE))
    axes = {1: 0, 2: per_span, 3: n}
    for axis, k in axes.items():
        for side, y in (("A", -DECK_HALF_WIDTH), ("B", DECK_HALF_WIDTH)):
            x = DECK_SPAN * k / per_span
            soffit, top = f"S{axis}{side}", f"P{axis}{side}"
            nodes += [Node(soffit, x, y, -DECK_OFFSET), Node(top, x, y, -DECK_OFFSET)]
            links.append(RigidLink(f"L{axis}{side}", f"G{side}{k}", soffit))
            if axis == 2:
                base = f"F{axis}{side}"
                nodes.append(Node(base, x, y, -DECK_OFFSET - PIER_HEIGHT))
                elements.append(FrameElement(f"pier{axis}{side}", base, top, PIER, CONCRETE))
                supports.append(Support(base))
            else:
                supports.append(Support(top))
            name = f"{axis}{side}"
            sliding = dict(law=law, law_params=params, vertical_stiffness=vertical_stiffness)
            if axis == 2 and side == "A":
                connectors.append(Connector(name, top, soffit, "join"))
            elif axis == 2:
                connectors.append(Connector(name, top, soffit, "axial", guided="y", **sliding))
            elif side == "A":
                connectors.append(Connector(name, top, soffit, "axial", guided="x", **sliding))
            else:
                connectors.append(Connector(name, top, soffit, "planar", **sliding))
    masses = [NodalMass(f"G{s}{per_span}", 4000.0) for s in "AB"]  # e.g. a lamp post at mid-length
    return Model(nodes, elements, connectors, links, supports, masses)
