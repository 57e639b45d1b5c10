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
of the derived models) are loaded only when a lookup or a selection may need them. The claim
modules import :mod:`chaplygin.verify.claims.base` (what a claim is, and :func:`register`), never
this module, which imports them by name.
"""

from __future__ import annotations

import fnmatch
import importlib
import pkgutil
from collections.abc import Iterable, Iterator, Mapping

from .base import (
    CLAIMS,
    KINDS,
    VERDICT_OF_METHOD,
    Check,
    Claim,
    ClaimStore,
    Computed,
    ComputedClaim,
    register,
)

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


#: Modules of this package that register claims about our own models (loaded last and
#: only when needed: registering them derives every built-in model variant).
_MODEL_MODULES = ("model_invariants",)
_MODEL_PREFIX = "MODEL:"
#: Modules of this package that register no claims.
_NOT_CLAIMS = ("base", "notation")


class ClaimRegistry(Mapping[str, Claim]):
    """The registered claims by ID, in registration order; fills itself on first use.

    Reading it (``REGISTRY[id]``, ``id in REGISTRY``, iteration) imports the claim modules
    of this package, where registration happens. The claims of :data:`_MODEL_MODULES`
    (``MODEL:...``) are loaded only by a lookup of such an ID, by iteration or by a
    selection whose patterns may match one.

    Parameters
    ----------
    store : ClaimStore, optional
        Where the claims are kept (default: a new, empty one; :data:`REGISTRY` reads the one
        :func:`register` fills).
    """

    def __init__(self, store: ClaimStore | None = None) -> None:
        self._store = store if store is not None else ClaimStore()
        self._claims: dict[str, Claim] = self._store.claims
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
        self._store.add(claim)

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
                (n for n in names if n not in _NOT_CLAIMS), key=lambda n: n in _MODEL_MODULES
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


REGISTRY = ClaimRegistry(CLAIMS)


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
