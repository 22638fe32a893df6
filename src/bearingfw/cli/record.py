"""``bearingfw record``: look at ground-motion records (``info``: peaks, PGA_H10, t_Ha, degree, spectra)."""

from __future__ import annotations

import argparse
import json
import textwrap

from bearingfw.parameters import ParameterError


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "record",
        help="inspect ground-motion records",
        description="Inspect ground-motion records: read files (PEER .AT2, NIED K-NET/KiK-net, CSV/whitespace columns, .npz, "
        "or any format a plugin registers) or generate the synthetic mining tremor.",
    )
    commands = parser.add_subparsers(dest="record_command", metavar="SUBCOMMAND")
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])

    info = commands.add_parser(
        "info",
        help="peaks, PGA_H10, t_Ha, Arias intensity, dominant frequencies, response spectra and intensity degree",
        description=textwrap.fill(
            "Print per-component peaks, Arias intensity and dominant frequency, the record's PGA_H10, t_Ha, "
            "horizontal Arias intensity and intensity degree, and the 5 % response spectrum (pseudo-spectral "
            "acceleration) of each component and of the horizontals (their geometric mean, what an Sa target "
            "scales) at T = " + ", ".join(f"{T:g}" for T in SPECTRUM_PERIODS) + " s. FILEs are read in the order "
            "horizontal 1, horizontal 2, vertical (three one-component files such as .AT2, or one file "
            "with three acceleration columns); or map one, two or three components to the axes with --x, --y, "
            "--z (a missing axis is zero; a component that looks vertical is refused on x or y). "
            "Accelerations are reported in m/s^2.",
            width=88,
        ),
        epilog="examples:\n"
        "  bearingfw record info RSN4843_CHUETSU_65006EW.AT2 RSN4843_CHUETSU_65006NS.AT2 RSN4843_CHUETSU_65006UD.AT2\n"
        "  bearingfw record info --x RSN4843_CHUETSU_65006EW.AT2 --y=-RSN4843_CHUETSU_65006NS.AT2 --period 0.5\n"
        "  bearingfw record info --x tremor.csv#1 --dt 0.005 --units cm/s^2 --target sa=2@0.5 --json\n"
        "  bearingfw record info tremor.csv --dt 0.005 --units cm/s^2 --json\n"
        "  bearingfw record info --synthetic 1 --plot figures/\n"
        "  bearingfw record info --synthetic 1 --level D_II --set-level D_II=0.5 --json\n"
        "\n"
        "A mapped component is FILE, FILE#k (the k-th component of a multi-component file, from 1) or\n"
        "-FILE (sign flipped; write it --x=-FILE so that it is not taken for an option).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    info.add_argument("files", nargs="*", metavar="FILE", help="record file(s): horizontal 1, horizontal 2, vertical")
    for axis, what in (("x", "global x (horizontal)"), ("y", "global y (horizontal)"), ("z", "global z (vertical, up)")):
        info.add_argument(
            f"--{axis}", metavar="[-]FILE[#k]", help=f"the component that drives {what}; instead of FILEs"
        )
    info.add_argument(
        "--vertical-as-horizontal", action="store_true",
        help="with --x/--y: accept a component that looks vertical (file name, PEER header, amplitudes) on x or y",
    )
    info.add_argument(
        "--target", metavar="TARGET",
        help="first scale the record to TARGET: as-recorded, a level (D_0 .. D_IV), pga_h10=VALUE, pga=VALUE "
        "(peak of the horizontal resultant) or sa=VALUE@PERIOD (Sa(T, 5 %%) of the horizontals' geometric mean); "
        "m/s^2 and s (not with --level)",
    )
    info.add_argument(
        "--period", type=float, action="append", default=[], metavar="SECONDS",
        help="also print Sa(T, 5 %%) of every component and of the horizontals at this period; repeatable "
        "(marked on the --plot spectrum)",
    )
    info.add_argument(
        "--synthetic", type=int, metavar="SEED",
        help="use the synthetic mining tremor with this seed (an integer >= 0) instead of files "
        "(not with --format, --dt, --units: they describe files)",
    )
    info.add_argument("--format", metavar="NAME", help="reader to use (default: chosen by file suffix; see 'bearingfw plugins')")
    info.add_argument(
        "--dt", type=float, metavar="SECONDS",
        help="time step for files that do not state one (no time column, header or '# dt:'); an error if a file "
        "states another",
    )
    info.add_argument(
        "--units", metavar="UNIT",
        help="units of the file values, g, m/s^2 or cm/s^2, for files that do not state them; an error if a file "
        "states other units (e.g. 'UNITS OF G' in an .AT2 header)",
    )
    info.add_argument("--scale", metavar="NAME", help="intensity scale (default: usb-pga-h10; see 'bearingfw plugins')")
    info.add_argument(
        "--level", metavar="LEVEL",
        help="first scale the record to the PGA_H10 of an intensity level D_0, D_I, D_II, D_III or D_IV "
        "(the paper's D_0 = 0.10 and D_II = 0.46 m/s^2; every value used is printed, 'levels' in --json); "
        "an error if its degree then differs",
    )
    info.add_argument(
        "--set-level", action="append", default=[], metavar="LEVEL=VALUE",
        help="with --level: change the PGA_H10 (m/s^2) of one level, e.g. --set-level D_II=0.5; repeat for "
        "several levels (each at most once; the levels must still increase from D_0 to D_IV)",
    )
    info.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    info.add_argument(
        "--plot", metavar="DIR",
        help="write acceleration histories, Fourier spectra, the intensity chart and the 5 %% response spectra "
        "to DIR (PNG and SVG)",
    )
    info.set_defaults(func=run_info)


#: Periods (s) of the response spectrum table of ``record info`` (and its ``--json``).
SPECTRUM_PERIODS = (0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0)


def _mapping(args) -> dict:
    return {axis: getattr(args, axis) for axis in ("x", "y", "z") if getattr(args, axis) is not None}


def _load(args):
    from bearingfw import motion

    mapping = _mapping(args)
    if args.vertical_as_horizontal and not mapping:
        raise ParameterError("--vertical-as-horizontal goes with --x/--y/--z (the components mapped to the axes)")
    if mapping:
        if args.files or args.synthetic is not None:
            raise ParameterError("give either FILEs, --x/--y/--z or --synthetic SEED, not several")
        return motion.load_directional(
            mapping, format=args.format, dt=args.dt, units=args.units, vertical_as_horizontal=args.vertical_as_horizontal
        )
    if args.synthetic is not None:
        if args.files:
            raise ParameterError("give either FILEs or --synthetic SEED, not both")
        file_options = [f"--{name}" for name in ("format", "dt", "units") if getattr(args, name) is not None]
        if file_options:
            raise ParameterError(
                f"{', '.join(file_options)} describe(s) record files; --synthetic SEED generates the record, "
                "so leave them out"
            )
        return motion.synthetic_tremor(args.synthetic)
    if not args.files:
        raise ParameterError("no record: give FILE(s), --x/--y/--z FILE or --synthetic SEED")
    return motion.read_record(args.files, format=args.format, dt=args.dt, units=args.units)


def _levels(args):
    """The intensity levels with the --set-level changes."""
    from bearingfw.motion import IntensityLevels

    if args.set_level and not (args.level or args.target):
        raise ParameterError("--set-level changes the levels that --level scales to; give --level as well")
    pairs = []
    for text in args.set_level:
        level, sep, value = text.partition("=")
        try:
            pairs.append((level.strip(), float(value)))
        except ValueError:
            sep = ""
        if not sep:
            raise ParameterError(f"--set-level expects LEVEL=VALUE (m/s^2), e.g. D_II=0.5, got {text!r}")
    return IntensityLevels.with_overrides(pairs)


def _periods(values) -> list[float]:
    for T in values:
        if not T > 0 or T != T or T == float("inf"):
            raise ParameterError(f"--period {T!r}: the period must be a finite number of seconds > 0")
    return list(values)


def info_data(record, scale, levels=None, periods=()) -> dict:
    """The ``--json`` object of ``record info`` (SI units: m/s^2, s, m/s, Hz).

    ``response_spectrum``: ``psa`` per role and ``horizontal`` (the geometric mean of the
    horizontals, :func:`bearingfw.motion.horizontal_spectrum`) at ``periods`` (default
    :data:`SPECTRUM_PERIODS`); ``sa``: the same at the ``--period`` values, if any.
    """
    from bearingfw.motion import DEFAULT_LEVELS, ROLES, horizontal_spectrum, record_degree, record_summary, response_spectrum

    summary = record_summary(record, periods=SPECTRUM_PERIODS)
    spectrum = summary["response_spectrum"]
    spectrum["horizontal"] = horizontal_spectrum(record, spectrum["periods"], spectrum["damping"]).tolist()
    data = {
        "source": record.title,
        "synthetic": record.synthetic,
        "files": list(record.metadata.get("files", [])),
        "dt": record.dt,
        "samples": record.n,
        "duration": record.duration,
        "units": record.units,
        "source_units": list(record.source_units),
        "names": list(record.names),
        "padded": list(record.padded_components),
        "resampled": list(record.resampled_components),
        "scale_factor": record.metadata.get("scale_factor", 1.0),
        "level": record.metadata.get("level"),
        "levels": (levels or DEFAULT_LEVELS).as_dict(),
        "pga_h10": summary["pga_h10"],
        "pga_h10_filter": summary["pga_h10_filter"],
        "t_ha": summary["t_ha"],
        "arias": summary["arias"],
        "degree": record_degree(record, scale),
        "scale": scale.name,
        "pga": summary["pga"],
        "components": summary["components"],
        "response_spectrum": spectrum,
        "notes": summary["notes"],
        "directions": dict(record.metadata.get("directions", {})),
        "missing": list(record.missing_directions),
        "target": record.metadata.get("target"),
    }
    if periods:
        periods = _periods(periods)
        data["sa"] = {
            "damping": spectrum["damping"],
            "periods": periods,
            "psa": {role: response_spectrum(values, record.dt, periods, spectrum["damping"]).psa.tolist()
                    for role, values in zip(ROLES, record.components)},
            "horizontal": horizontal_spectrum(record, periods, spectrum["damping"]).tolist(),
        }
    return data


def _print_spectrum(data: dict) -> None:
    spectrum = data["response_spectrum"]
    names = [c["name"] for c in data["components"]]
    print(f"Response spectrum: pseudo-spectral acceleration [m/s^2], {spectrum['damping']:.0%} damping")
    headers = ("T [s]", *names, "horizontal (geometric mean)")
    rows = [
        (f"{T:g}", *(f"{spectrum['psa'][c['role']][i]:.4g}" for c in data["components"]),
         f"{spectrum['horizontal'][i]:.4g}")
        for i, T in enumerate(spectrum["periods"])
    ]
    widths = [max(len(r[i]) for r in [headers, *rows]) for i in range(len(headers))]
    for row in [headers, *rows]:
        print("  " + "  ".join(cell.rjust(w) for cell, w in zip(row, widths)))
    if "sa" in data:
        sa = data["sa"]
        for i, T in enumerate(sa["periods"]):
            parts = ", ".join(f"{c['name']} {sa['psa'][c['role']][i]:.4g}" for c in data["components"])
            print(f"Sa(T = {T:g} s, {sa['damping']:.0%}) = {sa['horizontal'][i]:.4g} m/s^2 (horizontals' geometric "
                  f"mean); components: {parts}")


def _print_table(data: dict) -> None:
    print(f"Record: {data['source']}")
    if data["synthetic"]:
        print("  SYNTHETIC: generated by bearingfw (a mining tremor in kind), not a recording")
    units = ", ".join(sorted(set(data["source_units"])))
    print(f"  {data['samples']} samples at dt = {data['dt']:g} s ({data['duration']:.2f} s); "
          f"accelerations in m/s^2 (source units: {units})")
    if data["directions"]:
        mapped = ", ".join(f"{axis} = {text}" for axis, text in data["directions"].items())
        print(f"  components mapped to the axes: {mapped}" + (
            f"; {', '.join(data['missing'])}: zero" if data["missing"] else ""))
    if data["scale_factor"] != 1.0 or data["target"]:
        level = f" (to level {data['level']} = {data['levels'][data['level']]:g} m/s^2)" if data["level"] else ""
        target = f" (to {data['target']})" if data["target"] and not data["level"] else ""
        print(f"  scaled by {data['scale_factor']:.4g}{level}{target}")
    for c in data["components"]:
        if c["padded"]:
            print(f"  component {c['name']}: {c['samples']} samples, padded with zeros to {data['samples']}")
    for note in data["notes"]:
        print(f"  note: {note}")
    resampled = any(c["resampled"] for c in data["components"])
    headers = ("component", "peak [m/s^2]", "peak [g]", "Arias [m/s]", "dominant f [Hz]")
    if resampled:  # band-limited resampling changes peaks: show the file's too
        headers += ("peak before resampling [m/s^2]",)
    rows = []
    for c in data["components"]:
        row = (c["name"], f"{c['pga']:.4g}", f"{c['pga_g']:.4g}", f"{c['arias']:.4g}",
               "-" if c["dominant_frequency"] is None else f"{c['dominant_frequency']:.2f}")
        if resampled:
            row += (f"{c['pga_before_resampling']:.4g}",)
        rows.append(row)
    widths = [max(len(r[i]) for r in [headers, *rows]) for i in range(len(headers))]
    for row in [headers, *rows]:
        print("  " + "  ".join(cell.rjust(w) if i else cell.ljust(w) for i, (cell, w) in enumerate(zip(row, widths))))
    h10 = data["pga_h10_filter"]
    print(f"PGA_H10 = {data['pga_h10']:.4g} m/s^2  (resultant of both horizontals low-passed at {h10['cutoff_hz']:g} Hz: "
          f"order-{h10['order_per_pass']} Butterworth, forward and backward)")
    if data["t_ha"] is None:  # no horizontal motion (a vertical-only record): no Arias intensity to time
        t_ha, degree = "undefined  (no horizontal motion: 5-95 % of a zero Arias intensity)", "undefined  (no horizontal motion; "
    else:
        t_ha, degree = f"{data['t_ha']:.3g} s  (5-95 % of the horizontal Arias intensity)", f"{data['degree']}  ("
    print(f"t_Ha    = {t_ha}")
    print(f"Arias   = {data['arias']:.4g} m/s  (both horizontals)")
    print(f"Degree  = {degree}scale {data['scale']})")
    _print_spectrum(data)


def run_info(args) -> int:
    from bearingfw import motion

    # Errors propagate: bearingfw.cli.main gives each its message and exit status.
    if args.level and args.target:
        raise ParameterError("give either --level or --target, not both (--target D_II is --level D_II)")
    periods = _periods(args.period)
    record = _load(args)
    scale = motion.get_scale(args.scale)
    levels = _levels(args)
    if args.level:
        record = motion.scale_to_level(record, args.level, levels=levels, scale=scale)
    elif args.target:
        target = motion.parse_target(args.target, levels)
        if target.needs_period:
            raise ParameterError(f"--target {args.target}: T1 is a structure's first mode; give the period in s")
        record = motion.scale_record(record, target, scale)
    data = info_data(record, scale, levels, periods)
    written = []
    if args.plot:
        from bearingfw.motion.plot import write_figures

        written = write_figures(record, args.plot, scale=scale, marks=periods)
    if args.json:
        if written:
            data["figures"] = [str(p) for p in written]
        print(json.dumps(data, indent=2))
    else:
        _print_table(data)
        for path in written:
            print(f"wrote {path}")
    return 0
