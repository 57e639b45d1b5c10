"""The Model: what the derivation produces and every other layer consumes."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import sympy as sp

from .algebra import ConstraintIdeal
from .geometry import PoissonGroup

__all__ = ["Model", "ParameterSpec", "MODEL_FORMAT_VERSION"]

#: Bumped whenever the meaning of a Model field changes (part of every model hash).
MODEL_FORMAT_VERSION = 1


@dataclass(frozen=True)
class ParameterSpec:
    """A named group of parameters and the domain a physical value must lie in.

    Parameters
    ----------
    name : str
        Group name as a user types it (``I``, ``D``, ``b``, ``K``).
    symbols : tuple of sympy.Symbol
    domain : {"positive", "real"}
    description : str
    """

    name: str
    symbols: tuple[sp.Symbol, ...]
    domain: str
    description: str


@dataclass(frozen=True, eq=False)
class Model:
    """A derived model: ordered state, parameters, right-hand side and its invariants.

    The right-hand side and the integrals are written in the state symbols, the
    parameters and the *auxiliary* symbols of :attr:`aux` (``omega`` and the Woodbury
    coefficients ``Z``), which are defined, in order, in terms of the state. Code
    generators emit the auxiliary definitions first; :meth:`expand_aux` substitutes them.

    Attributes
    ----------
    system : str
        Name of the system family (``chaplygin_ball``).
    effects : frozenset of str
        Effects it was built with; an effect that is off leaves no term, state or
        parameter behind.
    state_groups : tuple of (str, tuple of sympy.Symbol)
        Ordered named groups (``M``, ``gamma``, ``alpha``, ``beta``, ``x``, ``y``).
    parameters : tuple of ParameterSpec
    aux : tuple of (sympy.Symbol, sympy.Expr)
        Auxiliary definitions, each in terms of the state and the earlier ones.
    rhs : tuple of sympy.Expr
        Time derivative of each state symbol, in state order.
    constraints : tuple of sympy.Expr
        Polynomials that vanish on the phase space (``(gamma, gamma) - 1`` ...).
    geometry : tuple of PoissonGroup
        The space-fixed vectors the constraints come from (used for exact sampling).
    integrals : tuple of (str, sympy.Expr)
        First integrals the model carries (energy, Casimirs, geometric constraints);
        numerics reports the drift of each, verify proves each.
    density : sympy.Expr or None
        Density of the invariant measure in the state variables.
    definitions : dict
        Derived objects kept for checks and documentation (momentum as a function of
        omega, inertia operator, reference-point velocity ...).
    references : dict of str to str
        Claim IDs (FORMULAS.md) the parts of the model correspond to.
    """

    system: str
    effects: frozenset[str]
    time: sp.Symbol
    state_groups: tuple[tuple[str, tuple[sp.Symbol, ...]], ...]
    parameters: tuple[ParameterSpec, ...]
    aux: tuple[tuple[sp.Symbol, sp.Expr], ...]
    rhs: tuple[sp.Expr, ...]
    constraints: tuple[sp.Expr, ...]
    geometry: tuple[PoissonGroup, ...]
    integrals: tuple[tuple[str, sp.Expr], ...]
    density: sp.Expr | None
    definitions: dict[str, Any] = field(default_factory=dict)
    references: dict[str, str] = field(default_factory=dict)

    # ----------------------------------------------------------------- structure
    @property
    def name(self) -> str:
        """Variant name: the system and its sorted effects (``chaplygin_ball__gyrostat``)."""
        return "__".join([self.system, *sorted(self.effects)])

    @cached_property
    def state(self) -> tuple[sp.Symbol, ...]:
        return tuple(s for _, group in self.state_groups for s in group)

    @cached_property
    def params(self) -> tuple[sp.Symbol, ...]:
        return tuple(s for spec in self.parameters for s in spec.symbols)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.state)

    @property
    def param_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.params)

    def group(self, name: str) -> sp.Matrix:
        """State group ``name`` as a column matrix."""
        return sp.Matrix(dict(self.state_groups)[name])

    def param_group(self, name: str) -> sp.Matrix:
        for spec in self.parameters:
            if spec.name == name:
                return sp.Matrix(spec.symbols)
        raise KeyError(name)

    @cached_property
    def vectors(self) -> dict[str, sp.Matrix]:
        """All state groups as column matrices, by name."""
        return {name: sp.Matrix(group) for name, group in self.state_groups}

    @property
    def aux_symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(s for s, _ in self.aux)

    @cached_property
    def _aux_expanded(self) -> dict[sp.Symbol, sp.Expr]:
        done: dict[sp.Symbol, sp.Expr] = {}
        for sym, expr in self.aux:
            done[sym] = expr.xreplace(done)
        return done

    def expand_aux(self, expr):
        """Substitute the auxiliary definitions: an expression in state and parameters."""
        return sp.sympify(expr).xreplace(self._aux_expanded)

    @cached_property
    def rhs_expanded(self) -> sp.Matrix:
        """Right-hand side in state and parameters only, shape (n, 1)."""
        return sp.Matrix([self.expand_aux(e) for e in self.rhs])

    def integral(self, name: str) -> sp.Expr:
        return dict(self.integrals)[name]

    @cached_property
    def ideal(self) -> ConstraintIdeal:
        """Ideal of the phase-space constraints in the Poisson-vector components."""
        gens = [s for g in self.geometry for n in g.names for s in self.vectors[n]]
        return ConstraintIdeal(self.constraints, gens)

    # ----------------------------------------------------------------- identity
    def canonical_text(self) -> str:
        """Deterministic text of everything that defines the model's code."""
        parts = [
            f"format {MODEL_FORMAT_VERSION}",
            f"system {self.system}",
            f"effects {','.join(sorted(self.effects))}",
            f"time {sp.srepr(self.time)}",
            "state " + ",".join(f"{n}:{sp.srepr(g)}" for n, g in self.state_groups),
            "params "
            + ",".join(f"{p.name}:{sp.srepr(p.symbols)}:{p.domain}" for p in self.parameters),
        ]
        parts += [f"aux {sp.srepr(s)} = {sp.srepr(e)}" for s, e in self.aux]
        parts += [f"rhs {sp.srepr(e)}" for e in self.rhs]
        parts += [f"integral {n} = {sp.srepr(e)}" for n, e in self.integrals]
        parts += [f"constraint {sp.srepr(e)}" for e in self.constraints]
        parts.append(f"density {sp.srepr(self.density)}")
        return "\n".join(parts)

    @cached_property
    def hash(self) -> str:
        """Stable content hash (sha256 hex) of :meth:`canonical_text`."""
        return hashlib.sha256(self.canonical_text().encode()).hexdigest()

    def __repr__(self) -> str:
        return (
            f"Model({self.name!r}, state={list(self.state_names)}, "
            f"params={list(self.param_names)}, hash={self.hash[:12]})"
        )
