"""``chaplygin integrate``: integrate a system and report the drift of its first integrals."""

from __future__ import annotations

import argparse
import math

from chaplygin.derive.errors import UserInputError

from .cli_common import EXIT_FAILED, EXIT_OK, json_text, key_values, positive_float

__all__ = ["add_parser", "run", "DEFAULT_MAX_STEPS"]

#: ``--max-steps``'s default: :data:`chaplygin.numerics.step_budget.DEFAULT_MAX_STEPS`, written
#: out so that building the parser loads no numerics (``tests/verify/test_cli_imports.py``
#: holds the two equal).
DEFAULT_MAX_STEPS = 10_000_000


def _rate(args: argparse.Namespace) -> float:
    """:func:`~chaplygin.numerics.step_budget.motion_rate` at the command's start, in double
    precision; 1 when the inputs cannot be read (``integrate()`` then says what is wrong)."""
    import numpy as np
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.inputs import Precision, pack_params, pack_state, parse_number
    from chaplygin.numerics.step_budget import motion_rate

    double = Precision("double")
    try:
        code = load_model_code(args.system, args.effects)
        p = np.array(pack_params(code, key_values(args.param, "--param"), double), float)
        y = np.array(pack_state(code, key_values(args.y0, "--y0"), double), float)
        t0 = float(parse_number(args.t_start))
    except (UserInputError, OverflowError, ValueError, TypeError):
        return 1.0
    return motion_rate(code, t0, y, p)


def _check_step_budget(args: argparse.Namespace, prec) -> None:
    """Refuse, before any work, a span whose estimated steps exceed the budget."""
    from chaplygin.numerics.inputs import parse_number
    from chaplygin.numerics.step_budget import estimated_steps

    if args.max_steps < 1:
        raise UserInputError(f"--max-steps must be a positive whole number, got {args.max_steps}")
    try:
        span = abs(float(parse_number(args.t_end) - parse_number(args.t_start)))
    except UserInputError:
        return  # integrate() reports the malformed time, in its own words
    if not math.isfinite(span):
        return  # (beyond double: integrate() says so)
    rate = _rate(args)
    steps = estimated_steps(span * rate, args.method, args.rtol, prec.is_double)
    if steps > args.max_steps:
        at = "" if rate == 1 else f" at a rate |f(y0)|/|y0| of {rate:.2g}"
        raise UserInputError(
            f"--t-end {args.t_end}: a span of {span:.3g}{at} needs about {steps:.2g} steps, "
            f"beyond the budget of {args.max_steps:.3g}; shorten the span or raise --max-steps "
            f"(default {DEFAULT_MAX_STEPS:.0e})"
        )


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin integrate``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0 when the integration succeeded, 1 otherwise.
    """
    from chaplygin.numerics import integrate
    from chaplygin.numerics.inputs import Precision

    params = key_values(args.param, "--param")
    y0 = key_values(args.y0, "--y0")
    prec = Precision(args.precision)
    # the times go to integrate() as typed: it reads them at the working precision
    t_end, t_start = args.t_end, args.t_start
    for name, value in (("--rtol", args.rtol), ("--atol", args.atol)):
        if value is not None and not value > 0:
            raise UserInputError(f"{name} must be a positive number, got {value}")
    t_eval = _t_eval(args, prec)
    if args.out is not None:
        _check_output(args.out)
    _check_step_budget(args, prec)
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
        t_eval=t_eval,
        max_steps=args.max_steps,  # the integrator enforces the same budget while it runs
    )
    if args.out is not None:
        from chaplygin.numerics.code import load_model_code

        from .outputs.trajectory import run_attributes, trajectory_columns, write_trajectory
        from .scene.result import software_versions

        code = load_model_code(args.system, args.effects)
        columns = trajectory_columns(result.t, result.y, result.state_names, code.state_groups)
        attrs = run_attributes(result, code, prec, software_versions(), system=args.system,
                               effects=_effects(args.effects))  # fmt: skip
        write_trajectory(args.out, columns, attrs)
    final = {k: prec.format(v) for k, v in result.y_final.items()}
    if args.json:
        out = {
            "status": result.status,
            "message": result.message,
            "system": args.system,
            "effects": _effects(args.effects),
            "model": result.model,
            "method": result.method,
            "backend": result.backend,
            "precision": prec.to_json(),
            "t": prec.format(result.t[-1]),
            "y": final,
            # untrusted evidence (NaN, inf) is null, never a bare NaN (not JSON)
            "drift": {k: (v if math.isfinite(v) else None) for k, v in result.drift.items()},
            "drift_absolute": list(result.drift_absolute),
            "nfev": result.nfev,
            "njev": result.njev,
            "steps": result.nsteps,
            "wall_s": result.wall_s,
            "setup_s": result.setup_s,
            "info": {
                k: v
                for k, v in result.info.items()
                if isinstance(v, int | str) or (isinstance(v, float) and math.isfinite(v))
            },
        }
        print(json_text(out))
    else:
        print(f"{result.model}: {result.message} (status {result.status})")
        print(
            f"method {result.method}, backend {result.backend}, precision {result.precision}, "
            f"{result.nsteps} steps, {result.nfev} rhs calls, {result.wall_s:.3f} s"
        )
        print(f"t = {prec.format(result.t[-1])}")
        for k, v in final.items():
            print(f"  {k:<8} = {v}")
        print("drift of the first integrals (relative; absolute where marked *):")
        for k, v in result.drift.items():
            mark = "*" if k in result.drift_absolute else " "
            print(f"  {k:<18}{mark} {v:.3e}")
    return EXIT_OK if result.success else EXIT_FAILED


def _t_eval(args: argparse.Namespace, prec) -> list | None:
    """``--points N``: N evenly spaced output times from --t-start to --t-end."""
    if args.points is None:
        return None
    if args.points < 2:
        raise UserInputError(f"--points needs at least 2 points, got {args.points}")
    from chaplygin.numerics.inputs import working_number

    t0, t1 = working_number(args.t_start, prec), working_number(args.t_end, prec)
    n = args.points
    return [t0 + (t1 - t0) * i / (n - 1) for i in range(n)]


def _effects(given: str | None) -> list[str]:
    """``--effects a,b`` as the sorted list the JSON of ``run`` also gives."""
    return sorted(e.strip() for e in (given or "").split(",") if e.strip())


def _check_output(path: str) -> None:
    from pathlib import Path

    out = Path(path)
    if out.suffix not in (".nc", ".csv"):
        raise UserInputError(f"--out must end in .nc (netCDF) or .csv, got {path!r}")
    if not out.parent.is_dir():
        raise UserInputError(f"--out: folder {str(out.parent)!r} does not exist")
    if out.is_dir():
        raise UserInputError(f"--out {path!r} is a folder")


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin integrate``.

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
        "integrate", help="integrate a system and report the drift of its integrals"
    )
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
        help="taylor (the default in every precision: the same bits on every machine); in "
        "double also scipy's DOP853, RK45, LSODA, Radau, BDF (last bits depend on BLAS); "
        "odefun (mpmath.odefun)",
    )
    p.add_argument(
        "--rtol", type=positive_float, default=None, help="default 1e-10 (double), 10 eps"
    )
    p.add_argument(
        "--atol", type=positive_float, default=None, help="default 1e-12 (double), 10 eps"
    )
    p.add_argument(
        "--precision", default="double", help="'double', 'quad' (binary128) or a number of digits"
    )
    p.add_argument(
        "--effects", default=None, help="comma-separated effects, e.g. gyrostat,contact_point"
    )
    p.add_argument("--backend", default="auto", choices=("auto", "c", "numpy"))
    p.add_argument(
        "--points",
        type=int,
        default=None,
        metavar="N",
        help="N evenly spaced output times from --t-start to --t-end (a scene's run.points)",
    )
    p.add_argument(
        "--out",
        default=None,
        metavar="FILE",
        help="write the trajectory: FILE.nc (netCDF, names and units) or FILE.csv",
    )
    # the old spellings (before the one vocabulary), kept working
    p.add_argument("--t-eval", dest="points", type=int, help=argparse.SUPPRESS)
    p.add_argument("--output", dest="out", help=argparse.SUPPRESS)
    p.add_argument(
        "--max-steps",
        type=int,
        default=DEFAULT_MAX_STEPS,
        help=(
            f"step budget (default {DEFAULT_MAX_STEPS:.0e}): a span needing more steps, "
            "estimated as T * rtol^(-1/(p+1)) for an order-p scipy method and T * e^2 for "
            "taylor and odefun, T = span * max(1, |f(y0)|/|y0|), is refused before any work"
        ),
    )
    p.add_argument("--json", action="store_true")
    return p
