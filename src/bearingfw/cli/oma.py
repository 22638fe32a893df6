"""``bearingfw oma``: modes identified from ambient accelerations (SSI-COV), or damping from a free decay."""

from __future__ import annotations

import argparse
import json
import math

from bearingfw.parameters import ParameterError


def _names(text: str | None) -> list[str] | None:
    return None if text is None else [n.strip() for n in text.split(",") if n.strip()]


def _frequencies(text: str) -> list[float]:
    """``--decay 1.5,3.36``: a comma-separated list (one argument, so FILE may follow it)."""
    expected = f"expected frequencies > 0 Hz separated by commas (e.g. 1.5,3.36), got {text!r}"
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(expected) from None
    if not values or not all(math.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(expected)
    return values


#: The defaults the help states; the options default to None, so that the library's defaults
#: (:class:`~bearingfw.oma.Criteria`, :class:`~bearingfw.oma.DecayFilter`, ``SSISettings``) apply
#: and the oma package is imported only when the command runs (a test checks these agree).
HELP_DEFAULTS = {
    "order": 60,
    "frequency": 0.02,
    "damping": 0.02,
    "mac": 0.9,
    "max_damping": 0.2,
    "min_fraction": 0.4,
    "min_presence": 0.8,
    "min_mpc": 0.8,
    "min_peak": 1.5,
    "relative_bandwidth": 0.2,
    "min_r2": 0.95,
}
#: Command-line option -> Criteria field.
CRITERIA_OPTIONS = {
    "frequency_tol": "frequency",
    "damping_tol": "damping",
    "mac": "mac",
    "max_damping": "max_damping",
    "fmin": "fmin",
    "fmax": "fmax",
    "min_fraction": "min_fraction",
    "min_presence": "min_presence",
    "min_mpc": "min_mpc",
    "min_peak": "min_peak",
}


def add_parser(subparsers) -> None:
    d = HELP_DEFAULTS
    parser = subparsers.add_parser(
        "oma",
        help="operational modal analysis: modes from ambient accelerations (SSI-COV), damping from a free decay",
        description="Identify natural frequencies, damping ratios and mode shapes from a multichannel ambient "
        "acceleration record (CSV with a header of channel names and a time column, or NPZ with one array per "
        "channel) by covariance-driven stochastic subspace identification: poles at every model order up to "
        "--order, the stabilisation criteria of the paper (2 % frequency, 2 % damping, 90 % MAC between orders) "
        "and an automatic selection of the modes (present at most orders from their first, real shapes, a peak in "
        "the averaged spectrum); rejected candidates are listed with the reason. Name channels "
        "'<node>.<component>' (e.g. 'GA32.uz') so that 'bearingfw tune --measured' can pair the modes with a "
        "model's by MAC at those DOFs; with --structure those names are checked against the model's DOFs first. "
        "With --decay, instead the logarithmic decrement of the free decay after a "
        "jumping test, per channel and averaged.",
    )
    parser.add_argument("file", metavar="FILE", help="multichannel acceleration file (.csv or .npz)")
    parser.add_argument(
        "--order",
        type=int,
        default=None,
        metavar="N",
        help=f"largest model order, even (default {d['order']}; the paper's was 30). A warning says "
        "when the top orders still add modes",
    )
    parser.add_argument(
        "--block-rows",
        type=int,
        default=None,
        metavar="I",
        help="block rows of the Toeplitz matrix (default: 40, or more if order / references needs them)",
    )
    parser.add_argument(
        "--fmin", type=float, default=None, metavar="HZ", help="lowest frequency of interest (default 0)"
    )
    parser.add_argument(
        "--fmax",
        type=float,
        default=None,
        metavar="HZ",
        help="highest frequency of interest, read off the spectrum (e.g. above the modes to be calibrated); the "
        "record is low-passed and resampled to 2.5 fmax first (default: up to the Nyquist frequency)",
    )
    parser.add_argument(
        "--frequency-tol",
        type=float,
        default=None,
        metavar="R",
        help=f"stable: relative frequency change between orders at most R (default {d['frequency']:g})",
    )
    parser.add_argument(
        "--damping-tol",
        type=float,
        default=None,
        metavar="R",
        help=f"stable: relative damping change between orders at most R (default {d['damping']:g})",
    )
    parser.add_argument(
        "--mac",
        type=float,
        default=None,
        metavar="M",
        help=f"stable: MAC between orders at least M (default {d['mac']:g})",
    )
    parser.add_argument(
        "--max-damping",
        type=float,
        default=None,
        metavar="ZETA",
        help=f"largest physical damping ratio (default {d['max_damping']:g})",
    )
    parser.add_argument(
        "--min-fraction",
        type=float,
        default=None,
        metavar="R",
        help="a mode must be stable (frequency and shape) at this share of the orders compared "
        f"(default {d['min_fraction']:g})",
    )
    parser.add_argument(
        "--min-presence",
        type=float,
        default=None,
        metavar="R",
        help="a mode must be present at this share of the orders from its first appearance to the top "
        f"(default {d['min_presence']:g}: noise poles come and go)",
    )
    parser.add_argument(
        "--min-mpc",
        type=float,
        default=None,
        metavar="R",
        help=f"least modal phase collinearity of a mode's shape (default {d['min_mpc']:g}: real shapes)",
    )
    parser.add_argument(
        "--min-peak",
        type=float,
        default=None,
        metavar="R",
        help="least prominence (a ratio) of the averaged spectrum's peak at a mode, more on short records "
        f"(default {d['min_peak']:g}; 0: no peak check)",
    )
    from bearingfw.structures import OPTION_HELP

    parser.add_argument(
        "--structure", metavar="SPEC",
        help="the structure the sensors were on: 'package.module:function', 'path/to/file.py:function' or "
        "'reference' (as 'bearingfw modal --structure'); every channel analysed must then name one of its DOFs "
        "('<node>.<component>'), checked before the identification (default: no check)",
    )
    parser.add_argument("--option", action="append", default=[], metavar="KEY=VALUE", help=OPTION_HELP)
    parser.add_argument("--channels", metavar="A,B,...", help="use only these channels (default all)")
    parser.add_argument("--references", metavar="A,B,...", help="reference channels of the correlations (default all)")
    parser.add_argument("--dt", type=float, default=None, metavar="S", help="time step, if the file states none")
    parser.add_argument("--units", default=None, help="units, if the file states none (default taken as m/s^2)")
    parser.add_argument(
        "--decay",
        type=_frequencies,
        default=None,
        metavar="HZ[,HZ...]",
        help="free-decay mode: logarithmic decrements at these frequencies (comma-separated, e.g. 1.5,3.36) "
        "instead of SSI",
    )
    parser.add_argument(
        "--bandwidth",
        type=float,
        default=None,
        metavar="HZ",
        help=f"--decay: band-pass width (default {d['relative_bandwidth'] * 100:.0f} %% of each frequency). "
        "The paper's "
        "0.04 Hz works too, but passes a 2-3 %% mode at a tenth of its amplitude or less while noise falls only "
        "as the square root of the band: the wider default keeps the decay clear of the noise (the start is "
        "always found with at least the default band, as a narrower one rings for longer than the mode decays)",
    )
    parser.add_argument(
        "--start",
        type=float,
        default=None,
        metavar="S",
        help="--decay: time the excitation stopped (default: found from the record)",
    )
    parser.add_argument(
        "--min-r2",
        type=float,
        default=None,
        metavar="R",
        help=f"--decay: least r^2 of the straight line through ln(peak) (default {d['min_r2']:g})",
    )
    parser.add_argument("--output", "-o", metavar="PATH", help="write the identified modes (JSON) to PATH")
    parser.add_argument("--plot", metavar="DIR", help="write the stabilisation diagram (or the decays) to DIR")
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    parser.set_defaults(func=run)


def check_structure(args, names) -> dict | None:
    """With ``--structure``: every channel names a DOF of the structure's model (an unknown one is an
    error naming it and the nearest names); channels at supported DOFs, which read the ground and can
    never pair with a mode, are warned about. None without ``--structure``."""
    if args.structure is None:
        if args.option:
            raise ParameterError("--option gives options to a structure: give --structure SPEC too")
        return None
    from bearingfw.model import as_system
    from bearingfw.oma import channel_dofs
    from bearingfw.structures import build_structure, parse_options
    from bearingfw.tuning import check_channels

    options = parse_options(args.option)
    model = build_structure(args.structure, options)
    check_channels(model, names)
    system = as_system(model)
    still = system.T.getnnz(axis=1)[channel_dofs(system, names)] == 0
    supported = [n for n, s in zip(names, still, strict=True) if s]
    warnings = []
    if supported:
        warnings.append(
            f"channel(s) {', '.join(supported)} are at supported DOFs of {model.name or 'the model'}: they read the "
            "ground, and 'bearingfw tune' refuses shapes there (leave them out with --channels)"
        )
    return {"structure": {"spec": args.structure, "options": options, "model": model.name}, "warnings": warnings}


def identify_data(args) -> tuple[dict, object, object]:
    """The ``--json`` object of an identification, the result and the channels read."""
    from bearingfw.oma import Criteria, SSISettings, identify, read_channels

    channels = read_channels(args.file, dt=args.dt, units=args.units)
    wanted = _names(args.channels)
    if wanted:
        channels = channels.select(wanted)
    checked = check_structure(args, channels.names)  # before the identification: a wrong name fails at once
    order = {} if args.order is None else {"max_order": args.order}
    settings = SSISettings(**order, block_rows=args.block_rows)
    given = {field: getattr(args, option) for option, field in CRITERIA_OPTIONS.items()}
    criteria = Criteria(**{k: v for k, v in given.items() if v is not None})
    result = identify(channels, settings, criteria, references=_names(args.references))
    data = result.to_dict()
    if checked is not None:
        data["structure"] = checked["structure"]
        data["warnings"] = [*checked["warnings"], *data["warnings"]]
    if channels.metadata.get("note"):
        data["note"] = channels.metadata["note"]
    return data, result, channels


def decay_data(args) -> tuple[dict, list, object]:
    """The ``--json`` object of ``--decay``: per frequency, each channel's decrement and the average."""
    from bearingfw.analysis.damping import damping_ratio_from_log_decrement, rayleigh_from_ratios
    from bearingfw.oma import DecayFilter, log_decrement, read_channels

    channels = read_channels(args.file, dt=args.dt, units=args.units)
    wanted = _names(args.channels)
    if wanted:
        channels = channels.select(wanted)
    check_structure(args, channels.names)
    spec = DecayFilter(bandwidth=args.bandwidth, **({} if args.min_r2 is None else {"min_r2": args.min_r2}))
    out, fits = [], []
    for frequency in args.decay:
        per_channel, failed = {}, {}
        for j, name in enumerate(channels.names):
            try:
                fit = log_decrement(channels.data[:, j], channels.dt, frequency, spec, start=args.start)
            except ParameterError as exc:
                failed[name] = str(exc)
                continue
            per_channel[name] = fit.to_dict()
            fits.append((frequency, name, fit))
        if not per_channel:
            raise ParameterError(f"--decay {frequency:g}: no channel gives a decay ({next(iter(failed.values()))})")
        mean = sum(d["decrement"] for d in per_channel.values()) / len(per_channel)
        out.append(
            {
                "frequency": frequency,
                "damped_frequency": sum(d["damped_frequency"] for d in per_channel.values()) / len(per_channel),
                "decrement": mean,
                "damping": damping_ratio_from_log_decrement(mean),
                "channels": per_channel,
                "failed": failed,
            }
        )
    data = {
        "source": channels.source,
        "synthetic": channels.synthetic,
        "filter": {
            "type": "butterworth band-pass, backward in time (anti-causal)",
            "order": spec.order,
            "bandwidth": args.bandwidth,
            "relative_bandwidth": None if args.bandwidth else spec.relative_bandwidth,
            "min_r2": spec.min_r2,
            "settle": spec.settle,
        },
        "decays": out,
    }
    if len(out) >= 2:
        try:
            alpha, beta = rayleigh_from_ratios(
                out[0]["frequency"], out[0]["damping"], out[1]["frequency"], out[1]["damping"]
            )
            data["rayleigh"] = {"alpha": alpha, "beta": beta}
        except ParameterError as exc:
            data["rayleigh"] = {"error": str(exc)}
    return data, fits, channels


def _print_modes(data: dict) -> None:
    ssi = data["ssi"]
    print(f"Operational modal analysis (SSI-COV): {data['source']}" + ("  [SYNTHETIC]" if data["synthetic"] else ""))
    print(
        f"  {len(data['channels'])} channels, {data['duration']:.1f} s at dt = {data['dt']:g} s"
        + (f" (analysed at {data['dt_analysed']:g} s)" if data["dt_analysed"] != data["dt"] else "")
        + f"; orders 2..{ssi['max_order']}, {ssi['block_rows']} block rows"
    )
    crit = data["criteria"]
    print(
        f"  stable: frequency change <= {crit['frequency']:.1%}, damping change <= {crit['damping']:.1%}, "
        f"MAC >= {crit['mac']:.0%}; poles: " + ", ".join(f"{k} {v}" for k, v in data["pole_counts"].items())
    )
    if data.get("note"):
        print(f"  note: {data['note']}")
    print(f"  {'mode':<9}{'f [Hz]':>9}{'+-':>8}{'zeta':>8}{'+-':>8}{'poles':>7}{'MPC':>6}  largest components")
    for m in data["modes"]:
        top = sorted(m["shape"].items(), key=lambda kv: -abs(kv[1]))[:3]
        print(
            f"  {m['name']:<9}{m['frequency']:9.4f}{m['frequency_std']:8.4f}{m['damping']:8.2%}{m['damping_std']:8.2%}"
            f"{m['poles']:7d}{m['mpc']:6.2f}  " + ", ".join(f"{c} {v:+.2f}" for c, v in top)
        )
    if not data["modes"]:
        print("  no modes: see the rejected candidates; try a higher --order, a band (--fmax), or looser criteria")
    # The near misses only: a noisy record has dozens of clusters failing most checks.
    near = [r for r in data["rejected"] if r["poles"] >= 2 and len(r["reasons"]) <= 2]
    if near:
        print(f"  near misses ({len(near)} of {len(data['rejected'])} rejected candidates; --json lists all):")
        for r in near:
            print(f"    {r['frequency']:9.4f} Hz  {r['poles']:3d} poles  " + "; ".join(r["reasons"]))
    for warning in data["warnings"]:
        print(f"  warning: {warning}")


def _print_decays(data: dict) -> None:
    print(f"Free decay: {data['source']}" + ("  [SYNTHETIC]" if data["synthetic"] else ""))
    for d in data["decays"]:
        print(
            f"  band at {d['frequency']:g} Hz: log decrement {d['decrement']:.3f} -> damping ratio {d['damping']:.2%}, "
            f"damped frequency {d['damped_frequency']:.3f} Hz (mean of {len(d['channels'])} channel(s))"
        )
        for name, c in d["channels"].items():
            print(
                f"    {name:<14} delta {c['decrement']:.3f}  zeta {c['damping']:.2%}  "
                f"f_d {c['damped_frequency']:.3f} Hz  "
                f"{c['peaks']} peaks {c['start']:.1f}-{c['end']:.1f} s  r2 {c['r2']:.3f}"
            )
        for name, why in d["failed"].items():
            print(f"    {name:<14} no decay: {why}")
    if "rayleigh" in data and "alpha" in data["rayleigh"]:
        r = data["rayleigh"]
        print(f"  Rayleigh through the first two: alpha = {r['alpha']:.3f} 1/s, beta = {r['beta']:.5f} s")


def run(args) -> int:
    # Errors propagate: bearingfw.cli.main gives each its message and exit status.
    written = []
    if args.decay:
        data, fits, channels = decay_data(args)
        if args.plot:
            from bearingfw.oma.plot import plot_decay
            from bearingfw.plotting import save

            for frequency, name, fit in fits:
                stem = f"decay-{frequency:g}Hz-{name}".replace("/", "_")
                written += save(plot_decay(fit, channels.dt, name, channels.synthetic), args.plot, stem)
    else:
        data, result, channels = identify_data(args)
        if args.output:
            from bearingfw.oma import write_modes

            written.append(write_modes(result.modes, args.output))
        if args.plot:
            from bearingfw.oma.plot import plot_stabilisation
            from bearingfw.plotting import save

            written += save(plot_stabilisation(result), args.plot, "stabilisation")
    if args.json:
        if written:
            data["files"] = [str(p) for p in written]
        print(json.dumps(data, indent=2))
        return 0
    (_print_decays if args.decay else _print_modes)(data)
    for path in written:
        print(f"wrote {path}")
    return 0
