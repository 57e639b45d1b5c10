"""What an effect adds to a mechanical description, as data.

An effect (:mod:`.effects`) reads the description it is applied to (its ``omega``, its
vectors, its state groups and parameters) and returns a :class:`Declaration`: the terms,
constraints, states, parameters, integrals ... it adds. The description merges it
(:meth:`~.description.MechanicalDescription.add`); the one finishing step
(:func:`~.description.form_model`) reads only the merged data. A declaration is plain
data: it can be printed, compared and checked against the model it ends up in
(``tests/derive/test_description.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import sympy as sp

from .model import ParameterSpec

__all__ = ["StateGroup", "Constraint", "Declaration"]


class StateGroup(NamedTuple):
    """A named group of state symbols and its rate.

    Attributes
    ----------
    name : str
    symbols : tuple of sympy.Symbol
    rate : tuple of sympy.Expr or None
        The time derivative of each symbol; None when the reduction stage derives it
        (the momentum ``M`` of a rigid body ...). A rate written in the reference-point
        velocity ``v`` is put on the admissible velocities by the finishing step.
    """

    name: str
    symbols: tuple[sp.Symbol, ...]
    rate: tuple[sp.Expr, ...] | None


class Constraint(NamedTuple):
    """A velocity constraint, linear and homogeneous in the velocities.

    Attributes
    ----------
    expr : sympy.Expr
    reacts_along : str or None
        For a constraint on omega alone ``(omega, X) = 0``: the name of the space-fixed
        vector ``X`` its reaction torque lies along. The flow keeps such a constraint (its
        multiplier is eliminated from ``d/dt (omega, X) = 0``): it is the model's
        invariant relation :attr:`relation_name`, and it kills the momentum integrals
        along ``X``.
    """

    expr: sp.Expr
    reacts_along: str | None = None

    @property
    def relation_name(self) -> str | None:
        """``"(omega,X)"`` for a constraint on omega alone, else None."""
        return None if self.reacts_along is None else f"(omega,{self.reacts_along})"


@dataclass(frozen=True)
class Declaration:
    """What one effect adds to a mechanical description; every field may stay empty.

    Attributes
    ----------
    kinetic_energy : sympy.Expr
        A term of ``T``.
    potential : sympy.Expr
        A term of the potential energy of the external forces.
    poisson_vectors : tuple of str
        Space-fixed vectors ``X`` (``X' = X x omega``, symbols ``X1, X2, X3``), added as
        kinematics and state groups unless the description has them already.
    constraints : tuple of Constraint
        Velocity constraints (those on omega alone with their reaction vector: they are
        the :attr:`invariant_relations`).
    states : tuple of StateGroup
        State groups with their rates, after the :attr:`poisson_vectors`.
    parameters : tuple of ParameterSpec
        Parameter groups (a second, identical declaration of a group is a no-op).
    redeclared_parameters : tuple of str
        Groups whose earlier declaration this one replaces: dropped before
        :attr:`parameters` are added (a group named here and not declared again is
        removed: its symbols became functions of time).
    integrals : tuple of (str, sympy.Expr)
        First integrals, or terms of an integral of that name already declared.
    phase_space : tuple of sympy.Expr
        Polynomials that vanish on the phase space.
    inertia : sympy.Matrix or None
        The body's inertia tensor in body axes, replacing the system's.
    moments : tuple of sympy.Symbol or None
        The parameters the principal moments are written in, replacing the system's
        (empty: the moments are functions of time).
    momentum_in_state : sympy.Matrix or None, shape (3, 1)
        Velocity-independent momentum the momentum state includes (BM20's total
        momentum includes ``k(t)``, BM20-2.2).
    completion : tuple of ((str, ...), str)
        How state groups a user omits are completed (``Model.completion``).
    """

    kinetic_energy: sp.Expr = sp.S.Zero
    potential: sp.Expr = sp.S.Zero
    poisson_vectors: tuple[str, ...] = ()
    constraints: tuple[Constraint, ...] = ()
    states: tuple[StateGroup, ...] = ()
    parameters: tuple[ParameterSpec, ...] = ()
    redeclared_parameters: tuple[str, ...] = ()
    integrals: tuple[tuple[str, sp.Expr], ...] = ()
    phase_space: tuple[sp.Expr, ...] = ()
    inertia: sp.Matrix | None = None
    moments: tuple[sp.Symbol, ...] | None = None
    momentum_in_state: sp.Matrix | None = None
    completion: tuple[tuple[tuple[str, ...], str], ...] = ()

    @property
    def invariant_relations(self) -> tuple[tuple[str, sp.Expr], ...]:
        """The relations ``(omega,X)`` of the constraints on omega alone.

        Returns
        -------
        tuple of (str, sympy.Expr)
        """
        return tuple((c.relation_name, c.expr) for c in self.constraints if c.reacts_along)
