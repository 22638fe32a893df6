"""Acceptance: the checks a computed cell passes before it is ``ok``.

A time-history analysis can finish and still be wrong: a step too coarse for the motion, a law
that misbehaves. Each computed cell is checked (tolerances from ``[run]``,
:class:`~bearingfw.experiment.spec.RunSpec`):

- ``energy``: the energy balance error, ``max |imbalance - numerical| / max |input work|`` (the
  transient result's ``balance_error``: work that no term of the balance accounts for) is at
  most ``energy_tolerance`` (default 1 %); and HHT's numerical dissipation (``numerical_dissipation``:
  the energy the scheme itself removed by the end, over ``max |input work|``; it grows with the
  step, and a step too coarse for the motion shows there: 65 % at a 0.5 s step) is at most
  ``dissipation_tolerance`` (default 5 %; a little is the point of HHT's ``alpha < 0``);
- ``finite``: every kept history is finite (NaN is by design in the friction ratio, where a
  bearing is unloaded, and in the slip of a law without one: :data:`NAN_BY_DESIGN`; elsewhere
  NaN is a fault) and no metric is infinite (NaN marks a metric that does not apply);
- ``peak``: resampling to the integration step kept at least ``min_peak_ratio`` of each record
  component's peak (a smaller ratio is refused before the analysis: the cell fails; the ratio
  is recorded here);
- ``compression``: connectors with uplift (compression-only vertical springs) never carry
  tension: ``N >= 0`` in the recorded normal force (to round-off).

A cell failing a check is stored with status ``suspect`` and the reasons (``acceptance`` in its
document): it is left out of the matrices, listed at the top of the report, counted in the
summary, and the run exits with status 1. It is computed again on the next run, like a failed cell.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from bearingfw.experiment.spec import RunSpec

__all__ = ["SUSPECT", "accept_cell", "acceptance_tolerances"]

#: The status of a cell that ran but failed an acceptance check.
SUSPECT = "suspect"
#: Histories where NaN is by design: the friction ratio of an unloaded bearing, the slip of a law
#: without slip (or outside its directions). Infinities are faults everywhere.
NAN_BY_DESIGN = frozenset({"bearings.friction_ratio", "bearings.slip"})
#: Tension below ``-TENSION_ROUNDOFF * max |N|`` in an uplift connector counts as tension.
TENSION_ROUNDOFF = 1e-9


def _finite_problems(histories: Mapping[str, np.ndarray], metrics: Mapping[str, dict]) -> list[str]:
    problems = []
    for key, values in histories.items():
        values = np.asarray(values, dtype=float)
        bad = np.isinf(values) if key in NAN_BY_DESIGN else ~np.isfinite(values)
        if bad.any():
            problems.append(f"history {key} has {int(bad.sum())} non-finite value(s)")
    for key, entry in metrics.items():
        value = entry.get("value") if isinstance(entry, Mapping) else entry
        if isinstance(value, float | np.floating) and math.isinf(value):
            problems.append(f"metric {key} is {value}")
    return problems


def _tension(histories: Mapping[str, np.ndarray], model) -> tuple[float | None, list[str]]:
    """The least normal force of the uplift connectors (None if none or not recorded), and problems."""
    normal = histories.get("bearings.normal_force")
    uplift = [k for k, c in enumerate(model.connectors) if getattr(c, "uplift", False)]
    if normal is None or not uplift:
        return None, []
    normal = np.asarray(normal, dtype=float)[:, uplift]
    least = float(np.nanmin(normal)) if normal.size else 0.0
    scale = float(np.nanmax(np.abs(normal))) if normal.size else 0.0
    if least >= -TENSION_ROUNDOFF * scale:
        return least, []
    k = int(np.nanargmin(normal.min(axis=0)))
    name = model.connectors[uplift[k]].name
    return least, [f"compression-only bearing {name} carries tension: N = {least:.4g} N < 0"]


def acceptance_tolerances(settings: RunSpec) -> dict:
    """The ``[run]`` settings that decide a cell's status (inputs of every cell)."""
    return {"energy_tolerance": settings.energy_tolerance, "dissipation_tolerance": settings.dissipation_tolerance,
            "min_peak_ratio": settings.min_peak_ratio}


def _number(value) -> float:
    return float(value) if isinstance(value, int | float | np.floating) and not isinstance(value, bool) else float("nan")


def accept_cell(stats: Mapping, histories: Mapping[str, np.ndarray], metrics: Mapping[str, dict], model,
                peak_ratio: float, settings: RunSpec) -> dict:
    """The acceptance of a computed cell (module docstring): ``{"passed", "problems", "measured",
    "tolerances"}``; ``histories``: every kept history (before thinning), ``peak_ratio``: the
    smallest kept fraction of a record component's peak."""
    problems = []
    error, dissipation = _number(stats.get("balance_error")), _number(stats.get("numerical_dissipation"))
    if math.isnan(error) and math.isnan(dissipation):  # a balance without the numerical column: all of it
        error, dissipation = _number(stats.get("energy_error")), 0.0
    if not error <= settings.energy_tolerance:  # NaN fails too
        problems.append(f"energy balance error {error:.3g} exceeds the tolerance {settings.energy_tolerance:g} "
                        "([run] energy_tolerance): work that no term of the balance accounts for")
    if not abs(dissipation) <= settings.dissipation_tolerance:
        problems.append(f"numerical dissipation {dissipation:.3g} of the input work exceeds the tolerance "
                        f"{settings.dissipation_tolerance:g} ([run] dissipation_tolerance): the integration step "
                        "is too coarse for the motion; a smaller dt_integration cures it")
    problems += _finite_problems(histories, metrics)
    if not peak_ratio >= settings.min_peak_ratio:
        problems.append(f"resampling kept {peak_ratio:.3g} of the record's peak, less than "
                        f"{settings.min_peak_ratio:g} ([run] min_peak_ratio)")
    least, tension = _tension(histories, model)
    problems += tension
    return {
        "passed": not problems,
        "problems": problems,
        "measured": {"balance_error": error, "numerical_dissipation": dissipation, "peak_ratio": peak_ratio,
                     "least_uplift_normal_force": least},
        "tolerances": acceptance_tolerances(settings),
    }
