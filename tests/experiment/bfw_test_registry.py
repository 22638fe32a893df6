"""A test-only plugin module adding a metric family and an executor, each one definition and a
registration, loaded by experiments through ``plugins = ["bfw_test_registry"]``.

- metric family ``normal_force_drop``: the largest fall of each connector's normal force below its
  dead-load value (N): ``max_t (N(0) - N(t))``;
- executor ``reversed``: the cells one after the other in this process, last planned first; it
  records the order it ran them in ``RUNS`` (module attribute) so that a test sees it was used.
"""

from __future__ import annotations

from bearingfw.experiment import MetricFamily, Peak
from bearingfw.experiment.execute import compute_and_store
from bearingfw.plugins.hookspecs import hookimpl

RUNS: list[list[str]] = []


def _normal_force_drop(response) -> dict:
    normal = response["bearings.normal_force"]  # (t, connectors), the dead-load state first
    time = response.time("bearings")
    drop = normal[:1] - normal
    out = {}
    for c, connector in enumerate(response.model.connectors):
        k = int(drop[:, c].argmax())
        out[connector.name] = Peak(float(drop[k, c]), float(time[k]), None)
    return out


NORMAL_FORCE_DROP = MetricFamily(
    "normal_force_drop", "N", "largest fall of the normal force below its dead-load value", "bearings",
    _normal_force_drop, note="N(0) - N(t), the most the vertical motion unloads the bearing", table=False,
)


class ReversedExecutor:
    name = "reversed"
    description = "the cells one after the other here, last first (a test executor)"

    def __init__(self, workers=None):
        self.workers = 1

    def run(self, jobs, store, done):
        RUNS.append([job.id for job in reversed(jobs)])
        for job in reversed(jobs):
            done(compute_and_store(job, str(store.root)))


@hookimpl
def bearingfw_register_metrics():
    return [NORMAL_FORCE_DROP]


@hookimpl
def bearingfw_register_executors():
    return [ReversedExecutor]
