"""From a concrete spherical support (balls and directions) to the closed model's parameters.

:func:`support_parameters` computes the parameters ``D_iso, D_al, D_be`` of
:func:`~.spherical_support.build_spherical_support` and the eigenframe of the support
tensor ``D_sup = sum_k w_k n_k ⊗ n_k`` from physical ball data, exactly when the
eigenvalues are rational.

References
----------
BKM12-2.1M, BKM12-33, BKM12-2.2 (FORMULAS.md §1.6, §1.7).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import mpmath
import sympy as sp

from .description import apply_effects
from .effects import parse_effects
from .errors import UserInputError
from .support_derivation import SUPPORTED_EFFECTS, ball_weight, spins_are_free, support_description
from .vectors import cross, dot

__all__ = ["SupportParameters", "support_parameters", "unit_exact"]


@dataclass(frozen=True)
class SupportParameters:
    """The closed model's parameters of a concrete support, and its eigenframe.

    Attributes
    ----------
    D_iso, D_al, D_be : sympy.Expr
        Parameters of :func:`build_spherical_support` (exact, or ``sympy.Float``).
    eigenvalues : tuple of sympy.Expr
        ``(D_al0, D_be0, D_ga0)``.
    frame : sympy.Matrix, shape (3, 3)
        Rows: space components of ``alpha, beta, gamma`` (right-handed, orthonormal).
    tensor : sympy.Matrix
        ``D_sup`` in space components.
    exact : bool
        False when the eigen-data are floating point (``dps`` digits).
    directions : tuple of sympy.Matrix
        The unit contact directions in space components.
    """

    D_iso: sp.Expr
    D_al: sp.Expr
    D_be: sp.Expr
    eigenvalues: tuple[sp.Expr, sp.Expr, sp.Expr]
    frame: sp.Matrix
    tensor: sp.Matrix
    exact: bool
    directions: tuple[sp.Matrix, ...]

    def params(self, inertia: Sequence[sp.Expr] | None = None) -> dict[str, object]:
        """``{"D_iso": ..., "D_al": ..., "D_be": ...}`` (+ ``"I"`` when given).

        Parameters
        ----------
        inertia : sequence of sympy.Expr, optional
            Principal moments ``I1, I2, I3`` of the body; None leaves ``"I"`` out.

        Returns
        -------
        dict of str to object
            Parameter values for the closed model: the three support parameters as
            ``sympy.Expr`` and, when given, ``"I"`` as a tuple of three values.
        """
        out: dict[str, object] = {"D_iso": self.D_iso, "D_al": self.D_al, "D_be": self.D_be}
        if inertia is not None:
            out["I"] = tuple(inertia)
        return out

    def eigen_coordinates(self, k: int) -> sp.Matrix:
        """Components of direction ``k`` along ``alpha, beta, gamma``.

        Parameters
        ----------
        k : int
            Index of the contact direction, ``0 .. N-1``.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            ``frame * n_k``: the direction in the eigenframe of the support tensor.
        """
        return self.frame * self.directions[k]


def _positive_number(value, what: str) -> sp.Expr:
    try:
        v = sp.nsimplify(value) if isinstance(value, float) else sp.sympify(value)
    except (sp.SympifyError, TypeError) as exc:
        raise UserInputError(f"{what} must be a number, got {value!r}") from exc
    if not v.is_number or not v.is_real or not v.is_finite:
        raise UserInputError(f"{what} must be a finite real number, got {value!r}")
    if not v.is_positive:
        raise UserInputError(f"{what} must be positive, got {value!r}")
    return v


def unit_exact(d: Sequence[object], k: int) -> sp.Matrix:
    """The exact unit vector along the contact direction ``d`` of ball ``k``.

    Parameters
    ----------
    d : sequence of three numbers
        Floats are read as the rationals they print as (``sympy.nsimplify``).
    k : int
        Index of the ball, ``0 .. N-1`` (for the messages).

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        ``d/|d|`` (exact; a square root when ``|d|^2`` is not a square).

    Raises
    ------
    UserInputError
        Not three real numbers, or the zero vector.
    """
    try:
        vec = sp.Matrix([sp.nsimplify(c) if isinstance(c, float) else sp.sympify(c) for c in d])
    except (sp.SympifyError, TypeError) as exc:
        raise UserInputError(f"direction n_{k + 1} must be three numbers, got {d!r}") from exc
    if vec.shape != (3, 1) or not all(c.is_number and c.is_real for c in vec):
        raise UserInputError(f"direction n_{k + 1} must be three real numbers, got {d!r}")
    norm2 = sp.nsimplify(dot(vec, vec))
    if norm2 == 0:
        raise UserInputError(f"direction n_{k + 1} is the zero vector: give the contact direction")
    return vec if norm2 == 1 else vec / sp.sqrt(norm2)


def _eigen_pairs(S: sp.Matrix, dps: int) -> tuple[bool, list[sp.Expr], list[sp.Matrix]]:
    """Eigenvalues and orthonormal eigenvectors of the support tensor: exact when they are
    rational, else ``dps`` digits (``exact`` says which)."""
    x = sp.Symbol("x")
    charpoly = sp.Poly(S.charpoly(x).as_expr(), x)
    exact = all(S[i, j].is_Rational for i in range(3) for j in range(3)) and all(
        sp.degree(f, x) == 1 for f, _ in sp.factor_list(charpoly.as_expr())[1]
    )
    if exact:
        pairs = []
        for val, _, vecs in S.eigenvects():
            basis = sp.GramSchmidt([sp.Matrix(v) for v in vecs], orthonormal=True)
            pairs += [(val, b) for b in basis]
        return True, [p[0] for p in pairs], [p[1] for p in pairs]
    with mpmath.workdps(dps):
        E, Q = mpmath.eigsy(
            mpmath.matrix(
                [
                    [
                        mpmath.mpf(sp.Rational(S[i, j]).p) / sp.Rational(S[i, j]).q
                        if S[i, j].is_Rational
                        else mpmath.mpf(str(sp.N(S[i, j], dps + 10)))
                        for j in range(3)
                    ]
                    for i in range(3)
                ]
            )
        )
        vals = [sp.Float(str(E[i]), dps) for i in range(3)]
        vecs = [sp.Matrix([sp.Float(str(Q[j, i]), dps) for j in range(3)]) for i in range(3)]
    return False, vals, vecs


def support_parameters(
    lambdas: Sequence[object],
    ratios: Sequence[object],
    directions: Sequence[Sequence[object]],
    effects: Iterable[str] | str | None = (),
    dps: int = 60,
) -> SupportParameters:
    """From physical ball data to the closed model's parameters and eigenframe.

    Parameters
    ----------
    lambdas : sequence of numbers
        Moments of inertia ``lambda_k > 0`` of the balls.
    ratios : sequence of numbers
        ``r_k = R_k/R0 > 0``.
    directions : sequence of 3-vectors
        Space components of the contact directions (normalised here; not zero).
    effects : iterable of str or str, optional
        ``"rubber_balls"`` fixes the balls' spins: the tensor is then
        ``sum lambda_k (1/r_k^2 - 1) n_k ⊗ n_k`` (:func:`~.support_derivation.ball_weight`).
    dps : int, optional
        Digits of the eigen-decomposition when the eigenvalues are not rational.

    Returns
    -------
    SupportParameters
        Exact (sympy) when the support tensor has rational eigenvalues, else floats with
        ``dps`` digits. Convention: ``gamma`` belongs to the simple eigenvalue when one is
        double, else to the smallest one (then ``D_al, D_be > 0``).

    Raises
    ------
    UserInputError
        No balls, lists of different lengths, a non-positive ``lambda_k`` or ``r_k``, a
        zero direction, or an isotropic support tensor (``D_al = D_be = 0``: no closed
        rank-2 model; the body moves as a free rigid body with inertia ``J``).

    Examples
    --------
    >>> p = support_parameters([1], [1], [(0, 0, 1)])
    >>> (p.D_iso, p.D_al, p.D_be)
    (0, -1, -1)
    """
    effects = parse_effects(effects, SUPPORTED_EFFECTS)
    n = len(directions)
    if n == 0:
        raise UserInputError("a spherical support needs at least one ball (N = 0 given)")
    if len(lambdas) != n or len(ratios) != n:
        raise UserInputError(
            f"give one lambda_k and one r_k per ball: {len(lambdas)} lambdas, "
            f"{len(ratios)} ratios, {n} directions"
        )
    lam = [
        _positive_number(v, f"lambda_{k + 1} (moment of inertia of ball {k + 1})")
        for k, v in enumerate(lambdas)
    ]
    rat = [
        _positive_number(v, f"r_{k + 1} (radius ratio R_{k + 1}/R0)") for k, v in enumerate(ratios)
    ]
    dirs = [unit_exact(d, k) for k, d in enumerate(directions)]
    one_ball = support_description(1, effects)
    apply_effects(one_ball, effects, SUPPORTED_EFFECTS)
    (spin_free,) = spins_are_free(one_ball)  # the effects fix the spin (rubber balls) or not
    w = [ball_weight(la, r, spin_free) for la, r in zip(lam, rat, strict=True)]
    S = sum((wk * d * d.T for wk, d in zip(w, dirs, strict=True)), sp.zeros(3, 3)).applyfunc(
        sp.nsimplify
    )
    iso = sum((la / r**2 for la, r in zip(lam, rat, strict=True)), sp.S.Zero)
    exact, vals, vecs = _eigen_pairs(S, dps)
    tol = sp.Float(10) ** (-(dps // 2))

    def same(a, b) -> bool:
        return a == b if exact else abs(a - b) <= tol * (1 + abs(a) + abs(b))

    order = sorted(range(3), key=lambda i: vals[i])
    if same(vals[order[0]], vals[order[2]]):
        raise UserInputError(
            "the support tensor is isotropic (D_sup = d Id): D_al = D_be = 0, the body moves as a "
            "free rigid body with J = I + (sum lambda_k/r_k^2 - d) Id; the closed rank-2 model "
            "does not apply"
        )
    if same(vals[order[0]], vals[order[1]]):
        g = order[2]  # double smallest: gamma takes the simple (largest) one
    else:
        g = order[0]  # distinct or double largest: gamma takes the smallest (simple) one
    a, b = [i for i in order if i != g][:2]
    ea, eb = vecs[a], vecs[b]
    eg = cross(ea, eb)  # right-handed
    frame = sp.Matrix.vstack(ea.T, eb.T, eg.T)
    D_al0, D_be0, D_ga0 = vals[a], vals[b], vals[g]
    return SupportParameters(
        D_iso=sp.nsimplify(iso - D_ga0) if exact else iso - D_ga0,
        D_al=D_al0 - D_ga0,
        D_be=D_be0 - D_ga0,
        eigenvalues=(D_al0, D_be0, D_ga0),
        frame=frame.applyfunc(sp.radsimp) if exact else frame,
        tensor=S,
        exact=exact,
        directions=tuple(dirs),
    )
