"""Small models for the tuning tests: a cantilever, and a cantilever next to a separate mast."""

from __future__ import annotations

from bearingfw.model import FrameElement, Material, Model, Node, Section, Support

STEEL = Material("steel", 210e9, density=7850.0, nu=0.3)
LENGTH = 10.0


def beam_section(Iy: float = 4e-3, Iz: float = 1e-3) -> Section:
    # Iy governs vertical bending, Iz lateral; distinct so that the two planes have distinct modes
    return Section("beam", A=0.05, Iy=Iy, Iz=Iz, J=2e-3)


def cantilever(Iy: float = 4e-3, Iz: float = 1e-3, n: int = 10, mast: bool = False) -> Model:
    """A cantilever along x from B0 (clamped) to B{n}; with ``mast``, a separate vertical cantilever M0..M4."""
    nodes = [Node(f"B{k}", LENGTH * k / n, 0.0, 0.0) for k in range(n + 1)]
    section = beam_section(Iy, Iz)
    elements = [FrameElement(f"E{k}", f"B{k}", f"B{k + 1}", section, STEEL) for k in range(n)]
    supports = [Support("B0")]
    if mast:
        nodes += [Node(f"M{k}", 30.0, 0.0, 1.5 * k) for k in range(5)]
        slim = Section("mast", A=2e-3, Iy=1e-6, Iz=1e-6, J=2e-6)
        elements += [FrameElement(f"F{k}", f"M{k}", f"M{k + 1}", slim, STEEL) for k in range(4)]
        supports.append(Support("M0"))
    return Model(nodes, elements, supports=supports)


def beam_nodes(n: int = 10) -> list[str]:
    return [f"B{k}" for k in range(n + 1)]
