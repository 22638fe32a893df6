"""``bearingfw plugins``: what is loaded, where it came from, and what failed to load."""

from __future__ import annotations

import json

from bearingfw.plugins import describe_parameters, get_registry
from bearingfw.protocol import OPTIONAL_FLAGS, law_flag

#: How the table names the protocol flags (the JSON uses the attribute names).
FLAG_LABELS = {
    "uses_velocity": "velocity",
    "normal_coupling": "normal coupling",
    "per_bearing": "per-bearing",
    "friction": "friction",
    "rate_dependent": "rate-dependent",
    "linear": "linear",
}


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "plugins",
        help="list the loaded plugins and what they register",
        description="List every registered bearing law (with its parameters, their ranges and units, and "
        "the protocol flags it declares), bearing preset, record reader, intensity scale, metric family "
        "and executor, the plugin and the distribution it came from, and every plugin that failed to "
        "load with its error.",
    )
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of tables")
    parser.set_defaults(func=run)


def _describe(entries: dict, details) -> list[dict]:
    """One JSON object per registry entry: its name and origin, then ``details(value)``."""
    return [
        {
            "name": entry.key,
            "plugin": entry.origin.plugin,
            "distribution": entry.origin.distribution,
            "version": entry.origin.version,
            **details(entry.value),
        }
        for entry in sorted(entries.values(), key=lambda e: e.key)
    ]


def _law_details(cls) -> dict:
    return {
        "class": f"{cls.__module__}.{cls.__qualname__}",
        "flags": {flag: law_flag(cls, flag) for flag in OPTIONAL_FLAGS},
        # offers compiled(n): the time step's Newton iteration can run compiled with it (bearingfw.protocol)
        "compiled": callable(getattr(cls, "compiled", None)),
        "parameters": describe_parameters(cls),
    }


def _description(item) -> dict:
    description = getattr(item, "description", "")
    return {"description": description if isinstance(description, str) else ""}


def listing() -> dict:
    """The registry as plain data (the ``--json`` output)."""
    registry = get_registry()
    return {
        "laws": _describe(registry.laws, _law_details),
        "presets": _describe(
            registry.presets,
            lambda preset: {"description": preset.description, "needs_dead_load": preset.needs_dead_load},
        ),
        "record_readers": _describe(
            registry.record_readers,
            lambda reader: {
                "suffixes": list(getattr(reader, "suffixes", ())),
                "description": getattr(reader, "description", "") or "",
            },
        ),
        "intensity_scales": _describe(
            registry.intensity_scales,
            lambda scale: {k: v for k, v in scale.to_dict().items() if k != "name"},
        ),
        "metrics": _describe(registry.metrics, _description),
        "executors": _describe(registry.executors, _description),
        "broken": [{"plugin": b.plugin, "distribution": b.distribution, "error": b.error} for b in registry.broken],
    }


def _format_parameter(p: dict) -> str:
    text = p["name"]
    if p["range"]:
        text += f" ({p['range']}{', ' + p['unit'] if p['unit'] else ''})"
    if not p["required"]:
        text += f" = {p['default']!r}"
    return text


def _format_flags(flags: dict, compiled: bool = False) -> str:
    labels = [FLAG_LABELS[flag] for flag in OPTIONAL_FLAGS if flags.get(flag)] + (["compiled"] if compiled else [])
    return ", ".join(labels) or "-"


def _print_table(title: str, kind: str, items: list[dict], columns: list[tuple[str, object]]) -> None:
    """Name (headed ``kind``), distribution, plugin and ``columns`` (header, item -> text) aligned; the last
    column free text."""
    print(title)
    if not items:
        print("  (none)")
        return
    head = (kind, "distribution", "plugin", *(header for header, _ in columns))
    rows = [
        (item["name"], f"{item['distribution'] or '?'} {item['version'] or ''}".strip(), item["plugin"],
         *(text(item) for _, text in columns))
        for item in items
    ]
    widths = [max(len(r[i]) for r in [head, *rows]) for i in range(len(head) - 1)]
    for row in [head, *rows]:
        print("  " + "  ".join(cell.ljust(w) for cell, w in zip(row[:-1], widths)) + "  " + row[-1])


def _with_description(item: dict) -> str:
    return item.get("description") or "-"


def run(args) -> int:
    """Exit status 1 when a plugin failed to load (the listing says which), else 0."""
    data = listing()
    status = 1 if data["broken"] else 0
    if args.json:
        print(json.dumps(data, indent=2, default=str))
        return status
    _print_table("Bearing laws:", "law", data["laws"], [
        ("flags", lambda law: _format_flags(law["flags"], law["compiled"])),
        ("parameters", lambda law: "; ".join(_format_parameter(p) for p in law["parameters"]) or "-"),
    ])
    print()
    _print_table("Bearing presets:", "preset", data["presets"], [
        ("description", lambda p: p["description"] + (" (uses the dead load)" if p["needs_dead_load"] else "")),
    ])
    print()
    _print_table("Record readers:", "reader", data["record_readers"],
                 [("files", lambda r: " ".join(r["suffixes"]) + (f"  {r['description']}" if r["description"] else ""))])
    print()
    _print_table("Intensity scales:", "scale", data["intensity_scales"], [("degrees", lambda s: " ".join(s["degrees"]))])
    print()
    _print_table("Metric families:", "metric", data["metrics"], [("description", _with_description)])
    print()
    _print_table("Executors:", "executor", data["executors"], [("description", _with_description)])
    if data["broken"]:
        print("\nBroken plugins (not loaded):")
        for b in data["broken"]:
            print(f"  {b['plugin']} ({b['distribution'] or 'unknown distribution'}): {b['error']}")
    return status
