"""The conformance suite passes for the built-in laws and names the property a broken law breaks."""

import numpy as np
import pytest

from bearingfw import LawResponse, create_law
from bearingfw.testing import ConformanceError, check_law, parametrize_with_checks

BUILT_IN = [
    create_law(name, dims=dims, **params)
    for name, params in [
        ("frictionless", {}),
        ("fixed", {}),
        ("linear-spring", {"k": 4e8}),
        ("regularized-coulomb", {"k": 4e8, "mu": 0.04}),
    ]
    for dims in (1, 2)
]


@parametrize_with_checks(BUILT_IN)
def test_built_in_laws_conform(law, check):
    check(law)


class Friction:
    """A correct 1-/2-D friction law written without bearingfw's help; broken variants below."""

    name = "test-friction"
    rigid = False

    def __init__(self, dims=2, k=1e6, mu=0.1):
        self.dims, self.k, self.mu = dims, k, mu

    def initial_state(self, n):
        return {"slip": np.zeros((n, self.dims))}

    def force_bound(self, normal_force):
        return self.mu * np.asarray(normal_force)

    def _capacity_scale(self, trial, normal_force):
        norm = np.linalg.norm(trial, axis=1)
        capacity = self.mu * np.asarray(normal_force)
        # No capacity (N = 0, as the kernel passes uplift): no force, so no stiffness either.
        sliding = (norm > capacity) | (capacity <= 0)
        return np.where(sliding, capacity / np.where(norm > 0, norm, 1), 1.0), norm

    def respond(self, state, u, normal_force, dt):
        trial = self.k * (u - state["slip"])
        scale, norm = self._capacity_scale(trial, normal_force)
        force = trial * scale[:, None]
        direction = trial / np.where(norm > 0, norm, 1)[:, None]
        sliding = ((norm > 0) & (scale < 1))[:, None, None]
        projector = np.eye(self.dims) - sliding * np.einsum("ij,ik->ijk", direction, direction)
        return LawResponse(force, self.k * scale[:, None, None] * projector, {"slip": u - force / self.k})


class ElasticTangentInSlip(Friction):
    """A classic bug: the stick stiffness returned as the tangent while sliding."""

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(response.force, np.broadcast_to(self.k * np.eye(self.dims), response.tangent.shape).copy(), response.state)


class BoxFriction(Friction):
    """Another bug: each component clipped to mu N, so the 2-D force leaves the circle."""

    def respond(self, state, u, normal_force, dt):
        capacity = self.mu * np.asarray(normal_force)[:, None]
        trial = self.k * (u - state["slip"])
        force = np.clip(trial, -capacity, capacity)
        sticking = (np.abs(trial) <= capacity) & (capacity > 0)  # no capacity: no force, no stiffness
        tangent = self.k * np.einsum("ij,jk->ijk", sticking.astype(float), np.eye(self.dims))
        return LawResponse(force, tangent, {"slip": u - force / self.k})


class MutatesState(Friction):
    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        state["slip"][...] = response.state["slip"]
        return response


class NegativeDamper:
    """F = -c du/dt: consistent tangent, odd, zero at rest, but it feeds energy in."""

    name, dims, rigid, c = "negative-damper", 1, False, 1e5

    def initial_state(self, n):
        return {"u": np.zeros((n, 1))}

    def respond(self, state, u, normal_force, dt):
        force = -self.c * (u - state["u"]) / dt
        return LawResponse(force, np.full((len(u), 1, 1), -self.c / dt), {"u": np.array(u, dtype=float)})


class QuadraticSpring:
    """F = k u + k2 u^2 is not odd, but says it is symmetric by omission."""

    name, dims, rigid, k, k2 = "quadratic-spring", 1, False, 1e6, 1e8

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        return LawResponse(self.k * u + self.k2 * u**2, (self.k + 2 * self.k2 * u)[:, :, None], state)


class LoopsOverConnectors(Friction):
    """Reads only the first connector's normal force: wrong when n > 1."""

    def respond(self, state, u, normal_force, dt):
        return super().respond(state, u, np.full(len(u), np.asarray(normal_force)[0]), dt)


class ForceAtRest(Friction):
    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(response.force + 1.0, response.tangent, response.state)


class WrongShape(Friction):
    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(response.force[:, 0], response.tangent, response.state)


class NoRigidFlag:
    name, dims = "no-rigid", 1

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        return LawResponse(np.zeros_like(u), np.zeros((len(u), 1, 1)), state)


def test_the_reference_friction_law_conforms_in_1d_and_2d():
    check_law(Friction(dims=1))
    check_law(Friction(dims=2))


@pytest.mark.parametrize(
    "law, prop",
    [
        (ElasticTangentInSlip(dims=1), "tangent"),
        (ElasticTangentInSlip(dims=2), "tangent"),
        (BoxFriction(dims=2), "force bound"),
        (MutatesState(), "purity"),
        (NegativeDamper(), "dissipation"),
        (QuadraticSpring(), "odd symmetry"),
        (LoopsOverConnectors(), "vectorised"),
        (ForceAtRest(), "zero force at rest"),
        (WrongShape(), "response shapes"),
        (NoRigidFlag(), "protocol"),
    ],
    ids=lambda v: v if isinstance(v, str) else type(v).__name__,
)
def test_a_broken_law_fails_with_the_property_it_breaks(law, prop):
    with pytest.raises(ConformanceError, match=f"breaks property '{prop}'") as info:
        check_law(law, max_examples=60, shrink=False)
    assert info.value.prop == prop


def test_box_friction_is_fine_in_1d_where_box_and_circle_agree():
    check_law(BoxFriction(dims=1))
