"""Comparison matrices: for each metric, models x intensities, values and ratios to a reference model.

With several records, a matrix entry combines the records' values (``[output] aggregate``):
``max``, ``mean``, or ``ec8`` (EN 1998-1 4.3.3.4.3: the mean of at least seven records, the most
unfavourable of fewer). An entry is NaN (null in JSON, empty in CSV) where the metric does not
apply (a fixed bearing's friction ratio) or a record's cell is missing or failed. Every
record's own values are in ``cells.csv``.

Files: ``matrices.json`` and ``ratios.json`` (``{metric: {model: {intensity: value}}}``, SI
units, named per metric in ``units.json`` beside them, :func:`units_table`),
``matrices/<metric>.csv`` and ``ratios/<metric>.csv`` (a row per model, a column per intensity;
the header names the unit: ``D_II [Pa]``, ``D_II [-]``), ``cells.csv`` (one row per cell and
metric, with its unit and the time and place of the peak).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence

import attrs
import numpy as np

from bearingfw.experiment.metrics import MetricFamily, display_scale, metric_families, metric_family
from bearingfw.experiment.store import Store

__all__ = ["Matrices", "collect_matrices", "format_tables", "units_table", "write_matrices"]


@attrs.frozen(eq=False)
class Matrices:
    """``values[metric][model][intensity]`` (SI, NaN where missing), the reference model, and the SI
    unit of each metric (``units``; "" where unknown)."""

    metrics: tuple[str, ...]
    models: tuple[str, ...]
    intensities: tuple[str, ...]
    reference: str
    values: dict
    units: dict = attrs.field(factory=dict)

    def unit(self, metric: str) -> str:
        return self.units.get(metric, "")

    def display(self, metric: str) -> tuple[float, str]:
        """(factor, label) of the unit the metric is shown in (MPa, kN, mm, ...)."""
        return display_scale(self.unit(metric))

    def value(self, metric: str, model: str, intensity: str) -> float:
        try:
            return self.values[metric][model][intensity]
        except KeyError:
            return math.nan

    def ratio(self, metric: str, model: str, intensity: str) -> float:
        """``value / value of the reference model`` at the same intensity (NaN if undefined)."""
        ref = self.value(metric, self.reference, intensity)
        value = self.value(metric, model, intensity)
        if not (math.isfinite(ref) and math.isfinite(value)) or ref == 0.0:
            return math.nan
        return value / ref

    def ratios(self) -> dict:
        return {m: {model: {i: self.ratio(m, model, i) for i in self.intensities} for model in self.models}
                for m in self.metrics}

    def as_dict(self) -> dict:
        """``{metric: {model: {intensity: value}}}``."""
        return {m: {model: dict(self.values[m][model]) for model in self.models} for m in self.metrics}


def _combine(values: list[float], expected: int, aggregate: str) -> float:
    if len(values) < expected or any(math.isnan(v) for v in values):
        return math.nan
    if aggregate == "mean" or (aggregate == "ec8" and expected >= 7):
        return float(np.mean(values))
    return float(np.max(values))


def _metric_names(documents: Iterable[dict], families: Mapping[str, MetricFamily]) -> tuple[str, ...]:
    seen: dict[str, None] = {}
    for d in documents:
        for name in d.get("metrics", {}):
            seen.setdefault(name, None)
    order = {family: i for i, family in enumerate(families)}
    return tuple(sorted(seen, key=lambda m: order.get(metric_family(m), len(order))))  # stable within a family


def collect_matrices(
    documents: Sequence[dict], models: Sequence[str], records: Sequence[str], intensities: Sequence[str],
    reference: str, aggregate: str = "ec8", families: Mapping[str, MetricFamily] | None = None,
) -> Matrices:
    """The matrices of the finished cells ``documents`` (their JSON documents; failed ones are skipped).

    ``families``: the metric families (default: the registered ones), which order the metrics and
    give their units where a document does not state them."""
    families = metric_families() if families is None else families
    ok = [d for d in documents if d.get("status") == "ok"]
    metrics = _metric_names(ok, families)
    found: dict = {}
    units: dict[str, str] = {}
    for d in ok:
        for name, entry in d["metrics"].items():
            value = entry["value"]
            found.setdefault((name, d["model"], d["intensity"]), []).append(math.nan if value is None else value)
            if entry.get("unit") is not None:
                units.setdefault(name, entry["unit"])
    for m in metrics:
        family = families.get(metric_family(m))
        units.setdefault(m, family.unit if family is not None else "")
    values = {
        m: {model: {i: _combine(found.get((m, model, i), []), len(records), aggregate) for i in intensities}
            for model in models}
        for m in metrics
    }
    return Matrices(tuple(metrics), tuple(models), tuple(intensities), reference, values,
                    {m: units[m] for m in metrics})


def _csv_value(value: float) -> str:
    return repr(value) if math.isfinite(value) else ""


def _with_unit(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


def write_matrices(store: Store, matrices: Matrices, documents: Sequence[dict]) -> list:
    """Write the files of the module docstring; return their paths."""
    paths = [store.write_json("matrices.json", matrices.as_dict()), store.write_json("ratios.json", matrices.ratios())]
    ratios = matrices.ratios()
    for m in matrices.metrics:
        for folder, table, unit in (("matrices", matrices.values[m], matrices.unit(m)), ("ratios", ratios[m], "-")):
            header = ["model", *(_with_unit(i, unit) for i in matrices.intensities)]
            rows = [[model, *(_csv_value(table[model][i]) for i in matrices.intensities)] for model in matrices.models]
            paths.append(store.write_csv(f"{folder}/{m}.csv", header, rows))
    rows = []
    for d in documents:
        measures = d.get("record_measures") or {}
        for name, entry in (d.get("metrics") or {}).items():
            value = math.nan if entry["value"] is None else entry["value"]
            rows.append([
                d["model"], d["record"], d["intensity"], _csv_value(measures.get("pga_h10", math.nan)),
                _csv_value(measures.get("scale_factor", math.nan)), name, _csv_value(value),
                entry.get("unit") or matrices.unit(name), "" if entry["time"] is None else repr(entry["time"]),
                entry["at"] or "",
            ])
    paths.append(store.write_csv(
        "cells.csv", ["model", "record", "intensity", "pga_h10 [m/s^2]", "scale_factor [-]", "metric", "value",
                      "unit", "time [s]", "at"], rows
    ))
    return paths


def units_table(matrices: Matrices) -> dict:
    """``units.json``: the unit of every number in the results files that carry none in their keys."""
    return {
        "matrices.json": {m: matrices.unit(m) for m in matrices.metrics},
        "ratios.json": "-",
        "cells/<model>/<record>/<intensity>.json": {"metrics.*.value": "unit given with each metric",
                                                    "metrics.*.time": "s", "wall_time": "s"},
        "records.json": {"dt": "s", "duration": "s", "pga_h10": "m/s^2", "t_ha": "s", "arias": "m/s",
                         "scale_factor": "-", "components.pga": "m/s^2", "components.dominant_frequency": "Hz",
                         "intensities.*.pga_h10": "m/s^2", "intensities.*.t_ha": "s", "intensities.*.arias": "m/s"},
        "modal.json": {"modes.frequency": "Hz", "modes.mass_ratio": "-"},
        "summary.json": {"wall_time": "s", "run_time": "s"},
    }


def _cell(value: float, ratio: float, factor: float) -> str:
    if not math.isfinite(value):
        return "-"
    text = f"{value * factor:.4g}"
    return f"{text} ({ratio:.2f})" if math.isfinite(ratio) else text


def format_tables(matrices: Matrices, metrics: Sequence[str]) -> str:
    """Plain-text tables of ``metrics``: values in display units, ratio to the reference in parentheses."""
    blocks = []
    for m in metrics:
        if m not in matrices.values:
            continue
        factor, unit = matrices.display(m)
        header = ["model", *matrices.intensities]
        rows = [[model, *(_cell(matrices.value(m, model, i), matrices.ratio(m, model, i), factor)
                          for i in matrices.intensities)] for model in matrices.models]
        widths = [max(len(r[k]) for r in [header, *rows]) for k in range(len(header))]
        lines = [f"{m} [{unit}]  (ratio to {matrices.reference})"]
        for row in [header, *rows]:
            lines.append("  " + "  ".join(c.ljust(w) if k == 0 else c.rjust(w) for k, (c, w) in
                                          enumerate(zip(row, widths))))
        blocks.append("\n".join(lines))
    return "\n\n".join(blocks)
