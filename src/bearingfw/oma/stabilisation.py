"""The stabilisation diagram: which poles are stable from order to order, and which are modes.

A physical mode is found again at every model order above the one where it first appears, with
nearly the same frequency, damping and shape; a noise pole is not. Each pole of order ``n`` is
compared with the pole of the previous order that is nearest in frequency:

- frequency: ``|f - f'| / f' <= frequency`` (the paper: 2 %);
- damping:   ``|zeta - zeta'| / zeta' <= damping`` (the paper: 2 %);
- shape:     ``MAC(phi, phi') >= mac`` (the paper's "convergence": 90 %; complex MAC).

A pole meeting all three is *stable*. Only *physical* poles count: ``0 < zeta <= max_damping``
and within ``[fmin, fmax]`` (a negative or very large damping ratio is a noise or a
mathematical pole).

Automatic selection. The poles stable in frequency and shape are grouped by hierarchical
clustering (average linkage) with the distance ``|f_i - f_j| / max(f_i, f_j) + 1 - MAC_ij``, cut
at ``cluster_distance`` (default: the frequency tolerance plus ``1 - mac``, the most two poles of
one mode may differ). Per cluster one pole per order is kept (the nearest to the cluster's
median frequency). A cluster is a mode when all of these hold (each failure is recorded as the
candidate's reason, :class:`Candidate`):

1. *count*: its poles come from at least ``min_fraction`` of the orders compared (and at least 3);
2. *presence*: from the order where it first appears up to ``max_order`` it is there at
   ``min_presence`` (80 %) of the orders: a physical mode, once found, stays; a noise pole
   comes and goes (the chain's and the bridge's modes: 100 % up to order 100; the chain's noise
   clusters: 10-90 %, most below 75 %);
3. *stable*: at least one of its poles is stable by all three criteria;
4. *scatter*: its frequencies scatter (standard deviation) by at most half the frequency
   tolerance: the poles of a physical mode agree to a fraction of a per cent, while a noise pole
   that happens to keep its shape between orders (easy with few channels) wanders;
5. *MPC*: the mean modal phase collinearity of its shapes is at least ``min_mpc`` (0.8): a
   classically damped structure has real (collinear) shapes, MPC near 1; with many channels
   noise poles have scattered phases (MPC 0.1-0.6 on white noise);
6. *peak*: the averaged spectrum peaks there (:func:`~bearingfw.oma.spectrum.peak_ratio`: the
   prominence of the peak within the mode's half-power band over the valleys on either side,
   on the CMIF curves and along the mode's own shape) by a ratio of at least ``min_peak`` (1.5),
   more on a short record whose estimate scatters (:func:`~bearingfw.oma.spectrum.least_peak`).
   The paper's rule: "only stable poles appearing in the CMIF can be treated as modes"; its
   stable poles near 12 Hz without a CMIF peak were rejected. A lightly damped mode alone gives
   ratios of 10-100 (the 3-DOF chain's), one among close neighbours on the reference bridge
   1.7-3; a mode that shows only as a shoulder on a stronger neighbour's flank 1.1-1.5 (the
   bridge's fourth vertical mode, 5 % below its fifth: rejected, and listed as a near miss); on
   white and low-passed noise the clusters that pass every other check give 1.0-1.5, and a
   pole on the flank of a real mode about 1. ``min_peak = 0`` leaves the check out.

Why not only the fully stable poles: the damping ratio is the least certain estimate, and a
2 % change between orders is a tight bound on it; a physical mode appears at every order above
its first, with frequency and shape stable, while its damping estimate may wander by a few per
cent at some orders. On the 3-DOF chain of the tests the physical modes are stable in frequency
and shape at 12-14 of 14 orders; fully stable, a physical mode may be at only 2. No single check
separates noise from modes on every record: the count and presence catch wandering noise poles,
the MPC catches them on many channels, the spectral peak on few channels, where a noise pole can
keep a real shape.

The mode's frequency and damping are the medians over its poles, its shape their mean (each real
shape turned to the first's sign).
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from scipy.cluster.hierarchy import fcluster, linkage
from scipy.spatial.distance import squareform

from bearingfw.oma.io import IdentifiedMode
from bearingfw.oma.spectrum import Spectrum, least_peak, peak_ratio
from bearingfw.oma.ssi import Poles, complex_mac, modal_phase_collinearity, real_shape
from bearingfw.parameters import ParameterError, parameter

__all__ = [
    "STATUS",
    "Candidate",
    "Criteria",
    "Stability",
    "accepted_modes",
    "candidates",
    "late_candidates",
    "least_orders",
    "select_modes",
    "stability",
]

#: Status of a pole in the diagram, from worst to best: not physical (damping or frequency out of
#: range), new (nothing to compare with at the previous order), unstable, stable in frequency,
#: in frequency and shape, in all three.
STATUS = ("unphysical", "new", "unstable", "frequency", "frequency+shape", "stable")


@attrs.frozen
class Criteria:
    """Stabilisation criteria and the automatic selection (module docstring); the first three are the paper's."""

    frequency: float = parameter(low=0.0, low_open=True, high=1.0, default=0.02, doc="relative frequency change")
    damping: float = parameter(low=0.0, low_open=True, high=10.0, default=0.02, doc="relative damping change")
    mac: float = parameter(low=0.0, high=1.0, default=0.90, doc="least MAC between orders")
    max_damping: float = parameter(low=0.0, low_open=True, high=1.0, default=0.20, doc="largest physical damping ratio")
    fmin: float = parameter(low=0.0, default=0.0, unit="Hz", doc="lowest frequency of interest")
    fmax: float | None = parameter(
        optional=True, low=0.0, low_open=True, unit="Hz", doc="highest frequency of interest"
    )
    min_fraction: float = parameter(
        low=0.0, low_open=True, high=1.0, default=0.4, doc="least share of the compared orders a mode is stable at"
    )
    cluster_distance: float | None = parameter(
        optional=True, low=0.0, low_open=True, high=2.0, doc="clustering cut (default frequency + 1 - mac)"
    )
    min_presence: float = parameter(
        low=0.0, high=1.0, default=0.8, doc="least share of the orders from a mode's first appearance it is present at"
    )
    min_mpc: float = parameter(low=0.0, high=1.0, default=0.8, doc="least modal phase collinearity of a mode's shapes")
    min_peak: float = parameter(
        low=0.0, default=1.5, doc="least prominence of the spectral peak at a mode, as a ratio (0: no peak check)"
    )

    def __attrs_post_init__(self):
        if self.fmax is not None and self.fmax <= self.fmin:
            raise ParameterError(f"Criteria: parameter 'fmax' = {self.fmax:g} Hz must exceed fmin = {self.fmin:g} Hz")

    @property
    def distance(self) -> float:
        return self.cluster_distance if self.cluster_distance is not None else self.frequency + 1.0 - self.mac


@attrs.frozen(eq=False)
class Stability:
    """Per pole: whether it is physical, its changes against the previous order, and its status (index into STATUS)."""

    physical: np.ndarray
    frequency_change: np.ndarray
    damping_change: np.ndarray
    mac: np.ndarray
    status: np.ndarray

    @property
    def stable(self) -> np.ndarray:
        return self.status == STATUS.index("stable")


def stability(poles: Poles, criteria: Criteria = Criteria()) -> Stability:
    """Compare every pole with the nearest (in frequency) physical pole of the previous order."""
    n = poles.size
    fmax = criteria.fmax if criteria.fmax is not None else 0.5 / poles.dt
    physical = (poles.damping > 0) & (poles.damping <= criteria.max_damping)
    physical &= (poles.frequency >= criteria.fmin) & (poles.frequency <= fmax)
    df, dd, mac = np.full(n, np.inf), np.full(n, np.inf), np.zeros(n)
    status = np.full(n, STATUS.index("new"))
    orders = poles.orders
    for previous, current in zip(orders[:-1], orders[1:]):
        now = np.flatnonzero((poles.order == current) & physical)
        before = np.flatnonzero((poles.order == previous) & physical)
        if now.size == 0 or before.size == 0:
            continue
        gap = (
            np.abs(poles.frequency[now][:, None] - poles.frequency[before][None, :]) / poles.frequency[before][None, :]
        )
        nearest = before[np.argmin(gap, axis=1)]
        df[now] = np.min(gap, axis=1)
        dd[now] = np.abs(poles.damping[now] - poles.damping[nearest]) / poles.damping[nearest]
        mac[now] = complex_mac(poles.shapes[now], poles.shapes[nearest], rowwise=True)
    ok_f, ok_d, ok_mac = df <= criteria.frequency, dd <= criteria.damping, mac >= criteria.mac
    status[np.isfinite(df)] = STATUS.index("unstable")
    status[ok_f] = STATUS.index("frequency")
    status[ok_f & ok_mac] = STATUS.index("frequency+shape")
    status[ok_f & ok_mac & ok_d] = STATUS.index("stable")
    status[~physical] = STATUS.index("unphysical")
    return Stability(physical, df, dd, mac, status)


@attrs.frozen(eq=False)
class Candidate:
    """A cluster of poles stable in frequency and shape, one per order, and how it fares in the selection.

    ``failed`` names the checks it fails (module docstring: ``count``, ``presence``, ``stable``,
    ``scatter``, ``mpc``, ``peak``) and ``reasons`` says why, one message each; none: it is a
    mode. ``presence``: the share of the orders from ``first_order`` to the largest at which it
    is present; ``scatter``: the standard deviation of its frequencies over their median;
    ``peak``: :func:`~bearingfw.oma.spectrum.peak_ratio` (NaN when not checked); ``shape``: the
    mean real shape of its poles (largest component +1).
    """

    members: np.ndarray
    frequency: float
    damping: float
    shape: np.ndarray
    first_order: int
    presence: float
    stable: bool
    scatter: float
    mpc: float
    peak: float
    failed: tuple[str, ...]
    reasons: tuple[str, ...]

    @property
    def accepted(self) -> bool:
        return not self.reasons

    @property
    def poles(self) -> int:
        return int(self.members.size)

    def to_dict(self) -> dict:
        return {
            "frequency": self.frequency,
            "damping": self.damping,
            "poles": self.poles,
            "first_order": self.first_order,
            "presence": self.presence,
            "mpc": self.mpc,
            "peak": None if math.isnan(self.peak) else self.peak,
            "failed": list(self.failed),
            "reasons": list(self.reasons),
        }


def _clusters(poles: Poles, members: np.ndarray, distance: float) -> list[np.ndarray]:
    if members.size == 0:
        return []
    if members.size == 1:
        return [members]
    f = poles.frequency[members]
    gap = np.abs(f[:, None] - f[None, :]) / np.maximum(f[:, None], f[None, :])
    d = gap + 1.0 - complex_mac(poles.shapes[members], poles.shapes[members])
    d = np.clip((d + d.T) / 2, 0.0, None)
    np.fill_diagonal(d, 0.0)
    labels = fcluster(linkage(squareform(d, checks=False), method="average"), t=distance, criterion="distance")
    return [members[labels == k] for k in np.unique(labels)]


def _one_per_order(poles: Poles, cluster: np.ndarray) -> np.ndarray:
    centre = np.median(poles.frequency[cluster])
    keep = []
    for order in np.unique(poles.order[cluster]):
        at = cluster[poles.order[cluster] == order]
        keep.append(at[np.argmin(np.abs(poles.frequency[at] - centre))])
    return np.array(keep, dtype=int)


def _mean_shape(shapes: np.ndarray) -> np.ndarray:
    real = real_shape(shapes)
    signs = np.sign(real @ real[0])
    mean = np.mean(real * np.where(signs == 0, 1.0, signs)[:, None], axis=0)
    return mean / mean[np.argmax(np.abs(mean))]


def least_orders(poles: Poles, criteria: Criteria) -> int:
    """The fewest orders a mode must be stable at (check 1): ``min_fraction`` of those compared, at least 3."""
    compared = max(len(poles.orders) - 1, 1)
    return max(3, math.ceil(criteria.min_fraction * compared))


def _candidate(
    poles: Poles, state: Stability, kept: np.ndarray, criteria: Criteria, spectrum: Spectrum | None, least: int
) -> Candidate:
    f, z = poles.frequency[kept], poles.damping[kept]
    frequency, damping = float(np.median(f)), float(np.median(z))
    first = int(poles.order[kept].min())
    presence = kept.size / int(np.count_nonzero(poles.orders >= first))
    scatter = float(np.std(f)) / frequency
    mpc = float(np.mean(modal_phase_collinearity(poles.shapes[kept])))
    stable = bool(np.any(state.stable[kept]))
    checked = spectrum is not None and criteria.min_peak > 0
    shape = _mean_shape(poles.shapes[kept])
    peak = peak_ratio(spectrum, frequency, damping, shape) if checked else math.nan
    least_peak_ratio = least_peak(spectrum, frequency, damping, criteria.min_peak) if checked else math.nan
    checks = {
        "count": (kept.size >= least, f"stable at {kept.size} orders, fewer than {least}"),
        "presence": (
            presence >= criteria.min_presence,
            f"present at {presence:.0%} of the orders from its first ({first}), below {criteria.min_presence:.0%}",
        ),
        "stable": (stable, "no pole stable in damping too"),
        "scatter": (
            scatter <= criteria.frequency / 2, f"frequency scatter {scatter:.2%} above {criteria.frequency / 2:.2%}"
        ),
        "mpc": (mpc >= criteria.min_mpc, f"MPC {mpc:.2f} below {criteria.min_mpc:g}"),
        "peak": (  # NaN (outside the spectrum) fails too
            not checked or peak >= least_peak_ratio,
            f"no spectral peak (ratio {peak:.2f} below {least_peak_ratio:.2f})",
        ),
    }
    failed = tuple(name for name, (ok, _) in checks.items() if not ok)
    return Candidate(
        members=kept,
        frequency=frequency,
        damping=damping,
        shape=shape,
        first_order=first,
        presence=presence,
        stable=stable,
        scatter=scatter,
        mpc=mpc,
        peak=peak,
        failed=failed,
        reasons=tuple(checks[name][1] for name in failed),
    )


def candidates(
    poles: Poles, state: Stability, criteria: Criteria = Criteria(), spectrum: Spectrum | None = None
) -> tuple[Candidate, ...]:
    """Every cluster of poles stable in frequency and shape, checked (module docstring), lowest frequency first.

    ``spectrum``: the singular spectrum of the analysed channels for the peak check (none: not checked).
    """
    least = least_orders(poles, criteria)
    members = np.flatnonzero(state.status >= STATUS.index("frequency+shape"))
    out = [
        _candidate(poles, state, _one_per_order(poles, cluster), criteria, spectrum, least)
        for cluster in _clusters(poles, members, criteria.distance)
    ]
    return tuple(sorted(out, key=lambda c: c.frequency))


#: The checks a candidate that appears too late may fail: too few orders, and with so few poles
#: possibly none stable in damping too.
LATE = {"count", "stable"}


def late_candidates(found: tuple[Candidate, ...]) -> tuple[Candidate, ...]:
    """Candidates that fail only for appearing too late: present at every order since a first order near the top.

    A physical mode that needs more states than the order gives appears at the last few orders,
    then stays: raise the order. (Its other checks pass; a noise cluster that appears late is
    seldom present at every order since, with a real shape and a spectral peak.)
    """
    return tuple(
        c for c in found if c.poles >= 2 and c.presence == 1.0 and "count" in c.failed and set(c.failed) <= LATE
    )


def accepted_modes(poles: Poles, found: tuple[Candidate, ...]) -> tuple[IdentifiedMode, ...]:
    """The accepted candidates as modes, in the order given, named ``mode 1``, ``mode 2``, ..."""
    modes = []
    for c in found:
        if not c.accepted:
            continue
        f, z = poles.frequency[c.members], poles.damping[c.members]
        modes.append(
            IdentifiedMode(
                c.frequency,
                c.damping,
                c.shape,
                frequency_std=float(np.std(f)),
                damping_std=float(np.std(z)),
                poles=c.poles,
                mpc=c.mpc,
                name=f"mode {len(modes) + 1}",
            )
        )
    return tuple(modes)


def select_modes(
    poles: Poles, state: Stability, criteria: Criteria = Criteria(), spectrum: Spectrum | None = None
) -> tuple[IdentifiedMode, ...]:
    """The modes among the stable poles (module docstring), lowest frequency first."""
    return accepted_modes(poles, candidates(poles, state, criteria, spectrum))
