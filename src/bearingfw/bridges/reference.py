"""The geometry of the reference bridge as a :class:`~bearingfw.model.Model`, bearing laws given.

Members and names (``k`` is the girder station, ``x = k * element_length``):

- girders A and B: a frame element per station interval (``GA<k>``, ``GB<k>``), T-sections of
  web plus half slab, E from eq. (1), superimposed dead load as added mass;
- deck cross-section: at every station girder B's node follows girder A's as a rigid body
  (rigid link ``X<k>``): the slab and the crossbars keep the deck's cross-section from
  distorting, in its plane (the slab's shear) and across it (the crossbars), so the two girders
  act as one deck in lateral bending and in torsion; the crossbars' own mass is lumped on the
  girder nodes (half on each) every ``crossbar_spacing``;
- pillars: ``pillar_elements`` frame elements per pillar (``P<bearing>.<i>``, nodes
  ``P<bearing>.0`` at the clamped base up to the bearing);
- arches: parabolic, one above each girder, a frame element per station of the arch span
  (``RA<k>``, ``RB<k>``), hinged (or clamped) at the springings; wind bracing: struts ``T<k>`` about the
  crown and steel X-diagonals ``DA<k>`` / ``DB<k>`` (truss bars) between consecutive struts;
- hangers: vertical truss bars from the girder axis up to the arch (``HA<j>``, ``HB<j>``,
  ``j = 1..hangers_per_arch``);
- bearings: connectors ``1A`` .. ``6B`` (:mod:`bearingfw.bridges.layout`) at the sliding
  surface, joined to the girder axis by rigid links ``L<bearing>`` (the soffit eccentricity plus
  the bearing height), on the pillar tops (axes 2-5) or on supported abutment nodes (axes 1, 6);
  the sliding bearings' vertical springs are compression-only when
  :attr:`~bearingfw.bridges.BridgeParameters.uplift` is set (the fixed bearing 4A, and any bearing
  a preset fixes, is a JOIN, which cannot lift).

Response elements (the paper's figure 17 is missing; these are the choices): ``S1`` is the
girder-A element that starts at the middle of the arch span, ``S2`` the girder-B element there;
``2A``..``5A`` and ``2B``..``5B`` are the girder elements that start over the bearing of that
axis and girder (their end i is over the bearing). All girder elements have recovery points
at the soffit (centre and corners) and at the slab top (centre and edges).
"""

from __future__ import annotations

from collections.abc import Mapping

import attrs
import numpy as np

from bearingfw.bridges.layout import BEARINGS, PILLAR_AXES, SIDES
from bearingfw.bridges.parameters import BridgeParameters
from bearingfw.bridges.sections import arch_section, girder_geometry, girder_section
from bearingfw.model import (
    Connector,
    ConnectorKind,
    FrameElement,
    Material,
    Model,
    ModelError,
    NodalMass,
    Node,
    RigidLink,
    Section,
    Support,
    TrussElement,
)

__all__ = [
    "DECK_COMPONENTS",
    "DECK_SHARE",
    "RESPONSE_ELEMENTS",
    "Grid",
    "bearing_offset",
    "bridge_model",
    "deck_nodes",
    "grid",
]

#: The paper's response elements (figure 17), in its order.
RESPONSE_ELEMENTS = ("S1", "S2", "2A", "3A", "4A", "5A", "2B", "3B", "4B", "5B")
#: What the paper's sensors saw (section 2.3, figure 11): the deck's vertical and transverse motion
#: (the vertical and the horizontal CMIF). Its modes are the deck's.
DECK_COMPONENTS = ("uy", "uz")
#: A computed mode counts as one of the deck's (one those sensors would identify) when at least
#: this share of its kinetic energy is in the deck's vertical and transverse motion. The arches'
#: own modes have a few per cent there; the deck's from about 25 % (the first vertical mode, in
#: which the arches swing with the deck) to nearly all.
DECK_SHARE = 0.2

_TOL = 1e-6  # station coincidence (m)
#: Restrained DOFs of an arch springing: a hinge about the transverse axis (in-plane rotation free),
#: or clamped.
SPRINGING_DOFS = {"hinged": ("ux", "uy", "uz", "rx", "rz"), "clamped": ("ux", "uy", "uz", "rx", "ry", "rz")}


@attrs.frozen
class Grid:
    """Girder stations: count, the stations of the axes, hangers, crossbars and bracing struts."""

    n: int
    step: float
    axes: tuple[int, ...]
    hangers: tuple[int, ...]
    crossbars: tuple[int, ...]
    struts: tuple[int, ...]

    @property
    def x(self) -> np.ndarray:
        return self.step * np.arange(self.n + 1)

    @property
    def arch(self) -> range:
        """Stations of the arch span, springings included."""
        return range(self.axes[2], self.axes[3] + 1)

    @property
    def middle(self) -> int:
        """The station at the middle of the arch span."""
        return (self.axes[2] + self.axes[3]) // 2


def _station(x: float, step: float, what: str) -> int:
    k = round(x / step)
    if abs(k * step - x) > _TOL:
        raise ModelError(
            f"BridgeParameters: {what} at x = {x:g} m does not fall on a girder node; choose an 'element_length' "
            f"(now {step:g} m) that divides it"
        )
    return int(k)


def grid(p: BridgeParameters) -> Grid:
    """The stations of ``p``'s girders (errors name what falls between nodes)."""
    step = p.element_length
    axes = tuple(_station(x, step, f"axis {i + 1}") for i, x in enumerate(p.axis_positions))
    if (axes[3] - axes[2]) % 2:
        raise ModelError("BridgeParameters: the arch span needs an even number of elements (a node at its middle)")
    x3, x4 = p.axis_positions[2], p.axis_positions[3]
    spacing = (x4 - x3) / (p.hangers_per_arch + 1)
    hangers = tuple(_station(x3 + j * spacing, step, f"hanger {j}") for j in range(1, p.hangers_per_arch + 1))
    # struts at the crown and every hanger spacing either side (an even count straddles the crown)
    struts = tuple(
        _station((x3 + x4) / 2 + (j - (p.bracing_struts - 1) / 2) * spacing, step, f"strut {j + 1}")
        for j in range(p.bracing_struts)
    )
    n = axes[-1]
    every = p.crossbar_spacing / step
    crossbars = {k for k in range(n + 1) if abs(k / every - round(k / every)) * step < _TOL} | set(axes)
    if not all(axes[2] < k < axes[3] for k in struts):
        raise ModelError("BridgeParameters: field 'bracing_struts' places struts beyond the arch springings")
    return Grid(n, step, axes, hangers, tuple(sorted(crossbars)), struts)


def bearing_offset(p: BridgeParameters) -> float:
    """Girder axis to the bearings' sliding surface (m): centroid height plus ``bearing_height``."""
    return girder_geometry(p).centroid + p.bearing_height


def deck_nodes(p: BridgeParameters) -> tuple[str, ...]:
    """The girder nodes of both girders: the deck, where the paper's sensors were."""
    n = grid(p).n
    return tuple(f"G{side}{k}" for side in SIDES for k in range(n + 1))


def _girder_element(side: str, k: int, g: Grid) -> str:
    if k == g.middle:
        return "S1" if side == "A" else "S2"
    if k in g.axes[1:5]:
        return f"{g.axes.index(k) + 1}{side}"
    return f"G{side}{k}"


def _materials(p: BridgeParameters, girder_area: float) -> dict[str, Material]:
    e_girder = Material.composite_modulus(p.girder_concrete_modulus, girder_area, p.tendon_modulus, p.tendon_area)
    rho, nu = p.concrete_density, p.concrete_poisson
    return {
        "girder": Material("C40/50 prestressed (eq. 1)", e_girder, density=rho, nu=nu),
        "pillar": Material("C30/37 (E from K_c)", p.pillar_modulus, density=rho, nu=nu),
        "arch": Material("C50/60", p.arch_modulus, density=rho, nu=nu),
        "steel": Material("S460", p.steel_modulus, density=p.steel_density, nu=p.steel_poisson),
    }


def bridge_model(
    p: BridgeParameters,
    laws: Mapping[str, tuple[str, Mapping] | None],
    name: str = "reference bridge",
) -> Model:
    """The reference bridge with the given law on each sliding bearing.

    ``laws`` maps every bearing name (``"1A"`` .. ``"6B"``) to ``(law, law_params)`` for its
    sliding direction(s), or to ``None`` to fix it (JOIN). Bearing 4A is fixed whatever it maps to.
    """
    missing = [b for b in BEARINGS if b not in laws]
    unknown = [b for b in laws if b not in BEARINGS]
    if missing or unknown:
        raise ModelError(f"bridge_model: field 'laws' must map every bearing; missing {missing}, unknown {unknown}")
    g = grid(p)
    geometry = girder_geometry(p)
    offset = bearing_offset(p)
    mat = _materials(p, geometry.area)
    girder = girder_section(p)
    # the crossbar below the slab, between the girder webs, half on each girder node
    crossbar_mass = p.concrete_density * p.crossbar_width * (p.crossbar_depth - p.slab_thickness) * (
        p.girder_spacing - p.girder_width
    ) / 2
    ys = {"A": -p.girder_spacing / 2, "B": p.girder_spacing / 2}
    x = g.x
    nodes: list[Node] = []
    elements: list = []
    links: list[RigidLink] = []
    connectors: list[Connector] = []
    supports: list[Support] = []
    masses: list[NodalMass] = []

    # deck
    for side in SIDES:
        nodes += [Node(f"G{side}{k}", x[k], ys[side], 0.0) for k in range(g.n + 1)]
        elements += [
            FrameElement(_girder_element(side, k, g), f"G{side}{k}", f"G{side}{k + 1}", girder, mat["girder"],
                         added_mass=p.superimposed_dead_load)
            for k in range(g.n)
        ]
    links += [RigidLink(f"X{k}", f"GA{k}", f"GB{k}") for k in range(g.n + 1)]
    masses += [NodalMass(f"G{side}{k}", crossbar_mass) for k in g.crossbars for side in SIDES]

    # arches, hangers, bracing
    x3, x4 = p.axis_positions[2], p.axis_positions[3]
    arch = arch_section(p)
    hanger_area = np.pi * p.hanger_diameter**2 / 4
    stations = list(g.arch)
    for side in SIDES:
        xi = (x[stations] - x3) / (x4 - x3)
        zs = -offset + p.arch_springing + 4 * p.arch_rise * xi * (1 - xi)
        nodes += [Node(f"R{side}{k}", x[k], ys[side], z) for k, z in zip(stations, zs)]
        elements += [
            FrameElement(f"R{side}{k}", f"R{side}{k}", f"R{side}{k + 1}", arch, mat["arch"]) for k in stations[:-1]
        ]
        fixity = SPRINGING_DOFS[p.arch_springings]
        supports += [Support(f"R{side}{stations[0]}", fixity), Support(f"R{side}{stations[-1]}", fixity)]
        elements += [
            TrussElement(f"H{side}{j}", f"G{side}{k}", f"R{side}{k}", hanger_area, mat["steel"])
            for j, k in enumerate(g.hangers, start=1)
        ]
    strut = Section.rectangle("strut", p.strut_side, p.strut_side)
    elements += [FrameElement(f"T{k}", f"RA{k}", f"RB{k}", strut, mat["arch"]) for k in g.struts]
    if p.bracing_diagonal_area > 0:
        for k1, k2 in zip(g.struts[:-1], g.struts[1:]):
            elements += [
                TrussElement(f"DA{k1}", f"RA{k1}", f"RB{k2}", p.bracing_diagonal_area, mat["steel"]),
                TrussElement(f"DB{k1}", f"RB{k1}", f"RA{k2}", p.bracing_diagonal_area, mat["steel"]),
            ]

    # bearings on rigid offsets, over pillars or abutments
    pillar = Section.rectangle("pillar", p.pillar_side, p.pillar_side)
    heights = np.linspace(-p.pillar_height, 0.0, p.pillar_elements + 1)
    for bearing, spec in BEARINGS.items():
        k = g.axes[spec.axis - 1]
        xb, yb, zb = x[k], ys[spec.side], -offset
        slide = f"{bearing}.girder"
        nodes.append(Node(slide, xb, yb, zb))
        links.append(RigidLink(f"L{bearing}", f"G{spec.side}{k}", slide))
        if spec.axis in PILLAR_AXES:
            names = [f"P{bearing}.{i}" for i in range(p.pillar_elements + 1)]
            nodes += [Node(n_, xb, yb, zb + h) for n_, h in zip(names, heights)]
            elements += [
                FrameElement(f"P{bearing}.{i + 1}", names[i], names[i + 1], pillar, mat["pillar"])
                for i in range(p.pillar_elements)
            ]
            supports.append(Support(names[0]))
            seat = names[-1]
        else:
            seat = f"{bearing}.abutment"
            nodes.append(Node(seat, xb, yb, zb))
            supports.append(Support(seat))
        law = laws[bearing]
        if spec.kind is ConnectorKind.JOIN or law is None:
            connectors.append(Connector(bearing, seat, slide, ConnectorKind.JOIN))
        else:
            guided = {"guided": spec.guided} if spec.kind is ConnectorKind.AXIAL else {}
            connectors.append(
                Connector(bearing, seat, slide, spec.kind, law=law[0], law_params=dict(law[1]),
                          vertical_stiffness=p.bearing_vertical_stiffness, uplift=p.uplift, **guided)
            )
    return Model(nodes, elements, connectors, rigid_links=links, supports=supports, masses=masses, name=name)
