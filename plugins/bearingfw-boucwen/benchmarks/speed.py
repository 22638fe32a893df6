#!/usr/bin/env python
"""Microseconds per ``BoucWen.respond`` call: 1, 5 and 12 connectors, 1-D and 2-D, increments of
0.1, 1 and 10 uy.

    python plugins/bearingfw-boucwen/benchmarks/speed.py              # n = 2 and n = 4
    python plugins/bearingfw-boucwen/benchmarks/speed.py --n 2 --json  # one exponent, JSON out

The law has the reference bridge's ``bouc-wen`` preset shape (``alpha = 0``, ``A = 1``,
``beta = gamma = 0.5``, ``k = 400 MN/m``, ``uy = 0.2 mm``: the friction force ``mu N_dead`` of a
2 MN bearing reached at the stick stiffness). Each call starts from one of 16 committed states
reached by a seeded random history (``z`` anywhere in the admissible ball, so the increments
load, unload and reverse) and moves every connector by the given length in a seeded random
direction. A cell reports the fastest of 5 rounds over the 16 calls (the least disturbed by
other processes), per call.

Whatever ``bearingfw_boucwen`` is importable is measured: to time another version of the plugin
put it first on ``PYTHONPATH``.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import bearingfw_boucwen
from bearingfw_boucwen import BoucWen

CONNECTORS = (1, 5, 12)
INCREMENTS = (0.1, 1.0, 10.0)
STATES = 16
ROUNDS = 5
PRESET_SHAPE = {"k": 4.0e8, "alpha": 0.0, "uy": 2.0e-4, "A": 1.0, "beta": 0.5, "gamma": 0.5}


def committed_states(law: BoucWen, m: int, rng: np.random.Generator) -> list[dict]:
    """``STATES`` committed states of ``m`` connectors after random histories of 1-3 uy steps."""
    states, state = [], law.initial_state(m)
    while len(states) < STATES:
        step = rng.uniform(-1.0, 1.0, (m, law.dims)) * law.uy * rng.uniform(1.0, 3.0)
        state = law.respond(state, state["u"] + step, np.ones(m), 0.01).state
        states.append(state)
    return states


def time_per_call(law: BoucWen, m: int, increment: float, rng: np.random.Generator) -> float:
    states = committed_states(law, m, rng)
    trials = []
    for state in states:
        direction = rng.normal(size=(m, law.dims))
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        trials.append((state, state["u"] + increment * law.uy * direction))
    normal = np.ones(m)
    best = np.inf
    for _ in range(ROUNDS):
        start = time.perf_counter()
        for state, u in trials:
            law.respond(state, u, normal, 0.01)
        best = min(best, (time.perf_counter() - start) / len(trials))
    return best * 1e6


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=float, action="append", help="Bouc-Wen exponent(s) (default: 2 and 4)")
    parser.add_argument("--json", action="store_true", help="print the table as JSON")
    args = parser.parse_args(argv)
    exponents = args.n or [2.0, 4.0]
    rows = []
    for n in exponents:
        for dims in (1, 2):
            law = BoucWen(**PRESET_SHAPE, n=n, dims=dims)
            for m in CONNECTORS:
                rng = np.random.default_rng(12345)
                cells = {f"{inc:g} uy": time_per_call(law, m, inc, rng) for inc in INCREMENTS}
                rows.append({"n": n, "dims": dims, "connectors": m, **cells})
    if args.json:
        print(json.dumps({"plugin": bearingfw_boucwen.__file__, "microseconds_per_call": rows}, indent=1))
        return
    print(f"BoucWen.respond, microseconds per call ({bearingfw_boucwen.__file__})")
    header = ["n", "dims", "connectors"] + [f"{inc:g} uy" for inc in INCREMENTS]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        cells = [f"{row['n']:g}", str(row["dims"]), str(row["connectors"])]
        cells += [f"{row[f'{inc:g} uy']:.0f}" for inc in INCREMENTS]
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
