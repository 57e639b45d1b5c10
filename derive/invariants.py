"""Linear invariant relations and symmetries of a stated form, exactly.

Both searches use the coordinates and the ansatz of :mod:`.discovery`: in the search
coordinates ``x = (u, g)`` (``u`` the momentum group or ``omega``, ``g`` the other state
variables) the vector field is ``x' = V(x) = P(x)/Q(x)`` with polynomials ``P_k`` and one
common denominator ``Q`` that does not vanish on the phase space, and the *linear class
of coefficient degree d* is the span of the monomials ``u^a g^b`` with ``|a| <= 1`` and
``|b| <= d`` (affine in ``u``), taken modulo the phase-space ideal ``I`` (geometric
constraints and declared invariant relations) by Groebner normal forms. Coefficients are
rational numbers: what is found holds for every value of the model's parameters (specialise
the model's parameters first to search at given values).

**Invariant relations** (:func:`find_invariant_relations`). ``F`` in the linear class,
``F`` not in ``I`` and not a constant, with

    dF/dt = lambda F  on the phase space,   lambda = K/Q,

``K`` a polynomial of total degree ``<= cofactor_degree`` in the state (the *cofactor*;
for a polynomial field, ``Q = 1``, ``lambda = K`` itself: ``cofactor_degree = 0`` is the
class of constant ``lambda``). Then ``{F = 0}`` is invariant (a particular integral, a
Darboux polynomial of the field ``P``). Multiplied by ``Q`` the condition is
``NF(sum_k dF/dx_k P_k - K F) = 0``: bilinear in the coefficients ``c`` of ``F`` and
``kappa`` of ``K``. It is solved exactly in three steps:

1. the equations (monomials of the normal form) in which no ``kappa`` occurs are linear
   in ``c``: their null space ``c = N z`` over QQ;
2. the rest is bilinear in ``(z, kappa)``. A solution has ``z != 0``; in the chart where
   ``z_i`` is the first non-zero coordinate it is scaled to ``z_i = 1`` (``z_j = 0`` for
   ``j < i``), and a lex Groebner basis (``z`` before ``kappa``) gives the elimination
   ideal in ``kappa`` of that chart: ``{1}`` proves the chart has no solution, a
   zero-dimensional ideal gives finitely many candidate cofactors (its roots, exact:
   rational or algebraic numbers); a positive-dimensional one is a family of cofactors,
   reported (``complete`` is then False) and not resolved;
3. at each candidate ``kappa*`` the system is linear again: the null space of
   ``NF(L(b_j) - K* b_j)`` is every ``F`` of the class with that cofactor, and its rank is
   the proof there is no other.

``K* = 0`` gives the first integrals of the class (constants included, reported modulo
constants and separately from the relations).

**Symmetries** (:func:`find_symmetries`). Vector fields ``X = sum_k X_k d/dx_k`` with
every component in the linear class (so ``X`` is affine in ``u``), tangent to the phase
space (``NF(X(c)) = 0`` for each generator ``c`` of ``I``) and commuting with the field
(``[X, V] = 0`` on the phase space). Multiplied by ``Q^2``,
``[X, V]_l = (X(P_l) Q - P_l X(Q) - Q sum_k P_k dX_l/dx_k)/Q^2`` gives conditions linear in
the coefficients of ``X``: a null space over QQ whose rank proves there is no other. The
*trivial* ones, parallel to the field on the phase space (``X_k P_l - X_l P_k`` in ``I``:
the field itself and its multiples by first integrals, when polynomial), are identified
and counted apart.

A modulo-``I`` argument divides by ``Q`` (and by ``F`` for the cofactor's uniqueness): it
takes ``Q`` to be a non-zero-divisor modulo ``I`` (each factor of ``Q`` has a non-zero
normal form, checked; with a prime ideal such as the sphere's this suffices).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import sympy as sp
from sympy.polys.domains import QQ
from sympy.polys.matrices import DomainMatrix

from .algebra import RationalFunctionBuilder, ring_normal_form
from .discovery import (
    MAX_UNKNOWNS,
    _ansatz_basis,
    _check_degree,
    _check_group_and_time,
    _check_ideal,
    _common_fraction,
    _Coordinates,
    _count_monomials,
    _group_sizes,
    _momentum_group,
    _null_space,
    _omega_coordinates,
    _state_coordinates,
    _through_momentum,
)
from .errors import UserInputError
from .model import Model

__all__ = [
    "LinearClass",
    "InvariantRelation",
    "RelationSearch",
    "find_invariant_relations",
    "specialise",
    "MAX_COFACTOR_UNKNOWNS",
]

#: Largest number of cofactor coefficients (the bilinear unknowns ``kappa``) searched.
MAX_COFACTOR_UNKNOWNS = 40
#: Largest number of linear unknowns left for the Groebner step of the relation search.
MAX_BILINEAR_UNKNOWNS = 24


@dataclass(frozen=True)
class LinearClass:
    """The linear class searched: affine in the momentum, polynomial coefficients.

    Attributes
    ----------
    kind : str
        ``"relations"`` or ``"symmetries"``.
    momentum : str
    momentum_symbols, other_symbols : tuple of sympy.Symbol
    coefficient_degree : int
        Largest total degree of the coefficients in the other state variables.
    cofactor_degree : int or None
        Largest total degree of the cofactor ``K`` (relations only).
    denominator : sympy.Expr
        The common denominator ``Q`` of the vector field in these coordinates
        (``lambda = K/Q``).
    ideal : tuple of sympy.Expr
    """

    kind: str
    momentum: str
    momentum_symbols: tuple[sp.Symbol, ...]
    other_symbols: tuple[sp.Symbol, ...]
    coefficient_degree: int
    cofactor_degree: int | None
    denominator: sp.Expr
    ideal: tuple[sp.Expr, ...]

    def describe(self) -> str:
        """The class in words.

        Returns
        -------
        str
        """
        u = ", ".join(s.name for s in self.momentum_symbols)
        g = ", ".join(s.name for s in self.other_symbols)
        ideal = ", ".join(f"{sp.sstr(c)} = 0" for c in self.ideal) or "none"
        linear = (
            f"affine in {self.momentum} = ({u}) with coefficients polynomials of degree "
            f"<= {self.coefficient_degree} in ({g}) over the rational numbers"
        )
        if self.kind == "relations":
            q = sp.sstr(self.denominator)
            rate = (
                f"lambda = K/Q, K a polynomial of degree <= {self.cofactor_degree} in the "
                f"state, Q = {q if len(q) <= 80 else q[:77] + '...'}"
            )
            return (
                f"F {linear}, not constant, with dF/dt = lambda F where {rate}; modulo "
                f"the phase-space ideal ({ideal})"
            )
        return (
            f"vector fields whose components are {linear}, tangent to the phase space and "
            f"commuting with the field; modulo the phase-space ideal ({ideal})"
        )

    def as_dict(self) -> dict:
        """The class as plain data (JSON-ready).

        Returns
        -------
        dict
        """
        return {
            "kind": self.kind,
            "momentum": self.momentum,
            "momentum_symbols": [s.name for s in self.momentum_symbols],
            "other_symbols": [s.name for s in self.other_symbols],
            "coefficient_degree": self.coefficient_degree,
            "cofactor_degree": self.cofactor_degree,
            "denominator": sp.sstr(self.denominator),
            "ideal": [sp.sstr(c) for c in self.ideal],
        }


@dataclass(frozen=True)
class InvariantRelation:
    """``F = 0`` is invariant: ``dF/dt = rate * F`` with ``rate = cofactor/denominator``.

    Attributes
    ----------
    expression : sympy.Expr
        ``F`` in the search coordinates (primitive).
    cofactor : sympy.Expr
        ``K`` (polynomial; non-zero on the phase space).
    rate : sympy.Expr
        ``lambda = K/Q``.
    """

    expression: sp.Expr
    cofactor: sp.Expr
    rate: sp.Expr


@dataclass(frozen=True)
class RelationSearch:
    """Result of :func:`find_invariant_relations`.

    Attributes
    ----------
    model : str
    search_class : LinearClass
    relations : tuple of InvariantRelation
        For each cofactor found, a basis of the relations with that cofactor.
    integrals : tuple of sympy.Expr
        The class's first integrals (cofactor 0), modulo constants.
    unknowns : int
        Dimension of the linear class modulo the ideal.
    cofactor_unknowns : int
        Coefficients of the cofactor.
    equations : int
        Rows of the bilinear system.
    linear_rank : int
        Rank of the rows free of the cofactor (step 1).
    charts : int
        Charts of the Groebner step (step 2).
    ranks : tuple of (str, int)
        ``(cofactor, rank)`` at each candidate cofactor (step 3): ``unknowns - rank``
        relations with that cofactor, and no other.
    complete : bool
        False when a chart gave a positive-dimensional family of cofactors (not resolved:
        the class then may hold more than what is listed).
    seconds : float
    stage_seconds : dict of str to float
    """

    model: str
    search_class: LinearClass
    relations: tuple[InvariantRelation, ...]
    integrals: tuple[sp.Expr, ...]
    unknowns: int
    cofactor_unknowns: int
    equations: int
    linear_rank: int
    charts: int
    ranks: tuple[tuple[str, int], ...]
    complete: bool
    seconds: float
    stage_seconds: dict[str, float] = field(default_factory=dict)

    def certificate(self) -> str:
        """Why the class holds no other relation (one sentence).

        Returns
        -------
        str
        """
        if not self.complete:
            return (
                "incomplete: a chart of the bilinear system has a positive-dimensional family "
                "of cofactors (not resolved); the class may hold more relations"
            )
        at = "; ".join(f"K = {k}: rank {r} of {self.unknowns}" for k, r in self.ranks)
        return (
            f"rank {self.linear_rank} of {self.unknowns} on the equations free of the "
            f"cofactor; lex Groebner bases of the {self.charts} charts of the bilinear rest "
            f"leave the cofactors listed and no other; {at}"
        )


def specialise(model: Model, values: dict) -> Model:
    """The model at given exact parameter values (a special case such as Hess's top).

    Parameters
    ----------
    model : Model
    values : dict of str or sympy.Symbol to number
        Exact values (int, fractions, sympy rationals, or text such as ``"13/11"``); a
        parameter group whose symbols all get values leaves the model's parameters.

    Returns
    -------
    Model
        Right-hand side, auxiliary definitions, constraints, relations, integrals and the
        momentum substituted; the density, the structured inverse, the reparametrisation,
        the sampler and the details (derived for the symbolic parameters) dropped.

    Raises
    ------
    UserInputError
        An unknown parameter or a value that is not an exact rational number.
    """
    import dataclasses

    by_name = {s.name: s for s in model.params}
    sub = {}
    for key, value in values.items():
        name = key.name if isinstance(key, sp.Symbol) else str(key)
        if name not in by_name:
            raise UserInputError(
                f"model {model.name} has no parameter {name!r}; valid: {', '.join(by_name)}"
            )
        try:
            number = sp.Rational(str(value) if not isinstance(value, sp.Basic) else value)
        except (TypeError, ValueError):
            raise UserInputError(f"{name} = {value!r} is not an exact rational number") from None
        sub[by_name[name]] = number

    def put(e):
        return sp.sympify(e).xreplace(sub)

    def put_matrix(m):
        return None if m is None else m.xreplace(sub)

    return dataclasses.replace(
        model,
        parameters=tuple(p for p in model.parameters if not set(p.symbols) <= set(sub)),
        aux=tuple((a, put(e)) for a, e in model.aux),
        rhs=tuple(put(e) for e in model.rhs),
        constraints=tuple(put(e) for e in model.constraints),
        integrals=tuple((n, put(e)) for n, e in model.integrals),
        invariant_relations=tuple((n, put(e)) for n, e in model.invariant_relations),
        density=None,
        momentum_of_omega=put_matrix(model.momentum_of_omega),
        inertia_operator=put_matrix(model.inertia_operator),
        euler_poincare_remainder=put_matrix(model.euler_poincare_remainder),
        structured_inverse=None,
        reparametrisation=None,
        sampler=None,
        details=None,
    )


# ----------------------------------------------------------------- shared set-up
@dataclass
class _Setup:
    coords: _Coordinates
    x: tuple[sp.Symbol, ...]
    builder: RationalFunctionBuilder
    ideal: list[sp.Expr]
    numerators: list
    denominator: object  # ring element
    basis: list


def _setup(model: Model, momentum: str | None, coefficient_degree: int, per_unknown: int):
    _check_degree("coefficient degree", coefficient_degree)
    _check_group_and_time(model, momentum, "invariant relations and symmetries")
    name = momentum or _momentum_group(model)
    n_u, n_g = _group_sizes(model, name)
    monomials = (n_u + 1) * _count_monomials(n_g, coefficient_degree) * per_unknown
    if monomials > MAX_UNKNOWNS:
        raise UserInputError(
            f"the linear class with coefficients of degree {coefficient_degree} in the other "
            f"{n_g} state variables has {monomials} unknowns, more than this machine searches "
            f"({MAX_UNKNOWNS}); lower the degree"
        )
    through = _through_momentum(model, name)
    coords = _omega_coordinates(model) if through else _state_coordinates(model, name)
    x = (*coords.u, *coords.g)
    builder = RationalFunctionBuilder([*x, *model.params])
    ideal = [sp.expand(c) for c in coords.ideal]
    _check_ideal(ideal, x, model)
    numerators, denominator = _common_fraction(coords.velocity, builder, ideal, model)
    basis = _ansatz_basis(coords, 1, coefficient_degree, builder, ideal, constants=True)
    return _Setup(coords, x, builder, ideal, numerators, denominator, basis)


def _lie(p, s: _Setup):
    """``sum_k dp/dx_k P_k`` (the Lie derivative times ``Q``)."""
    gens = s.builder.ring.gens
    out = s.builder.ring.zero
    for k in range(len(s.x)):
        d = p.diff(gens[k])
        if not d.is_zero:
            out += d * s.numerators[k]
    return out


def _combination(vector, basis) -> sp.Expr:
    return sp.expand(sum((v * b.as_expr() for v, b in zip(vector, basis, strict=True)), sp.S.Zero))


def _primitive(expr: sp.Expr, x) -> sp.Expr:
    num, _ = sp.fraction(sp.together(expr))
    poly = sp.Poly(sp.expand(num), *x)
    if poly.is_zero:
        return sp.S.Zero
    _, prim = poly.primitive()
    if prim.LC().could_extract_minus_sign():
        prim = -prim
    return prim.as_expr()


# ----------------------------------------------------------------- relations
def find_invariant_relations(
    model: Model,
    *,
    momentum: str | None = None,
    coefficient_degree: int = 1,
    cofactor_degree: int = 1,
) -> RelationSearch:
    """Every linear invariant relation ``F = 0``, ``dF/dt = (K/Q) F``, of a stated class.

    Parameters
    ----------
    model : Model
        An autonomous model.
    momentum : str, optional
        The group ``F`` is affine in: a state group or ``"omega"`` (default ``M``).
    coefficient_degree : int, optional
        Largest degree of ``F``'s coefficients in the other state variables.
    cofactor_degree : int, optional
        Largest total degree of the cofactor ``K`` in the state.

    Returns
    -------
    RelationSearch
        The relations grouped by cofactor, the integrals of the class, and the
        certificate that there is no other (module docstring).

    Raises
    ------
    UserInputError
        Bad degrees or group, a time-dependent model, a class too large (with its size),
        before the bilinear step.
    """
    start = time.perf_counter()
    _check_degree("cofactor degree", cofactor_degree)
    bound = _count_monomials(len(model.state), cofactor_degree)
    if bound > MAX_COFACTOR_UNKNOWNS:
        raise UserInputError(
            f"a cofactor of degree {cofactor_degree} in the {len(model.state)} state variables "
            f"has up to {bound} coefficients, more than this machine searches "
            f"({MAX_COFACTOR_UNKNOWNS}); lower the cofactor degree"
        )
    stages: dict[str, float] = {}
    clock = time.perf_counter()
    s = _setup(model, momentum, coefficient_degree, 1)
    everything = _Coordinates("x", s.x, (), [], [])
    cofactors = _ansatz_basis(everything, cofactor_degree, 0, s.builder, s.ideal, constants=True)
    if len(cofactors) > MAX_COFACTOR_UNKNOWNS:
        raise UserInputError(
            f"a cofactor of degree {cofactor_degree} in the {len(s.x)} state variables has "
            f"{len(cofactors)} coefficients, more than this machine searches "
            f"({MAX_COFACTOR_UNKNOWNS}); lower the cofactor degree"
        )
    stages["ansatz"] = time.perf_counter() - clock
    clock = time.perf_counter()
    n, m = len(s.basis), len(cofactors)
    lie = [ring_normal_form(_lie(b, s), s.ideal, s.builder) for b in s.basis]
    prod = [[ring_normal_form(k * b, s.ideal, s.builder) for k in cofactors] for b in s.basis]
    with_kappa = {mono for row in prod for p in row for mono in p.itermonoms()}
    free_rows = {mono for p in lie for mono in p.itermonoms()} - with_kappa
    stages["lie derivatives"] = time.perf_counter() - clock
    clock = time.perf_counter()
    # step 1: the rows free of kappa, linear in c
    columns = [{mono: c for mono, c in p.iterterms() if mono in free_rows} for p in lie]
    linear_rank, null = _null_space(columns, n, False, s.builder, len(s.x))
    # step 2: the bilinear rest in (z, kappa), chart by chart
    z = sp.symbols(f"z0:{len(null)}")
    kappa = sp.symbols(f"kappa0:{m}")
    if len(null) > MAX_BILINEAR_UNKNOWNS:
        raise UserInputError(
            f"the bilinear step of this class has {len(null)} + {m} unknowns, more than this "
            f"machine solves ({MAX_BILINEAR_UNKNOWNS} + {MAX_COFACTOR_UNKNOWNS}); lower a degree"
        )
    c_of_z = [sum((v[j] * z[i] for i, v in enumerate(null)), sp.S.Zero) for j in range(n)]
    rows: dict = {}
    for j in range(n):
        if c_of_z[j] == 0:
            continue
        for mono, coeff in lie[j].iterterms():
            if mono in with_kappa:
                rows[mono] = rows.get(mono, 0) + c_of_z[j] * QQ.to_sympy(QQ.convert(coeff))
        for k in range(m):
            for mono, coeff in prod[j][k].iterterms():
                term = c_of_z[j] * kappa[k] * QQ.to_sympy(QQ.convert(coeff))
                rows[mono] = rows.get(mono, 0) - term
    table = _linear_table(rows.values(), z)
    nrows = len(table)
    table, left = _constant_pivots(table, len(z))
    candidates, complete = _cofactor_candidates(table, len(left), kappa)
    stages["cofactors"] = time.perf_counter() - clock
    clock = time.perf_counter()
    # step 3: at each cofactor, linear again
    q = s.denominator.as_expr()
    relations, integrals, ranks = _relations_at(candidates, lie, prod, s, cofactors)
    stages["solve"] = time.perf_counter() - clock
    found_class = LinearClass(
        "relations",
        s.coords.momentum,
        s.coords.u,
        s.coords.g,
        coefficient_degree,
        cofactor_degree,
        q,
        tuple(s.ideal),
    )
    return RelationSearch(
        model.name,
        found_class,
        tuple(relations),
        integrals,
        n,
        m,
        len(free_rows) + nrows,
        linear_rank,
        len(left),
        tuple(ranks),
        complete,
        time.perf_counter() - start,
        stages,
    )


def _relations_at(candidates, lie, prod, s: _Setup, cofactors):
    """At each candidate cofactor the system is linear again: its solutions (relations;
    at the zero cofactor the class's integrals) and its rank (no other)."""
    relations: list[InvariantRelation] = []
    integrals: tuple[sp.Expr, ...] = ()
    ranks = []
    q = s.denominator.as_expr()
    for cand in sorted(candidates, key=lambda c: (any(c), sp.default_sort_key(c))):
        vectors, rank = _eigenspace(cand, lie, prod, len(s.basis))
        cofactor = _combination(cand, cofactors) if any(cand) else sp.S.Zero
        ranks.append((sp.sstr(cofactor), rank))
        exprs = [_combination(v, s.basis) for v in vectors]
        if not any(cand):
            integrals = _modulo_constants(exprs, s.x)
            continue
        for F in exprs:
            relations.append(
                InvariantRelation(_primitive(F, s.x), cofactor, sp.cancel(cofactor / q))
            )
    return relations, integrals, ranks


def _cofactor_candidates(table: list[dict], nleft: int, kappa) -> tuple[set, bool]:
    """The cofactors ``kappa`` for which the bilinear rows have a non-zero solution, chart
    by chart (the first non-zero coordinate set to 1): a lex Groebner basis eliminates
    the linear unknowns; ``{1}`` means none in the chart. Also whether the list is
    complete (False when a chart holds a family of cofactors)."""
    candidates: set[tuple] = {tuple([sp.S.Zero] * len(kappa))}
    complete = True
    zl = sp.symbols(f"y0:{nleft}")
    equations = [sp.expand(sum((e * zl[i] for i, e in row.items()), sp.S.Zero)) for row in table]
    equations = [e for e in equations if e != 0]
    for i in range(nleft):
        fixed = {**{zl[j]: 0 for j in range(i)}, zl[i]: 1}
        chart = [sp.expand(e.xreplace(fixed)) for e in equations]
        chart = [e for e in chart if e != 0]
        if not chart:  # z_i = 1 solves for every kappa: a family of cofactors
            complete = False
            continue
        basis = sp.groebner(chart, *zl[i + 1 :], *kappa, order="lex")
        if list(basis.exprs) == [1]:
            continue
        elimination = [g for g in basis.exprs if not g.free_symbols & set(zl)]
        if not elimination or not sp.groebner(elimination, *kappa, order="lex").is_zero_dimensional:
            complete = False  # a family of cofactors
            continue
        for sol in sp.solve(elimination, list(kappa), dict=True):
            candidates.add(tuple(sol[k] for k in kappa))
    return candidates, complete


def _linear_table(expressions, z) -> list[dict]:
    """Each expression (linear in ``z``) as ``{i: coefficient of z_i}`` (zero rows dropped)."""
    out: list[dict] = []
    if not z:
        return out
    for e in expressions:
        poly = sp.Poly(sp.expand(e), *z)
        row = {}
        for mono, c in poly.terms():
            if c != 0:
                row[mono.index(1)] = c
        if row:
            out.append(row)
    return out


def _constant_pivots(table: list[dict], ncols: int):
    """Gaussian elimination on the entries that are non-zero rational numbers.

    An equation whose coefficient of ``z_p`` is a number ``a != 0`` gives
    ``z_p = -(1/a) sum_{i != p} e_i z_i`` for *every* cofactor: ``z_p`` and the equation
    leave the system and the other entries stay polynomials in ``kappa``. Returns the
    remaining rows (keys renumbered) and the indices of the remaining unknowns.
    """
    table = [dict(r) for r in table]
    alive = set(range(ncols))
    while True:
        pivot = next(
            ((r, p) for r, row in enumerate(table) for p, e in row.items() if e.is_Rational),
            None,
        )
        if pivot is None:
            break
        r, p = pivot
        prow = table.pop(r)
        a = prow.pop(p)
        alive.discard(p)
        for row in table:
            e = row.pop(p, None)
            if e is None:
                continue
            for i, v in prow.items():
                new = sp.expand(row.get(i, 0) - e * v / a)
                if new == 0:
                    row.pop(i, None)
                else:
                    row[i] = new
        table = [row for row in table if row]
    left = sorted(alive)
    index = {c: k for k, c in enumerate(left)}
    return [{index[i]: e for i, e in row.items()} for row in table], left


def _eigenspace(cand, lie, prod, n):
    """Null space and rank of ``NF(L(b_j) - K b_j)`` at the cofactor coefficients ``cand``."""
    exact = all(c.is_Rational for c in cand)
    columns = []
    for j in range(n):
        col: dict = {}
        for mono, c in lie[j].iterterms():
            col[mono] = col.get(mono, 0) + QQ.to_sympy(QQ.convert(c))
        for k, ck in enumerate(cand):
            if ck:
                for mono, c in prod[j][k].iterterms():
                    col[mono] = col.get(mono, 0) - ck * QQ.to_sympy(QQ.convert(c))
        columns.append(col)
    keys = sorted({key for col in columns for key in col})
    if exact:
        rows = {
            i: {j: QQ.convert(col[key]) for j, col in enumerate(columns) if col.get(key)}
            for i, key in enumerate(keys)
        }
        matrix = DomainMatrix(rows, (max(len(keys), 1), n), QQ)
        null = matrix.to_Matrix().nullspace() if keys else sp.eye(n).columnspace()
        return [list(v) for v in null], matrix.rank()
    matrix = sp.Matrix(len(keys), n, lambda i, j: columns[j].get(keys[i], 0))
    null = matrix.nullspace(simplify=True)
    return [list(v) for v in null], matrix.rank(simplify=True)


def _modulo_constants(exprs, x) -> tuple[sp.Expr, ...]:
    """A basis of the span of ``exprs`` modulo constants (primitive polynomials)."""
    polys = [sp.Poly(e, *x) for e in exprs]
    polys = [p - p.coeff_monomial(1) for p in polys]
    monos = sorted({mono for p in polys for mono in p.monoms()}, reverse=True)
    if not monos:
        return ()
    matrix = sp.Matrix(len(polys), len(monos), lambda i, j: polys[i].coeff_monomial(monos[j]))
    reduced, _ = matrix.rref()
    out = []
    for i in range(reduced.rows):
        row = reduced.row(i)
        if any(row):
            expr = sum(
                (
                    c * sp.Mul(*(v**e for v, e in zip(x, mono, strict=True)))
                    for c, mono in zip(row, monos, strict=True)
                ),
                sp.S.Zero,
            )
            out.append(_primitive(expr, x))
    return tuple(out)


# ----------------------------------------------------------------- symmetries
