"""Three-vectors as sympy column matrices, in the notation of BKM12 (body frame)."""

from __future__ import annotations

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
    """
    return sp.Matrix(sp.symbols(f"{name}1:4", **assumptions))


def column(items) -> sp.Matrix:
    """Column matrix from an iterable of expressions."""
    return sp.Matrix(list(items))


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """Cross product ``a x b`` of two column 3-vectors."""
    return sp.Matrix(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def dot(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    """Scalar product ``(a, b)``."""
    return sum((a[i] * b[i] for i in range(a.shape[0])), sp.S.Zero)


def outer(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """Outer product ``a ⊗ b`` (``(a ⊗ b) x = a (b, x)``)."""
    return a * b.T
