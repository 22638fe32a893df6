"""``bearingfw tune``: step 1 of the paper's tuning on the reference bridge (K_s from the measured modes).

Without ``--measured`` the measured modes are the paper's (Table 2, paired by label as the deck
sensors see them). With ``--measured FILE`` they are modes identified by ``bearingfw oma``
(frequencies and shapes at the sensor channels), paired with the model's by MAC at those DOFs;
:func:`bearingfw.bridges.study.calibrate_ks_to_identified` does the work (the screening by MAC,
the scan of K_s that starts the least squares, the sensitivities and the damping) and this
module prints it.
"""

from __future__ import annotations

import json
import sys

from bearingfw.parameters import ParameterError


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "tune",
        help="step 1 of the paper's tuning: the stick stiffness K_s from the measured frequencies",
        description="Step 1 of the paper's two-step tuning on the reference bridge: the SDOF estimate of the "
        "sliding bearings' stick stiffness K_s (eq. 11, with the untuned model's lateral frequency), then a "
        "least-squares fit of K_s in the M1 model (linear springs on the sliding directions) to the measured "
        "frequencies of Table 2, modes paired by label as the deck sensors see them. Also the measured damping "
        "(logarithmic decrements, damping ratios, Rayleigh coefficients). With --measured, the measured modes are "
        "those identified by 'bearingfw oma' (frequencies and shapes at the sensor channels), paired by MAC at those "
        "DOFs; the output then adds each mode's sensitivity d ln f / d ln K_s. Step 2 is the M2 model with K_s: "
        "'bearingfw modal --model M2 --ks K_S' or bearingfw.bridges.study.tuned_bridge(K_S).",
    )
    parser.add_argument(
        "--measured", metavar="FILE",
        help="identified modes (JSON written by 'bearingfw oma --json' or --output) instead of the paper's Table 2; "
        "their shapes are at channels named '<node>.<component>' of the reference bridge (e.g. 'GA32.uz')",
    )
    parser.add_argument(
        "--min-mac", type=float, default=None, metavar="M",
        help="with --measured: identified modes whose best MAC with a computed mode stays below M are left out and "
        "named (default 0.8)",
    )
    parser.add_argument(
        "--modes", metavar="LIST",
        help="with --measured: use only these identified modes, by number or name, comma-separated (default all)",
    )
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    parser.set_defaults(func=run)


def tune_data() -> dict:
    """The ``--json`` object: eq. 11, the fit, the frequencies before (untuned, M0) and after, MACs, damping."""
    from bearingfw.bridges import BridgeParameters
    from bearingfw.bridges.paper import KS_EQ11, KS_FIT, PILLAR_STIFFNESS, TABLE2_OMA, TABLE3_TUNED
    from bearingfw.bridges.study import calibrate_ks, ks_estimate, measured_damping, modes

    params = BridgeParameters()
    ks0, f_a = ks_estimate(params)
    report = calibrate_ks(params, initial=ks0)
    _, untuned = modes("M0", params)
    names = [m.name for m in report.measurements]

    def by_name(values):
        return {n: float(v) for n, v in zip(names, values, strict=True)}

    return {
        "ks_eq11": ks0,
        "ks_fit": report.values["ks"],
        "eq11": {"k_c": params.pillar_stiffness, "f_a": f_a, "f_b": TABLE2_OMA["lateral 1"]},
        "paper": {"ks_eq11": KS_EQ11, "ks_fit": KS_FIT, "k_c": PILLAR_STIFFNESS, "tuned": dict(TABLE3_TUNED)},
        "measured": by_name(report.after.measured),
        "before": by_name(untuned.frequencies),
        "after": by_name(report.after.frequencies),
        "error_before": by_name(untuned.errors),
        "error_after": by_name(report.errors_after),
        "calibration": report.to_dict(),
        "damping": measured_damping(),
    }


def _selection(text: str | None):
    if text is None:
        return None
    return [int(t) if t.strip().isdigit() else t.strip() for t in text.split(",") if t.strip()]


def measured_tune_data(path, select=None, min_mac: float | None = None) -> dict:
    """The ``--json`` object with ``--measured``: :func:`~bearingfw.bridges.study.calibrate_ks_to_identified`."""
    from bearingfw.bridges.study import IdentifiedTuning, calibrate_ks_to_identified
    from bearingfw.oma import read_modes

    options = IdentifiedTuning() if min_mac is None else IdentifiedTuning(min_mac=min_mac)
    fit = calibrate_ks_to_identified(read_modes(path), options, select)
    return {"measured_file": str(path), **fit.to_dict()}


def _print_measured(data: dict) -> None:
    print(f"Step 1: stick stiffness K_s of the sliding bearings from identified modes ({data['measured_file']})"
          + ("  [SYNTHETIC data]" if data["synthetic"] else ""))
    eq = data["eq11"]
    if eq:
        print(f"  eq. 11: K_c = {eq['k_c'] / 1e6:.0f} MN/m, f_a = {eq['f_a']:.3f} Hz (untuned), "
              f"f_b = {eq['f_b']:.3f} Hz ({eq['mode']}) -> K_s = {data['ks_eq11'] / 1e6:.0f} MN/m")
    else:
        print("  eq. 11: no identified mode pairs with the untuned model's first lateral mode; "
              "the paper's K_s joins the scan")
    cal = data["calibration"]
    grid = sorted(item["ks"] for item in data["scan"])
    print(f"  scan: {len(grid)} values of K_s from {grid[0]:.0e} to {grid[-1]:.0e} N/m (with eq. 11's); "
          f"the best, {data['ks_start'] / 1e6:.0f} MN/m, starts the least squares")
    print(f"  least squares: K_s = {data['ks_fit'] / 1e6:.1f} MN/m   "
          f"({cal['evaluations']} modal analyses, {cal['message']})")
    print(f"  {'mode':<10}{'measured':>10}{'before':>9}{'error':>8}{'after':>9}{'error':>8}{'MAC':>6}  "
          f"{'paired with':<14}{'dlnf/dlnKs':>10}")
    for name in data["measured"]:
        print(f"  {name:<10}{data['measured'][name]:10.4f}{data['before'][name]:9.4f}{data['error_before'][name]:8.2%}"
              f"{data['after'][name]:9.4f}{data['error_after'][name]:8.2%}{data['mac_after'][name]:6.2f}  "
              f"{data['label_after'][name]:<14}{data['sensitivity'][name]:10.4f}")
    print("  (Hz; before: the untuned model M0; after: M1 with the fitted K_s; paired by MAC at the sensor channels; "
          "dlnf/dlnKs at the fitted K_s: a frequency error e moves K_s by about e / dlnf/dlnKs)")
    ray = data["damping"].get("rayleigh")
    if ray and "alpha" in ray:
        print(f"  Rayleigh through the identified damping of vertical 1 and vertical 2: "
              f"alpha = {ray['alpha']:.3f} 1/s, beta = {ray['beta']:.5f} s")
    for warning in data["warnings"]:
        print(f"  warning: {warning}")
    print(f"Step 2: 'bearingfw modal --model M2 --ks {data['ks_fit']:.4g}' (regularized Coulomb, mu = 0.04)")


def _print(data: dict) -> None:
    eq = data["eq11"]
    paper = data["paper"]
    print("Step 1: stick stiffness K_s of the sliding bearings (reference bridge, model M1)")
    print(f"  eq. 11: K_c = {eq['k_c'] / 1e6:.0f} MN/m, f_a = {eq['f_a']:.3f} Hz (untuned), f_b = {eq['f_b']:.2f} Hz "
          f"(measured) -> K_s = {data['ks_eq11'] / 1e6:.0f} MN/m   (paper: {paper['ks_eq11'] / 1e6:.0f} MN/m)")
    cal = data["calibration"]
    print(f"  least squares: K_s = {data['ks_fit'] / 1e6:.0f} MN/m   (paper: {paper['ks_fit'] / 1e6:.0f} MN/m; "
          f"{cal['evaluations']} modal analyses, {cal['message']})")
    print(f"  {'mode':<12}{'measured':>10}{'before':>9}{'error':>8}{'after':>9}{'error':>8}{'paper tuned':>13}")
    for name in data["measured"]:
        print(f"  {name:<12}{data['measured'][name]:10.2f}{data['before'][name]:9.3f}{data['error_before'][name]:8.1%}"
              f"{data['after'][name]:9.3f}{data['error_after'][name]:8.1%}{paper['tuned'][name]:13.2f}")
    print("  (Hz; before: the untuned model M0; after: M1 with the fitted K_s, starting from the eq. 11 estimate)")
    names = list(data["measured"])
    for title, table in (("MAC before/after", cal["mac_before_after"]), ("AutoMAC after", cal["automac_after"])):
        if table is None:
            continue
        print(f"  {title} (deck):")
        for name, row in zip(names, table, strict=True):
            print(f"    {name:<12}" + " ".join(f"{v:5.2f}" for v in row))
    damping = data["damping"]
    for d, r in zip(damping["decrements"], damping["ratios"], strict=True):
        print(f"  damping at {d['frequency']:.2f} Hz: log decrement {d['decrement']:.2f} -> ratio {r['ratio']:.2%}")
    ray, paper_ray = damping["rayleigh"], damping["rayleigh_paper_ratios"]
    print(f"  Rayleigh through both: alpha = {ray['alpha']:.3f} 1/s, beta = {ray['beta']:.5f} s   (through the paper's "
          f"rounded 2.1 % and 2.7 %: alpha = {paper_ray['alpha']:.3f} 1/s, beta = {paper_ray['beta']:.5f} s)")
    print(f"Step 2: 'bearingfw modal --model M2 --ks {data['ks_fit']:.4g}' (regularized Coulomb, mu = 0.04)")


def run(args) -> int:
    from bearingfw.tuning import PairingError

    try:
        if args.measured:
            data = measured_tune_data(args.measured, _selection(args.modes), args.min_mac)
        else:
            if args.modes or args.min_mac is not None:
                raise ParameterError("--modes and --min-mac need identified modes: give --measured FILE")
            data = tune_data()
    except (ParameterError, PairingError, OSError) as exc:
        print(f"bearingfw tune: error: {exc}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(data, indent=2))
    else:
        (_print_measured if args.measured else _print)(data)
    return 0
