"""Claims about a described system, kept in the user's own file: ``chaplygin verify --system``.

A TOML file with a ``[system]`` table (a scene or a description file) may name a class to
search (``[discover]``: ``degree``, ``coefficient_degree``, ``momentum``, ``in_parameters``,
``densities``, as ``chaplygin discover``'s options; each integral found and the density found
become claims ``<name>:found-F1`` ..., their statement saying the class and the rank that
proves there is no other) and list claims::

    [[claims]]
    id = "ROUTH-jellett"
    kind = "integral"                  # or "measure" (an invariant density)
    statement = "Jellett's integral (I omega, a + b gamma)"
    expression = "A*b*(gamma1*omega1 + gamma2*omega2) + C*(a + b*gamma3)*omega3"
    expected = "holds"                 # "fails" for a negative control

The expression is read without ``eval`` over the model's state (``M1`` ..., ``gamma1``
...), its angular velocity ``omega1 .. omega3`` and its parameters. Beside the file's claims,
every integral the derived model ships (``<name>:H`` ...) and its density (when it has one)
is a claim: the engine's statements proved by the same machinery; and ``<name>:kane``
compares the derived equations with ``sympy.physics.mechanics.KanesMethod``
(:mod:`.kane_rolling`) at generic exact parameter values (a ``numeric`` verdict: 40-digit
agreement within ``1e-30``). An integral is decided by
its Lie derivative (:func:`.identity.lie_derivative`), a density by Liouville's equation
(:func:`.identity.measure_residual`), each with :func:`.identity.decide` (a Groebner normal
form on the phase space, or an exact witness when it fails).

Worker processes find a claim by :func:`file_claim` (the file read again, the system
registered there too), so ``--jobs`` and ``--timeout`` work as for the papers' claims.
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

import sympy as sp
from pydantic import ValidationError

from ..derive.errors import UserInputError
from ..derive.expression_text import parse_expression
from ..derive.model import Model
from ..derive.rolling_system import RollingSystem
from ..derive.systems import build_model, register_system
from . import chained, omega_coordinates
from .claims.base import Check, Claim, Computed, ComputedClaim
from .identity import lie_derivative, measure_residual
from .scene.schema import FileClaim, FileDiscovery

__all__ = ["read_description", "claims_of_file", "file_claim", "file_lookup"]

#: Claims one file may hold.
MAX_CLAIMS = 200


def _validated(model_cls, data, name: str, key: str):
    """``model_cls`` of ``data``, or the first problem as one line naming ``key``."""
    try:
        return model_cls.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(k) for k in (key, *first["loc"]))
        raise UserInputError(f"{name}: {where}: {first['msg']}") from None


def read_description(path: str | Path) -> tuple[RollingSystem, FileDiscovery | None, list]:
    """The ``[system]``, ``[discover]`` and ``[[claims]]`` of a TOML file, validated.

    Parameters
    ----------
    path : str or Path
        A scene file or a file holding only the description.

    Returns
    -------
    system : RollingSystem
    discover : FileDiscovery or None
    claims : list of FileClaim

    Raises
    ------
    UserInputError
        An unreadable file, TOML syntax, no ``[system]`` table, a bad description, search
        class or claim entry, a claim id used twice (one line, nothing derived).
    """
    from .scene.reading import parse_toml, read_scene_file
    from .scene.schema import SystemTable

    name = str(path)
    try:
        data = parse_toml(read_scene_file(path).decode("utf-8"), name)
    except UnicodeDecodeError:
        raise UserInputError(f"{name}: not UTF-8 text") from None
    table = data.get("system")
    if not isinstance(table, dict):
        raise UserInputError(f"{name}: no [system] table (a described rolling system)")
    entries = data.get("claims", [])
    if not isinstance(entries, list) or len(entries) > MAX_CLAIMS:
        raise UserInputError(f"{name}: claims must be a list of at most {MAX_CLAIMS} tables")
    system = _validated(SystemTable, table, name, "system").rolling_system()
    claims = [_validated(FileClaim, e, name, f"claims[{i}]") for i, e in enumerate(entries)]
    ids = [c.id for c in claims]
    if len(set(ids)) != len(ids):
        raise UserInputError(f"{name}: a claim id is used twice")
    search = data.get("discover")
    search = None if search is None else _validated(FileDiscovery, search, name, "discover")
    return system, search, claims


def _found(name: str, file_name: str, search: FileDiscovery) -> list[Claim]:
    """The finds of a ``[discover]`` search as claims: each integral, the density, each
    invariant relation and symmetry, and per class searched its dimension (the rank that
    proves "no other in this class", recomputed exactly when the claim is checked).

    The search is :func:`.discover.discover` (answered from the discovery cache after the
    first time), so worker processes that read the file again do not search again.
    """
    from .discover import discover

    found = discover(
        name,
        degree=search.degree,
        momentum=search.momentum,
        coefficient_degree=search.coefficient_degree,
        in_parameters=search.in_parameters,
        densities=search.densities,
        relations=search.relations,
        symmetries=search.symmetries,
        linear_degree=search.linear_degree,
        cofactor_degree=search.cofactor_degree,
    )  # fmt: skip  (the claims below are the proofs)
    s = found.search
    source = f"{file_name} (its [discover] class)"
    rank = (
        f"found in the class of {s.search_class.describe()}; rank {s.rank} of {s.unknowns} "
        f"unknowns: the class holds no other ({s.dimension} found)"
    )
    out = [
        Claim(
            id=f"{name}:found-F{i}",
            source=source,
            kind="integral",
            statement=f"F{i} = {sp.sstr(F)}",
            note=rank,
            system=name,
            build=partial(_integral_check, F),
        )
        for i, F in enumerate(s.integrals, 1)
    ]
    out.append(_class_claim(name, source, "integrals", s.dimension, rank, search))
    densities = found.densities
    if densities is not None and densities.found:
        rho = densities.density()
        out.append(
            Claim(
                id=f"{name}:found-density",
                source=source,
                kind="measure",
                statement=f"rho = {sp.sstr(rho)}",
                note="exponents solved over the powers of the denominators' factors",
                system=name,
                build=partial(_measure_check, rho),
            )
        )
    r = found.relations
    if r is not None:
        for i, rel in enumerate(r.relations, 1):
            out.append(
                Claim(
                    id=f"{name}:found-R{i}",
                    source=source,
                    kind="integral",
                    statement=f"R{i} = {sp.sstr(rel.expression)} = 0 is invariant: "
                    f"dR{i}/dt = ({sp.sstr(rel.rate)}) R{i}",
                    note=f"found in the class of {r.search_class.describe()}; {r.certificate()}",
                    system=name,
                    build=partial(_relation_check, rel.expression, rel.rate),
                )
            )
        if r.complete:
            out.append(
                _class_claim(name, source, "relations", len(r.relations), r.certificate(), search)
            )
    y = found.symmetries
    if y is not None:
        coords = ", ".join(c.name for c in y.coordinates)
        for i, X in enumerate(y.fields, 1):
            out.append(
                Claim(
                    id=f"{name}:found-X{i}",
                    source=source,
                    kind="transformation",
                    statement=f"X{i} = ({', '.join(sp.sstr(c) for c in X)}) along ({coords}) "
                    "is a symmetry: [X, f] = 0, tangent to the phase space",
                    note=f"found in the class of {y.search_class.describe()}",
                    system=name,
                    build=partial(_symmetry_check, X, y.coordinates),
                )
            )
        note = f"rank {y.rank} of {y.unknowns} unknowns, {len(y.trivial)} parallel to the field"
        out.append(_class_claim(name, source, "symmetries", y.dimension, note, search))
    return out


def _class_claim(name, source, kind: str, dimension: int, note: str, search) -> Claim:
    what = {"integrals": "first integrals (modulo constants)", "relations": "invariant "
            "relations (cofactor not zero)", "symmetries": "symmetry fields"}[kind]  # fmt: skip
    return Claim(
        id=f"{name}:found-class-{kind}",
        source=source,
        kind="value",
        statement=f"the [discover] class holds exactly {dimension} independent {what}",
        note=f"{note}; recomputed exactly when checked (the residual is found - stated)",
        system=name,
        build=partial(_dimension_check, kind, dimension, search),
    )


def _dimension_check(kind: str, stated: int, search: FileDiscovery, model: Model) -> Check:
    """The class searched again, exactly, without the cache: ``found - stated`` must be 0."""
    from ..derive.discovery import find_polynomial_integrals
    from ..derive.invariants import find_invariant_relations
    from ..derive.symmetries import find_symmetries

    if kind == "integrals":
        found = find_polynomial_integrals(
            model, search.degree, momentum=search.momentum,
            coefficient_degree=search.coefficient_degree, in_parameters=search.in_parameters,
        ).dimension  # fmt: skip
    elif kind == "relations":
        found = len(
            find_invariant_relations(
                model, momentum=search.momentum, coefficient_degree=search.linear_degree,
                cofactor_degree=search.cofactor_degree,
            ).relations
        )  # fmt: skip
    else:
        found = find_symmetries(
            model, momentum=search.momentum, coefficient_degree=search.linear_degree
        ).dimension
    return Check(exprs=[sp.Integer(found - stated)])


def _relation_check(F: sp.Expr, rate: sp.Expr, model: Model) -> Check:
    from .discover import relation_residual

    return Check(exprs=[relation_residual(F, rate, model)])


def _symmetry_check(components, coordinates, model: Model) -> Check:
    from .discover import symmetry_residuals

    return Check(exprs=symmetry_residuals(components, coordinates, model))


def _names(model: Model) -> dict[str, sp.Expr]:
    names = {s.name: s for s in (*model.state, *model.params)}
    if model.omega is not None:
        names.update({s.name: s for s in model.omega})
    return names


#: What a check in the coordinates (omega, g) says with its verdict.
_IN_OMEGA = (
    "in the coordinates (omega, g): M = II(g) omega, proved to invert the model's omega; "
    "a witness gives omega"
)


def _integral_check(expr: sp.Expr, model: Model) -> Check:
    if chained.applies(model, expr):  # too large to expand: the rate through the auxiliaries
        return Check(
            exprs=[expr],
            along_flow=True,
            method="exact-sampled",
            note="the expanded rate is too large for a Groebner proof",
        )
    uses_aux = bool(sp.sympify(expr).free_symbols & set(model.aux_symbols))
    if uses_aux and omega_coordinates.applies(model):  # one denominator det II, not powers
        rate = omega_coordinates.integral_rate(expr, model)
        return Check(exprs=[rate], free=list(model.omega), note=_IN_OMEGA)
    return Check(exprs=[lie_derivative(expr, model)])


def _measure_check(expr: sp.Expr, model: Model) -> Check:
    if omega_coordinates.applies(model):
        residual = omega_coordinates.measure_residual(expr, model)
        return Check(exprs=[residual], free=list(model.omega), note=_IN_OMEGA)
    return Check(exprs=[measure_residual(expr, model)])


_CHECKS = {"integral": _integral_check, "measure": _measure_check}


def _build(kind: str, text: str, where: str, model: Model) -> Check:
    expr = parse_expression(text, _names(model), where)
    return _CHECKS[kind](expr, model)


def _shipped(model: Model, name: str, file_name: str) -> list[Claim]:
    """The integrals and the density the derived model ships, as claims."""
    out = []
    for integral, expr in model.integrals:
        out.append(
            Claim(
                id=f"{name}:{integral}",
                source=f"{file_name} (derived)",
                kind="integral",
                statement=f"{integral} is a first integral of the derived {name}",
                system=name,
                build=partial(_integral_check, expr),
            )
        )
    if model.density is not None:
        out.append(
            Claim(
                id=f"{name}:density",
                source=f"{file_name} (derived)",
                kind="measure",
                statement=f"rho = {sp.sstr(model.density)} is an invariant density of {name}",
                system=name,
                build=partial(_measure_check, model.density),
            )
        )
    return out


def kane_covers(system: RollingSystem) -> bool:
    """Whether :mod:`.kane_rolling` sets the system up: a spherical body, or a convex body
    on a plane (fixed, turning, shaken) or a fixed sphere — an ellipsoid on a plane with
    its contact point in closed form, any other with the contact point as coordinates
    (:mod:`.kane_implicit`) where the comparison's rays meet the surface. A ball on a
    support surface: on an ellipsoid (:mod:`.kane_support`: gravity, an offset and a constant
    rotor) or any convex support where the comparison's rays meet it
    (:mod:`.kane_support_implicit`: also a potential, rubber contact, ``I(t)`` and
    ``K(t)``). A convex body on a support surface: both contact points as coordinates
    (:mod:`.kane_body_support`), where the rays meet both surfaces. Not a body in
    a spherical support of balls (no Kane set-up of the balls: its model is the multi-body
    reduction the claims of BKM12 §2.1 check).

    Parameters
    ----------
    system : RollingSystem

    Returns
    -------
    bool
    """
    from .kane_support import is_ellipsoid, parametrised_covers
    from .kane_support_implicit import support_contacts

    if system.support == "balls":
        return False
    # at the parameter values _kane_computed takes
    values = {n: sp.Rational(7 + 4 * i, 5 + 3 * i) for i, n in enumerate(system.parameter_names)}
    at = lambda e: e.xreplace({s: values[s.name] for s in e.free_symbols if s.name in values})  # noqa: E731
    support, surface = system._parsed["support_surface"], system._parsed["surface"]
    if support is not None:  # on a support: an ellipsoid's parametrisation, or the contacts
        F = at(support)  # as coordinates placed on rays (also a convex body's, on its rays)
        if surface is None and is_ellipsoid(F) and parametrised_covers(system._parsed):
            return True
        try:
            support_contacts(F)
        except ValueError:
            return False
    if surface is None:
        return True
    # a convex body: its contact point in closed form (an ellipsoid on a plane) or carried
    # as coordinates (kane_implicit, kane_body_support); placed where the comparison's rays
    # from the centre of mass meet the surface
    from .kane_implicit import places_contacts

    return places_contacts(at(surface))


def _kane_computed(system, parameter_names: tuple[str, ...]) -> Computed:
    """The derived model against ``KanesMethod`` (:mod:`.kane_rolling`) at generic exact
    parameter values (distinct positive rationals, deterministic)."""
    from .kane_rolling import kane_compare

    values = {n: str(sp.Rational(7 + 4 * i, 5 + 3 * i)) for i, n in enumerate(parameter_names)}
    result = kane_compare(system, build_model(system.name), values)
    return Computed(
        error=max(
            result.max_acceleration_error,
            result.max_momentum_error,
            result.max_normal_rate_error,
        ),
        bound=result.tolerance,
        what=f"angular acceleration, contact momentum and the rates of the support's normal "
        f"(and of the contact's position on a turntable) against KanesMethod at "
        f"{result.points} exact points, 40 digits",
        values=values,
    )


def claims_of_file(path: str | Path) -> list[Claim]:
    """The claims about the system a file describes: the model's own, then the file's.

    Parameters
    ----------
    path : str or Path
        A TOML file with a ``[system]`` table and optional ``[[claims]]``.

    Returns
    -------
    list of Claim
        Registered nowhere; the system is registered (:func:`register_system`) so that
        ``claim.model()`` finds it.

    Raises
    ------
    UserInputError
        An unreadable file, no ``[system]`` table, a bad description or claim entry (one
        line), before anything is derived.
    """
    system, search, entries = read_description(path)
    name = register_system(system).name
    model = build_model(name)
    names = _names(model)
    file_name = Path(path).name
    claims = _shipped(model, name, file_name)
    if kane_covers(system):
        claims.append(
            ComputedClaim(
                id=f"{name}:kane",
                source=f"{file_name} (derived)",
                kind="equation",
                statement=f"the derived equations of {name} are Kane's (sympy.physics.mechanics)",
                system=name,
                compute=partial(_kane_computed, system, tuple(model.param_names)),
            )
        )
    if search is not None:
        claims += _found(name, file_name, search)
    for entry in entries:
        where = f"{file_name}: claim {entry.id}"
        parse_expression(entry.expression, names, where)  # refused here, before any check
        claims.append(
            Claim(
                id=entry.id,
                source=file_name,
                kind="measure" if entry.kind == "measure" else "integral",
                statement=entry.statement or f"{entry.kind}: {entry.expression}",
                system=name,
                build=partial(_build, entry.kind, entry.expression, where),
                expected=entry.expected,
            )
        )
    return claims


def file_claim(path: str, claim_id: str) -> Claim:
    """The claim ``claim_id`` of the file at ``path`` (how a worker process finds it).

    Parameters
    ----------
    path : str
    claim_id : str

    Returns
    -------
    Claim

    Raises
    ------
    KeyError
        No such claim in the file.
    """
    for claim in claims_of_file(path):
        if claim.id == claim_id:
            return claim
    raise KeyError(claim_id)


def file_lookup(path: str | Path) -> partial:
    """A picklable ``claim_id -> Claim`` for the claims of ``path`` (for ``iter_verdicts``).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    functools.partial
    """
    return partial(file_claim, str(Path(path).resolve()))
