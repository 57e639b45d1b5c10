"""Symmetries of a stated linear class: fields ``X`` with ``[X, V] = 0`` on the phase space.

The class, the ansatz and the exact linear algebra are those of the invariant relations
(:mod:`.invariants`): each component of ``X`` is affine in the momentum group with
coefficients polynomial of bounded degree in the other state variables; ``[X, V] Q^2``
reduced modulo the phase-space ideal and ``X`` tangent to it (``X(c)`` in the ideal for
every constraint ``c``) are linear in ``X``'s coefficients, so the rank of that system is
the proof that there is no other symmetry in the class. Fields parallel to ``V`` on the
phase space are reported apart (trivial).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import sympy as sp

from .algebra import ring_normal_form
from .discovery import _null_space
from .invariants import LinearClass, _combination, _lie, _Setup, _setup
from .model import Model

__all__ = ["SymmetrySearch", "find_symmetries"]


@dataclass(frozen=True)
class SymmetrySearch:
    """Result of :func:`find_symmetries`.

    Attributes
    ----------
    model : str
    search_class : LinearClass
    coordinates : tuple of sympy.Symbol
        The search coordinates ``x``; a field is the tuple of its components along them.
    fields : tuple of tuple of sympy.Expr
        A basis of the symmetries in the class that are not parallel to the field.
    trivial : tuple of tuple of sympy.Expr
        A basis of those parallel to the field on the phase space.
    unknowns : int
    equations : int
    rank : int
        ``unknowns - rank = len(fields) + len(trivial)``: no other in the class.
    seconds : float
    stage_seconds : dict of str to float
    """

    model: str
    search_class: LinearClass
    coordinates: tuple[sp.Symbol, ...]
    fields: tuple[tuple[sp.Expr, ...], ...]
    trivial: tuple[tuple[sp.Expr, ...], ...]
    unknowns: int
    equations: int
    rank: int
    seconds: float
    stage_seconds: dict[str, float] = field(default_factory=dict)

    @property
    def dimension(self) -> int:
        """Dimension of the space of symmetries in the class (``unknowns - rank``)."""
        return self.unknowns - self.rank


def find_symmetries(
    model: Model, *, momentum: str | None = None, coefficient_degree: int = 1
) -> SymmetrySearch:
    """Every symmetry field of a stated linear class, with the proof there is no other.

    Parameters
    ----------
    model : Model
        An autonomous model.
    momentum : str, optional
        The group the components are affine in (a state group or ``"omega"``).
    coefficient_degree : int, optional
        Largest degree of the components' coefficients in the other state variables.

    Returns
    -------
    SymmetrySearch
        The basis of the non-trivial symmetries, of the trivial ones (parallel to the
        field), the rank and the time.

    Raises
    ------
    UserInputError
        Bad degree or group, a time-dependent model, a class too large (with its size).
    """
    start = time.perf_counter()
    stages: dict[str, float] = {}
    clock = time.perf_counter()
    s = _setup(model, momentum, coefficient_degree, len(model.state))
    ring = s.builder.ring
    gens = ring.gens
    nx = len(s.x)
    q = s.denominator
    stages["ansatz"] = time.perf_counter() - clock
    clock = time.perf_counter()
    ideal_polys = [ring.from_expr(c) for c in s.ideal]
    # [b e_k, V]_l Q^2 = b (dP_l/dx_k Q - P_l dQ/dx_k) - delta_lk Q L(b)
    dq = [q.diff(gens[k]) for k in range(nx)]
    wedge = [
        [s.numerators[row].diff(gens[k]) * q - s.numerators[row] * dq[k] for k in range(nx)]
        for row in range(nx)
    ]
    columns = []
    for k in range(nx):
        for b in s.basis:
            col: dict = {}
            for i, c in enumerate(ideal_polys):
                d = c.diff(gens[k])
                if not d.is_zero:
                    for mono, v in ring_normal_form(b * d, s.ideal, s.builder).iterterms():
                        col[("tangent", i, mono)] = v
            lq = q * _lie(b, s)
            for row in range(nx):
                term = b * wedge[row][k]
                if row == k:
                    term = term - lq
                for mono, v in ring_normal_form(term, s.ideal, s.builder).iterterms():
                    col[("bracket", row, mono)] = v
            columns.append(col)
    equations = len({key for col in columns for key in col})
    stages["brackets"] = time.perf_counter() - clock
    clock = time.perf_counter()
    nb = len(s.basis)
    rank, null = _null_space(columns, nx * nb, False, s.builder, nx)
    fields = [
        tuple(_combination(v[k * nb : (k + 1) * nb], s.basis) for k in range(nx)) for v in null
    ]
    trivial, others = _split_parallel(fields, s)
    stages["solve"] = time.perf_counter() - clock
    found_class = LinearClass(
        "symmetries",
        s.coords.momentum,
        s.coords.u,
        s.coords.g,
        coefficient_degree,
        None,
        q.as_expr(),
        tuple(s.ideal),
    )
    return SymmetrySearch(
        model.name,
        found_class,
        s.x,
        others,
        trivial,
        nx * nb,
        equations,
        rank,
        time.perf_counter() - start,
        stages,
    )


def _split_parallel(fields, s: _Setup):
    """(basis of the fields parallel to ``P`` on the phase space, a complement basis)."""
    if not fields:
        return (), ()
    ring = s.builder.ring
    nx = len(s.x)
    comps = [[ring.from_expr(c) if c != 0 else ring.zero for c in f] for f in fields]
    columns = []
    for f in comps:
        col: dict = {}
        for k in range(nx):
            for row in range(k + 1, nx):
                w = f[k] * s.numerators[row] - f[row] * s.numerators[k]
                for mono, v in ring_normal_form(w, s.ideal, s.builder).iterterms():
                    col[(k, row, mono)] = v
        columns.append(col)
    _, null = _null_space(columns, len(fields), False, s.builder, nx)
    trivial = [
        tuple(
            sp.expand(sum((v[i] * fields[i][k] for i in range(len(fields))), sp.S.Zero))
            for k in range(nx)
        )
        for v in null
    ]
    if not trivial:
        return (), tuple(fields)
    # a complement: the found fields that raise the rank of the trivial span
    chosen: list = []
    span = list(trivial)
    for f in fields:
        trial = [*span, f]
        if _rank_of_fields(trial, s.x) > _rank_of_fields(span, s.x):
            chosen.append(f)
            span = trial
    return tuple(trivial), tuple(chosen)


def _rank_of_fields(fields, x) -> int:
    rows = []
    for f in fields:
        coeffs: dict = {}
        for k, comp in enumerate(f):
            for mono, c in sp.Poly(comp, *x).terms():
                coeffs[(k, mono)] = c
        rows.append(coeffs)
    keys = sorted({key for r in rows for key in r})
    return sp.Matrix(len(rows), len(keys), lambda i, j: rows[i].get(keys[j], 0)).rank()
