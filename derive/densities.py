"""Invariant densities found, not only checked: exponents of a product family, solved exactly.

The family is ``rho = prod_j |g_j|^(a_j)`` over fixed polynomial factors ``g_j`` of the
configuration and momenta: by default the irreducible factors of the denominators of the
model's right-hand side (the auxiliary definitions expanded: ``omega`` through the Woodbury
coefficient ``Z`` and the multipliers ``mu`` of the constraints on omega alone), and any
further factors a caller names (a quadratic form ``(gamma, S gamma)`` with a given ``S``...).
A quadratic form with an *unknown* matrix ``S`` is not in the family: its entries would
multiply the exponents (a bilinear system), so the family is always one of fixed factors.
Liouville's equation for ``rho`` is

    div f + sum_j a_j (f, grad g_j) / g_j = 0   on the phase space,

the convention of the verifier's ``measure_residual``. Writing ``f = P/Q`` over the common
denominator ``Q = prod g^(k_g)`` of its components, the left side is
``(S G + sum_j (a_j - k_j) N_j) / (Q G)`` with ``S = sum_i dP_i/dy_i``, ``G = prod_j g_j``
and ``N_j = (P, grad g_j) G / g_j``: a polynomial identity affine in the unknown exponents.
Its numerator is restricted to the invariant relations of the model (linear in the momentum:
solved for as many momentum components by Cramer's rule, the common denominator cleared),
reduced to its normal form modulo the Groebner basis of the geometric constraints, and split
into the coefficients of the state monomials: a linear system ``A a = b`` over the field of
rational functions of the parameters. Its solutions are the densities of the family.

Which divergence. The flow lives on the constraint manifold (and, for a constraint on omega
alone, on a level set of an invariant relation), but ``f`` is written on the ambient space.
The models' ``f`` keeps every level set of the constraint functions ``c`` (``(gamma,
gamma)``, the orthonormality of the frame: identically, off the manifold too) and of the
invariant relations ``r`` (``d r/dt = 0`` on the whole phase space: the claims
``BKM12-3rub.constraint``, ``BKM12-57.constraint`` and, for the rubber ball on a line with
both relations, ``BKM12-3rub57.constraint``). For a flow with that property,
``L_f(rho dV) = L_f(nu) ^ dc ^ dr`` where ``nu = rho dV / (dc dr)`` is the measure induced on
the level set; so the ambient residual vanishes on the phase space exactly when the induced
measure ``rho dV / (dc dr)`` is invariant there, whatever the extension off it. That is the
statement this module solves for (and the one the models' ``density`` fields state, "``rho
dM dgamma / d(omega, gamma)``" for the rubber ball). The level-set property is an input, not
checked here: the verifier proves it for the shipped models.

The solve is exact and certified. Rows are picked at a seeded rational value of the
parameters (a maximal independent set of ``[A | b]``), the small system on those rows is
solved over ``QQ(parameters)``, and every candidate (a particular solution, each basis
vector of the homogeneous solutions) is checked against *every* row exactly; a row that
fails joins the picked ones and the solve repeats. "None in this family" is the statement
``rank [A | b] = rank A + 1``: a non-zero minor of the picked rows bounds the first rank from
below, and the homogeneous solutions, verified on all rows, fix ``rank A``. Both ranks are
over ``QQ(parameters)``: the statement holds for generic parameters (special values, a
symmetric body say, can have more).
"""

from __future__ import annotations

import itertools
import random
import time
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.polys.domains import QQ
from sympy.polys.groebnertools import groebner
from sympy.polys.matrices import DomainMatrix
from sympy.polys.rings import ring

from .algebra import FACTOR_SEED, RationalFunctionBuilder, UnsupportedExpression, ring_normal_form
from .errors import DerivationError
from .model import Model

__all__ = ["DensitySearch", "find_invariant_densities"]

#: Seed of the rational parameter values at which the rows of the linear system are picked.
ROW_CHOICE_SEED = 20240624


@dataclass(frozen=True)
class DensitySearch:
    """What :func:`find_invariant_densities` found, with its evidence.

    Attributes
    ----------
    model : str
        Name of the model variant searched.
    factors : tuple of sympy.Expr
        The family's factors ``g_j``, in the model's parameters; the family is
        ``prod_j |g_j|^(a_j)``.
    denominator_powers : tuple of int
        Power of each factor in the common denominator of the right-hand side (0 for a
        factor named by the caller that is not in it).
    exponents : tuple of sympy.Expr or None
        A particular solution ``a`` (rational numbers, or rational functions of the
        parameters if the system says so); None when the family holds no density.
    directions : tuple of tuple of sympy.Expr
        A basis of the homogeneous solutions: products ``prod g_j^(v_j)`` that are first
        integrals on the phase space (any multiple may be added to ``exponents``).
    rank : int
        Rank of ``A`` over the rational functions of the parameters.
    augmented_rank : int
        Rank of ``[A | b]``: ``rank`` (a density exists) or ``rank + 1`` (none in the
        family; the certificate).
    equations : int
        Rows of the system (state monomials of the reduced numerator with a non-zero
        coefficient).
    certificate_rows : int
        Rows the exact solve used (the others were checked against its result).
    monomial_degree : int
        Total degree in the state of the reduced numerator.
    relations : tuple of sympy.Expr
        Invariant relations the identity was restricted to (aux expanded).
    eliminated : tuple of sympy.Symbol
        Momentum components solved for from the relations.
    seconds : float
        Wall time of the search.
    """

    model: str
    factors: tuple[sp.Expr, ...]
    denominator_powers: tuple[int, ...]
    exponents: tuple[sp.Expr, ...] | None
    directions: tuple[tuple[sp.Expr, ...], ...]
    rank: int
    augmented_rank: int
    equations: int
    certificate_rows: int
    monomial_degree: int
    relations: tuple[sp.Expr, ...]
    eliminated: tuple[sp.Symbol, ...]
    seconds: float

    @property
    def found(self) -> bool:
        """True when the family holds an invariant density."""
        return self.exponents is not None

    @property
    def family(self) -> str:
        """The family searched, in words."""
        names = ", ".join(f"g{j + 1}" for j in range(len(self.factors)))
        return (
            f"rho = prod |g_j|^(a_j) over {len(self.factors)} fixed factors ({names}), "
            "exponents a_j in the rational functions of the parameters"
        )

    def density(self, exponents: Sequence[sp.Expr] | None = None) -> sp.Expr:
        """The density ``prod g_j^(a_j)`` of an exponent vector.

        Parameters
        ----------
        exponents : sequence of sympy.Expr, optional
            Default: the particular solution :attr:`exponents`.

        Returns
        -------
        sympy.Expr
            The product (each factor may be negative on the phase space; a density is
            its absolute value).

        Raises
        ------
        ValueError
            When no exponents are given and the family holds no density, or the length
            differs from the number of factors.
        """
        a = self.exponents if exponents is None else tuple(exponents)
        if a is None or len(a) != len(self.factors):
            raise ValueError(f"{self.model}: no exponent vector of length {len(self.factors)}")
        return sp.Mul(*(g ** sp.sympify(e) for g, e in zip(self.factors, a, strict=True)))

    def summary(self) -> str:
        """A few lines for a report: the family, the verdict, its certificate, the time.

        Returns
        -------
        str
        """
        lines = [f"{self.model}: {self.family}"]
        for j, (g, k) in enumerate(zip(self.factors, self.denominator_powers, strict=True)):
            lines.append(f"  g{j + 1} = {g}   (power {k} in the denominator of f)")
        size = (
            f"{self.equations} equations in {len(self.factors)} unknowns (state degree "
            f"{self.monomial_degree}), {self.certificate_rows} rows solved exactly"
        )
        if self.found:
            lines.append(f"  density: exponents {list(self.exponents)}; {size}")
            lines += [f"  + any multiple of {list(v)}" for v in self.directions]
        else:
            lines.append(
                f"  none in this family: rank [A|b] = {self.augmented_rank} > rank A = "
                f"{self.rank}; {size}"
            )
        if self.relations:
            lines.append(f"  on the invariant relations, solved for {list(self.eliminated)}")
        lines.append(f"  {self.seconds:.2f} s")
        return "\n".join(lines)


def _working_parameters(model: Model) -> tuple[tuple[sp.Symbol, ...], dict, dict]:
    """Parameters the search runs in (the model's reparametrisation: ``A_i = 1/J_ii``)."""
    rep = model.reparametrisation
    if rep is None:
        return model.params, {}, {}
    new = tuple(rep.forward) + tuple(p for p in model.params if p not in rep.inverse)
    return new, dict(rep.inverse), dict(rep.forward)


def _check_model(model: Model) -> None:
    exprs = [*model.rhs, *(e for _, e in model.aux), *model.constraints]
    if any(model.time in sp.sympify(e).free_symbols for e in exprs):
        raise DerivationError(
            f"{model.name}: the right-hand side depends on time; the density search handles "
            "autonomous models only"
        )
    if any(sp.sympify(c).free_symbols - set(model.state) for c in model.constraints):
        raise DerivationError(
            f"{model.name}: a phase-space constraint involves parameters; the density search "
            "needs constraints in the state alone"
        )


def _builder(model: Model, inverse: dict, params: tuple[sp.Symbol, ...]) -> RationalFunctionBuilder:
    builder = RationalFunctionBuilder(model.state + params)
    try:
        for sym, expr in model.aux:
            builder.define(sym, expr.xreplace(inverse))
    except UnsupportedExpression as exc:
        raise DerivationError(
            f"{model.name}: an auxiliary definition is not a rational function of the state "
            f"({exc}); the density search needs a rational right-hand side"
        ) from None
    return builder


def _irreducible(poly, ring) -> tuple:
    """``(constant, [(monic irreducible factor, power)])`` of a PolyElement.

    Seeded like :func:`.algebra.seeded_factor` (Wang's algorithm draws random points: the
    same factorisation takes the same path and time in every process).
    """
    from sympy.core import random as sympy_random

    state = sympy_random.rng.getstate()
    sympy_random.rng.seed(FACTOR_SEED)
    try:
        const, parts = poly.factor_list()
    finally:
        sympy_random.rng.setstate(state)
    out = []
    for g, k in parts:
        lc = g.LC
        const = const * lc**k
        out.append((g.quo_ground(lc), k))
    return ring.domain.convert(const), out


def _common_denominator(model: Model, builder: RationalFunctionBuilder, inverse: dict):
    """Numerators ``P_i`` over ``Q = prod g^k`` (irreducible monic ``g``): ``(P, {g: k})``."""
    ring = builder.ring
    parts = []
    for e in model.rhs:
        try:
            num, den = builder.convert(e.xreplace(inverse))
        except UnsupportedExpression as exc:
            raise DerivationError(
                f"{model.name}: the right-hand side is not a rational function of the state "
                f"({exc}); the density search needs a rational right-hand side"
            ) from None
        const, powers = ring.domain.one, {}
        for f, k in den.items():
            c, irr = _irreducible(f, ring)
            const = const * c**k
            for g, e_g in irr:
                powers[g] = powers.get(g, 0) + e_g * k
        parts.append((num.quo_ground(const), powers))
    common: dict = {}
    for _, powers in parts:
        for g, k in powers.items():
            common[g] = max(common.get(g, 0), k)
    numerators = []
    for num, powers in parts:
        for g, k in common.items():
            if k - powers.get(g, 0):
                num = num * g ** (k - powers.get(g, 0))
        numerators.append(num)
    return numerators, common


def _caller_factors(model, builder, inverse, factors) -> list:
    """Monic irreducible factors (with state variables) of the caller's expressions."""
    ring = builder.ring
    out = []
    for expr in factors:
        num, den = builder.convert(model.expand_aux(sp.sympify(expr)).xreplace(inverse))
        if any(_has_state(f, len(model.state)) for f in den):
            raise DerivationError(f"{model.name}: the factor {expr} is not a polynomial")
        out += [g for g, _ in _irreducible(num, ring)[1]]
    return out


def _has_state(poly, n_state: int) -> bool:
    return any(any(m[:n_state]) for m in poly.monoms())


def _gradient_products(numerators, factors, ring, n_state):
    """``N_j = (P, grad g_j) prod_{l != j} g_l`` and ``S G`` (see the module docstring)."""
    gens = ring.gens[:n_state]
    divergence = ring.zero
    for p, y in zip(numerators, gens, strict=True):
        divergence += p.diff(y)
    product = ring.one
    for g in factors:
        product = product * g
    columns = []
    for j, g in enumerate(factors):
        flux = ring.zero
        for p, y in zip(numerators, gens, strict=True):
            flux += p * g.diff(y)
        others = ring.one
        for l, h in enumerate(factors):
            if l != j:
                others = others * h
        columns.append(flux * others)
    return divergence * product, columns


def _determinant(matrix: list[list]):
    """Laplace expansion (the matrices are at most 3 x 3: relations on omega)."""
    if len(matrix) == 1:
        return matrix[0][0]
    total = None
    for j, entry in enumerate(matrix[0]):
        minor = [row[:j] + row[j + 1 :] for row in matrix[1:]]
        term = entry * _determinant(minor)
        term = term if j % 2 == 0 else -term
        total = term if total is None else total + term
    return total


def _relation_solution(model, builder, inverse, constraints):
    """Momentum components solved from the invariant relations: ``(indices, U, V)``.

    ``u_k = U_k / V`` on the relations (Cramer's rule; ``V`` not zero on the phase space).
    """
    ring = builder.ring
    relations = [model.expand_aux(e).xreplace(inverse) for _, e in model.invariant_relations]
    if not relations:
        return (), (), None
    unknowns = [model.state.index(u) for u in model.relation_unknowns]
    rows = []
    for rel in relations:
        num = builder.numerator(rel)
        coeffs = [num.diff(ring.gens[i]) for i in unknowns]
        if any(_has_unknown(c, unknowns) for c in coeffs):
            raise DerivationError(
                f"{model.name}: the invariant relation {rel} is not linear in "
                f"{model.relation_unknowns}"
            )
        rows.append((coeffs, num))
    for picked in itertools.combinations(reversed(range(len(unknowns))), len(rows)):
        picked = sorted(picked)
        square = [[coeffs[k] for k in picked] for coeffs, _ in rows]
        # the relation minus its terms in the picked unknowns (the others stay free)
        rows_rest = []
        for coeffs, num in rows:
            rest = num
            for k in picked:
                rest = rest - coeffs[k] * ring.gens[unknowns[k]]
            rows_rest.append((coeffs, rest))
        denominator = _determinant(square)
        if ring_normal_form(denominator, constraints, builder).is_zero:
            continue
        solved = []
        for col in range(len(picked)):
            replaced = [
                [(-rest if k == col else row[k]) for k in range(len(picked))]
                for row, (_, rest) in zip(square, rows_rest, strict=True)
            ]
            solved.append(_determinant(replaced))
        indices = tuple(unknowns[k] for k in picked)
        for _, num in rows:  # a self-check: the relations hold after the substitution
            sub = _substitute(num, indices, solved, denominator, _max_degree(num, indices))
            if not ring_normal_form(sub, constraints, builder).is_zero:
                raise DerivationError(f"{model.name}: solving the invariant relations failed")
        return indices, tuple(solved), denominator
    raise DerivationError(f"{model.name}: the invariant relations are not independent")


def _has_unknown(poly, unknowns) -> bool:
    return any(any(m[i] for i in unknowns) for m in poly.monoms())


def _substitute(poly, indices, solved, denominator, degree):
    """``V^degree poly(u_k = U_k / V)``: a polynomial again."""
    ring = poly.ring
    groups: dict = {}
    for monom, coeff in poly.iterterms():
        key = tuple(monom[i] for i in indices)
        rest = list(monom)
        for i in indices:
            rest[i] = 0
        groups.setdefault(key, {})[tuple(rest)] = coeff
    out = ring.zero
    for key, terms in groups.items():
        part = ring.from_dict(terms)
        for u, e in zip(solved, key, strict=True):
            if e:
                part = part * u**e
        out += part * denominator ** (degree - sum(key))
    return out


def _max_degree(poly, indices) -> int:
    return max((sum(m[i] for i in indices) for m in poly.monoms()), default=0)


def _constraint_basis(model: Model, polys) -> list:
    """Monic grevlex Groebner basis (over ``QQ``, in the state ring) of the constraints,
    eliminated down to the state variables that occur in ``polys``.

    A polynomial in the remaining variables vanishes on the phase space exactly when it
    lies in the elimination ideal (the constraint ideals of the models are prime and their
    real points dense), so its normal form modulo the smaller basis decides the same
    question with fewer and lower reductions.
    """
    if not model.constraints:
        return []
    n_state = len(model.state)
    used = [any(m[i] for p in polys for m in p.monoms()) for i in range(n_state)]
    drop = [s for s, u in zip(model.state, used, strict=True) if not u]
    keep = [s for s, u in zip(model.state, used, strict=True) if u]
    constraints = [sp.expand(c) for c in model.constraints]
    if drop and any(c.free_symbols & set(drop) for c in constraints):
        eliminated = sp.groebner(constraints, *drop, *keep, order="lex")
        constraints = [g for g in eliminated.exprs if not g.free_symbols & set(drop)]
    state_ring, *_ = ring(model.state, QQ, order="grevlex")
    gb = groebner([state_ring.from_expr(c) for c in constraints], state_ring)
    return [g.monic() for g in gb]


def _coefficient_rows(polys, model: Model, params: tuple[sp.Symbol, ...]):
    """Normal forms modulo the constraints, split into rows ``{state monomial: coefficients}``.

    State variables that occur in none of ``polys`` (the frame vector ``beta`` of the ball
    along a line: nothing depends on it) are eliminated from the constraints first
    (:func:`_constraint_basis`). The reduction runs in ``QQ[params][state]`` (grevlex in
    the state): the constraints
    involve the state alone, so their Groebner basis over ``QQ`` is one over the
    parameters' polynomials and the normal form is the one over ``QQ(params)``, with far
    fewer terms than in the flat ring of state and parameters.

    Returns
    -------
    domain : sympy domain
        ``QQ[params]`` (``QQ`` without parameters): the ring of the coefficients.
    keys : list of tuple
        The state monomials, sorted.
    rows : list of list
        One coefficient per poly for each monomial.
    """
    n_state = len(model.state)
    domain = QQ[params] if params else QQ
    coefficient_ring, *_ = ring(model.state, domain, order="grevlex")
    basis = _constraint_basis(model, polys)
    rows: dict = {}
    for col, poly in enumerate(polys):
        grouped: dict = {}
        for monom, coeff in poly.iterterms():
            grouped.setdefault(monom[:n_state], {})[monom[n_state:]] = coeff
        if params:
            lifted = {k: domain.ring.from_dict(v) for k, v in grouped.items()}
        else:
            lifted = {k: v[()] for k, v in grouped.items()}
        reduced = coefficient_ring.from_dict(lifted)
        if basis and reduced:
            reduced = _remainder_monic(reduced, basis)
        for monom, coeff in reduced.iterterms():
            rows.setdefault(monom, [domain.zero] * len(polys))[col] = coeff
    keys = sorted(rows)
    return domain, keys, [rows[k] for k in keys]


def _remainder_monic(poly, basis):
    """Normal form of ``poly`` (coefficients in ``QQ[params]``) modulo a monic Groebner
    basis with rational coefficients (in a ring of the same monomial order).

    The division of :func:`.algebra.ring_normal_form` (monomials in a heap, largest first,
    each popped once), with the quotient's coefficients multiplied by the basis's rational
    numbers (``mul_ground``) instead of by polynomials: no division at all, as the basis is
    monic.
    """
    import heapq

    ring_ = poly.ring
    monomial_mul, monomial_div = ring_.monomial_mul, ring_.monomial_div
    key = lambda m: (-sum(m), m[::-1])  # noqa: E731  grevlex, largest first in a min-heap
    leads = [(g.LM, [(m, c) for m, c in g.iterterms() if m != g.LM]) for g in basis]
    todo = dict(poly.iterterms())
    heap = [(key(m), m) for m in todo]
    heapq.heapify(heap)
    out = {}
    while heap:
        _, m = heapq.heappop(heap)
        c = todo.pop(m, None)
        if c is None:
            continue
        for lm, tail in leads:
            q = monomial_div(m, lm)
            if q is None:
                continue
            for mg, cg in tail:
                m1 = monomial_mul(mg, q)
                old = todo.get(m1)
                step = c.mul_ground(cg) if hasattr(c, "mul_ground") else c * cg
                new = -step if old is None else old - step
                if not new:
                    todo.pop(m1, None)
                else:
                    if old is None:
                        heapq.heappush(heap, (key(m1), m1))
                    todo[m1] = new
            break
        else:
            out[m] = c
    return ring_.from_dict(out) if out else ring_.zero


@dataclass(frozen=True)
class _Solution:
    particular: list | None
    null: list[list]
    rank: int
    augmented_rank: int
    certificate_rows: int


def _independent_rows(values: list[list], limit: int) -> list[int]:
    """Indices of a maximal set of independent rows (exact, over QQ), in order."""
    basis: list[tuple[int, list]] = []  # (pivot column, reduced row)
    picked = []
    for index, row in enumerate(values):
        row = list(row)
        for col, b in basis:
            if row[col]:
                factor = row[col] / b[col]
                row = [x - factor * y for x, y in zip(row, b, strict=True)]
        pivot = next((c for c, x in enumerate(row) if x), None)
        if pivot is not None:
            basis.append((pivot, row))
            picked.append(index)
            if len(picked) == limit:
                break
    return picked


def _primitive(vector: list, domain) -> list:
    """``vector`` divided by the gcd of its entries (small numbers instead of the large
    polynomials a fraction-free elimination leaves behind)."""
    if domain == QQ:
        return vector
    common = domain.zero
    for x in vector:
        common = domain.gcd(common, x)
    return [domain.exquo(x, common) for x in vector] if common else vector


def _failing_row(full: DomainMatrix, vector: list) -> int | None:
    """First row ``r`` with ``full[r] . vector != 0`` (exact, in ``full``'s domain)."""
    column = DomainMatrix([[v] for v in vector], (len(vector), 1), full.domain)
    product = full.matmul(column).to_list()
    return next((r for r, (x,) in enumerate(product) if x), None)


def _solve(rows: list[list], n: int, domain) -> _Solution:
    """The affine solution space of ``A a = b`` (``rows`` are ``[A | -b]``), certified.

    Fraction-free: the null spaces of the picked rows are computed over the polynomial
    ring of the parameters (no gcds), a solution ``(a, 1)`` is a null vector ``v`` of
    ``[A | -b]`` with ``v_n != 0`` divided by ``v_n``, and every candidate is checked
    against all rows by polynomial products.
    """
    rng = random.Random(ROW_CHOICE_SEED)
    gens = domain.ring.gens if domain != QQ else ()
    point = [QQ(rng.randint(1, 97), rng.randint(1, 89)) for _ in gens]
    values = [[c(*point) if gens else c for c in row] for row in rows]
    picked = _independent_rows(values, n + 1)
    full = DomainMatrix(rows, (len(rows), n + 1), domain)
    coefficients = full.extract(list(range(len(rows))), list(range(n)))
    while True:
        sub = full.extract(picked, list(range(n + 1)))
        null = coefficients.extract(picked, list(range(n))).nullspace().to_list()
        null = [_primitive(v, domain) for v in null]
        augmented = [_primitive(v, domain) for v in sub.nullspace().to_list()]
        homogeneous = next((v for v in augmented if v[n]), None)
        candidates = [(coefficients, v) for v in null]
        if homogeneous is not None:
            candidates.append((full, homogeneous))
        failing = None
        for matrix, vector in candidates:
            failing = _failing_row(matrix, vector)
            if failing is not None:
                break
        if failing is None:
            break
        if failing in picked:  # cannot happen for an exact solve of the picked rows
            raise DerivationError("density search: the exact solve disagrees with its rows")
        picked.append(failing)
    field = domain.get_field()
    particular = None
    if homogeneous is not None:
        last = field.convert_from(homogeneous[n], domain)
        particular = [field.convert_from(x, domain) / last for x in homogeneous[:n]]
    null_field = [[field.convert_from(x, domain) for x in v] for v in null]
    rank = n - len(null)
    return _Solution(particular, null_field, rank, rank + (particular is None), len(picked))


def _sorted_factors(factors) -> list:
    return sorted(factors, key=lambda g: (max(map(sum, g.monoms())), str(g.as_expr())))


def find_invariant_densities(
    model: Model,
    *,
    factors: Sequence[sp.Expr] | None = None,
    extra_factors: Sequence[sp.Expr] = (),
) -> DensitySearch:
    """Invariant densities ``prod_j |g_j|^(a_j)`` of a model, exponents solved exactly.

    See the module docstring for the identity, the divergence on the phase space and
    the certificate of "none in this family".

    Parameters
    ----------
    model : Model
        An autonomous model whose right-hand side and auxiliary definitions are rational
        in the state (square roots are refused) and whose constraints involve the state
        alone.
    factors : sequence of sympy.Expr, optional
        The family's factors, polynomials in the state (and parameters; the model's
        auxiliary symbols are expanded); each is split into its irreducible factors.
        Default: the irreducible factors of the denominators of the right-hand side that
        involve the state.
    extra_factors : sequence of sympy.Expr
        Added to the family (a quadratic form ``(gamma, S gamma)`` with a given ``S``...).

    Returns
    -------
    DensitySearch
        The family, the affine space of exponent vectors (or the certificate that it is
        empty), the sizes of the system and the wall time.

    Raises
    ------
    DerivationError
        A time-dependent or non-rational model, constraints with parameters, a factor
        that is not a polynomial, dependent invariant relations, or an empty family.
    """
    start = time.perf_counter()
    _check_model(model)
    params, inverse, forward = _working_parameters(model)
    builder = _builder(model, inverse, params)
    ring, n_state = builder.ring, len(model.state)
    constraints = tuple(sp.expand(c) for c in model.constraints)
    numerators, denominator = _common_denominator(model, builder, inverse)
    state_factors = _sorted_factors(g for g in denominator if _has_state(g, n_state))
    if factors is None:
        family = list(state_factors)
    else:
        family = _caller_factors(model, builder, inverse, factors)
    for g in _caller_factors(model, builder, inverse, extra_factors):
        family.append(g)
    family = list(dict.fromkeys(g for g in family if _has_state(g, n_state)))
    if not family:
        raise DerivationError(f"{model.name}: the density family has no factor in the state")
    every = family + [g for g in state_factors if g not in family]
    base, columns = _gradient_products(numerators, every, ring, n_state)
    for g, column in zip(every, columns, strict=True):
        base = base - column * denominator.get(g, 0)
    polys = [*columns[: len(family)], base]
    indices, solved, common = _relation_solution(model, builder, inverse, constraints)
    if indices:
        degree = max(_max_degree(p, indices) for p in polys)
        polys = [_substitute(p, indices, solved, common, degree) for p in polys]
    domain, keys, rows = _coefficient_rows(polys, model, params)
    solution = _solve(rows, len(family), domain)
    field = domain.get_field()

    def expr(element) -> sp.Expr:
        return sp.sympify(field.to_sympy(element)).xreplace(forward)

    return DensitySearch(
        model=model.name,
        factors=tuple(g.as_expr().xreplace(forward) for g in family),
        denominator_powers=tuple(denominator.get(g, 0) for g in family),
        exponents=(
            None if solution.particular is None else tuple(expr(a) for a in solution.particular)
        ),
        directions=tuple(tuple(expr(a) for a in v) for v in solution.null),
        rank=solution.rank,
        augmented_rank=solution.augmented_rank,
        equations=len(keys),
        certificate_rows=solution.certificate_rows,
        monomial_degree=max((sum(k) for k in keys), default=0),
        relations=tuple(model.expand_aux(e) for _, e in model.invariant_relations),
        eliminated=tuple(model.state[i] for i in indices),
        seconds=time.perf_counter() - start,
    )
