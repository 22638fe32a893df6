"""Small models and helpers shared by the transient tests (built with the kernel's public API)."""

from __future__ import annotations

import contextlib
import importlib.metadata as metadata
import sys
import types
from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.model import Connector, FrameElement, Material, Model, NodalMass, Node, RigidLink, Section, Support
from bearingfw.plugins import load_registry

G = 9.81


# --- a mass on a massless cantilever column: an SDOF in y -------------------------------------
COLUMN_H = 5.0
COLUMN_MASS = 2.0e4
COLUMN_SECTION = Section("column", A=0.25, Iy=5e-3, Iz=5e-3, J=8e-3)
COLUMN_MATERIAL = Material("massless", 30e9, density=0.0)
#: Tip stiffness of the cantilever (rotation free at the tip, massless: condensed exactly).
COLUMN_K = 3 * COLUMN_MATERIAL.E * COLUMN_SECTION.Iz / COLUMN_H**3


def column_sdof() -> Model:
    """``top`` carries ``COLUMN_MASS`` on a massless cantilever from the fixed ``base``."""
    return Model(
        [Node("base", 0, 0, 0), Node("top", 0, 0, COLUMN_H)],
        [FrameElement("col", "base", "top", COLUMN_SECTION, COLUMN_MATERIAL)],
        supports=[Support("base")],
        masses=[NodalMass("top", COLUMN_MASS)],
    )


# --- masses on connectors ----------------------------------------------------------------------
def connector_chain(masses, laws, vertical_stiffness) -> Model:
    """Masses ``m1, m2, ...`` stacked on AXIAL connectors (guided along x) over the supported ``g``.

    ``laws``: one (law, params) per connector, connector ``c{k}`` joining the node below to ``m{k}``.
    All nodes coincide (connectors have no length); the y direction is tied, z is the vertical spring.
    """
    names = ["g"] + [f"m{k}" for k in range(1, len(masses) + 1)]
    nodes = [Node(n, 0.0, 0.0, 0.0) for n in names]
    kvs = np.broadcast_to(np.asarray(vertical_stiffness, dtype=float), (len(masses),))
    connectors = [
        Connector(f"c{k}", names[k - 1], names[k], "axial", law=law, law_params=params, vertical_stiffness=float(kv))
        for k, ((law, params), kv) in enumerate(zip(laws, kvs, strict=True), start=1)
    ]
    return Model(
        nodes,
        connectors=connectors,
        supports=[Support("g")],
        masses=[NodalMass(n, m) for n, m in zip(names[1:], masses, strict=True)],
    )


def friction_oscillator(m: float, k_spring: float, k_stick: float, mu: float, kv: float = 1e9) -> Model:
    """A mass on a linear spring and, in parallel, a regularized-Coulomb bearing (both AXIAL along x).

    Both connectors have the same vertical stiffness, so each carries half the weight: the
    friction bearing's normal force is ``m g / 2``.
    """
    return Model(
        [Node("g", 0, 0, 0), Node("m", 0, 0, 0)],
        connectors=[
            Connector("spring", "g", "m", "axial", law="linear-spring", law_params={"k": k_spring}, vertical_stiffness=kv),
            Connector(
                "friction", "g", "m", "axial", law="regularized-coulomb",
                law_params={"k": k_stick, "mu": mu}, vertical_stiffness=kv,
            ),
        ],
        supports=[Support("g")],
        masses=[NodalMass("m", m)],
    )


def band_limited_noise(steps: int, dt: float, seed: int, amplitude, corner: float = 8.0) -> np.ndarray:
    """Seeded random 3-component acceleration, low-passed (first-order, ``corner`` Hz), peak ``amplitude``."""
    rng = np.random.default_rng(seed)
    raw = rng.normal(size=(steps, 3))
    a = np.exp(-2 * np.pi * corner * dt)
    out = np.zeros_like(raw)
    for k in range(1, steps):
        out[k] = a * out[k - 1] + (1 - a) * raw[k]
    out *= np.asarray(amplitude, dtype=float) / np.max(np.abs(out), axis=0)
    out[0] = 0.0
    return out


def rel_err(a, b) -> float:
    """``max |a - b| / max |b|`` (NaNs where both are NaN are ignored)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    both = np.isnan(a) & np.isnan(b)
    a, b = np.where(both, 0.0, a), np.where(both, 0.0, b)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


# --- test-only laws ------------------------------------------------------------------------------
@attrs.frozen
class LyingSpring:
    """F = k u, but reports a zero tangent away from u = 0: Newton becomes a fixed-point iteration
    that converges only for small enough steps (contraction ``(1 + alpha) k beta h^2 / m < 1``).
    (At u = 0, where the gravity preload checks the structure with the laws' initial tangent, it
    tells the truth.)"""

    name: ClassVar[str] = "test-lying-spring"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        honest = np.all(u == 0.0, axis=1)[:, None, None] * np.eye(self.dims) * self.k
        return bearingfw.LawResponse(self.k * u, np.broadcast_to(honest, (u.shape[0], self.dims, self.dims)).copy(), state)


@attrs.frozen
class BrittleSpring:
    """F = k u up to ``|u| = limit``, then a non-finite force: no step can get past it."""

    name: ClassVar[str] = "test-brittle-spring"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    limit: float = bearingfw.parameter(low=0.0, low_open=True, unit="m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        broken = np.abs(u) > self.limit
        force = np.where(broken, np.nan, self.k * u)
        tangent = np.broadcast_to(self.k * np.eye(self.dims), (u.shape[0], self.dims, self.dims)).copy()
        return bearingfw.LawResponse(force, tangent, state)


@attrs.frozen
class StepLimitedSpring:
    """F = k u, but a non-finite force for a time step above ``dt_max`` (like a law that integrates
    itself explicitly and must not be called with long steps): every step longer than that fails,
    whatever Newton does, and only halving the step helps."""

    name: ClassVar[str] = "test-step-limited-spring"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    dt_max: float = bearingfw.parameter(low=0.0, low_open=True, unit="s")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        force = self.k * u if dt <= self.dt_max * (1 + 1e-12) else np.full_like(u, np.nan)
        tangent = np.broadcast_to(self.k * np.eye(self.dims), (u.shape[0], self.dims, self.dims)).copy()
        return bearingfw.LawResponse(force, tangent, state)


@attrs.frozen
class GrumpySpring:
    """F = k u up to ``|u| = limit``, then ``respond`` raises (a law bug, not a convergence problem)."""

    name: ClassVar[str] = "test-grumpy-spring"
    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    limit: float = bearingfw.parameter(low=0.0, low_open=True, unit="m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {"slip": np.zeros((n, self.dims))}  # a "slip" in the state, but no slip() member

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        if np.any(np.abs(u) > self.limit):
            raise ValueError(f"test-grumpy-spring: |u| = {np.abs(u).max():.3g} m beyond {self.limit} m")
        tangent = np.broadcast_to(self.k * np.eye(self.dims), (u.shape[0], self.dims, self.dims)).copy()
        return bearingfw.LawResponse(self.k * u, tangent, state)


# --- a rigid block rocking on two friction bearings: N coupled to the friction forces ----------
BLOCK_MASS = 2.0e4
BLOCK_INERTIA = 2.0e4  # kg m^2 about y
BLOCK_HEIGHT = 3.0  # centre of mass above the bearings' soffit
BLOCK_HALF_BASE = 1.0  # bearings at x = -+ this


def rocking_block(k_stick: float, mu: float, kv: float) -> Model:
    """A rigid block (mass, inertia about y at ``CG``) on two AXIAL regularized-Coulomb bearings
    (guided along x) at ``x = -+BLOCK_HALF_BASE``, ``BLOCK_HEIGHT`` below ``CG``, joined to it by
    rigid links. The friction forces act ``BLOCK_HEIGHT`` below the centre of mass: their moment
    rocks the block and moves load from one bearing to the other, so each bearing's ``N`` depends
    on the horizontal response. Roll (rx) is held at ``CG``; y and the twist are held by the guides.
    """
    nodes = [Node("CG", 0.0, 0.0, BLOCK_HEIGHT)]
    links, connectors, supports = [], [], [Support("CG", ("rx",))]
    for name, x in (("L", -BLOCK_HALF_BASE), ("R", BLOCK_HALF_BASE)):
        nodes += [Node(f"S{name}", x, 0.0, 0.0), Node(f"P{name}", x, 0.0, 0.0)]
        links.append(RigidLink(f"link{name}", "CG", f"S{name}"))
        connectors.append(
            Connector(
                f"c{name}", f"P{name}", f"S{name}", "axial", guided="x", law="regularized-coulomb",
                law_params={"k": k_stick, "mu": mu}, vertical_stiffness=kv,
            )
        )
        supports.append(Support(f"P{name}"))
    return Model(
        nodes, connectors=connectors, rigid_links=links, supports=supports,
        masses=[NodalMass("CG", BLOCK_MASS, iyy=BLOCK_INERTIA)],
    )


#: The test-only laws above, registered by :func:`registry_with_test_laws`.
TEST_LAWS = (LyingSpring, BrittleSpring, StepLimitedSpring, GrumpySpring)


@contextlib.contextmanager
def registry_with_test_laws(module_name: str = "bearingfw_transient_test_plugin"):
    """The installed plugins plus a test plugin (module ``module_name``) registering :data:`TEST_LAWS`."""
    module = types.ModuleType(module_name)

    @bearingfw.hookimpl
    def bearingfw_register_laws():
        return list(TEST_LAWS)

    module.bearingfw_register_laws = bearingfw_register_laws
    sys.modules[module_name] = module
    eps = list(metadata.entry_points(group="bearingfw"))
    eps.append(metadata.EntryPoint(name="transient-test-laws", value=module_name, group="bearingfw"))
    try:
        yield load_registry(eps)
    finally:
        sys.modules.pop(module_name, None)
