"""Discovery of first integrals: every polynomial integral of a stated class, exactly.

The class (:class:`IntegralClass`) is the span of the monomials ``u^a g^b`` with
``|a| <= degree`` in a *momentum* group ``u`` (a state group such as ``M``, or the
angular velocity ``omega`` of the model) and ``|b| <= coefficient_degree`` in the other
state variables ``g`` (``gamma`` ...), with unknown coefficients that are rational
numbers or, with ``in_parameters``, rational functions of the model's parameters.
Two members that differ by an element of the phase-space ideal (the geometric
constraints and the invariant relations) or by a constant are the same function on the
phase space, so the class is taken modulo both: the monomials' Groebner normal forms,
constant terms dropped, are row-reduced to a basis ``b_1 .. b_n`` (the unknowns).

``F = sum c_i b_i`` is a first integral when its Lie derivative vanishes on the phase
space. In the chosen coordinates ``x = (u, g)`` the vector field is ``x' = P(x)/Q(x)``
with polynomials ``P`` and a common denominator ``Q`` that does not vanish on the
phase space (checked: its factors have non-zero normal forms), so the condition is
``NF(sum_i c_i sum_k db_i/dx_k P_k) = 0``: the coefficients of the normal form's
monomials give a linear system ``A c = 0`` over QQ (every monomial in state *and*
parameters) or over QQ(parameters) (monomials in the state). Its null space is the
space of integrals in the class; ``rank A`` proves that there is no other:
``dimension = unknowns - rank``.

With ``momentum="omega"`` the coordinates are ``(omega, g)``: the momentum is replaced
by its expression ``M = M(omega, g)`` (the model's ``momentum_of_omega``) and
``omega' = II^-1 (M' - dM/dg g')``, ``II = dM/domega``. The energy of the ball is
polynomial there (it has the denominator ``D^-1 - (gamma, A gamma)`` in ``M``).

Only autonomous models are searched (an integral of a time-dependent flow would need
``dF/dt`` in the ansatz). Sizes are estimated before any work and a class that is too
large is refused (:data:`MAX_UNKNOWNS`, :data:`MAX_MATRIX_ENTRIES`).
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import sympy as sp
from sympy.polys.domains import QQ
from sympy.polys.matrices import DomainMatrix

from .algebra import (
    RationalFunctionBuilder,
    UnsupportedExpression,
    exact_quotient,
    ring_normal_form,
)
from .errors import UserInputError
from .model import Model
from .sparse_nullspace import annihilates, markowitz_null_vectors

__all__ = [
    "IntegralClass",
    "IntegralSearch",
    "find_polynomial_integrals",
    "MAX_UNKNOWNS",
    "MAX_MATRIX_ENTRIES",
    "MAX_DEGREE",
]

#: Largest number of ansatz monomials (before the reduction modulo the ideal) searched.
MAX_UNKNOWNS = 1500
#: Largest estimated size (unknowns x equations) of the linear system; the equations are
#: bounded by the monomials the Lie derivative's numerator can have (:func:`_equation_bound`),
#: known once the vector field is written in the search coordinates (a fraction of a second).
MAX_MATRIX_ENTRIES = 200_000_000
#: Largest degree accepted in either slot (a guard against typing mistakes).
MAX_DEGREE = 12

OMEGA = "omega"


@dataclass(frozen=True)
class IntegralClass:
    """The class of functions searched for first integrals.

    Attributes
    ----------
    momentum : str
        Name of the group the integrals are polynomial in (``"M"``, ``"omega"`` ...).
    momentum_symbols : tuple of sympy.Symbol
    other_symbols : tuple of sympy.Symbol
        The other state variables, in which the coefficients are polynomials.
    degree : int
        Largest total degree in the momentum group.
    coefficient_degree : int
        Largest total degree of the coefficients in the other variables.
    in_parameters : bool
        Coefficients rational functions of the parameters (else rational numbers).
    parameters : tuple of sympy.Symbol
        The model's parameters.
    ideal : tuple of sympy.Expr
        Generators of the phase-space ideal the class is taken modulo, in the
        coordinates ``momentum_symbols + other_symbols``.
    """

    momentum: str
    momentum_symbols: tuple[sp.Symbol, ...]
    other_symbols: tuple[sp.Symbol, ...]
    degree: int
    coefficient_degree: int
    in_parameters: bool
    parameters: tuple[sp.Symbol, ...]
    ideal: tuple[sp.Expr, ...]

    def describe(self) -> str:
        """The class in words.

        Returns
        -------
        str
            One sentence naming the degrees, the variables, the coefficient field and
            the ideal.
        """
        u = ", ".join(s.name for s in self.momentum_symbols)
        g = ", ".join(s.name for s in self.other_symbols)
        field_ = (
            "rational functions of " + ", ".join(s.name for s in self.parameters)
            if self.in_parameters
            else "rational numbers"
        )
        ideal = ", ".join(f"{sp.sstr(c)} = 0" for c in self.ideal) or "none"
        return (
            f"polynomials of degree <= {self.degree} in {self.momentum} = ({u}) whose "
            f"coefficients are polynomials of degree <= {self.coefficient_degree} in ({g}) "
            f"with coefficients {field_}; modulo constants and the phase-space ideal ({ideal})"
        )

    def as_dict(self) -> dict:
        """The class as plain data (JSON-ready).

        Returns
        -------
        dict
            ``momentum``, ``momentum_symbols``, ``other_symbols``, ``degree``,
            ``coefficient_degree``, ``in_parameters``, ``parameters``, ``ideal`` (strings).
        """
        return {
            "momentum": self.momentum,
            "momentum_symbols": [s.name for s in self.momentum_symbols],
            "other_symbols": [s.name for s in self.other_symbols],
            "degree": self.degree,
            "coefficient_degree": self.coefficient_degree,
            "in_parameters": self.in_parameters,
            "parameters": [s.name for s in self.parameters],
            "ideal": [sp.sstr(c) for c in self.ideal],
        }


@dataclass(frozen=True)
class IntegralSearch:
    """Result of :func:`find_polynomial_integrals`.

    Attributes
    ----------
    model : str
        Variant name of the model searched.
    search_class : IntegralClass
    integrals : tuple of sympy.Expr
        A basis of the integrals in the class (modulo constants and the ideal), in
        the class's coordinates, row-reduced against the ansatz basis and made
        primitive (integer or polynomial coefficients without common factor).
    monomials : int
        Monomials of the class before the reduction modulo the ideal and constants.
    unknowns : int
        Dimension of the class modulo the ideal and constants (unknowns of the system).
    equations : int
        Rows of the linear system (monomials of the Lie derivative's normal form).
    rank : int
        Rank of the system: ``dimension = unknowns - rank`` is the proof that the
        class holds no other integral.
    seconds : float
        Wall time of the search.
    stage_seconds : dict of str to float
        Wall time per stage (``vector field``, ``ansatz``, ``lie derivatives``,
        ``solve``).
    """

    model: str
    search_class: IntegralClass
    integrals: tuple[sp.Expr, ...]
    monomials: int
    unknowns: int
    equations: int
    rank: int
    seconds: float
    stage_seconds: dict[str, float] = field(default_factory=dict)

    @property
    def dimension(self) -> int:
        """Dimension of the space of integrals found (``unknowns - rank``)."""
        return self.unknowns - self.rank


# ----------------------------------------------------------------- coordinates
@dataclass
class _Coordinates:
    momentum: str
    u: tuple[sp.Symbol, ...]
    g: tuple[sp.Symbol, ...]
    velocity: list[sp.Expr]  # x' for x = u + g (rational functions of x and parameters)
    ideal: list[sp.Expr]


def _momentum_group(model: Model) -> str:
    names = [n for n, _ in model.state_groups]
    return "M" if "M" in names else names[0]


def _through_momentum(model: Model, name: str) -> bool:
    """Whether the search in ``name`` is in ``omega`` written through the momentum (``omega``
    not a state group; a convex body's ``omega`` is one: searched as the group itself)."""
    return name == OMEGA and OMEGA not in dict(model.state_groups)


def _relations(model: Model, subs: dict) -> list[sp.Expr]:
    """Numerators of the invariant relations in the search coordinates (unit factors dropped)."""
    out = []
    params = set(model.params)
    for _, rel in model.invariant_relations:
        num, _ = sp.fraction(sp.cancel(sp.together(sp.sympify(rel).xreplace(subs))))
        _, factors = sp.factor_list(sp.expand(num))
        kept = [f**k for f, k in factors if not f.free_symbols <= params]
        if kept:
            out.append(sp.expand(sp.Mul(*kept)))
    return out


def _state_coordinates(model: Model, name: str) -> _Coordinates:
    u = tuple(dict(model.state_groups)[name])
    g = tuple(s for s in model.state if s not in set(u))
    f = dict(zip(model.state, model.rhs_expanded, strict=True))
    subs = dict(model._aux_expanded)
    return _Coordinates(
        name,
        u,
        g,
        [f[s] for s in (*u, *g)],
        [*model.constraints, *_relations(model, subs)],
    )


def _omega_coordinates(model: Model) -> _Coordinates:
    if model.omega is None or model.momentum_of_omega is None:
        raise UserInputError(
            f"model {model.name} has no angular velocity expressed through its momentum: "
            "search in a state group instead (momentum=None)"
        )
    omega = tuple(model.omega)
    momentum = dict(model.state_groups)[_momentum_group(model)]
    g = tuple(s for s in model.state if s not in set(momentum))
    m_of_w = [sp.expand(e) for e in model.momentum_of_omega]
    sub = dict(zip(momentum, m_of_w, strict=True))
    done: dict = {}
    for sym, expr in model.aux:  # every auxiliary but omega, in (omega, g)
        if sym not in set(omega):
            done[sym] = sp.sympify(expr).xreplace({**sub, **done})
    rhs = dict(
        zip(model.state, (sp.sympify(e).xreplace({**sub, **done}) for e in model.rhs), strict=True)
    )
    g_dot = sp.Matrix([rhs[s] for s in g])
    m_dot = sp.Matrix([rhs[s] for s in momentum])
    jac_w = sp.Matrix(m_of_w).jacobian(omega)
    jac_g = sp.Matrix(m_of_w).jacobian(g)
    det = sp.expand(jac_w.det(method="berkowitz"))
    w_dot = jac_w.adjugate(method="berkowitz") * (m_dot - jac_g * g_dot) / det
    return _Coordinates(
        OMEGA, omega, g, [*w_dot, *g_dot], [*model.constraints, *_relations(model, {})]
    )


# ----------------------------------------------------------------- sizes
def _count_monomials(nvars: int, degree: int) -> int:
    return math.comb(nvars + degree, degree)


def _equation_bound(
    numerators, nx: int, degree: int, coefficient_degree: int, in_parameters: bool
) -> int:
    """Bound on the rows of the linear system, from the vector field's numerators.

    ``NF(sum_k db/dx_k P_k)`` has total degree at most ``degree + coefficient_degree - 1
    + max deg_x P_k`` in the coordinates (grevlex reduction does not raise the degree),
    and its parameter parts are among those of the ``P_k`` (the ansatz and the ideal are
    free of parameters); without ``in_parameters`` each pair is a row.
    """
    dx = max((max((sum(m[:nx]) for m in p.itermonoms()), default=0) for p in numerators), default=0)
    bound = _count_monomials(nx, degree + coefficient_degree - 1 + dx)
    if not in_parameters:
        bound *= len({m[nx:] for p in numerators for m in p.itermonoms()})
    return bound


def _check_degree(label: str, value: object) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_DEGREE:
        raise UserInputError(
            f"the {label} must be an integer between 0 and {MAX_DEGREE}, not {value!r}"
        )


def _check_group_and_time(model: Model, momentum: str | None, searched: str) -> None:
    """Refuse an unknown momentum group and a time-dependent model (``searched`` names
    what is searched, for the message)."""
    groups = [n for n, _ in model.state_groups]
    if momentum is not None and momentum != OMEGA and momentum not in groups:
        raise UserInputError(
            f"model {model.name} has no group {momentum!r}; valid: {', '.join([*groups, OMEGA])}"
        )
    used = set().union(*(sp.sympify(e).free_symbols for e in model.rhs_expanded))
    if model.time in used:
        raise UserInputError(
            f"model {model.name} is not autonomous (its right-hand side depends on "
            f"{model.time}): {searched} are searched only for autonomous models"
        )


def _group_sizes(model: Model, name: str) -> tuple[int, int]:
    """Sizes of the momentum group ``name`` (or omega) and of the other state variables."""
    through = _through_momentum(model, name)
    n_u = 3 if through else len(dict(model.state_groups)[name])
    n_g = len(model.state) - (len(model.group(_momentum_group(model))) if through else n_u)
    return n_u, n_g


def _check_request(model, degree, coefficient_degree, momentum) -> None:
    _check_degree("degree", degree)
    _check_degree("coefficient degree", coefficient_degree)
    if degree < 1:
        raise UserInputError("the degree in the momentum must be at least 1")
    _check_group_and_time(model, momentum, "first integrals independent of time")


# ----------------------------------------------------------------- the search
def find_polynomial_integrals(
    model: Model,
    degree: int,
    *,
    momentum: str | None = None,
    coefficient_degree: int = 0,
    in_parameters: bool = False,
) -> IntegralSearch:
    """Every first integral of ``model`` in a polynomial class, with the proof there are no others.

    Parameters
    ----------
    model : Model
        An autonomous model.
    degree : int
        Largest total degree in the momentum group (at least 1).
    momentum : str, optional
        The group the integrals are polynomial in: a state group of the model, or
        ``"omega"`` (the angular velocity; the momentum is then written through it).
        Default: the state group ``M`` (else the first state group).
    coefficient_degree : int, optional
        Largest total degree of the coefficients in the other state variables.
    in_parameters : bool, optional
        Let the coefficients be rational functions of the parameters (default: rational
        numbers, the integral then holds for every parameter value).

    Returns
    -------
    IntegralSearch
        The basis found, the class, ``unknowns``, ``rank`` and the time taken.

    Raises
    ------
    UserInputError
        For a degree out of range, an unknown group, a time-dependent model, or a class
        whose estimated size exceeds :data:`MAX_UNKNOWNS` or :data:`MAX_MATRIX_ENTRIES`
        (the message gives the sizes); before any derivation work.

    Examples
    --------
    >>> from chaplygin.derive import build_model
    >>> found = find_polynomial_integrals(build_model("chaplygin_ball"), 1,
    ...                                   coefficient_degree=1)
    >>> found.integrals
    (M1*gamma1 + M2*gamma2 + M3*gamma3,)
    """
    start = time.perf_counter()
    _check_request(model, degree, coefficient_degree, momentum)
    name = momentum or _momentum_group(model)
    n_u, n_g = _group_sizes(model, name)
    monomials = _count_monomials(n_u, degree) * _count_monomials(n_g, coefficient_degree)
    too_large = (
        f"the class of degree {degree} in {name} with coefficients of degree "
        f"{coefficient_degree} in the other {n_g} state variables"
    )
    if monomials > MAX_UNKNOWNS:
        raise UserInputError(
            f"{too_large} has {monomials} unknowns, more than this machine searches "
            f"({MAX_UNKNOWNS}); lower a degree"
        )
    stages: dict[str, float] = {}
    clock = time.perf_counter()
    through = _through_momentum(model, name)
    coords = _omega_coordinates(model) if through else _state_coordinates(model, name)
    x = (*coords.u, *coords.g)
    builder = RationalFunctionBuilder([*x, *model.params])
    ideal = [sp.expand(c) for c in coords.ideal]
    _check_ideal(ideal, x, model)
    numerators = _common_numerators(coords.velocity, builder, ideal, model)
    equations = _equation_bound(numerators, len(x), degree, coefficient_degree, in_parameters)
    if monomials * equations > MAX_MATRIX_ENTRIES:
        raise UserInputError(
            f"{too_large} has {monomials} unknowns and up to {equations} equations "
            f"({monomials * equations} matrix entries), more than this machine searches "
            f"({MAX_MATRIX_ENTRIES} entries); lower a degree"
        )
    stages["vector field"] = time.perf_counter() - clock
    clock = time.perf_counter()
    basis = _ansatz_basis(coords, degree, coefficient_degree, builder, ideal)
    stages["ansatz"] = time.perf_counter() - clock
    clock = time.perf_counter()
    matrix, rows = _lie_system(basis, numerators, builder, ideal, len(x), in_parameters)
    stages["lie derivatives"] = time.perf_counter() - clock
    clock = time.perf_counter()
    rank, null = _null_space(matrix, len(basis), in_parameters, builder, len(x))
    integrals = tuple(_integral_expr(v, basis, builder, x) for v in null)
    stages["solve"] = time.perf_counter() - clock
    found_class = IntegralClass(
        name,
        coords.u,
        coords.g,
        degree,
        coefficient_degree,
        in_parameters,
        model.params,
        tuple(ideal),
    )
    return IntegralSearch(
        model.name,
        found_class,
        integrals,
        monomials,
        len(basis),
        rows,
        rank,
        time.perf_counter() - start,
        stages,
    )


def _check_ideal(ideal: Sequence[sp.Expr], x: Sequence[sp.Symbol], model: Model) -> None:
    params = set(model.params)
    for c in ideal:
        if sp.sympify(c).free_symbols & params:
            raise UserInputError(
                f"model {model.name}: the phase-space relation {sp.sstr(c)} depends on the "
                "parameters in these coordinates; search in other ones (momentum='omega')"
            )
        if not sp.sympify(c).free_symbols <= set(x):
            raise UserInputError(
                f"model {model.name}: the relation {sp.sstr(c)} is not written in the "
                "search coordinates"
            )


def _common_numerators(velocity, builder, ideal, model):
    """Numerators ``P_k`` of ``x_k' = P_k/Q`` over one common denominator ``Q``, made small.

    Every factor of ``Q`` must be non-zero on the phase space (its normal form is not
    zero), else multiplying by ``Q`` would make any function an integral. Two changes
    leave the system's solutions as they are and shrink it (the rubber ball's numerators
    in ``omega``: 26522 terms of degree 10 in the state before, a few hundred after):

    - each ``P_k`` is replaced by its normal form modulo the ideal: ``sum_k db/dx_k P_k``
      changes by an element of the ideal, so its normal form does not change;
    - a factor of ``Q`` free of the state (a polynomial in the parameters, such as
      ``(D + I1)^4``) is divided out of all ``P_k`` as often as it divides every one of
      them exactly: every equation is multiplied by the same non-zero polynomial of the
      parameters (the ideal is free of them, so ``NF(c p) = c NF(p)``), which changes
      no rank over QQ(parameters) and, over QQ, no solution (QQ[parameters] has no
      zero divisors).
    """
    numerators, _, factors = _fraction_parts(velocity, builder, ideal, model)
    numerators = [ring_normal_form(p, ideal, builder) for p in numerators]
    nx = len(builder.gens) - len(model.params)
    for f, k in factors.items():
        if any(sum(m[:nx]) for m in f.itermonoms()):
            continue
        for _ in range(k):
            quotients = [exact_quotient(p, f) for p in numerators]
            if any(q is None for q in quotients):
                break
            numerators = quotients
    return numerators


def _common_fraction(velocity, builder, ideal, model):
    """``([P_k], Q)``: the vector field ``x_k' = P_k/Q`` over one common denominator ``Q``
    (ring elements), each factor of ``Q`` checked non-zero on the phase space."""
    numerators, common, _ = _fraction_parts(velocity, builder, ideal, model)
    return numerators, common


def _fraction_parts(velocity, builder, ideal, model):
    """``([P_k], Q, {factor: power of Q})``, see :func:`_common_fraction`."""
    try:
        parts = [builder.convert(sp.sympify(v)) for v in velocity]
    except (UnsupportedExpression, ZeroDivisionError) as exc:
        raise UserInputError(
            f"model {model.name}: the vector field is not a rational function of the "
            f"search coordinates ({exc})"
        ) from None
    den: dict = {}
    for _, d in parts:
        for f, k in d.items():
            den[f] = max(den.get(f, 0), k)
    for f in den:
        if ring_normal_form(f, ideal, builder).is_zero:
            raise UserInputError(
                f"model {model.name}: a denominator of the vector field ({f.as_expr()}) "
                "vanishes on the phase space"
            )
    out = []
    for num, d in parts:
        term = num
        for f, k in den.items():
            if k - d.get(f, 0):
                term = term * f ** (k - d.get(f, 0))
        out.append(term)
    common = builder.ring.one
    for f, k in den.items():
        common = common * f**k
    return out, common, den


def _ansatz_basis(coords, degree, coefficient_degree, builder, ideal, constants=False):
    """A basis of the class modulo the ideal and (unless ``constants``) the constants
    (ring elements over QQ)."""
    ring = builder.ring
    gens = ring.gens
    n_u = len(coords.u)
    polys = []
    for a in _exponents(n_u, degree):
        for b in _exponents(len(coords.g), coefficient_degree):
            mono = ring.one
            for gen, e in zip(gens, (*a, *b), strict=False):
                mono = mono * gen**e
            nf = ring_normal_form(mono, ideal, builder)
            if not constants and nf.coeff(1):
                nf = nf - nf.coeff(1)  # drop the constant term
            if not nf.is_zero:
                polys.append(nf)
    if not polys:
        return []
    monos = sorted({m for p in polys for m in p.itermonoms()}, reverse=True)
    index = {m: j for j, m in enumerate(monos)}
    rows = [[QQ.zero] * len(monos) for _ in polys]
    for i, p in enumerate(polys):
        for m, c in p.iterterms():
            rows[i][index[m]] = QQ.convert(c)
    reduced, _ = DomainMatrix(rows, (len(polys), len(monos)), QQ).rref()
    basis = []
    for row in reduced.to_list():
        if any(row):
            p = ring.zero
            for j, c in enumerate(row):
                if c:
                    p[monos[j]] = ring.domain.convert(c)
            basis.append(p)
    return basis


def _exponents(nvars: int, degree: int):
    """Exponent tuples of the monomials of total degree <= ``degree`` in ``nvars`` variables."""
    for total in range(degree + 1):
        for combo in itertools.combinations_with_replacement(range(nvars), total):
            e = [0] * nvars
            for i in combo:
                e[i] += 1
            yield tuple(e)


def _lie_system(basis, numerators, builder, ideal, nx, in_parameters):
    """The columns ``NF(Q L(b_i))`` as ``{row key: coefficient}``; the row count."""
    gens = builder.ring.gens
    columns = []
    keys: dict = {}
    for b in basis:
        lie = builder.ring.zero
        for k in range(nx):
            db = b.diff(gens[k])
            if not db.is_zero:
                lie += db * numerators[k]
        nf = ring_normal_form(lie, ideal, builder)
        col: dict = {}
        for m, c in nf.iterterms():
            key = m[:nx] if in_parameters else m
            if in_parameters:
                col.setdefault(key, {})[m[nx:]] = c
            else:
                col[key] = c
            keys.setdefault(key, len(keys))
        columns.append(col)
    return columns, len(keys)


def _null_space(columns, ncols, in_parameters, builder, nx):
    """(rank, null-space basis) of the system whose column ``j`` is ``columns[j]``.

    The system falls apart into blocks (columns joined when they share a row: the
    connected components of its sparsity pattern); rank and null space are the sums of
    the blocks'. Returns the null space as vectors of sympy numbers (or rational
    functions of the parameters), each block's basis row-reduced.
    """
    parent = list(range(ncols))

    def root(j):
        while parent[j] != j:
            parent[j] = parent[parent[j]]
            j = parent[j]
        return j

    owner: dict = {}
    for j, col in enumerate(columns):
        for key in col:
            if key in owner:
                parent[root(j)] = root(owner[key])
            else:
                owner[key] = j
    blocks: dict = {}
    for j in range(ncols):
        blocks.setdefault(root(j), []).append(j)
    rank, null = 0, []
    for cols in blocks.values():
        part = [columns[j] for j in cols]
        solve = _block_null_parametric if in_parameters else _block_null_rational
        r, vectors = solve(part, builder, nx)
        rank += r
        for v in vectors:
            full = [sp.S.Zero] * ncols
            for j, c in zip(cols, v, strict=True):
                full[j] = c
            null.append(full)
    return rank, null


def _sparse(columns, convert, domain):
    keys: dict = {}
    rows: dict = {}
    for j, col in enumerate(columns):
        for key, c in col.items():
            rows.setdefault(keys.setdefault(key, len(keys)), {})[j] = convert(c)
    return DomainMatrix(rows, (max(len(keys), 1), len(columns)), domain)


def _reduced_null(matrix):
    """Row-reduced basis of the null space of ``matrix`` (a DomainMatrix, rows) or None."""
    null = matrix.nullspace()
    if null.shape[0] == 0:
        return None
    reduced, _ = null.rref()
    return reduced


def _as_sympy(reduced, domain):
    if reduced is None:
        return []
    return [[domain.to_sympy(c) for c in r] for r in reduced.to_list() if any(r)]


def _block_null_rational(columns, builder, nx):
    matrix = _sparse(columns, QQ.convert, QQ)
    return matrix.rank(), _as_sympy(_reduced_null(matrix), QQ)


#: Rational point at which a parametric block is specialised first (its rank there is a
#: lower bound of the generic rank; a seeded generator keeps runs reproducible).
SPECIALISATION_SEED = 24


def _block_null_parametric(columns, builder, nx):
    """Rank and null space over QQ(parameters) of one block.

    At a rational point ``p0`` the rank ``r0`` is computed over QQ: the generic rank is
    at least ``r0`` (a non-zero minor at ``p0`` is a non-zero polynomial). Full rank
    there proves the block has no solution. Else ``r0`` rows independent at ``p0`` are
    solved over QQ(parameters) (Gauss elimination with Markowitz pivots,
    :func:`.sparse_nullspace.markowitz_null_vectors`), and every vector of their null
    space is checked against the whole block exactly over QQ[parameters]: when all
    ``n - r0`` pass, the null space has dimension at least ``n - r0`` and at most
    ``n - r0`` (the rank at the point), so it is exact and the rank is ``r0``; otherwise
    (an unlucky point) the whole block is solved over QQ(parameters).
    """
    import random

    domain = QQ.poly_ring(*builder.gens[nx:])
    field_ = domain.get_field()
    rng = random.Random(SPECIALISATION_SEED)
    point = [QQ(rng.randint(-97, 97) or 1, rng.randint(2, 89)) for _ in builder.gens[nx:]]

    def at_point(coeffs):
        return sum((c * _monomial_value(m, point) for m, c in coeffs.items()), QQ.zero)

    special = _sparse(columns, at_point, QQ)
    r0 = special.rank()
    if r0 == len(columns):
        return r0, []

    def exact(coeffs):
        return field_.convert_from(domain.ring.from_dict(coeffs), domain)

    _, pivots = special.transpose().rref()  # rows of the block independent at the point
    polynomial = _sparse(columns, domain.ring.from_dict, domain)
    chosen = _primitive_rows(polynomial, pivots, field_)
    vectors = markowitz_null_vectors(chosen.rep.to_sdm(), len(columns), field_)
    if vectors is not None and len(vectors) == len(columns) - r0:
        reduced = DomainMatrix(vectors, (len(vectors), len(columns)), field_).rref()[0]
        if annihilates(polynomial, reduced, domain, field_):
            return r0, _as_sympy(reduced, field_)
    matrix = _sparse(columns, exact, field_)
    return matrix.rank(), _as_sympy(_reduced_null(matrix), field_)


def _primitive_rows(matrix, rows, field_):
    """The given rows of a matrix over QQ[parameters], each divided by the gcd of its
    entries (a non-zero factor: the null space is the same, the fractions smaller)."""
    domain = matrix.domain
    out: dict = {}
    for k, i in enumerate(rows):
        row = matrix.rep.to_sdm().get(i, {})
        common = domain.zero
        for c in row.values():
            common = domain.gcd(common, c)
        out[k] = {j: field_.convert_from(domain.exquo(c, common), domain) for j, c in row.items()}
    return DomainMatrix(out, (len(rows), matrix.shape[1]), field_)


def _monomial_value(exponents, point):
    value = QQ.one
    for e, v in zip(exponents, point, strict=True):
        if e:
            value *= v**e
    return value


def _integral_expr(vector, basis, builder, x):
    """``sum v_i b_i`` as a primitive polynomial in the coordinates (sympy)."""
    expr = sp.together(
        sum((v * b.as_expr() for v, b in zip(vector, basis, strict=True)), sp.S.Zero)
    )
    num, _ = sp.fraction(expr)
    poly = sp.Poly(sp.expand(num), *x)
    _, prim = poly.primitive()
    if prim.LC().could_extract_minus_sign():
        prim = -prim
    return prim.as_expr()
