"""``chaplygin.discover``: first integrals, relations, symmetries found in a stated class,
each then proved.

The searches are :func:`chaplygin.derive.discovery.find_polynomial_integrals` (exact linear
algebra modulo the phase-space ideal; its rank proves that the class holds no other
integral) and, on request, :func:`chaplygin.derive.invariants.find_invariant_relations`
and :func:`~chaplygin.derive.symmetries.find_symmetries` (linear classes, see there). Each
find is then decided independently by the verifier's own machinery: the Lie derivative of
an integral along the model (:func:`.identity.lie_derivative`, which expands the auxiliary
symbols such as ``omega``), ``dF/dt - lambda F`` for a relation, the components of
``[X, f]`` and ``X(c)`` for a symmetry (``f`` the model's right-hand side in its state,
``c`` its constraints) are decided by :func:`.identity.decide` (a Groebner normal form
modulo the phase-space constraints).

A discovery is cached on disk (``<cache root>/discovery``, signed like the model cache:
:mod:`chaplygin.derive.cachefiles`), keyed by the system's variant key (its description's
fingerprint, the sources of ``derive/`` and the versions of Python, sympy and mpmath), the
sources of this module and of :mod:`.identity`, and the class asked for. An entry that is
absent, damaged, signed by someone else or stored under another key is recomputed.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import pickle
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import sympy as sp
from chaplygin.derive.cachefiles import cache_root, read_signed, write_signed
from chaplygin.derive.densities import DensitySearch, find_invariant_densities
from chaplygin.derive.discovery import IntegralSearch, find_polynomial_integrals
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.invariants import RelationSearch, find_invariant_relations, specialise
from chaplygin.derive.model import Model
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.symmetries import SymmetrySearch, find_symmetries

from .identity import Domain, Outcome, decide, lie_derivative, measure_residual

__all__ = ["Discovery", "discover", "discovery_cache_dir"]


@dataclass(frozen=True)
class Discovery:
    """The integrals found in a class and the verdict on each.

    Attributes
    ----------
    search : IntegralSearch
        The basis found, the class searched, the rank and the time of the search.
    proofs : tuple of Outcome
        One verdict per integral of ``search.integrals`` (``proved`` expected).
    seconds : float
        Wall time of the search and the proofs.
    """

    search: IntegralSearch
    proofs: tuple[Outcome, ...]
    seconds: float
    densities: DensitySearch | None = None
    density_proof: Outcome | None = None
    relations: RelationSearch | None = None
    relation_proofs: tuple[Outcome, ...] = ()
    symmetries: SymmetrySearch | None = None
    symmetry_proofs: tuple[Outcome, ...] = ()
    values: tuple[tuple[str, str], ...] = ()
    from_cache: bool = False

    @property
    def all_proved(self) -> bool:
        """True when every find (integral, density, relation, symmetry) is proved."""
        proofs = (
            *self.proofs,
            *(() if self.density_proof is None else (self.density_proof,)),
            *self.relation_proofs,
            *self.symmetry_proofs,
        )
        return all(p.verdict == "proved" for p in proofs)

    def relation_dict(self) -> dict | None:
        """The relation search as plain data (None when it was not asked for).

        Returns
        -------
        dict or None
            ``class``, ``relations`` (each with ``expression``, ``cofactor``, ``rate``
            and its verdict), the class's ``integrals`` (cofactor 0), ``complete``, the
            ``certificate`` and the time.
        """
        r = self.relations
        if r is None:
            return None
        return {
            "class": {"description": r.search_class.describe(), **r.search_class.as_dict()},
            "relations": [
                {
                    "expression": sp.sstr(rel.expression),
                    "cofactor": sp.sstr(rel.cofactor),
                    "rate": sp.sstr(rel.rate),
                    "verdict": p.verdict,
                    "method": p.method,
                }
                for rel, p in zip(r.relations, self.relation_proofs, strict=True)
            ],
            "integrals": [sp.sstr(F) for F in r.integrals],
            "unknowns": r.unknowns,
            "cofactor_unknowns": r.cofactor_unknowns,
            "complete": r.complete,
            "certificate": r.certificate(),
            "seconds": round(r.seconds, 3),
            "stage_seconds": {k: round(v, 3) for k, v in r.stage_seconds.items()},
        }

    def symmetry_dict(self) -> dict | None:
        """The symmetry search as plain data (None when it was not asked for).

        Returns
        -------
        dict or None
            ``class``, ``coordinates``, ``fields`` (components and verdict), ``trivial``
            (parallel to the field), ``unknowns``, ``rank``, ``dimension`` and the time.
        """
        y = self.symmetries
        if y is None:
            return None
        return {
            "class": {"description": y.search_class.describe(), **y.search_class.as_dict()},
            "coordinates": [c.name for c in y.coordinates],
            "fields": [
                {"components": [sp.sstr(c) for c in X], "verdict": p.verdict, "method": p.method}
                for X, p in zip(y.fields, self.symmetry_proofs, strict=True)
            ],
            "trivial": [[sp.sstr(c) for c in X] for X in y.trivial],
            "no_other": (
                f"rank {y.rank} of {y.unknowns} unknowns: the class holds exactly "
                f"{y.dimension} independent symmetries ({len(y.trivial)} parallel to the field)"
            ),
            "unknowns": y.unknowns,
            "rank": y.rank,
            "dimension": y.dimension,
            "equations": y.equations,
            "seconds": round(y.seconds, 3),
            "stage_seconds": {k: round(v, 3) for k, v in y.stage_seconds.items()},
        }

    def density_dict(self) -> dict | None:
        """The density search as plain data (None when it was not asked for).

        Returns
        -------
        dict or None
            ``family`` (the factors), ``density`` and its verdict, or ``none`` with the
            certificate (``rank`` and ``augmented_rank``), the free ``directions`` and the
            time.
        """
        d = self.densities
        if d is None:
            return None
        out = {
            "family": [sp.sstr(g) for g in d.factors],
            "rank": d.rank,
            "augmented_rank": d.augmented_rank,
            "directions": [[sp.sstr(e) for e in v] for v in d.directions],
            "seconds": round(d.seconds, 3),
        }
        if d.found:
            proof = self.density_proof
            out["density"] = sp.sstr(d.density())
            out["verdict"] = proof.verdict
            out["method"] = proof.method
        else:
            out["density"] = None
            out["none"] = (
                f"rank {d.rank} < augmented rank {d.augmented_rank}: no density of the form "
                "prod |g_j|^(a_j) in this family"
            )
        return out

    def as_dict(self) -> dict:
        """The discovery as plain data (JSON-ready).

        Returns
        -------
        dict
            ``model``, ``class`` (words and data), ``integrals`` (each with its verdict,
            method and seconds), ``unknowns``, ``rank``, ``dimension``, ``equations``,
            ``seconds`` and ``stage_seconds``.
        """
        s = self.search
        return {
            "model": s.model,
            "class": {"description": s.search_class.describe(), **s.search_class.as_dict()},
            "integrals": [
                {
                    "expression": sp.sstr(F),
                    "verdict": p.verdict,
                    "method": p.method,
                    "seconds": round(p.seconds, 3),
                }
                for F, p in zip(s.integrals, self.proofs, strict=True)
            ],
            "no_other": (
                f"rank {s.rank} of {s.unknowns} unknowns: the class holds exactly "
                f"{s.dimension} independent integrals modulo constants and the ideal"
            ),
            "unknowns": s.unknowns,
            "rank": s.rank,
            "dimension": s.dimension,
            "equations": s.equations,
            "monomials": s.monomials,
            "seconds": round(self.seconds, 3),
            "stage_seconds": {k: round(v, 3) for k, v in s.stage_seconds.items()},
            "density_search": self.density_dict(),
            "relation_search": self.relation_dict(),
            "symmetry_search": self.symmetry_dict(),
            "values": dict(self.values),
            "from_cache": self.from_cache,
        }


def discover(
    system: str | RollingSystem,
    effects: Iterable[str] | str = (),
    *,
    degree: int = 2,
    coefficient_degree: int = 2,
    momentum: str | None = None,
    in_parameters: bool = False,
    densities: bool = False,
    relations: bool = False,
    symmetries: bool = False,
    linear_degree: int = 1,
    cofactor_degree: int = 1,
    values: Mapping[str, object] | None = None,
    cache: bool = True,
) -> Discovery:
    """Find every first integral of a system in a polynomial class, and prove each.

    Parameters
    ----------
    system : str or RollingSystem
        A system's name (``chaplygin_ball`` ..., or one registered), or a description
        (registered under its name).
    effects : iterable of str or str, optional
        Effects of the variant (``gyrostat``, ``rubber`` ...; a string is comma-separated).
    degree : int, optional
        Largest degree in the momentum group.
    coefficient_degree : int, optional
        Largest degree of the coefficients in the other state variables.
    momentum : str, optional
        The group the integrals are polynomial in (a state group, or ``"omega"``).
    in_parameters : bool, optional
        Coefficients rational functions of the parameters (default rational numbers).
    densities : bool, optional
        Also search the invariant densities of the family of powers of the right-hand
        side's denominator factors (:func:`~chaplygin.derive.densities.find_invariant_densities`)
        and prove the one found by Liouville's equation (:func:`.identity.measure_residual`).
    relations : bool, optional
        Also search the linear invariant relations ``dF/dt = (K/Q) F``
        (:func:`~chaplygin.derive.invariants.find_invariant_relations`).
    symmetries : bool, optional
        Also search the symmetry fields of the linear class
        (:func:`~chaplygin.derive.symmetries.find_symmetries`).
    linear_degree : int, optional
        Degree of the coefficients (in the other state variables) of the linear class of
        the relations and the symmetries.
    cofactor_degree : int, optional
        Largest degree of the relations' cofactor ``K`` in the state.
    values : mapping of str to number, optional
        Exact parameter values at which every search is made (the model specialised:
        :func:`~chaplygin.derive.invariants.specialise`); default symbolic parameters.
    cache : bool, optional
        Read and write the discovery cache (:func:`discovery_cache_dir`).

    Returns
    -------
    Discovery

    Raises
    ------
    UserInputError
        An unknown system, effect or parameter, a bad degree or group, a time-dependent
        model, a class too large for the machine (with its size).

    Examples
    --------
    >>> import chaplygin
    >>> found = chaplygin.discover("chaplygin_ball", degree=1, coefficient_degree=1)
    >>> [sympy.sstr(F) for F in found.search.integrals], found.all_proved  # doctest: +SKIP
    (['M1*gamma1 + M2*gamma2 + M3*gamma3'], True)
    """
    request = {
        "degree": degree,
        "coefficient_degree": coefficient_degree,
        "momentum": momentum,
        "in_parameters": in_parameters,
        "densities": densities,
        "relations": relations,
        "symmetries": symmetries,
        "linear_degree": linear_degree,
        "cofactor_degree": cofactor_degree,
    }
    return _discover(system, effects, values, cache, request)


def _discover(system, effects, values, cache: bool, request: dict) -> Discovery:
    """:func:`discover` for a request (the class searched: the cache key's part)."""
    from chaplygin.derive.effects import parse_effects
    from chaplygin.derive.systems import (
        build_model,
        get_system,
        register_system,
        variant_cache_key,
    )

    start = time.perf_counter()
    if isinstance(system, RollingSystem):
        system = register_system(system).name
    if not isinstance(system, str):
        raise UserInputError(f"the system must be a name or a RollingSystem, not {system!r}")
    effect_list = effects if isinstance(effects, str) else list(effects)
    fixed = tuple(sorted((str(k), str(v)) for k, v in (values or {}).items()))
    request = {**request, "values": fixed}
    degree, momentum, linear_degree = (
        request["degree"],
        request["momentum"],
        request["linear_degree"],
    )
    chosen = parse_effects(effect_list, get_system(system).effects)  # bad input refused here
    path = None
    if cache:
        path = _cache_file(variant_cache_key(system, chosen), request)
        hit = _load(path)
        if hit is not None:
            return hit
    model = build_model(system, chosen)
    if fixed:
        model = specialise(model, dict(fixed))
    search = find_polynomial_integrals(
        model,
        degree,
        momentum=momentum,
        coefficient_degree=request["coefficient_degree"],
        in_parameters=request["in_parameters"],
    )
    proofs = tuple(decide([lie_derivative(F, model)], Domain(model)) for F in search.integrals)
    density_search, density_proof = _densities(model) if request["densities"] else (None, None)
    relation_search, relation_proofs = (
        _relations(model, momentum, linear_degree, request["cofactor_degree"])
        if request["relations"]
        else (None, ())
    )
    symmetry_search, symmetry_proofs = (
        _symmetries(model, momentum, linear_degree) if request["symmetries"] else (None, ())
    )
    found = Discovery(
        search,
        proofs,
        time.perf_counter() - start,
        density_search,
        density_proof,
        relation_search,
        relation_proofs,
        symmetry_search,
        symmetry_proofs,
        fixed,
    )
    if path is not None:
        _store(path, found)
    return found


def relation_residual(F: sp.Expr, rate: sp.Expr, model: Model) -> sp.Expr:
    """``dF/dt - rate F`` in the model's state and parameters (zero for a relation).

    Parameters
    ----------
    F, rate : sympy.Expr
        In the state, the parameters and the auxiliary symbols (``omega``).
    model : Model

    Returns
    -------
    sympy.Expr
    """
    return lie_derivative(F, model) - model.expand_aux(rate * F)


def symmetry_residuals(
    components: Iterable[sp.Expr], coordinates: Iterable[sp.Symbol], model: Model
) -> list[sp.Expr]:
    """The components of ``[X, f]`` and ``X(c)`` (``c`` each constraint and invariant
    relation) in the model's state: all zero on the phase space for a symmetry ``X``.

    Parameters
    ----------
    components : iterable of sympy.Expr
        ``X`` along ``coordinates``.
    coordinates : iterable of sympy.Symbol
        State symbols, or ``omega`` and the state without the momentum group (then ``X``
        is carried to the state by ``M = M(omega, g)``).
    model : Model

    Returns
    -------
    list of sympy.Expr
    """
    along = dict(zip(coordinates, components, strict=True))
    if model.omega is not None and set(model.omega) <= set(along):
        w_g = [*model.omega, *(s for s in model.state if s in along)]
        moved = {}
        for m, expr in zip(_momentum_symbols(model), model.momentum_of_omega, strict=True):
            moved[m] = sum((sp.diff(expr, v) * along[v] for v in w_g), sp.S.Zero)
        along = {**{s: along[s] for s in model.state if s in along}, **moved}
    X = [model.expand_aux(along.get(s, sp.S.Zero)) for s in model.state]
    f = model.rhs_expanded

    def apply(expr):
        return sum((sp.diff(expr, y) * X[k] for k, y in enumerate(model.state)), sp.S.Zero)

    out = [apply(f[i]) - lie_derivative(X[i], model) for i in range(len(model.state))]
    relations = [model.expand_aux(e) for _, e in model.invariant_relations]
    out += [apply(sp.sympify(c)) for c in (*model.constraints, *relations)]
    return out


def _momentum_symbols(model: Model) -> tuple[sp.Symbol, ...]:
    names = [n for n, _ in model.state_groups]
    return tuple(model.group("M" if "M" in names else names[0]))


# ----------------------------------------------------------------- the cache
#: First line of a discovery file: the format, then the HMAC of the pickle that follows.
_MAGIC = b"chaplygin-discovery-1\n"


def _densities(model: Model):
    """The density search and the verifier's proof of the density found (or None)."""
    search = find_invariant_densities(model)
    proof = None
    if search.found:
        proof = decide([measure_residual(search.density(), model)], Domain(model))
    return search, proof


def _relations(model: Model, momentum, linear_degree: int, cofactor_degree: int):
    """The relation search and the verifier's proof of each relation found."""
    search = find_invariant_relations(
        model, momentum=momentum, coefficient_degree=linear_degree,
        cofactor_degree=cofactor_degree,
    )  # fmt: skip
    proofs = tuple(
        decide([relation_residual(r.expression, r.rate, model)], Domain(model))
        for r in search.relations
    )
    return search, proofs


def _symmetries(model: Model, momentum, linear_degree: int):
    """The symmetry search and the verifier's proof of each symmetry found."""
    search = find_symmetries(model, momentum=momentum, coefficient_degree=linear_degree)
    proofs = tuple(
        decide(symmetry_residuals(X, search.coordinates, model), Domain(model))
        for X in search.fields
    )
    return search, proofs


def discovery_cache_dir() -> Path | None:
    """Folder of cached discoveries.

    Returns
    -------
    pathlib.Path or None
        ``<cache root>/discovery``; None when ``CHAPLYGIN_MODEL_CACHE=0`` (no cache).
    """
    if os.environ.get("CHAPLYGIN_MODEL_CACHE", "1") == "0":
        return None
    return cache_root() / "discovery"


def _code_digest() -> str:
    h = hashlib.sha256()
    here = Path(__file__).resolve().parent
    for name in ("discover.py", "identity.py"):
        h.update((here / name).read_bytes())
    return h.hexdigest()


def _cache_file(variant_key: str, request: dict) -> Path | None:
    folder = discovery_cache_dir()
    if folder is None:
        return None
    text = json.dumps({"variant": variant_key, "code": _code_digest(), **request}, sort_keys=True)
    return folder / f"{hashlib.sha256(text.encode()).hexdigest()[:40]}.pickle"


def _load(path: Path | None) -> Discovery | None:
    """The discovery stored at ``path``, or None (absent, damaged, not ours, another key).

    The pickle is read only after its HMAC (our per-user secret) checks out, and is used
    only when it names the same file (an entry of ours copied under another key is
    refused).
    """
    data = read_signed(path, _MAGIC)
    if data is None:
        return None
    try:
        name, found = pickle.loads(data)  # signed by us: our own bytes
    except Exception:  # an older class layout: recompute
        return None
    if name != path.name or not isinstance(found, Discovery):
        return None
    return dataclasses.replace(found, from_cache=True)


def _store(path: Path, found: Discovery) -> None:
    try:
        data = pickle.dumps((path.name, found), protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, AttributeError, TypeError):
        return  # the cache is only an aid
    write_signed(path, _MAGIC, data)
