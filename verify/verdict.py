"""Checking claims: the Verdict object and the runner."""

from __future__ import annotations

import time
from collections.abc import Iterable
from dataclasses import asdict, dataclass

from .claims import Claim
from .identity import Domain, decide

__all__ = ["Verdict", "check_claim", "check_claims"]


@dataclass
class Verdict:
    """Outcome of checking one claim.

    Attributes
    ----------
    id, statement, source, kind : str
        From the claim.
    verdict : {"proved", "exact-sampled", "numeric", "refuted"}
    method : str
        How it was decided.
    seconds : float
        Wall time of the check, derivation of the model excluded.
    residual : str or None
        ``"0"`` for a proof; the value at the witness for a refutation; the largest
        scaled residual for ``numeric``.
    witness : dict or None
        Exact point (``name -> rational``) where a refuted claim fails.
    expected : {"holds", "fails"}
    """

    id: str
    statement: str
    source: str
    kind: str
    verdict: str
    method: str
    seconds: float
    residual: str | None
    witness: dict | None
    expected: str

    @property
    def ok(self) -> bool:
        """True when the verdict is the expected one (a control must be refuted)."""
        refuted = self.verdict == "refuted"
        return refuted if self.expected == "fails" else not refuted

    def to_json(self) -> dict:
        out = asdict(self)
        out["ok"] = self.ok
        if out["witness"] is None:
            del out["witness"]
        return out


def check_claim(claim: Claim, method: str = "auto", points: int = 8) -> Verdict:
    """Build the claim's model and residuals and decide them.

    Parameters
    ----------
    claim : Claim
    method : {"auto", "symbolic", "exact-sampled", "numeric"}
    points : int
        Sample points for the sampled methods.
    """
    model = claim.model()
    start = time.perf_counter()
    check = claim.build(model)
    while True:
        domain = Domain(
            model,
            free=check.free,
            relations=check.on,
            model_relations=not check.everywhere,
        )
        chosen = check.method if method == "auto" else method
        outcome = decide(check.exprs, domain, method=chosen, points=points)
        if outcome.verdict != "refuted" or check.fallback is None:
            break
        check = check.fallback
    if check.note:
        outcome.method += f" ({check.note})"
    return Verdict(
        id=claim.id,
        statement=claim.statement,
        source=claim.source,
        kind=claim.kind,
        verdict=outcome.verdict,
        method=outcome.method,
        seconds=time.perf_counter() - start,
        residual=outcome.residual,
        witness=outcome.witness,
        expected=claim.expected,
    )


def check_claims(claims: Iterable[Claim], method: str = "auto") -> list[Verdict]:
    return [check_claim(c, method=method) for c in claims]
