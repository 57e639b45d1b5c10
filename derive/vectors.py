"""Three-vectors as sympy column matrices, in the notation of BKM12 (body frame)."""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

__all__ = ["vector", "cross", "dot", "outer", "column"]


def vector(name: str, **assumptions: bool) -> sp.Matrix:
    """Column 3-vector of symbols ``name1, name2, name3``.

    Parameters
    ----------
    name : str
        Base name; components are ``f"{name}1"`` ... ``f"{name}3"``.
    **assumptions
        Sympy assumptions for every component (``real=True`` ...).

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        The symbols ``name1, name2, name3``.
    """
    return sp.Matrix(sp.symbols(f"{name}1:4", **assumptions))


def column(items: Iterable[sp.Expr]) -> sp.Matrix:
    """Column matrix from an iterable of expressions.

    Parameters
    ----------
    items : iterable of sympy.Expr
        The entries, in order.

    Returns
    -------
    sympy.Matrix, shape (n, 1)
        The items as a column.
    """
    return sp.Matrix(list(items))


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """Cross product ``a x b`` of two column 3-vectors.

    Parameters
    ----------
    a, b : sympy.Matrix, shape (3, 1)
        The factors (any indexable of three expressions works).

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        ``a x b`` (components not simplified).
    """
    return sp.Matrix(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def dot(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    """Scalar product ``(a, b)``.

    Parameters
    ----------
    a, b : sympy.Matrix, shape (n, 1)
        The factors (``b`` at least as long as ``a``).

    Returns
    -------
    sympy.Expr
        ``sum_i a_i b_i`` (not simplified).
    """
    return sum((a[i] * b[i] for i in range(a.shape[0])), sp.S.Zero)


def outer(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """Outer product ``a ⊗ b`` (``(a ⊗ b) x = a (b, x)``).

    Parameters
    ----------
    a : sympy.Matrix, shape (n, 1)
        Left factor.
    b : sympy.Matrix, shape (m, 1)
        Right factor.

    Returns
    -------
    sympy.Matrix, shape (n, m)
        ``a b^T``.
    """
    return a * b.T
