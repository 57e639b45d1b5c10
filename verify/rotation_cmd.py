"""``chaplygin rotation``: actions, frequencies and rotation number of a torus at (M, gamma) = 0.

References
----------
K01-2.23, K01-2.26, K01-2.27 (with the true turning points, FORMULAS.md)
"""

from __future__ import annotations

import argparse

from .cli_common import EXIT_OK, add_precision_digits, json_text, key_values, precision_digits

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
                f"what --precision {digits} resolves; rescale the units or raise --precision"
            )


def _vector(text: str, flag: str, n: int, dps: int) -> list:
    from chaplygin.derive.errors import UserInputError
    from chaplygin.numerics.inputs import parse_number

    items = [s for s in str(text).split(",") if s.strip()]
    if len(items) != n:
        raise UserInputError(f"{flag} needs {n} comma-separated numbers, got {text!r}")
    return [parse_number(s, dps) for s in items]


def _named_values(args: argparse.Namespace) -> dict[str, str]:
    """``I, D`` from ``--param`` and ``M, gamma`` from ``--y0`` (or their old flags)."""
    from chaplygin.derive.errors import UserInputError

    params, y0 = key_values(args.param, "--param"), key_values(args.y0, "--y0")
    for flag, got, names in (("--param", params, ("I", "D")), ("--y0", y0, ("M", "gamma"))):
        unknown = sorted(set(got) - set(names))
        if unknown:
            raise UserInputError(
                f"{flag} {unknown[0]}: rotation takes {flag} " + " and ".join(names)
            )
    out = {}
    for flag, got, name in (
        ("--param", params, "I"),
        ("--param", params, "D"),
        ("--y0", y0, "M"),
        ("--y0", y0, "gamma"),
    ):
        old = getattr(args, name)
        if name in got and old is not None:
            raise UserInputError(f"give {name} once: {flag} {name}=... (--{name} is its old form)")
        value = got.get(name, old)
        if value is None:
            raise UserInputError(f"missing {flag} {name}=... (e.g. {_EXAMPLE[name]})")
        out[name] = value
    return out


_EXAMPLE = {
    "I": "--param I=1,1.5,3",
    "D": "--param D=1",
    "M": "--y0 M=0.48,0.5,-0.36",
    "gamma": "--y0 gamma=0.6,0,0.8",
}


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
    from chaplygin.numerics.ball.quadratures import measured_rotation_number, torus_quadratures
    from chaplygin.numerics.precision import Precision

    digits = precision_digits(args)
    given = _named_values(args)
    if digits < 15 or digits > 1000:
        raise UserInputError("--precision must be between 15 and 1000 digits")
    dps = digits + 10
    I = _vector(given["I"], "--param I", 3, dps)
    D = _vector(given["D"], "--param D", 1, dps)[0]
    M = _vector(given["M"], "--y0 M", 3, dps)
    gamma = _vector(given["gamma"], "--y0 gamma", 3, dps)
    if all(m == 0 for m in M):
        raise UserInputError("--M must not be zero: a ball at rest has no torus")
    with mpmath.workdps(dps):
        scales = {f"I{i + 1}": v for i, v in enumerate(I)}
        scales.update(D=D, **{"|M|": mpmath.sqrt(sum(m * m for m in M))})
    _check_scale(scales, digits)
    if args.simulate is not None and not (0 < args.simulate < 1e6):
        raise UserInputError("--simulate T needs 0 < T < 1e6")
    tq = torus_quadratures(I, D, M, gamma, digits=digits)
    d = digits

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
        "precision": Precision.working(d).to_json(),
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
            print(f"{k:16s} {Precision.working(d) if k == 'precision' else v}")
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
    p.add_argument(
        "--param",
        action="append",
        metavar="NAME=VALUE",
        help="I=I1,I2,I3 (I1 < I2 < I3) and D=m b^2, as for integrate",
    )
    p.add_argument(
        "--y0",
        action="append",
        metavar="NAME=VALUE",
        help="M=M1,M2,M3 and gamma=g1,g2,g3 (unit vector) with (M, gamma) = 0",
    )
    # the old spellings (before the one vocabulary), kept working
    for old in ("--I", "--D", "--M", "--gamma"):
        p.add_argument(old, default=None, help=argparse.SUPPRESS)
    add_precision_digits(p, 30)
    p.add_argument(
        "--simulate",
        type=float,
        default=None,
        metavar="T",
        help="also measure it from a DOP853 trajectory of length T",
    )
    p.add_argument("--json", action="store_true")
    return p
