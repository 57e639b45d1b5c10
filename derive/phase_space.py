"""Points of a model's phase space: the one sampler of the toolkit.

Tests, numerics and the verifier draw points here.

* Exact (:func:`sample_point`): parameters from their physical domain, the model's own
  :attr:`~.model.Model.sampler` (a surface, physical support parameters), the Poisson
  vectors of :attr:`~.model.Model.geometry` on their variety, the rest random, and the
  relation unknowns moved exactly onto the invariant relations. Everything is rational,
  so a point is exact and reproducible from the seed.
* Floating point (:func:`random_state`, :func:`random_frame`, :func:`random_unit`,
  :func:`random_orthonormal`): numpy generators, for numerical tests and studies.
"""

from __future__ import annotations

import math
import random
from collections.abc import Iterable, Sequence

import numpy as np
import sympy as sp

from ..arith import detlinalg
from .model import Model

__all__ = [
    "sample_point",
    "project_on_relations",
    "invariant_relation_exprs",
    "random_rational",
    "random_state",
    "random_frame",
    "random_unit",
    "random_orthonormal",
]


def random_rational(rng: random.Random, positive: bool) -> sp.Rational:
    """A random rational: in ``(0, 60]`` over ``1..12``, or in ``[-40, 40]`` over ``1..12``.

    Parameters
    ----------
    rng : random.Random
    positive : bool

    Returns
    -------
    sympy.Rational
    """
    if positive:
        return sp.Rational(rng.randint(1, 60), rng.randint(1, 12))
    return sp.Rational(rng.randint(-40, 40), rng.randint(1, 12))


def invariant_relation_exprs(model: Model) -> list[sp.Expr]:
    """The model's invariant relations in state and parameters (aux expanded).

    Parameters
    ----------
    model : Model

    Returns
    -------
    list of sympy.Expr
    """
    return [model.expand_aux(e) for _, e in model.invariant_relations]


def sample_point(
    model: Model,
    rng: random.Random,
    symbols: Iterable[sp.Symbol] = (),
    positive: Iterable[sp.Symbol] = (),
    relations: Sequence[sp.Expr] | None = None,
) -> dict[sp.Symbol, sp.Rational]:
    """An exact rational point of the model's phase space.

    The parameters are drawn from their physical domain (positive inertia ...) and
    mapped forward to the verification parameters of the model's reparametrisation, so
    a witness is always a physical point; a forward map that depends on time
    (``A_i = 1/J_ii(t)`` with BM20's ``I(t)``) is left out (the verifier evaluates it
    once the ``sin``/``cos`` generators have values).

    Parameters
    ----------
    model : Model
    rng : random.Random
    symbols : iterable of sympy.Symbol
        Further symbols to give values (free reals, or positive rationals when in
        ``positive`` or declared positive).
    positive : iterable of sympy.Symbol
    relations : sequence of sympy.Expr, optional
        Relations linear in ``model.relation_unknowns`` the point must satisfy (default:
        the model's own invariant relations, :func:`invariant_relation_exprs`).

    Returns
    -------
    dict of sympy.Symbol to sympy.Rational
        Values of the parameters, the state (with the relation unknowns on the
        relations) and ``symbols``.

    Raises
    ------
    ValueError
        Relations without relation unknowns, not linear in them, or degenerate.
    """
    point: dict[sp.Symbol, sp.Rational] = {}
    for spec in model.parameters:
        for s in spec.symbols:
            point[s] = random_rational(rng, spec.domain == "positive")
    # A model whose phase space is not made of Poisson vectors (the centre of a ball
    # on an ellipsoid ...) supplies its own exact sampler; it may also choose the
    # parameters that shape the variety (a rational point needs them to fit) and the
    # Poisson vectors (a body's frame its contact's normals align with).
    if model.sampler is not None:
        model.sampler(rng, point)
    rep = model.reparametrisation
    pending = set()
    if rep:
        for s, e in rep.forward.items():
            value = e.xreplace(point)
            if value.is_Rational:
                point[s] = value
            else:
                pending.add(s)
    for group in model.geometry:
        if all(x in point for name in group.names for x in model.vectors[name]):
            continue  # drawn by the model's sampler (a frame a contact is aligned with)
        for name, comps in group.sample_rational(rng).items():
            point.update(zip(model.vectors[name], comps, strict=True))
    positive = set(positive)
    unknowns = tuple(model.relation_unknowns)
    for s in sorted(set(symbols) | set(unknowns), key=lambda s: s.name):
        if s in point or s in pending:
            continue
        point[s] = random_rational(rng, s in positive or bool(s.is_positive))
    project_on_relations(
        point, invariant_relation_exprs(model) if relations is None else list(relations), unknowns
    )
    return point


def project_on_relations(
    point: dict[sp.Symbol, sp.Rational], relations: Sequence[sp.Expr], unknowns: Sequence[sp.Symbol]
) -> None:
    """Move the relation unknowns (drawn at random) onto the relations, exactly.

    The relations are linear in the unknowns: ``L u + c = 0``; the point becomes
    ``u - L^T (L L^T)^-1 (L u + c)``, rational like everything else.

    Parameters
    ----------
    point : dict
        Modified in place.
    relations : sequence of sympy.Expr
    unknowns : sequence of sympy.Symbol

    Raises
    ------
    ValueError
        Relations but no unknowns, relations not linear in them with rational
        coefficients at the point, or no independent relation.
    """
    if not relations:
        return
    if not unknowns:
        raise ValueError("invariant relations need Model.relation_unknowns")
    others = {s: v for s, v in point.items() if s not in unknowns}
    fixed = [e.xreplace(others) for e in relations]
    L = sp.Matrix([[sp.diff(e, u) for u in unknowns] for e in fixed])
    c = sp.Matrix([e.xreplace({u: 0 for u in unknowns}) for e in fixed])
    if L.free_symbols or c.free_symbols:
        raise ValueError(f"relations not linear in {unknowns} with rational coefficients")
    # keep a maximal independent set of rows ((M + K) x gamma = 0 has rank 2)
    rows: list[int] = []
    for i in range(L.shape[0]):
        if L.extract([*rows, i], list(range(L.shape[1]))).rank() == len(rows) + 1:
            rows.append(i)
    L, c = L.extract(rows, list(range(L.shape[1]))), c.extract(rows, [0])
    u = sp.Matrix([point[s] for s in unknowns])
    if not rows:
        raise ValueError("degenerate invariant relations at the sample point")
    u = u - L.T * (L * L.T).LUsolve(L * u + c)
    point.update(zip(unknowns, u, strict=True))


# ------------------------------------------------------------------ floating point
def random_unit(rng: np.random.Generator, n: int | None = None) -> np.ndarray:
    """Uniform random unit vector(s).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int, optional
        Number of vectors (columns).

    Returns
    -------
    numpy.ndarray, shape (3,) or (3, n)
    """
    v = rng.normal(size=(3,) if n is None else (3, n))
    return v / np.linalg.norm(v, axis=0)


def random_orthonormal(rng: np.random.Generator) -> np.ndarray:
    """A random orthogonal matrix (QR of uniform columns; its determinant is +-1).

    Parameters
    ----------
    rng : numpy.random.Generator

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        Orthonormal columns.
    """
    while True:  # Householder QR of uniform columns, fixed operation order (arith.detlinalg)
        q, r = detlinalg.qr(2.0 * rng.random((3, 3)) - 1.0)
        if np.min(np.diag(r)) > 1e-3:
            return q


def random_frame(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A random right-handed orthonormal frame ``(alpha, beta, gamma = alpha x beta)``.

    Parameters
    ----------
    rng : numpy.random.Generator

    Returns
    -------
    tuple of numpy.ndarray, each shape (3,)
    """
    q = random_orthonormal(rng)
    if math.fsum(float(v) for v in np.cross(q[:, 0], q[:, 1]) * q[:, 2]) < 0:  # det q
        q[:, 0] *= -1
    alpha, beta = q[:, 0], q[:, 1]
    return alpha, beta, np.cross(alpha, beta)


def random_state(state_groups: Iterable[str], rng: np.random.Generator) -> np.ndarray:
    """A random floating-point point of a ball's phase space, by its state groups.

    ``M`` normal, ``gamma`` a uniform unit vector, or ``alpha, beta, gamma`` a random
    frame when ``alpha`` is a group (then ``x, y`` normal).

    Parameters
    ----------
    state_groups : iterable of str
        Group names in state order (``Model.vectors`` or the generated code's
        ``state_groups``).
    rng : numpy.random.Generator

    Returns
    -------
    numpy.ndarray, shape (n_state,)
    """
    groups = list(state_groups)
    values: dict[str, np.ndarray] = {"M": rng.normal(size=3)}
    if "alpha" in groups:
        values["alpha"], values["beta"], values["gamma"] = random_frame(rng)
        values["x"], values["y"] = rng.normal(size=1), rng.normal(size=1)
    else:
        values["gamma"] = random_unit(rng)
    return np.concatenate([np.atleast_1d(values[name]) for name in groups])
