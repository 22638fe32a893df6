"""Nodes and what attaches to a single node: supports, lumped masses, point loads.

Global axes: x longitudinal, y transverse, z vertical (up). Every node carries six DOFs in the
order of :data:`COMPONENTS`: translations ``ux, uy, uz`` (m) and rotations ``rx, ry, rz`` (rad)
about the global axes.
"""

from __future__ import annotations

import attrs

from bearingfw.model._fields import ModelError, name_field, node_ref
from bearingfw.parameters import parameter

__all__ = ["COMPONENTS", "Node", "Support", "NodalMass", "NodalLoad", "FIXED", "PINNED"]

#: DOF components of a node, in the order of the DOF numbering.
COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")
#: All six DOFs restrained.
FIXED = COMPONENTS
#: Translations restrained, rotations free.
PINNED = ("ux", "uy", "uz")


@attrs.frozen
class Node:
    """A point of the model, coordinates in metres."""

    name: str = name_field()
    x: float = parameter(unit="m", doc="x coordinate (longitudinal)")
    y: float = parameter(unit="m", doc="y coordinate (transverse)")
    z: float = parameter(unit="m", doc="z coordinate (vertical, up)")

    @property
    def xyz(self) -> tuple[float, float, float]:
        return (self.x, self.y, self.z)


def _components(value):
    if isinstance(value, str):
        value = (value,)
    try:
        return tuple(str(v).lower() for v in value)
    except TypeError:
        return value


@attrs.frozen
class Support:
    """Restrained DOFs of one node (zero displacement relative to the ground)."""

    node: str = node_ref("the supported node")
    dofs: tuple[str, ...] = attrs.field(default=FIXED, converter=_components)

    @dofs.validator
    def _check(self, attribute, value):
        bad = [c for c in value if c not in COMPONENTS] if isinstance(value, tuple) else [value]
        if bad or not value or len(set(value)) != len(value):
            raise ModelError(
                f"support at node {self.node!r}: field 'dofs' must be distinct names among "
                f"{', '.join(COMPONENTS)}, got {value!r}"
            )

    @property
    def name(self) -> str:  # lets error messages name the object
        return f"support at {self.node}"


@attrs.frozen
class NodalMass:
    """A lumped mass (kg) and optional rotary inertias (kg m^2, about the global axes) at a node.

    It is non-structural mass: it enters the mass matrix and the gravity load alike.
    """

    node: str = node_ref("the node carrying the mass")
    mass: float = parameter(low=0.0, unit="kg", doc="translational mass")
    ixx: float = parameter(low=0.0, default=0.0, unit="kg m^2", doc="rotary inertia about x")
    iyy: float = parameter(low=0.0, default=0.0, unit="kg m^2", doc="rotary inertia about y")
    izz: float = parameter(low=0.0, default=0.0, unit="kg m^2", doc="rotary inertia about z")

    @property
    def name(self) -> str:
        return f"mass at {self.node}"


@attrs.frozen
class NodalLoad:
    """A static point load at a node in global axes: forces (N) and moments (N m)."""

    node: str = node_ref("the loaded node")
    fx: float = parameter(default=0.0, unit="N")
    fy: float = parameter(default=0.0, unit="N")
    fz: float = parameter(default=0.0, unit="N")
    mx: float = parameter(default=0.0, unit="N m")
    my: float = parameter(default=0.0, unit="N m")
    mz: float = parameter(default=0.0, unit="N m")

    @property
    def name(self) -> str:
        return f"load at {self.node}"

    @property
    def values(self) -> tuple[float, ...]:
        return (self.fx, self.fy, self.fz, self.mx, self.my, self.mz)
