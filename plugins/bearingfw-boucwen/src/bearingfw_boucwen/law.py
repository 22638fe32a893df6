"""The Bouc-Wen smooth hysteretic law, 1-D and biaxial (Park-Wen), integrated in displacement.

Force (SI: N, m)::

    F = alpha k u + (1 - alpha) k uy z

with the dimensionless hysteretic variable ``z`` obeying, in 1-D (Bouc 1971, Wen 1976)::

    uy dz = A du - beta |du| |z|^(n-1) z - gamma du |z|^n

and, for ``dims = 2``, the biaxial form of Park, Wen & Ang (1986) written for any exponent n::

    uy dz = A du - |z|^(n-2) (beta (|du_x z_x| + |du_y z_y|) + gamma z . du) z =: Phi(z, du)

which is the 1-D law when one component is zero and Park-Wen-Ang's equation for n = 2.
Both are rate independent, so ``z`` is integrated in ``u``: ``dt`` plays no part, and the path
between the committed and the trial displacement is the straight segment.

Admissible parameters. ``beta + gamma > 0`` bounds ``z`` by ``z_max = (A/(beta+gamma))^(1/n)``:
on ``|z| = z_max``, ``uy z . dz = A beta (z . du - sum_i |du_i z_i|) / (beta+gamma) <= 0``.
``beta >= |gamma|`` makes the dissipation non-negative at every instant. With the stored energy
``psi = (1-alpha) k uy^2 |z|^2 / (2 A)`` of the hysteretic spring (initial stiffness
``(1-alpha) k A``) the dissipation is ``(1-alpha) k uy |z|^n (beta sum_i |du_i z_i| +
gamma z . du) / A``, non-negative for every ``du`` exactly when ``beta >= |gamma|`` (the
thermodynamic-admissibility condition, cf. Erlicher & Point 2004). Together: ``beta > 0`` and
``-beta < gamma <= beta``. ``n >= 1`` keeps ``Phi`` Lipschitz at ``z = 0``.

Integration, n = 2 (Park-Wen-Ang's exponent): exact, in closed form. Along the increment
``du = L e`` (``|e| = 1``), at distance ``s = uy t``, and while the signs ``sigma_i`` of ``z``'s
components stay fixed (``sigma_i = sgn(z_i)``, or ``sgn(e_i)`` where ``z_i = 0``: the sign ``z_i``
takes at once), ``beta sum_i |du_i z_i| = ds (w_beta . z)`` with ``w_i = beta |e_i| sigma_i +
gamma e_i``, so the law is the vector Riccati equation ``dz/dt = A e - (w . z) z``. ``z = y / phi``
linearises it: ``y' = A e phi``, ``phi' = w . y``, a constant linear system whose matrix ``M``
has ``M^3 = c M`` (``c = A w . e``), so ``exp(t M) = I + sinh(k t)/k M + (cosh(k t) - 1)/k^2 M^2``
(``k = sqrt(c)``; ``sin``/``cos`` for ``c < 0``). From ``z_a`` (``q = w . z_a``), with the
half-angle variable ``v = tanh(k t / 2) / k`` (``tan`` for ``c < 0``, ``t/2`` for ``c = 0``)::

    z(t) = (z_a (1 - c v^2) + 2 A v (1 + q v) e) / (1 + 2 q v + c v^2)

which also tends to saturation without overflow (``v -> 1/k``). A component with
``z_i e_i < 0`` reaches 0 where ``(2 q + c T) v^2 + 2 v - T = 0``, ``T = -z_i / (A e_i)``: an
event, after which the integration restarts with the new sign (each component changes sign at
most once along a straight increment: at ``z_i = 0`` it moves with ``e_i``). In 1-D this is the
``tanh``/``tan`` solution of a scalar Riccati equation, written with the addition theorems.
The tangent is the exact derivative of this map. Along ``e``, ``dz/dL = F(z1)/uy`` with
``F = A e - (w . z) z``; across, ``dz/du p = (dz1/de p) / L`` (``p`` the unit normal of ``e``),
evaluated as the imaginary part of the same closed form with ``e + i h p`` (a complex step:
exact to round-off, the map being analytic in ``e`` for fixed signs, with ``|e_i|`` written as
``sgn(du_i) e_i``). An event's position drops out of the derivative: ``F`` is continuous where
``z_i = 0``, so moving the event changes the end state only to second order. In 1-D the tangent
is just ``F(z1)/uy``. The bound ``|z| <= z_max`` and the dissipation hold for the exact solution
(to round-off).

Integration, any other n: the increment ``du = u - u_committed`` is cut into substeps of length
at most ``h`` (see :attr:`BoucWen.substep`) along the segment, and each substep ``delta`` is a
backward-Euler step ``z1 = z0 + Phi(z1, delta) / uy`` solved by Newton for all connectors at once.
Backward Euler keeps ``|z| <= z_max`` for any step (``z . Phi(z) <= 0`` wherever ``|z| >= z_max``,
so a root outside the ball would satisfy ``|z1|^2 <= z1 . z0``, impossible) and, with
``beta >= |gamma|``, dissipates at every step. The returned tangent is the exact derivative of
this discrete map, chain-ruled through the substeps, so the kernel's Newton converges
quadratically. It costs a few numpy operations per substep, dozens to hundreds of substeps
per call.

Cost. The closed form of n = 2 is one evaluation for any increment (and a second or third
after an event). Vectorised over connectors it is a few dozen numpy operations, whose cost is
their per-call overhead on such small arrays (about a microsecond each): so the vectorised path
does only what depends on the call (issue 16). Whatever depends on the parameters alone (the
per-bearing columns, ``sqrt(b/A)``, ``z_max``, ``2 A``, ``A/uy``, the force's coefficients,
which connectors take the closed form) is computed once per law and connector count
(:meth:`BoucWen._prepared`, :class:`_Prepared`), with the very operations that used to be
repeated at every call, so that the answers are the same to the bit; sums over the two
components, the sign choice of the Park-Wen weights and the ``tanhc`` series take fewer numpy
calls (the same arithmetic). One connector (a law object serving a single bearing) is evaluated
with the same formulas in Python floats and complex numbers (``_riccati_1d_one``,
``_riccati_2d_one``): about 6 us (1-D) and 12 us (2-D) per call. The tests check that both
agree to round-off. ``benchmarks/law_cost.py`` (repository root) times every installed law.

Per-bearing parameters (``per_bearing = True``). Every numeric parameter may be an array with one
value per connector, as the kernel makes them when the bearings of one law differ (the
reference bridge's ``bouc-wen`` preset gives each its own ``uy``). A call then takes the
parameters as ``(m, 1)`` columns (:class:`_Values`); connectors with ``n = 2`` go through the
closed form and the others through the substeps, each group in one vectorised evaluation. With
scalar parameters the arithmetic is the same as before, operation for operation (Python floats).
Each connector of a per-bearing law answers, to the bit, as a scalar law with its values called
for several connectors (tests).
"""

from __future__ import annotations

import cmath
import math
import weakref
from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.laws import respond_inputs
from bearingfw.parameters import check_per_bearing


_NUMERIC = ("k", "alpha", "uy", "A", "beta", "gamma", "n")


def _parameter(**options):
    """A Bouc-Wen parameter: a real number, or one per connector (``per_bearing``)."""
    return bearingfw.parameter(per_bearing=True, **options)


@attrs.frozen
class _Values:
    """The law's parameters for the connectors of one call: Python floats when they are the same for
    all (the arithmetic of a scalar law, unchanged), else ``(m, 1)`` columns for every parameter."""

    k: float | np.ndarray
    alpha: float | np.ndarray
    uy: float | np.ndarray
    A: float | np.ndarray
    beta: float | np.ndarray
    gamma: float | np.ndarray
    n: float | np.ndarray

    @property
    def scalar(self) -> bool:
        return isinstance(self.k, float)

    def take(self, rows) -> _Values:
        """The parameters of the connectors ``rows`` (an index or mask array)."""
        if self.scalar:
            return self
        return _Values(*(getattr(self, name)[rows] for name in _NUMERIC))

    def matrix(self, value):
        """``value`` shaped to scale ``(m, dims, dims)`` stacks: itself if a float, ``(m, 1, 1)`` if a column."""
        return value if isinstance(value, float) else value[:, :, None]

    @property
    def z_max(self):
        return (self.A / (self.beta + self.gamma)) ** (1.0 / self.n)


def _uniform(value, target: float) -> bool:
    """Whether a parameter (a float or a column) equals ``target`` for every connector."""
    return value == target if isinstance(value, float) else bool(np.all(value == target))


def _wide(value, m: int, dims: int) -> np.ndarray:
    """``value`` (a float or an ``(m, 1)`` column) as a contiguous ``(m, dims)`` array.

    Numpy's operations on such small arrays cost their call, and about three times more when an
    operand is broadcast (a column against ``(m, 2)`` rows, or a scalar's stride-0 view) than when
    all have one shape: so the parameters come in the shape of the arrays they meet.
    """
    return np.array(np.broadcast_to(value, (m, dims)))


class _Closed:
    """What the n = 2 closed form needs of the parameters alone, for the connectors of one call.

    Computed once per law and connector count (:meth:`BoucWen._prepared`) with the very operations
    the closed form used to repeat at every call, then stored as contiguous ``(m, dims)`` arrays
    (:func:`_wide`; in 2-D every per-connector quantity of the closed form is kept in both
    columns, so that no operation broadcasts), so the results are unchanged to the bit.
    """

    #: the numeric constants, views of one stacked array (so that :meth:`take` is one indexing)
    NUMERIC = ("A", "beta", "gamma", "uy", "still", "s", "kappa", "z_max", "rate", "two_A", "A_uy", "bpg", "gmb")
    __slots__ = (*NUMERIC, "stack", "unloading", "linear", "unit_z_max")

    def __init__(self, p: _Values, m: int, dims: int, still: float):
        A, beta, gamma, uy = p.A, p.beta, p.gamma, p.uy
        # Unloading (zeta < 0) follows uy zeta' = A + b zeta^2, b = beta - gamma: tan for b > 0, linear for b = 0.
        b = beta - gamma
        if p.scalar:
            linear = not b > 0
            self.unloading = "linear" if linear else "tan"
            s, kappa = (1.0, 1.0) if linear else (math.sqrt(b / A), math.sqrt(A * b))
        else:
            linear = b <= 0
            self.unloading = "linear" if linear.all() else ("tan" if not linear.any() else "mixed")
            s, kappa = np.sqrt(np.where(linear, 1.0, b / A)), np.sqrt(np.where(linear, 1.0, A * b))
        z_max = _sqrt(A / (beta + gamma))
        # z_max = 1 (A = beta + gamma, the preset's): multiplying and dividing by it are exact, so skipped.
        self.unit_z_max = _uniform(z_max, 1.0)
        values = {
            "A": A, "beta": beta, "gamma": gamma, "uy": uy,
            "still": still * uy,  # increments shorter than this leave z as it is (BoucWen.STILL)
            "s": s, "kappa": kappa, "z_max": z_max, "rate": _sqrt(A * (beta + gamma)),
            "two_A": 2.0 * A, "A_uy": A / uy,
            # the Park-Wen weight's factor beta sgn + gamma for either sign (_coefficients)
            "bpg": beta + gamma, "gmb": gamma - beta,
        }  # fmt: skip
        self.linear = _wide(linear, m, dims)
        self._unpack(np.stack([_wide(values[name], m, dims) for name in _Closed.NUMERIC]))

    def _unpack(self, stack: np.ndarray):
        self.stack = stack
        for name, value in zip(_Closed.NUMERIC, stack, strict=True):
            setattr(self, name, value)  # a contiguous (m, dims) view

    def take(self, rows) -> _Closed:
        """The constants of the connectors ``rows`` (an index or mask array)."""
        part = object.__new__(_Closed)
        part.unloading, part.unit_z_max, part.linear = self.unloading, self.unit_z_max, self.linear[rows]
        part._unpack(self.stack[:, rows])
        return part


class _Prepared:
    """A law's parameters arranged for calls with ``m`` connectors, computed once (:meth:`BoucWen._prepared`).

    ``closed``: which connectors have ``n = 2`` (all, none, or a mask), with the closed form's constants
    of those; the force's coefficients as :meth:`BoucWen.respond` applies them, in the shapes of
    the force and the tangent.
    """

    __slots__ = (
        "values", "one", "all_closed", "none_closed", "closed_rows", "closed", "substepped", "hysteretic",
        "hysteretic_matrix", "alpha_zero", "alpha_k", "alpha_k_matrix",
    )

    def __init__(self, p: _Values, m: int, dims: int, still: float):
        self.values = p
        n2 = np.full(m, p.n == 2.0) if p.scalar else p.n[:, 0] == 2.0
        self.all_closed, self.none_closed = bool(np.all(n2)), not bool(np.any(n2))
        # one connector with scalar parameters: the closed form in Python floats (BoucWen._exact_one)
        self.one = p.scalar and self.all_closed and m == 1
        self.closed_rows = None if (self.all_closed or self.none_closed) else n2
        closed = p if self.all_closed else p.take(n2)
        self.closed = None if self.none_closed else _Closed(closed, int(np.count_nonzero(n2)), dims, still)
        self.substepped = None if self.none_closed or self.all_closed else p.take(~n2)
        hysteretic = (1.0 - p.alpha) * p.k * p.uy
        self.hysteretic = _wide(hysteretic, m, dims)
        self.hysteretic_matrix = np.array(np.broadcast_to(p.matrix(hysteretic), (m, dims, dims)))
        # alpha = 0 (the preset's): F = hysteretic z, the same numbers as 0 u + hysteretic z but for the sign of a zero.
        self.alpha_zero = _uniform(p.alpha, 0.0)
        self.alpha_k = _wide(p.alpha * p.k, m, dims)
        self.alpha_k_matrix = np.array(np.broadcast_to(p.matrix(p.alpha * p.k) * np.eye(dims), (m, dims, dims)))


#: Per law object (by id, while it lives): its :class:`_Prepared` per connector count.
_PREPARED: dict[int, tuple[weakref.ref, dict[int, _Prepared]]] = {}


def _forget(key: int):
    """A weakref callback: the law with this id is gone, so is its entry."""
    return lambda _ref: _PREPARED.pop(key, None)


@attrs.frozen
class BoucWen:
    """Smooth hysteresis: stiffness ``k`` at first, ``alpha k`` after yield at about ``uy``.

    State: ``{"z": (n, dims), "u": (n, dims)}``, the hysteretic variable and the displacement
    at the last committed step (``z`` is driven by the increment from it). The normal force is
    accepted and ignored: this form does not scale with N (a sliding bearing modelled with it
    has a yield force fixed by ``k uy``).

    Every numeric parameter may be one value per connector (``per_bearing``: a 1-D array of the
    length of the connectors the law serves); connectors with ``n = 2`` are integrated in closed
    form and the others by substeps, all in one vectorised call. The biaxial Park-Wen form is not
    isotropic (``isotropic = False``): it depends on the axes of the two shear directions.
    """

    name: ClassVar[str] = "bouc-wen"
    rigid: ClassVar[bool] = False
    symmetric: ClassVar[bool] = True
    per_bearing: ClassVar[bool] = True
    #: The |du_x z_x| + |du_y z_y| term of the Park-Wen form depends on the axes (module docstring).
    isotropic: ClassVar[bool] = False
    #: n != 2: substep length times the largest rate |d(dz/du)/dz| over the admissible ball.
    SUBSTEP_RATIO: ClassVar[float] = 0.03
    #: Substeps per call at most: a longer increment is cut into this many equal substeps.
    MAX_SUBSTEPS: ClassVar[int] = 1000
    #: Displacements (m) beyond this cannot be integrated in floating point (the squares of increments
    #: of about 1e154 overflow): they are answered like NaN (:meth:`_non_finite`).
    MAX_DISPLACEMENT: ClassVar[float] = 1e150
    MAX_NEWTON_ITERATIONS: ClassVar[int] = 30
    #: n = 2: an increment shorter than STILL uy leaves z as it is (its effect is relatively that small).
    STILL: ClassVar[float] = 1e-200

    k: float = _parameter(
        low=0.0, low_open=True, unit="N/m", doc="elastic stiffness (the initial stiffness when A = 1)", typical=4e8
    )
    alpha: float = _parameter(low=0.0, high=1.0, high_open=True, doc="post-yield to elastic stiffness ratio")
    uy: float = _parameter(low=0.0, low_open=True, unit="m", doc="yield displacement", typical=1e-3)
    A: float = _parameter(low=0.0, low_open=True, default=1.0, doc="hysteretic stiffness factor", typical=1.0)
    beta: float = _parameter(
        low=0.0, low_open=True, default=0.5, doc="loop shape; beta >= |gamma| and beta + gamma > 0", typical=0.5
    )
    gamma: float = _parameter(default=0.5, doc="loop shape; -beta < gamma <= beta", typical=0.5)
    n: float = _parameter(
        low=1.0, default=1.0, doc="smoothness exponent (larger: sharper yield; n = 2 is integrated exactly, fastest)",
        typical=1.0,
    )
    dims: int = bearingfw.dims_parameter()

    def __attrs_post_init__(self):
        lengths = {name: len(getattr(self, name)) for name in _NUMERIC if isinstance(getattr(self, name), np.ndarray)}
        if len(set(lengths.values())) > 1:
            listed = ", ".join(f"{name!r} ({length})" for name, length in lengths.items())
            raise bearingfw.ParameterError(
                f"{self.name}: per-bearing parameters must have one value per connector, all of the same length; "
                f"got {listed}"
            )
        # The single-parameter ranges are checked by the fields; these two involve both shape parameters.
        beta, gamma = np.asarray(self.beta), np.asarray(self.gamma)
        conditions = [
            ("beta + gamma > 0 (else z and the force grow without bound)", beta + gamma > 0),
            ("beta >= |gamma| (else the law creates energy on some unloading paths)", beta >= np.abs(gamma)),
        ]
        violated = [condition for condition, holds in conditions if not np.all(holds)]
        if violated:
            if beta.ndim == 0 and gamma.ndim == 0:
                values = f"'beta' = {self.beta!r} and 'gamma' = {self.gamma!r}"
            else:  # name the first connector that breaks a condition
                beta, gamma = np.broadcast_arrays(beta, gamma)
                bad = int(np.flatnonzero(~((beta + gamma > 0) & (beta >= np.abs(gamma))))[0])
                values = f"'beta'[{bad}] = {float(beta[bad])!r} and 'gamma'[{bad}] = {float(gamma[bad])!r}"
            raise bearingfw.ParameterError(
                f"{self.name}: parameters {values} must satisfy {' and '.join(violated)}; allowed: -beta < gamma <= beta"
            )

    @property
    def z_max(self):
        """The bound of ``|z|``, ``(A/(beta+gamma))^(1/n)`` (an array for per-bearing parameters).

        The hysteretic force ``F - alpha k u`` never exceeds ``(1-alpha) k uy z_max`` and tends to it
        on a long monotonic path.
        """
        return (self.A / (self.beta + self.gamma)) ** (1.0 / self.n)

    @property
    def substep(self):
        """The longest backward-Euler substep (m) for ``n != 2``: ``SUBSTEP_RATIO / lambda``.

        ``lambda = n (beta + |gamma|) z_max^(n-1) / uy`` is the largest ``|d(dz/du)/dz|`` of the 1-D law
        over ``|z| <= z_max``, the inverse of the shortest displacement over which ``z`` changes (the
        approach to saturation). A substep of ``0.03 / lambda`` (``0.03 uy`` for the defaults) keeps
        the backward-Euler lag in the knee to about 0.6 % of ``z_max`` (validation/laws.py: within
        1 % of an accurate solution on random paths, as the validation asks), and the Newton matrix within 0.1 of
        the identity (2-D included), so its root in the ball is unique and found in a few iterations.
        """
        return self._substep(self._values(None))

    def _substep(self, p: _Values):
        rate = p.n * (p.beta + abs(p.gamma)) * p.z_max ** (p.n - 1.0) / p.uy
        return self.SUBSTEP_RATIO / rate

    def _values(self, count: int | None) -> _Values:
        """The parameters for a call with ``count`` connectors (None: as the law holds them)."""
        values = [getattr(self, name) for name in _NUMERIC]
        if count is None or not any(isinstance(value, np.ndarray) for value in values):
            return _Values(*values)
        if count == 1:  # one connector: the scalar arithmetic, exactly as a law with these values
            return _Values(*(float(np.asarray(value).reshape(-1)[0]) for value in values))
        # Contiguous columns (a copy, not a broadcast view): numpy's fast loop needs them, several
        # times cheaper on so small arrays than the strided one a broadcast scalar would take.
        columns = (np.array(np.broadcast_to(np.asarray(value, dtype=float), (count,))) for value in values)
        return _Values(*(column.reshape(count, 1) for column in columns))

    def _prepared(self, count: int) -> _Prepared:
        """The parameters arranged for a call with ``count`` connectors, built (and the per-bearing
        lengths checked) at the first call with that count, then reused: they depend only on the
        law, which is immutable, and on ``count``. Kept beside the law, as a frozen attrs object
        holds only its fields."""
        entry = _PREPARED.get(id(self))
        if entry is None or entry[0]() is not self:
            entry = (weakref.ref(self, _forget(id(self))), {})
            _PREPARED[id(self)] = entry
        prepared = entry[1].get(count)
        if prepared is None:
            check_per_bearing(self, count)
            prepared = _Prepared(self._values(count), count, self.dims, self.STILL)
            entry[1][count] = prepared
        return prepared

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"z": np.zeros((n, self.dims)), "u": np.zeros((n, self.dims))}

    def slip(self, state) -> np.ndarray:
        """The plastic part of the displacement: ``u`` less the hysteretic spring's elastic part.

        The hysteretic spring has initial stiffness ``(1 - alpha) k A`` and force
        ``(1 - alpha) k uy z``, so its elastic deformation is ``uy z / A``.
        """
        p = self._prepared(len(state["u"])).values
        return state["u"] - p.uy * state["z"] / p.A

    def respond(self, state, u, normal_force, dt) -> bearingfw.LawResponse:
        # The shapes checked naming the law (numpy would broadcast a wrong one); then a copy: the state
        # must not alias the caller's array.
        u = np.array(respond_inputs(self, u, normal_force)[0])
        prepared = self._prepared(len(u))  # checks the per-bearing lengths at a new count
        if not _within(u, self.MAX_DISPLACEMENT):
            return self._non_finite(state, u, normal_force, dt)
        p = prepared.values
        du = u - state["u"]
        z = state["z"]
        # The signs of the increment's components, for the derivative of |du_i|: those of du, and
        # where du_i = 0 (a kink of the law) the unloading side (z_i moving towards 0): the
        # stiffer one, like an elastic predictor, and the one the friction law takes there too.
        # In the substep scheme they are the signs of every substep's delta (so that the tangent
        # is the derivative in the direction of motion even where a substep is empty).
        if prepared.one:
            # One connector: the closed form in Python floats, as numpy's per-operation overhead
            # would dominate.
            z, dz_du = self._exact_one(p, z, du)
        else:
            if self.dims == 1:
                direction = np.sign(du)
                if not _all(direction):  # a connector that does not move (typically a whole static call)
                    direction = np.where(du != 0, direction, -np.sign(z))
            else:  # a component often stays (a bearing moving along an axis): no test first
                direction = np.sign(np.where(du != 0, du, -z))
            if prepared.all_closed:
                z, dz_du = self._exact(prepared.closed, z, du, direction)
            elif prepared.none_closed:
                z, dz_du = self._substepped(p, z, du, direction)
            else:  # per connector: n = 2 in closed form, the others by substeps
                closed = prepared.closed_rows
                z, dz_du = z.copy(), np.empty(z.shape + (self.dims,))
                z0 = state["z"]
                z[closed], dz_du[closed] = self._exact(prepared.closed, z0[closed], du[closed], direction[closed])
                z[~closed], dz_du[~closed] = self._substepped(
                    prepared.substepped, z0[~closed], du[~closed], direction[~closed]
                )
        if prepared.alpha_zero:
            force, tangent = prepared.hysteretic * z, prepared.hysteretic_matrix * dz_du
        else:
            force = prepared.alpha_k * u + prepared.hysteretic * z
            tangent = prepared.alpha_k_matrix + prepared.hysteretic_matrix * dz_du
        # An increment with nothing to do hands z0 back: never share an array with the old state.
        z = z.copy() if z is state["z"] else z
        return bearingfw.LawResponse(force, tangent, {"z": z, "u": u})

    def _non_finite(self, state, u, normal_force, dt) -> bearingfw.LawResponse:
        """A call with NaN, infinite or absurd displacements (beyond :attr:`MAX_DISPLACEMENT`): they
        propagate to NaN forces and tangents of their connectors (which the kernel's step control
        detects), the others answer as usual."""
        bad = ~(np.abs(u) <= self.MAX_DISPLACEMENT).all(axis=1)
        sound = np.where(bad[:, None], state["u"], u)
        response = self.respond(state, sound, normal_force, dt)
        force, tangent = np.array(response.force, dtype=float), np.array(response.tangent, dtype=float)
        force[bad], tangent[bad] = np.nan, np.nan
        z = response.state["z"].copy()
        z[bad] = np.nan
        return bearingfw.LawResponse(force, tangent, {"z": z, "u": u})

    def _exact_one(self, p: _Values, z0, du):
        """:meth:`_exact` for one connector, in Python floats (the same operations, the same results)."""
        A, beta, gamma, uy = p.A, p.beta, p.gamma, p.uy
        z, d = z0[0].tolist(), du[0].tolist()
        direction = [(1.0 if di > 0 else -1.0) if di != 0 else -_sign(zi) for zi, di in zip(z, d, strict=True)]
        if self.dims == 1:
            if abs(d[0]) > self.STILL * uy:
                z1, slope = _riccati_1d_one(z[0], d[0], direction[0], A, beta, gamma, uy)
                return np.array([[z1]]), np.array([[[slope]]])
            abs_z = abs(z[0])
            return z0, np.array([[[(A - abs_z * (beta * z[0] * direction[0] + gamma * abs_z)) / uy]]])
        if math.hypot(*d) > self.STILL * uy:
            zx, zy, tangent = _riccati_2d_one(*z, *d, *direction, A, beta, gamma, uy)
            return np.array([[zx, zy]]), np.array([tangent])
        slope = [(beta * abs(zi) * di + gamma * zi) / -uy for zi, di in zip(z, direction, strict=True)]
        tangent = [[z[i] * slope[j] + (A / uy if i == j else 0.0) for j in range(2)] for i in range(2)]
        return z0, np.array([tangent])

    def _substepped(self, p: _Values, z, du, direction):
        """``z`` at the end of ``du`` and ``dz/du`` by backward-Euler substeps (any ``n``)."""
        # dz/du so far, chain-ruled through the substeps; the committed z does not depend on u.
        dz_du = np.zeros(z.shape + (self.dims,))
        for delta, d_delta in self._substeps(p, du):
            z, newton_matrix = self._backward_euler(p, z, delta)
            # Differentiate z1 - z0 - Phi(z1, delta)/uy = 0:  (I - dPhi/dz) dz1 = dz0 + dPhi/ddelta ddelta.
            dz_du = _solve(newton_matrix, dz_du + self._flow_delta_derivative(p, z, direction) @ d_delta)
        return z, dz_du

    def _exact(self, k: _Closed, z0, du, direction):
        """``z`` at the end of ``du`` and ``dz/du`` for ``n = 2``, in closed form (module docstring).

        Connectors that move by less than ``STILL uy`` (in length) keep ``z0``, with the derivative
        ``dPhi/ddelta / uy`` of the flow at ``z0`` in the direction of ``direction``: the limit of the
        moving case, from which they differ by about ``STILL`` relative (and the complex step would
        underflow below it).
        """
        if self.dims == 1:
            length = np.abs(du)
            if _all(length > k.still):  # the common case: every connector moves
                return _riccati_1d(z0, length, direction, k)
        else:  # |du| in both columns (hypot is symmetric): the closed form's shape (_Closed)
            length = np.hypot(du, du[:, ::-1])
            if _all(length > k.still):
                return _riccati_2d(z0, du, length, direction, k)
        moving = (length > k.still)[:, 0]
        # dPhi/ddelta / uy at z0 = (A I - z0 (beta |z0| direction + gamma z0)^T) / uy for n = 2
        slope = (k.beta * np.abs(z0) * direction + k.gamma * z0) / -k.uy
        z, dz_du = z0, z0[:, :, None] * slope[:, None, :] + k.A_uy[:, :1, None] * np.eye(self.dims)
        if moving.any():  # else nothing moves (the first evaluation of a time step, typically)
            z = z0.copy()
            part, z0, length, direction = k.take(moving), z0[moving], length[moving], direction[moving]
            if self.dims == 1:
                z[moving], dz_du[moving] = _riccati_1d(z0, length, direction, part)
            else:
                z[moving], dz_du[moving] = _riccati_2d(z0, du[moving], length, direction, part)
        return z, dz_du

    def _substeps(self, p: _Values, du):
        """Yield ``(delta, d delta / d du)`` per substep, ``(n, dims)`` and ``(n, dims, dims)``.

        Full substeps of length ``s = max(h, |du| / MAX_SUBSTEPS)`` along ``e = du/|du|``, then the
        remainder. A remainder (rather than equal substeps) keeps the result continuous in ``du``:
        where the count of full substeps jumps, the remainder is zero on one side and a full
        substep on the other. The tangent has a kink there (a step's derivative in its own
        length is smaller at ``h`` than at 0, by up to ``1/(1 + lambda h)``, about 9 %), as at a
        reversal; exactly at the jump it is the derivative on the side of longer increments.
        Connectors that need fewer substeps get empty ones, which leave ``z`` unchanged.
        """
        eye = np.eye(self.dims)
        h = self._substep(p)
        h = h if p.scalar else h[:, 0]
        length = _norm(du)[:, 0]
        if np.all(length < h):  # the common case of a short increment: one step
            yield du, np.broadcast_to(eye, du.shape + (self.dims,))
            return
        safe_length = np.where(length > 0, length, 1.0)
        e = du / safe_length[:, None]
        s = np.maximum(h, length / self.MAX_SUBSTEPS)
        full = np.floor(length / s)
        # d(s e)/d du = s'(L) e e^T + s (I - e e^T)/L, with s' = 0 or 1/MAX_SUBSTEPS.
        eet = e[:, :, None] * e[:, None, :]
        slope = np.where(h >= length / self.MAX_SUBSTEPS, 0.0, 1.0 / self.MAX_SUBSTEPS)
        # s/L only matters where there are full substeps (L >= s): elsewhere keep it finite.
        d_full = slope[:, None, None] * eet + (s / np.maximum(length, s))[:, None, None] * (eye - eet)
        full_step = s[:, None] * e
        remainder = du - full[:, None] * full_step
        d_remainder = eye - full[:, None, None] * d_full
        for j in range(int(full.max()) + 1):
            is_full, is_last = (j < full)[:, None], (j == full)[:, None]
            delta = is_full * full_step + is_last * remainder
            yield delta, is_full[:, :, None] * d_full + is_last[:, :, None] * d_remainder

    def _backward_euler(self, p: _Values, z0, delta):
        """Solve ``R(z) = z - z0 - Phi(z, delta)/uy = 0`` by Newton; return ``z`` and ``dR/dz`` there.

        Iterates are kept in the ball ``|z| <= z_max``: the root lies in it, so pulling an iterate
        back radially only brings it closer (and keeps ``|z|^n`` finite for large n). Converged
        when the residual is at round-off level, so the returned matrix is the exact ``dR/dz`` at
        the returned ``z``. Each connector keeps the iterate at which it converged (the others
        iterate on): a connector's answer does not depend on the connectors it is called with.
        """
        z_max = p.z_max
        eye = np.eye(self.dims)
        # Round-off of R is about eps (|z| + |A delta / uy|): stop well above it, per connector.
        tolerance = 1e-13 * (z_max + p.A * np.abs(delta) / p.uy)
        z = z0
        result, matrix = np.empty_like(z0), np.empty(z0.shape + (self.dims,))
        pending = np.ones(len(z0), dtype=bool)
        for _ in range(self.MAX_NEWTON_ITERATIONS):
            flow, flow_z = self._flow(p, z, delta)
            residual = z - z0 - flow
            newton_matrix = eye - flow_z
            converged = pending & np.all(np.abs(residual) <= tolerance, axis=1)
            if converged.all():  # one connector, or all at once: as they are
                return z, newton_matrix
            result[converged], matrix[converged] = z[converged], newton_matrix[converged]
            pending &= ~converged
            if not pending.any():
                return result, matrix
            z = z - _solve(newton_matrix, residual[:, :, None])[:, :, 0]
            if self.dims == 1:
                z = np.clip(z, -z_max, z_max)
            else:
                norm = _norm(z)
                z = np.where(norm > z_max, z * (z_max / np.maximum(norm, z_max)), z)
        # Not converged (an absurd increment, e.g. 1e300 m): NaN for those connectors, as for a non-finite
        # displacement; the kernel's step control takes a non-finite answer as a failed trial.
        result[pending], matrix[pending] = np.nan, np.nan
        return result, matrix

    def _flow(self, p: _Values, z, delta):
        """``Phi(z, delta)/uy`` and its derivative in ``z``, all connectors at once.

        With ``q = beta sum_i |delta_i z_i| + gamma z . delta`` and ``r = |z|``,
        ``Phi = A delta - r^(n-2) q z``. Since ``q`` is linear in ``z``, ``r^(n-2) q = r^(n-1) q_hat``
        with ``q_hat = q / r`` evaluated at the unit vector ``z_hat``: finite at ``z = 0`` for
        ``n >= 1`` (``z_hat`` is taken as 0 there). The derivative::

            d(r^(n-2) q z)/dz = r^(n-1) q_hat I + r^(n-1) z_hat ((n-2) q_hat z_hat + dq/dz)^T

        with ``dq/dz = beta |delta| sgn(z) + gamma delta`` (``sgn(0) = 0``: the mean of the one-sided
        derivatives). In 1-D, ``q_hat = beta |delta| + gamma delta sgn(z)`` and the derivative is
        ``n |z|^(n-1) q_hat``, evaluated in that closed form: guided bearings are the common case.
        """
        if self.dims == 1:
            c = np.abs(z) ** (p.n - 1.0) * (p.beta * np.abs(delta) + p.gamma * delta * np.sign(z))
            return (p.A * delta - c * z) / p.uy, (c * (p.n / -p.uy))[:, :, None]
        r = _norm(z)
        z_hat = z / np.where(r > 0, r, 1.0)  # 0 at z = 0
        r_n1 = r ** (p.n - 1.0)
        abs_delta = np.abs(delta)
        q_hat = (p.beta * abs_delta * np.abs(z_hat) + p.gamma * z_hat * delta).sum(axis=1)[:, None]
        c = r_n1 * q_hat
        flow = (p.A * delta - c * z) / p.uy
        dq_dz = p.beta * abs_delta * np.sign(z) + p.gamma * delta
        dw_dz = c[:, :, None] * np.eye(self.dims)
        dw_dz += (r_n1 * z_hat)[:, :, None] * ((p.n - 2.0) * q_hat * z_hat + dq_dz)[:, None, :]
        return flow, dw_dz / p.matrix(-p.uy)

    def _flow_delta_derivative(self, p: _Values, z, direction):
        """``d(Phi/uy)/d delta = (A I - r^(n-1) z_hat (beta |z| sgn(delta) + gamma z)^T) / uy``.

        ``sgn(delta)`` is taken as ``direction``, the signs of the whole increment (see respond).
        In 1-D: ``(A - |z|^(n-1) (beta z sgn(delta) + gamma |z|)) / uy``.
        """
        if self.dims == 1:
            abs_z = np.abs(z)
            slope = p.A - abs_z ** (p.n - 1.0) * (p.beta * z * direction + p.gamma * abs_z)
            return (slope / p.uy)[:, :, None]
        r = _norm(z)
        z_hat = z / np.where(r > 0, r, 1.0)
        dq_ddelta = p.beta * np.abs(z) * direction + p.gamma * z
        dw_ddelta = (r ** (p.n - 1.0) * z_hat)[:, :, None] * dq_ddelta[:, None, :]
        return (p.matrix(p.A) * np.eye(self.dims) - dw_ddelta) / p.matrix(p.uy)


def _riccati_1d(z0, length, direction, k: _Closed):
    """1-D: ``zeta = sgn(du) z`` only grows, by ``uy zeta' = A - (beta |zeta| + gamma zeta) zeta``.

    Below zero (unloading) ``uy zeta' = A + b zeta^2`` (``b = beta - gamma >= 0``): with
    ``s = sqrt(b/A)``, ``kappa = sqrt(A b)``, ``zeta = tan(atan(s zeta0) + kappa t)/s`` up to
    ``zeta = 0`` (``zeta0 + A t`` if ``b = 0``). Above (loading) ``uy zeta' = A - a zeta^2``
    (``a = beta + gamma``), ``zeta = z_max tanh(atanh(zeta0/z_max) + k t)``, ``k = sqrt(A a)``,
    by the addition theorem. ``t`` is the distance in units of ``uy`` (``length = |du|``). The
    tangent of an exact 1-D integration is the right-hand side at the end point: ``dz/du = F(z1)/uy``.
    """
    A = k.A
    zeta = direction * z0
    t = length / k.uy
    unloading = zeta < 0
    if unloading.any():
        if k.unloading == "tan":
            angle = np.arctan(k.s * zeta) + k.kappa * t  # zeta reaches 0 where the angle does
            zeta = np.where(unloading, np.tan(np.minimum(angle, 0.0)) / k.s, zeta)
            t = np.where(unloading, np.maximum(angle, 0.0) / k.kappa, t)
        elif k.unloading == "linear":
            left = zeta + A * t  # the distance left after zeta reaches 0, times A
            zeta = np.where(unloading, np.minimum(left, 0.0), zeta)
            t = np.where(unloading, np.maximum(left, 0.0) / A, t)
        else:  # per-bearing parameters with both cases: each chosen per connector
            linear, s, kappa = k.linear, k.s, k.kappa
            angle = np.arctan(s * zeta) + kappa * t
            left = zeta + A * t
            zeta_end = np.where(linear, np.minimum(left, 0.0), np.tan(np.minimum(angle, 0.0)) / s)
            t_left = np.where(linear, np.maximum(left, 0.0) / A, np.maximum(angle, 0.0) / kappa)
            zeta, t = np.where(unloading, zeta_end, zeta), np.where(unloading, t_left, t)
    rise = np.tanh(k.rate * t)
    if k.unit_z_max:
        zeta = (zeta + rise) / (1.0 + rise * zeta)
    else:
        zeta = (zeta + k.z_max * rise) / (1.0 + rise * zeta / k.z_max)
    # F(z1) / uy, with z1 = direction zeta1: (A - |zeta| (beta zeta + gamma |zeta|)) / uy
    abs_zeta = np.abs(zeta)
    slope = (A - abs_zeta * (k.beta * zeta + k.gamma * abs_zeta)) / k.uy
    return direction * zeta, slope[:, :, None]


def _riccati_2d(z0, du, length, direction, k: _Closed):
    """2-D: segments of fixed signs of ``z``; the transverse derivative by a complex step.

    ``dz/du = dz/dL e^T + dz/de (I - e e^T)/L`` with ``I - e e^T = p p^T`` (``p`` the unit normal
    of ``e``). Along ``e``: ``dz/dL = F(z1)/uy``. Across: ``dz/de p`` is the imaginary part of
    the same closed form evaluated with ``e + i h p`` (``|e_i|`` as ``direction_i e_i``, the
    derivative's convention at ``e_i = 0``), divided by ``h``: exact to round-off, as the map is
    analytic in ``e`` for fixed signs (with :func:`_tanhc`'s series near 0, and ``h t^2`` kept
    small, so that every imaginary part stays a perturbation). The segments' lengths are real and fixed: an event's
    position does not enter the derivative (``F`` is continuous where a component of ``z``
    changes sign, so moving the event changes nothing to first order). ``length = |du|``.
    """
    e = du / length
    p = e[:, ::-1] * _ROTATE
    t = length / k.uy  # the increment's length in units of uy
    tt = t * t
    h = _STEP / np.maximum(1.0, tt)  # Im(c t^2) stays at most about |_STEP|, whatever t
    e_step = e + h * p
    w, q, c = _coefficients(z0, e_step, direction, k)
    z, crossed = _segment(z0, e_step, q, c, t, tt, k.two_A)
    if crossed is not None:  # rare: a component of z changes sign within the increment
        z, w = z.copy(), w.copy()
        za, t_left, q, c = z0[crossed], t[crossed], q[crossed], c[crossed]
        part = k.take(crossed)
        for _ in range(2):  # each component crosses at most once
            e_c, e_step_c, direction_c = e[crossed], e_step[crossed], direction[crossed]
            first, t_first = _first_crossing(za.real, e_c, q.real, c.real, t_left, part.A)
            za = _segment(za, e_step_c, q, c, t_first, t_first * t_first, part.two_A, check=False)[0]
            hit = np.flatnonzero(first >= 0)
            za.real[hit, first[hit]] = 0.0  # exactly on the switching line
            t_left = t_left - t_first
            w_c, q, c = _coefficients(za, e_step_c, direction_c, part)
            z_c, again = _segment(za, e_step_c, q, c, t_left, t_left * t_left, part.two_A)
            z[crossed], w[crossed] = z_c, w_c
            if again is None:
                break
            crossed, za, t_left, q, c = crossed[again], za[again], t_left[again], q[again], c[again]
            part = part.take(again)
    z_end = z.real
    # F(z1)/uy = (A e - (w . z1) z1)/uy, with the last segment's signs (F is continuous across them).
    along = k.A_uy * e - _row_sums(w.real * z_end) * (z_end / k.uy)
    across = z.imag / (h.imag * length)
    return z_end, along[:, :, None] * e[:, None, :] + across[:, :, None] * p[:, None, :]


def _segment(za, e_step, q, c, t, tt, two_A, check=True):
    """The closed form over ``t`` (in units of uy; ``tt = t^2``) from ``za`` with coefficients ``q``, ``c``
    (``two_A = 2 A``): ``(z, crossed)``.

    ``crossed``: indices of the connectors along which a component of ``z`` would change sign
    (then ``z`` is not their end state), or None. Without a crossing ``f`` is increasing on the
    segment, so a component keeps its sign if it has it at the end, where ``1 + 2 q v + c v^2 > 0``
    (concave in ``v`` if ``c < 0``, so positive all along) and ``v`` is on its first branch.
    """
    y = c * (tt / 4.0)
    v = 0.5 * t * _tanhc(y)
    qv, cv2 = q * v, c * v * v
    denominator = 1.0 + 2.0 * qv + cv2
    z = (za * (1.0 - cv2) + two_A * (v + qv * v) * e_step) / denominator
    crossed = None
    if check:
        # One reduction for the common case: a sign flipped, 1 + 2 q v + c v^2 < 0, or the angle
        # of a c < 0 segment past pi (y < -pi^2/4, v past its first branch).
        real = za.real
        flags = np.minimum(real * z.real, np.minimum(denominator.real, y.real + _PI2_4))
        if np.minimum.reduce(flags, axis=None, initial=0.0) < 0:
            crossed = np.flatnonzero((flags < 0).any(axis=1))
    return z, crossed


def _coefficients(za, e, direction, k: _Closed):
    """``w``, ``q = w . za`` and ``c = A w . e`` of the segment starting at ``za`` (module docstring).

    ``w_i = beta |e_i| sgn(z_i) + gamma e_i = (beta sgn(z_i) direction_i + gamma) e_i`` (``|e_i| =
    direction_i e_i``), with ``sgn(z_i)`` that of ``za_i``, or where ``za_i = 0`` that of the motion
    (the sign ``z_i`` takes at once), i.e. ``sgn(z_i) direction_i = sgn(za_i direction_i + tiny)``
    (where also ``direction_i = 0``, ``e_i = 0`` and the factor multiplies nothing).
    """
    # beta sgn + gamma is beta + gamma or gamma - beta: one choice instead of sign, product and sum.
    # sgn(x + tiny) > 0 exactly where x > -tiny (rounding never changes the sign of a sum); it is
    # 0 only at x = -tiny, a product of no displacement.
    factor = np.where(za.real * direction > -_TINY, k.bpg, k.gmb)
    w = factor * e
    return w, _row_sums(w * za), k.A * _row_sums(w * e)


def _first_crossing(z, e, q, c, t, A):
    """Which component of ``z`` reaches 0 first along the segment, and where (in units of uy).

    Component ``i`` (``z_i e_i < 0``) reaches 0 where ``A e_i f(v) = -z_i``, with ``f(v) = (2 v +
    2 q v^2) / (1 - c v^2)`` increasing: ``(2 q + c T) v^2 + 2 v - T = 0``, ``T = -z_i/(A e_i)``,
    whose smallest positive root is ``T / (1 + sqrt(1 + (2 q + c T) T)) = 1 / (s + sqrt(s^2 + 2 q s
    + c))`` with ``s = 1/T`` (the discriminant is positive wherever the crossing is reached); then
    ``t = 2 v atanhc(c v^2)``. Called for connectors along which a crossing happens before ``t``:
    the result is at most ``t``.
    """
    opposite = z * e < 0
    with np.errstate(all="ignore"):  # 1/T overflows only for a component at 0: it crosses at once
        s = np.where(opposite, -A * e / z, 0.0)  # 1/T: no overflow where e_i is tiny
        discriminant = s * s + 2.0 * q * s + c  # (1 + (2 q + c T) T) / T^2
        v_cross = 1.0 / (s + np.sqrt(np.maximum(discriminant, 0.0)))
        y = c * v_cross * v_cross
        # c v^2 < 1: v on the branch where f is finite (else T is never reached: f < T all along).
        t_cross = np.where(opposite & (discriminant >= 0) & (y < 1), 2.0 * v_cross * _atanhc(y), np.inf)
    t_cross = np.where(t_cross >= 0, t_cross, np.inf)  # (nan: s = c = 0, a component that never moves)
    first = np.argmin(t_cross, axis=1)
    t_first = t_cross[np.arange(len(first)), first][:, None]
    # A flag without a crossing (round-off at a component ending exactly at 0): no component.
    return np.where(np.isfinite(t_first[:, 0]), first, -1), np.minimum(t_first, t)


def _row_sums(v):
    """The sums ``v_0 + v_1`` of ``(n, 2)`` rows, in both columns (``v_1 + v_0`` is the same number):
    ``v.sum(axis=1)``'s own sum, in the shape of the closed form's arrays (:class:`_Closed`)."""
    return v + v[:, ::-1]


def _all(flags) -> bool:
    """``flags.all()`` without the method's Python wrapper."""
    return bool(np.logical_and.reduce(flags, axis=None))


def _sqrt(x):
    """``math.sqrt`` for a float (a scalar law's arithmetic, unchanged), ``np.sqrt`` for per-bearing columns."""
    return math.sqrt(x) if isinstance(x, float) else np.sqrt(x)


def _within(u, bound: float) -> bool:
    """Whether every displacement is a number within ``[-bound, bound]`` (NaN fails every comparison).

    A few values are compared as Python floats: two numpy reductions cost more on so small arrays.
    """
    if u.size <= 16:
        values = u.ravel().tolist()
        if not values:
            return True
        total = sum(values)  # NaN or infinite if a value is (or if they overflow: absurd too)
        return total - total == 0.0 and -bound <= min(values) and max(values) <= bound
    return bool(-bound <= u.min() and u.max() <= bound)


_ROTATE = np.array([-1.0, 1.0])  # (e_y, e_x) * _ROTATE: e turned by +90 degrees
_TINY = 1e-300
#: The complex step (divided by t^2 for t > 1): derivatives are exact to round-off for any small step.
_STEP = 1e-20j


def _tanhc(y):
    """``tanh(sqrt(y))/sqrt(y)`` (``tan(sqrt(-y))/sqrt(-y)`` for ``y < 0``), complex ``y``.

    An even function of ``sqrt(y)``, so analytic in ``y`` whichever square root is taken. For
    ``|y| < 1e-2`` its power series (:data:`_TANHC_SERIES`; the rest is below 1e-19): the
    quotient's imaginary part would carry an absolute error of round-off size there, far larger
    than the complex step's ``h`` when ``Re y`` is about 0 (``c = 0``), where the series, a
    polynomial, keeps it exact. ``y = 0`` (``c = 0``: no sign-dependent term) gives 1.
    """
    size = np.abs(y)
    # (NaN fails both tests below: then the mixture, as for any y)
    all_small = np.maximum.reduce(size, axis=None, initial=0.0) < 1e-2
    if not all_small and np.minimum.reduce(size, axis=None, initial=np.inf) >= 1e-2:
        r = np.sqrt(y)
        return np.tanh(r) / r
    # Horner's scheme, in place (the same operations as series = series * y + coefficient).
    series = _TANHC_SERIES[-1] * y
    series += _TANHC_SERIES[-2]
    for coefficient in _TANHC_SERIES[-3::-1]:
        series *= y
        series += coefficient
    if all_small:
        return series
    small = size < 1e-2
    r = np.sqrt(np.where(small, 1.0, y))
    return np.where(small, series, np.tanh(r) / r)


def _tanhc_one(y):
    """:func:`_tanhc` of one complex number."""
    if abs(y) < 1e-2:
        series = _TANHC_SERIES[-1]
        for coefficient in _TANHC_SERIES[-2::-1]:
            series = series * y + coefficient
        return series
    r = cmath.sqrt(y)
    return cmath.tanh(r) / r


#: tanh(r)/r = sum_k a_k r^(2k), a_k = 2^(2k+2) (2^(2k+2) - 1) B_(2k+2) / (2k+2)!, B the Bernoulli numbers.
_TANHC_SERIES = (1.0, -1 / 3, 2 / 15, -17 / 315, 62 / 2835, -1382 / 155925, 21844 / 6081075, -929569 / 638512875)


def _atanhc(y):
    """The inverse for real ``y < 1``: ``atanh(sqrt(y))/sqrt(y)``, ``atan(sqrt(-y))/sqrt(-y)`` for ``y < 0``.

    Through the complex square root (``atanh(i x) = i atan(x)``), shifted like :func:`_tanhc`.
    """
    r = np.sqrt(y + (_TINY + 0j))
    return (np.arctanh(r) / r).real


# --- one connector: the same closed form in Python floats and complex numbers ----------------


def _sign(x):
    return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)


def _riccati_1d_one(z0, du, direction, A, beta, gamma, uy):
    """:func:`_riccati_1d` for one connector: ``(z1, dz/du)``."""
    zeta = direction * z0
    t = abs(du) / uy
    if zeta < 0:
        b = beta - gamma
        if b > 0:
            s, kappa = math.sqrt(b / A), math.sqrt(A * b)
            angle = math.atan(s * zeta) + kappa * t
            zeta, t = math.tan(min(angle, 0.0)) / s, max(angle, 0.0) / kappa
        else:
            left = zeta + A * t
            zeta, t = min(left, 0.0), max(left, 0.0) / A
    z_max = math.sqrt(A / (beta + gamma))
    rise = math.tanh(math.sqrt(A * (beta + gamma)) * t)
    zeta = (zeta + z_max * rise) / (1.0 + rise * zeta / z_max)
    abs_zeta = abs(zeta)
    return direction * zeta, (A - abs_zeta * (beta * zeta + gamma * abs_zeta)) / uy


def _riccati_2d_one(zx, zy, dx, dy, sx, sy, A, beta, gamma, uy):
    """:func:`_riccati_2d` for one connector (``s`` = direction): ``(z1x, z1y, dz/du as nested tuples)``."""
    length = math.hypot(dx, dy)
    ex, ey = dx / length, dy / length
    px, py = -ey, ex
    t = length / uy
    h = _STEP.imag / max(1.0, t * t)
    ecx, ecy = complex(ex, h * px), complex(ey, h * py)
    zax, zay = complex(zx), complex(zy)
    wx, wy, q, c = _coefficients_one(zax, zay, ecx, ecy, sx, sy, A, beta, gamma)
    for _ in range(3):  # at most two events
        zx1, zy1, y, denominator = _segment_one(zax, zay, ecx, ecy, q, c, t, A)
        if min(zax.real * zx1.real, zay.real * zy1.real, denominator.real, y.real + _PI2_4) >= 0:
            break  # no component changed sign (see _segment)
        first, t_first = _first_crossing_one(zax.real, zay.real, ex, ey, q.real, c.real, t, A)
        zax, zay = _segment_one(zax, zay, ecx, ecy, q, c, t_first, A)[:2]
        if first == 0:
            zax = complex(0.0, zax.imag)  # exactly on the switching line
        elif first == 1:
            zay = complex(0.0, zay.imag)
        t = t - t_first
        wx, wy, q, c = _coefficients_one(zax, zay, ecx, ecy, sx, sy, A, beta, gamma)
    z1x, z1y = zx1.real, zy1.real
    wz = wx.real * z1x + wy.real * z1y
    ax, ay = (A / uy) * ex - wz * (z1x / uy), (A / uy) * ey - wz * (z1y / uy)  # F(z1)/uy
    cx, cy = zx1.imag / (h * length), zy1.imag / (h * length)  # dz/de p / L
    return z1x, z1y, ((ax * ex + cx * px, ax * ey + cx * py), (ay * ex + cy * px, ay * ey + cy * py))


def _coefficients_one(zx, zy, ex, ey, sx, sy, A, beta, gamma):
    wx = (beta * _sign(zx.real * sx + _TINY) + gamma) * ex
    wy = (beta * _sign(zy.real * sy + _TINY) + gamma) * ey
    return wx, wy, wx * zx + wy * zy, A * (wx * ex + wy * ey)


def _segment_one(zx, zy, ex, ey, q, c, t, A):
    y = c * (t * t / 4.0)
    v = 0.5 * t * _tanhc_one(y)
    qv, cv2 = q * v, c * v * v
    denominator = 1.0 + 2.0 * qv + cv2
    along, keep = (2.0 * A) * (v + qv * v), 1.0 - cv2
    return (zx * keep + along * ex) / denominator, (zy * keep + along * ey) / denominator, y, denominator


def _first_crossing_one(zx, zy, ex, ey, q, c, t, A):
    first, t_first = -1, math.inf
    for i, (z, e) in enumerate(((zx, ex), (zy, ey))):
        if z * e < 0:
            s = -A * e / z
            discriminant = s * s + 2.0 * q * s + c
            if discriminant >= 0:
                v = 1.0 / (s + math.sqrt(discriminant))
                y = c * v * v
                if y < 1:
                    r = cmath.sqrt(y + _TINY)
                    t_cross = 2.0 * v * (cmath.atanh(r) / r).real
                    if 0 <= t_cross < t_first:
                        first, t_first = i, t_cross
    return first, min(t_first, t)


_PI2_4 = math.pi**2 / 4


def _norm(v):
    """Row norms of ``v`` (n, dims) as (n, 1); hypot does not underflow for tiny components."""
    return np.abs(v) if v.shape[1] == 1 else np.hypot(v[:, :1], v[:, 1:])


def _solve(matrix, rhs):
    """Solve ``matrix x = rhs`` for stacks of 1x1 or 2x2 matrices, ``rhs`` (n, dims, k).

    Closed form (the adjugate over the determinant): several times faster than LAPACK on so
    small systems, and these solves are the inner loop. The matrices are near the identity
    (see :attr:`BoucWen.substep`), so the closed form is well conditioned.
    """
    if matrix.shape[-1] == 1:
        return rhs / matrix
    # adj [[a, b], [c, d]] = [[d, -b], [-c, a]]: the reversed matrix, transposed, signs flipped.
    adjugate = matrix[:, ::-1, ::-1].transpose(0, 2, 1) * _ADJUGATE_SIGNS
    det = matrix[:, 0, 0] * matrix[:, 1, 1] - matrix[:, 0, 1] * matrix[:, 1, 0]
    return (adjugate @ rhs) / det[:, None, None]


_ADJUGATE_SIGNS = np.array([[1.0, -1.0], [-1.0, 1.0]])
