"""The ``chaplygin`` command line: verify, derive, integrate.

User errors (unknown names, wrong lengths, non-physical or non-finite values, malformed
numbers) print one line on stderr and exit with status 2; nothing is written.

Each subcommand is a module of this package with ``add_parser(subparsers)`` (returns its
parser) and ``run(args) -> int`` (the exit status); :data:`COMMANDS` lists them in the order
``chaplygin --help`` shows them.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from importlib.metadata import PackageNotFoundError, version

from chaplygin.derive.errors import UserInputError

from . import (
    bench_cmd,
    bifurcation_cmd,
    delta_cmd,
    derive_cmd,
    integrate_cmd,
    rotation_cmd,
    run_cmd,
    verify_cmd,
)
from .cli_common import EXIT_USAGE
from .vocabulary import to_cli

__all__ = ["main", "build_parser", "console", "COMMANDS"]

#: The subcommands, in the order of ``chaplygin --help``.
COMMANDS = (
    verify_cmd,
    derive_cmd,
    integrate_cmd,
    bench_cmd,
    delta_cmd,
    rotation_cmd,
    bifurcation_cmd,
    run_cmd,
)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit 2, no usage dump
        self.exit(EXIT_USAGE, f"chaplygin: error: {message} (see '{self.prog} --help')\n")


def _version() -> str:
    try:
        return version("chaplygin")
    except PackageNotFoundError:  # pragma: no cover - run from a source tree, not installed
        return "unknown (not installed)"


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``chaplygin`` and its subcommands.

    Returns
    -------
    argparse.ArgumentParser
        Parsed arguments carry ``run`` (the subcommand's ``run(args) -> int``).
    """
    parser = _Parser(prog="chaplygin", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for command in COMMANDS:
        command.add_parser(sub).set_defaults(run=command.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``chaplygin`` console script.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 success, 1 a failed check or run, 2 a user error.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except UserInputError as exc:  # the API speaks of arguments, the command line of flags
        print(f"chaplygin: error: {to_cli(str(exc))}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:  # pragma: no cover
        return 130


def console() -> None:
    """Console-script wrapper: exit with :func:`main`'s status."""
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    console()
