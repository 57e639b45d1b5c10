"""The ``chaplygin`` command line: verify, derive, integrate.

User errors (unknown names, wrong lengths, non-physical or non-finite values, malformed
numbers) print one line on stderr and exit with status 2; nothing is written.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path

__all__ = ["main", "build_parser", "COMMAND_MODULES"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2
#: Seconds one claim may take in 'chaplygin verify' (the slowest takes about 10 s).
DEFAULT_CLAIM_TIMEOUT = 600.0

#: Modules of ``chaplygin.verify`` that add a subcommand: each defines
#: ``add_parser(subparsers) -> None`` and sets ``func`` (args -> exit status) as a default.
COMMAND_MODULES: tuple[str, ...] = ("bench_cmd", "delta_cmd", "rotation_cmd", "bifurcation_cmd")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit 2, no usage dump
        self.exit(EXIT_USAGE, f"chaplygin: error: {message} (see 'chaplygin {self._sub} --help')\n")

    _sub = ""


def _key_values(items: Sequence[str] | None, flag: str) -> dict[str, str]:
    from chaplygin.derive.errors import UserInputError

    out: dict[str, str] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name or not value.strip():
            raise UserInputError(f"{flag} expects NAME=VALUE[,VALUE...], got {item!r}")
        if name in out:
            raise UserInputError(f"{flag} {name} given twice")
        out[name] = value.strip()
    return out


def generated_dir() -> Path:
    """The ``generated/`` folder of this installation (the repository's, when editable)."""
    spec = importlib.util.find_spec("chaplygin.generated")
    return Path(next(iter(spec.submodule_search_locations)))


# ------------------------------------------------------------------------------ verify
def _cmd_verify(args) -> int:
    from chaplygin.derive.errors import UserInputError

    from .claims import select_claims
    from .verdict import FAILURES, default_jobs, iter_verdicts

    if args.report:
        target = Path(args.report)
        if target.is_dir() or not target.parent.exists():
            raise UserInputError(
                f"cannot write the report to {args.report!r}: give a file in an existing folder"
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
    claims = select_claims(args.claims)
    if not claims:
        raise UserInputError(
            f"no claim matches {args.claims!r}; patterns are globs over IDs like 'BKM12-*,K01-2.2'"
        )
    jobs = default_jobs() if args.jobs is None else args.jobs
    if jobs < 1:
        raise UserInputError(f"--jobs must be a positive whole number, got {jobs}")
    if not (args.timeout >= 0 and math.isfinite(args.timeout)):
        raise UserInputError(f"--timeout must be a number of seconds >= 0, got {args.timeout}")
    timeout = args.timeout or None
    verdicts = []
    started = time.perf_counter()
    if not args.json:
        print(f"{'claim':<46} {'verdict':<14} {'ok':<3} {'seconds':>8}  method / statement")
    for v in iter_verdicts(claims, method=args.method, jobs=jobs, timeout=timeout):
        verdicts.append(v)
        if not args.json:
            flag = "yes" if v.ok else "NO"
            extra = "" if v.expected == "holds" else "  [expected: refuted]"
            print(f"{v.id:<46} {v.verdict:<14} {flag:<3} {v.seconds:8.3f}  {v.method}{extra}")
            print(f"{'':<46} {'':<14} {'':<3} {'':>8}  {v.statement}")
            if v.verdict == "refuted":
                print(f"{'':<72}residual {v.residual} at {v.witness}")
            sys.stdout.flush()
    if args.json:
        print(json.dumps([v.to_json() for v in verdicts], indent=2))
    if args.report:
        from .report import render_report

        Path(args.report).write_text(render_report(verdicts))
    bad = [v for v in verdicts if not v.ok]
    if not args.json:
        counts = {
            k: sum(v.verdict == k for v in verdicts)
            for k in ("proved", "exact-sampled", "numeric", "refuted", *FAILURES)
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


# ------------------------------------------------------------------------------ derive
def _cmd_derive(args) -> int:
    from chaplygin.derive.writer import check_generated, write_generated

    directory = Path(args.out) if args.out else generated_dir()
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


# ------------------------------------------------------------------------------ integrate
def _format_number(value, digits: int | None) -> str:
    if digits is None:
        return repr(float(value))
    import mpmath

    return mpmath.nstr(value, digits, strip_zeros=False)


def _cmd_integrate(args) -> int:
    from chaplygin.derive.errors import UserInputError
    from chaplygin.numerics import integrate
    from chaplygin.numerics.inputs import Precision, parse_number

    params = _key_values(args.param, "--param")
    y0 = _key_values(args.y0, "--y0")
    prec = Precision(args.precision)
    t_end = float(parse_number(args.t_end))
    t_start = float(parse_number(args.t_start))
    for name, value in (("--rtol", args.rtol), ("--atol", args.atol)):
        if value is not None and not value > 0:
            raise UserInputError(f"{name} must be a positive number, got {value}")
    result = integrate(
        args.system,
        y0,
        (t_start, t_end),
        params,
        effects=args.effects,
        method=args.method,
        precision=args.precision,
        rtol=args.rtol,
        atol=args.atol,
        backend=args.backend,
    )
    digits = prec.digits
    final = {k: _format_number(v, digits) for k, v in result.y_final.items()}
    if args.json:
        out = {
            "status": result.status,
            "message": result.message,
            "model": result.model,
            "method": result.method,
            "backend": result.backend,
            "precision": result.precision,
            "t": _format_number(result.t[-1], digits),
            "y": final,
            "drift": result.drift,
            "drift_absolute": list(result.drift_absolute),
            "nfev": result.nfev,
            "njev": result.njev,
            "nsteps": result.nsteps,
            "wall_s": result.wall_s,
            "setup_s": result.setup_s,
            "info": {k: v for k, v in result.info.items() if isinstance(v, (int, float, str))},
        }
        print(json.dumps(out, indent=2))
    else:
        print(f"{result.model}: {result.message} (status {result.status})")
        print(
            f"method {result.method}, backend {result.backend}, precision {result.precision}, "
            f"{result.nsteps} steps, {result.nfev} rhs calls, {result.wall_s:.3f} s"
        )
        print(f"t = {_format_number(result.t[-1], digits)}")
        for k, v in final.items():
            print(f"  {k:<8} = {v}")
        print("drift of the first integrals (relative; absolute where marked *):")
        for k, v in result.drift.items():
            mark = "*" if k in result.drift_absolute else " "
            print(f"  {k:<18}{mark} {v:.3e}")
    return EXIT_OK if result.success else EXIT_FAILED


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (value > 0 and value != float("inf")):
        raise argparse.ArgumentTypeError(f"{text!r} must be a positive finite number")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="chaplygin", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("verify", help="check every claim of the papers and report verdicts")
    p._sub = "verify"
    p.add_argument(
        "--claims", default=None, help="glob(s) over claim IDs, comma-separated (e.g. 'BKM12-*')"
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
        help="worker processes (default: the CPUs available)",
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
    p.set_defaults(func=_cmd_verify)

    p = sub.add_parser("derive", help="regenerate generated/ (or check it with --check)")
    p._sub = "derive"
    p.add_argument("--check", action="store_true", help="exit 1 when generated/ is out of date")
    p.add_argument("--out", default=None, help="directory (default: the package's generated/)")
    p.set_defaults(func=_cmd_derive)

    p = sub.add_parser("integrate", help="integrate a system and report the drift of its integrals")
    p._sub = "integrate"
    p.add_argument("system", help="system name, e.g. chaplygin_ball")
    p.add_argument(
        "--param", action="append", metavar="NAME=VALUE[,VALUE...]", help="e.g. I=1,2,3 D=1"
    )
    p.add_argument(
        "--y0", action="append", metavar="NAME=VALUE[,VALUE...]", help="e.g. M=0.7,-0.4,0.5"
    )
    p.add_argument("--t-end", required=True, help="final time")
    p.add_argument("--t-start", default="0", help="initial time (default 0)")
    p.add_argument(
        "--method",
        default=None,
        help="DOP853 (default in double), RK45, LSODA, Radau, BDF, taylor (default in quad "
        "and digits; also in double), odefun (mpmath.odefun)",
    )
    p.add_argument(
        "--rtol", type=_positive_float, default=None, help="default 1e-10 (double), 10 eps"
    )
    p.add_argument(
        "--atol", type=_positive_float, default=None, help="default 1e-12 (double), 10 eps"
    )
    p.add_argument(
        "--precision", default="double", help="'double', 'quad' (binary128) or a number of digits"
    )
    p.add_argument(
        "--effects", default=None, help="comma-separated effects, e.g. gyrostat,contact_point"
    )
    p.add_argument("--backend", default="auto", choices=("auto", "c", "numpy"))
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_integrate)

    for name in COMMAND_MODULES:
        importlib.import_module(f"{__package__}.{name}").add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``chaplygin`` console script; returns the exit status."""
    from chaplygin.derive.errors import UserInputError

    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except UserInputError as exc:
        print(f"chaplygin: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:  # pragma: no cover
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


def console() -> None:
    """Console-script wrapper: exit with :func:`main`'s status."""
    sys.exit(main())
