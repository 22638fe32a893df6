"""One exit-status convention for every command (bearingfw.cli.main's docstring), a quiet end when the
reader of the output leaves, OS errors that name their path, and warnings reported once.

The subprocess tests run the installed ``bearingfw`` as a user would; each failed on the code before
the convention (a BrokenPipeError traceback and status 1, "[Errno 28]" alone, raw warnings).
"""

from __future__ import annotations

import errno
import re
import subprocess
import sys
from pathlib import Path

import pytest

from bearingfw.cli import main as cli
from bearingfw.cli.main import main

BEARINGFW = [sys.executable, "-m", "bearingfw"]
#: How Python prints a warning that nobody caught: "path.py:12: RuntimeWarning: ...".
RAW_WARNING = re.compile(r"^\S+:\d+: \w*Warning: ", re.MULTILINE)


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_the_codes_are_the_documented_ones():
    assert (cli.OK, cli.RESULTS_FAILED, cli.INPUT_ERROR, cli.ENVIRONMENT_ERROR, cli.INTERNAL_ERROR) == (0, 1, 2, 3, 4)
    assert (cli.INTERRUPTED, cli.BROKEN_PIPE) == (130, 141)
    meanings = {0: "success", 1: "the work ran to its end, but some results failed", 2: "bad input",
                3: "the environment refused", 4: "internal error", 130: "interrupted",
                141: "standard output was closed by its reader"}
    for code, meaning in meanings.items():
        assert re.search(rf"^{code}\s+{meaning}", cli.__doc__, re.MULTILINE), (code, meaning)


# -- the reader of the output leaves ----------------------------------------------------------------


@pytest.mark.parametrize("argv", [["plugins"], ["record", "info", "--synthetic", "1", "--json"]],
                         ids=["plugins", "record-info-json"])
def test_a_closed_pipe_ends_quietly_with_141(argv):
    # The read end is closed before the command writes, so every write fails (`| head -c 0`, deterministic).
    process = subprocess.Popen([*BEARINGFW, *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    process.stdout.close()
    err = process.stderr.read().decode()
    assert process.wait(timeout=120) == 141
    assert err == ""  # no traceback, no "Exception ignored" at exit


# -- bad input: 2, for every command ----------------------------------------------------------------


@pytest.mark.parametrize(
    "argv, message",
    [
        (["record", "info", "{tmp}/missing.AT2"], "missing.AT2: no such file"),
        (["record", "info", "{tmp}"], "is a directory, not a record file"),
        (["record", "info", "--synthetic", "1", "--plot", "/dev/null/figures"], "/dev/null/figures: Not a directory"),
        (["oma", "{tmp}/missing.csv"], "missing.csv"),
        (["modal", "--modes", "0"], "--modes must be an integer >= 1, got 0"),
        (["tune", "--option", "span=20"], "apply to --structure"),
        (["tune", "--measured", "{tmp}/junk.json"], "junk.json: not UTF-8 text (byte b'\\xff' at offset 0)"),
    ],
    ids=["record-missing", "record-directory", "record-plot-path", "oma-missing", "modal-value", "tune-option",
         "tune-not-utf8"],
)
def test_bad_input_is_2_with_one_line(capsys, tmp_path, argv, message):
    (tmp_path / "junk.json").write_bytes(b"\xff\xfe{\x80 junk")
    code, out, err = run(capsys, *[a.replace("{tmp}", str(tmp_path)) for a in argv])
    assert code == 2 and message in err and out == "", err
    assert err.count("\n") == 1 and err.startswith(f"bearingfw {argv[0]}")  # one line, no traceback


def test_a_usage_error_is_argparse_2(capsys):
    with pytest.raises(SystemExit) as ended:
        main(["plugins", "--bogus"])
    assert ended.value.code == 2
    assert "unrecognized arguments: --bogus" in capsys.readouterr().err


# -- the environment refuses: 3, naming the path --------------------------------------------------------


def test_a_full_disk_under_the_output_is_3_and_says_standard_output(tmp_path):
    with open("/dev/full", "w") as full:
        done = subprocess.run([*BEARINGFW, "plugins"], stdout=full, stderr=subprocess.PIPE, text=True, timeout=120)
    assert done.returncode == 3
    assert done.stderr == "bearingfw plugins: error: standard output: No space left on device\n"


def test_a_full_disk_under_a_figure_names_the_option_and_directory(tmp_path):
    figures = tmp_path / "figures"
    figures.mkdir()
    (figures / "synthetic-seed1_acceleration.png").symlink_to("/dev/full")  # the first figure written
    done = subprocess.run([*BEARINGFW, "record", "info", "--synthetic", "1", "--plot", str(figures)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 3
    assert done.stderr.strip() == f"bearingfw record info: error: No space left on device (while writing --plot {figures})"
    assert "Errno" not in done.stderr


def test_a_refused_write_names_the_path_and_is_3(capsys, tmp_path, monkeypatch):
    import bearingfw.motion.plot

    target = tmp_path / "figures" / "x.png"

    def refused(*args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied", str(target))

    monkeypatch.setattr(bearingfw.motion.plot, "write_figures", refused)
    code, out, err = run(capsys, "record", "info", "--synthetic", "1", "--plot", tmp_path / "figures")
    assert code == 3 and err == f"bearingfw record info: error: {target}: Permission denied\n" and out == ""

    def read_only(*args, **kwargs):  # an error at close: no path in it
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(bearingfw.motion.plot, "write_figures", read_only)
    code, _, err = run(capsys, "record", "info", "--synthetic", "1", "--plot", tmp_path / "ro")
    assert code == 3
    assert err == f"bearingfw record info: error: Read-only file system (while writing --plot {tmp_path / 'ro'})\n"


# -- results that failed: 1; a bug: 4; Ctrl-C: 130 ----------------------------------------------------


def test_a_plugin_that_failed_to_load_makes_plugins_exit_1(capsys, monkeypatch):
    import importlib.metadata as metadata

    import bearingfw.cli.plugins as command
    from bearingfw.plugins import load_registry

    registry = load_registry([
        *metadata.entry_points(group="bearingfw", name="builtin-laws"),
        metadata.EntryPoint("no-such-plugin", "no_such_module_anywhere", "bearingfw"),
    ])
    assert [b.plugin for b in registry.broken] == ["no-such-plugin"]
    monkeypatch.setattr(command, "get_registry", lambda: registry)
    code, out, _ = run(capsys, "plugins")
    assert code == 1 and "Broken plugins (not loaded):" in out and "no-such-plugin" in out
    code, out, _ = run(capsys, "plugins", "--json")
    assert code == 1 and '"no-such-plugin"' in out


@pytest.mark.parametrize(
    "raised, code, last_line",
    [
        (KeyboardInterrupt(), 130, "bearingfw modal: interrupted"),
        (ZeroDivisionError("division by zero"), 4, "bearingfw modal: internal error (a bug in bearingfw or a plugin; "
                                                   "please report it with the traceback above): ZeroDivisionError: "
                                                   "division by zero"),
    ],
    ids=["interrupt", "bug"],
)
def test_interrupts_and_bugs(capsys, monkeypatch, raised, code, last_line):
    import bearingfw.cli.modal as command

    def fail(*args, **kwargs):
        raise raised

    monkeypatch.setattr(command, "modal_data", fail)
    got, out, err = run(capsys, "modal", "--modes", "3")
    assert got == code and err.rstrip().splitlines()[-1] == last_line and out == ""
    assert ("Traceback (most recent call last)" in err) == (code == 4)  # a bug keeps its traceback for the report


def test_running_out_of_memory_is_3(capsys, monkeypatch):
    import bearingfw.cli.modal as command

    def fail(*args, **kwargs):
        raise MemoryError("Unable to allocate 146. TiB")

    monkeypatch.setattr(command, "modal_data", fail)
    code, _, err = run(capsys, "modal")
    assert code == 3 and err == "bearingfw modal: error: not enough memory (Unable to allocate 146. TiB)\n"


def test_a_computation_that_did_not_converge_is_1(capsys, monkeypatch):
    import bearingfw.cli.modal as command
    from bearingfw.analysis.static import ConvergenceError

    def fail(*args, **kwargs):
        raise ConvergenceError("no equilibrium after 50 iterations")

    monkeypatch.setattr(command, "modal_data", fail)
    code, _, err = run(capsys, "modal")
    assert code == 1 and err == "bearingfw modal: failed: no equilibrium after 50 iterations\n"


# -- warnings: once each, not raw --------------------------------------------------------------------

OVERFLOWING_PLUGINS = """
import sys
import numpy as np
import bearingfw.cli.plugins as command
from bearingfw.cli.main import main

listing = command.listing

def overflowing():
    np.float64(1e308) * np.arange(1.0, 3.0)  # "overflow encountered in multiply" here ...
    np.float64(1e308) * np.arange(2.0, 4.0)  # ... and here: one message, reported once
    return listing()

command.listing = overflowing
sys.exit(main(["plugins", "--json"]))
"""


def test_warnings_are_reported_once_each_and_not_raw():
    done = subprocess.run([sys.executable, "-c", OVERFLOWING_PLUGINS], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.startswith("{")
    assert not RAW_WARNING.search(done.stderr), done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("bearingfw plugins: warning: overflow encountered in multiply (RuntimeWarning in ")


def test_warnings_come_before_the_error_line(capsys, monkeypatch):
    import warnings

    import bearingfw.cli.modal as command
    from bearingfw.parameters import ParameterError

    def warn_then_fail(*args, **kwargs):
        for _ in range(2):
            warnings.warn("a slow convergence", RuntimeWarning, stacklevel=1)
        raise ParameterError("--ks must be > 0")

    monkeypatch.setattr(command, "modal_data", warn_then_fail)
    code, _, err = run(capsys, "modal")
    assert code == 2
    warning, error = err.splitlines()
    assert warning.startswith("bearingfw modal: warning: a slow convergence (RuntimeWarning in ")
    assert warning.endswith(f"{Path(__file__).name}:{warn_then_fail.__code__.co_firstlineno + 2})")
    assert error == "bearingfw modal: error: --ks must be > 0"
