"""Models, test laws and helpers shared by the kernel tests (model, static, modal and transient;
imported by the test modules of this folder)."""

from __future__ import annotations

import contextlib
import importlib.metadata as metadata
import sys
import types
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
from bearingfw.plugins import load_registry

G = 9.81

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


# --- test-only laws, and registries that hold them ---------------------------------------------
def elastic_tangent(k, n: int, dims: int) -> np.ndarray:
    """``k I`` for each of ``n`` connectors, (n, dims, dims) (``k`` a scalar or (n,))."""
    return np.asarray(k, dtype=float).reshape(-1, 1, 1) * np.broadcast_to(np.eye(dims), (n, dims, dims))


@contextlib.contextmanager
def registry_with(laws, plugin: str, module_name: str):
    """The installed plugins plus a test plugin ``plugin`` (module ``module_name``) registering ``laws``."""
    module = types.ModuleType(module_name)

    @bearingfw.hookimpl
    def bearingfw_register_laws():
        return list(laws)

    module.bearingfw_register_laws = bearingfw_register_laws
    sys.modules[module_name] = module
    eps = list(metadata.entry_points(group="bearingfw"))
    eps.append(metadata.EntryPoint(name=plugin, value=module_name, group="bearingfw"))
    try:
        yield load_registry(eps)
    finally:
        sys.modules.pop(module_name, None)


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
        return bearingfw.LawResponse(2 * self.k * u, elastic_tangent(2 * self.k, u.shape[0], self.dims), state)


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
        return bearingfw.LawResponse(k[:, None] * u, elastic_tangent(k, u.shape[0], self.dims), state)


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
            Connector(
                "spring", "g", "m", "axial", law="linear-spring", law_params={"k": k_spring}, vertical_stiffness=kv
            ),
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
class _TestSpring:
    """What the test springs below share: ``F = k u`` parameters, no state, the elastic tangent."""

    rigid: ClassVar[bool] = False
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m")
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return {}

    def tangent(self, u: np.ndarray) -> np.ndarray:
        return elastic_tangent(self.k, u.shape[0], self.dims)


@attrs.frozen
class LyingSpring(_TestSpring):
    """F = k u, but reports a zero tangent away from u = 0: Newton becomes a fixed-point iteration
    that converges only for small enough steps (contraction ``(1 + alpha) k beta h^2 / m < 1``).
    (At u = 0, where the gravity preload checks the structure with the laws' initial tangent, it
    tells the truth.)"""

    name: ClassVar[str] = "test-lying-spring"

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        honest = elastic_tangent(self.k * np.all(u == 0.0, axis=1), u.shape[0], self.dims)
        return bearingfw.LawResponse(self.k * u, honest, state)


@attrs.frozen(kw_only=True)
class BrittleSpring(_TestSpring):
    """F = k u up to ``|u| = limit``, then a non-finite force: no step can get past it."""

    name: ClassVar[str] = "test-brittle-spring"
    limit: float = bearingfw.parameter(low=0.0, low_open=True, unit="m")

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        return bearingfw.LawResponse(np.where(np.abs(u) > self.limit, np.nan, self.k * u), self.tangent(u), state)


@attrs.frozen(kw_only=True)
class StepLimitedSpring(_TestSpring):
    """F = k u, but a non-finite force for a time step above ``dt_max`` (like a law that integrates
    itself explicitly and must not be called with long steps): every step longer than that fails,
    whatever Newton does, and only halving the step helps."""

    name: ClassVar[str] = "test-step-limited-spring"
    dt_max: float = bearingfw.parameter(low=0.0, low_open=True, unit="s")

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        force = self.k * u if dt <= self.dt_max * (1 + 1e-12) else np.full_like(u, np.nan)
        return bearingfw.LawResponse(force, self.tangent(u), state)


@attrs.frozen(kw_only=True)
class GrumpySpring(_TestSpring):
    """F = k u up to ``|u| = limit``, then ``respond`` raises (a law bug, not a convergence problem)."""

    name: ClassVar[str] = "test-grumpy-spring"
    limit: float = bearingfw.parameter(low=0.0, low_open=True, unit="m")

    def initial_state(self, n):
        return {"slip": np.zeros((n, self.dims))}  # a "slip" in the state, but no slip() member

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        if np.any(np.abs(u) > self.limit):
            raise ValueError(f"test-grumpy-spring: |u| = {np.abs(u).max():.3g} m beyond {self.limit} m")
        return bearingfw.LawResponse(self.k * u, self.tangent(u), state)


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


def registry_with_test_laws(module_name: str = "bearingfw_transient_test_plugin"):
    """The installed plugins plus a test plugin registering :data:`TEST_LAWS` (a context manager)."""
    return registry_with(TEST_LAWS, "transient-test-laws", module_name)


# --- protocol v2: laws that ask for the velocity, dF/dN, per-bearing parameters ------------------
@attrs.frozen
class LinearDashpot:
    """A test-only viscous law ``F = c v`` (the kernel's trial velocity), per-bearing ``c``: the
    same force as a linear dashpot, so an SDOF on it must equal one with Rayleigh damping ``c = a0 m``."""

    name: ClassVar[str] = "test-linear-dashpot"
    rigid: ClassVar[bool] = False
    uses_velocity: ClassVar[bool] = True
    per_bearing: ClassVar[bool] = True
    c: float = bearingfw.parameter(low=0.0, low_open=True, unit="N s/m", per_bearing=True)
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        return None

    def respond(self, state, u, normal_force, dt, velocity):
        u = np.asarray(u, dtype=float)
        bearingfw.parameters.check_per_bearing(self, u.shape[0])
        c = np.asarray(self.c, dtype=float)[..., None]
        v = np.asarray(velocity, dtype=float)
        assert v.shape == u.shape
        dfdv = elastic_tangent(np.broadcast_to(self.c, (u.shape[0],)), u.shape[0], self.dims)
        return bearingfw.LawResponse(c * v, np.zeros_like(dfdv), state, dforce_dvelocity=dfdv)


#: respond() calls of :class:`CountingSpring` objects, by dims (reset by the tests)
LAW_CALLS: dict[int, int] = {}


@attrs.frozen
class CountingSpring:
    """A test-only per-bearing linear spring ``F = k u`` that counts its ``respond`` calls (by dims)
    and records how many connectors each call served."""

    name: ClassVar[str] = "test-counting-spring"
    rigid: ClassVar[bool] = False
    per_bearing: ClassVar[bool] = True
    k: float = bearingfw.parameter(low=0.0, low_open=True, unit="N/m", per_bearing=True)
    dims: int = bearingfw.dims_parameter()

    def initial_state(self, n):
        bearingfw.parameters.check_per_bearing(self, n)
        return None

    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        bearingfw.parameters.check_per_bearing(self, u.shape[0])
        LAW_CALLS[self.dims] = LAW_CALLS.get(self.dims, 0) + 1
        k = np.asarray(self.k, dtype=float)
        tangent = elastic_tangent(np.broadcast_to(k, (u.shape[0],)), u.shape[0], self.dims)
        return bearingfw.LawResponse(k[..., None] * u, tangent, state)


from bearingfw.laws.coulomb import RegularizedCoulomb  # noqa: E402


class CoupledCoulomb(RegularizedCoulomb):
    """Regularized Coulomb friction with its dF/dN in Newton (``normal_coupling``)."""

    name = "test-coupled-coulomb"
    normal_coupling = True


class LaggedCoulomb(RegularizedCoulomb):
    """The same law without ``normal_coupling``: the kernel lets its ``N`` lag one iteration."""

    name = "test-lagged-coulomb"
    normal_coupling = False


#: The protocol-v2 test laws, registered by :func:`registry_with_protocol_laws`.
PROTOCOL_LAWS = (LinearDashpot, CountingSpring, CoupledCoulomb, LaggedCoulomb, DoubledSpring)


def registry_with_protocol_laws(module_name: str = "bearingfw_protocol_test_plugin"):
    """The installed plugins plus a test plugin registering :data:`PROTOCOL_LAWS` (a context manager)."""
    return registry_with(PROTOCOL_LAWS, "protocol-test-laws", module_name)


def with_uplift(model: Model, names=None) -> Model:
    """``model`` with ``uplift=True`` on its PLANAR and AXIAL connectors (or those named)."""
    connectors = tuple(
        attrs.evolve(c, uplift=True) if c.kind != "join" and (names is None or c.name in names) else c
        for c in model.connectors
    )
    return attrs.evolve(model, connectors=connectors)
