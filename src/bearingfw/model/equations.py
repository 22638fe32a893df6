"""A homogeneous linear constraint equation on the full DOF vector (see ``constraints``)."""

from __future__ import annotations

import attrs
import numpy as np

__all__ = ["Equation"]


@attrs.frozen(eq=False)
class Equation:
    """One homogeneous constraint ``sum(coefficients * u[dofs]) = 0``.

    ``source`` is ``"support"``, ``"link"`` or ``"connector"``; ``index`` the position of its
    owner in the model's list; ``component`` the DOF component (supports and links) or local
    direction 0/1/2 = x/y/z (connector ties). ``candidates`` are groups of preferred slave DOFs.
    """

    dofs: np.ndarray
    coefficients: np.ndarray
    source: str
    index: int
    component: int
    candidates: tuple[tuple[int, ...], ...] = ()
