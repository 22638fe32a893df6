"""DOF numbering: six DOFs per node, node-major.

Global DOF ``6 * n + c`` is component ``c`` (:data:`~bearingfw.model.nodes.COMPONENTS`:
``ux, uy, uz, rx, ry, rz``) of the node with index ``n`` in ``Model.nodes``. This "full"
numbering holds every DOF of every node; the constraints later map it to the smaller set of
independent DOFs (see :mod:`bearingfw.model.constraints`).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence

import attrs
import numpy as np

from bearingfw.model._fields import ModelError
from bearingfw.model.nodes import COMPONENTS

__all__ = ["DofMap", "NDOF_NODE", "component_index"]

NDOF_NODE = 6


def component_index(component: str | int) -> int:
    """``"uz"`` -> 2; integers 0..5 pass through."""
    if isinstance(component, (int, np.integer)) and 0 <= component < NDOF_NODE:
        return int(component)
    try:
        return COMPONENTS.index(str(component).lower())
    except ValueError:
        raise ModelError(f"unknown DOF component {component!r}; components: {', '.join(COMPONENTS)}") from None


@attrs.frozen(eq=False)
class DofMap:
    """Maps (node name, component) to the full DOF index.

    It holds the one node-name index of a model (:attr:`bearingfw.model.Model.dofmap`); node
    names must be unique.
    """

    node_names: tuple[str, ...] = attrs.field(converter=tuple)
    _index: dict[str, int] = attrs.field(init=False, repr=False)

    def __attrs_post_init__(self):
        index = {name: k for k, name in enumerate(self.node_names)}
        if len(index) != len(self.node_names):
            twice = sorted(n for n, count in Counter(self.node_names).items() if count > 1)
            raise ModelError(f"DofMap: field 'node_names' repeats {', '.join(map(repr, twice))}")
        object.__setattr__(self, "_index", index)

    @property
    def n_nodes(self) -> int:
        return len(self.node_names)

    @property
    def n_dof(self) -> int:
        return NDOF_NODE * len(self.node_names)

    def node_index(self, node: str) -> int:
        try:
            return self._index[node]
        except KeyError:
            raise ModelError(f"unknown node {node!r}") from None

    def dof(self, node: str, component: str | int) -> int:
        """The full DOF index of one component of one node."""
        return NDOF_NODE * self.node_index(node) + component_index(component)

    def node_dofs(self, node: str | Sequence[str]) -> np.ndarray:
        """The six DOF indices of a node, shape (6,); of a sequence of nodes, shape (n, 6)."""
        if isinstance(node, str):
            return self.node_dofs([node])[0]
        idx = np.array([self.node_index(n) for n in node], dtype=int).reshape(-1)
        return NDOF_NODE * idx[:, None] + np.arange(NDOF_NODE)[None, :]

    def dofs(self, nodes: Iterable[str], components: Sequence[str | int] = COMPONENTS) -> np.ndarray:
        """DOF indices for every node in ``nodes`` and every component, node-major.

        Use it to pick the DOFs at which mode shapes are compared (e.g. the sensor nodes'
        ``uz``) for :func:`bearingfw.analysis.mac`.
        """
        comps = [component_index(c) for c in components]
        return np.array([NDOF_NODE * self.node_index(n) + c for n in nodes for c in comps], dtype=int)

    def component_dofs(self, component: str | int) -> np.ndarray:
        """The indices of one component at all nodes (e.g. every ``uz``)."""
        return np.arange(component_index(component), self.n_dof, NDOF_NODE)

    def describe(self, dof: int) -> str:
        """``"N3.uz"`` for a DOF index."""
        return f"{self.node_names[dof // NDOF_NODE]}.{COMPONENTS[dof % NDOF_NODE]}"
