"""The ``chaplygin`` command line: verify, derive, integrate.

User errors (unknown names, wrong lengths, non-physical or non-finite values, malformed
numbers, unwritable output paths, work beyond a flag's documented bound) print one line on
stderr and exit with status 2; they are found before any work, so nothing is written. An
error of the system met while working (a full disk, a file removed meanwhile: any
``OSError``) is one line and status 1. Anything else is a bug: one "internal error" line
saying where to report it and status 3; ``--debug`` shows its traceback.

Each subcommand is a module of this package with ``add_parser(subparsers)`` (returns its
parser) and ``run(args) -> int`` (the exit status); :data:`COMMANDS` lists them in the order
``chaplygin --help`` shows them. A command module imports at its top only the standard library,
the command-line helpers and ``chaplygin.derive.errors``; the work (sympy, numpy, the numerics,
matplotlib, Dask) is imported inside ``run``, so ``--help`` and ``--version`` build the parser
without it (``tests/verify/test_cli_imports.py``).
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Sequence
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from chaplygin.derive.errors import UserInputError

from . import (
    bench_cmd,
    bifurcation_cmd,
    delta_cmd,
    derive_cmd,
    discover_cmd,
    integrate_cmd,
    rotation_cmd,
    run_cmd,
    sweep_cmd,
    verify_cmd,
)
from .cli_common import EXIT_FAILED, EXIT_INTERNAL, EXIT_USAGE, printable
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
    sweep_cmd,
    discover_cmd,
)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit 2, no usage dump
        message = " ".join(message.split())
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
    parser.add_argument("--debug", action="store_true", help=_DEBUG_HELP)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for command in COMMANDS:
        p = command.add_parser(sub)
        # also accepted after the subcommand; SUPPRESS keeps a --debug given before it
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help=_DEBUG_HELP)
        p.set_defaults(run=command.run)
    return parser


_DEBUG_HELP = "show the traceback of an internal error"

#: Where an internal error is to be reported (printed with it).
REPORT_TO = (
    "please report it to the chaplygin developers (the project's issue tracker) with the "
    "command line and 'chaplygin --version'"
)


def _internal_error(exc: BaseException, debug: bool) -> int:
    frames = traceback.extract_tb(exc.__traceback__) if exc.__traceback__ else []
    where = ""
    if frames:
        # the innermost frame of this project (the place to look), and the raising one
        ours = {Path(m.__file__).parent for n, m in list(sys.modules.items())
                if n.startswith("chaplygin.") and getattr(m, "__file__", None)}
        mine = [f for f in frames if Path(f.filename).parent in ours] or frames
        where = f" at {Path(mine[-1].filename).name}:{mine[-1].lineno}"
        if mine[-1] is not frames[-1]:
            where += f" (raised in {Path(frames[-1].filename).name}:{frames[-1].lineno})"
    if debug:
        traceback.print_exception(exc, file=sys.stderr)
    message = " ".join(str(exc).split())[:200]
    hint = "" if debug else "; rerun with --debug for the traceback"
    print(
        printable(
            f"chaplygin: internal error: {type(exc).__name__}{': ' if message else ''}{message}"
            f"{where}; {REPORT_TO}{hint}",
            keep="",
        ),
        file=sys.stderr,
    )
    return EXIT_INTERNAL


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``chaplygin`` console script.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 success, 1 a failed check or run (or an error of the system
        while working), 2 a user error, 3 an internal error (a bug).
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error already printed
        return exc.code if isinstance(exc.code, int) else EXIT_USAGE
    try:
        return args.run(args)
    except UserInputError as exc:  # the API speaks of arguments, the command line of flags
        message = printable(to_cli(" ".join(str(exc).split())), keep="")
        print(f"chaplygin: error: {message}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        if args.debug:
            traceback.print_exception(exc, file=sys.stderr)
        name = f"{exc.filename}: " if exc.filename else ""
        print(printable(f"chaplygin: error: {name}{exc.strerror or exc}", keep=""), file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:  # pragma: no cover
        print("chaplygin: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # the last resort: a bug, never a bare traceback
        return _internal_error(exc, args.debug)


def console() -> None:
    """Console-script wrapper: exit with :func:`main`'s status."""
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    console()
