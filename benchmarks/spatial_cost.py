#!/usr/bin/env python
"""What one realisation of spatially varying ground motion costs, and how close its spectra stay (issue 17).

Usage::

    python benchmarks/spatial_cost.py                  # Manjil, both coherency models, seeds 0-2
    python benchmarks/spatial_cost.py --seeds 0-9      # more seeds
    python benchmarks/spatial_cost.py --record chuetsu # the Chuetsu 2007 record (dt 0.01 s, 60 s)
    python benchmarks/spatial_cost.py --quick          # one model, one seed

Case: the record of ``examples/data/records`` (three components), four supports on a line at 0, 40,
100 and 160 m, apparent velocity 600 m/s along the line, the coherency model and seed of the row,
:class:`bearingfw.motion.spatial.SpatialVariation`'s default passes. One realisation is one call of
:func:`~bearingfw.motion.spatial.spatial_motions` (three generated supports x three components).

Columns: ``wall s`` and ``cpu s`` of that call (the process's CPU time: on a busy machine wall time
grows, CPU time much less; the load average is printed at the top); ``worst``: the largest
``|PSA_support / PSA_record - 1|`` over the three generated supports, every component and
``--frequencies`` frequencies (default 1000) log-spaced over 0.5-10 Hz, 5 % damping, both spectra from
:func:`bearingfw.motion.response_spectrum` (the definition the tests use, independent of the
generator's own evaluation); ``at``: the support, component and frequency of that worst misfit;
``mean``: the mean misfit. The last line gives the largest ``worst`` and the median and largest time.

Machine of the figures in the module docstring of ``bearingfw.motion.spatial``: 2 cores shared with
other jobs (load average about 3).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from bearingfw.motion import read_record, response_spectrum
from bearingfw.motion.spatial import SpatialVariation, spatial_motions

RECORDS = Path(__file__).resolve().parents[1] / "examples" / "data" / "records"
FILES = {
    "manjil": [f"RSN1633_MANJIL_ABBAR--{c}.AT2" for c in "LTV"],
    "chuetsu": [f"RSN4843_CHUETSU_65006{c}.AT2" for c in ("EW", "NS", "UD")],
}
POSITIONS = {"A": (0.0, 0.0), "B": (40.0, 0.0), "C": (100.0, 0.0), "D": (160.0, 0.0)}


def _seeds(text: str) -> list[int]:
    if "-" in text:
        lo, hi = (int(v) for v in text.split("-"))
        return list(range(lo, hi + 1))
    return [int(v) for v in text.split(",")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", choices=sorted(FILES), default="manjil")
    parser.add_argument("--models", default="harichandran-vanmarcke,luco-wong")
    parser.add_argument("--seeds", default="0-2", help="'0-9' or '0,3,5'")
    parser.add_argument("--frequencies", type=int, default=1000)
    parser.add_argument("--quick", action="store_true", help="the first model and seed only")
    args = parser.parse_args()
    models, seeds = args.models.split(","), _seeds(args.seeds)
    if args.quick:
        models, seeds = models[:1], seeds[:1]
    rec = read_record([RECORDS / name for name in FILES[args.record]])
    a, dt = np.column_stack([rec.h1, rec.h2, rec.v]), rec.dt
    periods = 1.0 / np.geomspace(0.5, 10.0, args.frequencies)
    reference = [response_spectrum(a[:, c], dt, periods).psa for c in range(3)]
    print(f"{args.record}: {a.shape[0]} samples of {dt:g} s; load average {os.getloadavg()[0]:.2f}")
    print(f"{'model':24s} {'seed':>4s} {'wall s':>7s} {'cpu s':>7s} {'worst':>7s} {'mean':>7s}  at")
    worst_all, times = 0.0, []
    for model in models:
        for seed in seeds:
            variation = SpatialVariation(apparent_velocity=600.0, coherency=model, seed=seed)
            wall, cpu = time.perf_counter(), time.process_time()
            out = spatial_motions(a, dt, POSITIONS, variation)
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            misfit = np.array([[np.abs(response_spectrum(out[s][:, c], dt, periods).psa / reference[c] - 1.0)
                                for c in range(3)] for s in "BCD"])
            s, c, k = np.unravel_index(np.argmax(misfit), misfit.shape)
            worst_all = max(worst_all, float(misfit.max()))
            times.append(cpu)
            print(f"{model:24s} {seed:4d} {wall:7.2f} {cpu:7.2f} {misfit.max():7.3f} {misfit.mean():7.4f}  "
                  f"{'BCD'[s]}/{'123'[c]} {1.0 / periods[k]:.2f} Hz", flush=True)
    print(f"largest misfit {worst_all:.3f}; cpu s per realisation: median {np.median(times):.2f}, "
          f"largest {max(times):.2f}")


if __name__ == "__main__":
    main()
