"""A law whose response has the wrong shape is refused where the kernel receives it, naming the law
(issue 15, item 7: before, numpy's broadcast error surfaced far from the law, without its name)."""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np
import pytest
import scipy.sparse as sp

from bearingfw.model import ModelError
from bearingfw.model.connectors import ConnectorOperators, LawGroup
from bearingfw.protocol import LawResponse


@attrs.frozen
class ShapedLaw:
    """Returns force, tangent and dF/dN of the shapes it is told (a linear spring otherwise)."""

    name: ClassVar[str] = "test-shaped"
    rigid: ClassVar[bool] = False
    normal_coupling: ClassVar[bool] = True
    dims: int = 2
    force_shape: tuple | None = None
    tangent_shape: tuple | None = None
    dfdn_shape: tuple | None = None
    as_list: bool = False

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        n, d = u.shape
        force = np.zeros(self.force_shape or (n, d))
        tangent = np.zeros(self.tangent_shape or (n, d, d))
        dfdn = np.zeros(self.dfdn_shape or (n, d))
        if self.as_list:
            force = force.tolist()
        return LawResponse(force, tangent, state, dforce_dnormal=dfdn)


def operators(law, n: int = 3) -> ConnectorOperators:
    """``n`` PLANAR-like connectors governed by ``law`` (two rows each), one vertical spring each."""
    dims = law.dims
    m = n * dims
    group = LawGroup(law, np.arange(n), slice(0, m), np.arange(n))
    return ConnectorOperators(
        D=sp.csr_matrix((3 * n, 3 * n)), B=sp.identity(m, format="csr"), V=sp.csr_matrix((n, 3 * n)),
        kv=np.full(n, 1e9), spring_connectors=np.arange(n), groups=(group,), ties=(),
        governed=tuple((c, k) for c in range(n) for k in range(dims)), translations=np.zeros((n, 2, 3), dtype=int),
    )  # fmt: skip


def respond(law, n: int = 3):
    ops = operators(law, n)
    return ops.respond(ops.initial_states(), np.zeros(n * law.dims), np.full(n, 1e6), 0.01)


def test_a_response_of_the_right_shapes_passes():
    responses = respond(ShapedLaw())
    assert responses[0].force.shape == (3, 2) and responses[0].tangent.shape == (3, 2, 2)


def test_a_force_given_as_a_list_of_the_right_shape_still_passes():
    assert np.shape(respond(ShapedLaw(as_list=True))[0].force) == (3, 2)


@pytest.mark.parametrize(
    ("law", "field", "got", "expected"),
    [
        (ShapedLaw(force_shape=(3,)), "force", (3,), (3, 2)),
        (ShapedLaw(force_shape=(2, 2)), "force", (2, 2), (3, 2)),
        (ShapedLaw(tangent_shape=(3, 2)), "tangent", (3, 2), (3, 2, 2)),
        (ShapedLaw(tangent_shape=(1, 2, 2)), "tangent", (1, 2, 2), (3, 2, 2)),
        (ShapedLaw(dfdn_shape=(3, 1)), "dforce_dnormal", (3, 1), (3, 2)),
        (ShapedLaw(dims=1, force_shape=(3, 3)), "force", (3, 3), (3, 1)),
    ],
)
def test_a_wrong_shape_is_refused_naming_the_law_the_field_and_both_shapes(law, field, got, expected):
    with pytest.raises(ModelError) as info:
        respond(law)
    message = str(info.value)
    assert "law 'test-shaped'" in message and f"{field!r}" in message
    assert f"of shape {got}" in message and f"must have shape {expected}" in message


def test_a_response_that_is_not_a_law_response_is_refused_naming_the_law():
    @attrs.frozen
    class TupleLaw(ShapedLaw):
        def respond(self, state, u, normal_force, dt):
            return (np.zeros(u.shape), np.zeros((*u.shape, u.shape[1])), state)

    with pytest.raises(ModelError, match=r"law 'test-shaped': respond\(\) must return a LawResponse, got tuple"):
        respond(TupleLaw())
