"""The bearing-law protocol: the only thing the kernel knows about a bearing's behaviour.

A law is any object with the five members of :class:`BearingLaw`; no base class is needed.
Its state lives outside it, so that the time integrator can try a trial state in every Newton
iteration and adopt it only when the step is committed, and so that property-based tests can
drive a law directly.

Shapes (``n`` connectors governed by one law object, ``dims`` shear directions each):

- ``u``: total relative shear displacement at the trial point, ``(n, dims)``, metres;
- ``normal_force``: compressive normal force, ``(n,)``, newtons (``>= 0``; a law treats a
  negative value, i.e. uplift, as zero contact);
- ``force``: resisting force, ``(n, dims)``: a linear spring returns ``+k * u``;
- ``tangent``: the algorithmic (consistent) tangent d force / d u, ``(n, dims, dims)``.

Arguments of other shapes are refused, never broadcast into an answer: ``respond`` raises
:class:`bearingfw.ParameterError` naming the law, the argument, the shape expected and the one
given, and likewise for a ``normal_force`` that is NaN or infinite (a friction law would read NaN
as "no sliding" and stick). A NaN or infinite ``u`` may propagate instead, to a non-finite force,
which the kernel's step control detects. The built-in laws do both checks with
:func:`bearingfw.laws.respond_inputs` (shape comparisons and one sum over the normal forces, a
few microseconds per call); a plugin's law can call it too.

Optional members that tools use when present:

- ``symmetric`` (bool, default True): the response is odd in ``u``; the conformance suite
  checks it unless the law says False.
- ``force_bound(normal_force) -> (n,)``: an upper bound of ``|force|`` the law promises
  (friction: ``mu * N``); the conformance suite checks it.
- ``slip(state) -> (n, dims)``: the irreversible part of the relative displacement in a
  committed state (friction: the accumulated slip ``u_p``); recorders report it as "slip".
- ``compiled(n) -> CompiledLaw | None``: the same law as a compiled function
  (:class:`CompiledLaw`) for ``n`` connectors. When every law of a run offers one and none uses
  the velocity, a time step's Newton iteration runs compiled, calling these functions instead of
  ``respond`` (:mod:`bearingfw.analysis.hht_newton`); ``respond`` stays the law's definition,
  and the conformance suite checks that the two agree.

What a law may ask for (class attributes, all optional; a law that declares none of them is
called exactly as above):

- ``uses_velocity = True``: ``respond(state, u, normal_force, dt, velocity=v)`` with ``v``
  ``(n, dims)``, the trial relative velocity (m/s) of the governed directions at the trial point,
  consistent with the integrator (zeros in static calls). Since the integrator's velocity moves
  with ``u`` (HHT: ``dv/du = gamma / (beta dt)``), the response may carry
  ``dforce_dvelocity`` ``(n, dims, dims)``; the kernel adds it to ``tangent`` with that factor.
  ``tangent`` is then d force / d u at fixed velocity.
- ``normal_coupling = True``: the response carries ``dforce_dnormal`` ``(n, dims)``, d force / d N
  at fixed ``u`` (and velocity), so that Newton includes the friction-normal force coupling
  (without it the kernel lets ``N`` lag one iteration).
- ``per_bearing = True``: every numeric parameter (made with ``bearingfw.parameter(...,
  per_bearing=True)``) may be a real number or an array of one value per connector; the kernel
  then gives all connectors of this law and ``dims`` one law object (one call per Newton
  iteration), with arrays only for the parameters that differ between them.
- ``friction = True``: the force is carried by contact at a sliding surface; force and tangent
  are zero whenever ``N <= 0`` (tension, lift-off).
- ``rate_dependent = True``: the response depends on ``dt`` or the velocity (implied by
  ``uses_velocity``). A law that does not say so must give the same forces along a displacement
  path whatever the time step.
- ``linear = True``: the force is affine in ``u`` with one constant tangent, ``F(u) = F(0) + K u``,
  whatever the state, normal force and ``dt``, and the state never changes (a linear spring, free
  sliding). A run whose laws are all linear folds ``K`` into the kernel's factorised matrix: a step
  is one back-substitution, with no law call. The conformance suite checks the claim.
- ``rate_independent_limit() -> (law, equivalent)``: for a rate-dependent law, a copy of it with
  its rate dependence switched off and a rate-independent law that must then respond identically.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import attrs
import numpy as np

__all__ = ["BearingLaw", "CompiledLaw", "LawResponse", "OPTIONAL_FLAGS", "PROTOCOL_MEMBERS", "law_flag"]

#: Members every law must have; the plugin registry reports a law class that lacks one.
PROTOCOL_MEMBERS = ("name", "dims", "rigid", "initial_state", "respond")
#: Optional boolean class attributes by which a law asks for more (module docstring), all False
#: when absent.
OPTIONAL_FLAGS = ("uses_velocity", "normal_coupling", "per_bearing", "friction", "rate_dependent", "linear")


def law_flag(law: Any, flag: str) -> bool:
    """The value of the optional protocol flag ``flag`` of ``law`` (an object or a class); False if absent.

    ``rate_dependent`` is implied by ``uses_velocity``.
    """
    if flag not in OPTIONAL_FLAGS:
        raise ValueError(f"unknown protocol flag {flag!r}; one of {', '.join(OPTIONAL_FLAGS)}")
    value = bool(getattr(law, flag, False))
    if flag == "rate_dependent":
        value = value or bool(getattr(law, "uses_velocity", False))
    return value


@attrs.frozen
class LawResponse:
    """What :meth:`BearingLaw.respond` returns for a trial displacement.

    ``state`` is the trial state: the caller adopts it only when the time step is committed.
    ``dforce_dnormal`` ``(n, dims)`` and ``dforce_dvelocity`` ``(n, dims, dims)`` are given by laws
    that declare ``normal_coupling`` and ``uses_velocity`` (module docstring), else None.
    """

    force: np.ndarray
    tangent: np.ndarray
    state: Any
    dforce_dnormal: np.ndarray | None = None
    dforce_dvelocity: np.ndarray | None = None


@attrs.frozen(eq=False)
class CompiledLaw:
    """A law's ``respond`` as a compiled function, for ``n`` connectors (the optional ``compiled(n)``).

    ``function``: a C-callable function of :func:`bearingfw.jit.law_signature` (made with
    :func:`bearingfw.jit.law_kernel`), given ``parameters`` and the state packed as a flat float64
    array; it writes the force, the tangent, ``dforce_dnormal`` (zeros for a law without it) and
    the new state, and must give what ``respond`` gives; it returns :data:`bearingfw.jit.ANSWERED`
    (anything else hands the call back to ``respond``). ``pack(state)`` flattens a state of ``n``
    connectors to ``state_size`` floats each; ``unpack(array)`` makes the state from such an array
    (which it may keep: the kernel never writes it again)."""

    function: Any
    parameters: np.ndarray
    state_size: int
    pack: Any
    unpack: Any


@runtime_checkable
class BearingLaw(Protocol):
    """A bearing behaviour, vectorised over the connectors that share it."""

    #: Registry key, e.g. ``"regularized-coulomb"``.
    name: str
    #: Shear directions governed together: 1 (guided bearing) or 2 (free sliding).
    dims: int
    #: True only for a law whose directions the kernel ties instead of calling ``respond``.
    rigid: bool

    def initial_state(self, n: int) -> Any:
        """The virgin state of ``n`` connectors (zero force at zero displacement)."""
        ...

    def respond(self, state: Any, u: np.ndarray, normal_force: np.ndarray, dt: float) -> LawResponse:
        """Force and consistent tangent at trial displacement ``u`` from committed ``state``.

        Must be pure: it never mutates ``state``; the new state goes into the response.
        """
        ...
