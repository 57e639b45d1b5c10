"""``chaplygin delta``: the contact-point displacement per tumble along the separatrix.

``chaplygin delta --param I=1,3,5 --param D=1 --param b=1 --precision 30 [--json]
[--plot FILE.png] [--figures DIR]`` prints ``mu = xi = kap/lam``, Delta by the full
equations (Taylor integration at high precision), by the quadrature of K01 (3.7) and by
the closed form ``pi b/ch(pi mu/2)``, the number of digits on which they agree and the
wall time (K01-3.4 ... 3.7, Fig. 4).
"""

from __future__ import annotations

import argparse
import time

from chaplygin.derive.errors import UserInputError

from .cli_common import (
    EXIT_FAILED,
    EXIT_OK,
    add_precision_digits,
    check_output_dir,
    check_output_file,
    json_text,
    key_values,
    precision_digits,
)

__all__ = [
    "add_parser",
    "run",
    "MIN_DIGITS",
    "MAX_DIGITS",
    "PLOT_SUFFIXES",
    "MAX_MU",
    "MAX_MAGNITUDE",
]

MIN_DIGITS, MAX_DIGITS = 5, 200

#: Largest mu = kap/lam: the steps of the full equations grow like 14 mu (mu = 500 takes
#: 7,000 steps, 45 s), and Delta = pi b/ch(pi mu/2) is below 1e-67 b beyond it.
MAX_MU = 100

#: I, D, b and |C| must lie between 1/MAX_MAGNITUDE and MAX_MAGNITUDE.
MAX_MAGNITUDE = 1e100

#: The file types --plot writes (by its name's suffix, never added silently).
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _params(items) -> dict:
    import mpmath
    from chaplygin.numerics.inputs import parse_number

    raw = key_values(items, "--param")
    unknown = set(raw) - {"I", "D", "b", "C"}
    if unknown:
        raise UserInputError(
            f"unknown parameter(s) {', '.join(sorted(unknown))}: delta takes I=I1,I2,I3, D, b "
            "and optionally C"
        )
    for need in ("I", "D", "b"):
        if need not in raw:
            raise UserInputError(
                f"--param {need}=... is required (e.g. --param I=1,3,5 --param D=1 --param b=1)"
            )
    # read at more digits than any --precision (was 60: 100 digits lost the inputs' digits)
    dps = MAX_DIGITS + 10
    with mpmath.workdps(dps):
        out = {
            "I": [parse_number(v, dps) for v in raw["I"].split(",")],
            "D": parse_number(raw["D"], dps),
            "b": parse_number(raw["b"], dps),
            "C": parse_number(raw.get("C", "1"), dps),
        }
    for name, values in out.items():
        for v in values if name == "I" else [values]:
            if v != 0 and not 1 / MAX_MAGNITUDE <= abs(v) <= MAX_MAGNITUDE:
                raise UserInputError(
                    f"--param {name}: {mpmath.nstr(v, 6)} is beyond the range "
                    f"{1 / MAX_MAGNITUDE:g}..{MAX_MAGNITUDE:g} of delta; rescale the units"
                )
    if out["b"] <= 0:
        raise UserInputError("b (the radius) must be positive")
    if out["C"] == 0:
        raise UserInputError(
            "C = (M, gamma) must not be zero (C = 0 has no separatrix of this kind)"
        )
    return out


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin delta``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0 when the three values agree on the digits asked for, 1 otherwise.
    """
    import mpmath
    from chaplygin.numerics.ball.separatrix import check_inertia, delta_three_ways, mu_of
    from chaplygin.numerics.precision import Precision

    plot = figures = None
    if args.plot is not None:
        plot = check_output_file(args.plot, "--plot", PLOT_SUFFIXES, "the plot")
    if args.figures is not None:
        figures = check_output_dir(args.figures, "--figures", "the figures")
    digits = precision_digits(args)
    if not MIN_DIGITS <= digits <= MAX_DIGITS:
        raise UserInputError(
            f"--precision {digits}: give between {MIN_DIGITS} and {MAX_DIGITS} digits"
        )
    P = _params(args.param)
    check_inertia(P["I"], P["D"])
    with mpmath.workdps(digits + 10):
        try:
            mu = mu_of(P["I"], P["D"])
        except ZeroDivisionError:  # J1, J2, J3 equal at this precision
            mu = mpmath.inf
    if not mu <= MAX_MU:
        raise UserInputError(
            f"mu = kap/lam = {mpmath.nstr(mu, 6)} is above {MAX_MU}: the moments I + D are "
            f"too close (D much larger than the differences of I); Delta is below 1e-67 b there "
            f"and the full equations would take about {mpmath.nstr(14 * mu, 2)} steps"
        )
    start = time.perf_counter()
    r = delta_three_ways(P["I"], P["D"], P["b"], digits, C=abs(P["C"]), engine=args.engine)
    wall = time.perf_counter() - start
    show = digits + 3

    def fmt(v):
        return mpmath.nstr(v, show, min_fixed=-mpmath.inf, max_fixed=mpmath.inf)

    agree = min(r.digits_agree, float(digits + 5))
    ok = r.digits_agree >= digits
    if args.json:
        print(
            json_text(
                {
                    "mu": fmt(r.mu),
                    "delta_ode": fmt(r.ode),
                    "delta_quadrature": fmt(r.quadrature),
                    "delta_closed_form": fmt(r.closed),
                    "precision": Precision.working(digits).to_json(),
                    "digits_agree": round(agree, 2),
                    "ok": ok,
                    "wall_s": round(wall, 3),
                    "seconds": {k: round(v, 3) for k, v in r.seconds.items()},
                    "ode_steps": r.ode_info.get("steps"),
                    "ode_working_digits": r.ode_info.get("work_digits"),
                    "ode_lam_t_end": float(r.ode_info.get("L", 0)),
                    "ode_tail": mpmath.nstr(r.ode_info.get("tail"), 6),
                    "ode_tail_bound": mpmath.nstr(r.ode_info.get("tail_bound"), 3),
                    "engine": args.engine,
                },
            )
        )
    else:
        I = ", ".join(mpmath.nstr(v, 10) for v in P["I"])
        print(
            f"separatrix on M || gamma at h2 = C^2/(2 I2): I = ({I}), "
            f"D = {mpmath.nstr(P['D'], 10)}, b = {mpmath.nstr(P['b'], 10)}"
        )
        print(f"mu = xi = kap/lam = {fmt(r.mu)}")
        print(
            f"Delta (full equations, Taylor {r.ode_info['work_digits']} digits, "
            f"{r.ode_info['steps']} steps, |lam t| <= {float(r.ode_info['L']):.2f} + tails "
            f"[bound {mpmath.nstr(r.ode_info['tail_bound'], 2)}]) = {fmt(r.ode)}"
        )
        print(f"Delta (quadrature of K01 (3.7))  = {fmt(r.quadrature)}")
        print(f"Delta (closed form pi b/ch(pi mu/2)) = {fmt(r.closed)}")
        print(f"agree on {agree:.1f} digits (requested {digits}): {'ok' if ok else 'NOT OK'}")
        times = ", ".join(f"{k} {v:.2f} s" for k, v in r.seconds.items())
        print(f"wall time {wall:.2f} s ({times})")
    if plot is not None or figures is not None:
        from .plots import delta_of_mu_figure, separatrix_figures

        if plot is not None:
            delta_of_mu_figure(float(P["b"])).savefig(plot, dpi=110, format=plot.suffix[1:].lower())
        if figures is not None:
            figures.mkdir(exist_ok=True)
            drawn = separatrix_figures([float(v) for v in P["I"]], float(P["D"]), float(P["b"]))
            for name, figure in drawn.items():
                figure.savefig(figures / name, dpi=110)
    return EXIT_OK if ok else EXIT_FAILED


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin delta``.

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
        "delta",
        help="displacement of the contact point along the separatrix (K01 §3.3), three ways",
    )
    p.add_argument(
        "--param",
        action="append",
        metavar="NAME=VALUE[,VALUE...]",
        help="I=I1,I2,I3 (I2 the middle moment), D=m b^2, b=radius, C=(M,gamma)",
    )
    add_precision_digits(p, 30)
    p.add_argument("--json", action="store_true", help="values as decimal strings in JSON")
    p.add_argument(
        "--engine",
        default="taylor",
        choices=("taylor", "odefun", "jet"),
        help="integrator of the full equations (default: taylor, the generated Taylor "
        "integrator; jet is an alias of taylor, odefun is mpmath.odefun)",
    )
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write Delta(mu) (Fig. 5)")
    p.add_argument(
        "--figures",
        default=None,
        metavar="DIR",
        help="write Delta(mu) and the contact-point traces (Figs. 4-6) into DIR",
    )
    return p
