"""The experiment's figures as the paper draws them (issue 18) and written safely (issue 16): the models
drawn in each figure, the reference on top, one legend entry per line outside the data, no empty
panel, titles inside the figure, the formats asked for, atomic files; ``[figures] draw`` and
``bearingfw run --figures``."""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import numpy as np
import pytest
from tiny_experiment import write_tiny

from bearingfw.experiment import ProcessExecutor, Progress, SerialExecutor, load_experiment, run_experiment
from bearingfw.experiment.figures import (
    plot_bearing_force,
    plot_friction_ratio,
    plot_heatmap,
    plot_hysteresis,
    plot_stress_histories,
)
from bearingfw.experiment.spec import FIGURE_DRAW, FIGURE_FORMATS, SpecError, parse_experiment
from bearingfw.plotting import FIGURE_FORMATS as PLOTTING_FORMATS
from bearingfw.plotting import Margins, new_figure, save

MODELS = ("M0", "M1", "M2")
BEARINGS = ["1A", "1B", "2B", "3B", "4B", "5B"]
SLIDING = {"1A": [0], "1B": [0, 1], "2B": [1], "3B": [0, 1], "4B": [1], "5B": [0]}


def _cell(seed: int, still: tuple[str, ...] = ()):
    """Synthetic histories of one cell as the store keeps them: stresses at S1 and 3B, six bearings
    (``still`` ones never move nor carry force, as a bearing sliding across a plane motion)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 10.0, 501)
    wave = np.sin(2 * np.pi * (1.5 + 0.1 * seed) * t) * np.exp(-0.2 * t)
    h = {"time": t}
    for e in ("S1", "3B"):
        h[f"stress_dynamic.{e}"] = np.abs(wave) * 1e6 * (1 + seed)
        h[f"stress.{e}"] = 5e6 + wave * 1e6 * (1 + seed)
    force = rng.normal(size=(t.size, len(BEARINGS), 3)) * 1e4 + wave[:, None, None] * 5e4
    displacement = np.cumsum(rng.normal(size=force.shape), axis=0) * 1e-5
    for b in still:
        force[:, BEARINGS.index(b)] = 0.0
        displacement[:, BEARINGS.index(b)] = 0.0
    h["bearings.force"] = force
    h["bearings.displacement"] = displacement
    h["bearings.friction_ratio"] = np.clip(np.abs(wave) * 0.05, 0, 0.04)
    h["bearings.friction_ratio"] = np.repeat(h["bearings.friction_ratio"][:, None], len(BEARINGS), axis=1)
    return h, {"bearings": BEARINGS, "sliding": SLIDING}


CELLS = {m: _cell(k) for k, m in enumerate(MODELS)}


def _lines(ax):
    """The model lines of an axes (labelled), as (label, gid, zorder)."""
    return [(line.get_label(), line.get_gid(), line.get_zorder()) for line in ax.get_lines()
            if not line.get_label().startswith("_")]


def _legend_texts(figure) -> list[str]:
    assert not any(ax.get_legend() for ax in figure.axes), "a legend inside an axes covers data"
    assert len(figure.legends) == 1
    return [t.get_text() for t in figure.legends[0].get_texts()]


def _renderer(figure):
    return figure.canvas.get_renderer()


def _outside_every_axes(figure) -> None:
    """The legend's box overlaps no axes' box (it never covers data) and lies inside the figure."""
    renderer = _renderer(figure)
    box = figure.legends[0].get_window_extent(renderer)
    for ax in figure.axes:
        assert not box.overlaps(ax.get_window_extent(renderer)), ax.get_title()
    assert figure.bbox.contains(box.x0, box.y0) and figure.bbox.contains(box.x1, box.y1)


def _inside_figure(figure, artist) -> None:
    box = artist.get_window_extent(_renderer(figure))
    assert box.x0 >= 0 and box.y0 >= 0 and box.x1 <= figure.bbox.width and box.y1 <= figure.bbox.height, box


def test_stress_figure_shows_the_compared_models_reference_on_top_legend_outside():
    figure = plot_stress_histories(CELLS, ["S1", "3B"], "Maximum principal stress: tremor, D_0",
                                   synthetic=True, reference="M2")
    assert len(figure.axes) == 4
    for ax in figure.axes:
        drawn = _lines(ax)
        assert [label for label, _, _ in drawn] == list(MODELS) and [gid for _, gid, _ in drawn] == list(MODELS)
        zorder = {label: z for label, _, z in drawn}
        assert zorder["M2"] > max(zorder["M0"], zorder["M1"])  # the reference never disappears under the others
    assert _legend_texts(figure) == list(MODELS)  # one entry per model, not one per panel
    _outside_every_axes(figure)
    _inside_figure(figure, figure._suptitle)
    caption = " ".join(figure._suptitle.get_text().split())
    assert "σ1 of the ground motion's own stress state" in caption and "≥ 0 by definition" in caption  # says why
    assert "SYNTHETIC" in figure._suptitle.get_text()
    # the right-hand panels show the compared metric, non-negative; the left ones the signed total
    left, right = figure.axes[0], figure.axes[1]
    assert right.get_title().endswith("ground motion's part") and left.get_title().endswith("total")
    assert min(line.get_ydata().min() for line in right.get_lines()) >= 0.0


def test_only_the_models_given_are_drawn():
    chosen = {m: CELLS[m] for m in ("M1", "M2")}
    figure = plot_bearing_force(chosen, "3B", "Force in bearing 3B", reference="M2")
    for ax in figure.axes:
        assert [label for label, _, _ in _lines(ax)] == ["M1", "M2"]
    assert _legend_texts(figure) == ["M1", "M2"]
    _outside_every_axes(figure)


def test_bearing_force_has_no_flat_panel():
    flat = {m: _cell(k, still=("3B",)) for k, m in enumerate(MODELS)}
    for h, _ in flat.values():
        h["bearings.force"][:, BEARINGS.index("1B"), 1] = 0.0  # nothing across: y of 1B carries no force
    figure = plot_bearing_force(flat, "1B", "Force in bearing 1B", reference="M2")
    assert len(figure.axes) == 1 and figure.axes[0].get_ylabel().startswith("Fx")
    assert "no force in y (not drawn)" in figure._suptitle.get_text()


def test_friction_ratio_has_one_mu_line_per_value_and_no_duplicate_entries():
    cells = {"M2": CELLS["M2"], "bouc-wen": CELLS["M1"]}
    figure = plot_friction_ratio(cells, "3B", {"M2": 0.04, "bouc-wen": 0.04}, "Friction ratio", reference="M2")
    texts = _legend_texts(figure)
    assert texts == ["M2", "bouc-wen", "mu = 0.04 (M2, bouc-wen)"]
    assert len(texts) == len(set(texts))
    mu_lines = [line for line in figure.axes[0].get_lines() if line.get_gid() == "mu=0.04"]
    assert len(mu_lines) == 1 and np.allclose(mu_lines[0].get_ydata(), 0.04)
    _outside_every_axes(figure)
    # two values: two lines, each naming its model
    figure = plot_friction_ratio(cells, "3B", {"M2": 0.04, "bouc-wen": 0.05}, "Friction ratio")
    assert _legend_texts(figure)[2:] == ["mu = 0.04 (M2)", "mu = 0.05 (bouc-wen)"]


def test_hysteresis_sheet_has_no_empty_panel():
    figure = plot_hysteresis(_cell(0, still=("2B",)), "Bearing hysteresis, M2: tremor, D_II", synthetic=True)
    titles = [ax.get_title() for ax in figure.axes]
    assert titles == ["1A", "1B", "3B", "4B", "5B"]  # 2B never moved: not an empty panel but named in the title
    assert "no force and no movement at 2B" in figure._suptitle.get_text()
    for ax in figure.axes:
        lines = ax.get_lines()
        assert lines and all(np.ptp(line.get_xdata()) > 0 and np.ptp(line.get_ydata()) > 0 for line in lines)
        assert ax.get_legend() is None
    assert sorted(_legend_texts(figure)) == ["x direction", "y direction"]
    _outside_every_axes(figure)
    _inside_figure(figure, figure._suptitle)


def test_a_long_title_is_wrapped_inside_the_figure(tmp_path):
    title = "Maximum principal stress: " + "a-very-long-record-name-from-a-real-station " * 4 + ", D_IV"
    figure = plot_stress_histories(CELLS, ["S1"], title, reference="M2")
    assert figure._suptitle.get_text().count("\n") >= 2  # the title took two lines, the caption one
    _inside_figure(figure, figure._suptitle)
    # the commands' figures (constrained layout) are wrapped by save() too
    wide = new_figure(4.0, 3.0)
    wide.subplots().plot([0, 1])
    wide.suptitle("Response spectra (5% damping): " + "a long real record title " * 5, fontsize=10)
    save(wide, tmp_path, "wide", ("png",))
    _inside_figure(wide, wide._suptitle)


def test_heatmap_labels_and_title_fit():
    from bearingfw.experiment.matrices import Matrices

    matrices = _matrices()
    assert isinstance(matrices, Matrices)
    figure = plot_heatmap(matrices, "stress_dynamic.S1")
    renderer = _renderer(figure)
    ax = figure.axes[0]
    for label in (*ax.get_yticklabels(), *ax.get_xticklabels(), ax.title):
        _inside_figure(figure, label)
    assert [t.get_text() for t in ax.get_yticklabels()] == ["M0", "M1", "M2", "bouc-wen"]
    assert renderer is not None


def _matrices():
    from bearingfw.experiment.matrices import collect_matrices
    from bearingfw.experiment.metrics import metric_families

    documents = []
    for k, model in enumerate(("M0", "M1", "M2", "bouc-wen")):
        for j, level in enumerate(("D_0", "D_II")):
            documents.append({"id": f"{model}/r/{level}", "model": model, "record": "r", "intensity": level,
                              "status": "ok", "metrics": {"stress_dynamic.S1": {
                                  "value": 1e6 * (1 + k) * (1 + j), "unit": "Pa", "time": 1.0, "at": None}}})
    return collect_matrices(documents, ("M0", "M1", "M2", "bouc-wen"), ("r",), ("D_0", "D_II"), "M2", "ec8",
                            metric_families())


def test_pixel_sizes_stay_sensible(tmp_path):
    import matplotlib.image

    figure = plot_stress_histories(CELLS, ["S1", "3B"], "Maximum principal stress", reference="M2")
    png = save(figure, tmp_path, "stress", ("png",), dpi=100)[0]
    height, width = matplotlib.image.imread(png).shape[:2]
    assert (width, height) == (1200, 620)  # 12 x 6.2 in at 100 dpi: legible, and not a poster


# ---- writing ---------------------------------------------------------------------------------------------
def test_save_writes_only_the_formats_asked_for(tmp_path):
    figure = plot_friction_ratio({"M2": CELLS["M2"]}, "3B", {"M2": 0.04}, "Friction ratio")
    paths = save(figure, tmp_path, "friction", ("pdf", "svg"))
    assert [p.name for p in paths] == ["friction.pdf", "friction.svg"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["friction.pdf", "friction.svg"]
    assert paths[0].read_bytes().startswith(b"%PDF") and b"<svg" in paths[1].read_bytes()[:1000]
    with pytest.raises(ValueError, match="figure format 'gif': the formats are png, svg, pdf"):
        save(figure, tmp_path, "friction", ("gif",))
    assert FIGURE_FORMATS == PLOTTING_FORMATS  # the spec's list (no matplotlib import there) is plotting's


@pytest.mark.parametrize("interruption", [KeyboardInterrupt, OSError])
def test_an_interrupted_save_leaves_no_partial_file(tmp_path, interruption):
    figure = new_figure(3.0, 2.0, margins=Margins())
    figure.subplots().plot([0, 1], [0, 1])
    Margins().apply(figure)
    old = save(figure, tmp_path, "kept", ("png",))[0].read_bytes()

    def failing(target, **kwargs):  # a writer that dies half-way through the file
        target.write(b"\x89PNG half a figure")
        raise interruption("stop")

    figure.savefig = failing
    with pytest.raises(interruption):
        save(figure, tmp_path, "kept", ("png",))
    with pytest.raises(interruption):
        save(figure, tmp_path, "new", ("png",))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.png"]  # no temporary, no half of new.png
    assert (tmp_path / "kept.png").read_bytes() == old  # the previous figure stands whole


# ---- [figures] draw and formats, --figures -----------------------------------------------------------------
BASE = 'name = "x"\n[models.M2]\npreset = "M2"\n[records.r]\nseed = 0\n'


@pytest.mark.parametrize(("given", "draw"), [("", "report"), ("draw = true", "report"), ("draw = false", "none"),
                                             ('draw = "all"', "all"), ('draw = "None"', "none")])
def test_draw_takes_a_choice_and_the_older_true_false(given, draw):
    assert parse_experiment(BASE + f"[figures]\n{given}\n").figures.draw == draw
    assert draw in FIGURE_DRAW


@pytest.mark.parametrize(("given", "message"), [
    ('draw = "some"', "figures.draw: field 'draw' must be true or false, or one of 'none', 'report', 'all'"),
    ('formats = ["gif"]', "figures.formats: field 'formats' must list figure formats among 'png', 'svg', 'pdf'"),
    ("formats = []", "figures.formats: field 'formats' must list figure formats among 'png', 'svg', 'pdf'; none"),
    ('formats = ["png", "PNG"]', "figures.formats: field 'formats' names a format twice"),
])
def test_bad_figure_settings_name_the_field_and_what_is_allowed(given, message):
    with pytest.raises(SpecError, match="^x.toml: " + message.replace("(", r"\(").replace("[", r"\[")):
        parse_experiment(BASE + f"[figures]\n{given}\n", origin="x.toml")


def test_formats_default_to_png_and_take_svg_pdf():
    assert parse_experiment(BASE).figures.formats == ("png",)
    assert parse_experiment(BASE + '[figures]\nformats = ["SVG", "pdf"]\n').figures.formats == ("svg", "pdf")
    assert parse_experiment(BASE + '[figures]\nformats = "svg"\n').figures.formats == ("svg",)


def _cli_experiment(*args):
    from bearingfw.cli import run as run_cli

    parser = argparse.ArgumentParser()
    run_cli.add_parser(parser.add_subparsers())
    return run_cli._experiment(parser.parse_args(["run", *args]))


def test_the_figures_option_overrides_the_file(tmp_path):
    path = tmp_path / "e.toml"
    path.write_text(BASE + '[figures]\ndraw = "all"\n')
    assert _cli_experiment(str(path)).figures.draw == "all"
    assert _cli_experiment(str(path), "--figures", "none").figures.draw == "none"
    assert _cli_experiment(str(path), "--figures", "report").figures.draw == "report"
    assert _cli_experiment(str(path), "--no-figures").figures.draw == "none"
    from bearingfw.parameters import ParameterError

    with pytest.raises(ParameterError, match="--no-figures and --figures all contradict"):
        _cli_experiment(str(path), "--no-figures", "--figures", "all")


# ---- in a run ----------------------------------------------------------------------------------------------
def test_a_run_draws_the_report_figures_in_png_and_reports_each(tmp_path):
    """Default [figures]: the figures the report shows (no hysteresis sheets), PNG only, each on the
    progress display; an intensity's figures are drawn as soon as its cells are done, while the
    other intensity's cells run (the last cell sleeps in its law, so that the overlap does not depend
    on how fast the machine is)."""
    path = write_tiny(tmp_path / "spec", models=("M1", "M2", "slow"), levels=("D_0", "D_II"), figures=True, delay=1e-3)
    stream = io.StringIO()
    # one worker: the cells in plan order (model by model), so D_0 is complete before the last cell, slow at D_II
    summary = run_experiment(load_experiment(path), tmp_path / "out", ProcessExecutor(1), progress=Progress(stream))
    names = sorted(Path(p).name for p in summary.files["figures"])
    assert all(n.endswith(".png") for n in names) and not any(n.startswith("hysteresis") for n in names)
    assert {"stress_tremor_D_0.png", "bearing-force_1B_tremor_D_0.png", "friction-ratio_1B_tremor_D_0.png",
            "intensity-chart.png", "heatmap_stress.G4.png"} <= set(names)
    folder = tmp_path / "out" / "figures"
    assert sorted(p.name for p in folder.iterdir()) == sorted([*names, "index.json"])  # no SVG, no temporary
    lines = stream.getvalue().splitlines()
    drawn = [line for line in lines if line.startswith("[figure ")]
    assert len(drawn) == len(names)
    order = [line.split()[2] for line in drawn]
    assert order.index("stress_tremor_D_0") < order.index("heatmap_stress.G4")
    first_figure = next(k for k, line in enumerate(lines) if line.startswith("[figure "))
    last_cell = next(k for k, line in enumerate(lines) if line.startswith("[6/6]"))
    assert first_figure < last_cell and "stress_tremor_D_0" in lines[first_figure]  # overlapped with the cells
    assert f"{len(names)} figure(s) drawn" in lines[-1]
    report = (tmp_path / "out" / "report.md").read_text()
    assert "![stress_tremor_D_0](figures/stress_tremor_D_0.png)" in report


def test_ctrl_c_while_drawing_leaves_no_partial_figure(tmp_path, monkeypatch):
    """Interrupted in the middle of writing a figure file, the run stops and leaves no part of a file."""
    from matplotlib.figure import Figure

    path = write_tiny(tmp_path / "spec", models=("M1",), levels=("D_0",), figures=True)
    experiment = load_experiment(path)
    run_experiment(experiment, tmp_path / "out", SerialExecutor(), models=("M1",))  # the cell, and its figures
    folder = tmp_path / "out" / "figures"
    before = {p.name: p.read_bytes() for p in folder.iterdir() if p.suffix == ".png"}
    calls = []
    real = Figure.savefig

    def interrupted(self, target, **kwargs):
        calls.append(1)
        if len(calls) == 3:  # the third file: half written, then Ctrl-C
            target.write(b"\x89PNG half")
            raise KeyboardInterrupt
        return real(self, target, **kwargs)

    monkeypatch.setattr(Figure, "savefig", interrupted)
    (folder / "index.json").unlink()  # every figure is drawn again
    with pytest.raises(KeyboardInterrupt):
        run_experiment(experiment, tmp_path / "out", SerialExecutor())
    assert len(calls) == 3
    assert not [p.name for p in (tmp_path / "out").rglob(".partial-*")]
    for p in folder.iterdir():
        if p.suffix == ".png":
            assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", p.name  # whole files only
    assert {p.name for p in folder.iterdir() if p.suffix == ".png"} == set(before)  # none lost, none half made


def test_the_report_links_one_file_per_figure_png_first():
    from types import SimpleNamespace

    from bearingfw.experiment.report import _pngs

    folder = Path("out/figures")
    data = SimpleNamespace(figures=(folder / "stress_r_D_0.svg", folder / "stress_r_D_0.png",
                                    folder / "heatmap_stress.S1.pdf", folder / "heatmap_stress.S1.svg"))
    assert _pngs(data, "") == [folder / "stress_r_D_0.png", folder / "heatmap_stress.S1.pdf"]
    assert _pngs(data, "heatmap_stress.S1.") == [folder / "heatmap_stress.S1.pdf"]


def test_progress_reports_each_figure_on_its_own_line():
    stream = io.StringIO()
    progress = Progress(stream)
    progress.begin(["M1", "M2"], 0, "processes", 2)
    progress.figure("stress_tremor_D_0", 0.42)
    progress.figure("heatmap_stress.S1", 0.1)
    lines = stream.getvalue().splitlines()
    assert lines[1].startswith("[figure 1] stress_tremor_D_0 (0.4 s) | cells 0/2 | elapsed ")
    assert lines[2].startswith("[figure 2] heatmap_stress.S1 (0.1 s) | cells 0/2")
    assert progress.figures == 2
    quiet = Progress(io.StringIO(), quiet=True)
    quiet.figure("x", 1.0)
    assert quiet.figures == 1 and quiet.stream.getvalue() == ""


def test_the_model_on_top_is_the_reference_if_compared_else_the_first_compared(tmp_path):
    import attrs

    from bearingfw.experiment.runner import check_experiment, figure_plan

    experiment = load_experiment(write_tiny(tmp_path / "spec", figures=True))  # reference M1, compare M1, M2
    checked = check_experiment(experiment)
    plan = figure_plan(experiment, checked, None)
    assert (plan["reference"], plan["compare"], plan["draw"], plan["formats"]) == ("M1", ("M1", "M2"), "report", ("png",))
    other = attrs.evolve(experiment, figures=attrs.evolve(experiment.figures, compare=("M2", "M0")))
    assert figure_plan(other, checked, None)["reference"] == "M2"
