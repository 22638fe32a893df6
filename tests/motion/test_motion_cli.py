"""``bearingfw record info`` and the motion part of ``bearingfw plugins``."""

import json
import math

import numpy as np
import pytest
from scipy import signal
from motion_records import CHUETSU, G, MANJIL, at2_values

from bearingfw.cli.main import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def arias(values, dt):
    return np.pi / (2 * G) * np.trapezoid(np.asarray(values) ** 2, dx=dt)


def sdof_psa(acc, dt, period, damping=0.05, steps_per_period=40):
    """omega^2 max|u| of the oscillator u'' + 2 zeta omega u' + omega^2 u = -a_g, for a_g linear between
    samples: scipy's exact (matrix exponential, first-order hold) solution on a grid of period / 40 or
    finer, which misses a peak between its points by at most 1 - cos(pi / 40) = 0.31 %."""
    m = math.ceil(steps_per_period * dt / period)
    t = np.arange((acc.size - 1) * m + 1) * (dt / m)
    load = np.interp(t, np.arange(acc.size) * dt, acc)
    omega = 2 * np.pi / period
    oscillator = (np.array([[0.0, 1.0], [-omega**2, -2 * damping * omega]]), np.array([[0.0], [-1.0]]),
                  np.array([[1.0, 0.0]]), np.array([[0.0]]))
    _, u, _ = signal.lsim(oscillator, load, t, interp=True)
    return omega**2 * np.max(np.abs(u))


@pytest.mark.parametrize("files", [CHUETSU, MANJIL], ids=["chuetsu", "manjil"])
def test_record_info_json_on_real_files(capsys, files):
    code, out, _ = run(capsys, "record", "info", *map(str, files), "--json", "--period", "0.002")
    assert code == 0
    data = json.loads(out)
    values = [at2_values(p) for p in files]
    for role, v, component in zip(("h1", "h2", "v"), values, data["components"]):
        assert data["pga"][role] == pytest.approx(max(map(abs, v)) * G, rel=1e-12)
        assert component["pga_before_resampling"] == data["pga"][role] and not component["resampled"]
    dt = data["dt"]
    assert data["arias"] == pytest.approx(sum(arias(np.array(v) * G, dt) for v in values[:2]), rel=1e-6)
    assert 0 < data["pga_h10"] <= np.hypot(data["pga"]["h1"], data["pga"]["h2"])
    assert 0 < data["t_ha"] < data["duration"]
    assert data["degree"] == "above IV"  # earthquakes far stronger than the tremors of the scale
    assert data["synthetic"] is False
    lengths = [len(v) for v in values]
    assert data["padded"] == [c["name"] for c, k in zip(data["components"], lengths) if k < max(lengths)]
    assert data["pga_h10_filter"]["order_per_pass"] == 4 and data["pga_h10_filter"]["passes"] == 2
    spectrum = data["response_spectrum"]
    assert spectrum["damping"] == 0.05 and 0.1 in spectrum["periods"] and 1.0 in spectrum["periods"]
    for role, v in zip(("h1", "h2", "v"), values):
        psa = spectrum["psa"][role]
        assert len(psa) == len(spectrum["periods"]) and all(p > 0 for p in psa)
        # The printed spectrum is the oscillators' peak: the independent solution bounds it from above
        # (a sampled peak is never above the true one; 0.31 % slack for the reference's own sampling)
        # and from below by the 5 % that the documented sub-steps (at most T / 10) can miss.
        for period in (0.05, 1.0):
            exact = sdof_psa(np.array(v) * G, dt, period)
            assert exact * (1 - 0.049) <= psa[spectrum["periods"].index(period)] <= exact * 1.004
        # The rigid limit: an oscillator of T = 0.002 s (dt / 5 or less) follows the ground: Sa = PGA (1 %).
        assert data["sa"]["psa"][role][0] == pytest.approx(data["pga"][role], rel=0.01)


def test_record_info_on_files_of_different_time_steps(capsys):
    files = [CHUETSU[0], MANJIL[1], MANJIL[2]]
    code, out, _ = run(capsys, "record", "info", *map(str, files), "--json")
    data = json.loads(out)
    assert code == 0 and data["resampled"] == ["T", "V"]
    for path, component in zip(files, data["components"]):
        # The acceptance check on the files as read, before resampling.
        assert component["pga_before_resampling"] == pytest.approx(max(map(abs, at2_values(path))) * G, rel=1e-12)
    assert data["components"][1]["pga"] > 1.02 * data["components"][1]["pga_before_resampling"]
    assert len(data["notes"]) == 2
    code, out, _ = run(capsys, "record", "info", *map(str, files))
    assert "note: T resampled from dt = 0.02 s to 0.01 s" in out and "peak before resampling" in out


def test_record_info_json_on_the_synthetic_tremor(capsys):
    code, out, _ = run(capsys, "record", "info", "--synthetic", "1", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["synthetic"] is True and "synthetic" in data["source"].lower()
    assert data["pga_h10"] == pytest.approx(0.46, rel=1e-6)
    assert 3.0 <= data["t_ha"] <= 4.0
    assert data["degree"] == "II"
    assert set(data["pga"]) == {"h1", "h2", "v"}
    assert data["arias"] > 0


def test_record_info_table_says_synthetic_and_level_scaling_works(capsys):
    code, out, _ = run(capsys, "record", "info", "--synthetic", "2")
    assert code == 0
    assert "SYNTHETIC" in out and "PGA_H10" in out and "Degree  = II" in out
    code, out, _ = run(capsys, "record", "info", "--synthetic", "2", "--level", "D_IV", "--json")
    data = json.loads(out)
    assert data["degree"] == "IV" and data["pga_h10"] == pytest.approx(1.10, rel=1e-6)
    assert data["level"] == "D_IV" and data["levels"]["D_IV"] == 1.10


def test_record_info_level_values_can_be_set(capsys):
    code, out, _ = run(
        capsys, "record", "info", "--synthetic", "2", "--level", "D_II", "--set-level", "D_II=0.5",
        "--set-level", "D_III=0.8", "--json",
    )
    data = json.loads(out)
    assert code == 0 and data["pga_h10"] == pytest.approx(0.5, rel=1e-6) and data["degree"] == "II"
    assert data["levels"] == {"D_0": 0.10, "D_I": 0.23, "D_II": 0.5, "D_III": 0.8, "D_IV": 1.10}
    code, out, _ = run(capsys, "record", "info", "--synthetic", "2", "--level", "II", "--set-level", "d2=0.55")
    assert code == 0 and "to level D_II = 0.55 m/s^2" in out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--level", "D_II", "--set-level", "D_II=0.5", "--set-level", "d2=0.6"], "intensity level D_II is given twice"),
        (["--level", "D_II", "--set-level", "D_II:0.5"], "--set-level expects LEVEL=VALUE"),
        (["--level", "D_II", "--set-level", "D_II=half"], "--set-level expects LEVEL=VALUE"),
        (["--level", "D_II", "--set-level", "D_V=0.5"], "unknown intensity level 'D_V'"),
        (["--level", "D_II", "--set-level", "D_II=0.05"], "must increase from D_0 to D_IV"),
        (["--set-level", "D_II=0.5"], "give --level as well"),
        (["--dt", "0.01"], "--dt describe(s) record files; --synthetic SEED generates the record"),
        (["--units", "g", "--format", "npz"], "--format, --units describe(s) record files"),
    ],
)
def test_record_info_option_errors(capsys, argv, message):
    code, _, err = run(capsys, "record", "info", "--synthetic", "1", *argv)
    assert code == 2 and message in err, err


def test_units_option_conflicting_with_the_file_is_an_error(capsys):
    code, _, err = run(capsys, "record", "info", *map(str, CHUETSU), "--units", "cm/s^2")
    assert code == 2 and f"{CHUETSU[0]}, line 3:" in err and "states g but units = 'cm/s^2' was given" in err
    code, _, _ = run(capsys, "record", "info", *map(str, CHUETSU), "--units", "g", "--json")
    assert code == 0


def test_record_info_plot_writes_figures(capsys, tmp_path):
    code, out, _ = run(capsys, "record", "info", *map(str, MANJIL), "--plot", str(tmp_path))
    assert code == 0
    pngs = sorted(tmp_path.glob("*.png"))
    assert {p.stem.rsplit("_", 1)[1] for p in pngs} == {"acceleration", "fourier", "intensity", "spectrum"}
    for path in pngs:
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000
        assert path.with_suffix(".svg").stat().st_size > 5000
    code, out, _ = run(capsys, "record", "info", "--synthetic", "0", "--plot", str(tmp_path / "syn"))
    svg = (tmp_path / "syn" / "synthetic-seed0_acceleration.svg").read_text()
    assert "SYNTHETIC" in svg
    assert "SYNTHETIC" in (tmp_path / "syn" / "synthetic-seed0_spectrum.svg").read_text()


def test_a_real_record_named_like_a_synthetic_one_is_plotted(tmp_path):
    from bearingfw.motion import Record
    from bearingfw.motion.plot import write_figures

    t = np.arange(400) * 0.01
    record = Record(h1=np.sin(7 * t), h2=np.cos(5 * t), v=np.sin(3 * t), dt=0.01, source="a real file")
    written = write_figures(record, tmp_path, stem="synthetic-seed7", formats=("svg",))  # KeyError 'seed' before
    chart = next(p for p in written if p.stem.endswith("_intensity")).read_text()
    assert "synthetic-seed7" in chart and "SYNTHETIC" not in chart


def test_column_file_needs_dt_and_units_options(capsys, tmp_path):
    path = tmp_path / "tremor.txt"
    rng = np.random.default_rng(0)
    np.savetxt(path, rng.normal(size=(400, 3)))
    code, _, err = run(capsys, "record", "info", str(path))
    assert code == 2 and "tremor.txt" in err and "--dt" in err
    code, out, _ = run(capsys, "record", "info", str(path), "--dt", "0.01", "--units", "cm/s^2", "--json")
    assert code == 0 and json.loads(out)["dt"] == 0.01


def test_errors_are_reported_not_raised(capsys, tmp_path):
    bad = tmp_path / "bad.AT2"
    lines = CHUETSU[0].read_bytes().split(b"\r\n")
    lines[9] = b"   .1E-03   oops   .1E-03"
    bad.write_bytes(b"\r\n".join(lines))
    code, _, err = run(capsys, "record", "info", str(bad), *map(str, CHUETSU[1:]))
    assert code == 2 and f"{bad}, line 10:" in err and "'oops' is not a number" in err
    code, _, err = run(capsys, "record", "info", "--synthetic", "1", "--scale", "nope")
    assert code == 2 and "known scales" in err
    code, _, err = run(capsys, "record", "info")
    assert code == 2 and "--synthetic" in err


def test_help_texts(capsys):
    with pytest.raises(SystemExit) as info:
        main(["record", "info", "--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    for option in ("--dt", "--units", "--scale", "--synthetic", "--json", "--plot", "--format", "--set-level"):
        assert option in out
    assert "for files that do not state them" in " ".join(out.split())


def test_plugins_lists_readers_and_scales(capsys):
    code, out, _ = run(capsys, "plugins", "--json")
    data = json.loads(out)
    assert {"laws", "broken"} <= set(data)
    assert {r["name"] for r in data["record_readers"]} >= {"peer-at2", "columns", "npz"}
    scale = next(s for s in data["intensity_scales"] if s["name"] == "usb-pga-h10")
    assert scale["degrees"] == ["0", "I", "II", "III", "IV"]
    code, out, _ = run(capsys, "plugins")
    assert "Record readers:" in out and "peer-at2" in out and "usb-pga-h10" in out


def test_record_info_prints_the_response_spectrum_table(capsys):
    from bearingfw.cli.record import SPECTRUM_PERIODS
    from bearingfw.motion import read_record, response_spectrum
    from bearingfw.motion.metrics import SUMMARY_PERIODS

    assert SPECTRUM_PERIODS == SUMMARY_PERIODS  # the documented table and the summary's --json periods
    code, out, _ = run(capsys, "record", "info", *map(str, CHUETSU))
    assert code == 0
    lines = out.splitlines()
    start = lines.index("Response spectrum: pseudo-spectral acceleration [m/s^2], 5% damping")
    assert lines[start + 1].split() == ["T", "[s]", "EW", "NS", "UD", "horizontal", "(geometric", "mean)"]
    rows = [line.split() for line in lines[start + 2: start + 2 + len(SPECTRUM_PERIODS)]]
    record = read_record(CHUETSU)
    psa = [response_spectrum(c, record.dt, SPECTRUM_PERIODS).psa for c in record.components]
    for i, (row, period) in enumerate(zip(rows, SPECTRUM_PERIODS)):
        assert float(row[0]) == period
        assert [float(x) for x in row[1:4]] == pytest.approx([p[i] for p in psa], rel=5e-4)  # 4 digits printed
        assert float(row[4]) == pytest.approx(np.sqrt(psa[0][i] * psa[1][i]), rel=5e-4)


def test_record_info_period_and_target(capsys):
    from bearingfw.motion import read_record, response_spectrum

    record = read_record(CHUETSU)
    sa = [response_spectrum(c, record.dt, [0.5, 1.0]).psa for c in record.horizontal]
    code, out, _ = run(capsys, "record", "info", *map(str, CHUETSU), "--period", "0.5", "--period", "1", "--json")
    data = json.loads(out)
    assert code == 0 and data["sa"]["periods"] == [0.5, 1.0]
    assert data["sa"]["psa"]["h1"] == pytest.approx(sa[0], rel=1e-12)
    assert data["sa"]["horizontal"] == pytest.approx(np.sqrt(sa[0] * sa[1]), rel=1e-12)
    # Scaled to Sa(0.5 s) = 2 m/s^2: the factor is 2 / the geometric mean, and Sa then reads 2.
    code, out, _ = run(capsys, "record", "info", *map(str, CHUETSU), "--target", "sa=2@0.5", "--period", "0.5", "--json")
    data = json.loads(out)
    assert data["scale_factor"] == pytest.approx(2.0 / np.sqrt(sa[0][0] * sa[1][0]), rel=1e-12)
    assert data["sa"]["horizontal"][0] == pytest.approx(2.0, rel=1e-12) and data["target"] == "sa=2@0.5s"
    code, out, _ = run(capsys, "record", "info", *map(str, CHUETSU), "--period", "0.5")
    assert f"Sa(T = 0.5 s, 5%) = {np.sqrt(sa[0][0] * sa[1][0]):.4g} m/s^2 (horizontals' geometric mean)" in out
    code, out, _ = run(capsys, "record", "info", *map(str, CHUETSU), "--target", "as-recorded", "--json")
    assert code == 0 and json.loads(out)["scale_factor"] == 1.0


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--period", "0"], "--period 0.0: the period must be a finite number of seconds > 0"),
        (["--target", "sa=2@T1"], "T1 is a structure's first mode; give the period in s"),
        (["--target", "sa=2"], "Sa needs a period"),
        (["--target", "D_II", "--level", "D_II"], "give either --level or --target"),
    ],
)
def test_record_info_spectrum_option_errors(capsys, argv, message):
    code, _, err = run(capsys, "record", "info", "--synthetic", "1", *argv)
    assert code == 2 and message in err, err


def test_record_info_plot_marks_the_periods(capsys, tmp_path):
    code, out, _ = run(capsys, "record", "info", "--x", str(CHUETSU[0]), "--period", "0.5", "--plot", str(tmp_path))
    assert code == 0
    svg = next(tmp_path.glob("*_spectrum.svg")).read_text()
    assert "horizontal (geometric mean)" in svg and "Sa(0.5 s) = " in svg
