"""Small models and helpers shared by the transient tests (built with the kernel's public API)."""

from __future__ import annotations

from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.model import Connector, FrameElement, Material, Model, NodalMass, Node, Section, Support

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
