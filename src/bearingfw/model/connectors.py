"""Connectors (bearings): description, and the sparse operators the analyses work with.

A connector joins node ``i`` (support side: pier top, abutment) and node ``j`` (girder side:
bearing soffit), which coincide. Its local frame has rows ``e_x`` (longitudinal), ``e_y``
(transverse), ``e_z`` (vertical), built from ``x_axis`` and ``z_axis``: ``e_z = z / |z|``,
``e_x`` = ``x_axis`` made orthogonal to ``e_z``, ``e_y = e_z x e_x``. The relative translation
in that frame is ``d = R (u_j - u_i)``. Rotations are free (a pot bearing rotates).

``e_z`` must point up (``e_z . Z > 0``; it may be tilted, e.g. normal to a sloping sliding
plane): it is the direction in which the girder (node ``j``) presses on the bearing, so that
the normal force ``N`` is positive in compression whatever the frame. A frame with ``e_z``
pointing down would silently flip the sign of ``N`` (and a friction law would then see no
contact), so it is rejected.

=========  ==========================  ==========================================
kind       vertical ``d_z``            horizontal ``d_x``, ``d_y``
=========  ==========================  ==========================================
JOIN       tied                        both tied
PLANAR     spring ``vertical_stiffness``  both governed by the law, ``dims = 2``
AXIAL      spring ``vertical_stiffness``  ``guided`` one by the law (``dims = 1``), the other tied
=========  ==========================  ==========================================

The vertical direction of a sliding bearing is a stiff user-given spring, not a tie: its
deformation ``d_z`` gives the normal force ``N = -kv d_z`` that a friction law reads at every
step (dead load plus vertical dynamics) without a constraint force solve. Choose
``vertical_stiffness`` as the bearing's real vertical stiffness (pot bearings: some GN/m); it
also enters the modal analysis.

Uplift: with ``uplift=True`` (PLANAR and AXIAL) the vertical spring is compression-only. It
then leaves the linear stiffness ``K`` and its row ``e_z`` becomes a governed row of ``B``,
ruled by an internal law, :class:`CompressionOnlyGap`: ``F_z = kv d_z`` while the bearing is
closed (``d_z <= 0``, the *total* ``d_z`` from the undeformed geometry, dead load included), zero
when the gap is open (``d_z > 0``): no vertical stiffness and ``N = 0``, so no friction capacity.
It closes again under compression. Its ``N = -kv d_z`` still comes from ``V`` (clamped at zero
before a law sees it), which is exact whenever the gap is closed.

A law is built with :func:`bearingfw.create_law` from its name and parameters; connectors
that share (law, parameters, dims) share one law object (vectorised over them). A law class that
declares ``per_bearing = True`` (:mod:`bearingfw.protocol`) gets one object for all its
connectors of the same ``dims`` (and equal non-numeric parameters): parameters equal over them
stay scalars, differing ones become arrays in connector order, so the kernel calls it once per
Newton iteration however many bearings it governs. If the law is ``rigid`` its directions are
tied like JOIN's. Tied directions become constraint equations (:mod:`bearingfw.model.constraints`),
never penalty springs.

Operators (full DOF numbering, ``n_dof`` columns):

- ``D`` (3 per connector): every relative translation, row ``3 c + k`` = ``e_k . (u_j - u_i)``.
- ``B`` (rows of ``D`` governed by non-rigid laws), grouped law by law: group ``g`` owns rows
  ``g.rows``, connector-major then direction, so ``(B u)[g.rows].reshape(n, dims)`` is the
  ``u`` its law takes. Law forces assemble as ``B^T f`` and tangents as ``B^T K_t B``. The
  ``e_z`` rows of uplift connectors come last, in one group of the internal gap law
  (``gap_rows``).
- ``V`` (the ``e_z`` rows of connectors with a vertical spring): the vertical spring force is
  ``F_z = kv * (V u)``; the bearing's compressive normal force is ``N = -F_z = -kv * (V u)``
  (compression positive: node ``j`` pressed down onto ``i``; :func:`normal_force`). Only the
  springs without uplift enter ``K`` (:meth:`ConnectorOperators.spring_stiffness`).

Sign of connector forces: ``F = R (force the connector exerts on node i)``, i.e. the force
resisting ``d``; a linear spring gives ``F = +k d`` and the force on node ``j`` is ``-F``.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.model._fields import ModelError, choice, name_field, node_ref, vector3
from bearingfw.model.dofs import DofMap
from bearingfw.model.equations import Equation
from bearingfw.parameters import ParameterError, parameter
from bearingfw.plugins import Registry, UnknownLawError, create_law, describe_parameters, get_registry
from bearingfw.protocol import BearingLaw, CompiledLaw, LawResponse, law_flag

__all__ = [
    "ConnectorKind",
    "Connector",
    "LawGroup",
    "ConnectorOperators",
    "CompressionOnlyGap",
    "build_connector_operators",
    "connector_frame",
    "axes_from_rotation",
    "normal_force",
    "LOCAL_DIRECTIONS",
]

LOCAL_DIRECTIONS = ("x", "y", "z")


class ConnectorKind(enum.StrEnum):
    """Abaqus-style connector kinds used by the paper for the pot bearings."""

    JOIN = "join"  # fixed pot bearing
    PLANAR = "planar"  # multidirectional sliding
    AXIAL = "axial"  # guided sliding


def _to_kind(value):
    if isinstance(value, ConnectorKind):
        return value
    if isinstance(value, str):
        try:
            return ConnectorKind(value.lower())
        except ValueError:
            return value
    return value


def _to_params(value):
    if value is None:
        return ()
    if isinstance(value, Mapping):
        return tuple(sorted(value.items()))
    return value


def normal_force(local_force_z):
    """The compressive normal force ``N = -F_z`` from a connector's local vertical force ``F_z``.

    ``F_z`` resists ``d_z`` (module docstring: positive when the bearing is pulled apart), so a
    bearing pressed together has ``F_z < 0`` and ``N > 0``.
    """
    return -np.asarray(local_force_z, dtype=float)


def axes_from_rotation(rotation) -> dict[str, tuple[float, float, float]]:
    """``x_axis`` and ``z_axis`` keywords for a :class:`Connector` from a rotation matrix.

    ``rotation`` has the local axes as rows (``d = R (u_j - u_i)``); it must be orthonormal and
    right-handed.
    """
    R = np.asarray(rotation, dtype=float)
    if R.shape != (3, 3) or not np.allclose(R @ R.T, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise ModelError(f"connector frame: rotation must be a proper 3x3 rotation matrix, got {R.tolist()!r}")
    return {"x_axis": tuple(R[0].tolist()), "z_axis": tuple(R[2].tolist())}


def connector_frame(x_axis: Sequence[float], z_axis: Sequence[float]) -> np.ndarray:
    """Orthonormal rows ``e_x, e_y, e_z``: ``e_z`` along ``z_axis``, ``e_x`` the part of ``x_axis`` normal to it."""
    ez = np.asarray(z_axis, dtype=float)
    ez = ez / np.linalg.norm(ez)
    ex = np.asarray(x_axis, dtype=float)
    ex = ex - (ex @ ez) * ez
    norm = np.linalg.norm(ex)
    if norm < 1e-9 * np.linalg.norm(x_axis):
        raise ModelError("connector frame: x_axis is parallel to z_axis")
    ex = ex / norm
    return np.array([ex, np.cross(ez, ex), ez])


@attrs.frozen
class Connector:
    """A bearing between ``node_i`` (support side) and ``node_j`` (girder side).

    ``law`` (a registered law name) and ``law_params`` govern the horizontal directions of
    PLANAR and AXIAL connectors; JOIN takes neither. ``vertical_stiffness`` (N/m) is required
    for PLANAR and AXIAL and not taken by JOIN. ``guided`` is the AXIAL connector's governed
    local direction, ``"x"`` (longitudinally guided, the default) or ``"y"``; other kinds take
    none. ``z_axis`` must point up (module docstring). ``uplift=True`` (PLANAR and AXIAL) makes
    the vertical spring compression-only: the bearing lifts off instead of pulling (module
    docstring); the default False keeps the linear spring.
    """

    name: str = name_field()
    node_i: str = node_ref("support-side node (pier top)")
    node_j: str = node_ref("girder-side node (soffit)")
    kind: ConnectorKind = attrs.field(converter=_to_kind)
    law: str | None = attrs.field(default=None)
    law_params: tuple[tuple[str, Any], ...] = attrs.field(default=(), converter=_to_params)
    vertical_stiffness: float | None = parameter(optional=True, low=0.0, low_open=True, unit="N/m", doc="vertical spring")
    guided: str | None = choice(
        LOCAL_DIRECTIONS[:2], default=None, optional=True, doc="AXIAL: the governed local direction (default x)"
    )
    x_axis: tuple[float, float, float] = vector3(default=(1.0, 0.0, 0.0), nonzero=True, doc="local x (longitudinal)")
    z_axis: tuple[float, float, float] = vector3(default=(0.0, 0.0, 1.0), nonzero=True, doc="local z (vertical)")
    uplift: bool = attrs.field(default=False, metadata={"doc": "compression-only vertical spring (lift-off)"})
    _rotation: np.ndarray = attrs.field(init=False, repr=False, eq=False)

    def __attrs_post_init__(self):
        me = f"connector {self.name!r}"
        if not isinstance(self.kind, ConnectorKind):
            raise ModelError(f"{me}: field 'kind' must be one of join, planar, axial; got {self.kind!r}")
        if self.node_i == self.node_j:
            raise ModelError(f"{me}: fields 'node_i' and 'node_j' name the same node {self.node_i!r}")
        if not isinstance(self.law_params, tuple) or not all(
            isinstance(p, tuple) and len(p) == 2 and isinstance(p[0], str) for p in self.law_params
        ):
            raise ModelError(f"{me}: field 'law_params' must be a mapping of parameter names to values")
        if "dims" in dict(self.law_params):
            raise ModelError(f"{me}: field 'law_params' must not set 'dims' (the connector kind sets it)")
        try:
            hash(self.law_params)
        except TypeError:
            raise ModelError(f"{me}: field 'law_params' must hold hashable values (numbers, strings)") from None
        if not isinstance(self.uplift, (bool, np.bool_)):
            raise ModelError(f"{me}: field 'uplift' must be True or False, got {self.uplift!r}")
        object.__setattr__(self, "uplift", bool(self.uplift))
        if self.kind is ConnectorKind.JOIN:
            if self.uplift:
                raise ModelError(
                    f"{me}: field 'uplift' applies to PLANAR and AXIAL connectors (their vertical spring can "
                    "lift off); a JOIN connector ties the vertical direction, so it cannot lift: model a bearing "
                    "that can lift as a PLANAR or AXIAL connector"
                )
            if self.law is not None or self.law_params:
                raise ModelError(f"{me}: field 'law' must be None for a JOIN connector (it ties every direction)")
            if self.vertical_stiffness is not None:
                raise ModelError(
                    f"{me}: field 'vertical_stiffness' must be None for a JOIN connector (vertical is tied)"
                )
        else:
            if not isinstance(self.law, str) or not self.law:
                raise ModelError(f"{me}: field 'law' must name a bearing law for a {self.kind.value.upper()} connector")
            if self.vertical_stiffness is None:
                raise ModelError(
                    f"{me}: field 'vertical_stiffness' is required for a {self.kind.value.upper()} connector"
                )
        if self.kind is ConnectorKind.AXIAL:
            if self.guided is None:
                object.__setattr__(self, "guided", "x")
        elif self.guided is not None:
            raise ModelError(
                f"{me}: field 'guided' applies to AXIAL connectors only; a {self.kind.value.upper()} connector "
                f"{'governs both horizontal directions' if self.kind is ConnectorKind.PLANAR else 'ties them'}"
            )
        try:
            rotation = connector_frame(self.x_axis, self.z_axis)
        except ModelError:
            raise ModelError(f"{me}: fields 'x_axis' and 'z_axis' are parallel") from None
        if not rotation[2, 2] > 0.0:
            raise ModelError(
                f"{me}: field 'z_axis' {self.z_axis} must point up (a positive global z component): it is the "
                "direction in which the girder presses on the bearing, and N > 0 in compression"
            )
        rotation.setflags(write=False)
        object.__setattr__(self, "_rotation", rotation)

    @property
    def rotation(self) -> np.ndarray:
        """Rows ``e_x, e_y, e_z`` of the local frame in global axes."""
        return self._rotation

    @property
    def params(self) -> dict[str, Any]:
        return dict(self.law_params)

    @property
    def dims(self) -> int:
        """Directions the law governs: 2 (PLANAR), 1 (AXIAL), 0 (JOIN)."""
        return {ConnectorKind.JOIN: 0, ConnectorKind.PLANAR: 2, ConnectorKind.AXIAL: 1}[self.kind]

    @property
    def law_directions(self) -> tuple[int, ...]:
        """Local directions (0 = x, 1 = y) given to the law, in the order of its ``u`` columns."""
        if self.kind is ConnectorKind.PLANAR:
            return (0, 1)
        if self.kind is ConnectorKind.AXIAL:
            return (LOCAL_DIRECTIONS.index(self.guided),)
        return ()

    @property
    def tied_directions(self) -> tuple[int, ...]:
        """Local directions tied by the kind itself (a rigid law adds its ``law_directions``)."""
        if self.kind is ConnectorKind.JOIN:
            return (0, 1, 2)
        if self.kind is ConnectorKind.AXIAL:
            return (1 - LOCAL_DIRECTIONS.index(self.guided),)
        return ()

    @property
    def law_key(self) -> tuple:
        """Connectors with equal keys share one law object."""
        return (self.law, self.law_params, self.dims)


@attrs.frozen(eq=False)
class LawGroup:
    """One law object and the connectors it governs (model order).

    ``velocity`` and ``coupling``: the law's protocol flags ``uses_velocity`` and
    ``normal_coupling``; ``gap``: the internal compression-only gap law of uplift connectors
    (its rows are the connectors' vertical ``e_z`` rows, not law directions).
    """

    law: BearingLaw
    connectors: np.ndarray  # indices into Model.connectors
    rows: slice  # rows of B
    springs: np.ndarray  # rows of V (vertical springs) of these connectors, for N
    velocity: bool = attrs.field(default=None)
    coupling: bool = attrs.field(default=None)
    gap: bool = False

    def __attrs_post_init__(self):
        if self.velocity is None:
            object.__setattr__(self, "velocity", law_flag(self.law, "uses_velocity"))
        if self.coupling is None:
            object.__setattr__(self, "coupling", law_flag(self.law, "normal_coupling"))

    @property
    def n(self) -> int:
        return int(self.connectors.size)

    @property
    def dims(self) -> int:
        return int(self.law.dims)


@attrs.frozen(eq=False)
class CompressionOnlyGap:
    """The vertical spring of uplift connectors (module docstring), an internal law of the kernel.

    ``u`` (n, 1) is the total vertical relative displacement ``d_z`` (zero at the undeformed
    geometry); the force resisting it is ``kv d_z`` while closed (``d_z <= 0``) and zero when
    open, the tangent ``kv`` or zero. It has no state: the gap is elastic.
    """

    name: ClassVar[str] = "compression-only gap"
    rigid: ClassVar[bool] = False
    dims: ClassVar[int] = 1
    kv: np.ndarray  # (n,) vertical stiffness, N/m

    def initial_state(self, n: int) -> None:
        return None

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        d = np.asarray(u, dtype=float)
        kv = self.kv[:, None]
        closed = d <= 0.0
        force = np.where(closed, kv * d, 0.0)
        tangent = np.where(closed, kv, 0.0)[:, :, None]
        return LawResponse(force, tangent, state)

    def compiled(self, n: int) -> CompiledLaw:
        """The gap as a compiled law (:func:`bearingfw.model.gap_kernel.compression_only_gap`; no state)."""
        from bearingfw.model.gap_kernel import compression_only_gap

        return CompiledLaw(
            compression_only_gap, np.array(self.kv, dtype=float), 0, pack=lambda state: np.zeros(0), unpack=lambda array: None
        )


def _make_law(name: str, params: dict, dims: int, registry: Registry, who: str) -> BearingLaw:
    try:
        cls = registry.law_class(name)
        # dims is set by the connector kind when the law takes it; otherwise it is fixed (a
        # class attribute) and must match.
        if "dims" in {d["name"] for d in describe_parameters(cls)}:
            law = create_law(name, registry=registry, dims=dims, **params)
        else:
            law = create_law(name, registry=registry, **params)
    except UnknownLawError as exc:
        raise ModelError(f"{who}: field 'law': {exc}") from exc
    except ParameterError as exc:
        raise ModelError(f"{who}: field 'law_params': {exc}") from exc
    if law.dims != dims:
        raise ModelError(
            f"{who}: field 'law': law {name!r} governs {law.dims} direction(s); the connector needs {dims}"
        )
    return law


@attrs.frozen(eq=False)
class ConnectorOperators:
    """The sparse maps from global displacements to connector quantities (module docstring).

    ``uplift`` (bool per spring row): the compression-only springs, ruled by the gap group (the
    last of ``groups`` when there is one) instead of entering ``K``.
    """

    D: sp.csr_matrix
    B: sp.csr_matrix
    V: sp.csr_matrix
    kv: np.ndarray
    spring_connectors: np.ndarray
    groups: tuple[LawGroup, ...]
    ties: tuple[tuple[int, int], ...]  # (connector, local direction) pairs tied as constraints
    governed: tuple[tuple[int, int], ...]  # (connector, local direction) per row of B
    translations: np.ndarray  # (n, 2, 3): translation DOFs of node i and node j
    uplift: np.ndarray = attrs.field(default=None)
    #: whether any group's law uses the velocity, or declares dF/dN
    any_velocity: bool = attrs.field(init=False)
    any_coupling: bool = attrs.field(init=False)
    #: the rows of B of the laws with dF/dN and the spring row (N) of each (:meth:`normal_derivatives`)
    coupling_rows: np.ndarray = attrs.field(init=False)
    coupling_springs: np.ndarray = attrs.field(init=False)
    #: per group, what :meth:`respond` needs on every call: ``(group, rows, (n, dims), springs)``,
    #: ``springs`` a slice where they are consecutive (a view instead of a copy)
    _calls: tuple = attrs.field(init=False, repr=False)

    def __attrs_post_init__(self):
        if self.uplift is None:
            object.__setattr__(self, "uplift", np.zeros(self.kv.size, dtype=bool))
        object.__setattr__(self, "any_velocity", any(g.velocity for g in self.groups))
        object.__setattr__(self, "any_coupling", any(g.coupling for g in self.groups))
        coupled = [g for g in self.groups if g.coupling]
        rows = [np.arange(g.rows.start, g.rows.stop) for g in coupled]
        springs = [np.repeat(g.springs, g.dims) for g in coupled]
        object.__setattr__(self, "coupling_rows", np.concatenate(rows) if rows else np.zeros(0, dtype=int))
        object.__setattr__(self, "coupling_springs", np.concatenate(springs) if springs else np.zeros(0, dtype=int))
        calls = []
        for g in self.groups:
            springs = np.asarray(g.springs)
            first = int(springs[0]) if springs.size else 0
            consecutive = np.array_equal(springs, np.arange(first, first + springs.size))
            if springs.ndim == 1 and springs.dtype.kind in "iu" and consecutive:
                springs = slice(first, first + springs.size)
            calls.append((g, g.rows, (g.n, g.dims), springs))
        object.__setattr__(self, "_calls", tuple(calls))

    @property
    def n_connectors(self) -> int:
        return self.D.shape[0] // 3

    @property
    def n_governed(self) -> int:
        return self.B.shape[0]

    @property
    def gap_group(self) -> LawGroup | None:
        """The group of the internal compression-only gap law (None without uplift connectors)."""
        return self.groups[-1] if self.groups and self.groups[-1].gap else None

    @property
    def gap_rows(self) -> np.ndarray:
        """Rows of ``B`` ruled by the gap law: the ``e_z`` rows of the uplift connectors."""
        g = self.gap_group
        return np.arange(g.rows.start, g.rows.stop) if g is not None else np.zeros(0, dtype=int)

    # ---- pure helpers over flat vectors ---------------------------------------------------
    def split(self, d: np.ndarray) -> list[np.ndarray]:
        """Governed displacements ``d = B u`` (flat) -> per group ``(n, dims)`` arrays."""
        return [d[g.rows].reshape(g.n, g.dims) for g in self.groups]

    def normal_forces(self, v: np.ndarray) -> np.ndarray:
        """Compressive normal force of each spring connector from ``v = V u`` (``N = -kv v``)."""
        return normal_force(self.kv * v)

    def initial_states(self) -> tuple:
        return tuple(g.law.initial_state(g.n) for g in self.groups)

    def respond(
        self,
        states: Sequence,
        d: np.ndarray,
        N_springs: np.ndarray,
        dt: float,
        reference: np.ndarray | None = None,
        velocity: np.ndarray | None = None,
    ) -> list[LawResponse]:
        """Call every law at governed displacements ``d`` (flat) with normal forces per spring row.

        The laws see ``d - reference``: ``reference`` is the governed displacement at which
        their displacement is zero (``StaticResult.law_reference``; bearings set after the dead
        load), default zero. The protocol's ``normal_force`` is ``>= 0``: uplift (``N < 0``)
        reaches the law as 0. ``velocity`` (flat, like ``d``): the trial velocities, given to the
        laws that declare ``uses_velocity`` (zeros when None: static calls); the others never
        receive the keyword.
        """
        contact = np.maximum(N_springs, 0.0)
        if reference is not None:
            d = d - reference
        out = []
        for (g, rows, shape, springs), state in zip(self._calls, states, strict=True):
            u = d[rows].reshape(shape)
            try:
                if g.velocity:
                    v = np.zeros_like(u) if velocity is None else velocity[rows].reshape(shape)
                    response = g.law.respond(state, u, contact[springs], dt, velocity=v)
                else:
                    response = g.law.respond(state, u, contact[springs], dt)
            except Exception as exc:  # the law's own error, kept as it is, with where it came from
                exc.add_note(f"raised by law {getattr(g.law, 'name', type(g.law).__name__)!r} in respond() "
                             f"(a group of {g.n} connector(s))")
                raise
            _check_response(g, response, shape)
            out.append(response)
        return out

    def forces(self, responses: Sequence[LawResponse]) -> np.ndarray:
        """Flat law forces aligned with the rows of ``B`` (assemble with ``B.T @ f``)."""
        if not self.groups:
            return np.zeros(0)
        if len(responses) == 1:  # one law for every bearing (the usual case): no copy
            return np.asarray(responses[0].force, dtype=float).reshape(-1)
        return np.concatenate([np.asarray(r.force, dtype=float).reshape(-1) for r in responses])

    def tangent_blocks(self, responses: Sequence[LawResponse], rate: float = 0.0) -> list[np.ndarray]:
        """The laws' tangents per group, ``(n, dims, dims)``: ``tangent``, plus ``rate`` times
        ``dforce_dvelocity`` for laws that use the velocity (``rate = dv/du`` of the integrator,
        ``gamma / (beta h)`` for HHT; 0 in static analyses)."""
        blocks = []
        for g, r in zip(self.groups, responses, strict=True):
            t = np.asarray(r.tangent, dtype=float)
            if g.velocity and rate and r.dforce_dvelocity is not None:
                t = t + rate * np.asarray(r.dforce_dvelocity, dtype=float)
            blocks.append(t)
        return blocks

    def tangent(self, responses: Sequence[LawResponse], rate: float = 0.0) -> sp.csr_matrix:
        """Block-diagonal law tangent (n_governed x n_governed); assemble with ``B.T @ Kt @ B``
        (``rate``: :meth:`tangent_blocks`)."""
        rows, cols, vals = [], [], []
        for g, t in zip(self.groups, self.tangent_blocks(responses, rate), strict=True):
            n, m = g.n, g.dims
            base = g.rows.start + m * np.arange(n)
            idx = base[:, None] + np.arange(m)[None, :]
            rows.append(np.repeat(idx, m, axis=1).reshape(-1))
            cols.append(np.tile(idx, (1, m)).reshape(-1))
            vals.append(t.reshape(-1))
        if not rows:
            return sp.csr_matrix((0, 0))
        k = self.n_governed
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(k, k))

    def normal_derivatives(
        self, responses: Sequence[LawResponse], N_springs: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``d f / d N`` of the laws that declare ``normal_coupling``, as triplets ``(rows of B,
        spring rows, values)`` (the rows and springs are :attr:`coupling_rows` and
        :attr:`coupling_springs`): zero where ``N <= 0``, where the kernel's clamp ``max(N, 0)``
        holds the law's normal force at zero, and for a response without ``dforce_dnormal``."""
        values = [
            np.zeros(g.n * g.dims) if r.dforce_dnormal is None else np.asarray(r.dforce_dnormal, dtype=float).reshape(-1)
            for g, r in zip(self.groups, responses, strict=True)
            if g.coupling
        ]
        if not values:
            return self.coupling_rows, self.coupling_springs, np.zeros(0)
        values = values[0] if len(values) == 1 else np.concatenate(values)
        return self.coupling_rows, self.coupling_springs, values * (np.asarray(N_springs)[self.coupling_springs] > 0.0)

    def spring_stiffness(self) -> sp.csr_matrix:
        """``V^T diag(kv) V`` of the linear vertical springs (uplift springs excluded), full DOFs."""
        if not self.uplift.any():
            return (self.V.T @ sp.diags(self.kv) @ self.V).tocsr()
        keep = np.flatnonzero(~self.uplift)
        V = self.V[keep]
        return (V.T @ sp.diags(self.kv[keep]) @ V).tocsr()

    def tie_equations(self) -> list[Equation]:
        eqs = []
        for c, k in self.ties:
            row = self.D.getrow(3 * c + k)
            dofs, coeffs = row.indices.copy(), row.data.copy()
            # Prefer eliminating the girder-side node j, then the support side i.
            i_side, j_side = (tuple(int(d) for d in self.translations[c, s]) for s in (0, 1))
            eqs.append(Equation(dofs, coeffs, "connector", c, k, (j_side, i_side)))
        return eqs


def _has_shape(array, shape: tuple) -> bool:
    """An optional array of a response: absent (None), or an ndarray of ``shape``."""
    return array is None or (type(array) is np.ndarray and array.shape == shape)


def _check_response(g: LawGroup, response, shape: tuple | None = None) -> None:
    """Refuse a response whose arrays do not have the shapes the protocol gives (a wrong shape would
    otherwise broadcast into a numpy error, or a plausible answer, far from the law that made it).
    ``shape``: ``(g.n, g.dims)`` when the caller has it."""
    shape = shape or (g.n, g.dims)
    n, dims = shape
    force, tangent = getattr(response, "force", None), getattr(response, "tangent", None)
    if (  # the usual case, in a few attribute reads
        type(force) is np.ndarray
        and type(tangent) is np.ndarray
        and force.shape == shape
        and tangent.shape == (n, dims, dims)
        and force.dtype.kind == "f"
        and tangent.dtype.kind == "f"
        and (not g.coupling or _has_shape(response.dforce_dnormal, (n, dims)))
        and (not g.velocity or _has_shape(response.dforce_dvelocity, (n, dims, dims)))
    ):
        return
    try:
        shapes = [("force", np.shape(response.force), (n, dims)), ("tangent", np.shape(response.tangent), (n, dims, dims))]
        if g.coupling and response.dforce_dnormal is not None:
            shapes.append(("dforce_dnormal", np.shape(response.dforce_dnormal), (n, dims)))
        if g.velocity and response.dforce_dvelocity is not None:
            shapes.append(("dforce_dvelocity", np.shape(response.dforce_dvelocity), (n, dims, dims)))
    except AttributeError:
        raise ModelError(
            f"law {getattr(g.law, 'name', type(g.law).__name__)!r}: respond() must return a LawResponse, got "
            f"{type(response).__name__}"
        ) from None
    for field, got, expected in shapes:
        if got != expected:
            raise ModelError(
                f"law {getattr(g.law, 'name', type(g.law).__name__)!r}: respond() returned {field!r} of shape {got} "
                f"for {n} connector(s) with dims = {dims}; it must have shape {expected}"
            )
    for field in ("force", "tangent"):  # a complex or object array would be cast, or warn, far from the law
        kind = np.asarray(getattr(response, field)).dtype.kind
        if kind not in "fiu":
            raise ModelError(
                f"law {getattr(g.law, 'name', type(g.law).__name__)!r}: respond() returned {field!r} of dtype "
                f"{np.asarray(getattr(response, field)).dtype}; it must hold real numbers (float)"
            )


def _group_key(con: Connector, registry: Registry) -> tuple:
    """Connectors with equal keys are governed by one law object: ``(law, params, dims)``, or
    ``(law, dims)`` for a law class that declares ``per_bearing`` (module docstring)."""
    try:
        cls = registry.law_class(con.law)
    except UnknownLawError:
        return con.law_key  # reported when the law is made
    if law_flag(cls, "per_bearing") and attrs.has(cls):
        return ("per-bearing", con.law, con.dims)
    return con.law_key


def _field_alias(field: attrs.Attribute) -> str:
    return getattr(field, "alias", None) or field.name.lstrip("_")


def _per_bearing_laws(
    name: str, dims: int, members: list[int], connectors, registry: Registry
) -> list[tuple[BearingLaw, list[int]]]:
    """One law object per set of equal non-numeric parameters of a per-bearing law's connectors,
    its numeric parameters arrays in connector order where they differ (module docstring)."""
    made: dict[tuple, BearingLaw] = {}
    for c in members:
        key = connectors[c].law_key
        if key not in made:
            made[key] = _make_law(name, dict(key[1]), dims, registry, f"connector {connectors[c].name!r}")
    first = made[connectors[members[0]].law_key]
    fields = [f for f in attrs.fields(type(first)) if f.init]
    numeric = [f for f in fields if f.metadata.get("per_bearing")]
    others = [f for f in fields if not f.metadata.get("per_bearing")]
    subsets: dict[tuple, list[int]] = {}
    for c in members:
        law = made[connectors[c].law_key]
        try:
            key = tuple(getattr(law, f.name) for f in others)
            hash(key)
        except TypeError:  # an unhashable non-numeric parameter: one object per parameter set
            key = connectors[c].law_key
        subsets.setdefault(key, []).append(c)
    out = []
    for subset in subsets.values():
        laws = [made[connectors[c].law_key] for c in subset]
        base = laws[0]
        changes = {}
        for f in numeric:
            values = [getattr(law, f.name) for law in laws]
            for c, v in zip(subset, values, strict=True):
                if isinstance(v, np.ndarray):
                    raise ModelError(
                        f"connector {connectors[c].name!r}: field 'law_params': parameter {f.name!r} of law {name!r} "
                        "must be one number per connector (the kernel gathers the connectors' values into an array)"
                    )
            if any(v != values[0] for v in values[1:]):
                changes[_field_alias(f)] = np.array(values, dtype=float)
        if changes:
            try:
                base = attrs.evolve(base, **changes)
            except ParameterError as exc:
                who = ", ".join(repr(connectors[c].name) for c in subset)
                raise ModelError(f"connector {who}: field 'law_params': {exc}") from exc
        out.append((base, subset))
    return out


def build_connector_operators(model, dofmap: DofMap, registry: Registry | None = None) -> ConnectorOperators:
    """Build the laws (grouped) and the operators ``D``, ``B``, ``V`` of ``model``'s connectors."""
    connectors = model.connectors
    n = len(connectors)
    rows, cols, vals = [], [], []
    translations = np.zeros((n, 2, 3), dtype=int)
    for c, con in enumerate(connectors):
        ti = dofmap.node_dofs(con.node_i)[:3]
        tj = dofmap.node_dofs(con.node_j)[:3]
        translations[c] = ti, tj
        R = con.rotation
        for k in range(3):
            rows.extend([3 * c + k] * 6)
            cols.extend([*tj, *ti])
            vals.extend([*R[k], *(-R[k])])
    D = sp.csr_matrix((vals, (rows, cols)), shape=(3 * n, dofmap.n_dof))
    D.eliminate_zeros()

    springs = [c for c, con in enumerate(connectors) if con.kind is not ConnectorKind.JOIN]
    spring_row = {c: r for r, c in enumerate(springs)}
    kv = np.array([connectors[c].vertical_stiffness for c in springs], dtype=float)
    uplift = np.array([connectors[c].uplift for c in springs], dtype=bool)
    V = D[[3 * c + 2 for c in springs], :] if springs else sp.csr_matrix((0, dofmap.n_dof))

    ties = [(c, k) for c, con in enumerate(connectors) for k in con.tied_directions]
    registry = registry or get_registry()
    # Group the law connectors by (law, params, dims) (per-bearing laws: by (law, dims)), in
    # order of first appearance.
    by_key: dict[tuple, list[int]] = {}
    for c, con in enumerate(connectors):
        if con.dims:
            by_key.setdefault(_group_key(con, registry), []).append(c)
    groups, governed = [], []

    def add_group(law, members: list[int], directions, gap: bool = False) -> None:
        start = len(governed)
        governed.extend((c, k) for c in members for k in directions(c))
        springs_of = np.array([spring_row[c] for c in members], dtype=int)
        if gap:
            groups.append(LawGroup(law, np.array(members), slice(start, len(governed)), springs_of, False, False, True))
        else:
            groups.append(LawGroup(law, np.array(members), slice(start, len(governed)), springs_of))

    for key, members in by_key.items():
        if key[0] == "per-bearing":
            _, name, dims = key
            laws = _per_bearing_laws(name, dims, members, connectors, registry)
        else:
            name, params, dims = key
            who = "connector " + ", ".join(repr(connectors[c].name) for c in members)
            laws = [(_make_law(name, dict(params), dims, registry, who), members)]
        for law, subset in laws:
            if law.rigid:
                ties.extend((c, k) for c in subset for k in connectors[c].law_directions)
                continue
            add_group(law, subset, lambda c: connectors[c].law_directions)
    lifting = [c for c in springs if connectors[c].uplift]
    if lifting:
        gap_kv = np.array([connectors[c].vertical_stiffness for c in lifting], dtype=float)
        gap_kv.setflags(write=False)
        add_group(CompressionOnlyGap(gap_kv), lifting, lambda c: (2,), gap=True)
    B = D[[3 * c + k for c, k in governed], :] if governed else sp.csr_matrix((0, dofmap.n_dof))
    return ConnectorOperators(
        D=D.tocsr(),
        B=B.tocsr(),
        V=V.tocsr(),
        kv=kv,
        spring_connectors=np.array(springs, dtype=int),
        groups=tuple(groups),
        ties=tuple(ties),
        governed=tuple(governed),
        translations=translations,
        uplift=uplift,
    )
