"""Bifurcation analysis of the ball and of the spherical support (BKM12 §1.5, §2.7; K01 §3).

Everything here is derived from a model's own momentum ``M = II(vectors) omega``
(``Model.momentum_of_omega``), nothing is typed in from the papers:

* :func:`steady_rotation_residual` -- for a *constant* body-frame angular velocity the
  space-fixed vectors rotate, ``v' = v x omega``, and ``M' - M x omega`` reduces to
  ``(J omega) x omega``: the steady rotations are the rotations about a principal axis
  (:func:`steady_axes`).
* :func:`steady_rotation` -- the explicit family of these periodic solutions: every
  space-fixed vector turned about ``e_i`` by the angle ``-w t``, ``omega = w e_i``, the
  momentum from the model (BKM12-25, BKM12-crit, K01-3.2, BKM12-2.7a/b).
* :func:`bifurcation_curve` -- the values of the integrals on that family with the family's
  parameters eliminated (a lex Groebner basis): the bifurcation curves ``Sigma_i`` of the
  ball (BKM12-24, Sigma_i, K01-3.1, K01-3.2c) and the surfaces of the support (BKM12-2.7b).
* :func:`multiple_root_locus` -- the multiple-root condition of the polynomial
  ``R(x) = Phi(x) ((C - E D) x - E D)`` of the separated quadratures (BKM12-1.5R).

The paper's own formulas are compared with these derived objects in
``verify/claims/bifurcation.py``; numerical stability is in ``numerics/ball/stability.py``.

References
----------
BKM12-1.5R, BKM12-24, BKM12-25, BKM12-Sigma_i, BKM12-crit, BKM12-Sigma45, BKM12-Fig3,
BKM12-2.7a, BKM12-2.7b, BKM12-2.7c, K01-3.1, K01-3.2, K01-3.2c, K01-3.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import seeded_factor
from .model import Model
from .vectors import cross, dot

__all__ = [
    "SteadyRotation",
    "axis_rotation",
    "steady_rotation_residual",
    "steady_axes",
    "steady_rotation",
    "family_integrals",
    "bifurcation_curve",
    "multiple_root_locus",
    "casimir_names",
    "steady_parameters",
]


def axis_rotation(i: int, angle: sp.Expr) -> sp.Matrix:
    """Rotation matrix about the body axis ``e_i`` (``i`` = 0, 1, 2) by ``angle``.

    ``v(t) = axis_rotation(i, -w t) v0`` solves ``v' = v x (w e_i)``.

    Parameters
    ----------
    i : int
        The axis, 0, 1 or 2.
    angle : sympy.Expr
        Rotation angle (counter-clockwise about ``e_i``).

    Returns
    -------
    sympy.Matrix, shape (3, 3)
        The rotation matrix.
    """
    c, s = sp.cos(angle), sp.sin(angle)
    j, k = (i + 1) % 3, (i + 2) % 3
    R = sp.eye(3)
    R[j, j], R[j, k], R[k, j], R[k, k] = c, -s, s, c
    return R


def _vector_names(model: Model) -> list[str]:
    return [n for g in model.geometry for n in g.names]


def steady_rotation_residual(model: Model) -> sp.Matrix:
    """``d/dt M(omega, v(t)) - M x omega`` for a constant body-frame ``omega``.

    ``M = model.momentum_of_omega`` depends on ``omega`` (the model's symbols)
    and the space-fixed vectors ``v``; with ``omega`` constant each vector obeys
    ``v' = v x omega`` (the model's Poisson equations). Expanded: a polynomial vector in
    ``omega`` and the vectors.

    Parameters
    ----------
    model : Model
        A model with ``omega`` and ``momentum_of_omega`` (a rigid-body model).

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        The residual, zero exactly for the steady rotations.

    References
    ----------
    BKM12-25
    """
    w = sp.Matrix(model.omega)
    M = model.momentum_of_omega
    rate = sp.zeros(3, 1)
    for name in _vector_names(model):
        v = model.vectors[name]
        vdot = cross(v, w)
        rate += M.jacobian(v) * vdot
    return (rate - cross(M, w)).applyfunc(sp.expand)


def steady_axes(model: Model) -> list[sp.Matrix]:
    """The directions of constant ``omega`` that are solutions: ``omega = w e_i``.

    Solves :func:`steady_rotation_residual` ``= 0`` for ``omega`` (the vectors drop out
    of it); with distinct principal moments the solutions are the three axes.

    Parameters
    ----------
    model : Model
        A model with ``omega`` and ``momentum_of_omega`` (a rigid-body model).

    Returns
    -------
    list of sympy.Matrix, shape (3, 1)
        The unit vectors ``e_i`` for which ``omega = w e_i`` (other components zero)
        solves the residual.

    References
    ----------
    BKM12-25
    """
    w = list(model.omega)
    res = steady_rotation_residual(model)
    W = sp.Symbol("w", real=True)
    axes = []
    for i in range(3):
        trial = {w[j]: (W if j == i else sp.Dummy("x", real=True)) for j in range(3)}
        others = [trial[w[j]] for j in range(3) if j != i]
        sols = sp.solve(list(res.xreplace(trial)), others, dict=True)
        if any(all(s.get(o, o) == 0 for o in others) for s in sols):
            axes.append(sp.Matrix([1 if j == i else 0 for j in range(3)]))
    return axes


@dataclass
class SteadyRotation:
    """The family of steady rotations about the body axis ``e_i``.

    Attributes
    ----------
    axis : int
        0, 1 or 2 (``e_1, e_2, e_3``).
    w : sympy.Symbol
        The angular speed, ``omega = w e_i`` (either sign).
    omega : sympy.Matrix
    vectors : dict of str to sympy.Matrix
        Each space-fixed vector as a function of time: the model's own symbols (its
        value at ``t = 0``, any point of the phase space) turned about ``e_i`` by ``-w t``.
    M : sympy.Matrix
        The momentum ``II(vectors(t)) omega`` (the model's momentum of omega).
    state : dict of sympy.Symbol to sympy.Expr
        Every state symbol of the model as a function of time.
    """

    axis: int
    w: sp.Symbol
    omega: sp.Matrix
    vectors: dict[str, sp.Matrix]
    M: sp.Matrix
    state: dict[sp.Symbol, sp.Expr]


def steady_rotation(model: Model, axis: int, w: sp.Symbol | None = None) -> SteadyRotation:
    """The explicit periodic solutions ``omega = w e_i`` of a model (BKM12-25, crit, 2.7).

    Parameters
    ----------
    model : Model
        The ball (``gamma``; ``alpha, beta`` too with ``contact_point``) or the spherical
        support (``alpha, beta, gamma``).
    axis : int
        0, 1 or 2.
    w : sympy.Symbol, optional
        The angular speed (default: a real symbol ``w``).

    Returns
    -------
    SteadyRotation
        The family, every state symbol as a function of ``model.time``.

    References
    ----------
    BKM12-25, BKM12-crit, BKM12-2.7a-sol, BKM12-2.7b, K01-3.2
    """
    t = model.time
    w = sp.Symbol("w", real=True) if w is None else w
    omega = sp.Matrix([w if j == axis else 0 for j in range(3)])
    R = axis_rotation(axis, -w * t)
    vectors = {name: R * model.vectors[name] for name in _vector_names(model)}
    sub = {s: e for name, v in vectors.items() for s, e in zip(model.vectors[name], v, strict=True)}
    sub.update(dict(zip(model.omega, omega, strict=True)))
    M = model.momentum_of_omega.xreplace(sub)
    state = dict(sub)
    for s in model.omega:
        state.pop(s)
    state.update(dict(zip(model.vectors["M"], M, strict=True)))
    return SteadyRotation(axis, w, omega, vectors, M, state)


def casimir_names(model: Model) -> list[str]:
    """Names of the linear integrals ``(M, v)`` of the model's space-fixed vectors.

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    list of str
        ``"(M,<name>)"`` for each vector of the model's Poisson groups, in order.
    """
    return [f"(M,{name})" for name in _vector_names(model)]


def family_integrals(model: Model, fam: SteadyRotation) -> dict[str, sp.Expr]:
    """``E = (M, omega)``, ``C = (M, M)`` and ``(M, v)`` for each vector, on a family.

    They are constant along the family (proved in the claims); returned at ``t = 0``.

    Parameters
    ----------
    model : Model
        The model the family belongs to.
    fam : SteadyRotation
        A family of :func:`steady_rotation`.

    Returns
    -------
    dict of str to sympy.Expr
        ``"E"``, ``"C"`` and ``"(M,<name>)"`` for each vector, in ``w``, the vectors'
        components at ``t = 0`` and the parameters.
    """
    at0 = {model.time: 0}
    M = fam.M.xreplace(at0)
    out = {"E": dot(M, fam.omega), "C": dot(M, M)}
    for name in _vector_names(model):
        out[f"(M,{name})"] = dot(M, fam.vectors[name].xreplace(at0))
    return out


def bifurcation_curve(model: Model, axis: int) -> sp.Expr:
    """The energy on the steady rotations about ``e_i`` as a function of the integrals.

    The integrals of :func:`family_integrals` depend on the family's speed ``w`` and on
    the ``i``-th components of the space-fixed vectors at ``t = 0`` (a unit vector: the
    ``i``-th row of an orthogonal matrix, or ``gamma_i`` alone for the ball). Those
    parameters are eliminated with a lex Groebner basis; the element of the elimination
    ideal that is linear in ``E`` is solved for it.

    Parameters
    ----------
    model : Model
        The ball (possibly with ``contact_point``) or the spherical support.
    axis : int
        0, 1 or 2.

    Returns
    -------
    sympy.Expr
        ``E`` in the symbols ``C`` and ``M_<name>`` (``M_gamma`` for the ball,
        ``M_alpha, M_beta, M_gamma`` for the support) and the model's parameters.

    Raises
    ------
    ValueError
        When the elimination ideal has no element linear in ``E``.

    References
    ----------
    BKM12-24, BKM12-Sigma_i, BKM12-2.7b, K01-3.1, K01-3.2c
    """
    fam = steady_rotation(model, axis)
    vals = family_integrals(model, fam)
    names = _vector_names(model)
    comps = [s for name in names for s in model.vectors[name]]
    # the other components are eliminated with the phase-space constraints
    ordered = sorted(comps, key=lambda s: (model.vectors[s.name[:-1]][axis] == s, s.name))
    E = sp.Symbol("E", real=True)
    C = sp.Symbol("C", real=True)
    targets = {"E": E, "C": C}
    targets.update({f"(M,{n})": sp.Symbol(f"M_{n}", real=True) for n in names})
    polys = [vals[k] - targets[k] for k in vals] + list(model.constraints)
    elim = [fam.w, *ordered]
    keep = list(targets.values())
    G = sp.groebner(polys, *elim, *keep, order="lex")
    for g in G.exprs:
        if g.free_symbols & set(elim):
            continue
        if sp.degree(g, E) == 1:
            return seeded_factor(sp.solve(g, E)[0])
    raise ValueError("no element of the elimination ideal is linear in E")


def steady_parameters(model: Model, axis: int) -> list[dict[str, sp.Expr]]:
    """Speed ``w`` and ``gamma_i`` of the ball's steady rotations on a level ``(C, M_gamma)``.

    Solves ``family_integrals`` (``C = (M, M)``, ``M_gamma = (M, gamma)``; they depend on
    ``gamma(0)`` only through ``gamma_i``) for ``w`` and ``gamma_i``: two solutions, one
    for each sense of rotation (BKM12-crit: two critical solutions per ``M_gamma``).

    Parameters
    ----------
    model : Model
        A model with a ``gamma`` vector (the ball).
    axis : int
        0, 1 or 2.

    Returns
    -------
    list of dict
        ``{"w": expr, "g": expr}`` in the symbols ``C``, ``M_gamma`` and the parameters.

    References
    ----------
    BKM12-crit
    """
    fam = steady_rotation(model, axis)
    gamma = model.vectors["gamma"]
    g = sp.Symbol("g", real=True)
    j = (axis + 1) % 3
    at = {gamma[axis]: g, gamma[j]: sp.sqrt(1 - g**2), gamma[(axis + 2) % 3]: 0}
    vals = {k: sp.simplify(v.xreplace(at)) for k, v in family_integrals(model, fam).items()}
    C, Mg = sp.Symbol("C", real=True), sp.Symbol("M_gamma", real=True)
    sols = sp.solve([vals["C"] - C, vals["(M,gamma)"] - Mg], [fam.w, g], dict=True)
    return [{"w": sp.simplify(s_[fam.w]), "g": sp.simplify(s_[g])} for s_ in sols]


def multiple_root_locus(
    a: tuple[sp.Expr, sp.Expr, sp.Expr], D: sp.Expr, E: sp.Symbol, C: sp.Symbol
) -> list[sp.Expr]:
    """Factors of the multiple-root condition of ``R(x) = Phi(x) L(x)`` that involve ``E, C``.

    ``Phi(x) = (1 + x)(a1 - x)(a2 - x)(a3 - x)`` (BKM12-1.2b, ``a_i = D/I_i``),
    ``L(x) = (C - E D) x - E D``. Since ``disc(Phi L) = disc(Phi) disc(L) res(Phi, L)^2``
    and ``disc(Phi)`` depends on the parameters alone, ``R`` has a multiple root for
    distinct ``a_i`` exactly where ``res(Phi, L) = 0`` (or ``L`` degenerates). The
    factors of the resultant that involve ``E`` or ``C`` are returned, each once and
    monic in ``E`` where it contains ``E``.

    Parameters
    ----------
    a : tuple of three sympy.Expr
        ``a_i = D/I_i``.
    D : sympy.Expr
        ``m b^2``.
    E : sympy.Symbol
        Twice the energy.
    C : sympy.Symbol
        The integral ``(M, M)``.

    Returns
    -------
    list of sympy.Expr
        The factors, each in factored form.

    References
    ----------
    BKM12-1.5R, BKM12-11.
    """
    x = sp.Symbol("x")
    Phi = (1 + x) * (a[0] - x) * (a[1] - x) * (a[2] - x)
    L = (C - E * D) * x - E * D
    res = sp.resultant(sp.expand(Phi), L, x)
    _, factors = sp.factor_list(sp.numer(sp.together(res)))
    out = []
    for f, _k in factors:
        if not f.free_symbols & {E, C}:
            continue
        if f.has(E):
            f = sp.expand(f / sp.Poly(f, E).LC())
        out.append(seeded_factor(f))
    return out
