"""``chaplygin bench``: the work-precision study of issue 5 §4 (table, plot, JSON)."""

from __future__ import annotations

import argparse
import sys

from chaplygin.derive.errors import UserInputError

from .cli_common import EXIT_OK, add_quiet, check_output_dir, json_text

__all__ = ["add_parser", "run", "MAX_REPEATS"]

#: Most runs per row 'chaplygin bench --repeats' accepts.
MAX_REPEATS = 100


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin bench``: write ``bench.md``, ``bench.png`` and ``bench.json``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0.
    """
    from .bench import PROBLEMS, run_study
    from .bench_report import render_markdown
    from .plots import work_precision_figure

    out = check_output_dir(args.out, "--out", "the study")
    problems = [p.strip() for p in args.problems.split(",") if p.strip()]
    bad = [p for p in problems if p not in PROBLEMS]
    if bad or not problems:
        raise UserInputError(
            f"unknown problem {bad[0] if bad else args.problems!r}; valid: {', '.join(PROBLEMS)}"
        )
    if args.repeats is not None and not 1 <= args.repeats <= MAX_REPEATS:
        raise UserInputError(
            f"--repeats must be a whole number in 1..{MAX_REPEATS}, got {args.repeats}"
        )

    def progress(msg: str) -> None:
        if not (args.json or args.quiet):
            print(f"  {msg}", file=sys.stderr, flush=True)

    study = run_study(
        out, quick=args.quick, repeats=args.repeats, problems=problems, progress=progress
    )
    table = render_markdown(study)
    (out / "bench.md").write_text(table)
    work_precision_figure(study).savefig(out / "bench.png", dpi=110)
    (out / "bench.json").write_text(json_text(study, indent=1))
    if args.json:
        print(json_text(study["rows"], indent=1))
    else:
        print(table)
        print(f"wrote {out / 'bench.md'}, {out / 'bench.png'} and {out / 'bench.json'}")
    return EXIT_OK


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin bench``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    p = subparsers.add_parser(
        "bench", help="work-precision study: error and drift against wall time, per method"
    )
    p.add_argument("--out", default="bench-out", help="output folder (table, plot, reference)")
    p.add_argument("--json", action="store_true", help="print the rows as JSON")
    p.add_argument(
        "--quick", action="store_true",
        help="one run per row, shortened spans (flagged in the table); for tests",
    )
    p.add_argument(
        "--repeats",
        type=int,
        default=None,
        help=f"runs per row, 1..{MAX_REPEATS} (default 5; quick 1)",
    )
    p.add_argument(
        "--problems", default="reference,separatrix", help="comma-separated: reference,separatrix"
    )
    add_quiet(p, "no progress lines on stderr")
    return p
