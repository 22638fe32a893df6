"""``bearingfw oma`` (identification and --decay) and ``bearingfw tune --measured`` through the entry point."""

from __future__ import annotations

import json

import numpy as np
import pytest
from oma_systems import JUMP_DT as DT
from oma_systems import JUMP_RATIOS as RATIOS
from oma_systems import chain_modes, chain_record, jumping_test

from bearingfw.cli.main import build_parser, main
from bearingfw.oma import Channels, read_modes


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture(scope="module")
def chain_file(tmp_path_factory):
    return chain_record().to_npz(tmp_path_factory.mktemp("chain") / "chain.npz")


def test_oma_json_output_plot_and_modes_file(capsys, chain_file, tmp_path):
    code, out, _ = run(capsys, "oma", chain_file, "--json", "--plot", tmp_path, "-o", tmp_path / "modes.json")
    assert code == 0
    data = json.loads(out)
    f = chain_modes()[0]
    np.testing.assert_allclose([m["frequency"] for m in data["modes"]], f, rtol=0.01)
    assert data["ssi"]["max_order"] == 60 and data["criteria"]["mac"] == 0.9 and data["synthetic"] is True
    assert data["warnings"] == [] and all(r["reasons"] for r in data["rejected"])
    names = {p.name for p in tmp_path.iterdir()}
    assert {"stabilisation.png", "stabilisation.svg", "modes.json"} <= names
    assert (tmp_path / "stabilisation.png").stat().st_size > 10_000
    assert read_modes(tmp_path / "modes.json").channels == ("m1.ux", "m2.ux", "m3.ux")
    assert sorted(data["files"]) == sorted(
        str(tmp_path / n) for n in ("modes.json", "stabilisation.png", "stabilisation.svg")
    )


def test_oma_table_and_options(capsys, chain_file):
    code, out, _ = run(
        capsys, "oma", chain_file, "--order", "20", "--fmax", "4", "--channels", "m3.ux,m1.ux", "--mac", "0.95"
    )
    assert code == 0
    assert "SSI-COV" in out and "orders 2..20" in out and "analysed at 0.1 s" in out
    assert "mode 1" in out and "mode 2" in out and "mode 3" not in out
    assert "m3.ux" in out and "m2.ux" not in out


def test_oma_table_lists_near_misses_and_warns_when_the_order_is_too_low(capsys, chain_file):
    """Order 10 holds the chain's third mode at its last two orders only: too few to count, and said so."""
    code, out, _ = run(capsys, "oma", chain_file, "--order", "10")
    assert code == 0
    assert "mode 1" in out and "mode 3" not in out
    assert "warning: the top orders still add stable poles: 4.8" in out and "raise the order above 10" in out
    assert "near misses" in out and "stable at 2 orders, fewer than 3" in out


def test_oma_criteria_options_reach_the_selection(capsys, chain_file):
    code, out, _ = run(
        capsys, "oma", chain_file, "--json", "--min-presence", "0.5", "--min-mpc", "0.9", "--min-peak", "3"
    )
    assert code == 0
    crit = json.loads(out)["criteria"]
    assert (crit["min_presence"], crit["min_mpc"], crit["min_peak"]) == (0.5, 0.9, 3.0)
    code, _, err = run(capsys, "oma", chain_file, "--min-mpc", "1.5")
    assert code == 2 and "min_mpc" in err


def test_the_help_states_the_library_defaults():
    """The options default to None so that the library's defaults apply; the help quotes them."""
    from bearingfw.cli.oma import HELP_DEFAULTS
    from bearingfw.oma import Criteria, DecayFilter, SSISettings

    criteria, decay = Criteria(), DecayFilter()
    library = {name: getattr(criteria, name, getattr(decay, name, None)) for name in HELP_DEFAULTS}
    library["order"] = SSISettings().max_order
    assert library == HELP_DEFAULTS


def test_oma_decay(capsys, tmp_path):
    record = Channels(jumping_test()[:, None], DT, ("GA32.uz",), source="jumping test")
    path = record.to_csv(tmp_path / "jump.csv")
    # FILE after the option: --decay takes one comma-separated argument
    code, out, _ = run(capsys, "oma", "--decay", "1.5,3.36", path, "--json", "--plot", tmp_path)
    assert code == 0
    data = json.loads(out)
    assert [d["frequency"] for d in data["decays"]] == [1.5, 3.36]
    assert data["decays"][0]["damping"] == pytest.approx(RATIOS[0], rel=0.05)
    assert data["decays"][0]["damped_frequency"] == pytest.approx(1.5, rel=0.01)
    fit = data["decays"][0]["channels"]["GA32.uz"]
    assert fit["peaks"] >= 20 and fit["damped_frequency"] == pytest.approx(1.5, rel=0.01) and fit["r2"] > 0.99
    assert data["filter"]["min_r2"] == 0.95
    assert data["rayleigh"]["alpha"] > 0 and data["rayleigh"]["beta"] > 0
    assert (tmp_path / "decay-1.5Hz-GA32.uz.png").exists()
    code, out, _ = run(capsys, "oma", path, "--decay", "1.5", "--bandwidth", "0.04", "--start", "20")
    assert code == 0 and "log decrement" in out and "damping ratio 2.1" in out and "damped frequency 1.5" in out


def test_oma_decay_of_a_record_cut_during_the_decay_is_refused(capsys, tmp_path):
    record = Channels(jumping_test(duration=25.0)[:, None], DT, ("GA32.uz",), source="jumping test")
    path = record.to_csv(tmp_path / "cut.csv")
    code, _, err = run(capsys, "oma", path, "--decay", "1.5")
    assert code == 2 and "no channel gives a decay" in err and "filter time constants" in err


@pytest.mark.parametrize("value", ["1.5,x", "0", "-1.5", ""])
def test_oma_decay_frequencies_are_checked(capsys, value):
    with pytest.raises(SystemExit):
        main(["oma", "x.csv", "--decay", value])
    assert "frequencies" in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv, message",
    [
        (["oma", "missing.npz"], "bearingfw oma: error"),
        (["oma", "{chain}", "--order", "31"], "'max_order' must be even"),
        (["oma", "{chain}", "--channels", "nope"], "no channel 'nope'"),
        (["oma", "{chain}", "--fmax", "40"], "Nyquist"),
        (["oma", "{chain}", "--references", "m9.ux"], "references"),
        (["oma", "{chain}", "--decay", "0.001"], "no channel gives a decay"),
    ],
)
def test_oma_errors_are_named(capsys, chain_file, argv, message):
    code, _, err = run(capsys, *[a.replace("{chain}", str(chain_file)) for a in argv])
    assert code == 2 and message in err


def test_oma_is_a_command_with_help():
    parser = build_parser()
    assert "oma" in parser.format_help()
    with pytest.raises(SystemExit):
        main(["oma", "--help"])


@pytest.mark.parametrize(
    "argv, message",
    [
        (["tune", "--modes", "1"], "need identified modes"),
        (["tune", "--min-mac", "0.9"], "need identified modes"),
        (["tune", "--measured", "missing.json"], "cannot read"),
        (["tune", "--scan", "3"], "apply to --structure"),
        (["tune", "--n-modes", "30", "--measured", "missing.json"], "apply to --structure"),
    ],
)
def test_tune_measured_errors_are_named(capsys, tmp_path, argv, message):
    code, _, err = run(capsys, *argv)
    assert code == 2 and message in err


def test_tune_help_states_the_least_mac():
    from bearingfw.tuning import MIN_MAC

    parser = build_parser()
    tune = parser._subparsers._group_actions[0].choices["tune"]  # the sub-command's parser
    assert f"(default {MIN_MAC:g})" in " ".join(tune.format_help().split())


def test_tune_has_no_by_option(capsys):
    """Pairing follows from the input (by label for Table 2, by MAC for identified modes): nothing to choose."""
    with pytest.raises(SystemExit):
        main(["tune", "--by", "mac"])
    assert "unrecognized arguments: --by" in capsys.readouterr().err
