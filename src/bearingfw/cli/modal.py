"""``bearingfw modal``: the modes of a structure: the reference bridge under one of the paper's bearing
models (default), or a user's structure (``--structure module:function`` with ``--option key=value``)."""

from __future__ import annotations

import json

from bearingfw.parameters import ParameterError


def add_parser(subparsers) -> None:
    # bearingfw.bridges.paper is light; the model itself is imported when the command runs
    from bearingfw.bridges.paper import KS_FIT

    from bearingfw.structures import OPTION_HELP, STRUCTURE_HELP

    parser = subparsers.add_parser(
        "modal",
        help="natural frequencies and mode shapes of the reference bridge or of your structure",
        description="Modal analysis of the paper's reference bridge with a bearing model: frequencies, labels "
        "(vertical, lateral, longitudinal, torsional), the share of each mode's kinetic energy in the deck "
        "(where the paper's sensors were), effective masses, and which modes answer the paper's Table 2. "
        "With --structure, the modes of your own structure as its function builds it (its bearings' laws as it "
        "sets them): frequencies, labels from the modal kinetic energy (x along the bridge, z up), each mode's "
        "dominant component and its effective masses.",
    )
    parser.add_argument("--structure", metavar="SPEC", help=STRUCTURE_HELP)
    parser.add_argument("--option", action="append", default=[], metavar="KEY=VALUE", help=OPTION_HELP)
    parser.add_argument(
        "--model", default=None, metavar="NAME",
        help="reference bridge: bearing model, a preset of bearingfw.bridges: M0 (frictionless, default), "
        "M1 (linear springs K_s), M2 (regularized Coulomb), fixed (every bearing fixed) or bouc-wen",
    )
    parser.add_argument(
        "--ks", type=float, default=None, metavar="N/M",
        help=f"reference bridge: stick stiffness K_s of M1, M2 and bouc-wen (default {KS_FIT:g} N/m, the paper's)",
    )
    parser.add_argument("--modes", type=int, default=20, metavar="N", help="modes to compute (default 20)")
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    parser.add_argument(
        "--plot", metavar="DIR",
        help="write the Table 2 modes' shapes and their AutoMAC to DIR (PNG and SVG); with --structure, the shapes "
        "of the first 12 modes and their AutoMAC"
    )
    parser.set_defaults(func=run)


def _reference_options(model: str | None, ks: float | None, options: dict | None) -> dict:
    """The reference bridge's options from --model, --ks and --option (the same one given twice: an error)."""
    from bearingfw.structures import StructureError

    options = dict(options or {})
    for flag, key, value in (("--model", "preset", model), ("--ks", "ks", ks)):
        if value is not None:
            if key in options:
                raise StructureError(f"{flag} and --option {key}=... both give the {key}: give one")
            options[key] = value
    return options


def modal_data(
    model: str | None = "M0", ks: float | None = None, n_modes: int = 20, options: dict | None = None
) -> tuple[dict, object]:
    """The ``--json`` object and the modal result of the reference bridge (``options``: those of
    :func:`bearingfw.structures.reference_parameters`, besides ``model`` and ``ks``)."""
    from bearingfw.analysis import solve_modal
    from bearingfw.analysis.static import StiffnessRangeError
    from bearingfw.bridges import PRESETS, reference_bridge
    from bearingfw.bridges.paper import MODES, TABLE2_FE
    from bearingfw.bridges.study import deck_observation, mode_labels
    from bearingfw.structures import reference_parameters
    from bearingfw.tuning import observed_modes

    model_ks = ks
    given = _reference_options(model, ks, options)
    if given.get("preset", "M0") not in PRESETS:
        flag = "--model" if model is not None else "--option preset"
        raise ParameterError(f"{flag} must be one of {', '.join(PRESETS)}, got {given['preset']!r}")
    model, ks, friction, params = reference_parameters(given)
    if not (isinstance(n_modes, int) and n_modes >= 1):
        raise ParameterError(f"--modes must be an integer >= 1, got {n_modes!r}")
    try:
        modal = solve_modal(reference_bridge(model, ks=ks, params=params, friction=friction), n_modes)
    except StiffnessRangeError as exc:
        if "ks" not in given or exc.law is None:  # not the laws' stiffness that --ks sets
            raise
        flag = "--ks" if model_ks is not None else "--option ks"
        allowed = f"<= {exc.limit:.2g} N/m for this bridge" if exc.limit is not None else "finite"
        raise ParameterError(f"{flag} = {ks:g} N/m is out of range: allowed 0 < ks {allowed} ({exc})") from exc
    seen = observed_modes(modal, deck_observation(params))
    deck_label = {m: lab for lab, m in seen.numbered.items()}
    paper = {mode: seen.numbered[mode] for mode in MODES if mode in seen.numbered}
    modes = _mode_entries(modal)
    whose = mode_labels(modal, params)  # "deck lateral 1", "arches lateral 1": the labels the report uses
    for m, entry in enumerate(modes):
        entry.update(deck_share=float(seen.share[m]), deck_label=deck_label.get(m), whose=whose[m])
    data = {
        "structure": "reference",
        "options": {k: v for k, v in given.items() if k not in ("preset", "ks")},
        "model": model,
        "ks": ks if model in ("M1", "M2", "bouc-wen") else None,
        "ks_source": _ks_source(model, ks),
        "modes": modes,
        "paper": {
            mode: {"index": m + 1, "frequency": float(modal.frequencies[m]), "table2_fe": TABLE2_FE[mode]}
            for mode, m in paper.items()
        },
    }
    return data, modal


def _ks_source(model: str, ks: float) -> str | None:
    """Where the K_s of ``model`` comes from: the default study's value (``bearingfw tune``) or the user's."""
    from bearingfw.bridges import DEFAULT_KS, KS_SOURCE

    if model not in ("M1", "M2", "bouc-wen"):
        return None
    return KS_SOURCE if ks == DEFAULT_KS else "given (--ks or --option ks), not the default study's K_s"


def _mode_entries(modal) -> list[dict]:
    """Per mode: index, frequency, the kernel's numbered label and the effective mass shares in x, y, z."""
    total = {d: modal.total_mass[d] for d in ("x", "y", "z")}
    return [
        {
            "index": m + 1,
            "frequency": float(modal.frequencies[m]),
            "label": modal.numbered_labels[m],
            "participation": {d: float(modal.effective_mass[d][m] / total[d]) if total[d] else 0.0 for d in total},
        }
        for m in range(modal.n_modes)
    ]


def structure_modal_data(
    spec: str, options: dict | None = None, n_modes: int = 20, base_dir=None, origins: dict | None = None
) -> tuple[dict, object]:
    """The ``--json`` object and the modal result of a user's structure (:mod:`bearingfw.structures`).

    Per mode: frequency, the kernel's label (the largest kinetic-energy share among vertical,
    lateral, longitudinal, torsional, with x along the bridge and z up), the dominant component
    (the largest share of the kinetic energy among ux .. rz) and the effective mass shares in x, y, z
    (of all the mass; ``effective_mass`` in kg). ``origins``: how the user gave each option, for
    messages (:func:`bearingfw.structures.build_structure`).
    """
    import numpy as np

    from bearingfw.analysis import solve_modal
    from bearingfw.analysis.modal import TooManyModes
    from bearingfw.model import COMPONENTS
    from bearingfw.structures import build_structure

    if not (isinstance(n_modes, int) and n_modes >= 1):
        raise ParameterError(f"--modes must be an integer >= 1, got {n_modes!r}")
    # check: a value the bearing laws refuse is an error here, put on the option that gave it
    model = build_structure(spec, options or {}, base_dir=base_dir, check=True, origins=origins)
    try:
        modal = solve_modal(model, n_modes)
    except TooManyModes as exc:
        raise ParameterError(f"--modes {n_modes} (the default is 20) is more than this structure has: it has "
                             f"{exc.available} DOFs with mass, so give --modes {exc.available} or fewer") from None
    energy = modal.shapes * (modal.system.M @ modal.shapes)
    per_component = np.array([energy[k::len(COMPONENTS)].sum(axis=0) for k in range(len(COMPONENTS))])
    per_component /= np.where(per_component.sum(axis=0) > 0, per_component.sum(axis=0), 1.0)
    total = {d: modal.total_mass[d] for d in ("x", "y", "z")}
    modes = _mode_entries(modal)
    for m, entry in enumerate(modes):
        entry.update(
            dominant=COMPONENTS[int(np.argmax(per_component[:, m]))],
            energy={c: float(per_component[k, m]) for k, c in enumerate(COMPONENTS)},
            effective_mass={d: float(modal.effective_mass[d][m]) for d in total},
        )
    data = {
        "structure": spec,
        "options": dict(options or {}),
        "model": model.name,
        "nodes": len(model.nodes),
        "dofs": int(modal.system.n_dof),
        "total_mass": total,
        "modes": modes,
    }
    return data, modal


def _plot_structure(modal, data: dict, directory) -> list:
    """Every computed mode's shape (up to 12) and their AutoMAC over all DOFs."""
    from bearingfw.analysis import automac
    from bearingfw.plotting import save
    from bearingfw.tuning.plot import plot_mac, plot_mode

    written = []
    chosen = list(range(min(modal.n_modes, 12)))
    for m in chosen:
        written += save(plot_mode(modal, m), directory, f"mode-{m + 1}")
    names = [f"{m + 1}: {modal.numbered_labels[m]}" for m in chosen]
    written += save(plot_mac(automac(modal.shapes[:, chosen]), names, title=f"AutoMAC ({data['model']})"),
                    directory, "automac")
    return written


def _plot(modal, data: dict, directory) -> list:
    from bearingfw.analysis import automac
    from bearingfw.bridges.study import deck_observation
    from bearingfw.plotting import save
    from bearingfw.structures import reference_parameters
    from bearingfw.tuning.plot import plot_mac, plot_mode

    written = []
    chosen = [(name, entry["index"] - 1) for name, entry in data["paper"].items()]
    for name, m in chosen:
        title = f"{data['model']}: {name} (deck), mode {m + 1}, {modal.frequencies[m]:.3f} Hz"
        written += save(plot_mode(modal, m, title), directory, f"mode-{name.replace(' ', '-')}")
    if chosen:
        params = reference_parameters(data["options"])[3]
        dofs = deck_observation(params).dofs(modal.system)
        table = automac(modal.shapes[dofs][:, [m for _, m in chosen]])
        names = [name for name, _ in chosen]
        written += save(plot_mac(table, names, title=f"AutoMAC of the Table 2 modes ({data['model']}, deck)"),
                        directory, "automac")
    return written


def _print_structure(data: dict) -> None:
    options = ", ".join(f"{k} = {v!r}" for k, v in data["options"].items())
    print(f"{data['model'] or 'model'} ({data['structure']}{'; ' + options if options else ''}): "
          f"{data['nodes']} nodes, {data['dofs']} DOFs")
    print(f"  {'mode':>4}  {'f [Hz]':>8}  {'label':<16}{'dominant':<10}{'Mx':>6}{'My':>6}{'Mz':>6}")
    for m in data["modes"]:
        part = m["participation"]
        print(f"  {m['index']:>4}  {m['frequency']:8.3f}  {m['label']:<16}{m['dominant']:<10}"
              f"{part['x']:6.0%}{part['y']:6.0%}{part['z']:6.0%}")
    print("  (label: the largest share of the modal kinetic energy, x along the bridge and z up; dominant: the "
          "component with the largest share; M: effective mass share of all the mass)")


def run(args) -> int:
    from bearingfw.structures import REFERENCE, option_origins, parse_options

    # Errors propagate: bearingfw.cli.main gives each its message and exit status.
    user = args.structure is not None and args.structure != REFERENCE
    options = parse_options(args.option)
    if user:
        if args.model is not None or args.ks is not None:
            raise ParameterError(
                "--model and --ks choose the reference bridge's bearing model; your structure's function sets "
                "its bearings' laws (give it options with --option key=value)"
            )
        data, modal = structure_modal_data(args.structure, options, args.modes, origins=option_origins(args.option))
        written = _plot_structure(modal, data, args.plot) if args.plot else []
    else:
        data, modal = modal_data(args.model, args.ks, args.modes, options)
        written = _plot(modal, data, args.plot) if args.plot else []
    if args.json:
        if written:
            data["figures"] = [str(p) for p in written]
        print(json.dumps(data, indent=2))
        return 0
    if user:
        _print_structure(data)
        for path in written:
            print(f"wrote {path}")
        return 0
    print(f"Reference bridge, bearing model {data['model']}" + (f" (K_s = {data['ks']:g} N/m)" if data["ks"] else ""))
    print(f"  {'mode':>4}  {'f [Hz]':>8}  {'whose mode':<22}{'deck':>6}{'Mx':>6}{'My':>6}{'Mz':>6}")
    for m in data["modes"]:
        part = m["participation"]
        print(f"  {m['index']:>4}  {m['frequency']:8.3f}  {m['whose']:<22}{m['deck_share']:6.0%}"
              f"{part['x']:6.0%}{part['y']:6.0%}{part['z']:6.0%}")
    print("  (whose mode: the deck's modes numbered as the paper's Table 2 numbers them, the others by the part with "
          "the largest share of the kinetic energy; deck: share of the kinetic energy in the deck's vertical and "
          "transverse motion; M: effective mass share)")
    for name, entry in data["paper"].items():
        print(f"  {name:<12} mode {entry['index']:>3}: {entry['frequency']:.3f} Hz   "
              f"(paper, Table 2 FE: {entry['table2_fe']:.2f} Hz)")
    for path in written:
        print(f"wrote {path}")
    return 0
