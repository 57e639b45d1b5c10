"""Independent Taylor coefficients of the exact solution, for tests of the recurrences.

The model's aux definitions and right-hand side as derived (no CSE, not the Taylor
program) are evaluated on truncated power series by a separate implementation: products by
the Cauchy formula, quotients by long division, rational powers by the binomial series,
``sin``/``cos``/``exp`` by their addition theorems and Maclaurin series; Picard iteration
``y <- y0 + int_0^s f(t0 + s, y(s)) ds`` fixes one more coefficient per pass. The
coefficients are computed with mpmath at the caller's working precision from exact
rational data. :func:`lie_coefficients` gives a few coefficients exactly (sympy rationals)
by repeated differentiation along the flow ``d/dt F = dF/dt + J F``.
"""

from __future__ import annotations

import mpmath
import sympy as sp

__all__ = ["series_coefficients", "lie_coefficients"]


def _mul(a, b, K):
    return [mpmath.fsum(a[j] * b[k - j] for j in range(k + 1)) for k in range(K + 1)]


def _inv(b, K):
    c = [1 / b[0]]
    for k in range(1, K + 1):
        c.append(-mpmath.fsum(b[j] * c[k - j] for j in range(1, k + 1)) / b[0])
    return c


def _compose(a, coeffs, K):
    """``sum_m coeffs[m] u^m`` with ``u = a - a0`` (no constant term)."""
    u = [mpmath.mpf(0)] + list(a[1:])
    out = [mpmath.mpf(0)] * (K + 1)
    power = [mpmath.mpf(1)] + [mpmath.mpf(0)] * K
    for m in range(K + 1):
        out = [o + coeffs[m] * p for o, p in zip(out, power, strict=True)]
        power = _mul(power, u, K)
    return out


def _series(expr, env, K, memo):
    if expr in memo:
        return memo[expr]
    zero = [mpmath.mpf(0)] * K
    if expr.is_Number:
        r = [mpmath.mpf(sp.Rational(expr).p) / sp.Rational(expr).q] + zero
    elif expr.is_Symbol:
        r = env[expr]
    elif expr.is_Add:
        parts = [_series(a, env, K, memo) for a in expr.args]
        r = [mpmath.fsum(p[k] for p in parts) for k in range(K + 1)]
    elif expr.is_Mul:
        r = None
        for a in expr.args:
            s = _series(a, env, K, memo)
            r = s if r is None else _mul(r, s, K)
    elif expr.is_Pow:
        b = _series(expr.base, env, K, memo)
        e = sp.Rational(expr.exp)
        if e.is_Integer and e >= 0:
            r = [mpmath.mpf(1)] + zero
            for _ in range(int(e)):
                r = _mul(r, b, K)
        elif e.is_Integer:
            inv = _inv(b, K)
            r = [mpmath.mpf(1)] + zero
            for _ in range(-int(e)):
                r = _mul(r, inv, K)
        else:  # b0^e (1 + u/b0)^e by the binomial series
            ee = mpmath.mpf(e.p) / e.q
            scaled = [v / b[0] for v in b]
            coeffs = [mpmath.binomial(ee, m) for m in range(K + 1)]
            r = [b[0] ** ee * v for v in _compose(scaled, coeffs, K)]
    elif isinstance(expr, (sp.sin, sp.cos)):
        a = _series(expr.args[0], env, K, memo)
        fact = [mpmath.factorial(m) for m in range(K + 1)]
        cu = _compose(a, [(-1) ** (m // 2) / fact[m] if m % 2 == 0 else 0 for m in range(K + 1)], K)
        su = _compose(a, [(-1) ** (m // 2) / fact[m] if m % 2 else 0 for m in range(K + 1)], K)
        s0, c0 = mpmath.sin(a[0]), mpmath.cos(a[0])
        if isinstance(expr, sp.sin):
            r = [s0 * x + c0 * y for x, y in zip(cu, su, strict=True)]
        else:
            r = [c0 * x - s0 * y for x, y in zip(cu, su, strict=True)]
    elif isinstance(expr, sp.exp):
        a = _series(expr.args[0], env, K, memo)
        r = [
            mpmath.exp(a[0]) * v
            for v in _compose(a, [1 / mpmath.factorial(m) for m in range(K + 1)], K)
        ]
    else:
        raise NotImplementedError(type(expr).__name__)
    memo[expr] = r
    return r


def _mp(q):
    q = sp.Rational(q)
    return mpmath.mpf(q.p) / q.q


def series_coefficients(model, t0, y0, params, K):
    """Coefficients ``y_i^(k)(t0)/k!``, ``k <= K``, as lists of mpf (``n x (K + 1)``).

    ``t0``, ``y0``, ``params`` are exact rationals (sympy); evaluated at the working precision.
    """
    f = [sp.sympify(e) for e in model.rhs]
    zero = [mpmath.mpf(0)] * K
    env = {s: [_mp(v)] + zero for s, v in zip(model.params, params, strict=True)}
    env[model.time] = [_mp(t0), mpmath.mpf(1)] + [mpmath.mpf(0)] * (K - 1)
    Y = [[_mp(v)] + zero for v in y0]
    for _ in range(K):
        env.update(dict(zip(model.state, Y, strict=True)))
        memo: dict = {}
        for sym, definition in model.aux:  # in order, each in terms of the earlier ones
            env[sym] = _series(sp.sympify(definition), env, K, memo)
        F = [_series(e, env, K, memo) for e in f]
        Y = [
            [_mp(v)] + [Fi[k - 1] / k for k in range(1, K + 1)] for v, Fi in zip(y0, F, strict=True)
        ]
    return Y


def lie_coefficients(model, t0, y0, params, K):
    """Exact rational coefficients up to order ``K`` by differentiation along the flow."""
    subs = dict(zip(model.params, params, strict=True))
    f = [e.xreplace(subs) for e in model.rhs_expanded]
    point = dict(zip(model.state, y0, strict=True))
    point[model.time] = t0
    g = list(model.state)
    out = [[sp.Rational(v) for v in y0]]
    for k in range(1, K + 1):
        g = [
            sp.diff(e, model.time)
            + sum(sp.diff(e, s) * fi for s, fi in zip(model.state, f, strict=True))
            for e in g
        ]
        out.append([sp.nsimplify(e.xreplace(point)) / sp.factorial(k) for e in g])
    return [[out[k][i] for k in range(K + 1)] for i in range(len(y0))]
