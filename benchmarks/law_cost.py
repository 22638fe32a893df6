#!/usr/bin/env python
"""What one ``respond`` call costs, in microseconds, for every installed bearing law (issue 16).

Usage::

    python benchmarks/law_cost.py                  # every registered law, 11 connectors, 1-D and 2-D
    python benchmarks/law_cost.py --law bouc-wen   # one law (repeat --law for several)
    python benchmarks/law_cost.py --connectors 1   # another connector count
    python benchmarks/law_cost.py --json           # the table as JSON on stdout

A call serves all the connectors of one law, as the kernel makes it once per Newton iteration
(the reference bridge has 11 sliding bearings: 6 guided, 1-D, and 5 free, 2-D). Each law is built
from its parameters' ``typical`` values (else their defaults; a required parameter with neither
takes the low end of its range), with, for a law that takes per-bearing parameters, its first
such parameter spread over 0.7-1.3 times that value across the connectors (as the reference
bridge's presets give each bearing its own ``uy`` or friction force): the ``per-bearing`` column;
the ``scalar`` column is the same law with one value for all. ``bouc-wen n=2`` is Bouc-Wen at the
exponent of the registered ``bouc-wen`` preset (``n = 2``, integrated in closed form; the
parameters' typical ``n = 1`` takes backward-Euler substeps), ``alpha = 0``.

The calls. A displacement scale ``d`` per law: where it yields from rest
(:func:`bearingfw.testing.conformance.yield_displacement`, found with the law's initial
stiffness), or 1 mm for a law that does not yield. Committed states come from a seeded random
walk (steps of 0.3-3 ``d`` per connector), so that the trials load, unload and reverse; a trial
moves each connector from one of them by 0.01-1 ``d`` (log-uniform) in a random direction, like
the corrections of a Newton iteration. Normal forces 1-3 MN. A cell is the fastest of
``--rounds`` rounds over the ``--calls`` trials, per call (fewer rounds for a slow law, once
``--budget`` seconds are spent), in the process's CPU time (``--wall``: wall-clock): on a busy
machine the least disturbed round is the closest to the cost itself, and CPU time is less
disturbed than wall-clock time. The laws' own output is not checked here (their tests
do that). The script reports; it asserts nothing. It times whatever is importable: to time
another version of a law package, put it first on ``PYTHONPATH``.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import attrs
import numpy as np

import bearingfw
from bearingfw.testing.conformance import yield_displacement

SPREAD = (0.7, 1.3)
DT = 0.005


def typical_parameters(cls) -> dict:
    """Keyword parameters of ``cls`` from its fields' ``typical`` values, else defaults, else range's low end."""
    params = {}
    for field in attrs.fields(cls):
        if field.name == "dims" or not field.init:
            continue
        typical = field.metadata.get("typical")
        if typical is not None:
            params[field.name] = typical
        elif field.default is attrs.NOTHING:
            low = field.metadata.get("bounds", (None,))[0]
            params[field.name] = 0.0 if low is None else low
    return params


def spread_parameter(cls, params: dict, m: int) -> dict:
    """``params`` with the first per-bearing parameter spread over ``SPREAD`` times its value across ``m``."""
    for field in attrs.fields(cls):
        value = params.get(field.name)
        if field.metadata.get("per_bearing") and isinstance(value, float) and value != 0.0:
            return params | {field.name: value * np.linspace(*SPREAD, m)}
    return params


def displacement_scale(cls, params: dict, dims: int) -> float:
    """Where one connector of the law yields from rest, or 1 mm if it does not (module docstring)."""
    law = cls(**params, dims=dims)
    normal = np.array([2e6])
    probe = np.zeros((1, dims))
    probe[0, 0] = 1e-9
    stiffness = float(np.asarray(law.respond(law.initial_state(1), probe, normal, DT).tangent)[0, 0, 0])
    scale = yield_displacement(law, normal, DT, stiffness) if stiffness > 0 else None
    return scale or 1e-3


def trials(law, m: int, scale: float, calls: int, rng: np.random.Generator):
    """``calls`` trial calls ``(state, u, normal)`` from committed states of a random walk."""
    normal = rng.uniform(1e6, 3e6, m)
    state, u = law.initial_state(m), np.zeros((m, law.dims))  # the state's layout is the law's own
    out = []
    for _ in range(calls):
        step = rng.normal(size=(m, law.dims))
        step *= (scale * rng.uniform(0.3, 3.0, (m, 1))) / np.linalg.norm(step, axis=1, keepdims=True)
        u = u + step
        state = law.respond(state, u, normal, DT).state
        direction = rng.normal(size=(m, law.dims))
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        length = scale * 10.0 ** rng.uniform(-2.0, 0.0, (m, 1))
        out.append((state, u + length * direction, normal))
    return out


def cost(
    law, m: int, scale: float, calls: int, rounds: int, budget: float, seed: int, clock=time.process_time
) -> float:
    """Microseconds per ``respond`` call: the fastest of ``rounds`` rounds over ``calls`` trials
    (fewer rounds, at least one, once ``budget`` seconds of ``clock`` are spent: a slow law)."""
    calls_ = trials(law, m, scale, calls, np.random.default_rng(seed))
    respond, best, spent = law.respond, math.inf, 0.0
    for _ in range(rounds):
        start = clock()
        for state, u, normal in calls_:
            respond(state, u, normal, DT)
        elapsed = clock() - start
        best, spent = min(best, elapsed / len(calls_)), spent + elapsed
        if spent > budget:
            break
    return best * 1e6


def cases(names: list[str] | None):
    """``(label, class, params)`` per law to measure: every registered non-rigid law (or ``names``)."""
    registry = bearingfw.get_registry()
    out = []
    for name, entry in registry.laws.items():
        cls = entry.value
        if getattr(cls, "rigid", False) or not attrs.has(cls) or (names and name not in names):
            continue
        params = typical_parameters(cls)
        out.append((name, cls, params))
        if name == "bouc-wen":
            out.append(("bouc-wen n=2", cls, params | {"n": 2.0, "alpha": 0.0}))
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--law", action="append", help="a registered law's name (repeat for several; default all)")
    parser.add_argument("--connectors", type=int, default=11, help="connectors per call (default 11)")
    parser.add_argument("--calls", type=int, default=200, help="trial calls per round (default 200)")
    parser.add_argument("--rounds", type=int, default=5, help="rounds; the fastest counts (default 5)")
    parser.add_argument("--budget", type=float, default=2.0, help="seconds per cell after which no new round starts")
    parser.add_argument("--wall", action="store_true", help="time wall-clock instead of the process's CPU time")
    parser.add_argument("--json", action="store_true", help="print the table as JSON")
    args = parser.parse_args(argv)
    clock = time.perf_counter if args.wall else time.process_time
    m = args.connectors
    rows = []
    for label, cls, params in cases(args.law):
        row = {"law": label}
        for dims in (1, 2):
            scale = displacement_scale(cls, params, dims)
            row[f"scale {dims}-D [m]"] = scale
            variants = {"scalar": params}
            if getattr(cls, "per_bearing", False):
                variants["per-bearing"] = spread_parameter(cls, params, m)
            for variant, values in variants.items():
                law = cls(**values, dims=dims)
                row[f"{dims}-D {variant}"] = cost(
                    law, m, scale, args.calls, args.rounds, args.budget, seed=12345 + dims, clock=clock
                )
        rows.append(row)
    if args.json:
        document = {"connectors": m, "clock": "wall" if args.wall else "cpu", "microseconds_per_call": rows}
        print(json.dumps(document, indent=1))
        return
    columns = ["1-D scalar", "1-D per-bearing", "2-D scalar", "2-D per-bearing"]
    print(
        f"respond(), {'wall-clock' if args.wall else 'CPU'} microseconds per call for {m} connectors "
        f"(fastest of up to {args.rounds} rounds of {args.calls} calls)"
    )
    print("| law | " + " | ".join(columns) + " |")
    print("|---|" + "---:|" * len(columns))
    for row in rows:
        cells = [f"{row[c]:.1f}" if c in row else "-" for c in columns]
        print(f"| {row['law']} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
