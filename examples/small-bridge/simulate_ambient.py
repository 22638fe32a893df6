"""Simulated ambient vibration test of the small bridge: the input of ``bearingfw oma`` in this example.

The "real" bridge is ``small_bridge.build`` with sticking pot bearings, linear springs of
``--bearing-stiffness`` (default 2e8 N/m) in their sliding directions; ``bearingfw tune`` should
find that value back from the identified modes. Its response to white-noise ground motion (x, y,
z) and to random forces of traffic and wind on the deck is computed by exact modal superposition
(:func:`bearingfw.oma.simulate_ambient`, 2 % damping in every mode, 5 % measurement noise) at the
sensor channels below, named ``<node>.<component>`` so that ``bearingfw oma --structure`` can
check them and ``bearingfw tune`` can pair the identified shapes there:

    python examples/small-bridge/simulate_ambient.py --out ambient.npz

The file (NPZ, about 2.6 MB for the default 600 s at 50 Hz) is not part of the repository: the
script writes it in a few seconds.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: Accelerometers on the girder's axis (nodes 3 m apart; G8 over the pier): vertical and transverse
#: at both spans' quarter points and middles, longitudinal at the first mid-span (the girder
#: moves along the bridge as one).
CHANNELS = (
    "G2.uz", "G4.uz", "G6.uz", "G10.uz", "G12.uz", "G14.uz",
    "G2.uy", "G4.uy", "G12.uy", "G14.uy",
    "G4.ux",
)
#: Traffic and wind: independent random forces (RMS, N) at the mid-spans, vertical and transverse.
TRAFFIC = {"G4.uz": 2e4, "G12.uz": 2e4, "G4.uy": 1e4, "G12.uy": 1e4}
BEARING_STIFFNESS = 2e8


def simulate(
    bearing_stiffness: float = BEARING_STIFFNESS, duration: float = 600.0, dt: float = 0.02, seed: int = 1,
):
    """The simulated channels (:class:`bearingfw.oma.Channels`) of the bridge with ``bearing_stiffness``."""
    sys.path.insert(0, str(HERE))
    from small_bridge import build

    from bearingfw.analysis import solve_modal
    from bearingfw.oma import simulate_ambient

    modal = solve_modal(build(bearing_stiffness=bearing_stiffness), 30)
    return simulate_ambient(
        modal, CHANNELS, duration, dt, damping=0.02, ground=(0.01, 0.01, 0.01), loads=TRAFFIC, noise=0.05, seed=seed
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="ambient.npz", help="the NPZ file to write (default ambient.npz)")
    parser.add_argument("--bearing-stiffness", type=float, default=BEARING_STIFFNESS, metavar="N/M",
                        help=f"the sliding bearings' stiffness of the 'real' bridge (default {BEARING_STIFFNESS:g})")
    parser.add_argument("--duration", type=float, default=600.0, metavar="S", help="record length (default 600 s)")
    parser.add_argument("--dt", type=float, default=0.02, metavar="S", help="sampling interval (default 0.02 s)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    args = parser.parse_args(argv)
    channels = simulate(args.bearing_stiffness, args.duration, args.dt, args.seed)
    path = channels.to_npz(args.out)
    print(f"wrote {path}: {channels.n_channels} channels ({', '.join(channels.names)}), "
          f"{channels.duration:g} s at dt = {channels.dt:g} s, bearing stiffness {args.bearing_stiffness:g} N/m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
