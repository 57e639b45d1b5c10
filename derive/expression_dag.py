"""Walks of a sympy expression as the graph it is: each distinct subexpression once.

A derived residual shares its subexpressions (the Lie derivative of an energy repeats the
flow's components and omega(M) in every term), and sympy's own walks (``atoms``,
``xreplace``, ``replace``) follow the tree: a shared subexpression is visited once per
occurrence. The walks here remember what they have done per distinct subexpression
(sympy's structural equality), and return exactly what sympy's walks return: each is the
same function of a subexpression, computed once.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

import sympy as sp

__all__ = ["subexpressions", "dag_xreplace", "dag_replace"]


def subexpressions(exprs: Iterable[sp.Basic]) -> set[sp.Basic]:
    """Every distinct subexpression of ``exprs`` (themselves included), each once.

    Parameters
    ----------
    exprs : iterable of sympy.Basic
        The expressions.

    Returns
    -------
    set of sympy.Basic
        The nodes sympy's ``preorder_traversal`` visits, without repetition: ``{a for a in
        that if isinstance(a, T)}`` is ``expr.atoms(T)`` united over ``exprs``.
    """
    seen: set[sp.Basic] = set()
    stack = [e for e in exprs if isinstance(e, sp.Basic)]
    while stack:
        e = stack.pop()
        if e not in seen:
            seen.add(e)
            stack.extend(a for a in e.args if isinstance(a, sp.Basic))
    return seen


def dag_xreplace(expr: sp.Basic, rule: Mapping, memo: dict | None = None) -> sp.Basic:
    """``expr.xreplace(rule)``, each distinct subexpression replaced once.

    Parameters
    ----------
    expr : sympy.Basic
        The expression.
    rule : mapping
        Subexpression to replacement, as for ``xreplace``.
    memo : dict, optional
        Results kept across calls with the same ``rule`` (several expressions that share
        subexpressions).

    Returns
    -------
    sympy.Basic
        The same expression ``xreplace`` gives (``Basic._xreplace``'s rule: a node in
        ``rule`` is replaced whole, otherwise it is rebuilt from its replaced arguments
        when one of them changed).
    """
    if not rule:
        return expr
    memo = {} if memo is None else memo
    return _xreplace(expr, rule, memo)[0]


def _xreplace(e, rule, memo):
    hit = memo.get(e)
    if hit is not None:
        return hit
    if e in rule:
        out = (rule[e], True)
    else:
        args, changed = [], False
        for a in e.args:
            if isinstance(a, sp.Basic):
                value, moved = _xreplace(a, rule, memo)
                args.append(value)
                changed |= moved
            else:
                args.append(a)
        out = (e.func(*args), True) if changed else (e, False)
    memo[e] = out
    return out


def dag_replace(
    expr: sp.Basic,
    query: Callable[[sp.Basic], bool],
    value: Callable[[sp.Basic], sp.Basic],
) -> sp.Basic:
    """``expr.replace(query, value)`` for a callable query and value, each distinct
    subexpression walked once.

    Parameters
    ----------
    expr : sympy.Basic
        The expression.
    query : callable
        Which nodes to replace.
    value : callable
        The replacement of a node the query selects.

    Returns
    -------
    sympy.Basic
        What ``Basic.replace`` gives (simultaneous, bottom up: a node's arguments are
        replaced first, the node rebuilt, then the query asked of the rebuilt node).
    """
    memo: dict = {}

    def walk(rv):
        hit = memo.get(rv)
        if hit is not None:
            return hit
        out = rv
        args = getattr(rv, "args", None)
        if args is not None:
            newargs = tuple(walk(a) for a in args)
            if args != newargs:
                out = rv.func(*newargs)
                # an argument already changed that the rebuilt node equals is not
                # replaced again (Basic.replace's simultaneous rule)
                if any(out == e and e != n for e, n in zip(args, newargs, strict=True)):
                    memo[rv] = out
                    return out
            found = query(out)
            if found or found == {}:
                v = value(out)
                if v is not None and v != out:
                    out = v
        memo[rv] = out
        return out

    return walk(expr)
