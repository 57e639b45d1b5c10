"""Null spaces of sparse matrices over QQ(parameters), by elimination with Markowitz pivots.

Used by :mod:`.discovery` for the blocks of the integrals' linear system whose entries are
polynomials in the parameters: sympy's ``rref`` over the field of fractions takes the first
non-zero entry of each column as pivot, and with seven parameters (the gyrostat's ``I, D,
K``) its fractions grow past any time bound; pivots that bound the fill-in and have few
terms keep them small. The vectors found are checked exactly against every row of the block
(:func:`annihilates`): the caller's proof of "no other" does not rest on the elimination.
"""

from __future__ import annotations

from sympy.polys.domains import Domain
from sympy.polys.matrices import DomainMatrix

__all__ = ["markowitz_null_vectors", "annihilates"]


def markowitz_null_vectors(rows: dict, ncols: int, field_: Domain) -> list[list] | None:
    """A basis of the null space of a sparse matrix over a field (rows ``{j: entry}``), by
    Gauss elimination with Markowitz pivots, or None when a row becomes zero.

    Each step takes the pivot that minimises ``(row length - 1) (column count - 1)``
    (the fill-in bound), the entry with the fewest terms among those: over QQ(parameters)
    that keeps the fractions small (sympy's ``rref`` takes the first non-zero entry of
    each column, and its fractions of seven parameters grow past any time bound, the
    gyrostat at degree 2/2). The rows given are independent at a rational point, so
    each one gives a pivot (a zero row is reported, never skipped). The null vectors are
    ``e_j`` for the free columns ``j`` completed by back substitution.

    Parameters
    ----------
    rows : dict of int to dict of int to field element
        The matrix's rows (sparse: ``{row: {column: entry}}``).
    ncols : int
        Number of columns.
    field_ : sympy.polys.domains.Domain
        The field of the entries (QQ or QQ(parameters)).

    Returns
    -------
    list of list or None
        One null vector per free column (dense, field elements), or None when the rows
        turn out dependent.
    """
    active = [dict(r) for r in rows.values()]
    done: list[tuple[int, dict]] = []
    while active:
        counts: dict = {}
        for r in active:
            for j in r:
                counts[j] = counts.get(j, 0) + 1
        best = None
        for i, r in enumerate(active):
            if not r:
                return None
            for j, v in r.items():
                size = _terms(field_.numer(v)) + _terms(field_.denom(v))
                key = ((len(r) - 1) * (counts[j] - 1), size, i, j)
                if best is None or key < best:
                    best = key
        _, _, i, j = best
        pivot_row = active.pop(i)
        inverse = field_.one / pivot_row[j]
        pivot_row = {k: v * inverse for k, v in pivot_row.items()}
        for r in active:
            factor = r.get(j)
            if factor is None:
                continue
            for k, v in pivot_row.items():
                value = r.get(k, field_.zero) - factor * v
                if value:
                    r[k] = value
                else:
                    r.pop(k, None)
        done.append((j, pivot_row))
    pivot_columns = {j for j, _ in done}
    vectors = []
    for free in (j for j in range(ncols) if j not in pivot_columns):
        v = {free: field_.one}
        for j, row in reversed(done):
            value = -sum((c * v[k] for k, c in row.items() if k != j and k in v), field_.zero)
            if value:
                v[j] = value
        vectors.append([v.get(k, field_.zero) for k in range(ncols)])
    return vectors


def annihilates(
    polynomial: DomainMatrix, reduced: DomainMatrix, domain: Domain, field_: Domain
) -> bool:
    """True when every row of ``reduced`` (over QQ(parameters)) is a null vector of the
    whole block ``polynomial`` (over QQ[parameters]): each row is multiplied by the
    least common multiple of its denominators and the products are computed exactly.

    Parameters
    ----------
    polynomial : DomainMatrix
        The block over QQ[parameters].
    reduced : DomainMatrix
        Candidate null vectors (rows) over QQ(parameters).
    domain, field_ : sympy.polys.domains.Domain
        QQ[parameters] and its field of fractions.

    Returns
    -------
    bool
        True when every product vanishes identically.
    """
    entries = polynomial.rep.to_sdm()
    for row in reduced.to_list():
        common = domain.one
        for c in row:
            if c:
                common = domain.lcm(common, field_.denom(c))
        vector = {
            j: domain.exquo(field_.numer(c) * common, field_.denom(c))
            for j, c in enumerate(row)
            if c
        }
        for line in entries.values():
            if sum((c * vector[j] for j, c in line.items() if j in vector), domain.zero):
                return False
    return True


def _terms(element) -> int:
    """Number of terms of a polynomial (1 for a number)."""
    return len(element) if hasattr(element, "__len__") else 1
