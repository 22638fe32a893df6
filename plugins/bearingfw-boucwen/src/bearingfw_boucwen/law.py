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
backward-Euler step ``z1 = z0 + Phi(z1, delta) / uy`` solved by Newton.
Backward Euler keeps ``|z| <= z_max`` for any step (``z . Phi(z) <= 0`` wherever ``|z| >= z_max``,
so a root outside the ball would satisfy ``|z1|^2 <= z1 . z0``, impossible) and, with
``beta >= |gamma|``, dissipates at every step. The returned tangent is the exact derivative of
this discrete map, chain-ruled through the substeps, so the kernel's Newton converges
quadratically. Dozens to hundreds of substeps per call.

Cost. The arithmetic runs in compiled loops over the connectors (:mod:`bearingfw_boucwen._kernels`,
numba, issue 16): numpy's per-operation overhead, about a microsecond on arrays of a few
connectors, had made a call cost 50-500 us. The closed form of n = 2 is one evaluation for any
increment (and a second or third after an event), about 0.2 us (1-D) and 0.7 us (2-D) per
connector; a backward-Euler substep a few Newton iterations. Whatever depends on the
parameters alone (``sqrt(b/A)``, ``z_max``, the substep, the force's coefficients) is computed
once per law and connector count (:meth:`BoucWen._prepared`, :class:`_Prepared`). numba is
imported at the first call of ``respond``, not when the plugin is registered; the compiled code
is cached on disk beside the module (the first call in a fresh installation compiles it, about
10 CPU s; later processes load it in about a second, numba's import included).
``benchmarks/law_cost.py`` (repository root) times every installed law; the plugin's
``tests/test_reference.py`` holds the answers of the former numpy implementation, which the
compiled one matches to 1e-12 relative.

Per-bearing parameters (``per_bearing = True``). Every numeric parameter may be an array with one
value per connector, as the kernel makes them when the bearings of one law differ (the
reference bridge's ``bouc-wen`` preset gives each its own ``uy``). The compiled loop takes one
row of parameters per connector, so connectors with ``n = 2`` go through the closed form and the
others through the substeps in the same call, and each connector of a per-bearing law answers,
to the bit, as a scalar law with its values (tests).
"""

from __future__ import annotations

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

    @property
    def z_max(self):
        return (self.A / (self.beta + self.gamma)) ** (1.0 / self.n)


class _Prepared:
    """A law's parameters arranged for calls with ``m`` connectors, computed once (:meth:`BoucWen._prepared`).

    ``table``: the compiled kernels' parameter table, one row per connector (the columns of
    :mod:`bearingfw_boucwen._kernels`): the parameters and whatever depends on them alone
    (``sqrt(b/A)``, ``z_max``, the substep, the force's coefficients), C-contiguous float64.
    ``kernel``: the compiled ``respond`` of the law's ``dims`` (importing numba at the first call).
    """

    __slots__ = ("values", "table", "kernel")

    def __init__(self, law: BoucWen, p: _Values, m: int):
        self.values = p
        kernels = _kernels()
        A, beta, gamma, uy, n = (np.broadcast_to(np.asarray(v, dtype=float).reshape(-1), (m,)) for v in
                                 (p.A, p.beta, p.gamma, p.uy, p.n))  # fmt: skip
        # Unloading with n = 2 follows uy zeta' = A + b zeta^2, b = beta - gamma: tan for b > 0, linear for b = 0.
        b = beta - gamma
        linear = ~(b > 0)
        ratio = A / (beta + gamma)
        columns = {
            kernels.COL_A: A, kernels.COL_BETA: beta, kernels.COL_GAMMA: gamma, kernels.COL_UY: uy, kernels.COL_N: n,
            kernels.COL_STILL: law.STILL * uy,
            kernels.COL_S: np.sqrt(np.where(linear, 1.0, b / A)),
            kernels.COL_KAPPA: np.sqrt(np.where(linear, 1.0, A * b)),
            kernels.COL_LINEAR: linear.astype(float),
            # the closed form takes z_max as a square root, the substeps as the power (the same to round-off)
            kernels.COL_Z_MAX: np.where(n == 2.0, np.sqrt(ratio), ratio ** (1.0 / n)),
            kernels.COL_RATE: np.sqrt(A * (beta + gamma)),
            kernels.COL_SUBSTEP: law._substep(p),
            kernels.COL_MAX_SUBSTEPS: float(law.MAX_SUBSTEPS),
            kernels.COL_MAX_ITERATIONS: float(law.MAX_NEWTON_ITERATIONS),
            kernels.COL_HYSTERETIC: (1.0 - p.alpha) * p.k * p.uy, kernels.COL_ALPHA_K: p.alpha * p.k,
        }  # fmt: skip
        table = np.empty((m, kernels.COLUMNS))
        for column, value in columns.items():
            table[:, column] = np.broadcast_to(np.asarray(value, dtype=float).reshape(-1), (m,))
        self.table = table
        self.kernel = kernels.respond_1d if law.dims == 1 else kernels.respond_2d


def _kernels():
    """The compiled kernels' module, imported at the first call of ``respond`` (numba's import costs
    a few tenths of a second: registering or listing the plugin does not pay it)."""
    from bearingfw_boucwen import _kernels as module

    return module


#: Per law object (by id, while it lives): its :class:`_Prepared` per connector count.
_PREPARED: dict[int, tuple[weakref.ref, dict[int, _Prepared]]] = {}


def _forget(key: int):
    """A weakref callback: the law with this id is gone, so is its entry."""
    table = _PREPARED  # bound now: at interpreter exit the module's globals may already be None
    return lambda _ref: table.pop(key, None)


@attrs.frozen
class BoucWen:
    """Smooth hysteresis: stiffness ``k`` at first, ``alpha k`` after yield at about ``uy``.

    State: ``{"z": (n, dims), "u": (n, dims)}``, the hysteretic variable and the displacement
    at the last committed step (``z`` is driven by the increment from it). The normal force is
    accepted and ignored: this form does not scale with N (a sliding bearing modelled with it
    has a yield force fixed by ``k uy``).

    Every numeric parameter may be one value per connector (``per_bearing``: a 1-D array of the
    length of the connectors the law serves); connectors with ``n = 2`` are integrated in closed
    form and the others by substeps, all in one call. The biaxial Park-Wen form is not
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
        """The parameters for a call with ``count`` connectors (None: as the law holds them); with
        per-bearing arrays, each a column ``(count, 1)``, which broadcasts over ``(count, dims)``."""
        values = [getattr(self, name) for name in _NUMERIC]
        if count is None or not any(isinstance(value, np.ndarray) for value in values):
            return _Values(*values)
        return _Values(*(np.broadcast_to(np.asarray(value, dtype=float), (count,)).reshape(count, 1) for value in values))

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
            values = self._values(count)
            prepared = _Prepared(self, values, count)
            entry[1][count] = prepared
        return prepared

    def initial_state(self, n: int) -> dict:
        check_per_bearing(self, n)
        return {"z": np.zeros((n, self.dims)), "u": np.zeros((n, self.dims))}

    def compiled(self, n: int) -> bearingfw.CompiledLaw:
        """This law as a compiled function (``_kernels.compiled_law``): the parameter table and
        :attr:`MAX_DISPLACEMENT`; the state packed per connector as ``z`` then ``u``."""
        prepared = self._prepared(n)
        parameters = np.append(prepared.table.reshape(-1), self.MAX_DISPLACEMENT)
        dims = self.dims

        def pack(state) -> np.ndarray:
            return np.concatenate((np.asarray(state["z"], dtype=float).reshape(n, dims),
                                   np.asarray(state["u"], dtype=float).reshape(n, dims)), axis=1).reshape(-1)  # fmt: skip

        def unpack(array: np.ndarray) -> dict:
            packed = array.reshape(n, 2 * dims)
            return {"z": packed[:, :dims], "u": packed[:, dims:]}

        return bearingfw.CompiledLaw(_kernels().compiled_law, parameters, 2 * dims, pack=pack, unpack=unpack)

    def slip(self, state) -> np.ndarray:
        """The plastic part of the displacement: ``u`` less the hysteretic spring's elastic part.

        The hysteretic spring has initial stiffness ``(1 - alpha) k A`` and force
        ``(1 - alpha) k uy z``, so its elastic deformation is ``uy z / A``.
        """
        p = self._prepared(len(state["u"])).values
        return state["u"] - p.uy * state["z"] / p.A

    def respond(self, state, u, normal_force, dt) -> bearingfw.LawResponse:
        # The shapes checked naming the law; then a copy (the state must not alias the caller's
        # array), C-contiguous float64: the kernels' one signature.
        u = np.array(respond_inputs(self, u, normal_force)[0], order="C")
        prepared = self._prepared(len(u))  # checks the per-bearing lengths at a new count
        if not _within(u, self.MAX_DISPLACEMENT):
            return self._non_finite(state, u, normal_force, dt)
        z0, u0 = _state_array(self, state, "z", u.shape), _state_array(self, state, "u", u.shape)
        # Every connector in one compiled loop: n = 2 in closed form, the others by substeps. The signs
        # of the increment's components, for the derivative of |du_i|, are those of du, and where
        # du_i = 0 (a kink of the law) the unloading side (z_i moving towards 0): the stiffer one,
        # like an elastic predictor, and the one the friction law takes there too.
        force, tangent, z = prepared.kernel(prepared.table, z0, u0, u)
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


def _state_array(law, state, key: str, shape) -> np.ndarray:
    """``state[key]`` as a C-contiguous, writeable float64 array of ``shape`` (the compiled kernels'
    one signature; they do not check bounds, so the shape is checked here)."""
    value = state[key]
    if type(value) is not np.ndarray or value.dtype != np.float64 or not value.flags.c_contiguous:
        value = np.array(value, dtype=float, order="C")
    elif not value.flags.writeable:  # numba compiles read-only arrays as another type
        value = value.copy()
    if value.shape != shape:
        raise bearingfw.ParameterError(
            f"law {law.name!r}: respond() argument 'state'[{key!r}] must have the shape of 'u', {shape}, got shape "
            f"{value.shape}"
        )
    return value
