"""Which modes carry a response element's stress, per bearing model and record: a response-spectrum breakdown.

For a linear model (M0 frictionless, M1 springs) under the same acceleration at every support, the
dynamic response is the sum of its modes, each an oscillator driven by the ground: mode k's peak
coordinate from direction d is ``|Gamma_kd| Sd_d(f_k, zeta_k)`` (participation factor of the
mass-normalised shape, displacement spectrum of that ground component at the mode's frequency and
Rayleigh damping ratio). Times the normal stress that mode's shape puts into the element's
recovery points, that is the mode's peak share of the element's dynamic stress. This script lists
the largest shares and their square-root-of-sum-of-squares (SRSS) per model, and the SRSS ratio
M0/M1, to set against the ratio of the time histories (robustness.py). An estimate, not a time
history: it says *which* modes and *which* ground component decide the ratio.

    python examples/paper-study/modal_contributions.py                 # S1 and 3B, the records of robustness.toml
    python examples/paper-study/modal_contributions.py --element 3B --records seed0 chuetsu
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
EXPERIMENT = HERE / "robustness.toml"
DIRECTIONS = ("x", "y", "z")


def ground_motions(experiment, names=None, level: str = "D_0") -> dict[str, tuple[np.ndarray, float]]:
    """``{record: (acceleration (steps, 3) in x, y, z, dt)}`` as the experiment applies it at ``level``."""
    from bearingfw.experiment.records import ground_acceleration, load_record, scaled_record

    out = {}
    intensity = next(i for i in experiment.intensity_list if i.name == level)
    for spec in experiment.records:
        if names and spec.name not in names:
            continue
        record = scaled_record(load_record(experiment, spec), intensity, experiment.intensities,
                               experiment.integration.dt_integration)
        out[spec.name] = (ground_acceleration(record, None if record.directional else spec.components), record.dt)
    return out


def modal_stresses(model_name: str, experiment, element: str, n_modes: int = 60):
    """The model's modes, each one's normal stress at the element's recovery points (both ends), and their labels."""
    from bearingfw.analysis import solve_modal
    from bearingfw.analysis.results import element_stresses
    from bearingfw.bridges.study import mode_labels
    from bearingfw.experiment.structure import build_model

    spec = next(m for m in experiment.models if m.name == model_name)
    modal = solve_modal(build_model(experiment, spec), n_modes)
    sigma = np.stack([element_stresses(modal.system, modal.shapes[:, k], [element])[element].sigma.ravel()
                      for k in range(modal.n_modes)])  # (modes, ends x points)
    return modal, sigma, mode_labels(modal)


def breakdown(modal, sigma, labels, ground: np.ndarray, dt: float, rayleigh) -> dict:
    """Per mode and ground direction: the peak stress share; the SRSS at the governing recovery point."""
    from bearingfw.motion.metrics import response_spectrum

    f = modal.frequencies
    zeta = rayleigh.alpha / (4 * math.pi * f) + rayleigh.beta * math.pi * f
    share = np.zeros((modal.n_modes, 3, sigma.shape[1]))
    for d, direction in enumerate(DIRECTIONS):
        gamma = modal.participation[direction]
        for k in range(modal.n_modes):
            sd = response_spectrum(ground[:, d], dt, [1.0 / f[k]], float(zeta[k])).sd[0]
            share[k, d] = abs(gamma[k]) * sd * sigma[k]
    srss = np.sqrt(np.sum(share**2, axis=(0, 1)))
    point = int(np.argmax(srss))
    table = share[:, :, point]
    order = np.argsort(-np.abs(table).ravel())
    total = float(srss[point])
    top = []
    for flat in order[:6]:
        k, d = divmod(int(flat), 3)
        top.append({"mode": labels[k], "frequency": float(f[k]), "direction": DIRECTIONS[d],
                    "stress": float(abs(table[k, d])), "share": float(table[k, d] ** 2 / total**2)})
    return {"srss": total, "top": top}


def spectral_acceleration(acc: np.ndarray, dt: float, frequency: float, damping: float = 0.05) -> float:
    """Sa (pseudo-acceleration, m/s^2) of ``acc`` at ``frequency``."""
    from bearingfw.motion.metrics import response_spectrum

    return float(response_spectrum(acc, dt, [1.0 / frequency], damping).psa[0])


def main(argv=None) -> int:
    from bearingfw.analysis import Rayleigh
    from bearingfw.experiment import load_experiment

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--experiment", default=str(EXPERIMENT))
    parser.add_argument("--element", action="append", help="response element(s) (default S1 and 3B)")
    parser.add_argument("--records", nargs="*", help="records of the experiment (default all)")
    parser.add_argument("--level", default="D_0")
    args = parser.parse_args(argv)
    experiment = load_experiment(args.experiment)
    (f1, z1), (f2, z2) = experiment.damping.ratios
    rayleigh = Rayleigh.from_ratios(f1, z1, f2, z2)
    motions = ground_motions(experiment, args.records, args.level)
    for element in args.element or ["S1", "3B"]:
        models = {m: modal_stresses(m, experiment, element) for m in ("M0", "M1")}
        print(f"\n{element}, {args.level}: the largest modal shares of the peak dynamic normal stress (SRSS)")
        for name, (ground, dt) in motions.items():
            result = {m: breakdown(*models[m], ground, dt, rayleigh) for m in models}
            ratio = result["M0"]["srss"] / result["M1"]["srss"]
            lead = {m: r["top"][0] for m, r in result.items()}
            sa = {m: spectral_acceleration(ground[:, DIRECTIONS.index(t["direction"])], dt, t["frequency"])
                  for m, t in lead.items()}
            print(f"  {name}: SRSS M0 {result['M0']['srss'] / 1e3:.0f} kPa, M1 {result['M1']['srss'] / 1e3:.0f} kPa, "
                  f"M0/M1 = {ratio:.2f}; Sa_{lead['M0']['direction']}({lead['M0']['frequency']:.2f} Hz) / "
                  f"Sa_{lead['M1']['direction']}({lead['M1']['frequency']:.2f} Hz) = {sa['M0'] / sa['M1']:.2f} "
                  "(5 %, each model's leading mode)")
            for m, r in result.items():
                parts = ", ".join(f"{t['mode']} {t['frequency']:.2f} Hz from {t['direction']} {t['share']:.0%}"
                                  for t in r["top"][:4])
                print(f"    {m}: {parts}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
