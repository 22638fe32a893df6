"""``bearingfw tune``: step 1 of the paper's tuning on the reference bridge (K_s from the measured modes),
or the calibration of any named parameters of a user's structure (``--structure``, ``--param``).

Without ``--measured`` the measured modes are the paper's (Table 2, paired by label as the deck
sensors see them). With ``--measured FILE`` they are modes identified by ``bearingfw oma``
(frequencies and shapes at the sensor channels), paired with the model's by MAC at those DOFs;
:func:`bearingfw.bridges.study.calibrate_ks_to_identified` does the work (the screening by MAC,
the scan of K_s that starts the least squares, the sensitivities and the damping) and this
module prints it.

With ``--structure SPEC`` (and ``--option``) or ``--param``: :func:`bearingfw.tuning.fit_parameters`
on the structure's builder, its keyword parameters ``--param NAME=LOW:HIGH[:START]`` against the
measured-modes file of :mod:`bearingfw.tuning.measured` (the format is in :data:`EPILOG`).
"""

from __future__ import annotations

import json

from bearingfw.parameters import ParameterError


#: The measured-modes file, as ``bearingfw tune --help`` shows it (:mod:`bearingfw.tuning.measured`).
EPILOG = """\
your structure:
  bearingfw tune --structure small_bridge.py:build --param bearing_stiffness=1e7:1e10 --measured modes.json
  calibrates the keyword parameters --param NAME=LOW:HIGH[:START] of the structure's function (START
  default: the function's default if within the bounds, else the middle of the range, geometric for a
  positive one) within their bounds, searched in log(p) when LOW > 0. --option fixes other keywords.
  Reported: the frequencies before (at START) and after with their errors, the MAC of each pair and
  the MAC table (measured x paired computed shapes), and the sensitivities d ln f / d ln p at the optimum.
  A parameter the function declares an int cannot be calibrated (fix it with --option). Without
  --structure, the reference bridge: --param ks=LOW:HIGH needs a bearing model with K_s, e.g.
  --option preset=M1 (linear springs; the default M0 has none and is refused).

the measured-modes file (--measured): the output of 'bearingfw oma --json' / --output, or TOML
(.toml) or JSON (any other name) written by hand:

  source = "ambient test, 3 May"           # optional
  channels = ["G4.uz", "G12.uz", "G4.ux"]  # optional: the order of shapes given as arrays
  [[modes]]
  name = "first bending"       # optional (default: the label, else "mode <k>")
  frequency = 2.55             # Hz, required
  label = "vertical 1"         # optional: the k-th computed mode with that label
  damping = 0.021              # optional damping ratio, 0 <= damping < 1 (reported)
  shape = { "G4.uz" = 1.0, "G12.uz" = -0.98, "G4.ux" = 0.02 }   # optional: at "<node>.<component>"

  Every mode with a shape (at the same channels): paired by MAC there, one-to-one, and modes whose
  best MAC stays below --min-mac are left out and named. Otherwise every mode with a label (vertical,
  lateral, longitudinal, torsional and k, as 'bearingfw modal --structure' labels the modes; each
  label once): paired by label. Never by index. Frequencies in Hz (a fit that stays more than 10 %
  off is warned about: rad/s is 6.28 times Hz).
"""


def add_parser(subparsers) -> None:
    import argparse
    import textwrap

    from bearingfw.structures import OPTION_HELP, STRUCTURE_HELP

    parser = subparsers.add_parser(
        "tune",
        help="calibrate a model against measured modes: the paper's K_s, or any parameter of your structure",
        # the epilog's file example keeps its lines (a raw formatter), so the description is wrapped here
        description=textwrap.fill("Step 1 of the paper's two-step tuning on the reference bridge: the SDOF estimate of the "
        "sliding bearings' stick stiffness K_s (eq. 11, with the untuned model's lateral frequency), then a "
        "least-squares fit of K_s in the M1 model (linear springs on the sliding directions) to the measured "
        "frequencies of Table 2, modes paired by label as the deck sensors see them, with K_s at most the paper's "
        "400 MN/m (--ks-max): the paper's fit stopped there because its first vertical frequency rose too much, and "
        "this model's hardly moves with K_s, so the stop is an explicit bound; the fit without it is printed too. "
        "The bounded value is the K_s of the default study and of 'bearingfw modal'. Also the measured damping "
        "(logarithmic decrements, damping ratios, Rayleigh coefficients). With --measured, the measured modes are "
        "those identified by 'bearingfw oma' (frequencies and shapes at the sensor channels), paired by MAC at those "
        "DOFs; the output then adds each mode's sensitivity d ln f / d ln K_s. Step 2 is the M2 model with K_s: "
        "'bearingfw modal --model M2 --ks K_S' or bearingfw.bridges.study.tuned_bridge(K_S). "
        "With --structure and --param: any keyword parameters of your structure against a measured-modes file "
        "(below).", width=100),
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--measured", metavar="FILE",
        help="identified modes (JSON written by 'bearingfw oma --json' or --output) instead of the paper's Table 2; "
        "their shapes are at channels named '<node>.<component>' of the reference bridge (e.g. 'GA32.uz'); with "
        "--structure, a measured-modes file (below)",
    )
    parser.add_argument("--structure", metavar="SPEC", help=STRUCTURE_HELP)
    parser.add_argument("--option", action="append", default=[], metavar="KEY=VALUE", help=OPTION_HELP)
    parser.add_argument(
        "--param", action="append", default=[], metavar="NAME=LOW:HIGH[:START]",
        help="a keyword parameter of the structure's function to calibrate within [LOW, HIGH], repeatable",
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
    parser.add_argument(
        "--n-modes", type=int, default=None, metavar="N",
        help="with --structure: modes computed per trial (default 20); every measured mode must be among them",
    )
    parser.add_argument(
        "--scan", type=int, default=None, metavar="N",
        help="with --structure: values of each parameter over its bounds tried for the start of the least squares "
        "(default 9; 0: start at START)",
    )
    parser.add_argument(
        "--ks-max", type=float, default=None, metavar="N/M",
        help="without --measured and --structure: the upper bound of K_s in step 1 (default 4e8, the paper's stop: "
        "its fit ended where the first vertical frequency rose too much; 1e11 leaves the fit unbounded)",
    )
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    parser.set_defaults(func=run)


def tune_data(ks_max: float | None = None) -> dict:
    """The ``--json`` object: eq. 11, the fit, the frequencies before (untuned, M0) and after, MACs, damping.

    Step 1 as the paper did it (:func:`bearingfw.bridges.study.calibrate_ks_as_paper`): the least
    squares with K_s at most ``ks_max`` (default the paper's stop, 400 MN/m), and without the bound.
    ``ks`` (= ``ks_fit``) is the bounded value, the one step 2 and the default study use when
    ``ks_max`` is the default; ``ks_source`` says where it comes from; ``constraint`` has the
    unbounded value and each mode's frequency at both.
    """
    from bearingfw.bridges import DEFAULT_KS, KS_SOURCE, BridgeParameters
    from bearingfw.bridges.paper import KS_EQ11, KS_FIT, PILLAR_STIFFNESS, TABLE2_OMA, TABLE3_TUNED
    from bearingfw.bridges.study import (
        KS_BOUNDS, KS_PAPER_BOUND, calibrate_ks_as_paper, ks_estimate, measured_damping, modes,
    )

    params = BridgeParameters()
    ks0, f_a = ks_estimate(params)
    bound = KS_PAPER_BOUND if ks_max is None else ks_max
    if not (isinstance(bound, (int, float)) and KS_BOUNDS[0] < bound <= KS_BOUNDS[1]):
        raise ParameterError(f"--ks-max must be within ({KS_BOUNDS[0]:g}, {KS_BOUNDS[1]:g}] N/m, got {bound!r}")
    step1 = calibrate_ks_as_paper(params, bound=bound, initial=ks0)
    report = step1.constrained
    _, untuned = modes("M0", params)
    names = [m.name for m in report.measurements]

    def by_name(values):
        return {n: float(v) for n, v in zip(names, values, strict=True)}

    if step1.ks == DEFAULT_KS:
        source = KS_SOURCE
    else:
        source = (f"step 1 with --ks-max {bound:g}: the least squares against Table 2 with K_s at most {bound:g} N/m "
                  f"(not the default study's {DEFAULT_KS:g} N/m: run it with ks = {step1.ks:.4g} on its models)")
    return {
        "ks": step1.ks,
        "ks_source": source,
        "constraint": step1.to_dict(),
        "ks_eq11": ks0,
        "ks_fit": step1.ks,
        "ks_study": DEFAULT_KS,
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
          f"({_analyses(cal['evaluations'])}, {cal['message']})")
    print(f"  {'mode':<10}{'measured':>10}{'before':>9}{'error':>8}{'after':>9}{'error':>8}{'MAC':>7}  "
          f"{'paired with':<14}{'dlnf/dlnKs':>10}")
    for name in data["measured"]:
        print(f"  {name:<10}{data['measured'][name]:10.4f}{data['before'][name]:9.4f}{data['error_before'][name]:8.2%}"
              f"{data['after'][name]:9.4f}{data['error_after'][name]:8.2%}{data['mac_after'][name]:7.3f}  "
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
    c = data["constraint"]
    print(f"  least squares with K_s <= {c['bound'] / 1e6:.0f} MN/m: K_s = {data['ks_fit'] / 1e6:.0f} MN/m"
          + (" (on the bound)" if c["active"] else "")
          + f"   (paper: {paper['ks_fit'] / 1e6:.0f} MN/m; {_analyses(cal['evaluations'])}, {cal['message']})")
    f1, fl = "vertical 1", "lateral 1"
    print(f"  without the bound: K_s = {c['ks_unbounded'] / 1e6:.0f} MN/m, where vertical 1 moves by "
          f"{c['change'][f1]:+.1%} ({c['frequencies_bounded'][f1]:.3f} -> {c['frequencies_unbounded'][f1]:.3f} Hz) and "
          f"lateral 1 by {c['change'][fl]:+.1%} ({c['frequencies_bounded'][fl]:.3f} -> "
          f"{c['frequencies_unbounded'][fl]:.3f} Hz); sum of squared errors {c['sum_squares_bounded']:.4f} -> "
          f"{c['sum_squares_unbounded']:.4f}")
    print(f"  the bound: {c['reason']}")
    print(f"  {'deck mode':<12}{'measured':>10}{'before':>9}{'error':>8}{'after':>9}{'error':>8}{'paper tuned':>13}")
    for name in data["measured"]:
        print(f"  {name:<12}{data['measured'][name]:10.2f}{data['before'][name]:9.3f}{data['error_before'][name]:8.1%}"
              f"{data['after'][name]:9.3f}{data['error_after'][name]:8.1%}{paper['tuned'][name]:13.2f}")
    print("  (Hz; before: the untuned model M0; after: M1 with the fitted K_s, starting from the eq. 11 estimate; "
          "deck modes numbered as the deck sensors see them: 'lateral 1' is the deck's, 2.3 Hz, not the arches' "
          "sway at 0.94 Hz, see bearingfw.bridges.study.mode_labels)")
    names = list(data["measured"])
    tables = (("MAC at eq. 11's K_s / after", cal["mac_start_after"]), ("AutoMAC after", cal["automac_after"]))
    for title, table in tables:
        if table is None:
            continue
        print(f"  {title} (deck):")
        for name, row in zip(names, table, strict=True):
            print(f"    {name:<12}" + " ".join(f"{v:6.3f}" for v in row))
    damping = data["damping"]
    for d, r in zip(damping["decrements"], damping["ratios"], strict=True):
        print(f"  damping at {d['frequency']:.2f} Hz: log decrement {d['decrement']:.2f} -> ratio {r['ratio']:.2%}")
    ray, paper_ray = damping["rayleigh"], damping["rayleigh_paper_ratios"]
    print(f"  Rayleigh through both: alpha = {ray['alpha']:.3f} 1/s, beta = {ray['beta']:.5f} s   (through the paper's "
          f"rounded 2.1 % and 2.7 %: alpha = {paper_ray['alpha']:.3f} 1/s, beta = {paper_ray['beta']:.5f} s)")
    study = "the default study's K_s" if data["ks"] == data["ks_study"] else (
        f"not the default study's {data['ks_study'] / 1e6:.0f} MN/m")
    print(f"K_s = {data['ks'] / 1e6:.0f} MN/m ({study}); source: {data['ks_source']}")
    print(f"Step 2: 'bearingfw modal --model M2 --ks {data['ks_fit']:.4g}' (regularized Coulomb, mu = 0.04)")


def _analyses(count: int) -> str:
    return f"{count} modal analys{'is' if count == 1 else 'es'}"


def parse_param(
    text: str, keywords: dict | None = None, takes_any: bool = False
) -> tuple[str, tuple[float, float, float]]:
    """``"NAME=LOW:HIGH[:START]"`` -> ``(NAME, (START, LOW, HIGH))``.

    START defaults to the builder's default for NAME (``keywords``: the keywords the builder names,
    :func:`bearingfw.structures.builder_signature`) when it is a number within the bounds, else the
    middle of the range (geometric for ``LOW > 0``). A NAME the builder does not name is an error
    unless it ``takes_any`` keyword (``**kwargs``).
    """
    import difflib
    import math

    expected = f"--param {text!r}: expected NAME=LOW:HIGH or NAME=LOW:HIGH:START (numbers, e.g. k=1e7:1e10)"
    name, eq, bounds = text.partition("=")
    name = name.strip()
    if not eq or not name.isidentifier():
        raise ParameterError(expected)
    parts = bounds.split(":")
    if len(parts) not in (2, 3):
        raise ParameterError(expected)
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ParameterError(expected) from None
    if not all(math.isfinite(v) for v in values):
        raise ParameterError(f"--param {text!r}: the bounds and start must be finite")
    low, high = values[:2]
    if not low < high:
        raise ParameterError(f"--param {text!r}: LOW < HIGH is needed, got LOW = {low:g}, HIGH = {high:g}")
    if keywords is not None and name not in keywords and not takes_any:
        near = difflib.get_close_matches(name, list(keywords), n=3)
        raise ParameterError(
            f"--param {text!r}: the structure's function has no parameter {name!r}"
            + (f" (did you mean {', '.join(near)}?)" if near else "")
            + f"; it takes {', '.join(keywords) or 'none'}"
        )
    if len(values) == 3:
        start = values[2]
        if not low <= start <= high:
            raise ParameterError(f"--param {text!r}: START = {start:g} is outside [{low:g}, {high:g}]")
    else:
        default = None if keywords is None else keywords.get(name)
        numeric = isinstance(default, (int, float)) and not isinstance(default, bool)
        if numeric and low <= default <= high:
            start = float(default)
        else:
            start = math.sqrt(low * high) if low > 0 else 0.5 * (low + high)
    return name, (start, low, high)


def _whole_number(builder, name: str, default) -> str | None:
    """``"annotated"`` if ``builder`` declares ``name`` an ``int``, ``"default"`` if only its default is one."""
    import inspect

    try:
        annotation = inspect.signature(builder).parameters[name].annotation
    except (KeyError, TypeError, ValueError):
        annotation = inspect.Parameter.empty
    if annotation in (int, "int"):
        return "annotated"
    if annotation is inspect.Parameter.empty and isinstance(default, int) and not isinstance(default, bool):
        return "default"
    return None


def structure_tune_data(
    spec: str, options: dict, params: list[str], measured_path, select=None, *, min_mac=None, n_modes=None, scan=None,
    base_dir=None, origins: dict | None = None,
) -> dict:
    """The ``--json`` object of ``tune --structure``: :func:`bearingfw.tuning.fit_parameters` on ``spec``'s builder.

    ``origins``: how the user gave each option (:func:`bearingfw.structures.option_origins`), for messages.
    """
    import difflib

    from bearingfw.structures import REFERENCE, build_structure, builder_signature, load_builder, reference_ignores
    from bearingfw.tuning import FitOptions, fit_parameters, read_measured

    if not params:
        raise ParameterError("--structure: give the parameters to calibrate, --param NAME=LOW:HIGH[:START]")
    if not measured_path:
        raise ParameterError("--structure: give the measured modes, --measured FILE (see 'bearingfw tune --help')")
    builder = load_builder(spec, base_dir=base_dir)
    keywords, takes_any = builder_signature(builder)
    variables = {}
    notes = []  # warnings of the command line, before the fit's own
    for text in params:
        name, bounds = parse_param(text, keywords, takes_any)
        if name in variables:
            raise ParameterError(f"--param {name}: given twice")
        if name in options:
            raise ParameterError(f"--param {name} and --option {name}=...: a parameter is either fixed or calibrated")
        whole = _whole_number(builder, name, keywords.get(name))
        if whole == "annotated":
            raise ParameterError(
                f"--param {name}: the structure's function declares {name} an integer, and a calibration moves a "
                f"parameter continuously between LOW and HIGH; fix it with --option {name}=N and calibrate a "
                "real-valued parameter"
            )
        if whole == "default":
            notes.append(f"--param {name}: its default is a whole number ({keywords[name]}); the calibration gives it "
                         "real values between LOW and HIGH")
        if name not in keywords:  # a **kwargs builder takes it, whatever it is: a typo would change nothing
            near = difflib.get_close_matches(name, list(keywords), n=3)
            notes.append(f"--param {name}: the structure's function does not name a parameter {name!r} (it takes "
                         "any keyword): check its spelling" + (f" (did you mean {', '.join(near)}?)" if near else ""))
        variables[name] = bounds
    given = {"min_mac": min_mac, "n_modes": n_modes, "scan_points": scan}
    fit_options = FitOptions(**{k: v for k, v in given.items() if v is not None})
    measured = read_measured(measured_path).select(select)
    if min_mac is not None and measured.pair_by == "label":
        notes.append(f"--min-mac {min_mac:g} does nothing here: the measured modes have no shapes, so they are paired "
                     "by label, not by MAC")
    # the start first, checked (the bearing laws too): a refused value names the option or --param that gave it
    start = {name: bounds[0] for name, bounds in variables.items()}
    origins = {**(origins or {}), **{n: f"--param {n} = {v:g} (START)" for n, v in start.items()}}
    model = build_structure(spec, {**options, **start}, base_dir=base_dir, check=True, origins=origins)
    if spec == REFERENCE:
        for name in variables:
            preset = reference_ignores(options, name)
            if preset is not None:
                hint = " (the paper's step 1: --option preset=M1, linear springs K_s)" if name == "ks" else ""
                raise ParameterError(
                    f"--param {name}: the reference bridge's bearing model {preset} does not use {name}, so no mode "
                    f"depends on it; choose one that does with --option preset=NAME{hint}"
                )

    def build(values):
        return build_structure(spec, {**options, **values}, base_dir=base_dir)

    fit = fit_parameters(build, measured, variables, fit_options, describe=lambda name: f"--param {name}")
    data = fit.to_dict()
    data["warnings"] = notes + data["warnings"]
    return {"structure": spec, "options": options, "model": model.name, "measured_file": str(measured_path), **data}


def _print_structure(data: dict) -> None:
    options = ", ".join(f"{k} = {v!r}" for k, v in data["options"].items())
    print(f"Calibration of {data['model'] or 'the model'} ({data['structure']}{'; ' + options if options else ''}) "
          f"against {data['measured_file']}" + ("  [SYNTHETIC data]" if data["synthetic"] else ""))
    if data["pairing"] == "mac":
        print(f"  pairing: by MAC at {len(data['sensors'])} channels ({', '.join(data['sensors'])}), "
              f"least MAC {data['min_mac']:g}")
    else:
        print("  pairing: by label (the labels of the whole computed modes)")
    cal = data["calibration"]
    for name, p in data["parameters"].items():
        print(f"  {name}: {p['fitted']:.6g}   (start {p['start']:.4g}, scan start {p['scan_start']:.4g}, "
              f"bounds {p['low']:.4g} .. {p['high']:.4g}, {p['scale']} scale)")
    scanned = f"after a scan of {len(data['scan'])} value{'s' if len(data['scan']) != 1 else ''}" if data["scan"] else (
        "from the start values (no scan)")
    print(f"  least squares: {_analyses(cal['evaluations'])} {scanned}, {cal['message']}")
    names = list(data["parameters"])
    head = "".join(f"{'dlnf/dln ' + n:>{max(14, len(n) + 10)}}" for n in names)
    print(f"  {'mode':<16}{'measured':>10}{'before':>9}{'error':>8}{'after':>9}{'error':>8}{'MAC':>7}  "
          f"{'paired with':<16}{head}")
    for m in data["modes"]:
        mac = "-" if m["mac_after"] is None else f"{m['mac_after']:.3f}"
        sens = "".join(
            f"{('-' if m['sensitivity'][n] is None else format(m['sensitivity'][n], '.4f')):>{max(14, len(n) + 10)}}"
            for n in names
        )
        print(f"  {m['name']:<16}{m['measured']:10.4f}{m['before']:9.4f}{m['error_before']:8.2%}{m['after']:9.4f}"
              f"{m['error_after']:8.2%}{mac:>7}  {m['label_after'] + ' (' + str(m['mode_after']) + ')':<16}{sens}")
    print("  (Hz; before: at the start values; after: at the fitted ones; paired with: the computed mode's label "
          "and number; dlnf/dln p: a frequency error e moves p by about e / that)")
    if data["mac"] is not None:
        print("  MAC table (measured x paired computed shapes, after):")
        for m, row in zip(data["modes"], data["mac"], strict=True):
            print(f"    {m['name']:<16}" + " ".join(f"{v:6.3f}" for v in row))
    damped = {m["name"]: m["damping"] for m in data["modes"] if m["damping"] is not None}
    if damped:
        print("  measured damping: " + ", ".join(f"{n} {z:.2%}" for n, z in damped.items()))
    for warning in data["warnings"]:
        print(f"  warning: {warning}")


def run(args) -> int:
    from bearingfw.structures import option_origins, parse_options

    # Errors propagate: bearingfw.cli.main gives each its message and exit status.
    generic = args.structure is not None or bool(args.param)
    if args.ks_max is not None and (generic or args.measured):
        raise ParameterError("--ks-max bounds step 1 against the paper's Table 2; it does not apply with --measured "
                             "or --structure (there --param NAME=LOW:HIGH gives the bounds)")
    if not generic and (args.option or args.n_modes is not None or args.scan is not None):
        raise ParameterError("--option, --n-modes and --scan apply to --structure (with --param)")
    try:
        if generic:
            from bearingfw.structures import REFERENCE

            data = structure_tune_data(
                args.structure or REFERENCE, parse_options(args.option), args.param, args.measured,
                _selection(args.modes), min_mac=args.min_mac, n_modes=args.n_modes, scan=args.scan,
                origins=option_origins(args.option),
            )
        elif args.measured:
            data = measured_tune_data(args.measured, _selection(args.modes), args.min_mac)
        else:
            if args.modes or args.min_mac is not None:
                raise ParameterError("--modes and --min-mac need identified modes: give --measured FILE")
            data = tune_data(args.ks_max)
    except UnicodeDecodeError as exc:  # the only text file read here is the measured-modes file
        if not args.measured:
            raise
        raise ParameterError(
            f"{args.measured}: not UTF-8 text (byte {exc.object[exc.start:exc.start + 1]!r} at offset {exc.start}); "
            "a measured-modes file is JSON or TOML in UTF-8"
        ) from None
    if args.json:
        print(json.dumps(data, indent=2))
    elif generic:
        _print_structure(data)
    else:
        (_print_measured if args.measured else _print)(data)
    return 0
