"""``chaplygin discover``: every first integral of a stated polynomial class, proved.

``chaplygin discover SYSTEM [--effects E1,E2] [--degree 2] [--coefficient-degree 2]
[--momentum M|omega] [--in-parameters] [--densities] [--relations] [--symmetries]
[--linear-degree 1] [--cofactor-degree 1] [--values I1=7/5,D=9/7] [--no-cache] [--json]``
prints the class searched (in words), the basis of the integrals found with the
verifier's verdict on each, the rank of the linear system (the proof that the class holds
no other) and the time per stage; with ``--relations`` and ``--symmetries`` the same for
the linear invariant relations and the symmetry fields of the linear class. A second
identical run answers from the discovery cache. Exit status 0 when every find is proved,
1 otherwise.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from chaplygin.derive.errors import UserInputError

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
        relations=args.relations,
        symmetries=args.symmetries,
        linear_degree=args.linear_degree,
        cofactor_degree=args.cofactor_degree,
        values=parse_values(args.values),
        cache=not args.no_cache,
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
        _print_relations(found)
        _print_symmetries(found)
        if found.values:
            print("at " + ", ".join(f"{k} = {v}" for k, v in found.values))
        when = "when computed, answered now from the discovery cache, " if found.from_cache else ""
        print(f"time {found.seconds:.2f} s ({when}search {s.seconds:.2f} s: {stages})")
    return EXIT_OK if found.all_proved else EXIT_FAILED


def _print_relations(found) -> None:
    r = found.relation_dict()
    if r is None:
        return
    print(f"invariant relations: {r['class']['description']}")
    for i, rel in enumerate(r["relations"], 1):
        print(f"  R{i} = {rel['expression']} = 0,  dR{i}/dt = ({rel['rate']}) R{i}")
        print(f"       {rel['verdict']} ({rel['method']})")
    if not r["relations"]:
        print("  none")
    if r["integrals"]:
        print(f"  (integrals of this class, lambda = 0: {', '.join(r['integrals'])})")
    print(f"  {'no other in this class: ' if r['complete'] else ''}{r['certificate']}")


def _print_symmetries(found) -> None:
    y = found.symmetry_dict()
    if y is None:
        return
    print(f"symmetries: {y['class']['description']}")
    coords = ", ".join(y["coordinates"])
    for i, X in enumerate(y["fields"], 1):
        print(f"  X{i} = ({', '.join(X['components'])}) along ({coords})")
        print(f"       {X['verdict']} ({X['method']})")
    if not y["fields"]:
        print("  none")
    for X in y["trivial"]:
        print(f"  trivial (parallel to the field): ({', '.join(X)})")
    print(f"  no other in this class: {y['no_other']}")


def parse_values(text: str | None) -> dict[str, str] | None:
    """``"I1=7/5,D=9/7"`` as ``{"I1": "7/5", "D": "9/7"}`` (the values are read as exact
    rationals by :func:`chaplygin.derive.invariants.specialise`, never evaluated).

    Parameters
    ----------
    text : str or None

    Returns
    -------
    dict of str to str or None

    Raises
    ------
    UserInputError
        An entry that is not ``NAME=VALUE``.
    """
    if not text:
        return None
    out = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise UserInputError(f"--values: {item!r} is not NAME=VALUE (e.g. I1=7/5)")
        out[name.strip()] = value.strip()
    return out


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
    p.add_argument(
        "--relations",
        action="store_true",
        help="also search linear invariant relations dF/dt = lambda F (F affine in the momentum)",
    )
    p.add_argument(
        "--symmetries",
        action="store_true",
        help="also search symmetry fields [X, f] = 0 affine in the momentum",
    )
    p.add_argument(
        "--linear-degree",
        type=int,
        default=1,
        help="degree of the coefficients of relations and symmetries in the other state "
        "variables (default 1)",
    )
    p.add_argument(
        "--cofactor-degree",
        type=int,
        default=1,
        help="degree of a relation's cofactor K (lambda = K/Q) in the state (default 1)",
    )
    p.add_argument(
        "--values",
        default=None,
        help="search at exact parameter values, e.g. I1=7/5,I2=7/5,I3=13/4,D=9/7",
    )
    p.add_argument("--no-cache", action="store_true", help="neither read nor write the cache")
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
