"""A bearingfw :class:`~bearingfw.model.Model` built again in OpenSeesPy, and analysed there.

:func:`build` walks the model's description (not bearingfw's matrices) and issues the OpenSees
commands for the same structure; :func:`gravity`, :func:`transient` and :func:`eigen` run the
analyses the validation scripts and the benchmark compare. What maps to what, and why:

==========================  ===================================================================
bearingfw                   OpenSees
==========================  ===================================================================
FrameElement (EB)           ``elasticBeamColumn`` with ``geomTransf Linear`` whose ``vecxz`` is
                            bearingfw's local z (:func:`bearingfw.model.assembly.frame_axes`),
                            ``-mass m -cMass`` (``m = rho A + added``). OpenSees's consistent
                            torsional mass is ``m J / A`` per length, bearingfw's ``rho (Iy + Iz)``
                            (the polar moment, without the added mass): the element gets
                            ``J' = rho (Iy + Iz) A / m`` and ``G' = G J / J'``, so that
                            ``G' J' = G J`` and both torsional masses are bearingfw's
TrussElement                ``Truss`` with an ``Elastic`` material, ``-rho (rho A + added)
                            -cMass 1 -doRayleigh 1`` (a truss takes no Rayleigh damping otherwise)
RigidLink                   ``rigidLink beam``; a chain (a master that is itself a slave) is
                            collapsed onto its root master, which is the same rigid body, because
                            OpenSees's Transformation handler does not follow chains (it
                            silently drops the inner link's offset)
Support, NodalMass          ``fix``, ``mass``
JOIN, tied directions       a ``zeroLength`` "tie" with stiffness ``K_TIE`` in the connector
                            frame (a penalty: equalDOF would chain with rigid links and with the
                            bearings' own links, see above)
vertical spring ``kv``      in the bearing element (below), plus a ``zeroLength`` dashpot
                            ``Elastic(0, eta = a1 kv)`` when the run has stiffness-proportional
                            damping: bearingfw's ``C = a0 M + a1 K_free`` includes ``kv`` (a
                            linear spring of the structure) but not the laws
``frictionless``            nothing in the law directions
``linear-spring`` k         ``zeroLength`` ``Elastic k`` in the law directions (with ``kv``)
``regularized-coulomb``     ``flatSliderBearing`` with ``frictionModel Coulomb mu``, ``kInit = k``
k, mu                       and axial ``Elastic kv``: it takes ``N`` from its axial force at every
                            trial, as bearingfw's law reads ``N = -kv d_z``. Between two extra
                            nodes with fixed rotations, linked to the connector's nodes by
                            ``K_TIE`` springs: the element adds P-Delta moments ``N du / 2`` to
                            both of its nodes' rotations (a real slider's shifting contact point),
                            which a bearingfw connector does not have (rotations free, no couple)
==========================  ===================================================================

Damping: ``rayleigh a0 0 a1 0`` (initial stiffness): frames take ``a0 M_e + a1 K_e``, nodes
``a0 m``; trusses with ``-doRayleigh 1``; zeroLength ties, springs and flat sliders have
``doRayleigh`` off by default, so the laws and the ties are undamped, as in bearingfw.

Gravity: a static step with the members' weight as ``eleLoad -beamUniform`` (the same
work-equivalent end forces as bearingfw's consistent load), truss weight at the ends and nodal
masses' weight, then ``loadConst -time 0``. The transient starts from there, at rest; the
ground acceleration is ``UniformExcitation`` in global x, y, z with ``Path`` series.

HHT: OpenSees's ``integrator HHT alpha`` uses ``alpha_OS`` in ``[2/3, 1]`` with
``gamma = 3/2 - alpha_OS``, ``beta = (2 - alpha_OS)^2 / 4``; bearingfw's ``alpha`` in
``[-1/3, 0]`` with ``gamma = 1/2 - alpha``, ``beta = (1 - alpha)^2 / 4``: the same scheme for
``alpha_OS = 1 + alpha`` (bearingfw's -0.05 is OpenSees's 0.95). One difference remains for
nonlinear elements: OpenSees evaluates the internal forces at the interpolated displacement
``U_{n+alpha_OS}`` (element state from step n), bearingfw interpolates the forces
``(1 + alpha) f(U_{n+1}) - alpha f(U_n)``. They agree for linear members, and for any element
when ``alpha = 0``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import attrs
import numpy as np

import _opensees

from bearingfw.model import ConnectorKind, FrameElement, Model, TrussElement
from bearingfw.model.assembly import frame_axes

__all__ = [
    "K_TIE_FACTOR",
    "Built",
    "Settings",
    "TransientRun",
    "build",
    "eigen",
    "ensure",
    "gravity",
    "opensees",
    "opensees_alpha",
    "path_values",
    "tie_stiffness",
    "transient",
]

#: Tie and link stiffness, as a multiple of the largest bearing stiffness (kv or a law's k): a
#: penalty whose compliance, about 1e-6 of the bearings', is far below the 1 % being checked.
K_TIE_FACTOR = 1e6
#: The vertical dashpot's direction and the three translations, as zeroLength directions.
_VERTICAL, _TRANSLATIONS = 3, (1, 2, 3)


def opensees_alpha(alpha: float) -> float:
    """OpenSees's ``integrator HHT`` parameter for bearingfw's HHT ``alpha`` (module docstring)."""
    return 1.0 + alpha


@attrs.define
class _Tags:
    """Running tag counters (OpenSees tags are positive integers, one space per kind)."""

    node: int
    element: int = 0
    material: int = 0
    transform: int = 0

    def next(self, kind: str) -> int:
        value = getattr(self, kind) + 1
        setattr(self, kind, value)
        return value


@attrs.frozen
class Built:
    """What :func:`build` created: tags to read results from."""

    nodes: dict  # bearingfw node name -> OpenSees tag
    bearings: dict  # law connector name -> (element tag, "slider" | "spring" | "none": how to read its law force)
    directions: dict  # connector name -> law directions (local indices)
    frames: tuple  # (FrameElement, local axes, element tag)
    k_tie: float
    n_nodes: int
    n_elements: int


def _root(master: str, slave_of: dict) -> str:
    seen = set()
    while master in slave_of:
        if master in seen:
            raise ValueError(f"rigid links form a loop through {master!r}")
        seen.add(master)
        master = slave_of[master]
    return master


def _frame_axes(model: Model) -> list[tuple[FrameElement, np.ndarray]]:
    """Every frame element with its local axes (rows x, y, z), as bearingfw computes them."""
    frames = [e for e in model.elements if isinstance(e, FrameElement)]
    if not frames:
        return []
    coords = model.coordinates
    xi = coords[[model.node_index(e.i) for e in frames]]
    xj = coords[[model.node_index(e.j) for e in frames]]
    orient = np.array([e.orientation if e.orientation is not None else (np.nan,) * 3 for e in frames], dtype=float)
    return list(zip(frames, frame_axes(xi, xj, orient), strict=True))


def _torsion_constant(e: FrameElement, mass_line: float) -> float:
    """``J'`` with OpenSees's torsional mass ``mass_line J' / A`` equal to bearingfw's ``rho (Iy + Iz)``
    (added mass has no rotary inertia in bearingfw); the element then gets ``G' = G J / J'``."""
    polar_mass = e.material.density * (e.section.Iy + e.section.Iz)
    if mass_line == 0.0:
        return e.section.J
    if polar_mass == 0.0:
        raise NotImplementedError(f"{e.name}: added mass on a member without density (no torsional mass)")
    return polar_mass * e.section.A / mass_line


def _frames(ops, model: Model, nodes: dict, tags: _Tags) -> list[tuple[FrameElement, np.ndarray, int]]:
    transforms: dict[tuple, int] = {}
    out = []
    for e, R in _frame_axes(model):
        if e.shear_deformation:
            raise NotImplementedError(f"{e.name}: Timoshenko members are not translated")
        if e.mass != "consistent":
            # OpenSees's lumped beam mass has no torsional inertia; bearingfw's has rho Ip L / 2.
            raise NotImplementedError(f"{e.name}: only the consistent mass is translated")
        key = tuple(np.round(R[2], 12))
        if key not in transforms:
            transforms[key] = tags.next("transform")
            ops.geomTransf("Linear", transforms[key], *map(float, R[2]))
        s, m = e.section, e.material
        mass_line = m.density * s.A + e.added_mass
        torsion = _torsion_constant(e, mass_line)
        tag = tags.next("element")
        ops.element(
            "elasticBeamColumn", tag, nodes[e.i], nodes[e.j], s.A, m.E, m.shear_modulus * s.J / torsion,
            torsion, s.Iy, s.Iz, transforms[key], "-mass", mass_line, "-cMass",
        )  # fmt: skip
        out.append((e, R, tag))
    return out


def _trusses(ops, model: Model, nodes: dict, tags: _Tags) -> None:
    materials: dict[float, int] = {}
    for e in model.elements:
        if not isinstance(e, TrussElement):
            continue
        if e.material.E not in materials:
            materials[e.material.E] = tags.next("material")
            ops.uniaxialMaterial("Elastic", materials[e.material.E], e.material.E)
        consistent = 1 if e.mass == "consistent" else 0
        mass_line = e.material.density * e.area + e.added_mass
        ops.element(
            "Truss", tags.next("element"), nodes[e.i], nodes[e.j], e.area, materials[e.material.E],
            "-rho", mass_line, "-cMass", consistent, "-doRayleigh", 1,
        )  # fmt: skip


def _zero_length(ops, tags: _Tags, i: int, j: int, rotation, stiffness: dict[int, float], damping: float = 0.0) -> int:
    """A zeroLength element in the frame ``rotation`` (rows: local x, y, z) with an elastic spring per
    direction (1..3 -> stiffness); ``damping`` > 0 makes a pure dashpot in direction 3 instead."""
    mats, dirs = [], []
    for d, k in stiffness.items():
        tag = tags.next("material")
        if damping:
            ops.uniaxialMaterial("Elastic", tag, 0.0, damping)
        else:
            ops.uniaxialMaterial("Elastic", tag, k)
        mats.append(tag)
        dirs.append(d)
    element = tags.next("element")
    R = np.asarray(rotation, dtype=float)
    ops.element("zeroLength", element, i, j, "-mat", *mats, "-dir", *dirs, "-orient", *R[0], *R[1])
    return element


def _isolated(ops, model: Model, nodes: dict, tags: _Tags, name: str, k_tie: float) -> int:
    """A node at ``name`` with fixed rotations, tied to it in translation (``k_tie``): a fully
    supported node is used as is (its rotations are fixed already)."""
    support = next((s for s in model.supports if s.node == name), None)
    if support is not None and len(support.dofs) == 6:
        return nodes[name]
    tag = tags.next("node")
    ops.node(tag, *map(float, model.node(name).xyz))
    ops.fix(tag, 0, 0, 0, 1, 1, 1)
    _zero_length(ops, tags, nodes[name], tag, np.eye(3), dict.fromkeys(_TRANSLATIONS, k_tie))
    return tag


def _connectors(ops, model: Model, nodes: dict, tags: _Tags, k_tie: float, a1: float) -> tuple[dict, dict]:
    bearings, directions = {}, {}
    friction = 0
    for c in model.connectors:
        R = c.rotation
        i, j = nodes[c.node_i], nodes[c.node_j]
        tied = dict.fromkeys((d + 1 for d in c.tied_directions), k_tie)
        if c.kind is ConnectorKind.JOIN:
            _zero_length(ops, tags, i, j, R, tied)
            continue
        if tied:
            _zero_length(ops, tags, i, j, R, tied)
        params = c.params
        governed = [d + 1 for d in c.law_directions]
        directions[c.name] = c.law_directions
        if c.law == "frictionless":
            bearings[c.name] = (_zero_length(ops, tags, i, j, R, {_VERTICAL: c.vertical_stiffness}), "none")
        elif c.law == "linear-spring":
            springs = {**dict.fromkeys(governed, params["k"]), _VERTICAL: c.vertical_stiffness}
            bearings[c.name] = (_zero_length(ops, tags, i, j, R, springs), "spring")
        elif c.law == "regularized-coulomb":
            friction += 1
            bi = _isolated(ops, model, nodes, tags, c.node_i, k_tie)
            bj = _isolated(ops, model, nodes, tags, c.node_j, k_tie)
            ops.frictionModel("Coulomb", friction, params["mu"])
            axial, other = tags.next("material"), tags.next("material")
            ops.uniaxialMaterial("Elastic", axial, c.vertical_stiffness)
            ops.uniaxialMaterial("Elastic", other, k_tie)  # torsion and rocking: the extra nodes' rotations are fixed
            element = tags.next("element")
            # local x (axial) = e_z, local y = e_x, so local z = e_z x e_x = e_y: shear y, z = connector x, y
            ops.element(
                "flatSliderBearing", element, bi, bj, friction, params["k"], "-P", axial, "-T", other,
                "-My", other, "-Mz", other, "-orient", *R[2], *R[0], "-iter", 50, 1e-12,
            )  # fmt: skip
            bearings[c.name] = (element, "slider")
        else:
            raise NotImplementedError(f"connector {c.name!r}: law {c.law!r} is not translated")
        if a1:
            _zero_length(ops, tags, i, j, R, {_VERTICAL: 1.0}, damping=a1 * c.vertical_stiffness)
    return bearings, directions


def tie_stiffness(model: Model) -> float:
    """``K_TIE_FACTOR`` times the stiffest bearing spring (``kv`` or a law's ``k``), at least 1e9 N/m."""
    stiffest = 1e9
    for c in model.connectors:
        stiffest = max(stiffest, c.vertical_stiffness or 0.0, float(c.params.get("k", 0.0)))
    return K_TIE_FACTOR * stiffest


def build(ops, model: Model, a1: float = 0.0, k_tie: float | None = None) -> Built:
    """Issue the OpenSees commands for ``model`` (after ``wipe``); ``a1``: Rayleigh's stiffness
    coefficient, for the vertical dashpots (module docstring)."""
    k_tie = tie_stiffness(model) if k_tie is None else k_tie
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    nodes = {n.name: k + 1 for k, n in enumerate(model.nodes)}
    for n in model.nodes:
        ops.node(nodes[n.name], float(n.x), float(n.y), float(n.z))
    tags = _Tags(node=len(nodes))
    for s in model.supports:
        ops.fix(nodes[s.node], *(int(c in s.dofs) for c in ("ux", "uy", "uz", "rx", "ry", "rz")))
    masses: dict[str, np.ndarray] = {}
    for m in model.masses:
        masses.setdefault(m.node, np.zeros(6))
        masses[m.node] += (m.mass, m.mass, m.mass, m.ixx, m.iyy, m.izz)
    for name, values in masses.items():
        ops.mass(nodes[name], *map(float, values))
    slave_of = {link.slave: link.master for link in model.rigid_links}
    for link in model.rigid_links:
        ops.rigidLink("beam", nodes[_root(link.master, slave_of)], nodes[link.slave])
    frames = _frames(ops, model, nodes, tags)
    _trusses(ops, model, nodes, tags)
    bearings, directions = _connectors(ops, model, nodes, tags, k_tie, a1)
    return Built(nodes, bearings, directions, tuple(frames), k_tie, tags.node, tags.element)


# --------------------------------------------------------------------------------------------
# Analyses


@attrs.frozen
class Settings:
    """OpenSees's solution options (see the benchmark's README section for the choice)."""

    system: str = "UmfPack"
    numberer: str = "RCM"
    test: tuple = ("NormDispIncr", 1e-10, 50)
    #: the ``algorithm`` command's arguments, e.g. ("Newton",) or ("KrylovNewton", "-iterate", "initial")
    algorithm: tuple = ("Newton",)


def _analysis_options(ops, settings: Settings) -> None:
    ops.constraints("Transformation")
    ops.numberer(settings.numberer)
    ops.system(settings.system)
    ops.test(*settings.test)
    ops.algorithm(*settings.algorithm)


def gravity(ops, model: Model, built: Built, g: float = 9.81, settings: Settings = Settings()) -> None:
    """The dead load in one static step, then held constant (``loadConst -time 0``)."""
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    coords = model.coordinates
    for e, R, tag in built.frames:
        w = (e.material.density * e.section.A + e.added_mass) * g
        wx, wy, wz = R @ np.array([0.0, 0.0, -w])
        ops.eleLoad("-ele", tag, "-type", "-beamUniform", float(wy), float(wz), float(wx))
    loads: dict[str, float] = {}
    for e in model.elements:
        if isinstance(e, TrussElement):
            length = np.linalg.norm(coords[model.node_index(e.j)] - coords[model.node_index(e.i)])
            half = (e.material.density * e.area + e.added_mass) * g * length / 2
            loads[e.i] = loads.get(e.i, 0.0) - half
            loads[e.j] = loads.get(e.j, 0.0) - half
    for m in model.masses:
        loads[m.node] = loads.get(m.node, 0.0) - m.mass * g
    for name, fz in loads.items():
        ops.load(built.nodes[name], 0.0, 0.0, float(fz), 0.0, 0.0, 0.0)
    _analysis_options(ops, settings)
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees gravity analysis failed")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()


@attrs.frozen
class TransientRun:
    """Histories (steps + 1 rows, the first at rest) and the wall time of the time loop."""

    time: np.ndarray
    displacement: dict  # node name -> (steps + 1, 3), from the gravity state
    force: dict  # connector name -> (steps + 1, law dims), the law force
    seconds: float
    setup_seconds: float
    #: flat sliders (``record_sliders``): name -> basic forces and deformations, (integration steps + 1, 6) each
    sliders: dict = attrs.field(factory=dict)


def _bearing_force(ops, built: Built, name: str) -> np.ndarray:
    element, kind = built.bearings[name]
    dirs = built.directions[name]
    if kind == "none":
        return np.zeros(len(dirs))
    q = ops.eleResponse(element, "basicForce")
    if kind == "slider":  # basic forces: axial (connector z), shear y (connector x), shear z (connector y)
        return np.array([q[1 + d] for d in dirs])
    return np.array([q[k] for k in range(len(dirs))])  # zeroLength: one per -dir, law directions first


def path_values(samples) -> list[float]:
    """A ``Path`` series' values: the samples with the last one repeated, because the series is 0
    from its last time on and the last step's time can land a round-off beyond it."""
    values = [float(v) for v in samples]
    return [*values, values[-1]]


def transient(
    ops,
    built: Built,
    ground_acceleration: np.ndarray,
    dt: float,
    *,
    alpha: float,
    rayleigh: tuple[float, float],
    nodes: Sequence[str] = (),
    bearings: Sequence[str] = (),
    substeps: int = 1,
    settings: Settings = Settings(),
    record_sliders: bool = False,
) -> TransientRun:
    """HHT (bearingfw's ``alpha``, mapped) under ``ground_acceleration`` (steps + 1, 3) in global
    x, y, z sampled every ``dt``, integrated at ``dt / substeps``; records every record sample
    (``record_sliders``: also the flat sliders' basic forces and deformations at every integration
    step, for evidence)."""
    start = time.perf_counter()
    ag = np.asarray(ground_acceleration, dtype=float)
    for d in range(3):
        tag = 10 + d
        ops.timeSeries("Path", tag, "-dt", float(dt), "-values", *path_values(ag[:, d]))
        ops.pattern("UniformExcitation", tag, d + 1, "-accel", tag)
    a0, a1 = rayleigh
    ops.rayleigh(float(a0), 0.0, float(a1), 0.0)
    _analysis_options(ops, settings)
    ops.integrator("HHT", opensees_alpha(alpha))
    ops.analysis("Transient")
    tags = [built.nodes[n] for n in nodes]
    base = {n: np.array(ops.nodeDisp(t)[:3]) for n, t in zip(nodes, tags, strict=True)}

    def sample():
        return (
            [np.array(ops.nodeDisp(t)[:3]) for t in tags],
            [_bearing_force(ops, built, b) for b in bearings],
        )

    rows = [sample()]
    sliders = {b: built.bearings[b][0] for b in bearings if built.bearings[b][1] == "slider"}
    def slider_sample():
        return [(ops.eleResponse(t, "basicForce"), ops.eleResponse(t, "basicDeformation")) for t in sliders.values()]

    slider_rows = [slider_sample()]
    h = dt / substeps
    setup = time.perf_counter() - start
    loop = time.perf_counter()
    for k in range(len(ag) - 1):
        for _ in range(substeps):
            if ops.analyze(1, h) != 0:
                raise RuntimeError(f"OpenSees transient failed at step {k + 1}")
            if record_sliders:  # every integration step: evidence of what each step committed
                slider_rows.append(slider_sample())
        rows.append(sample())
    seconds = time.perf_counter() - loop
    disp = {n: np.array([r[0][i] for r in rows]) - base[n] for i, n in enumerate(nodes)}
    force = {b: np.array([r[1][i] for r in rows]) for i, b in enumerate(bearings)}
    slider_data = {}
    if record_sliders:
        for i, b in enumerate(sliders):
            slider_data[b] = (np.array([r[i][0] for r in slider_rows]), np.array([r[i][1] for r in slider_rows]))
    return TransientRun(np.arange(len(ag)) * dt, disp, force, seconds, setup, slider_data)


def eigen(ops, count: int) -> np.ndarray:
    """The ``count`` lowest natural frequencies (Hz)."""
    try:
        values = ops.eigen(count)
    except Exception:  # noqa: BLE001 - small systems: Arpack needs more DOFs than modes
        values = ops.eigen("-fullGenLapack", count)
    return np.sqrt(np.asarray(values, dtype=float)) / (2.0 * np.pi)


def opensees():
    """``openseespy.opensees`` (see :mod:`_opensees` for the library path on Linux)."""
    return _opensees.import_opensees()


def ensure() -> None:
    """For scripts: make OpenSeesPy importable, re-executing with ``LD_LIBRARY_PATH`` if needed."""
    _opensees.ensure_opensees()
