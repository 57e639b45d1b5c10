"""Base class of the emitters and the language-neutral routines they print.

A model is turned into *routines* (rhs, Jacobian, auxiliary quantities, integrals), each a
list of output expressions in the state and parameters with common subexpressions
eliminated once here; an emitter only prints them (``_emit_files`` hook).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import mpmath
import sympy as sp

from ..expression_dag import subexpressions
from ..model import Model

__all__ = [
    "Routine",
    "ModelRoutines",
    "Emitter",
    "EMITTERS",
    "get_emitter",
    "header_lines",
    "GENERATOR_VERSION",
]

#: Version of the code generator: part of every stamp (bump when the output changes).
GENERATOR_VERSION = "4"


@dataclass(frozen=True)
class Routine:
    """Straight-line code: ``temporaries`` then ``outputs`` (both after CSE)."""

    name: str
    temporaries: tuple[tuple[sp.Symbol, sp.Expr], ...]
    outputs: tuple[sp.Expr, ...]
    shape: tuple[int, ...]

    @property
    def operation_count(self) -> int:
        """Size of the routine, for reports and tests.

        Returns
        -------
        int
            ``sympy.count_ops`` summed over the temporaries and the outputs.
        """
        exprs = [e for _, e in self.temporaries] + list(self.outputs)
        return int(sum(sp.count_ops(e) for e in exprs))


def _temporaries(taken: set[str]):
    """``x0, x1, ...`` skipping every name a model symbol already has (a state ``x1``)."""
    for sym in sp.numbered_symbols("x"):
        if sym.name not in taken:
            yield sym


def _cse(name: str, exprs: list[sp.Expr], shape: tuple[int, ...]) -> Routine:
    # every symbol's name, each distinct subexpression visited once (free_symbols walks a
    # shared subtree once per path to it); a bound symbol's name too, which only skips a
    # temporary's name
    taken = {s.name for s in subexpressions([sp.sympify(e) for e in exprs])
             if isinstance(s, sp.Symbol)}
    temps, reduced = sp.cse(exprs, symbols=_temporaries(taken), order="canonical")
    return Routine(name, tuple(temps), tuple(reduced), shape)


#: Above this many operations in the right-hand side with the auxiliaries substituted
#: (estimated through them, :func:`expanded_size`), the right-hand side and its Jacobian
#: are written from the auxiliaries in order (:func:`_chained`) rather than expanded and
#: reduced by common subexpression elimination: a ball of any inertia on a support surface
#: has some 10^6 operations per component expanded, 5 10^3 in its auxiliaries. Every model
#: in ``generated/`` is far below it (their code does not change).
CHAIN_OPS = 200_000


def expanded_size(model: Model, exprs: Sequence[sp.Expr] | None = None) -> int:
    """The operations of the largest right-hand side component once the auxiliaries are
    substituted, estimated from each auxiliary's own count (no expansion is made).

    Parameters
    ----------
    model : Model
    exprs : sequence of sympy.Expr, optional
        The expressions to size instead of the right-hand side's components.

    Returns
    -------
    int
    """
    size: dict[sp.Symbol, int] = {}

    def of(expr: sp.Expr) -> int:
        used = [a for a in sp.sympify(expr).free_symbols if a in size]
        return sp.count_ops(expr) + sum(size[a] * sp.sympify(expr).count(a) for a in used)

    for symbol, expr in model.aux:
        size[symbol] = of(expr)
    return max((of(e) for e in (model.rhs if exprs is None else exprs)), default=0)


def _chained(name: str, model: Model, rhs: bool, jacobian: bool) -> Routine:
    """The right-hand side and/or its Jacobian from the auxiliaries in order: the
    auxiliaries' definitions, then (for the Jacobian) each auxiliary's derivatives by the
    state, ``dA_i/dy_k = de_i/dy_k + sum_j de_i/dA_j dA_j/dy_k`` (forward, one temporary per
    non-zero entry), as temporaries; no common subexpression elimination."""
    state = list(model.state)
    temps: list[tuple[sp.Symbol, sp.Expr]] = list(model.aux)
    taken = {s.name for s in (*state, *model.params, *(a for a, _ in model.aux))}
    fresh = _temporaries(taken)
    derivative: dict[sp.Symbol, list[sp.Expr]] = {}

    def total(expr: sp.Expr) -> list[sp.Expr]:
        inner = [a for a in sp.sympify(expr).free_symbols if a in derivative]
        partial = {a: sp.diff(expr, a) for a in inner}
        return [
            sp.diff(expr, y) + sum((partial[a] * derivative[a][k] for a in inner), sp.S.Zero)
            for k, y in enumerate(state)
        ]

    if jacobian:
        for symbol, expr in model.aux:
            row = []
            for entry in total(expr):
                if entry == 0:
                    row.append(sp.S.Zero)
                    continue
                d = next(fresh)
                temps.append((d, entry))
                row.append(d)
            derivative[symbol] = row
    outputs = list(model.rhs) if rhs else []
    if jacobian:
        outputs += [entry for e in model.rhs for entry in total(e)]
    n = len(state)
    shape = (n + n * n,) if rhs and jacobian else (n, n) if jacobian else (n,)
    return Routine(name, tuple(temps), tuple(outputs), shape)


class ModelRoutines:
    """The routines of a model, shared by all emitters.

    Parameters
    ----------
    model : Model
        The model whose routines are built (each on first access, then cached).
    """

    def __init__(self, model: Model):
        self.model = model

    @cached_property
    def rhs(self) -> Routine:
        """Right-hand side ``y' = f(t, y, p)``.

        Returns
        -------
        Routine
            ``"rhs"``, outputs of shape ``(n,)`` with ``n`` the state dimension.
        """
        if self.chained:
            return _chained("rhs", self.model, rhs=True, jacobian=False)
        return _cse("rhs", list(self.model.rhs_expanded), (len(self.model.state),))

    @cached_property
    def chained(self) -> bool:
        """Whether the right-hand side and its Jacobian are written from the auxiliaries in
        order (the expanded right-hand side is over :data:`CHAIN_OPS` operations).

        Returns
        -------
        bool
        """
        return bool(self.model.aux) and expanded_size(self.model) > CHAIN_OPS

    @cached_property
    def jacobian(self) -> Routine:
        """Row-major ``d rhs_i / d y_j``.

        Returns
        -------
        Routine
            ``"jac"``, outputs of shape ``(n, n)``, row-major.
        """
        if self.chained:
            return _chained("jac", self.model, rhs=False, jacobian=True)
        J = self.model.jacobian_expanded
        n = len(self.model.state)
        return _cse("jac", list(J), (n, n))

    @cached_property
    def rhs_jacobian(self) -> Routine:
        """The right-hand side and the Jacobian in one routine (one common subexpression
        elimination: ``sin(Omega t)`` and the temporaries they share computed once), what the
        variational equations evaluate at every stage.

        Returns
        -------
        Routine
            ``"rhs_jac"``, outputs of shape ``(n + n n,)``: ``f`` then ``J`` row-major.
        """
        if self.chained:
            return _chained("rhs_jac", self.model, rhs=True, jacobian=True)
        n = len(self.model.state)
        exprs = list(self.model.rhs_expanded) + list(self.model.jacobian_expanded)
        return _cse("rhs_jac", exprs, (n + n * n,))

    @cached_property
    def aux(self) -> Routine:
        """Auxiliary quantities (``omega`` ...) in the state and parameters.

        Returns
        -------
        Routine
            ``"aux"``, one output per auxiliary symbol of the model.
        """
        exprs = [self.model.expand_aux(s) for s in self.model.aux_symbols]
        return _cse("aux", exprs, (len(exprs),))

    @cached_property
    def integrals(self) -> Routine:
        """First integrals of the model, in the model's order.

        Returns
        -------
        Routine
            ``"integrals"``, one output per integral.
        """
        exprs = [self.model.expand_aux(e) for _, e in self.model.integrals]
        return _cse("integrals", exprs, (len(exprs),))

    @cached_property
    def density(self) -> Routine:
        """Invariant-measure density (``1`` when the model has none).

        Returns
        -------
        Routine
            ``"density"``, one output.
        """
        exprs = [self.model.expand_aux(self.model.density if self.model.density is not None else 1)]
        return _cse("density", exprs, (1,))

    @cached_property
    def constraints(self) -> Routine:
        """The phase-space constraints and their scales (Python emitters only).

        Returns
        -------
        Routine
            ``"constraints"``: ``2 k`` outputs for ``k`` constraints, first the value of
            each (zero on the phase space: ``|gamma|^2 - 1``, ``(x, B^-1 x) - 1`` ...) then
            its scale, the sum of the absolute values of its terms (what "small" is
            measured against when a user's state is checked).
        """
        values = [sp.expand(self.model.expand_aux(c)) for c in self.model.constraints]
        scales = [sum((sp.Abs(term) for term in sp.Add.make_args(v)), sp.S.Zero) for v in values]
        return _cse("constraints", values + scales, (2 * len(values),))

    def all(self) -> tuple[Routine, ...]:
        """Every routine, in the order the emitters print them.

        Returns
        -------
        tuple of Routine
            ``(rhs, jacobian, aux, integrals, density)``.
        """
        return (self.rhs, self.jacobian, self.aux, self.integrals, self.density)


def header_lines(model: Model, language: str) -> list[str]:
    """Deterministic stamp of a generated file (no time, no host).

    Parameters
    ----------
    model : Model
        The model the file is generated from.
    language : str
        Emitter name written into the stamp.

    Returns
    -------
    list of str
        Lines without comment markers: generator, sympy and mpmath versions, the
        "do not edit" notice, system and effects, model hash, state and parameters.
    """
    return [
        f"Generated by chaplygin code generator {GENERATOR_VERSION} ({language}), "
        f"sympy {sp.__version__}, mpmath {mpmath.__version__}.",
        "DO NOT EDIT: regenerate with `chaplygin derive`.",
        f"model: {model.system}; effects: {', '.join(sorted(model.effects)) or 'none'}",
        f"model hash: {model.hash}",
        f"state: {', '.join(model.state_names)}",
        f"parameters: {', '.join(model.param_names)}",
    ]


class Emitter:
    """Base emitter: ``emit(model)`` returns ``[(filename, text)]``.

    Subclasses set :attr:`language` and :attr:`ending` and fill :meth:`_emit_files`.
    """

    language: str = ""
    #: What follows the model's name in the emitted file's name (``"_taylor.c"``).
    ending: str = ""

    def filename(self, model: Model) -> str:
        """Name of the emitted file.

        Parameters
        ----------
        model : Model
            The model printed.

        Returns
        -------
        str
            ``"<model name><ending>"``.
        """
        return f"{model.name}{self.ending}"

    def emit(self, model: Model, routines: ModelRoutines | None = None) -> list[tuple[str, str]]:
        """Source files for ``model``; deterministic for a given model hash.

        Parameters
        ----------
        model : Model
            The model to print.
        routines : ModelRoutines, optional
            Routines of ``model`` already built (shared between emitters); built
            here when omitted.

        Returns
        -------
        list of (str, str)
            ``(filename, text)`` pairs.
        """
        return self._emit_files(model, routines or ModelRoutines(model))

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        raise NotImplementedError


EMITTERS: dict[str, type[Emitter]] = {}


def register(cls: type[Emitter]) -> type[Emitter]:
    """Class decorator: add an emitter to :data:`EMITTERS` under its ``language``.

    Parameters
    ----------
    cls : type of Emitter
        The emitter class.

    Returns
    -------
    type of Emitter
        ``cls`` itself.
    """
    EMITTERS[cls.language] = cls
    return cls


def get_emitter(language: str | type[Emitter] | Emitter) -> Emitter:
    """Emitter by name (``numpy``, ``mpmath``, ``c``), class or instance.

    Parameters
    ----------
    language : str or type of Emitter or Emitter
        A registered name, an emitter class (instantiated), or an instance (returned
        as is).

    Returns
    -------
    Emitter
        A new instance for a name or a class; ``language`` itself for an instance.

    Raises
    ------
    ValueError
        For an unknown name; the message lists the valid ones.
    """
    if isinstance(language, Emitter):
        return language
    if isinstance(language, type) and issubclass(language, Emitter):
        return language()
    try:
        return EMITTERS[language]()
    except KeyError:
        raise ValueError(
            f"unknown emitter {language!r}; valid: {', '.join(sorted(EMITTERS))}"
        ) from None
