"""The papers' objects written from a model's symbols (BKM12 notation, FORMULAS.md §0.1).

These are typed from the papers on purpose: they are what the claims compare the
derived model against.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.vectors import cross, dot

__all__ = ["BallNotation", "ball_notation"]


@dataclass
class BallNotation:
    M: sp.Matrix
    gamma: sp.Matrix
    omega: sp.Matrix  # the model's auxiliary omega symbols
    I: sp.Matrix  # the papers' name
    D: sp.Symbol
    A: sp.Matrix  # (I + D Id)^-1
    J: sp.Matrix  # I + D Id
    Z: sp.Expr  # (A M, gamma) / (D^-1 - (gamma, A gamma))
    K: sp.Matrix | None
    b: sp.Symbol | None
    alpha: sp.Matrix | None
    beta: sp.Matrix | None

    def momentum(self, omega: sp.Matrix) -> sp.Matrix:
        """BKM12-1: ``I omega + D gamma x (omega x gamma)``.

        Parameters
        ----------
        omega : sympy.Matrix, shape (3, 1)
            Angular velocity in the body frame.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            Angular momentum about the contact point.

        References
        ----------
        BKM12-1
        """
        return sp.diag(*self.I) * omega + self.D * cross(self.gamma, cross(omega, self.gamma))

    def omega_formula(self) -> sp.Matrix:
        """BKM12-3: ``A (M + Z gamma)``.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            ``omega`` in ``M``, ``gamma`` and the parameters.

        References
        ----------
        BKM12-3
        """
        return self.A * (self.M + self.Z * self.gamma)

    def rho(self, exponent: sp.Expr = sp.S.Half * -1) -> sp.Expr:
        """BKM12-4: ``(D^-1 - (gamma, A gamma))^exponent``.

        Parameters
        ----------
        exponent : sympy.Expr, optional
            ``-1/2`` gives the density of BKM12-4; other exponents give its powers.

        Returns
        -------
        sympy.Expr
            The density (or its power) in ``gamma`` and the parameters.

        References
        ----------
        BKM12-4
        """
        return (1 / self.D - dot(self.gamma, self.A * self.gamma)) ** exponent


def ball_notation(model: Model) -> BallNotation:
    """BKM12's objects written from the symbols of a ball model.

    Parameters
    ----------
    model : Model
        A ball model (groups ``M``, ``gamma``; parameters ``I``, ``D``; optionally
        ``K``, ``b`` and the vectors ``alpha``, ``beta``).

    Returns
    -------
    BallNotation
        ``I``, ``D``, ``J = I + D Id``, ``A = J^-1``, ``Z`` of FORMULAS.md §0.1; the
        optional fields are None when the model lacks them.

    References
    ----------
    BKM12-3
    """
    I = model.param_group("I")
    D = model.param_group("D")[0]
    M, gamma = model.group("M"), model.group("gamma")
    J = sp.diag(*[I[i] + D for i in range(3)])
    A = sp.diag(*[1 / (I[i] + D) for i in range(3)])
    Z = dot(A * M, gamma) / (1 / D - dot(gamma, A * gamma))
    names = {p.name for p in model.parameters}
    return BallNotation(
        M=M,
        gamma=gamma,
        omega=sp.Matrix(model.omega),
        I=I,
        D=D,
        A=A,
        J=J,
        Z=Z,
        K=model.param_group("K") if "K" in names else None,
        b=model.param_group("b")[0] if "b" in names else None,
        alpha=model.group("alpha") if "alpha" in model.vectors else None,
        beta=model.group("beta") if "beta" in model.vectors else None,
    )
