"""The claim registry: every statement of the papers (and of our models) with a check.

A claim has a stable ID from ``FORMULAS.md`` (``BKM12-4``, ``K01-2.2`` ...), a sub-ID after
a dot for one part of a numbered claim (``BKM12-5.H``), ``/literal`` for the literal
reading of a garbled formula, and ``/control-...`` for a negative control: a deliberately
wrong statement that the same machinery must refute (``expected="fails"``).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import sympy as sp
from chaplygin.derive import Model, build_model

__all__ = [
    "Claim",
    "Check",
    "Computed",
    "computed_build",
    "REGISTRY",
    "register",
    "select_claims",
    "KINDS",
]

KINDS = ("equation", "integral", "measure", "definition", "transformation", "solution", "value")


@dataclass
class Check:
    """What to decide for a claim: residuals that vanish on the phase space iff it holds.

    Parameters
    ----------
    exprs : list of sympy.Expr
    free : list of sympy.Symbol
        Variables other than state, Poisson vectors and parameters (velocities ...).
    on : list of sympy.Expr
        Restrict the check to a subset of the phase space: relations linear in the
        model's ``relation_unknowns`` (a level set of a linear integral, ``(K, beta) = 0``).
    everywhere : bool
        Decide on the whole phase space, without the model's invariant relations.
    fallback : Check, optional
        A check to decide when this one is refuted. ``exprs`` may then state something
        stronger than the claim (vanishing for every value of a multiplier kept free):
        its proof proves the claim, its refutation does not refute it.
    note : str
        Appended to the verdict's method (what the check's residuals are).
    method : str
        The method used when the caller asks for ``auto``: ``exact-sampled`` where the
        Groebner proof is known to take minutes (the note says so).
    computed : callable, optional
        For a claim about a computed quantity (a Floquet multiplier, a rotation number
        measured on a trajectory, a critical energy): a function of no arguments that
        runs the computation and returns a :class:`Computed`. ``exprs`` is then empty
        and the verdict is ``numeric`` (error within its derived bound) or ``refuted``.
    """

    exprs: list[sp.Expr]
    free: list[sp.Symbol] = field(default_factory=list)
    on: list[sp.Expr] = field(default_factory=list)
    everywhere: bool = False
    fallback: Check | None = None
    note: str = ""
    method: str = "auto"
    computed: Callable[[], Computed] | None = None


@dataclass
class Computed:
    """Outcome of the computation behind a numerical claim.

    Parameters
    ----------
    error : float
        The discrepancy measured (non-negative; NaN counts as failure).
    bound : float
        What the error may be: derived from the tolerance of the computation or the
        digits a paper prints (the ``what`` says which).
    what : str
        What was computed and compared, for the report.
    values : dict
        The numbers behind the verdict (``name -> value`` as strings): the witness of a
        refutation.
    """

    error: float
    bound: float
    what: str
    values: dict[str, str] = field(default_factory=dict)

    @property
    def holds(self) -> bool:
        return bool(self.error <= self.bound)  # False for NaN


def computed_build(fn: Callable[[], Computed], note: str = "") -> Callable:
    """``build`` of a claim about a computed quantity: a :class:`Check` whose ``computed``
    is ``fn``. It needs no model (``build.needs_model`` is False: the verifier does not
    derive one)."""

    def build(model: Model | None) -> Check:
        return Check([], computed=fn, note=note)

    build.needs_model = False
    return build


@dataclass(frozen=True)
class Claim:
    """One statement and how to check it.

    Parameters
    ----------
    id : str
        Stable ID (``FORMULAS.md``).
    source : str
        Paper and place (``BKM12 §1.1, eq. (4)``).
    kind : str
        One of :data:`KINDS`.
    statement : str
        The statement in plain-text math, in the notation of ``FORMULAS.md``.
    system : str
    effects : tuple of str
        The model the claim is about.
    build : callable
        ``build(model) -> Check``.
    expected : {"holds", "fails"}
        ``fails`` for negative controls and literal readings known to be wrong.
    note : str
    latex : str, optional
        The statement in LaTeX for the report (default: translated from ``statement``).
    covers : tuple of str
        Further FORMULAS.md entries whose statement this verdict settles (a control whose
        refutation is what the paper asserts: "the special distribution is needed").
    """

    id: str
    source: str
    kind: str
    statement: str
    system: str
    effects: tuple[str, ...]
    build: Callable[[Model], Check]
    expected: str = "holds"
    note: str = ""
    latex: str = ""
    covers: tuple[str, ...] = ()

    def model(self) -> Model:
        return build_model(self.system, self.effects)


REGISTRY: dict[str, Claim] = {}


def register(claim: Claim) -> Claim:
    if claim.id in REGISTRY:
        raise ValueError(f"duplicate claim ID {claim.id}")
    if claim.kind not in KINDS:
        raise ValueError(f"unknown claim kind {claim.kind}")
    REGISTRY[claim.id] = claim
    return claim


def select_claims(patterns: str | Iterable[str] | None = None) -> list[Claim]:
    """Claims whose ID matches any of the glob patterns (comma-separated), in order.

    An empty selection is an error for the caller to report (see the CLI).
    """
    _load()
    if patterns is None or patterns == "":
        return list(REGISTRY.values())
    if isinstance(patterns, str):
        patterns = [p.strip() for p in patterns.split(",") if p.strip()]
    return [c for c in REGISTRY.values() if any(fnmatch.fnmatchcase(c.id, p) for p in patterns)]


_LOADED = False


def _load() -> None:
    """Import every claim module of this package (registration happens on import).

    ``model_invariants`` comes last so that the papers' claims lead the report.
    """
    global _LOADED
    if _LOADED:
        return
    import importlib
    import pkgutil

    names = sorted(m.name for m in pkgutil.iter_modules(__path__) if m.name != "notation")
    names.sort(key=lambda n: n == "model_invariants")
    for name in names:
        importlib.import_module(f"{__name__}.{name}")
    _LOADED = True
