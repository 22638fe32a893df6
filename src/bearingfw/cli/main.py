"""The ``bearingfw`` command: one sub-command per module in this package.

Each command module has ``add_parser(subparsers)``, which adds its parser and sets
``func(args) -> int`` (the exit code) as the parser's default. A command returns 0 or
:data:`RESULTS_FAILED`, or raises: :func:`main` turns what it raises into a one-line message and
the exit status below, the same for every command.

Exit status
-----------

=====  =========================================================================================
0      success: the work was done and its results passed their checks
1      the work ran to its end, but some results failed or are suspect, and the output says which
       (``run``: a cell failed or did not pass its acceptance checks; ``plugins``: a plugin failed
       to load; any command: a computation that did not converge)
2      bad input: an unknown option or a wrong value (argparse's usage errors included), a missing
       or malformed input file, a path that names nothing usable, an unknown name. Rerunning the
       same command fails again: fix the command line or the file
3      the environment refused: an output that cannot be written (disk full, read-only file
       system, permission denied), an executor that cannot be reached, not enough memory. The
       same command can succeed once that is fixed
4      internal error: a bug in bearingfw or in a plugin; the traceback is printed for a report
130    interrupted (Ctrl-C: 128 + SIGINT)
141    standard output was closed by its reader (``bearingfw plugins | head -1``): the output
       stops quietly, as that of a program ended by SIGPIPE (128 + 13) does
=====  =========================================================================================

Why these: 1 keeps "it ran, look at the results" apart from 2-4, "it did not run"; 2 is
argparse's own status for usage errors, so that every input error has one code whether argparse
or a command finds it; 3 tells a script that retrying can help (2 never does); 4 keeps a crash
from passing for 1; 130 and 141 are what a shell reports for a program ended by those signals,
so that ``set -o pipefail`` scripts treat bearingfw like any other tool.

Messages go to standard error as ``bearingfw COMMAND: error: ...``; an operating-system error
names the path (or the output option) it concerns. Warnings raised while a command runs (a
numerical overflow, say) are collected and printed once each at the end as
``bearingfw COMMAND: warning: ...``; they do not change the exit status.
"""

from __future__ import annotations

import argparse
import errno
import os
import sys
import traceback
import warnings
from pathlib import Path

from bearingfw import __version__
from bearingfw.cli import modal, oma, plugins, record, run, tune

COMMANDS = [plugins, record, oma, modal, tune, run]

#: The exit codes (module docstring).
OK, RESULTS_FAILED, INPUT_ERROR, ENVIRONMENT_ERROR, INTERNAL_ERROR = 0, 1, 2, 3, 4
INTERRUPTED, BROKEN_PIPE = 130, 141

#: An OSError with one of these says that the path given names nothing usable: bad input (2), not
#: a refusal of the environment (3).
_BAD_PATH_ERRNOS = frozenset({errno.ENOENT, errno.ENOTDIR, errno.EISDIR, errno.ENAMETOOLONG, errno.ELOOP, errno.EEXIST})
#: Options that name what a command writes (named when an OS error carries no path).
_OUTPUT_OPTIONS = ("output", "plot", "out")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="bearingfw",
        description="Dynamic analysis of bridges whose bearings are interchangeable models.",
        epilog="exit status: 0 success; 1 it ran, but some results failed or are suspect; 2 bad input (an option, "
        "a value or a file); 3 the environment refused (an output not writable, a full disk, an unreachable "
        "executor, too little memory); 4 internal error (a bug: please report it); 130 interrupted; 141 the reader "
        "of the output closed it",
    )
    parser.add_argument("--version", action="version", version=f"bearingfw {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


#: The exceptions that mean bad input (exit 2), a computation that ran and did not converge
#: (exit 1) or an unreachable executor (exit 3), as (module, class name): looked up among the modules already imported, since an
#: exception of a class can only have been raised once its module was, and importing one here
#: could fail in turn.
_INPUT_ERRORS = (
    ("bearingfw.parameters", "ParameterError"),
    ("bearingfw.motion.errors", "RecordFormatError"),
    ("bearingfw.motion.errors", "UnknownReaderError"),
    ("bearingfw.motion.errors", "UnknownScaleError"),
    ("bearingfw.motion.errors", "IntensityMismatchError"),
    ("bearingfw.plugins.registry", "UnknownLawError"),
    ("bearingfw.plugins.registry", "UnknownPresetError"),
    ("bearingfw.tuning.pairing", "PairingError"),
    ("builtins", "UnicodeDecodeError"),
)
_FAILED_COMPUTATIONS = (
    ("bearingfw.analysis.static", "ConvergenceError"),
    ("bearingfw.analysis.transient", "TransientError"),
)
#: Refusals of the environment besides OSError and MemoryError (exit 3).
_ENVIRONMENT_ERRORS = (("bearingfw.experiment.executors", "ExecutorError"),)


def _is_one_of(exc: BaseException, classes) -> bool:
    for module, name in classes:
        cls = getattr(sys.modules.get(module), name, None)
        if isinstance(cls, type) and isinstance(exc, cls):
            return True
    return False


def _label(args) -> str:
    words = ["bearingfw", getattr(args, "command", None), getattr(args, "record_command", None)]
    return " ".join(w for w in words if w)


def _say(text: str) -> None:
    """A line to stderr, which may itself be closed (then nothing is said)."""
    try:
        print(text, file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass


def _os_error(exc: OSError, args) -> tuple[int, str]:
    """The exit code and message of an OSError: the path it concerns, never a bare ``[Errno N]``."""
    what = exc.strerror or str(exc) or type(exc).__name__
    paths = [str(p) for p in (exc.filename, exc.filename2) if p is not None]
    if paths:
        text = f"{' -> '.join(paths)}: {what}"
    else:  # a failed flush or close carries no path: name what the command was writing
        written = [f"--{option} {getattr(args, option)}" for option in _OUTPUT_OPTIONS if getattr(args, option, None)]
        where = f"while writing {', '.join(written)}" if written else f"operating-system error {exc.errno}"
        text = f"{what} ({where})"
    return (INPUT_ERROR if exc.errno in _BAD_PATH_ERRNOS else ENVIRONMENT_ERROR), text


def _where(message: warnings.WarningMessage) -> str:
    """``package/module.py:line`` of a warning (the part of the path after site-packages or src)."""
    parts = Path(message.filename).parts
    for anchor in ("site-packages", "src"):
        if anchor in parts:
            parts = parts[len(parts) - parts[::-1].index(anchor):]
            break
    return f"{Path(*parts) if parts else message.filename}:{message.lineno}"


def _report_warnings(label: str, caught: list[warnings.WarningMessage]) -> None:
    seen = set()
    for message in caught:
        key = (message.category, str(message.message))
        if key in seen:
            continue
        seen.add(key)
        _say(f"{label}: warning: {message.message} ({message.category.__name__} in {_where(message)})")


class _WatchedStream:
    """Standard output while a command runs: remembers the OS error that writing to it raised, so that
    such an error is told apart from one about a file (and a reader that left, from a broken socket)."""

    def __init__(self, stream):
        self._stream = stream
        self.error: OSError | None = None

    def write(self, text):
        try:
            return self._stream.write(text)
        except OSError as exc:
            self.error = exc
            raise

    def flush(self):
        try:
            return self._stream.flush()
        except OSError as exc:
            self.error = exc
            raise

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _silence_stdout() -> None:
    # The interpreter flushes stdout once more at exit: point it at devnull so that this flush
    # does not print "Exception ignored ... BrokenPipeError" after we have ended quietly.
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # no real file descriptor (captured by a test)
        pass


def _run(args) -> tuple[int, str | None]:
    """The command's exit code and, unless it returned normally, what to say (module docstring)."""
    label = _label(args)
    stdout = sys.stdout = _WatchedStream(sys.stdout)
    try:
        code = args.func(args)
        sys.stdout.flush()  # a reader that left shows here, not in the interpreter's last flush
        return code, None
    except KeyboardInterrupt:
        return INTERRUPTED, f"\n{label}: interrupted"
    except Exception as exc:  # noqa: BLE001 - every exception gets a status and a message
        if isinstance(exc, OSError) and exc is stdout.error:
            _silence_stdout()
            if isinstance(exc, BrokenPipeError):  # the reader left: end quietly
                return BROKEN_PIPE, None
            return ENVIRONMENT_ERROR, f"{label}: error: standard output: {exc.strerror or exc}"
        if isinstance(exc, OSError):
            code, text = _os_error(exc, args)
            return code, f"{label}: error: {text}"
        if isinstance(exc, MemoryError):  # the inputs are bounded: this machine is short of memory
            return ENVIRONMENT_ERROR, f"{label}: error: not enough memory" + (f" ({exc})" if str(exc) else "")
        if _is_one_of(exc, _ENVIRONMENT_ERRORS):
            return ENVIRONMENT_ERROR, f"{label}: error: {exc}"
        if _is_one_of(exc, _INPUT_ERRORS):
            return INPUT_ERROR, f"{label}: error: {exc}"
        if _is_one_of(exc, _FAILED_COMPUTATIONS):
            return RESULTS_FAILED, f"{label}: failed: {exc}"
        return INTERNAL_ERROR, (
            "".join(traceback.format_exception(exc)).rstrip()
            + f"\n{label}: internal error (a bug in bearingfw or a plugin; please report it with the traceback "
            f"above): {type(exc).__name__}: {exc}"
        )
    finally:
        sys.stdout = stdout._stream


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return INPUT_ERROR
    with warnings.catch_warnings(record=True) as caught:
        code, message = _run(args)
    _report_warnings(_label(args), caught)  # before the error: the last line says how it ended
    if message:
        _say(message)
    return code


if __name__ == "__main__":
    sys.exit(main())
