"""A homogeneous ball rolling on a fixed support surface ``F(p) = 0`` (fixed frame).

M03 §1's ball (:mod:`.ball_on_surface`) is written with its centre ``x`` on the surface
the centre describes, ``f(x) = 0``: for a support ``F`` that is the parallel surface at
distance ``R``, which is not algebraic in general. Here the state is the contact point
``p`` on the support itself:

* the support's unit normal ``nu(p) = grad F/|grad F|`` (``F < 0`` inside the support),
  and the normal from the contact to the ball's centre ``n = s nu`` (``s = 1``: the ball
  on the side ``nu`` points to, outside; ``s = -1``: inside);
* the centre ``x = p + R n(p)``, so ``x' = (Id + s R dnu/dp) p'``; the fixed-frame
  derivation (:func:`~.ball_on_surface.derive_fixed_frame`, the abstract normal ``nu``
  and its rate) gives ``x' = R omega x n`` and ``omega'``; ``p'`` solves ``(Id + s R
  dnu/dp) p' = R omega x n`` (adjugate over determinant), and ``n' = s (dnu/dp) p'``;
* gravity ``g`` along ``-e3``: the force ``(0, 0, -m g)`` at the centre; the energy ``T +
  m g (p3 + s R nu3(p))``.

The support's level ``F(p)`` is an integral (``(nu, p') = 0``: ``nu^T dnu/dp = 0``, so
``(nu, x') = (nu, p')``, and ``x'`` is tangent).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .ball_on_surface import FixedFrameDerivation, derive_fixed_frame
from .body_on_sphere import _adjugate_and_det
from .description import MechanicalDescription, Reduced
from .model import ModelDetails
from .vectors import dot

__all__ = ["SupportSurfaceReduction", "SupportSurfaceEquations", "SupportNormal", "support_normal"]


@dataclass(frozen=True)
class SupportNormal:
    """The support's geometry as a ball's reduction uses it (shared by the homogeneous and
    the general ball).

    Attributes
    ----------
    nu : sympy.Matrix
        The auxiliary symbols ``nu1 .. nu3`` of the unit normal.
    normal : sympy.Matrix
        ``nu(p) = grad F/|grad F|``.
    curvature : sympy.Matrix
        The auxiliary symbols ``Dnu11 ..`` of ``dnu/dp``.
    pdot : sympy.Matrix
        The auxiliary symbols ``pdot1 .. pdot3`` of the contact's rate.
    adjugate, determinant :
        Of ``Id + s R dnu/dp`` (in the symbols): ``p' = adj (x')/det`` for the centre's
        velocity ``x'``.
    level : sympy.Expr
        ``F`` without its constant term (an integral: the contact stays on its level set).
    """

    nu: sp.Matrix
    normal: sp.Matrix
    curvature: sp.Matrix
    pdot: sp.Matrix
    adjugate: sp.Matrix
    determinant: sp.Expr
    level: sp.Expr

    def aux(self, p: sp.Matrix, p_rate: sp.Matrix) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """The normal, its Jacobian and the contact's rate, as auxiliaries in that order.

        Parameters
        ----------
        p : sympy.Matrix
            The contact point's state symbols.
        p_rate : sympy.Matrix
            ``p'`` in the state and the auxiliary symbols.

        Returns
        -------
        tuple of (sympy.Symbol, sympy.Expr)
        """
        return (
            tuple(zip(self.nu, self.normal, strict=True))
            + tuple(zip(self.curvature, self.normal.jacobian(p), strict=True))
            + tuple(zip(self.pdot, p_rate, strict=True))
        )


def support_normal(F: sp.Expr, p: sp.Matrix, side: int, radius: sp.Expr) -> SupportNormal:
    """The unit normal of ``F(p) = 0``, its curvature and the contact's rate's solver.

    Parameters
    ----------
    F : sympy.Expr
        The support in the contact point's symbols.
    p : sympy.Matrix
        Those symbols.
    side : int
        1 outside, -1 inside.
    radius : sympy.Expr
        The ball's radius ``R``.

    Returns
    -------
    SupportNormal
    """
    grad = sp.Matrix([sp.diff(F, c) for c in p])
    norm = sp.sqrt(sp.factor_terms(sp.expand(dot(grad, grad))))
    J = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Dnu{i + 1}{j + 1}", real=True))
    adj, det = _adjugate_and_det(sp.eye(3) + side * radius * J)
    return SupportNormal(
        nu=sp.Matrix(sp.symbols("nu1:4", real=True)),
        normal=(grad / norm).applyfunc(sp.factor_terms),
        curvature=J,
        pdot=sp.Matrix(sp.symbols("pdot1:4", real=True)),
        adjugate=adj,
        determinant=det,
        level=sp.expand(F - F.xreplace(dict.fromkeys(p, 0))),
    )


@dataclass
class SupportSurfaceEquations(ModelDetails):
    """The derivation on a concrete support ``F(p) = 0`` (the ``details`` of the model).

    Attributes
    ----------
    support : sympy.Expr
        ``F(p)``.
    normal : sympy.Matrix
        ``nu(p) = grad F/|grad F|``.
    side : int
        ``s``: 1 outside, -1 inside.
    p_rate, omega_rate : sympy.Matrix
        In the state and the auxiliary symbols.
    energy : sympy.Expr
    derivation : FixedFrameDerivation
    """

    support: sp.Expr
    normal: sp.Matrix
    side: int
    p_rate: sp.Matrix
    omega_rate: sp.Matrix
    energy: sp.Expr
    derivation: FixedFrameDerivation


@dataclass(frozen=True)
class SupportSurfaceReduction:
    """A homogeneous ball on the fixed support ``F(p) = 0``, state ``omega`` and ``p``.

    Parameters
    ----------
    support : sympy.Expr
        ``F`` in the contact point's state symbols.
    mass, effective_mass, radius : sympy.Expr
        ``m``, ``m_e`` (``I = m_e R^2``) and ``R``.
    side : int
        1: the ball outside the support (on the side of ``grad F``); -1: inside.
    gravity : sympy.Expr
        ``g`` of a field along ``-e3`` (0: none).
    angular_velocity, contact : str
        The state groups ``omega`` and ``p``.
    """

    support: sp.Expr
    mass: sp.Expr
    effective_mass: sp.Expr
    radius: sp.Expr
    side: int = 1
    gravity: sp.Expr = sp.S.Zero
    angular_velocity: str = "omega"
    contact: str = "p"

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """``omega'`` and ``p'``, the energy ``H`` and the support's level ``F``.

        Parameters
        ----------
        desc : MechanicalDescription
            With the state groups :attr:`angular_velocity` and :attr:`contact`.

        Returns
        -------
        Reduced
            ``details`` a :class:`SupportSurfaceEquations`; no density (``chaplygin
            discover`` searches for one).

        Raises
        ------
        DerivationError
            For declared data this derivation does not take, or from
            :func:`~.ball_on_surface.derive_fixed_frame`.
        """
        desc.refuse(
            "support-surface",
            ("inertia", "kinetic_energy", "potential", "constraints", "kinematics")
            + ("momentum_in_state", "bodies", "positions"),
        )
        omega = desc.state_group(self.angular_velocity)
        p = desc.state_group(self.contact)
        m, R, s = self.mass, self.radius, self.side
        der = derive_fixed_frame(m, self.effective_mass, R, omega)
        geometry = support_normal(self.support, p, s, R)
        nu, nu_of_p, J, pdot = geometry.nu, geometry.normal, geometry.curvature, geometry.pdot
        n = s * nu  # from the contact to the centre
        x_rate = der.v.xreplace(der.velocity_map).xreplace(dict(zip(der.nu, n, strict=True)))
        p_rate = (geometry.adjugate * x_rate / geometry.determinant).applyfunc(sp.expand)
        force = sp.Matrix([0, 0, -m * self.gravity])
        to_support = {
            **dict(zip(der.nu, n, strict=True)),
            **dict(zip(der.nudot, s * J * pdot, strict=True)),
            **dict(zip(der.force, force, strict=True)),
        }
        omega_rate = der.omega_rate.xreplace(to_support)
        height = p[2] + s * R * nu_of_p[2]
        energy = der.energy.xreplace(to_support) + m * self.gravity * height
        details = SupportSurfaceEquations(
            support=self.support, normal=nu_of_p, side=s, p_rate=p_rate,
            omega_rate=omega_rate, energy=energy, derivation=der,
        )  # fmt: skip
        return Reduced(
            rates={self.angular_velocity: list(omega_rate), self.contact: list(pdot)},
            aux=geometry.aux(p, p_rate),
            integrals=[("H", energy), ("F", geometry.level)],
            density=None,
            omega=omega,
            details=details,
        )
