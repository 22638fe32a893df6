"""``bearingfw modal``: the reference bridge's modes under one of the paper's bearing models."""

from __future__ import annotations

import json
import sys

from bearingfw.parameters import ParameterError


def add_parser(subparsers) -> None:
    # bearingfw.bridges.paper is light; the model itself is imported when the command runs
    from bearingfw.bridges.paper import KS_FIT

    parser = subparsers.add_parser(
        "modal",
        help="natural frequencies and mode shapes of the reference bridge",
        description="Modal analysis of the paper's reference bridge with a bearing model: frequencies, labels "
        "(vertical, lateral, longitudinal, torsional), the share of each mode's kinetic energy in the deck "
        "(where the paper's sensors were), effective masses, and which modes answer the paper's Table 2.",
    )
    parser.add_argument(
        "--model", default="M0", metavar="NAME",
        help="bearing model, a preset of bearingfw.bridges: M0 (frictionless, default), M1 (linear springs K_s), "
        "M2 (regularized Coulomb), fixed (every bearing fixed) or bouc-wen",
    )
    parser.add_argument(
        "--ks", type=float, default=KS_FIT, metavar="N/M",
        help=f"stick stiffness K_s of M1, M2 and bouc-wen (default {KS_FIT:g} N/m, the paper's)",
    )
    parser.add_argument("--modes", type=int, default=20, metavar="N", help="modes to compute (default 20)")
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of a table")
    parser.add_argument(
        "--plot", metavar="DIR", help="write the Table 2 modes' shapes and their AutoMAC to DIR (PNG and SVG)"
    )
    parser.set_defaults(func=run)


def modal_data(model: str = "M0", ks: float | None = None, n_modes: int = 20) -> tuple[dict, object]:
    """The ``--json`` object and the modal result."""
    from bearingfw.analysis import solve_modal
    from bearingfw.bridges import DEFAULT_KS, PRESETS, BridgeParameters, reference_bridge
    from bearingfw.bridges.paper import MODES, TABLE2_FE
    from bearingfw.bridges.study import deck_observation
    from bearingfw.tuning import observed_modes

    ks = DEFAULT_KS if ks is None else ks
    if model not in PRESETS:
        raise ParameterError(f"--model must be one of {', '.join(PRESETS)}, got {model!r}")
    if not (isinstance(n_modes, int) and n_modes >= 1):
        raise ParameterError(f"--modes must be an integer >= 1, got {n_modes!r}")
    params = BridgeParameters()
    modal = solve_modal(reference_bridge(model, ks=ks, params=params), n_modes)
    seen = observed_modes(modal, deck_observation(params))
    deck_label = {m: lab for lab, m in seen.numbered.items()}
    paper = {mode: seen.numbered[mode] for mode in MODES if mode in seen.numbered}
    total = {d: modal.total_mass[d] for d in ("x", "y", "z")}
    modes = []
    for m in range(modal.n_modes):
        modes.append(
            {
                "index": m + 1,
                "frequency": float(modal.frequencies[m]),
                "label": modal.numbered_labels[m],
                "deck_share": float(seen.share[m]),
                "deck_label": deck_label.get(m),
                "participation": {d: float(modal.effective_mass[d][m] / total[d]) if total[d] else 0.0 for d in total},
            }
        )
    data = {
        "model": model,
        "ks": ks if model in ("M1", "M2", "bouc-wen") else None,
        "modes": modes,
        "paper": {
            mode: {"index": m + 1, "frequency": float(modal.frequencies[m]), "table2_fe": TABLE2_FE[mode]}
            for mode, m in paper.items()
        },
    }
    return data, modal


def _plot(modal, data: dict, directory) -> list:
    from bearingfw.analysis import automac
    from bearingfw.bridges import BridgeParameters
    from bearingfw.bridges.study import deck_observation
    from bearingfw.plotting import save
    from bearingfw.tuning.plot import plot_mac, plot_mode

    written = []
    chosen = [(name, entry["index"] - 1) for name, entry in data["paper"].items()]
    for name, m in chosen:
        title = f"{data['model']}: {name} (deck), mode {m + 1}, {modal.frequencies[m]:.3f} Hz"
        written += save(plot_mode(modal, m, title), directory, f"mode-{name.replace(' ', '-')}")
    if chosen:
        dofs = deck_observation(BridgeParameters()).dofs(modal.system)
        table = automac(modal.shapes[dofs][:, [m for _, m in chosen]])
        names = [name for name, _ in chosen]
        written += save(plot_mac(table, names, title=f"AutoMAC of the Table 2 modes ({data['model']}, deck)"),
                        directory, "automac")
    return written


def run(args) -> int:
    try:
        data, modal = modal_data(args.model, args.ks, args.modes)
        written = _plot(modal, data, args.plot) if args.plot else []
    except (ParameterError, OSError) as exc:
        print(f"bearingfw modal: error: {exc}", file=sys.stderr)
        return 1
    if args.json:
        if written:
            data["figures"] = [str(p) for p in written]
        print(json.dumps(data, indent=2))
        return 0
    print(f"Reference bridge, bearing model {data['model']}" + (f" (K_s = {data['ks']:g} N/m)" if data["ks"] else ""))
    print(f"  {'mode':>4}  {'f [Hz]':>8}  {'label':<16}{'deck':>6}  {'deck mode':<14}{'Mx':>6}{'My':>6}{'Mz':>6}")
    for m in data["modes"]:
        part = m["participation"]
        print(f"  {m['index']:>4}  {m['frequency']:8.3f}  {m['label']:<16}{m['deck_share']:6.0%}  "
              f"{(m['deck_label'] or '-'):<14}{part['x']:6.0%}{part['y']:6.0%}{part['z']:6.0%}")
    print("  (deck: share of the kinetic energy in the deck's vertical and transverse motion; deck mode: label among "
          "the modes the deck sensors see; M: effective mass share)")
    for name, entry in data["paper"].items():
        print(f"  {name:<12} mode {entry['index']:>3}: {entry['frequency']:.3f} Hz   "
              f"(paper, Table 2 FE: {entry['table2_fe']:.2f} Hz)")
    for path in written:
        print(f"wrote {path}")
    return 0
