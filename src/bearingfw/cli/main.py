"""The ``bearingfw`` command: one sub-command per module in this package.

Each command module has ``add_parser(subparsers)``, which adds its parser and sets
``func(args) -> int`` (the exit code) as the parser's default.
"""

from __future__ import annotations

import argparse
import sys

from bearingfw import __version__
from bearingfw.cli import modal, oma, plugins, record, run, tune

COMMANDS = [plugins, record, oma, modal, tune, run]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="bearingfw",
        description="Dynamic analysis of bridges whose bearings are interchangeable models.",
    )
    parser.add_argument("--version", action="version", version=f"bearingfw {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
