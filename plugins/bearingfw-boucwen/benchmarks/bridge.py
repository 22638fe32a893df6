#!/usr/bin/env python
"""Time of the reference bridge with the ``bouc-wen`` preset over the synthetic tremor.

    python plugins/bearingfw-boucwen/benchmarks/bridge.py [--seconds 3] [--dt 0.005] [--exponent N]
    python plugins/bearingfw-boucwen/benchmarks/bridge.py --preset M2      # the friction law, for scale

The synthetic tremor (seed 0) scaled to D_II, its first ``--seconds`` seconds, integrated at
``--dt`` (sampled at every ``--dt`` from the 0.005 s record); the gravity preload is computed
(and timed) separately. Prints the transient's wall and CPU time, the number of Bouc-Wen calls
and the CPU time spent in them, and peak bearing force and displacement; ``--save FILE`` stores
the horizontal bearing forces (npz) so that two runs can be compared (``--compare FILE``).
``--exponent`` overrides ``BridgeParameters.boucwen_exponent``. The plugin timed is whatever
``bearingfw_boucwen`` is importable (put another version first on ``PYTHONPATH`` to compare).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bearingfw.analysis import ConnectorResponse, gravity, solve_transient
from bearingfw.bridges import BridgeParameters, reference_bridge
from bearingfw.motion import scale_to_level, synthetic_tremor


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--dt", type=float, default=0.005)
    parser.add_argument("--preset", default="bouc-wen")
    parser.add_argument("--exponent", type=float, help="the preset's Bouc-Wen n (default: BridgeParameters')")
    parser.add_argument("--save")
    parser.add_argument("--compare")
    args = parser.parse_args(argv)

    record = scale_to_level(synthetic_tremor(seed=0), "D_II")
    steps = int(round(args.seconds / record.dt)) + 1
    acceleration = record.components.T[:steps]
    if abs(args.dt - record.dt) > 1e-12:  # resample linearly onto the integration step
        t = np.arange(steps) * record.dt
        t_new = np.arange(int(round(args.seconds / args.dt)) + 1) * args.dt
        acceleration = np.stack([np.interp(t_new, t, c) for c in acceleration.T], axis=1)

    params = BridgeParameters() if args.exponent is None else BridgeParameters(boucwen_exponent=args.exponent)
    model = reference_bridge(args.preset, params=params)
    start = time.perf_counter()
    preload = gravity(model)
    gravity_time = time.perf_counter() - start

    law_calls, law_time = [0], [0.0]
    cls = None
    try:
        import bearingfw_boucwen

        cls = bearingfw_boucwen.BoucWen
        original = cls.respond

        def counted(self, *a, **k):
            law_calls[0] += 1
            start = time.process_time()
            try:
                return original(self, *a, **k)
            finally:
                law_time[0] += time.process_time() - start

        cls.respond = counted
    except ImportError:
        pass

    recorder = ConnectorResponse()
    start, cpu = time.perf_counter(), time.process_time()
    result = solve_transient(model, acceleration, args.dt, preload=preload, recorders=[recorder])
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    if cls is not None:
        cls.respond = original

    forces = np.asarray(result[f"{recorder.label}.force"])
    displacement = np.asarray(result[f"{recorder.label}.displacement"])
    stats = result.stats
    print(f"preset {args.preset}: {args.seconds:g} s at dt {args.dt:g} s: transient {wall:.2f} s wall, {cpu:.2f} s CPU "
          f"(gravity {gravity_time:.2f} s); steps {stats['steps']}, Newton iterations {stats['iterations']}, "
          f"Bouc-Wen calls {law_calls[0]} ({law_time[0]:.2f} s CPU in them)")
    horizontal = forces[..., :2]
    print(f"peak |horizontal bearing force| {np.abs(horizontal).max():.6g} N, "
          f"peak |bearing displacement| {np.abs(displacement[..., :2]).max():.4g} m")
    if args.save:
        np.savez(args.save, force=horizontal)
    if args.compare:
        other = np.load(args.compare)["force"]
        diff = np.abs(horizontal - other).max() / np.abs(other).max()
        print(f"max |horizontal force - saved| / its peak = {diff:.3g}")


if __name__ == "__main__":
    main()
