"""``bearingfw plugins``: what is loaded, where it came from, and what failed to load."""

from __future__ import annotations

import json

from bearingfw.plugins import describe_parameters, get_registry


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "plugins",
        help="list the loaded plugins and what they register",
        description="List every registered bearing law (with its parameters), record reader and "
        "intensity scale, the plugin and the distribution it came from, and every plugin that "
        "failed to load with its error.",
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


def listing() -> dict:
    """The registry as plain data (the ``--json`` output)."""
    registry = get_registry()
    return {
        "laws": _describe(
            registry.laws,
            lambda cls: {"class": f"{cls.__module__}.{cls.__qualname__}", "parameters": describe_parameters(cls)},
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
        "broken": [{"plugin": b.plugin, "distribution": b.distribution, "error": b.error} for b in registry.broken],
    }


def _format_parameter(p: dict) -> str:
    text = p["name"]
    if p["range"]:
        text += f" ({p['range']}{', ' + p['unit'] if p['unit'] else ''})"
    if not p["required"]:
        text += f" = {p['default']!r}"
    return text


def _print_table(title: str, headers: tuple[str, str], items: list[dict], last_column) -> None:
    """Name, distribution and plugin columns aligned; the last column free text."""
    print(title)
    rows = [
        (item["name"], f"{item['distribution'] or '?'} {item['version'] or ''}".strip(), item["plugin"], last_column(item))
        for item in items
    ]
    if not rows:
        print("  (none)")
        return
    head = (headers[0], "distribution", "plugin", headers[1])
    widths = [max(len(r[i]) for r in [head, *rows]) for i in range(3)]
    for row in [head, *rows]:
        print("  " + "  ".join(cell.ljust(w) for cell, w in zip(row[:3], widths)) + "  " + row[3])


def run(args) -> int:
    data = listing()
    if args.json:
        print(json.dumps(data, indent=2, default=str))
        return 0
    _print_table("Bearing laws:", ("law", "parameters"), data["laws"],
                 lambda law: "; ".join(_format_parameter(p) for p in law["parameters"]) or "-")
    print()
    _print_table("Record readers:", ("reader", "files"), data["record_readers"],
                 lambda r: " ".join(r["suffixes"]) + (f"  {r['description']}" if r["description"] else ""))
    print()
    _print_table("Intensity scales:", ("scale", "degrees"), data["intensity_scales"], lambda s: " ".join(s["degrees"]))
    if data["broken"]:
        print("\nBroken plugins (not loaded):")
        for b in data["broken"]:
            print(f"  {b['plugin']} ({b['distribution'] or 'unknown distribution'}): {b['error']}")
    return 0
