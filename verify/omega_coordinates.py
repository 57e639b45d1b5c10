"""Integrals and densities decided in the coordinates ``(omega, g)`` instead of ``(M, g)``.

A model whose angular velocity is an auxiliary, ``omega = II(g)^-1 (M - b(g))`` written
with the adjugate (a body in a spherical support of balls: ``II`` depends on the whole
frame ``g = (alpha, beta, gamma)``), puts powers of ``det II(g)`` into every rate once
the auxiliaries are expanded: the Lie derivative of ``H = (M, omega)/2`` has a numerator
of some 10^5 terms and its Groebner proof takes minutes. The map ``(omega, g) -> (M, g)``
with ``M = m(omega, g) = II(g) omega + b(g)`` (the model's ``momentum_of_omega``) is a
change of coordinates wherever ``det II`` does not vanish, and there the flow is

    ``g' = f_g``, ``omega' = adj(II) (M' - (d m/d g) g') / det II``

(the momentum's rate and ``f_g`` with ``M = m(omega, g)``: polynomial for the balls), so
an integral ``F`` is decided by the rate of ``F(m(omega, g), g, omega)`` in these
coordinates, and a density ``rho`` in ``(M, g)`` by Liouville's equation of the density
``rho det II`` in ``(omega, g)`` (``dM ^ dg = det II domega ^ dg``): with ``II``
independent of ``omega``,

    ``div f = (sum_i (adj(II) d v/d omega_i)_i + tr(adj(II) d II/dt)) / det II + div_g f_g``,

``v = M' - (d m/d g) g'`` and ``d log det II/dt = tr(II^-1 d II/dt)`` (Jacobi). Both
residuals have the one denominator ``det II``; they are decided by
:func:`~chaplygin.verify.identity.decide` with ``omega`` as free variables: a Groebner
normal form modulo the model's constraints (on ``g``) is a proof on the phase space where
``det II != 0``, a non-zero value at an exact point ``(omega, g)`` a refutation at ``M =
m(omega, g)``.

The route is taken only where it is sound (:func:`applies`): an autonomous model without
invariant relations whose ``omega`` are auxiliaries, whose momentum is linear in
``omega`` with a state-dependent ``II`` and a general inverse (no structured inverse),
rational in its symbols, small enough to expand (a right-hand side of at most
:data:`~chaplygin.derive.emit.base.CHAIN_OPS` operations expanded: larger models are
:mod:`.chained`'s), and whose ``omega`` solves ``M = m(omega, g)`` -- proved, not assumed:
``m(omega(M, g), g) - M`` has a zero normal form modulo the constraints.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import sympy as sp

from ..derive.algebra import RationalFunctionBuilder, UnsupportedExpression, ring_normal_form
from ..derive.body_on_sphere import _adjugate_and_det
from ..derive.emit.base import CHAIN_OPS, expanded_size
from ..derive.model import Model

__all__ = ["OmegaCoordinates", "applies", "coordinates", "integral_rate", "measure_residual"]


@dataclass(frozen=True)
class OmegaCoordinates:
    """The model's flow in the coordinates ``(omega, g)``.

    Attributes
    ----------
    omega : tuple of sympy.Symbol
        The angular velocity (the model's auxiliaries, here coordinates).
    g : tuple of sympy.Symbol
        The state but the momentum.
    substitution : dict
        The momentum ``M -> m(omega, g)`` and every other auxiliary in ``(omega, g)``.
    inertia : sympy.Matrix, shape (3, 3)
        ``II = d m/d omega`` (expanded entries, free of ``omega``).
    adjugate : sympy.Matrix, shape (3, 3)
        ``adj(II)`` by cofactors (unexpanded products of the entries).
    det : sympy.Expr
        ``det II`` by cofactors (unexpanded).
    v : sympy.Matrix, shape (3, 1)
        ``M' - (d m/d g) g'`` in ``(omega, g)`` (expanded): ``omega' = adj(II) v / det II``.
    g_dot : sympy.Matrix
        ``g'`` in ``(omega, g)``.
    """

    omega: tuple[sp.Symbol, ...]
    g: tuple[sp.Symbol, ...]
    substitution: dict
    inertia: sp.Matrix
    adjugate: sp.Matrix
    det: sp.Expr
    v: sp.Matrix
    g_dot: sp.Matrix

    def omega_dot(self, i: int) -> sp.Expr:
        """``omega_i'``: ``(adj(II) v)_i / det II``.

        Parameters
        ----------
        i : int
            0, 1 or 2.

        Returns
        -------
        sympy.Expr
        """
        return sum((self.adjugate[i, k] * self.v[k] for k in range(3)), sp.S.Zero) / self.det


def _momentum(model: Model) -> tuple[sp.Symbol, ...]:
    names = [n for n, _ in model.state_groups]
    return tuple(dict(model.state_groups)["M" if "M" in names else names[0]])


def _shape_serves(model: Model) -> bool:
    """The model's shape (see the module docstring), before anything is computed."""
    if model.omega is None or model.momentum_of_omega is None or model.invariant_relations:
        return False
    if model.structured_inverse is not None or not set(model.omega) <= set(model.aux_symbols):
        return False
    if expanded_size(model) > CHAIN_OPS:  # too large to expand (verify/chained.py's models)
        return False
    exprs = [*model.rhs, *(e for _, e in model.aux), *model.momentum_of_omega]
    if any(model.time in sp.sympify(e).free_symbols for e in exprs):
        return False
    m = sp.Matrix([sp.expand(e) for e in model.momentum_of_omega])
    A = m.jacobian(list(model.omega))
    state = set(model.state)
    return not (A.free_symbols & set(model.omega)) and bool(A.free_symbols & state)


def _solves(model: Model) -> bool:
    """``m(omega(M, g), g) = M`` modulo the constraints, ``omega`` as the model defines it
    (a normal form in sympy's sparse polynomial ring); False where not rational."""
    M = _momentum(model)
    residuals = [model.expand_aux(m) - s for m, s in zip(model.momentum_of_omega, M, strict=True)]
    symbols = set(model.state) | set(model.params)
    builder = RationalFunctionBuilder(sorted(symbols, key=lambda s: s.name))
    try:
        numerators = [builder.numerator(e) for e in residuals]
    except UnsupportedExpression:
        return False
    return all(ring_normal_form(n, model.constraints, builder).is_zero for n in numerators)


_COORDINATES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def coordinates(model: Model) -> OmegaCoordinates | None:
    """The model's flow in ``(omega, g)``, or None where the route does not apply.

    Computed once per model (the proof that ``omega`` solves ``M = m(omega, g)``
    included).

    Parameters
    ----------
    model : Model

    Returns
    -------
    OmegaCoordinates or None
    """
    if model in _COORDINATES:
        return _COORDINATES[model]
    out = _coordinates(model) if _shape_serves(model) and _solves(model) else None
    _COORDINATES[model] = out
    return out


def _coordinates(model: Model) -> OmegaCoordinates:
    omega, M = tuple(model.omega), _momentum(model)
    g = tuple(s for s in model.state if s not in set(M))
    m = sp.Matrix([sp.expand(e) for e in model.momentum_of_omega])
    sub: dict = dict(zip(M, m, strict=True))
    for symbol, definition in model.aux:  # every auxiliary but omega, in (omega, g)
        if symbol not in set(omega):
            sub[symbol] = sp.sympify(definition).xreplace(sub)
    rate = dict(zip(model.state, model.rhs, strict=True))
    g_dot = sp.Matrix([sp.expand(sp.sympify(rate[s]).xreplace(sub)) for s in g])
    m_dot = sp.Matrix([sp.sympify(rate[s]).xreplace(sub) for s in M])
    A = m.jacobian(omega).applyfunc(sp.expand)
    v = (m_dot - m.jacobian(g) * g_dot).applyfunc(sp.expand)
    adj, det = _adjugate_and_det(A)
    return OmegaCoordinates(omega, g, sub, A, adj, det, v, g_dot)


def applies(model: Model) -> bool:
    """Whether integrals and densities of the model are decided in ``(omega, g)``.

    Parameters
    ----------
    model : Model

    Returns
    -------
    bool
        See the module docstring (the proof that ``omega`` solves ``M = m(omega, g)``
        is made here, once per model).
    """
    return coordinates(model) is not None


def integral_rate(expr: sp.Expr, model: Model) -> sp.Expr:
    """The rate of a would-be integral along the flow, in ``(omega, g)``.

    Parameters
    ----------
    expr : sympy.Expr
        A function of the state, the parameters and the auxiliaries.
    model : Model
        One the route applies to (:func:`applies`).

    Returns
    -------
    sympy.Expr
        ``sum_i dF/domega_i omega_i' + sum_j dF/dg_j g_j'`` with ``F = expr(m(omega, g),
        g, omega)``: zero on the phase space (``det II != 0``) exactly when ``expr`` is an
        integral.
    """
    c = coordinates(model)
    F = sp.sympify(expr).xreplace(c.substitution)
    terms = [sp.diff(F, w) * c.omega_dot(i) for i, w in enumerate(c.omega) if F.has(w)]
    terms += [sp.diff(F, y) * c.g_dot[j] for j, y in enumerate(c.g) if F.has(y)]
    return sp.Add(*terms)


def measure_residual(density: sp.Expr, model: Model) -> sp.Expr:
    """Liouville's residual of a density given in ``(M, g)``, in ``(omega, g)``.

    Parameters
    ----------
    density : sympy.Expr
        ``rho`` in the model's state, parameters and auxiliaries.
    model : Model
        One the route applies to (:func:`applies`).

    Returns
    -------
    sympy.Expr
        ``div f + (f, grad log(rho det II))`` in ``(omega, g)``: zero on the phase space
        (``det II != 0``) exactly when ``rho`` is an invariant density.
    """
    c = coordinates(model)
    adj, A = c.adjugate, c.inertia
    A_dot = sum((A.diff(y) * c.g_dot[j] for j, y in enumerate(c.g)), sp.zeros(3, 3))
    top = sp.Add(*(adj[i, k] * c.v[k].diff(w) for i, w in enumerate(c.omega) for k in range(3)))
    top += sp.Add(*(adj[i, k] * A_dot[k, i] for i in range(3) for k in range(3)))
    log_rho = sp.expand_log(sp.log(sp.sympify(density).xreplace(c.substitution)), force=True)
    along = [sp.diff(log_rho, w) * c.omega_dot(i) for i, w in enumerate(c.omega)]
    along += [sp.diff(log_rho, y) * c.g_dot[j] + c.g_dot[j].diff(y) for j, y in enumerate(c.g)]
    return top / c.det + sp.Add(*along)
