"""``chaplygin derive``: regenerate ``generated/`` (or check that it is up to date)."""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

from chaplygin.derive.errors import UserInputError

from .cli_common import EXIT_FAILED, EXIT_OK, check_output_dir

__all__ = ["add_parser", "run", "generated_dir"]


def generated_dir() -> Path:
    """The ``generated/`` folder of this installation (the repository's, when editable).

    Returns
    -------
    pathlib.Path
    """
    spec = importlib.util.find_spec("chaplygin.generated")
    return Path(next(iter(spec.submodule_search_locations)))


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin derive``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0, or 1 when ``--check`` finds stale files.
    """
    from chaplygin.derive.writer import check_generated, write_generated

    if args.out is None:
        directory = generated_dir()
        if not args.check:
            check_output_dir(str(directory), "derive", "the generated code")
    elif args.check:  # read only: the folder need not be writable (or exist)
        if not args.out.strip():
            raise UserInputError("--out needs a folder name, got an empty one")
        directory = Path(args.out)
    else:
        directory = check_output_dir(args.out, "--out", "the generated code")
    if args.check:
        problems = check_generated(directory)
        if problems:
            print(
                f"generated code in {directory} is stale; run 'chaplygin derive':", file=sys.stderr
            )
            for p in problems:
                print(f"  {p}", file=sys.stderr)
            return EXIT_FAILED
        print(f"generated code in {directory} is up to date")
        return EXIT_OK
    changed = write_generated(directory)
    print(
        f"wrote {len(changed)} file(s) in {directory}"
        + (": " + ", ".join(changed) if changed else "")
    )
    return EXIT_OK


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin derive``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    p = subparsers.add_parser("derive", help="regenerate generated/ (or check it with --check)")
    p.add_argument("--check", action="store_true", help="exit 1 when generated/ is out of date")
    p.add_argument("--out", default=None, help="directory (default: the package's generated/)")
    return p
