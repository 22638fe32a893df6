"""The :class:`Model` container: everything that describes a structure, checked as a whole."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import attrs
import numpy as np

from bearingfw.model._fields import ModelError
from bearingfw.model.connectors import Connector, ConnectorKind
from bearingfw.model.dofs import DofMap
from bearingfw.model.elements import FrameElement, RigidLink, TrussElement
from bearingfw.model.nodes import NodalMass, Node, Support

__all__ = ["Model", "CONNECTOR_LENGTH_TOLERANCE"]

#: The two nodes of a connector must coincide within this distance (m): a connector has no
#: length, so that it transmits forces without a couple. Use a rigid link for an offset.
CONNECTOR_LENGTH_TOLERANCE = 1e-6


def _tuple_of(*kinds: type):
    def convert(value):
        try:
            return tuple(value)
        except TypeError:
            return value

    def check(instance, attribute, value):
        if not isinstance(value, tuple):
            raise ModelError(f"Model: field {attribute.name!r} must be a sequence, got {value!r}")
        for item in value:
            if not isinstance(item, kinds):
                names = " or ".join(k.__name__ for k in kinds)
                raise ModelError(f"Model: field {attribute.name!r} holds {item!r}, expected {names}")

    return attrs.field(default=(), converter=convert, validator=check)


def _unique(field: str, items: Iterable[Any]) -> dict[str, int]:
    index: dict[str, int] = {}
    for k, item in enumerate(items):
        if item.name in index:
            raise ModelError(f"Model: field {field!r} has two entries named {item.name!r}")
        index[item.name] = k
    return index


@attrs.frozen(eq=False)
class Model:
    """Nodes, members, rigid links, connectors (bearings), supports and lumped masses.

    Members and connectors refer to nodes by name; the model checks every reference, that
    names are unique (nodes; elements; connectors; rigid links), that members have a length
    and that each connector's two nodes coincide. Look objects up by name with
    :meth:`node`, :meth:`element`, :meth:`connector`.
    """

    nodes: tuple[Node, ...] = _tuple_of(Node)
    elements: tuple[FrameElement | TrussElement, ...] = _tuple_of(FrameElement, TrussElement)
    connectors: tuple[Connector, ...] = _tuple_of(Connector)
    rigid_links: tuple[RigidLink, ...] = _tuple_of(RigidLink)
    supports: tuple[Support, ...] = _tuple_of(Support)
    masses: tuple[NodalMass, ...] = _tuple_of(NodalMass)
    name: str = "model"
    _index: dict[str, dict[str, int]] = attrs.field(init=False, repr=False)
    _coords: np.ndarray = attrs.field(init=False, repr=False)
    _dofmap: DofMap = attrs.field(init=False, repr=False)

    def __attrs_post_init__(self):
        if not self.nodes:
            raise ModelError("Model: field 'nodes' is empty")
        # The DofMap holds the one node-name index (node lookups and DOF numbering alike).
        names = tuple(n.name for n in self.nodes)
        try:
            dofmap = DofMap(names)
        except ModelError:
            twice = next(n for k, n in enumerate(names) if n in names[:k])
            raise ModelError(f"Model: field 'nodes' has two entries named {twice!r}") from None
        object.__setattr__(self, "_dofmap", dofmap)
        index = {
            "elements": _unique("elements", self.elements),
            "connectors": _unique("connectors", self.connectors),
            "rigid_links": _unique("rigid_links", self.rigid_links),
        }
        object.__setattr__(self, "_index", index)
        coords = np.array([n.xyz for n in self.nodes], dtype=float)
        coords.setflags(write=False)
        object.__setattr__(self, "_coords", coords)

        def ref(kind: str, owner: str, field: str, node: str) -> int:
            try:
                return dofmap.node_index(node)
            except ModelError:
                raise ModelError(f"{kind} {owner!r}: field {field!r} names unknown node {node!r}") from None

        for e in self.elements:
            i, j = ref(type(e).__name__, e.name, "i", e.i), ref(type(e).__name__, e.name, "j", e.j)
            if np.linalg.norm(coords[j] - coords[i]) == 0.0:
                raise ModelError(f"{type(e).__name__} {e.name!r}: nodes {e.i!r} and {e.j!r} coincide (zero length)")
        for link in self.rigid_links:
            ref("RigidLink", link.name, "master", link.master)
            ref("RigidLink", link.name, "slave", link.slave)
        for c in self.connectors:
            i, j = ref("connector", c.name, "node_i", c.node_i), ref("connector", c.name, "node_j", c.node_j)
            gap = float(np.linalg.norm(coords[j] - coords[i]))
            if gap > CONNECTOR_LENGTH_TOLERANCE:
                raise ModelError(
                    f"connector {c.name!r}: nodes {c.node_i!r} and {c.node_j!r} are {gap:g} m apart; a connector has "
                    "zero length (join the girder axis to the bearing with a RigidLink)"
                )
        seen: set[str] = set()
        for s in self.supports:
            ref("support", s.node, "node", s.node)
            if s.node in seen:
                raise ModelError(
                    f"Model: field 'supports' has two supports at node {s.node!r}; give one with all its dofs"
                )
            seen.add(s.node)
        for m in self.masses:
            ref("NodalMass", m.node, "node", m.node)

    # ---- look-ups -------------------------------------------------------------------------
    def _get(self, kind: str, name: str):
        try:
            return getattr(self, kind)[self._index[kind][name]]
        except KeyError:
            raise ModelError(f"Model: no {kind[:-1].replace('_', ' ')} named {name!r}") from None

    def node(self, name: str) -> Node:
        return self.nodes[self.node_index(name)]

    def element(self, name: str) -> FrameElement | TrussElement:
        return self._get("elements", name)

    def connector(self, name: str) -> Connector:
        return self._get("connectors", name)

    def rigid_link(self, name: str) -> RigidLink:
        return self._get("rigid_links", name)

    def node_index(self, name: str) -> int:
        try:
            return self._dofmap.node_index(name)
        except ModelError:
            raise ModelError(f"Model: no node named {name!r}") from None

    def element_index(self, name: str) -> int:
        self.element(name)
        return self._index["elements"][name]

    def connector_index(self, name: str) -> int:
        self.connector(name)
        return self._index["connectors"][name]

    @property
    def node_names(self) -> tuple[str, ...]:
        return self._dofmap.node_names

    @property
    def dofmap(self) -> DofMap:
        """The DOF numbering of this model (six DOFs per node, node-major; the node-name index)."""
        return self._dofmap

    @property
    def coordinates(self) -> np.ndarray:
        """Node coordinates, shape (n_nodes, 3), read-only."""
        return self._coords

    # ---- variants -------------------------------------------------------------------------
    def with_law(
        self,
        law: str,
        law_params: Mapping[str, Any] | None = None,
        *,
        connectors: Iterable[str] | None = None,
    ) -> Model:
        """A copy whose sliding connectors (or the named ones) use ``law`` with ``law_params``.

        JOIN connectors have no law and are left alone unless named (which is an error). This
        is how a study swaps the bearing model (frictionless, spring, friction, ...).
        """
        names = None if connectors is None else set(connectors)
        if names is not None:
            for n in names:
                self.connector(n)
        new = []
        for c in self.connectors:
            chosen = c.name in names if names is not None else c.kind is not ConnectorKind.JOIN
            new.append(attrs.evolve(c, law=law, law_params=dict(law_params or {})) if chosen else c)
        return attrs.evolve(self, connectors=tuple(new))
