"""``bearingfw plugins``: what is loaded, where it came from, and what failed to load."""

from __future__ import annotations

import json

from bearingfw.plugins import describe_parameters, get_registry


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "plugins",
        help="list the loaded plugins and the laws they register",
        description="List every registered bearing law with its parameters, the plugin and the "
        "distribution it came from, and every plugin that failed to load with its error.",
    )
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    parser.set_defaults(func=run)


def listing() -> dict:
    """The registry as plain data (the ``--json`` output)."""
    registry = get_registry()
    laws = [
        {
            "name": entry.key,
            "plugin": entry.origin.plugin,
            "distribution": entry.origin.distribution,
            "version": entry.origin.version,
            "class": f"{entry.value.__module__}.{entry.value.__qualname__}",
            "parameters": describe_parameters(entry.value),
        }
        for entry in sorted(registry.laws.values(), key=lambda e: e.key)
    ]
    broken = [
        {"plugin": b.plugin, "distribution": b.distribution, "error": b.error} for b in registry.broken
    ]
    return {"laws": laws, "broken": broken}


def _format_parameter(p: dict) -> str:
    text = p["name"]
    if p["range"]:
        text += f" ({p['range']}{', ' + p['unit'] if p['unit'] else ''})"
    if not p["required"]:
        text += f" = {p['default']!r}"
    return text


def run(args) -> int:
    data = listing()
    if args.json:
        print(json.dumps(data, indent=2, default=str))
        return 0
    print("Bearing laws:")
    rows = [
        (law["name"], f"{law['distribution'] or '?'} {law['version'] or ''}".strip(), law["plugin"],
         "; ".join(_format_parameter(p) for p in law["parameters"]) or "-")
        for law in data["laws"]
    ]
    headers = ("law", "distribution", "plugin", "parameters")
    widths = [max(len(r[i]) for r in [headers, *rows]) for i in range(3)]
    for row in [headers, *rows]:
        print("  " + "  ".join(cell.ljust(w) for cell, w in zip(row[:3], widths)) + "  " + row[3])
    if data["broken"]:
        print("\nBroken plugins (not loaded):")
        for b in data["broken"]:
            print(f"  {b['plugin']} ({b['distribution'] or 'unknown distribution'}): {b['error']}")
    return 0
