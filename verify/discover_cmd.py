"""``chaplygin discover``: every first integral of a stated polynomial class, proved.

``chaplygin discover SYSTEM [--effects E1,E2] [--degree 2] [--coefficient-degree 2]
[--momentum M|omega] [--in-parameters] [--json]`` prints the class searched (in words),
the basis of the integrals found with the verifier's verdict on each, the rank of the
linear system (the proof that the class holds no other) and the time per stage.
Exit status 0 when every integral found is proved, 1 otherwise.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from .cli_common import EXIT_FAILED, EXIT_OK, json_text

if TYPE_CHECKING:
    from ..derive.rolling_system import RollingSystem

__all__ = ["add_parser", "run"]


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin discover``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0 when every integral found is proved, 1 otherwise.
    """
    import sympy as sp

    from .discover import discover

    system = args.system
    if system.endswith(".toml"):
        system = described_system(system)
    found = discover(
        system,
        args.effects or (),
        degree=args.degree,
        coefficient_degree=args.coefficient_degree,
        momentum=args.momentum,
        in_parameters=args.in_parameters,
        densities=args.densities,
    )
    if args.json:
        print(json_text(found.as_dict()))
    else:
        s = found.search
        print(f"{s.model}: first integrals in the class of {s.search_class.describe()}")
        for i, (F, proof) in enumerate(zip(s.integrals, found.proofs, strict=True), 1):
            print(f"  F{i} = {sp.sstr(F)}")
            print(f"       {proof.verdict} ({proof.method}, {proof.seconds:.2f} s)")
        if not s.integrals:
            print("  none")
        print(
            f"no other in this class: rank {s.rank} of {s.unknowns} unknowns "
            f"({s.monomials} monomials, {s.equations} equations), dimension {s.dimension}"
        )
        stages = ", ".join(f"{k} {v:.2f} s" for k, v in s.stage_seconds.items())
        density = found.density_dict()
        if density is not None:
            family = ", ".join(density["family"]) or "no factor"
            print(f"invariant densities prod |g_j|^(a_j) over g_j in: {family}")
            if density["density"] is not None:
                print(f"  rho = {density['density']}")
                print(f"       {density['verdict']} ({density['method']})")
            else:
                print(f"  none: {density['none']}")
            for v in density["directions"]:
                print(f"  times any power of the integral with exponents ({', '.join(v)})")
        print(f"time {found.seconds:.2f} s (search {s.seconds:.2f} s: {stages})")
    return EXIT_OK if found.all_proved else EXIT_FAILED


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin discover``.

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
        "discover",
        help="find every polynomial first integral of a stated class, exactly, and prove it",
    )
    p.add_argument(
        "system",
        help="system name, e.g. chaplygin_ball, or a TOML file with a [system] table "
        "(a scene or a description file)",
    )
    p.add_argument(
        "--effects", default=None, help="comma-separated effects, e.g. gyrostat or rubber"
    )
    p.add_argument("--degree", type=int, default=2, help="degree in the momentum (default 2)")
    p.add_argument(
        "--coefficient-degree",
        type=int,
        default=2,
        help="degree of the coefficients in the other state variables (default 2)",
    )
    p.add_argument(
        "--momentum",
        default=None,
        help="group the integrals are polynomial in: a state group (default M) or omega",
    )
    p.add_argument(
        "--in-parameters",
        action="store_true",
        help="coefficients rational functions of the parameters (default rational numbers)",
    )
    p.add_argument(
        "--densities",
        action="store_true",
        help="also search invariant densities (powers of the denominators' factors)",
    )
    p.add_argument("--json", action="store_true", help="the result as JSON")
    return p


def described_system(path: str) -> RollingSystem:
    """The :class:`~chaplygin.derive.rolling_system.RollingSystem` of a TOML file's
    ``[system]`` table (a scene file or a file holding only the table).

    Parameters
    ----------
    path : str

    Returns
    -------
    RollingSystem

    Raises
    ------
    UserInputError
        An unreadable file, TOML syntax, no ``[system]`` table, a bad description (or a
        bad ``[discover]``/``[[claims]]`` entry: :func:`.user_claims.read_description`).
    """
    from .user_claims import read_description

    return read_description(path)[0]
