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

Optional members that tools use when present:

- ``symmetric`` (bool, default True): the response is odd in ``u``; the conformance suite
  checks it unless the law says False.
- ``force_bound(normal_force) -> (n,)``: an upper bound of ``|force|`` the law promises
  (friction: ``mu * N``); the conformance suite checks it.
- ``slip(state) -> (n, dims)``: the irreversible part of the relative displacement in a
  committed state (friction: the accumulated slip ``u_p``); recorders report it as "slip".
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import attrs
import numpy as np

__all__ = ["BearingLaw", "LawResponse", "PROTOCOL_MEMBERS"]

#: Members every law must have; the plugin registry reports a law class that lacks one.
PROTOCOL_MEMBERS = ("name", "dims", "rigid", "initial_state", "respond")


@attrs.frozen
class LawResponse:
    """What :meth:`BearingLaw.respond` returns for a trial displacement.

    ``state`` is the trial state: the caller adopts it only when the time step is committed.
    """

    force: np.ndarray
    tangent: np.ndarray
    state: Any


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
