"""The claim registry: every statement of the papers (and of our models) with a check.

A claim has a stable ID from ``FORMULAS.md`` (``BKM12-4``, ``K01-2.2`` ...), a sub-ID after
a dot for one part of a numbered claim (``BKM12-5.H``), ``/literal`` for the literal
reading of a garbled formula, and ``/control-...`` for a negative control: a deliberately
wrong statement that the same machinery must refute (``expected="fails"``).

A claim module registers its claims in one call, with keyword arguments::

    register(
        Claim(id="BKM12-4", source="BKM12 §1.1, eq. (4)", kind="measure", statement="...",
              system="chaplygin_ball", build=_bkm12_4),
        ComputedClaim(id="BKM12-1.5stab", ..., compute=_printed_multipliers(...)),
    )

:data:`REGISTRY` fills itself on first use: ``REGISTRY["BKM12-4"]`` imports the claim
modules; the claims about the built-in models (``MODEL:...``, whose IDs name the integrals
of the derived models) are loaded only when a lookup or a selection may need them.
"""

from __future__ import annotations

import fnmatch
import importlib
import pkgutil
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field

import sympy as sp
from chaplygin.derive import Model, build_model

__all__ = [
    "Claim",
    "ComputedClaim",
    "Check",
    "Computed",
    "ClaimRegistry",
    "REGISTRY",
    "register",
    "select_claims",
    "KINDS",
    "VERDICT_OF_METHOD",
]

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
    """

    error: float
    bound: float
    what: str
    values: dict[str, str] = field(default_factory=dict)

    @property
    def holds(self) -> bool:
        """The error is within the bound (False for NaN)."""
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
    """

    build: None = None
    compute: Callable[[], Computed]

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
            ``"numeric"`` or ``"refuted"``.
        """
        return "refuted" if self.expected == "fails" else "numeric"


#: Modules of this package that register claims about our own models (loaded last and
#: only when needed: registering them derives every built-in model variant).
_MODEL_MODULES = ("model_invariants",)
_MODEL_PREFIX = "MODEL:"


class ClaimRegistry(Mapping[str, Claim]):
    """The registered claims by ID, in registration order; fills itself on first use.

    Reading it (``REGISTRY[id]``, ``id in REGISTRY``, iteration) imports the claim modules
    of this package, where registration happens. The claims of :data:`_MODEL_MODULES`
    (``MODEL:...``) are loaded only by a lookup of such an ID, by iteration or by a
    selection whose patterns may match one.
    """

    def __init__(self) -> None:
        self._claims: dict[str, Claim] = {}
        self._loaded: set[str] = set()
        self._modules: list[str] = []

    def add(self, claim: Claim) -> None:
        """Register one claim (its ID must be new).

        Parameters
        ----------
        claim : Claim
            The claim (or :class:`ComputedClaim`) to add under ``claim.id``.

        Raises
        ------
        ValueError
            If a claim with the same ID is already registered.
        """
        if claim.id in self._claims:
            raise ValueError(f"duplicate claim ID {claim.id}")
        self._claims[claim.id] = claim

    def load(self, models: bool = True) -> None:
        """Import the claim modules (the papers' first; ``models``: the model claims too).

        Modules already imported are skipped; a module whose import fails is imported
        again (and raises again) at the next call.

        Parameters
        ----------
        models : bool, default True
            Also import :data:`_MODEL_MODULES` (the ``MODEL:...`` claims, which derive
            every built-in model variant).
        """
        if not self._modules:
            names = sorted(m.name for m in pkgutil.iter_modules(__path__))
            self._modules = sorted(
                (n for n in names if n != "notation"), key=lambda n: n in _MODEL_MODULES
            )
        for name in self._modules:
            if name in self._loaded or (name in _MODEL_MODULES and not models):
                continue
            self._loaded.add(name)  # before the import: a module may read the registry
            try:
                importlib.import_module(f"{__name__}.{name}")
            except BaseException:
                self._loaded.discard(name)  # the next lookup raises the same error again
                raise

    def __getitem__(self, claim_id: str) -> Claim:
        self.load(models=claim_id.startswith(_MODEL_PREFIX))
        try:
            return self._claims[claim_id]
        except KeyError:
            raise KeyError(
                f"no claim {claim_id!r} is registered; IDs look like 'BKM12-4', 'K01-2.2', "
                "'BKM12-4/control-rho=1' (select_claims() lists them)"
            ) from None

    def __contains__(self, claim_id: object) -> bool:
        self.load(models=isinstance(claim_id, str) and claim_id.startswith(_MODEL_PREFIX))
        return claim_id in self._claims

    def __iter__(self) -> Iterator[str]:
        self.load()
        return iter(self._claims)

    def __len__(self) -> int:
        self.load()
        return len(self._claims)

    def __repr__(self) -> str:
        return f"<ClaimRegistry: {len(self._claims)} claims loaded>"


REGISTRY = ClaimRegistry()


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
    """
    for claim in claims:
        REGISTRY.add(claim)
    return claims


def _may_match_model_claims(pattern: str) -> bool:
    """Whether a glob may match a ``MODEL:`` ID: its literal head (up to the first
    wildcard) and ``MODEL:`` are prefixes of one another."""
    head = pattern
    for wildcard in "*?[":
        head = head.split(wildcard, 1)[0]
    return _MODEL_PREFIX.startswith(head) or head.startswith(_MODEL_PREFIX)


def select_claims(patterns: str | Iterable[str] | None = None) -> list[Claim]:
    """Claims whose ID matches any of the glob patterns (comma-separated), in order.

    Parameters
    ----------
    patterns : str or iterable of str, optional
        Globs over claim IDs (``"BKM12-*,K01-2.2"``); none or empty: every claim.

    Returns
    -------
    list of Claim
        In registration order. An empty selection is an error for the caller to report
        (see the CLI).
    """
    if patterns is None or patterns == "":
        REGISTRY.load()
        return list(REGISTRY.values())
    if isinstance(patterns, str):
        patterns = [p.strip() for p in patterns.split(",") if p.strip()]
    patterns = list(patterns)
    REGISTRY.load(models=any(_may_match_model_claims(p) for p in patterns))
    return [
        c for c in REGISTRY._claims.values() if any(fnmatch.fnmatchcase(c.id, p) for p in patterns)
    ]
