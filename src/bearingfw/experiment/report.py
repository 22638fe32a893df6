"""``report.md``: an experiment's inputs, record measures, modal results, matrices, figures, run
statistics and failed cells, as Markdown with the figures linked relative to the results directory.

Pure text assembly from what the run produced (:class:`ReportData`); nothing is computed here.
"""

from __future__ import annotations

import datetime
import math
import platform
from collections.abc import Sequence
from pathlib import Path

import attrs

from bearingfw.experiment.findings import Finding
from bearingfw.experiment.matrices import Matrices
from bearingfw.experiment.metrics import display_scale, metric_family
from bearingfw.experiment.spec import Experiment

__all__ = ["ReportData", "render_report"]


@attrs.frozen(eq=False)
class ReportData:
    """Everything the report shows. ``cells``: ``(cell id, document or None)`` for every planned cell;
    ``intensities`` and ``rayleigh``: as resolved for the run; ``families``: the metric families."""

    experiment: Experiment
    out: Path
    summary: object  # bearingfw.experiment.runner.RunSummary
    matrices: Matrices
    table: tuple[str, ...]
    cells: tuple[tuple[str, dict | None], ...]
    records: dict
    modal: dict
    figures: tuple[Path, ...]
    findings: tuple[Finding, ...]
    intensities: tuple
    rayleigh: object  # bearingfw.analysis.Rayleigh
    elements: tuple[str, ...]
    families: dict


def _row(cells: Sequence) -> str:
    return "| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in cells) + " |"


def _table(header: Sequence, rows: Sequence[Sequence]) -> list[str]:
    return [_row(header), _row(["---"] * len(header)), *(_row(r) for r in rows)]


def _g(value, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value:.{digits}g}" if isinstance(value, float) else str(value)


def _figure_link(data: ReportData, path: Path, alt: str) -> str:
    return f"![{alt}]({Path(path).relative_to(data.out).as_posix()})"


def _pngs(data: ReportData, prefix: str) -> list[Path]:
    """The figures whose name starts with ``prefix``, one file each: the PNG, else the first format written."""
    shown: dict[str, Path] = {}
    for p in data.figures:
        if p.name.startswith(prefix) and (p.stem not in shown or p.suffix == ".png"):
            shown[p.stem] = Path(p)
    return list(shown.values())


def _summary(data: ReportData) -> list[str]:
    s = data.summary
    missing = sum(1 for _, d in data.cells if d is None)
    failed = sum(1 for _, d in data.cells if d is not None and d.get("status") not in ("ok", "suspect"))
    suspect = [(i, d) for i, d in data.cells if d is not None and d.get("status") == "suspect"]
    lines = []
    if suspect:  # first: a result that is not to be trusted must not be missed
        lines += ["## Suspect cells", "",
                  (f"**{len(suspect)} cell(s) ran but failed an acceptance check** (`[run]` tolerances); their "
                   "values are left out of the matrices and they are computed again on the next run:"), ""]
        lines += [f"- **{i}**: {(d.get('error') or {}).get('message', '')}" for i, d in suspect]
        lines += [""]
    lines += [
        "## Summary", "",
        (f"- cells: {s.cells} ({len(data.experiment.models)} models x {len(data.experiment.records)} record(s) x "
         f"{len(data.intensities)} intensities); {len(s.computed)} computed in this run, "
         f"{len(s.skipped)} kept from earlier runs"
         + (f" ({len(s.thinned)} of them with their histories thinned to the new `every`)" if s.thinned else "")
         + f", {failed} failed, {len(suspect)} suspect, {missing} not computed"),
        (f"- cells computed in {s.run_time:.1f} s of wall time on the {s.executor} executor ({s.workers} worker(s)); "
         f"whole run {s.wall_time:.1f} s"),
    ]
    if getattr(s, "damaged", ()):
        lines += [f"- {len(s.damaged)} stored cell(s) failed their integrity check (checksums) and were computed "
                  "again:"]
        lines += [f"  - {cell}: {problem}" for cell, problem in s.damaged]
    lines += _findings(data.findings)
    return lines


def _findings(findings: Sequence[Finding]) -> list[str]:
    """The declared findings, a table per group, in the order declared (``[[findings]]``)."""
    lines = []
    groups: dict[str, list[Finding]] = {}
    for f in findings:
        groups.setdefault(f.group, []).append(f)
    for group, members in groups.items():
        lines += ["", f"### {group}", ""]
        marks = {True: "yes", False: "**no**", None: "n/a"}
        if any(f.explanation for f in members):  # why a finding does not hold, from this run's numbers
            lines += _table(["finding", "this run", "holds", "why not (this run)"],
                            [(f.statement, f.measured, marks[f.holds], f.explanation) for f in members])
        else:
            lines += _table(["finding", "this run", "holds"],
                            [(f.statement, f.measured, marks[f.holds]) for f in members])
    return lines


def _inputs(data: ReportData) -> list[str]:
    e = data.experiment
    st = e.structure
    options = ", ".join(f"{k} = {v}" for k, v in st.options.items()) or "defaults"
    lines = ["## Inputs", "", "### Structure", "",
             f"- builder: `{st.builder}`; options: {options}",
             f"- response elements: {', '.join(data.elements) or 'none'}"]
    lines += ["", "### Bearing models", ""]
    rows = []
    for m in e.models:
        laws = _laws_of(data, m.name)
        rows.append((m.name + (" (reference)" if m.name == data.matrices.reference else ""), m.describe(), laws))
    lines += _table(["model", "definition", "sliding bearings (law: bearings)"], rows)
    lines += ["", "### Records", ""]
    rows = []
    for name, r in data.records.items():
        axes = ", ".join(f"{axis} = {role}" for axis, role in r["axes"].items())
        # t_Ha and the degree are undefined (NaN/None) for a record with no horizontal motion.
        t_ha = "undefined" if r["t_ha"] is None or not math.isfinite(r["t_ha"]) else f"{r['t_ha']:.2f}"
        rows.append((name, r["source"], _g(r["dt"]), f"{r['duration']:.2f}", _g(r["pga_h10"]), t_ha,
                     _g(r["arias"]), r["degree"] or "undefined (no horizontal motion)", axes))
    lines += _table(["record", "source", "dt [s]", "duration [s]", "PGA_H10 [m/s²]", "t_Ha [s]", "Arias [m/s]",
                     "degree", "applied as"], rows)
    for name, r in data.records.items():
        for note in r["notes"]:
            lines.append(f"\n- {name}: {note}")
        if r["synthetic"]:
            lines.append(f"\n- {name} is SYNTHETIC: generated by bearingfw (a mining tremor in kind), not a recording.")
    lines += ["", "### Intensities", ""]
    levels = all(i.pga_h10 is not None for i in data.intensities)
    header = ["intensity", "PGA_H10 [m/s²]" if levels else "target"]
    header += [f"{name}: scale factor, degree" for name in data.records]
    rows = []
    for i in data.intensities:
        row = [i.name, _g(i.pga_h10) if levels else i.target.describe()]
        for r in data.records.values():
            m = r["intensities"].get(i.name, {})
            row.append(f"error: {m['error']}" if "error" in m else f"{m['scale_factor']:.4g}, {m['degree'] or 'undefined'}")
        rows.append(row)
    lines += _table(header, rows)
    rayleigh = data.rayleigh
    ratios = e.damping.ratios
    if ratios:
        source = f" (from {ratios[0][1]:.1%} at {ratios[0][0]:g} Hz and {ratios[1][1]:.1%} at {ratios[1][0]:g} Hz)"
    elif e.damping.alpha is None:
        source = f" ({e.damping.modal_ratio:.1%} at the structure's first two natural frequencies, as built)"
    else:
        source = ""
    integration = ", ".join(f"{k} = {v}" for k, v in attrs.asdict(e.integration).items())
    lines += ["", "### Analysis", "",
              f"- integration (HHT-alpha, Newton on the bearing laws): {integration}",
              f"- Rayleigh damping: alpha = {rayleigh.alpha:.4g} 1/s, beta = {rayleigh.beta:.4g} s{source}",
              ("- the same ground acceleration at every support" if not any(r.spatial for r in e.records) else
               "- the ground acceleration at every support, or per support group where a record says so (Support "
               "motion below)") + "; dead load first (bearings set after it), then the ground motion"]
    chart = _pngs(data, "intensity-chart")
    if chart:
        lines += ["", _figure_link(data, chart[0], "intensity chart")]
    return lines


def _laws_of(data: ReportData, model: str) -> str:
    """``law (parameters): bearings`` per law; a parameter that differs between bearings as its range."""
    for _, d in data.cells:
        if d is None or d.get("model") != model or not d.get("laws"):
            continue
        groups: dict[str, list[tuple[str, dict]]] = {}
        for bearing, law in d["laws"].items():
            if law["law"] is not None:
                groups.setdefault(law["law"], []).append((bearing, law["params"]))
        parts = []
        for law, members in groups.items():
            shown = []
            for key in members[0][1]:
                values = [params.get(key) for _, params in members]
                if all(v == values[0] for v in values):
                    shown.append(f"{key} = {_g(values[0])}")
                else:
                    shown.append(f"{key} = {_g(min(values))} .. {_g(max(values))} (per bearing)")
            parts.append(f"{law}" + (f" ({', '.join(shown)})" if shown else "") + ": "
                         + ", ".join(b for b, _ in members))
        return "; ".join(parts) or "all fixed (JOIN)"
    return "-"


def _modal(data: ReportData) -> list[str]:
    lines = ["## Modal results", "",
             ("The lowest modes of each model, every bearing law at its initial tangent (frictionless sliding "
              "free, springs and friction at their stick stiffness)."), ""]
    models = [m for m in data.modal if "modes" in data.modal[m]]
    if models:
        count = max(len(data.modal[m]["modes"]) for m in models)
        rows = []
        for k in range(count):
            row = [k + 1]
            for m in models:
                modes = data.modal[m]["modes"]
                row.append(f"{modes[k]['frequency']:.3f} ({modes[k]['label']})" if k < len(modes) else "")
            rows.append(row)
        lines += _table(["mode", *(f"{m}: f [Hz] (label)" for m in models)], rows)
    for m, entry in data.modal.items():
        if "error" in entry:
            lines.append(f"\n- {m}: modal analysis failed: {entry['error']}")
    return lines


def _matrices(data: ReportData) -> list[str]:
    mx = data.matrices
    lines = ["## Comparison matrices", "",
             (f"Peak responses per model and intensity; in parentheses the ratio to {mx.reference}. All metrics are "
              "in `matrices.json` and `ratios.json` (`{metric: {model: {intensity: value}}}`, SI units), one CSV per "
              "metric in `matrices/` and `ratios/`, and every cell's values with the time and place of each peak in "
              "`cells.csv`.")]
    records = len(data.experiment.records)
    if records > 1:
        how = data.experiment.output.aggregate
        rule = {"max": "the largest of the records' values", "mean": "the mean of the records' values",
                "ec8": ("the mean of the records' values" if records >= 7 else "the most unfavourable (largest) of the "
                        "records' values") + " (EN 1998-1 4.3.3.4.3: the mean of at least seven records, else the "
                        "most unfavourable)"}[how]
        lines += ["", (f"Each entry combines the {records} records (`aggregate = \"{how}\"`): {rule}; an entry is "
                       "empty when a record's cell is missing or failed.")]
    for metric in data.table:
        if metric not in mx.values:
            continue
        factor, unit = mx.display(metric)
        family = data.families.get(metric_family(metric))
        lines += ["", f"### `{metric}` [{unit}]", ""]
        lines += [f"{family.description}.", ""] if family is not None else []
        rows = []
        for model in mx.models:
            row = [model]
            for i in mx.intensities:
                v, r = mx.value(metric, model, i), mx.ratio(metric, model, i)
                ratio = f" ({r:.2f})" if math.isfinite(r) else ""
                row.append("-" if not math.isfinite(v) else f"{v * factor:.4g}{ratio}")
            rows.append(row)
        lines += _table(["model", *mx.intensities], rows)
        heat = _pngs(data, f"heatmap_{metric}.")
        if heat:
            lines += ["", _figure_link(data, heat[0], f"heatmap {metric}")]
    lines += ["", "### All metrics", ""]
    present = list(dict.fromkeys(metric_family(m) for m in mx.metrics))
    for name in present:
        family = data.families.get(name)
        items = [m.partition(".")[2] for m in mx.metrics if metric_family(m) == name]
        unit = mx.unit(f"{name}.{items[0]}")
        what = f", {family.description}" if family is not None else ""
        lines.append(f"- `{name}` ({unit or '?'}{what}): {', '.join(items)}")
    notes = [data.families[f] for f in present if f in data.families and data.families[f].note]
    if notes:
        lines += ["", "Definitions:", ""]
        lines += [f"- `{family.name}`: {family.note}." for family in notes]
    return lines


def _support_motion(data: ReportData) -> list[str]:
    """Cells whose ground motion varies between supports: how (each record's description), the peak differential
    ground displacements between support groups, the bearings' quasi-static share, and the table's metrics per
    record (the matrices combine the records)."""
    cells = [(i, d) for i, d in data.cells if d is not None and (d.get("record_measures") or {}).get("spatial")]
    if not cells:
        return []
    lines = ["## Support motion", ""]
    described = {d["record"]: d["record_measures"]["spatial"] for _, d in cells}
    lines += [f"- {record}: {text}" for record, text in described.items()]
    factor, unit = display_scale("m")
    lines += ["", ("Peak differential ground displacement between two support groups (the pair in parentheses) and the "
                   "largest quasi-static share over the bearings (peak deformation the quasi-static support motion "
                   "imposes over peak bearing displacement):"), ""]
    rows = []
    for cell_id, d in cells:
        metrics = d.get("metrics") or {}
        row = [cell_id]
        for direction in ("x", "y", "z"):
            m = metrics.get(f"differential_displacement.{direction}") or {}
            value = m.get("value")
            row.append("-" if value is None else f"{value * factor:.4g}" + (f" ({m['at']})" if m.get("at") else ""))
        shares = [(k.partition(".")[2], m.get("value")) for k, m in metrics.items()
                  if k.startswith("quasi_static_share.") and m.get("value") is not None]
        best = max(shares, key=lambda kv: kv[1], default=None)
        row.append("-" if best is None else f"{best[1]:.3g} ({best[0]})")
        rows.append(row)
    lines += _table(["cell", f"x [{unit}]", f"y [{unit}]", f"z [{unit}]", "quasi-static share (bearing)"], rows)
    records = data.experiment.record_names
    if len(records) > 1:
        lines += ["", "The table's metrics per record (uniform and varying support motion side by side):"]
        documents = {(d["model"], d["record"], d["intensity"]): d for _, d in data.cells if d is not None}
        intensities = [i.name for i in data.intensities]
        for metric in data.table:
            scale, shown = display_scale(data.matrices.unit(metric))
            lines += ["", f"`{metric}` [{shown}]", ""]
            rows = []
            for model in data.matrices.models:
                row = [model]
                for record in records:
                    for intensity in intensities:
                        d = documents.get((model, record, intensity))
                        value = ((d or {}).get("metrics") or {}).get(metric, {}).get("value")
                        row.append("-" if value is None else f"{value * scale:.4g}")
                rows.append(row)
            lines += _table(["model", *(f"{r} {i}" for r in records for i in intensities)], rows)
    return lines


def _figures(data: ReportData) -> list[str]:
    lines = ["## Figures", ""]
    pngs = {p.stem: p for p in _pngs(data, "")}
    for record in data.records:
        for intensity in (i.name for i in data.intensities):
            tag = f"_{record}_{intensity.replace('=', '')}"
            main = [p for stem, p in pngs.items() if stem.endswith(tag) and not stem.startswith("hysteresis_")]
            loops = [(m, pngs[f"hysteresis_{m}{tag}"]) for m in data.experiment.model_names
                     if f"hysteresis_{m}{tag}" in pngs]
            if not main and not loops:
                continue
            lines += [f"### {record}, {intensity}", ""]
            for p in main:
                lines += [_figure_link(data, p, p.stem), ""]
            if loops:
                lines += ["Bearing hysteresis loops: " + ", ".join(
                    f"[{m}]({p.relative_to(data.out).as_posix()})" for m, p in loops), ""]
    return lines


def _statistics(data: ReportData) -> list[str]:
    rows = []
    for cell_id, d in data.cells:
        if d is None:
            rows.append((cell_id, "not computed", "", "", "", "", "", ""))
            continue
        st = d.get("stats") or {}
        rows.append((cell_id, d["status"], f"{d['wall_time']:.2f}", st.get("steps", ""), st.get("substeps", ""),
                     st.get("iterations", ""), st.get("subdivisions", ""), _g(st.get("energy_error"), 3)))
    noted = [(cell_id, d["warnings"]) for cell_id, d in data.cells if d is not None and d.get("warnings")]
    notes = ["", "Warnings raised while computing cells (each once, with how often):", ""] if noted else []
    notes += [f"- {cell_id}: {note}" for cell_id, found in noted for note in found]
    return ["## Run statistics", "",
            ("Per cell (the last time it was computed): wall time, integration steps and sub-steps, Newton "
             "iterations, step halvings, and the energy balance error max abs(imbalance) / max abs(input work)."), "",
            *_table(["cell", "status", "wall time [s]", "steps", "sub-steps", "iterations", "halvings", "energy error"],
                    rows), *notes]


def _failures(data: ReportData) -> list[str]:
    failed = [(i, d) for i, d in data.cells if d is not None and d.get("status") not in ("ok", "suspect")]
    if not failed:
        return ["## Failed cells", "", "None."]
    lines = ["## Failed cells", "", "Each failed cell is tried again on the next run.", ""]
    for cell_id, d in failed:
        error = d.get("error") or {}
        lines += [f"### {cell_id}", "", f"**{error.get('type', 'error')}**: {error.get('message', '')}", "",
                  "<details><summary>traceback</summary>", "", "```", (error.get("traceback") or "").rstrip(), "```",
                  "", "</details>", ""]
    return lines


def render_report(data: ReportData) -> str:
    """The Markdown text of the report."""
    from bearingfw import __version__

    e = data.experiment
    when = datetime.datetime.now().isoformat(sep=" ", timespec="seconds")
    lines = [f"# {e.name}: bearingfw experiment report", ""]
    if e.description:
        lines += [e.description.strip(), ""]
    lines += [f"Generated {when} by bearingfw {__version__} on {platform.node() or 'this machine'}.", ""]
    for part in (_summary, _inputs, _modal, _matrices, _support_motion, _figures, _statistics, _failures):
        lines += part(data) + [""]
    return "\n".join(lines)
