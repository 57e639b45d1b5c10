"""``chaplygin verify``: check the claims of the papers and report their verdicts."""

from __future__ import annotations

import argparse
import math
import sys
import time

from chaplygin.derive.errors import UserInputError

from .cli_common import EXIT_FAILED, EXIT_OK, add_quiet, check_output_file, json_text

__all__ = ["add_parser", "run", "DEFAULT_CLAIM_TIMEOUT", "MAX_JOBS"]

#: Seconds one claim may take in 'chaplygin verify' (the slowest takes about 10 s).
DEFAULT_CLAIM_TIMEOUT = 600.0

#: Most worker processes 'chaplygin verify --jobs' starts.
MAX_JOBS = 256


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin verify``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0 when every verdict is the expected one, 1 otherwise.
    """
    from .claims import select_claims
    from .verdict import FAILURES, default_jobs, iter_verdicts

    report = None
    if args.report is not None:
        report = check_output_file(args.report, "--report", what="the report")
    if args.claims is not None and not args.claims.replace(",", "").strip():
        raise UserInputError(
            f"--claims {args.claims!r} names no claim; give globs over IDs like "
            "'BKM12-*,K01-2.2' (or leave --claims out to check every claim)"
        )
    jobs = default_jobs() if args.jobs is None else args.jobs
    if not 1 <= jobs <= MAX_JOBS:
        raise UserInputError(f"--jobs must be a whole number in 1..{MAX_JOBS}, got {jobs}")
    if not (args.timeout >= 0 and math.isfinite(args.timeout)):
        raise UserInputError(
            f"--timeout must be a finite number of seconds >= 0 (0: none), got {args.timeout}"
        )
    if args.coverage:
        from .coverage import coverage
        from .report import render_coverage

        rows = coverage(select_claims())
        print("\n".join(render_coverage(rows)))
        missing = sum(r.checkable and not r.covered for r in rows)
        print(
            f"\n{sum(r.checkable for r in rows)} checkable entries in FORMULAS.md, "
            f"{missing} without a verdict yet"
        )
        return EXIT_OK
    lookup = None
    if args.system is not None:  # the claims of a user's own file
        import fnmatch

        from .user_claims import claims_of_file, file_lookup

        claims = claims_of_file(args.system)
        if args.claims is not None:
            patterns = [p.strip() for p in args.claims.split(",") if p.strip()]
            claims = [c for c in claims if any(fnmatch.fnmatchcase(c.id, p) for p in patterns)]
        lookup = file_lookup(args.system)
    else:
        claims = select_claims(args.claims)
    if not claims:
        raise UserInputError(
            f"no claim matches {args.claims!r}; patterns are globs over IDs like 'BKM12-*,K01-2.2'"
        )
    timeout = args.timeout or None
    verdicts = []
    started = time.perf_counter()
    listing = not (args.json or args.quiet)  # a line per claim as it is decided
    if listing:
        print(f"{'claim':<46} {'verdict':<14} {'ok':<3} {'seconds':>8}  method / statement")
    extra = {} if lookup is None else {"lookup": lookup}
    for v in iter_verdicts(claims, method=args.method, jobs=jobs, timeout=timeout, **extra):
        verdicts.append(v)
        if listing:
            flag = "yes" if v.ok else "NO"
            extra = "" if v.expected == "holds" else "  [expected: refuted]"
            print(f"{v.id:<46} {v.verdict:<14} {flag:<3} {v.seconds:8.3f}  {v.method}{extra}")
            print(f"{'':<46} {'':<14} {'':<3} {'':>8}  {v.statement}")
            if v.verdict == "refuted":
                print(f"{'':<72}residual {v.residual} at {v.witness}")
            sys.stdout.flush()
    if args.json:
        print(json_text([v.to_json() for v in verdicts]))
    if report is not None:
        from .report import render_report

        report.write_text(render_report(verdicts))
    bad = [v for v in verdicts if not v.ok]
    if not args.json:
        counts = {
            k: sum(v.verdict == k for v in verdicts)
            for k in (
                "proved",
                "proved by computation",
                "exact-sampled",
                "numeric",
                "refuted",
                *FAILURES,
            )
        }
        counts = {k: n for k, n in counts.items() if n or k not in FAILURES}
        total = sum(v.seconds for v in verdicts)
        wall = time.perf_counter() - started
        print(
            f"\n{len(verdicts)} claims: "
            + ", ".join(f"{n} {k}" for k, n in counts.items())
            + f"; {len(bad)} unexpected; {total:.1f} s of checking, {wall:.1f} s wall"
            + f" with {jobs} process(es), model derivation included"
        )
        for v in bad:
            print(f"UNEXPECTED: {v.id}: {v.problem}")
    return EXIT_FAILED if bad else EXIT_OK


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin verify``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    p = subparsers.add_parser("verify", help="check every claim of the papers and report verdicts")
    p.add_argument(
        "--claims", default=None, help="glob(s) over claim IDs, comma-separated (e.g. 'BKM12-*')"
    )
    p.add_argument(
        "--system",
        default=None,
        metavar="FILE.toml",
        help="check the claims about the system a file describes ([system] and [[claims]]: "
        "the derived model's integrals and density, then the file's claims)",
    )
    p.add_argument("--json", action="store_true", help="print a JSON list of verdicts")
    p.add_argument(
        "--report",
        default=None,
        metavar="FILE.md",
        help="also write a Markdown report (LaTeX statements, errata, counts per paper)",
    )
    p.add_argument(
        "--method",
        default="auto",
        choices=("auto", "symbolic", "exact-sampled", "numeric"),
        help="auto: symbolic proof, refutation with an exact witness (default)",
    )
    p.add_argument(
        "--coverage",
        action="store_true",
        help="list which checkable entries of FORMULAS.md have a claim (checks nothing)",
    )
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help=f"worker processes, 1..{MAX_JOBS} (default: the CPUs available)",
    )
    p.add_argument(
        "--timeout",
        type=float,
        default=DEFAULT_CLAIM_TIMEOUT,
        metavar="SECONDS",
        help=(
            f"time limit of one claim (default {DEFAULT_CLAIM_TIMEOUT:g} s): past it the claim is"
            " reported as 'timeout' and the run goes on; 0 means none, and with --jobs 1 then"
            " checks in this process"
        ),
    )
    add_quiet(p, "no line per claim (the summary and the unexpected verdicts only)")
    return p
