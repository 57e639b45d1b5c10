"""The 3-2-1 Euler angles' kinematics shared by the Kane cross-checks
(:mod:`.kane_rolling`, :mod:`.kane_support`)."""

from __future__ import annotations

from functools import lru_cache

import sympy as sp
import sympy.physics.mechanics as me

__all__ = ["euler_rates"]


@lru_cache(maxsize=2)
def euler_rates(components: str = "space") -> dict[sp.Expr, sp.Expr]:
    """The rates of 3-2-1 (``zyx``) Euler angles ``q1, q2, q3`` of ``B`` in ``N`` in terms
    of the angular velocity's components ``u1, u2, u3`` on ``N.x, N.y, N.z`` (``"space"``)
    or on ``B.x, B.y, B.z`` (``"body"``).

    The kinematic equations are linear in the rates: solved by the adjugate over the
    determinant ``-cos q2`` (only ``1/cos q2``, the 3-2-1 singularity, is left; the
    implicit form LU-solved by KanesMethod divides by spurious factors). The same for
    every body, so formed once per process (``sympy.solve`` and ``simplify`` took 25 s).

    Parameters
    ----------
    components : {"space", "body"}
        The frame whose axes the speeds ``u1, u2, u3`` are components on.

    Returns
    -------
    dict
        ``{q_i'(t): expression in q1, q2, q3, u1, u2, u3}``.
    """
    q = me.dynamicsymbols("q1 q2 q3")
    u = me.dynamicsymbols("u1 u2 u3")
    t = me.dynamicsymbols._t
    N, B = me.ReferenceFrame("N"), me.ReferenceFrame("B")
    B.orient_body_fixed(N, tuple(q), "zyx")
    w = B.ang_vel_in(N)
    rates = [s.diff(t) for s in q]
    axes = {"space": (N.x, N.y, N.z), "body": (B.x, B.y, B.z)}[components]
    implicit = [w.dot(e) - ui for e, ui in zip(axes, u, strict=True)]
    A, b = sp.linear_eq_to_matrix(implicit, rates)
    A = A.applyfunc(sp.trigsimp)
    det = sp.trigsimp(A.det())
    adjugate = A.adjugate().applyfunc(sp.trigsimp)
    return {r: sp.trigsimp(sp.expand(e / det)) for r, e in zip(rates, adjugate * b, strict=True)}
