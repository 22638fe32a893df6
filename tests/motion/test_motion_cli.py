"""``bearingfw record info`` and the motion part of ``bearingfw plugins``."""

import json

import numpy as np
import pytest
from conftest import CHUETSU, G, MANJIL, at2_values

from bearingfw.cli.main import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def arias(values, dt):
    return np.pi / (2 * G) * np.trapezoid(np.asarray(values) ** 2, dx=dt)


@pytest.mark.parametrize("files", [CHUETSU, MANJIL], ids=["chuetsu", "manjil"])
def test_record_info_json_on_real_files(capsys, files):
    code, out, _ = run(capsys, "record", "info", *map(str, files), "--json")
    assert code == 0
    data = json.loads(out)
    values = [at2_values(p) for p in files]
    for role, v in zip(("h1", "h2", "v"), values):
        assert data["pga"][role] == pytest.approx(max(map(abs, v)) * G, rel=1e-12)
    dt = data["dt"]
    assert data["arias"] == pytest.approx(sum(arias(np.array(v) * G, dt) for v in values[:2]), rel=1e-6)
    assert 0 < data["pga_h10"] <= np.hypot(data["pga"]["h1"], data["pga"]["h2"])
    assert 0 < data["t_ha"] < data["duration"]
    assert data["degree"] == "above IV"  # earthquakes far stronger than the tremors of the scale
    assert data["synthetic"] is False
    lengths = [len(v) for v in values]
    assert data["padded"] == [c["name"] for c, k in zip(data["components"], lengths) if k < max(lengths)]


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


def test_record_info_plot_writes_figures(capsys, tmp_path):
    code, out, _ = run(capsys, "record", "info", *map(str, MANJIL), "--plot", str(tmp_path))
    assert code == 0
    pngs = sorted(tmp_path.glob("*.png"))
    assert {p.stem.rsplit("_", 1)[1] for p in pngs} == {"acceleration", "fourier", "intensity"}
    for path in pngs:
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000
        assert path.with_suffix(".svg").stat().st_size > 5000
    code, out, _ = run(capsys, "record", "info", "--synthetic", "0", "--plot", str(tmp_path / "syn"))
    svg = (tmp_path / "syn" / "synthetic-seed0_acceleration.svg").read_text()
    assert "SYNTHETIC" in svg


def test_column_file_needs_dt_and_units_options(capsys, tmp_path):
    path = tmp_path / "tremor.txt"
    rng = np.random.default_rng(0)
    np.savetxt(path, rng.normal(size=(400, 3)))
    code, _, err = run(capsys, "record", "info", str(path))
    assert code == 1 and "tremor.txt" in err and "--dt" in err
    code, out, _ = run(capsys, "record", "info", str(path), "--dt", "0.01", "--units", "cm/s^2", "--json")
    assert code == 0 and json.loads(out)["dt"] == 0.01


def test_errors_are_reported_not_raised(capsys, tmp_path):
    bad = tmp_path / "bad.AT2"
    lines = CHUETSU[0].read_bytes().split(b"\r\n")
    lines[9] = b"   .1E-03   oops   .1E-03"
    bad.write_bytes(b"\r\n".join(lines))
    code, _, err = run(capsys, "record", "info", str(bad), *map(str, CHUETSU[1:]))
    assert code == 1 and f"{bad}, line 10:" in err and "'oops' is not a number" in err
    code, _, err = run(capsys, "record", "info", "--synthetic", "1", "--scale", "nope")
    assert code == 1 and "known scales" in err
    code, _, err = run(capsys, "record", "info")
    assert code == 1 and "--synthetic" in err


def test_help_texts(capsys):
    with pytest.raises(SystemExit) as info:
        main(["record", "info", "--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    for option in ("--dt", "--units", "--scale", "--synthetic", "--json", "--plot", "--format"):
        assert option in out


def test_plugins_lists_readers_and_scales(capsys):
    code, out, _ = run(capsys, "plugins", "--json")
    data = json.loads(out)
    assert {"laws", "broken"} <= set(data)
    assert {r["name"] for r in data["record_readers"]} >= {"peer-at2", "columns", "npz"}
    scale = next(s for s in data["intensity_scales"] if s["name"] == "usb-pga-h10")
    assert scale["degrees"] == ["0", "I", "II", "III", "IV"]
    code, out, _ = run(capsys, "plugins")
    assert "Record readers:" in out and "peer-at2" in out and "usb-pga-h10" in out
