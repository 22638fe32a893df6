"""Recorders: what a transient run keeps, chosen by the user (nothing else is stored per step).

Each recorder is a validated attrs object naming what to record; ``every=k`` keeps every k-th
integration step (step 0, the preload state, always). Its arrays go into
:attr:`TransientResult.data <bearingfw.analysis.TransientResult>` under keys that start with the
recorder's ``name``, with its sample times under ``"<name>.time"``:

=====================  =====================================================================
recorder               arrays (``t`` = number of samples)
=====================  =====================================================================
ElementStress          ``<name>.<element>``: maximum principal stress (Pa), (t, 2 ends, points)
ElementForces          ``<name>``: section forces, (t, elements, 2 ends, 6: N Vy Vz T My Mz)
ConnectorResponse      ``<name>.force`` (t, c, 3) local x, y, z forces resisting the relative
                       displacement; ``.displacement`` (t, c, 3) relative displacement
                       ``R (u_j - u_i)`` (total: the dead-load part included);
                       ``.law_displacement`` (t, c, 3) what the law sees, ``B u - law_reference``
                       (zero at the preload for bearings set after the dead load: plot the
                       hysteresis against this one), NaN outside the law's directions;
                       ``.normal_force`` (t, c) compression > 0; ``.slip`` (t, c, 3) the law's
                       ``slip(state)`` (the irreversible displacement, see the law protocol) in
                       its directions, NaN for a law without ``slip``; ``.friction_ratio`` (t, c)
                       ``|F_law| / N``, the force in the law's directions (not a guide's or a
                       tie's reaction) over ``N`` (NaN when ``N <= 0``, e.g. lifted off, or the
                       connector has no law); only when the connectors include one with
                       ``uplift=True``: ``.gap`` (t, c) its vertical gap ``max(d_z, 0)`` (m; 0
                       while closed, NaN for connectors without uplift) and ``.lifted`` (t, c)
                       True while it is open
NodalResponse          ``<name>``: (t, nodes, components) displacement, velocity or acceleration
SupportResponse        ``<name>.displacement`` (t, groups, 3) each support group's displacement
                       relative to the reference group; ``.quasi_static`` (t, c, 3) the law
                       displacement the quasi-static support motion imposes on each connector
=====================  =====================================================================

Differential support motion (:class:`~bearingfw.analysis.excitation.SupportMotion`): the kernel's
``x`` is the motion relative to the quasi-static one, ``Psi delta(t)``; stresses, section forces,
connector displacements, spring forces and tie forces add it (they are total), as do total nodal
responses (displacement: relative to the reference support group's rigid motion; velocity and
acceleration: absolute).

Totals: stresses, section forces and connector quantities are *total* (dead load + dynamic), as
in the paper's figures. Nodal responses: see :class:`NodalResponse` for what ``total`` adds.

Section forces are linear in the displacements, so a recorder reads the map from displacements
to the section forces of its elements off the kernel's :func:`section_forces` once (one call per
DOF those elements touch) and then costs one small sparse product per sample. Tied connector
directions (JOIN, the guided direction's neighbour) carry constraint forces: a
:class:`ConnectorResponse` that includes such a connector solves for the Lagrange multipliers of
the dynamic residual at every sample (:meth:`Context.full_residual`: with HHT ``alpha < 0`` the
residual of the alpha-weighted equilibrium the scheme solved, so that tie forces and reactions
balance the structure exactly).

Keys: a recorder's ``name`` has no ``.`` and is none of :data:`RESERVED_NAMES`, and recorders in one
run have distinct names, so keys never clash; an :class:`ElementStress` refuses an element named
``time`` (its key would be the recorder's sample times).

A recorder of one's own is any object with ``label``, ``every`` and ``bind(context)`` (a
:class:`Context`), which returns a probe: ``times`` (a list the run reads), ``sample(snapshot)``
(a :class:`Snapshot`) and ``finish()`` (its arrays, with ``<label>.time``, and a description).
A probe may also offer ``sample_many(samples)``: the time loop then hands it the instants of a
run of compiled steps at once, as :class:`Samples` (arrays side by side), instead of one
snapshot each; without it, or with a ``sample`` set on the instance, it sees every snapshot.
"""

from __future__ import annotations

import weakref
from collections.abc import Sequence

import attrs
import numpy as np
import scipy.sparse as sp

from bearingfw.analysis.excitation import Excitation
from bearingfw.analysis.results import SECTION_COMPONENTS, element_stresses, section_forces, section_stresses
from bearingfw.analysis.static import ForceRecovery, StaticResult
from bearingfw.model import COMPONENTS, FrameElement, ModelError, System
from bearingfw.model.connectors import normal_force
from bearingfw.parameters import ParameterError, choice, integer_parameter

__all__ = [
    "ElementStress",
    "ElementForces",
    "ConnectorResponse",
    "NodalResponse",
    "SupportResponse",
    "Context",
    "MultiplierMap",
    "Snapshot",
    "Samples",
    "RESERVED_NAMES",
]

#: Instants a probe holds before it evaluates them together (they keep the states alive), counted
#: from the run's start: a chunk ends after every 64th sample (step 63, 127, ... when every step is kept).
CHUNK = 64
#: Names a recorder may not take (they are keys of the result file).
RESERVED_NAMES = ("time", "energy", "meta")
QUANTITIES = ("displacement", "velocity", "acceleration")


def _names(value):
    if isinstance(value, str):
        return (value,)
    try:
        return tuple(value)
    except TypeError:
        return value


def _check_names(instance, attribute, value):
    if value is None and attribute.default is None:
        return
    if not isinstance(value, tuple) or not value or not all(isinstance(v, str) and v for v in value):
        raise ParameterError(f"{type(instance).__name__}: field {attribute.name!r} must be a non-empty list of names")
    if len(set(value)) != len(value):
        raise ParameterError(f"{type(instance).__name__}: field {attribute.name!r} names an item twice: {value!r}")


def _check_key_names(instance, attribute, value):
    """Names that become key suffixes (``<name>.<item>``) must not be the sample-times key ``time``."""
    _check_names(instance, attribute, value)
    if "time" in value:
        raise ParameterError(
            f"{type(instance).__name__}: field {attribute.name!r} names an item 'time', whose key "
            f"'<name>.time' is the recorder's sample times; record it with ElementForces instead"
        )


def _check_label(instance, attribute, value):
    if value is None and attribute.default is None:
        return
    if not isinstance(value, str) or not value or "." in value or value in RESERVED_NAMES:
        raise ParameterError(
            f"{type(instance).__name__}: field 'name' must be a non-empty string without '.' and not one of "
            f"{', '.join(RESERVED_NAMES)}; got {value!r}"
        )


def _names_field(*, optional: bool = False, doc: str = "", validator=_check_names):
    return attrs.field(
        default=None if optional else attrs.NOTHING, converter=attrs.converters.optional(_names),
        validator=validator, metadata={"doc": doc},
    )


def _label_field(default):
    return attrs.field(default=default, validator=_check_label, metadata={"doc": "prefix of the result keys"})


def _every_field():
    return integer_parameter(low=1, high=10**9, default=1, doc="keep every k-th integration step")


# ---- what probes read -----------------------------------------------------------------------
@attrs.frozen(eq=False)
class Snapshot:
    """A committed instant as recorders see it (``x``, ``v``, ``a`` relative to the preload/ground).

    ``d``: the law displacements (what the laws see, rows of ``B``; None: recorders compute it).
    ``a_equilibrium``: the relative acceleration whose inertia HHT's alpha-weighted equilibrium
    balances at ``t`` (:class:`bearingfw.analysis.hht.State`; None: ``a``, exact for ``alpha = 0``).
    """

    t: float
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    f: np.ndarray  # law forces, total
    law_states: tuple
    ground_acceleration: np.ndarray  # (3,)
    ground_velocity: np.ndarray  # (3,)
    nodal: np.ndarray | None  # full dynamic nodal loads
    d: np.ndarray | None = None
    a_equilibrium: np.ndarray | None = None


class Samples:
    """Instants side by side, as probes evaluate them: :class:`Snapshot`'s fields with one row per
    instant (``x`` (k, n), ``ground_acceleration`` (k, 3), ...; ``nodal``, ``d`` and
    ``a_equilibrium`` None where an instant lacks them), and ``law_states``, a sequence with one
    entry per instant, read only by the probes that need them (a run of compiled steps unpacks
    them on demand).

    Made from arrays (a run of steps: ``Samples(law_states, t=..., x=..., ...)``, every field
    given), or from ``parts``, snapshots and other samples in time order (:meth:`of`), whose
    fields are joined when a probe first reads them."""

    ARRAYS = ("t", "x", "v", "a", "f", "ground_acceleration", "ground_velocity")
    OPTIONAL = ("nodal", "d", "a_equilibrium")

    def __init__(self, law_states: Sequence, parts: Sequence | None = None, **arrays):
        if parts is None and set(arrays) != {*self.ARRAYS, *self.OPTIONAL}:
            raise TypeError(f"Samples: give every one of {self.ARRAYS + self.OPTIONAL}, or parts")
        self.law_states = law_states
        self.parts = parts
        self.__dict__.update(arrays)

    @classmethod
    def of(cls, parts: Sequence) -> Samples:
        """The instants of ``parts`` (:class:`Snapshot` or :class:`Samples`, in time order); one
        :class:`Samples` is itself."""
        if len(parts) == 1 and isinstance(parts[0], Samples):
            return parts[0]
        states = [(p.law_states,) if isinstance(p, Snapshot) else p.law_states for p in parts]
        return cls(_Picked.joined(states), list(parts))

    def __getattr__(self, field: str):
        # only for what is not set yet: a field of the parts, joined at its first reading
        if field not in self.ARRAYS + self.OPTIONAL or self.__dict__.get("parts") is None:
            raise AttributeError(field)
        values = [getattr(p, field) for p in self.parts]
        if field in self.OPTIONAL and any(v is None for v in values):
            joined = None
        elif all(isinstance(p, Snapshot) for p in self.parts):
            joined = np.array(values)
        else:
            joined = np.concatenate([np.asarray(v)[None] if isinstance(p, Snapshot) else v
                                     for v, p in zip(values, self.parts, strict=True)])  # fmt: skip
        self.__dict__[field] = joined
        return joined

    def __len__(self) -> int:
        return len(self.law_states)

    def each(self) -> list[Snapshot]:
        """The instants one by one."""
        if self.parts is not None:
            return [s for p in self.parts for s in ((p,) if isinstance(p, Snapshot) else p.each())]
        return [self.snapshot(j) for j in range(len(self))]

    def snapshot(self, j: int) -> Snapshot:
        """Instant ``j``."""
        if self.parts is not None:
            return self.each()[j]

        def row(field):
            values = getattr(self, field)
            return None if values is None else values[j]

        return Snapshot(float(self.t[j]), *map(row, ("x", "v", "a", "f")), self.law_states[j],
                        *map(row, ("ground_acceleration", "ground_velocity", *self.OPTIONAL)))  # fmt: skip

    def take(self, rows: slice | np.ndarray) -> Samples:
        """The instants ``rows`` (a slice, or indices in time order)."""
        index = np.arange(len(self))[rows]
        if self.parts is not None:
            everyone = self.each()
            return Samples.of([everyone[j] for j in index.tolist()])
        arrays = {f: getattr(self, f) for f in self.ARRAYS + self.OPTIONAL}
        return Samples(_Picked(self.law_states, index), **{f: None if v is None else v[rows] for f, v in arrays.items()})


class _Picked(Sequence):
    """Items of sequences, fetched when read (a run's law states are unpacked on demand): item ``j``
    is ``items[owner[j]][rows[j]]``."""

    def __init__(self, items: Sequence, rows: np.ndarray, owner: np.ndarray | None = None):
        self.items, self.rows = ([items], rows) if owner is None else (items, rows)
        self.owner = np.zeros(rows.size, dtype=int) if owner is None else owner

    @classmethod
    def joined(cls, sequences: Sequence[Sequence]) -> _Picked:
        """The items of ``sequences``, one after the other."""
        sizes = [len(s) for s in sequences]
        owner = np.repeat(np.arange(len(sequences)), sizes)
        rows = np.concatenate([np.arange(n) for n in sizes]) if sizes else np.zeros(0, dtype=int)
        return cls(list(sequences), rows, owner)

    def __len__(self) -> int:
        return self.rows.size

    def __getitem__(self, j):
        j = range(self.rows.size)[j]  # an IndexError past the end (iteration stops there)
        if isinstance(j, range):
            return [self[k] for k in j]
        return self.items[int(self.owner[j])][int(self.rows[j])]


@attrs.frozen(eq=False)
class MultiplierMap:
    """The dynamic multipliers of some constraint equations (``rows``) as a linear map of the state.

    They are rows of ``(C C^T)^-1 C r`` with ``r`` the residual of :meth:`Context.full_residual`,
    which is linear in ``(a_equilibrium + a0 v, x + a1 v, ground acceleration, f - f_0, nodal)``.
    Folding ``(C C^T)^-1`` (those rows only), ``C``, ``M``, ``K`` and ``T`` into one small matrix
    per term once makes a sample a few products with ``len(rows)`` rows, instead of full-DOF
    products and a solve with the whole Gram matrix.
    """

    rows: np.ndarray
    # sparse: a tie's rows touch the few DOFs near it (the reference bridge's: 2 % of the columns)
    inertia: sp.csr_matrix  # (rows, n_free): G_rows C M T
    stiffness: sp.csr_matrix  # (rows, n_free): G_rows C K T
    ground: np.ndarray  # (rows, 3): G_rows C M R
    laws: sp.csr_matrix  # (rows, m): G_rows C B^T
    nodal: sp.csr_matrix  # (rows, n_dof): G_rows C
    support_inertia: np.ndarray | None = None  # (rows, k): G_rows C M Psi (differential support motion)
    support_stiffness: np.ndarray | None = None  # (rows, k): G_rows C K Psi

    @classmethod
    def of(cls, system: System, R: np.ndarray, rows, psi: np.ndarray | None = None) -> MultiplierMap:
        rows = np.asarray(rows, dtype=int)
        constraints = system.constraints
        unit = np.zeros((len(constraints.equations), rows.size))
        unit[rows, np.arange(rows.size)] = 1.0
        # rows of (C C^T)^-1, which is symmetric: its columns at ``rows``, transposed
        G_rows = np.atleast_2d(constraints.solve_gram(unit)).reshape(len(constraints.equations), rows.size).T
        GC = sp.csr_matrix(G_rows) @ constraints.C.tocsr()
        GCM = GC @ system.M
        return cls(
            rows=rows,
            inertia=sp.csr_matrix(GCM @ system.T),
            stiffness=sp.csr_matrix(GC @ system.K @ system.T),
            ground=np.asarray(GCM @ R),
            laws=sp.csr_matrix(GC @ system.connectors.B.T),
            nodal=sp.csr_matrix(GC),
            support_inertia=None if psi is None else np.asarray(GCM @ psi),
            support_stiffness=None if psi is None else np.asarray(GC @ (system.K @ psi)),
        )

    def dynamic(self, s: Snapshot, a0: float, a1: float, law_forces0: np.ndarray, support=None) -> np.ndarray:
        """The multipliers ``rows`` beyond the preload's at the instant ``s``; ``support``: the differential
        support motion ``(delta, delta', delta'')`` at ``s.t`` (:meth:`Excitation.support_differences`)."""
        a = s.a if s.a_equilibrium is None else s.a_equilibrium
        return self.combine(s.x, s.v, a, s.ground_acceleration, s.f, s.nodal, a0, a1, law_forces0, support)

    def combine(self, x, v, a, ground, f, nodal, a0: float, a1: float, law_forces0: np.ndarray, support=None):
        """:meth:`dynamic` from the state's arrays: vectors for one instant, or instants side by side as
        columns (then ``law_forces0`` stays a vector and ``support`` holds columns too)."""
        lam = (
            self.inertia @ (a + a0 * v)
            + self.stiffness @ (x + a1 * v)
            + self.ground @ ground
            + self.laws @ (f - (law_forces0 if f.ndim == 1 else law_forces0[:, None]))
        )
        if support is not None and self.support_inertia is not None:
            lam = lam + self.support_inertia @ support[2] + self.support_stiffness @ support[0]
        return lam if nodal is None else lam - self.nodal @ nodal


@attrs.frozen(eq=False)
class Context:
    """What recorders need to know about the run."""

    system: System
    preload: StaticResult
    excitation: Excitation
    a0: float
    a1: float
    _Bt: sp.csr_matrix = attrs.field(init=False, repr=False)

    def __attrs_post_init__(self):
        object.__setattr__(self, "_Bt", self.system.connectors.B.T.tocsr())

    @property
    def q0(self) -> np.ndarray:
        return self.preload.q

    def full_residual(self, s: Snapshot) -> np.ndarray:
        """Dynamic part of the full-DOF residual (inertia with the ground acceleration, damping,
        stiffness, laws, minus nodal loads): the constraint forces beyond the preload's.

        HHT (``alpha < 0``) balances ``M a_{n+1} + (1 + alpha) G_{n+1} - alpha G_n`` (``G`` all but
        the relative inertia; the constraint forces weighted like the other forces), not the
        equilibrium at ``t_{n+1}``. Writing that as ``M ae_{n+1} + G_{n+1}`` with
        ``ae_{n+1} = (a_{n+1} + alpha ae_n) / (1 + alpha)`` (``s.a_equilibrium``) makes the residual
        one the constraint forces balance exactly: its multipliers ``lambda_{n+1}`` satisfy
        ``(1 + alpha) lambda_{n+1} - alpha lambda_n = lambda_{n+alpha}``, those of the weighted
        equation. (The residual with ``a_{n+1}`` is not in the range of ``C^T``; its least-squares
        multipliers would mix in the free DOFs' out-of-balance force ``-alpha (G_{n+1} - G_n)``.)
        """
        sys = self.system
        T = sys.T
        a = s.a if s.a_equilibrium is None else s.a_equilibrium
        acc = T @ a + self.excitation.R @ s.ground_acceleration
        vel = T @ s.v
        disp = T @ s.x
        quasi = self.excitation.pseudo_static(s.t)
        if quasi is not None:  # differential support motion: Psi delta, damped only through x' (excitation)
            disp, acc = disp + quasi[0], acc + quasi[2]
        r = sys.M @ (acc + self.a0 * vel) + sys.K @ (disp + self.a1 * vel)
        r = r + self._Bt @ (s.f - self.preload.law_forces)
        return r if s.nodal is None else r - s.nodal

    def multiplier_map(self, rows) -> MultiplierMap:
        """:class:`MultiplierMap` of the constraint equations ``rows`` (for recorders: build once)."""
        dif = self.excitation.differential
        return MultiplierMap.of(self.system, self.excitation.R, rows, None if dif is None else dif.psi)

    def support_differences(self, t: float):
        """The differential support motion at ``t`` (None for uniform motion): :meth:`Excitation.support_differences`."""
        return self.excitation.support_differences(t)


class _Probe:
    """Collects one recorder's samples; ``finish`` returns its arrays and description.

    Samples are evaluated in chunks of :attr:`CHUNK` instants side by side (:class:`Samples`): a
    product of a recorder's matrix with a chunk's states costs about what one product with one
    state does, so the per-step cost of recording is a list append (:meth:`sample`), or nothing
    per step where a run of steps comes at once (:meth:`sample_many`). The chunks are the same
    however the instants come (one by one or in runs): a dense product's rounding can depend on
    the number of columns, and a run must not depend on how its steps were taken. A probe gives
    ``_sample_many`` (a chunk, in time order) or ``_sample`` (one snapshot; the default
    ``_sample_many`` loops over it)."""

    CHUNK = CHUNK

    def __init__(self, spec):
        self.spec = spec
        self.label = spec.label
        self.every = spec.every
        self.times: list[float] = []
        self._pending: list = []  # snapshots and samples, in time order
        self._held = 0  # instants in _pending

    def sample(self, s: Snapshot) -> None:
        self.times.append(s.t)
        self._pending.append(s)
        self._held += 1
        if self._held >= self.CHUNK:
            self.flush()

    def sample_many(self, samples: Samples) -> None:
        """Record the instants ``samples`` (in time order, after those held)."""
        self.times.extend(samples.t.tolist())
        start, k = 0, len(samples)
        while start < k:
            take = min(self.CHUNK - self._held, k - start)
            self._pending.append(samples if take == k else samples.take(slice(start, start + take)))
            self._held += take
            start += take
            if self._held >= self.CHUNK:
                self.flush()

    def flush(self) -> None:
        """Evaluate the instants held so far."""
        if self._pending:
            pending, self._pending, self._held = self._pending, [], 0
            self._sample_many(Samples.of(pending))

    def _sample_many(self, samples: Samples) -> None:
        for s in samples.each():
            self._sample(s)

    def finish(self) -> tuple[dict[str, np.ndarray], dict]:
        self.flush()
        data, meta = self._finish()
        data[f"{self.label}.time"] = np.array(self.times)
        return data, meta


def _section_force_map(ctx: Context, names: tuple[str, ...]) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray | None]:
    """``(L, F_dead, L_psi)``: section forces (elements x 2 x 6, flattened) = ``L x + L_psi delta + F_dead`` for
    ``x = q - q_0`` and the differential support motion ``delta`` (``L_psi`` None for uniform motion)."""
    sys = ctx.system
    maps = _FORCE_MAPS.setdefault(sys, {})
    if names not in maps:
        maps[names] = _read_force_map(sys, names)
    L_full, L = maps[names]
    dead = section_forces(sys, ctx.preload.u, names, g=ctx.preload.g).values
    dif = ctx.excitation.differential
    return L, dead, None if dif is None else np.asarray(L_full @ dif.psi)


#: per system (the runs of an experiment's cells share one): element names -> (L_full, L) of _read_force_map
_FORCE_MAPS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _read_force_map(sys: System, names: tuple[str, ...]) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The section forces of ``names`` as a linear map of the full displacements ``u`` (``L_full``) and
    of the free ones (``L = L_full T``), read off the kernel one DOF at a time."""
    model = sys.model
    for n in names:
        model.element(n)
    nodes = {nd for n in names for nd in (model.element(n).i, model.element(n).j)}
    dofs = np.concatenate([sys.dofmap.node_dofs(nd) for nd in sorted(nodes)])
    cols = []
    probe = np.zeros(sys.n_dof)
    for dof in dofs:
        probe[dof] = 1.0
        cols.append(section_forces(sys, probe, names).values.reshape(-1))
        probe[dof] = 0.0
    L_dofs = sp.csr_matrix(np.column_stack(cols))
    L_full = sp.csr_matrix((L_dofs.data, dofs[L_dofs.indices], L_dofs.indptr), shape=(L_dofs.shape[0], sys.n_dof))
    return L_full, (L_full @ sys.T).tocsr()


def _support_columns(ctx: Context, samples: Samples) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The differential support displacement, velocity and acceleration (3 per differing group, instants)
    at the instants, one column each; None for uniform motion."""
    if ctx.excitation.differential is None:
        return None
    at = [ctx.excitation.support_differences(t) for t in samples.t.tolist()]
    return tuple(np.array([d[k] for d in at]).T for k in range(3))


def _rows_with_support(rows: list, value: np.ndarray, quasi: np.ndarray | None, ctx: Context, samples) -> None:
    """Append the columns of ``value`` (n, instants), plus the quasi-static share, as rows."""
    if quasi is not None:
        value = value + quasi @ _support_columns(ctx, samples)[0]
    rows.extend(value.T)


# ---- element stresses and section forces ------------------------------------------------------
@attrs.frozen
class ElementStress:
    """Maximum principal stress at both ends of frame ``elements``, at the sections' recovery
    ``points`` (default: all of them; a section's points are set on :class:`~bearingfw.model.Section`)."""

    elements: tuple[str, ...] = _names_field(doc="frame elements (not one named 'time')", validator=_check_key_names)
    points: tuple[str, ...] | None = _names_field(optional=True, doc="recovery points (default all)")
    every: int = _every_field()
    name: str = _label_field("stress")

    @property
    def label(self) -> str:
        return self.name

    def bind(self, ctx: Context) -> _Probe:
        return _StressProbe(self, ctx)


class _StressProbe(_Probe):
    def __init__(self, spec: ElementStress, ctx: Context):
        super().__init__(spec)
        model = ctx.system.model
        self.sections, self.pick = [], []
        for n in spec.elements:
            e = model.element(n)
            if not isinstance(e, FrameElement):
                raise ModelError(
                    f"ElementStress: element {n!r} is not a frame element (record its axial force with ElementForces)"
                )
            available = [p.name for p in e.section.points]
            wanted = available if spec.points is None else list(spec.points)
            missing = [p for p in wanted if p not in available]
            if missing or not wanted:
                raise ModelError(
                    f"ElementStress: section {e.section.name!r} of element {n!r} has no recovery point(s) "
                    f"{missing or wanted}; it has {available}"
                )
            self.sections.append(e.section)
            self.pick.append([available.index(p) for p in wanted])
        element_stresses(ctx.system, ctx.preload.u, spec.elements, g=ctx.preload.g)  # the kernel's own checks
        self.L, self.dead, self.L_psi = _section_force_map(ctx, spec.elements)
        self.ctx = ctx
        self.rows: list[np.ndarray] = []

    def _sample_many(self, samples: Samples) -> None:
        _rows_with_support(self.rows, self.L @ samples.x.T, self.L_psi, self.ctx, samples)

    def _finish(self):
        spec = self.spec
        n = len(spec.elements)
        forces = np.array(self.rows).reshape(-1, n, 2, 6) + self.dead[None]
        data, points = {}, {}
        for k, name in enumerate(spec.elements):
            st = section_stresses(forces[:, k], self.sections[k])
            data[f"{self.label}.{name}"] = st.sigma1[..., self.pick[k]]
            points[name] = [st.points[i] for i in self.pick[k]]
        meta = {"kind": "element stress", "elements": list(spec.elements), "points": points,
                "ends": ["i", "j"], "unit": "Pa", "quantity": "maximum principal stress (total)"}
        return data, meta


@attrs.frozen
class ElementForces:
    """Section forces (total) at both ends of ``elements`` (frames and trusses), local axes."""

    elements: tuple[str, ...] = _names_field(doc="elements")
    every: int = _every_field()
    name: str = _label_field("section_forces")

    @property
    def label(self) -> str:
        return self.name

    def bind(self, ctx: Context) -> _Probe:
        return _ForcesProbe(self, ctx)


class _ForcesProbe(_Probe):
    def __init__(self, spec: ElementForces, ctx: Context):
        super().__init__(spec)
        self.L, self.dead, self.L_psi = _section_force_map(ctx, spec.elements)
        self.ctx = ctx
        self.rows: list[np.ndarray] = []

    def _sample_many(self, samples: Samples) -> None:
        _rows_with_support(self.rows, self.L @ samples.x.T, self.L_psi, self.ctx, samples)

    def _finish(self):
        n = len(self.spec.elements)
        values = np.array(self.rows).reshape(-1, n, 2, 6) + self.dead[None]
        meta = {"kind": "section forces", "elements": list(self.spec.elements), "ends": ["i", "j"],
                "components": list(SECTION_COMPONENTS), "unit": "N, N m"}
        return {self.label: values}, meta


# ---- connectors ---------------------------------------------------------------------------------
@attrs.frozen
class ConnectorResponse:
    """Force, relative and law displacement, normal force, slip and friction ratio of ``connectors``
    (default all); see the module docstring for the arrays."""

    connectors: tuple[str, ...] | None = _names_field(optional=True, doc="connector names (default all)")
    every: int = _every_field()
    name: str = _label_field("connectors")

    @property
    def label(self) -> str:
        return self.name

    def bind(self, ctx: Context) -> _Probe:
        return _ConnectorProbe(self, ctx)


class _ConnectorProbe(_Probe):
    def __init__(self, spec: ConnectorResponse, ctx: Context):
        super().__init__(spec)
        sys = ctx.system
        model = sys.model
        names = tuple(c.name for c in model.connectors) if spec.connectors is None else spec.connectors
        self.names = names
        self.index = np.array([model.connector_index(n) for n in names], dtype=int)
        ops = sys.connectors
        rows = (3 * self.index[:, None] + np.arange(3)[None, :]).reshape(-1)
        self.D = (ops.D[rows] @ sys.T).tocsr()
        self.D0 = ops.D[rows] @ ctx.preload.u
        dif = ctx.excitation.differential
        self.D_psi = None if dif is None else np.asarray(ops.D[rows] @ dif.psi)
        # law quantities (rows of B, per group) -> (selected connector, local direction) slots
        selected = {int(c): k for k, c in enumerate(self.index)}
        self.governed = np.zeros((self.index.size, 3), dtype=bool)
        self.slots: list[tuple[int, np.ndarray, np.ndarray, np.ndarray]] = []  # (group, members, rows, slot index)
        for gi, g in enumerate(ops.groups):
            if g.gap:
                continue  # the uplift springs' rows: recorded as the gap (below), not as law directions
            members, slot = [], []
            for pos, c in enumerate(g.connectors.tolist()):
                if c in selected:
                    dirs = model.connectors[c].law_directions
                    members.append(pos)
                    slot.append([3 * selected[c] + k for k in dirs])
                    self.governed[selected[c], list(dirs)] = True
            if members:
                members = np.array(members, dtype=int)
                rows_b = (g.rows.start + g.dims * members[:, None] + np.arange(g.dims)[None, :]).reshape(-1)
                self.slots.append((gi, members, rows_b, np.array(slot, dtype=int).reshape(-1)))
        # the laws' slip (an optional protocol member) of the groups whose law has one
        self.slips = []
        for gi, members, _, slot in self.slots:
            law = ops.groups[gi].law
            if hasattr(law, "slip"):
                self.slips.append((gi, law.slip, members, slot))
        # uplift connectors: their gap rows of B, and where they go among the selected connectors
        gap = ops.gap_group
        self.gap_rows, self.gap_slots = np.zeros(0, int), np.zeros(0, int)
        if gap is not None:
            pos = [(k, selected[int(c)]) for k, c in enumerate(gap.connectors.tolist()) if int(c) in selected]
            self.gap_rows = np.array([gap.rows.start + k for k, _ in pos], dtype=int)
            self.gap_slots = np.array([slot for _, slot in pos], dtype=int)
        self.law_rows = np.concatenate([rows_b for _, _, rows_b, _ in self.slots]) if self.slots else np.zeros(0, int)
        self.law_slots = np.concatenate([slot for _, _, _, slot in self.slots]) if self.slots else np.zeros(0, int)
        self.reference = np.asarray(ctx.preload.law_reference, dtype=float)
        self.B = sys.B_free
        self.recovery = ForceRecovery.of(sys)
        # the tie multipliers these connectors' forces need, as a map of the state (Context.multiplier_map)
        ties = np.isin(self.recovery.tie_slots // 3, self.index)
        self.multipliers = ctx.multiplier_map(self.recovery.tie_rows[ties]) if np.any(ties) else None
        self.springs = (ops.V @ sys.T).tocsr() if ops.spring_connectors.size else None
        self.springs0 = ops.V @ ctx.preload.u if ops.spring_connectors.size else None
        self.springs_psi = None if (dif is None or self.springs is None) else np.asarray(ops.V @ dif.psi)
        self.kv = ops.kv
        self.ctx = ctx
        self.forces, self.disp, self.law_disp, self.slip, self.gaps = [], [], [], [], []

    def _sample(self, s: Snapshot) -> None:
        ctx = self.ctx
        support = ctx.support_differences(s.t)  # None: uniform motion
        lam = ctx.preload.multipliers
        if self.multipliers is not None:
            lam = lam.copy()
            lam[self.multipliers.rows] += self.multipliers.dynamic(s, ctx.a0, ctx.a1, ctx.preload.law_forces, support)
        if self.springs is not None:
            shortening = self.springs @ s.x if support is None else self.springs @ s.x + self.springs_psi @ support[0]
            springs = self.kv * (self.springs0 + shortening)
        else:
            springs = np.zeros(0)
        forces = self.recovery.connector_forces(springs, s.f, lam)
        self.forces.append(forces[self.index])
        moved = self.D @ s.x if support is None else self.D @ s.x + self.D_psi @ support[0]
        self.disp.append((self.D0 + moved).reshape(-1, 3))
        if s.d is None:
            d = self.B @ (ctx.q0 + s.x) - self.reference
            if support is not None:
                d = d + ctx.excitation.bearing_offset(s.t)[0][: self.B.shape[0]]
        else:
            d = s.d
        law_disp = np.full(3 * self.index.size, np.nan)
        law_disp[self.law_slots] = d[self.law_rows]
        slip = np.full(3 * self.index.size, np.nan)
        for gi, slip_of, members, slot in self.slips:
            slip[slot] = np.asarray(slip_of(s.law_states[gi]), dtype=float)[members].reshape(-1)
        self.law_disp.append(law_disp.reshape(-1, 3))
        self.slip.append(slip.reshape(-1, 3))
        if self.gap_rows.size:
            gap = np.full(self.index.size, np.nan)
            gap[self.gap_slots] = d[self.gap_rows]  # the total d_z: > 0 open
            self.gaps.append(gap)

    def _sample_many(self, samples: Samples) -> None:
        if samples.d is None or samples.a_equilibrium is None:
            super()._sample_many(samples)  # a state without its law displacements: one at a time
            return
        ctx = self.ctx
        k = len(samples)
        x = samples.x.T
        f = samples.f.T
        d = samples.d.T
        support = _support_columns(ctx, samples)
        lam = np.tile(ctx.preload.multipliers, (k, 1))
        if self.multipliers is not None:
            nodal = None if samples.nodal is None else samples.nodal.T
            lam[:, self.multipliers.rows] += self.multipliers.combine(
                x, samples.v.T, samples.a_equilibrium.T, samples.ground_acceleration.T, f, nodal, ctx.a0, ctx.a1,
                ctx.preload.law_forces, support,
            ).T
        if self.springs is not None:
            shortening = self.springs @ x if support is None else self.springs @ x + self.springs_psi @ support[0]
            springs = (self.kv[:, None] * (self.springs0[:, None] + shortening)).T
        else:
            springs = np.zeros((k, 0))
        forces = self.recovery.connector_forces(springs, f.T, lam)
        self.forces.extend(forces[:, self.index])
        moved = self.D @ x if support is None else self.D @ x + self.D_psi @ support[0]
        self.disp.extend((self.D0[:, None] + moved).T.reshape(k, -1, 3))
        law_disp = np.full((k, 3 * self.index.size), np.nan)
        law_disp[:, self.law_slots] = d[self.law_rows].T
        self.law_disp.extend(law_disp.reshape(k, -1, 3))
        slip = np.full((k, 3 * self.index.size), np.nan)
        if self.slips:
            for row, states in zip(slip, samples.law_states, strict=True):
                for gi, slip_of, members, slot in self.slips:
                    row[slot] = np.asarray(slip_of(states[gi]), dtype=float)[members].reshape(-1)
        self.slip.extend(slip.reshape(k, -1, 3))
        if self.gap_rows.size:
            gap = np.full((k, self.index.size), np.nan)
            gap[:, self.gap_slots] = d[self.gap_rows].T  # the total d_z: > 0 open
            self.gaps.extend(gap)

    def _finish(self):
        name = self.label
        c = self.index.size
        force = np.array(self.forces).reshape(-1, c, 3)
        N = normal_force(force[..., 2])
        # friction: the force in the law's directions only (a guided bearing's guide reaction and
        # a fixed bearing's tie forces are not friction)
        governed = self.governed
        friction = np.sqrt(np.sum(np.where(governed[None], force, 0.0) ** 2, axis=-1))
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where((N > 0) & governed.any(axis=1)[None], friction / np.where(N > 0, N, 1.0), np.nan)
        data = {
            f"{name}.force": force,
            f"{name}.displacement": np.array(self.disp).reshape(-1, c, 3),
            f"{name}.law_displacement": np.array(self.law_disp).reshape(-1, c, 3),
            f"{name}.normal_force": N,
            f"{name}.slip": np.array(self.slip).reshape(-1, c, 3),
            f"{name}.friction_ratio": ratio,
        }
        units = {"force": "N", "displacement": "m", "law_displacement": "m", "normal_force": "N", "slip": "m",
                 "friction_ratio": "-"}
        if self.gap_rows.size:
            dz = np.array(self.gaps).reshape(-1, c)
            data[f"{name}.gap"] = np.where(np.isnan(dz), np.nan, np.maximum(dz, 0.0))
            data[f"{name}.lifted"] = dz > 0.0  # NaN (no uplift) compares False
            units.update(gap="m", lifted="-")
        meta = {"kind": "connector response", "connectors": list(self.names), "directions": ["x", "y", "z"],
                "units": units}
        return data, meta


# ---- support motion -----------------------------------------------------------------------------
@attrs.frozen
class SupportResponse:
    """The support groups' differential motion and what it imposes on the bearings quasi-statically.

    ``<name>.displacement`` (t, groups, 3): each support group's displacement relative to the
    reference group (global x, y, z; m), as the analysis applies it (zero for uniform motion and for
    the reference); ``<name>.quasi_static`` (t, c, 3): the law displacement that the quasi-static
    motion ``Psi delta`` imposes on each connector (``e`` of
    :meth:`~bearingfw.analysis.excitation.Excitation.bearing_offset`: what the bearing would deform
    if the bridge followed the support motion quasi-statically with its bearings at their initial
    tangent), in the law's directions, NaN elsewhere. The description names the groups and the
    reference group.
    """

    every: int = _every_field()
    name: str = _label_field("supports")

    @property
    def label(self) -> str:
        return self.name

    def bind(self, ctx: Context) -> _Probe:
        return _SupportProbe(self, ctx)


class _SupportProbe(_Probe):
    def __init__(self, spec: SupportResponse, ctx: Context):
        super().__init__(spec)
        exc = ctx.excitation
        sys = ctx.system
        model = sys.model
        ops = sys.connectors
        motion = exc.support
        self.groups = list(motion.groups) if motion is not None else []
        self.reference = motion.reference_group if motion is not None else None
        dif = exc.differential
        # columns of the differences -> (group, direction) slots
        self.columns = np.zeros(0, dtype=int)
        if dif is not None:
            self.columns = np.concatenate([3 * self.groups.index(g) + np.arange(3) for g in dif.groups])
        self.n_connectors = len(model.connectors)
        rows, slots = [], []
        for g in ops.groups:
            if g.gap:
                continue
            for pos, c in enumerate(g.connectors.tolist()):
                for k, direction in enumerate(model.connectors[c].law_directions):
                    rows.append(g.rows.start + g.dims * pos + k)
                    slots.append(3 * c + direction)
        self.law_rows, self.law_slots = np.array(rows, dtype=int), np.array(slots, dtype=int)
        self.ctx = ctx
        self.disp, self.quasi = [], []

    def _sample(self, s: Snapshot) -> None:
        exc = self.ctx.excitation
        disp = np.zeros(3 * len(self.groups))
        quasi = np.full(3 * self.n_connectors, np.nan)
        quasi[self.law_slots] = 0.0
        support = exc.support_differences(s.t)
        if support is not None:
            disp[self.columns] = support[0]
            quasi[self.law_slots] = exc.bearing_offset(s.t)[0][self.law_rows]
        self.disp.append(disp.reshape(-1, 3))
        self.quasi.append(quasi.reshape(-1, 3))

    def _finish(self):
        name = self.label
        data = {
            f"{name}.displacement": np.array(self.disp).reshape(len(self.times), len(self.groups), 3),
            f"{name}.quasi_static": np.array(self.quasi).reshape(len(self.times), self.n_connectors, 3),
        }
        meta = {"kind": "support response", "groups": list(self.groups), "reference": self.reference,
                "connectors": [c.name for c in self.ctx.system.model.connectors], "directions": ["x", "y", "z"],
                "units": {"displacement": "m", "quasi_static": "m"}}
        return data, meta


# ---- nodes --------------------------------------------------------------------------------------
def _components(value):
    if isinstance(value, str):
        return (value.lower(),)
    try:
        return tuple(str(v).lower() for v in value)
    except TypeError:
        return value


def _check_components(instance, attribute, value):
    valid = isinstance(value, tuple) and value and all(c in COMPONENTS for c in value)
    if not valid or len(set(value)) != len(value):
        raise ParameterError(
            f"NodalResponse: field 'components' must be distinct names among {', '.join(COMPONENTS)}, got {value!r}"
        )


@attrs.frozen
class NodalResponse:
    """Displacement, velocity or acceleration of ``nodes`` (global components).

    The solver integrates the motion relative to the ground (every support moves with the same
    ground motion), measured from the gravity preload. ``total`` adds what that leaves out, which
    differs by quantity (under differential support motion also the quasi-static motion
    ``Psi delta``, so a total displacement is relative to the reference group's rigid motion, and
    the default the motion relative to the quasi-static one):

    ============  ===========================================  =================================
    quantity      ``total=False`` (default)                    ``total=True``
    ============  ===========================================  =================================
    displacement  dynamic part: from the preload, relative      plus the dead-load deflection;
                  to the ground                                 still relative to the ground (the
                                                                ground's own displacement is never
                                                                integrated)
    velocity      relative to the ground                        absolute: plus the ground velocity
                                                                (translations; rotations unchanged)
    acceleration  relative to the ground                        absolute: plus the ground
                                                                acceleration (what an accelerometer
                                                                on the bridge measures)
    ============  ===========================================  =================================

    The result's description (``TransientResult.recorders[name]["reference"]``) states which.
    """

    nodes: tuple[str, ...] = _names_field(doc="node names")
    quantity: str = choice(QUANTITIES, default="displacement", doc="what to record")
    components: tuple[str, ...] = attrs.field(
        default=("ux", "uy", "uz"), converter=_components, validator=_check_components
    )
    total: bool = attrs.field(default=False, validator=attrs.validators.instance_of(bool))
    every: int = _every_field()
    name: str | None = _label_field(None)

    @property
    def label(self) -> str:
        return self.name or self.quantity

    def bind(self, ctx: Context) -> _Probe:
        return _NodalProbe(self, ctx)


class _NodalProbe(_Probe):
    def __init__(self, spec: NodalResponse, ctx: Context):
        super().__init__(spec)
        sys = ctx.system
        dofs = sys.dofmap.dofs(spec.nodes, spec.components)
        self.T = sys.T[dofs].tocsr()
        self.shape = (len(spec.nodes), len(spec.components))
        self.offset = ctx.preload.u[dofs] if (spec.total and spec.quantity == "displacement") else None
        self.R = ctx.excitation.R[dofs] if (spec.total and spec.quantity != "displacement") else None
        dif = ctx.excitation.differential
        self.psi = dif.psi[dofs] if (spec.total and dif is not None) else None
        self.ctx = ctx
        self.rows: list[np.ndarray] = []

    def _sample_many(self, samples: Samples) -> None:
        quantity = self.spec.quantity
        value = self.T @ getattr(samples, {"displacement": "x", "velocity": "v", "acceleration": "a"}[quantity]).T
        if self.offset is not None:
            value = value + self.offset[:, None]
        if self.R is not None:
            value = value + self.R @ getattr(
                samples, "ground_velocity" if quantity == "velocity" else "ground_acceleration"
            ).T
        if self.psi is not None:  # the quasi-static motion of the differential support motion
            value = value + self.psi @ _support_columns(self.ctx, samples)[QUANTITIES.index(quantity)]
        self.rows.extend(value.T)

    def _finish(self):
        spec = self.spec
        unit = {"displacement": "m, rad", "velocity": "m/s, rad/s", "acceleration": "m/s^2, rad/s^2"}[spec.quantity]
        reference = {
            (False, "displacement"): "dynamic part: from the preload, relative to the ground",
            (True, "displacement"): "dead-load deflection plus the dynamic part, relative to the ground",
            (False, "velocity"): "relative to the ground",
            (True, "velocity"): "absolute: relative plus the ground velocity (translations)",
            (False, "acceleration"): "relative to the ground",
            (True, "acceleration"): "absolute: relative plus the ground acceleration (translations)",
        }[spec.total, spec.quantity]
        meta = {"kind": "nodal response", "quantity": spec.quantity, "total": spec.total, "nodes": list(spec.nodes),
                "components": list(spec.components), "unit": unit, "reference": reference}
        return {self.label: np.array(self.rows).reshape(-1, *self.shape)}, meta
