"""Uplift metrics: how often, how long and how far the compression-only bearings lift off.

A connector with ``uplift=True`` (:mod:`bearingfw.model.connectors`) cannot pull: when the
vertical motion would stretch it, its gap opens, its normal force is zero and it carries no
friction. The connector recorder then keeps its gap (m, every integration step; NaN for
connectors that cannot lift) and these families reduce it per bearing:

=================  =====  =======================================================================
family             unit   value
=================  =====  =======================================================================
lift_offs.<b>      -      how many times the gap opened (closed -> open transitions)
uplift_time.<b>    s      total time the gap was open (sum of the steps that end open)
uplift_gap.<b>     m      largest gap opening (0 if it never lifted)
=================  =====  =======================================================================

All three are NaN for a bearing that cannot lift (its vertical spring pulls as well as pushes),
so a matrix of a model without compression-only bearings says "does not apply", not "never
lifted". While a bearing is lifted its friction ratio is NaN (N = 0; see
:mod:`bearingfw.experiment.metrics`).
"""

from __future__ import annotations

import math

import numpy as np

from bearingfw.experiment.metrics import BEARINGS, CellResponse, MetricFamily, Peak

__all__ = ["UPLIFT_FAMILIES"]


def _gaps(response: CellResponse) -> np.ndarray | None:
    """The recorded gaps (t, connectors), or None when no connector of the model can lift."""
    try:
        return np.asarray(response[f"{BEARINGS}.gap"], dtype=float)
    except KeyError:
        return None


def _per_bearing(measure) -> callable:
    """A reduction applying ``measure(gap history (t,), time (t,)) -> Peak`` to each liftable bearing."""

    def reduce(response: CellResponse) -> dict[str, Peak]:
        gaps = _gaps(response)
        time = response.time(BEARINGS)
        out = {}
        for c, connector in enumerate(response.model.connectors):
            if gaps is None or np.all(np.isnan(gaps[:, c])):
                out[connector.name] = Peak(math.nan)
            else:
                out[connector.name] = measure(gaps[:, c], time)
        return out

    return reduce


def _lift_offs(gap: np.ndarray, time: np.ndarray) -> Peak:
    lifted = gap > 0.0
    starts = np.flatnonzero(lifted[1:] & ~lifted[:-1]) + 1
    count = int(starts.size + (1 if lifted[0] else 0))
    first = None if count == 0 else float(time[0] if lifted[0] else time[starts[0]])
    return Peak(float(count), first, None)


def _uplift_time(gap: np.ndarray, time: np.ndarray) -> Peak:
    lifted = gap[1:] > 0.0
    return Peak(float(np.sum(np.diff(time)[lifted])), None, None)


def _uplift_gap(gap: np.ndarray, time: np.ndarray) -> Peak:
    k = int(np.nanargmax(gap))
    return Peak(float(max(gap[k], 0.0)), float(time[k]) if gap[k] > 0 else None, None)


UPLIFT_FAMILIES = (
    MetricFamily(
        "lift_offs", "-", "number of lift-offs of a compression-only bearing", BEARINGS, _per_bearing(_lift_offs),
        note="closed -> open transitions of the bearing's vertical gap; NaN for a bearing that cannot lift",
        table=False,
    ),
    MetricFamily(
        "uplift_time", "s", "total time a compression-only bearing was lifted off", BEARINGS,
        _per_bearing(_uplift_time),
        note="the sum of the integration steps that end with the gap open; NaN for a bearing that cannot lift",
        table=False,
    ),
    MetricFamily(
        "uplift_gap", "m", "largest lift-off gap of a compression-only bearing", BEARINGS, _per_bearing(_uplift_gap),
        note="the largest vertical opening (0 if it never lifted); NaN for a bearing that cannot lift", table=False,
    ),
)
