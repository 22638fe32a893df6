"""The bearing layout of the reference bridge: which bearing sits where and what it lets slide.

Axes 1..6 along the bridge: 1 and 6 are the abutments, 2..5 the pillar pairs. Each axis carries
two bearings, one under girder A (``y < 0``) and one under girder B (``y > 0``), named after
the axis and the girder: ``"1A"``, ``"1B"``, ..., ``"6B"``. The paper's figure 6 is missing;
its text (section 2.2.1) gives the scheme used here, the usual one for a fixed point at axis 4:

====  ===========================================  ==================================================
axis  girder A                                     girder B
====  ===========================================  ==================================================
4     fixed (JOIN)                                 transversally guided (AXIAL, slides in y, tied in x)
else  longitudinally guided (AXIAL, slides in x,   multidirectional (PLANAR, slides in x and y)
      tied in y)
====  ===========================================  ==================================================

So with frictionless sliding the deck is held longitudinally only at axis 4 (both bearings)
and transversally only under girder A (4A included): the B pillars of axes 2, 3 and 5 then carry
no horizontal load, and the paper's springs (M1) bring them in.
"""

from __future__ import annotations

import attrs

from bearingfw.bridges.paper import BEARING_CAPACITY
from bearingfw.model import ConnectorKind

__all__ = ["ABUTMENT_AXES", "AXES", "BEARINGS", "FIXED_AXIS", "PILLAR_AXES", "SIDES", "BearingSpec", "bearing_names"]

AXES = (1, 2, 3, 4, 5, 6)
ABUTMENT_AXES = (1, 6)
PILLAR_AXES = (2, 3, 4, 5)
FIXED_AXIS = 4
SIDES = ("A", "B")


@attrs.frozen
class BearingSpec:
    """One bearing: its axis, girder, connector kind, guided (sliding) direction and capacity (N)."""

    axis: int
    side: str
    kind: ConnectorKind
    guided: str | None  # the AXIAL connector's sliding direction ("x" or "y"); None otherwise
    capacity: float

    @property
    def name(self) -> str:
        return f"{self.axis}{self.side}"

    @property
    def on_pillar(self) -> bool:
        return self.axis in PILLAR_AXES

    @property
    def sliding_directions(self) -> tuple[str, ...]:
        """Local directions the bearing lets slide (the ones a bearing law governs)."""
        if self.kind is ConnectorKind.PLANAR:
            return ("x", "y")
        return () if self.guided is None else (self.guided,)


def _spec(axis: int, side: str) -> BearingSpec:
    if axis == FIXED_AXIS:
        kind, guided = (ConnectorKind.JOIN, None) if side == "A" else (ConnectorKind.AXIAL, "y")
    else:
        kind, guided = (ConnectorKind.AXIAL, "x") if side == "A" else (ConnectorKind.PLANAR, None)
    return BearingSpec(axis, side, kind, guided, BEARING_CAPACITY[axis])


#: Every bearing by name, axis-major ("1A", "1B", "2A", ...).
BEARINGS: dict[str, BearingSpec] = {s.name: s for s in (_spec(a, side) for a in AXES for side in SIDES)}


def bearing_names() -> tuple[str, ...]:
    return tuple(BEARINGS)
