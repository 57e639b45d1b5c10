"""The Model: what the derivation produces and every other layer consumes."""

from __future__ import annotations

import hashlib
import random
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property

import sympy as sp

from .algebra import ConstraintIdeal
from .engine import StructuredInverse
from .errors import DerivationError
from .geometry import PoissonGroup

__all__ = [
    "Model",
    "ModelDetails",
    "ParameterSpec",
    "PhaseSpaceSampler",
    "Reparametrisation",
    "MODEL_FORMAT_VERSION",
]

#: Rules by which a missing state group is completed (see ``Model.completion``).
COMPLETION_RULES = ("zero", "frame_bkm12_7", "normal")

#: ``sampler(rng, point)`` writes an exact rational point of a model's phase space (and
#: the parameters that shape it) into the dict ``point``; picklable (models are cached).
PhaseSpaceSampler = Callable[[random.Random, dict], None]

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


@dataclass(frozen=True)
class Reparametrisation:
    """An invertible change of parameters used by exact identity checks.

    The verifier rewrites a residual in the new parameters (``inverse``) and computes
    their values from the physical ones (``forward``); ``A_i = 1/J_ii`` keeps the
    numerators of the Chaplygin ball small.

    Attributes
    ----------
    forward : dict of sympy.Symbol to sympy.Expr
        New parameter -> expression in the model's parameters (and possibly time).
    inverse : dict of sympy.Symbol to sympy.Expr
        Model parameter -> expression in the new parameters.
    """

    forward: Mapping[sp.Symbol, sp.Expr]
    inverse: Mapping[sp.Symbol, sp.Expr]


class ModelDetails:
    """Base of the system-specific derivation records a Model carries in ``details``.

    Each system module defines a (frozen) dataclass subclass whose fields are the
    derived objects its claims and tests read (``BallDetails`` of
    :mod:`.chaplygin_ball` ...); they do not enter the model hash.
    """


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
    omega : sympy.Matrix or None, shape (3, 1)
        Angular-velocity symbols (auxiliary symbols, or state symbols of a model
        written in ``omega``).
    momentum_of_omega : sympy.Matrix or None, shape (3, 1)
        The momentum state as a function of ``omega`` (``M = II omega`` plus what the
        state includes, ``k(t)`` with ``variable_gyrostat``).
    inertia_operator : sympy.Matrix or None, shape (3, 3)
        ``II = dM/domega``.
    structured_inverse : StructuredInverse or None
        ``II = J + U C U^T`` on the phase space (the Woodbury form behind ``omega``).
    euler_poincare_remainder : sympy.Matrix or None, shape (3, 1)
        ``M' - (M + P0) x omega`` as derived (zero for the ball and the support).
    invariant_relations : tuple of (str, sympy.Expr)
        Constraints on omega alone kept by the flow (``(omega, gamma)`` ...): zero on
        the phase space; linear in :attr:`relation_unknowns`.
    relation_unknowns : tuple of sympy.Symbol
        State symbols the invariant relations (and a check's level sets of linear
        integrals) are solved for when a point is sampled (the momentum).
    reparametrisation : Reparametrisation or None
        Invertible change of parameters for exact checks.
    sampler : callable or None
        ``sampler(rng, point)``: exact rational point of a phase space that is not made
        of the Poisson vectors of :attr:`geometry` (and the parameters that shape it);
        see :mod:`.phase_space`.
    details : ModelDetails or None
        System-specific derived objects (a typed record of the system's module).
    references : dict of str to str
        Claim IDs (FORMULAS.md) the parts of the model correspond to.
    completion : tuple of ((str, ...), str)
        How a partial initial state is completed, declared by the system or an effect:
        groups and a rule of :data:`COMPLETION_RULES` (``"zero"``: start at 0;
        ``"frame_bkm12_7"``: ``alpha = M x gamma/|M x gamma|``, ``beta = gamma x alpha``;
        ``"normal"``: a fixed vector starting as the model's unit vector outside its frame,
        the normal ``gamma`` of a fixed sphere).
        A group without a rule must be given. Not part of the hash.

    Raises
    ------
    DerivationError
        When made with a symbol in the right-hand side, an auxiliary definition, an
        integral, a constraint, the density or an invariant relation that is neither
        state, parameter, auxiliary nor time; with a parameter that neither the
        right-hand side nor an auxiliary definition uses; or with invariant relations
        but no relation unknowns.
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
    omega: sp.Matrix | None = None
    momentum_of_omega: sp.Matrix | None = None
    inertia_operator: sp.Matrix | None = None
    structured_inverse: StructuredInverse | None = None
    euler_poincare_remainder: sp.Matrix | None = None
    invariant_relations: tuple[tuple[str, sp.Expr], ...] = ()
    relation_unknowns: tuple[sp.Symbol, ...] = ()
    reparametrisation: Reparametrisation | None = None
    sampler: PhaseSpaceSampler | None = None
    details: ModelDetails | None = None
    references: dict[str, str] = field(default_factory=dict)
    completion: tuple[tuple[tuple[str, ...], str], ...] = ()

    def __post_init__(self) -> None:
        self._validate()

    def _validate(self) -> None:
        """Every symbol declared, every parameter used (see the class docstring)."""
        declared = set(self.params) | set(self.state) | set(self.aux_symbols) | {self.time}
        parts: list[tuple[str, object]] = [("the right-hand side", e) for e in self.rhs]
        parts += [(f"the auxiliary definition of {s}", e) for s, e in self.aux]
        parts += [(f"the integral {n}", e) for n, e in self.integrals]
        parts += [(f"the invariant relation {n}", e) for n, e in self.invariant_relations]
        parts += [("a phase-space constraint", e) for e in self.constraints]
        if self.density is not None:
            parts.append(("the density", self.density))
        for where, expr in parts:
            undeclared = sp.sympify(expr).free_symbols - declared
            if undeclared:
                names = ", ".join(sorted(s.name for s in undeclared))
                raise DerivationError(
                    f"model {self.name}: {where} uses {names}, which is neither a state, a "
                    "parameter, an auxiliary symbol nor time: declare it (a ParameterSpec, "
                    "a state group or an aux definition)"
                )
        used = set().union(
            *(sp.sympify(e).free_symbols for e in (*self.rhs, *(e for _, e in self.aux)))
        )
        unused = [s.name for s in self.params if s not in used]
        if unused:
            raise DerivationError(
                f"model {self.name}: parameters {', '.join(unused)} are used by no equation: "
                "remove them from the parameters (an effect that is off leaves none behind)"
            )
        for groups, rule in self.completion:
            if rule not in COMPLETION_RULES or not set(groups) <= {n for n, _ in self.state_groups}:
                raise DerivationError(
                    f"model {self.name}: completion {groups} by {rule!r}: the rule must be one "
                    f"of {', '.join(COMPLETION_RULES)} and the groups states of the model"
                )
        if self.invariant_relations and not self.relation_unknowns:
            raise DerivationError(
                f"model {self.name}: invariant relations need relation_unknowns (the state "
                "symbols they are solved for when a point is sampled)"
            )

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
        """State group ``name`` as a column matrix.

        Parameters
        ----------
        name : str
            Name of a state group (``"M"``, ``"gamma"``, ...).

        Returns
        -------
        sympy.Matrix
            Its state symbols, shape (len(group), 1).

        Raises
        ------
        KeyError
            If the model has no state group ``name``.
        """
        return sp.Matrix(dict(self.state_groups)[name])

    def param_group(self, name: str) -> sp.Matrix:
        """Parameter group ``name`` as a column matrix.

        Parameters
        ----------
        name : str
            Name of a :class:`ParameterSpec` of the model (``"I"``, ``"D"``, ...).

        Returns
        -------
        sympy.Matrix
            Its parameter symbols, shape (len(spec.symbols), 1).

        Raises
        ------
        KeyError
            If the model has no parameter group ``name``.
        """
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

    def expand_aux(
        self, expr: sp.Expr | sp.MatrixBase | float
    ) -> sp.Expr | sp.ImmutableDenseMatrix:
        """Substitute the auxiliary definitions: an expression in state and parameters.

        Parameters
        ----------
        expr : sympy.Expr or sympy.Matrix or float
            An expression (or matrix of them) that may use the auxiliary symbols.

        Returns
        -------
        sympy.Expr or sympy.ImmutableDenseMatrix
            ``sympify(expr)`` with every auxiliary symbol replaced by its definition
            (itself expanded), so only state, parameters and time remain; a matrix
            comes back immutable, of the same shape.
        """
        return sp.sympify(expr).xreplace(self._aux_expanded)

    @cached_property
    def rhs_expanded(self) -> sp.Matrix:
        """Right-hand side in state and parameters only, shape (n, 1)."""
        return sp.Matrix([self.expand_aux(e) for e in self.rhs])

    def state_derivatives(self, expr: sp.Expr) -> list[sp.Expr]:
        """``d expr / d y_j`` for every state variable, through the auxiliary definitions.

        The chain rule on the model as written: ``d expr/dy = partial_y expr + sum_a
        partial_a expr da/dy`` with each auxiliary's total derivative formed once from
        its own definition (the auxiliaries are defined in order). Differentiating the
        expanded expression instead walks the auxiliaries' trees again in every
        factor: 3-4 times slower and larger after CSE (the rubber ball's Jacobian 17.5 s
        and 1129 operations, here 6.1 s and 869).

        Parameters
        ----------
        expr : sympy.Expr
            An expression in state, parameters, time and auxiliary symbols.

        Returns
        -------
        list of sympy.Expr
            One derivative per state variable, in state, parameters and time only.
        """
        totals = self._aux_state_derivatives
        e = sp.sympify(expr)
        used = [a for a in self.aux_symbols if a in e.free_symbols]
        partial = {a: e.diff(a) for a in used}
        out = []
        for j, y in enumerate(self.state):
            d = e.diff(y) + sp.Add(*(partial[a] * totals[a][j] for a in used))
            out.append(self.expand_aux(d))
        return out

    @cached_property
    def _aux_state_derivatives(self) -> dict[sp.Symbol, list[sp.Expr]]:
        """Each auxiliary's total derivative by each state variable (in state and aux)."""
        totals: dict[sp.Symbol, list[sp.Expr]] = {}
        for sym, expr in self.aux:
            used = [a for a in totals if a in expr.free_symbols]
            partial = {a: expr.diff(a) for a in used}
            totals[sym] = [
                expr.diff(y) + sp.Add(*(partial[a] * totals[a][j] for a in used))
                for j, y in enumerate(self.state)
            ]
        return totals

    @cached_property
    def jacobian_expanded(self) -> sp.Matrix:
        """``d rhs_i / d y_j`` in state and parameters, shape (n, n), by the chain rule
        through the auxiliary definitions (:meth:`state_derivatives`)."""
        return sp.Matrix([self.state_derivatives(f) for f in self.rhs])

    def integral(self, name: str) -> sp.Expr:
        """The first integral called ``name``.

        Parameters
        ----------
        name : str
            Name of an integral of the model (``"H"``, ``"F1"``, ...).

        Returns
        -------
        sympy.Expr
            Its expression (it may use auxiliary symbols; see :meth:`expand_aux`).

        Raises
        ------
        KeyError
            If the model has no integral ``name``.
        """
        return dict(self.integrals)[name]

    @cached_property
    def ideal(self) -> ConstraintIdeal:
        """Ideal of the phase-space constraints in the Poisson-vector components."""
        gens = [s for g in self.geometry for n in g.names for s in self.vectors[n]]
        return ConstraintIdeal(self.constraints, gens)

    # ----------------------------------------------------------------- identity
    def canonical_text(self) -> str:
        """Deterministic text of everything that defines the model's code.

        Returns
        -------
        str
            One line each for the format version, system, effects, time, state groups,
            parameters, auxiliary definitions, right-hand side, integrals, constraints
            and density, written with ``sympy.srepr``.
        """
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
