"""A user's own bridge for ``bearingfw run``: a two-span continuous concrete girder on pot bearings.

The experiment file names this builder as ``builder = "small_bridge:build"``; ``bearingfw run``
imports this module (the experiment file's folder is on the import path), calls ``build`` with
``[structure] options`` as keyword arguments, and puts each bearing model on the sliding
bearings (every connector that is not JOIN, unless ``[structure] bearings`` lists them).

Layout (SI units, x along the bridge, z up)::

    axis:   1 (abutment)            2 (pier)             3 (abutment)
            |<------- span ------->|<------- span ------->|
    girder  G0 ---------------------G<n>------------------ G<2n>      (y = 0, z = 0)
    A side  1A: guided along x      2A: fixed (JOIN)      3A: guided along x    (y = -bearing_spacing / 2)
    B side  1B: multidirectional    2B: guided along y    3B: multidirectional  (y = +bearing_spacing / 2)

Each bearing sits on a rigid offset ``bearing_offset`` below the girder axis (its soffit) and
``bearing_spacing / 2`` to the side; the abutment seats are fixed, the pier seats sit on a rigid
cross-head on top of one square column clamped at its base. Stress recovery points are the
default ones of the rectangular sections. The fixed bearing 2A and the guide of 2B hold the deck
along the bridge, the guides of 1A and 3A and bearing 2A across it, as on the paper's bridge.
"""

from __future__ import annotations

from bearingfw.model import (
    Connector,
    FrameElement,
    Material,
    Model,
    Node,
    RigidLink,
    Section,
    Support,
)

__all__ = ["build"]


def build(
    span: float = 24.0,
    elements_per_span: int = 8,
    girder_width: float = 4.0,
    girder_depth: float = 1.0,
    pier_height: float = 6.0,
    pier_side: float = 1.0,
    bearing_spacing: float = 3.0,
    bearing_offset: float = 0.6,
    superimposed_dead_load: float = 3000.0,
    bearing_vertical_stiffness: float = 5e9,
    bearing_stiffness: float | None = None,
    concrete_modulus: float = 34e9,
) -> Model:
    """The two-span girder (module docstring).

    Every sliding bearing starts frictionless (the models of an experiment replace it), or, with
    ``bearing_stiffness`` (N/m), a linear spring of that stiffness in its sliding directions: a
    pot bearing that sticks under ambient vibration, the parameter ``bearingfw tune`` calibrates
    here. ``concrete_modulus`` (Pa) is the girder's and the pier's E; ``superimposed_dead_load``
    (kg/m) the girder's added mass: both parameters worth tuning too.

    Elements: girder ``G0`` .. ``G<2n-1>`` (``G<n>`` starts over the pier, ``G<n//2>`` at the first
    mid-span), pier ``P1`` .. ``P4``. Bearings ``1A`` .. ``3B``. Nodes: girder axis ``G0`` ..
    ``G<2n>``, pier ``P0`` (base) .. ``P4`` (top), each bearing's ``<name>.girder`` and ``<name>.seat``.
    """
    concrete = Material("C35/45", concrete_modulus, density=2500.0, nu=0.2)
    law = ("frictionless", {}) if bearing_stiffness is None else ("linear-spring", {"k": bearing_stiffness})
    girder = Section.rectangle("girder", girder_width, girder_depth)
    column = Section.rectangle("pier", pier_side, pier_side)
    n = elements_per_span
    step = span / n
    half = bearing_spacing / 2
    nodes = [Node(f"G{k}", k * step, 0.0, 0.0) for k in range(2 * n + 1)]
    elements = [
        FrameElement(f"G{k}", f"G{k}", f"G{k + 1}", girder, concrete, added_mass=superimposed_dead_load)
        for k in range(2 * n)
    ]
    links, connectors, supports = [], [], []
    sliding = {
        1: {"A": ("axial", "x"), "B": ("planar", None)},
        2: {"A": ("join", None), "B": ("axial", "y")},
        3: {"A": ("axial", "x"), "B": ("planar", None)},
    }
    # pier: a column clamped at its base, a rigid cross-head carrying both bearing seats
    x_pier = span
    top = -bearing_offset
    heights = [top - pier_height + pier_height * i / 4 for i in range(5)]
    nodes += [Node(f"P{i}", x_pier, 0.0, z) for i, z in enumerate(heights)]
    elements += [FrameElement(f"P{i + 1}", f"P{i}", f"P{i + 1}", column, concrete) for i in range(4)]
    supports.append(Support("P0"))
    for axis, station in ((1, 0), (2, n), (3, 2 * n)):
        x = station * step
        for side, y in (("A", -half), ("B", half)):
            name = f"{axis}{side}"
            girder_side, seat = f"{name}.girder", f"{name}.seat"
            nodes += [Node(girder_side, x, y, -bearing_offset), Node(seat, x, y, -bearing_offset)]
            links.append(RigidLink(f"L{name}", f"G{station}", girder_side))
            if axis == 2:
                links.append(RigidLink(f"H{name}", "P4", seat))  # the pier's cross-head
            else:
                supports.append(Support(seat))
            kind, guided = sliding[axis][side]
            if kind == "join":
                connectors.append(Connector(name, seat, girder_side, "join"))
            else:
                connectors.append(Connector(
                    name, seat, girder_side, kind, law=law[0], law_params=law[1],
                    vertical_stiffness=bearing_vertical_stiffness, **({"guided": guided} if guided else {}),
                ))
    return Model(nodes, elements, connectors, rigid_links=links, supports=supports, name="two-span girder")
