"""What a claim is (:class:`Claim`, :class:`ComputedClaim`, their checks) and :func:`register`,
the one way a claim module adds its claims.

Claim modules import this module (never the package's ``__init__``, which imports them by name
when the registry is read: :class:`chaplygin.verify.claims.ClaimRegistry`), so the claims and
their registry form no import cycle.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import sympy as sp
from chaplygin.derive import Model, build_model

__all__ = [
    "Claim",
    "ComputedClaim",
    "Check",
    "Computed",
    "register",
    "ClaimStore",
    "CLAIMS",
    "KINDS",
    "VERDICT_OF_METHOD",
    "PROVED_BY_COMPUTATION",
]

#: The verdict of a statement decided by enclosures in ball arithmetic.
PROVED_BY_COMPUTATION = "proved by computation"

KINDS = ("equation", "integral", "measure", "definition", "transformation", "solution", "value")

#: The verdict a claim that holds must get when its check asks for a method: a proof
#: (``auto`` and ``symbolic``: a Groebner normal form) or the sampled method asked for.
VERDICT_OF_METHOD = {
    "auto": "proved",
    "symbolic": "proved",
    "exact-sampled": "exact-sampled",
    "numeric": "numeric",
}


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
        Groebner proof is known to take minutes, ``numeric`` for floating-point
        residuals. A check that chooses a method says why in its ``note``.
    along_flow : bool
        ``exprs`` are would-be integrals whose rate along the flow is decided through the
        model's auxiliaries at exact points (:mod:`~chaplygin.verify.chained`: models whose
        expanded right-hand side is too large to expand); the method is ``exact-sampled``.

    Raises
    ------
    ValueError
        An unknown method, or a method chosen without a note.
    """

    exprs: list[sp.Expr]
    free: list[sp.Symbol] = field(default_factory=list)
    on: list[sp.Expr] = field(default_factory=list)
    everywhere: bool = False
    fallback: Check | None = None
    note: str = ""
    method: str = "auto"
    along_flow: bool = False

    def __post_init__(self) -> None:
        if self.method not in VERDICT_OF_METHOD:
            raise ValueError(
                f"unknown method {self.method!r}; valid: {', '.join(VERDICT_OF_METHOD)}"
            )
        if self.method != "auto" and not self.note:
            raise ValueError(f"a check that chooses the method {self.method!r} says why (note)")


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
    decided : {"proved", "refuted", "undecided"} or None
        For a computation in ball arithmetic (a proof by computation): what the enclosures
        decided. None for a floating-point computation (``error`` against ``bound``).
    """

    error: float
    bound: float
    what: str
    values: dict[str, str] = field(default_factory=dict)
    decided: str | None = None

    @property
    def holds(self) -> bool:
        """The statement holds: proved by the enclosures, or (floating point) the error is
        within the bound (False for NaN)."""
        if self.decided is not None:
            return self.decided == "proved"
        return bool(self.error <= self.bound)


@dataclass(frozen=True, kw_only=True)
class Claim:
    """One statement and how to check it (keyword arguments only).

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
    effects: tuple[str, ...] = ()
    build: Callable[[Model], Check]
    expected: str = "holds"
    note: str = ""
    latex: str = ""
    covers: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"unknown claim kind {self.kind!r}; valid: {', '.join(KINDS)}")
        if self.expected not in ("holds", "fails"):
            raise ValueError(f"expected must be 'holds' or 'fails', got {self.expected!r}")

    def model(self) -> Model:
        """The model the claim is about (derived, or loaded from the model cache).

        Returns
        -------
        Model
            ``build_model(self.system, self.effects)``.
        """
        return build_model(self.system, self.effects)

    def expected_verdict(self, check: Check | None = None, method: str = "auto") -> str:
        """The verdict this claim must get.

        Parameters
        ----------
        check : Check, optional
            The claim's check (its ``method`` chooses the verdict of a claim that holds).
        method : {"auto", "symbolic", "exact-sampled", "numeric"}
            The method the caller asked for.

        Returns
        -------
        str
            ``"refuted"`` for a claim expected to fail; otherwise ``"proved"``, or the
            sampled method the check (under ``auto``) or the caller chose.
        """
        if self.expected == "fails":
            return "refuted"
        if check is not None and check.along_flow:  # decided by exact sampling, always
            return "exact-sampled"
        chosen = check.method if method == "auto" and check is not None else method
        return VERDICT_OF_METHOD[chosen]


@dataclass(frozen=True, kw_only=True)
class ComputedClaim(Claim):
    """A claim about a computed quantity (a Floquet multiplier, a rotation number measured
    on a trajectory, a critical energy): no residuals and no model to derive.

    Parameters
    ----------
    compute : callable
        A function of no arguments that runs the computation and returns a
        :class:`Computed`. The verdict is ``numeric`` (error within its derived bound)
        or ``refuted``, whatever method the caller asks for.
    rigorous : bool
        The computation is in ball arithmetic and decides the statement
        (:attr:`Computed.decided`): the verdict is ``proved by computation`` or ``refuted``;
        an enclosure too wide to decide gives ``numeric`` (not the expected verdict).
    """

    build: None = None
    compute: Callable[[], Computed]
    rigorous: bool = False

    def model(self) -> None:
        """A computed claim needs no model (the verifier derives none)."""
        return None

    def expected_verdict(self, check: Check | None = None, method: str = "auto") -> str:
        """``"numeric"`` for a claim that holds, ``"refuted"`` for one that fails.

        Parameters
        ----------
        check : Check, optional
            Ignored (a computed claim has no check).
        method : {"auto", "symbolic", "exact-sampled", "numeric"}
            Ignored: the verdict does not depend on the method asked for.

        Returns
        -------
        str
            ``"proved by computation"`` (a rigorous claim that holds), ``"numeric"`` or
            ``"refuted"``.
        """
        if self.expected == "fails":
            return "refuted"
        return PROVED_BY_COMPUTATION if self.rigorous else "numeric"


class ClaimStore:
    """Claims by ID, in registration order; an ID is added once.

    Attributes
    ----------
    claims : dict of str to Claim
    """

    def __init__(self) -> None:
        self.claims: dict[str, Claim] = {}

    def add(self, claim: Claim) -> None:
        """Add one claim (its ID must be new).

        Parameters
        ----------
        claim : Claim

        Raises
        ------
        ValueError
            If a claim with the same ID is already there.
        """
        if claim.id in self.claims:
            raise ValueError(f"duplicate claim ID {claim.id}")
        self.claims[claim.id] = claim


#: Where :func:`register` puts the claims (:data:`chaplygin.verify.claims.REGISTRY` reads it).
CLAIMS = ClaimStore()


def register(*claims: Claim) -> tuple[Claim, ...]:
    """Register claims (the one way a claim module adds its claims).

    Parameters
    ----------
    *claims : Claim
        Built with keyword arguments; IDs must be new.

    Returns
    -------
    tuple of Claim
        The claims, registered.

    Raises
    ------
    ValueError
        If a claim with the same ID is already registered.
    """
    for claim in claims:
        CLAIMS.add(claim)
    return claims
