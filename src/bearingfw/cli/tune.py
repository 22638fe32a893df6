"""``bearingfw tune``: step 1 of the paper's tuning on the reference bridge (K_s from the measured modes)."""

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
        "(logarithmic decrements, damping ratios, Rayleigh coefficients). Step 2 is the M2 model with K_s: "
        "'bearingfw modal --model M2 --ks K_S' or bearingfw.bridges.study.tuned_bridge(K_S).",
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
    try:
        data = tune_data()
    except (ParameterError, OSError) as exc:
        print(f"bearingfw tune: error: {exc}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(data, indent=2))
    else:
        _print(data)
    return 0
