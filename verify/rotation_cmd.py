"""``chaplygin rotation``: actions, frequencies and rotation number of a torus at (M, gamma) = 0.

References
----------
K01-2.23, K01-2.26, K01-2.27 (with the true turning points, FORMULAS.md)
"""

from __future__ import annotations

import argparse

from .cli_common import EXIT_OK, json_text

__all__ = ["add_parser", "run"]


def _check_scale(values: dict, digits: int) -> None:
    """Refuse I, D, |M| outside ``10**(-digits/2) .. 10**(digits/2)`` (before any work).

    The separation roots and quadratures lose every digit beyond it (division by zero,
    root finders that do not converge).
    """
    import mpmath
    from chaplygin.derive.errors import UserInputError

    bound = mpmath.mpf(10) ** (digits // 2)
    for name, v in values.items():
        if v != 0 and not 1 / bound <= abs(v) <= bound:
            raise UserInputError(
                f"{name} = {mpmath.nstr(v, 6)} is beyond 1e-{digits // 2}..1e{digits // 2}, "
                f"what --digits {digits} resolves; rescale the units or raise --digits"
            )


def _vector(text: str, flag: str, n: int, dps: int) -> list:
    from chaplygin.derive.errors import UserInputError
    from chaplygin.numerics.inputs import parse_number

    items = [s for s in str(text).split(",") if s.strip()]
    if len(items) != n:
        raise UserInputError(f"{flag} needs {n} comma-separated numbers, got {text!r}")
    return [parse_number(s, dps) for s in items]


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin rotation``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0.
    """
    import mpmath
    from chaplygin.derive.errors import UserInputError
    from chaplygin.numerics.quadratures import measured_rotation_number, torus_quadratures

    if args.digits < 15 or args.digits > 1000:
        raise UserInputError("--digits must be between 15 and 1000")
    dps = args.digits + 10
    I = _vector(args.I, "--I", 3, dps)
    D = _vector(args.D, "--D", 1, dps)[0]
    M = _vector(args.M, "--M", 3, dps)
    gamma = _vector(args.gamma, "--gamma", 3, dps)
    if all(m == 0 for m in M):
        raise UserInputError("--M must not be zero: a ball at rest has no torus")
    with mpmath.workdps(dps):
        scales = {f"I{i + 1}": v for i, v in enumerate(I)}
        scales.update(D=D, **{"|M|": mpmath.sqrt(sum(m * m for m in M))})
    _check_scale(scales, args.digits)
    if args.simulate is not None and not (0 < args.simulate < 1e6):
        raise UserInputError("--simulate T needs 0 < T < 1e6")
    tq = torus_quadratures(I, D, M, gamma, digits=args.digits)
    d = args.digits

    def s(x):
        return mpmath.nstr(x, d)

    out = {
        "rotation_number": s(tq.rotation_number),
        "frequencies_tau": [s(x) for x in tq.frequencies],
        "actions": [s(x) for x in tq.actions],
        "ranges": [[s(lo), s(hi)] for lo, hi in tq.ranges],
        "q_star": s(tq.details["q_star"]),
        "h": s(tq.h),
        "n": s(tq.n),
        "digits": d,
    }
    if args.simulate is not None:
        mr = measured_rotation_number(
            [float(x) for x in I],
            float(D),
            [float(x) for x in M],
            [float(x) for x in gamma],
            t_end=args.simulate,
        )
        out["measured"] = {
            "rotation_number": mr.value,
            "difference": float(tq.rotation_number) - mr.value,
            "oscillations": list(mr.oscillations),
            "drift_H": mr.drift["H"],
        }
    if args.json:
        print(json_text(out, indent=1))
    else:
        for k, v in out.items():
            print(f"{k:16s} {v}")
    return EXIT_OK


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin rotation``.

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
        "rotation",
        help="rotation number, frequencies and actions of a torus at (M, gamma) = 0 (K01-2.27)",
    )
    p.add_argument("--I", required=True, help="I1,I2,I3 with I1 < I2 < I3")
    p.add_argument("--D", required=True, help="D = m b^2")
    p.add_argument("--M", required=True, help="M1,M2,M3 with (M, gamma) = 0")
    p.add_argument("--gamma", required=True, help="gamma1,gamma2,gamma3 (unit vector)")
    p.add_argument("--digits", type=int, default=30)
    p.add_argument(
        "--simulate",
        type=float,
        default=None,
        metavar="T",
        help="also measure it from a DOP853 trajectory of length T",
    )
    p.add_argument("--json", action="store_true")
    return p
