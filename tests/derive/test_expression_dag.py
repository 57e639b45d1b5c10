"""The graph walks of derive/expression_dag.py against sympy's own tree walks."""

from __future__ import annotations

import random

import sympy as sp
from chaplygin.derive.expression_dag import dag_replace, dag_xreplace, subexpressions

x = sp.symbols("x0:4", real=True)
t = sp.Symbol("t", real=True)
f = sp.Function("f")


def _expressions(seed: int, count: int) -> list[sp.Expr]:
    """Random expressions that share subexpressions (a pool reused at every level), with
    square roots, sin/cos of t, an undefined function of t and its derivative."""
    rng = random.Random(seed)
    pool = [*x, sp.sin(t), sp.cos(t), f(t), sp.Derivative(f(t), t), sp.Rational(3, 7)]
    for _ in range(40):
        a, b = rng.choice(pool), rng.choice(pool)
        kind = rng.randrange(5)
        if kind == 0:
            pool.append(a + b)
        elif kind == 1:
            pool.append(a * b)
        elif kind == 2:
            pool.append(sp.sqrt(a**2 + b**2 + 1))
        elif kind == 3:
            pool.append(a / (b**2 + 2))
        else:
            pool.append((a - b) ** rng.choice([2, 3, sp.Rational(3, 2)]))
    return [rng.choice(pool[-15:]) for _ in range(count)]


def test_the_graph_walks_are_sympys_tree_walks():
    """subexpressions' atoms, dag_xreplace and dag_replace give what atoms, xreplace and
    replace give, on expressions with shared parts; a memo shared by two calls too."""
    exprs = _expressions(3, 6)
    nodes = subexpressions(exprs)
    for kind in (sp.Pow, sp.Function, sp.Derivative, sp.Symbol):
        expected = set().union(*(e.atoms(kind) for e in exprs))
        assert {a for a in nodes if isinstance(a, kind)} == expected
    radicands = sorted({p.base for p in nodes if isinstance(p, sp.Pow) and p.exp == sp.S.Half},
                       key=sp.default_sort_key)  # fmt: skip
    assert radicands
    r = sp.Dummy("r")
    rule = {x[0]: sp.Rational(2, 3), sp.sin(t): x[1], radicands[0]: r}
    memo: dict = {}
    for e in exprs:
        assert dag_xreplace(e, rule, memo) == e.xreplace(rule)
        assert dag_xreplace(e, {}) is e

        def query(y, S=radicands[0]):
            return y.is_Pow and y.base == S and y.exp.is_Rational and y.exp.q == 2

        def value(y):
            return r ** int(2 * y.exp)

        assert dag_replace(e, query, value) == e.replace(query, value)
    point = {s: sp.Rational(i + 2, 5) for i, s in enumerate(x)}
    point.update({sp.sin(t): sp.Rational(3, 5), sp.cos(t): sp.Rational(4, 5), f(t): 2})
    point[sp.Derivative(f(t), t)] = sp.Rational(-1, 3)
    assert [dag_xreplace(e, point) for e in exprs] == [e.xreplace(point) for e in exprs]
