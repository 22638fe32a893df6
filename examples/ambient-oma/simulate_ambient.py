"""SIMULATED ambient vibration test of the reference bridge: the data set of this example (``ambient.npz``).

Not a measurement. The "real" bridge is bearingfw's reference bridge with sticking pot bearings,
the M1 model (linear springs K_s in the sliding directions, K_s = ``--ks``, default the study's
400 MN/m), with the paper's Rayleigh damping (alpha = 0.21 1/s, beta = 0.00208 s). Its response
to white-noise support acceleration (0.01 m/s^2 RMS in x, y and z) is computed by exact modal
superposition (:func:`bearingfw.oma.simulate_ambient`, 5 % measurement noise), at the paper's
measurement points P1..P7 (section 2.3) on girder A, transverse and vertical: 14 channels named
``<node>.<component>`` (``GA12.uz``), so that ``bearingfw oma --structure reference`` checks them
and ``bearingfw tune --measured`` pairs the identified shapes there by MAC.

Stored as float32 (the accelerations' 7 significant digits are far below the 5 % noise) to keep
the file small: 14 channels x 4800 samples (240 s at 20 Hz), about 270 kB. Regenerate it with

    python examples/ambient-oma/simulate_ambient.py --out examples/ambient-oma/ambient.npz

(seeded: the same file every time on the same numpy).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DURATION = 240.0
DT = 0.05
GROUND = (0.01, 0.01, 0.01)
SEED = 1
#: The label every copy of the data carries (the NPZ's ``source``; ``synthetic`` is True).
SOURCE = "SIMULATED ambient test of the bearingfw reference bridge (M1, K_s = {ks:g} N/m), not a measurement"


def channels_of_points() -> list[str]:
    """P1..P7 on girder A, transverse and vertical (``bearingfw.bridges.study.paper_sensors``)."""
    from bearingfw.bridges.study import paper_sensors

    return [c for point in paper_sensors().values() for c in point if c.startswith("GA")]


def simulate(ks: float | None = None, duration: float = DURATION, dt: float = DT, seed: int = SEED):
    """The simulated channels (:class:`bearingfw.oma.Channels`) of the M1 bridge with ``ks`` (default the study's)."""
    from bearingfw.analysis import Rayleigh, solve_modal
    from bearingfw.bridges import DEFAULT_KS, reference_bridge
    from bearingfw.bridges.paper import RAYLEIGH
    from bearingfw.oma import simulate_ambient

    ks = DEFAULT_KS if ks is None else ks
    modal = solve_modal(reference_bridge("M1", ks=ks), 60)
    record = simulate_ambient(modal, channels_of_points(), duration, dt, damping=Rayleigh(*RAYLEIGH), ground=GROUND,
                              seed=seed)
    return record, ks


def write(record, ks: float, path) -> Path:
    """The NPZ archive ``bearingfw oma`` reads: one float32 array per channel, ``dt``, ``units``, the label."""
    path = Path(path)
    arrays = {name: record.data[:, j].astype(np.float32) for j, name in enumerate(record.names)}
    np.savez_compressed(path, dt=record.dt, units=record.units, names=np.array(record.names),
                        source=SOURCE.format(ks=ks), synthetic=True, **arrays)
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(HERE / "ambient.npz"), help="the NPZ file to write (default: next to "
                        "this script)")
    parser.add_argument("--ks", type=float, default=None, metavar="N/M",
                        help="K_s of the simulated bridge (default the study's, 4e8)")
    parser.add_argument("--seed", type=int, default=SEED, help=f"random seed (default {SEED})")
    args = parser.parse_args(argv)
    record, ks = simulate(args.ks, seed=args.seed)
    path = write(record, ks, args.out)
    print(f"wrote {path} ({path.stat().st_size / 1e3:.0f} kB): SIMULATED, {record.n_channels} channels, "
          f"{record.duration:g} s at dt = {record.dt:g} s, K_s = {ks:g} N/m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
