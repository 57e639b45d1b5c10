"""Checking claims: the Verdict object and the runner."""

from __future__ import annotations

import multiprocessing
import os
import time
from collections.abc import Iterable, Iterator
from dataclasses import asdict, dataclass

from .claims import Claim
from .identity import Domain, decide

__all__ = ["Verdict", "check_claim", "check_claims", "iter_verdicts", "default_jobs"]


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


def default_jobs() -> int:
    """Worker processes for a verification: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover  (not Linux)
        return max(1, os.cpu_count() or 1)


def _check_by_id(task: tuple[int, str, str]) -> tuple[int, Verdict]:
    from .claims import REGISTRY, select_claims

    index, claim_id, method = task
    select_claims()  # a spawned worker loads the registry; a forked one has it
    return index, check_claim(REGISTRY[claim_id], method=method)


def iter_verdicts(
    claims: Iterable[Claim], method: str = "auto", jobs: int = 1
) -> Iterator[Verdict]:
    """Check claims, yielding the verdicts in the order of ``claims``.

    Parameters
    ----------
    claims : iterable of Claim
        Registered claims (workers look them up by ID).
    method : {"auto", "symbolic", "exact-sampled", "numeric"}
    jobs : int
        Worker processes. With more than one, the claims are decided in parallel (each
        worker derives the models it needs once); a verdict is the same whichever process
        decides it (the sampler is seeded).
    """
    claims = list(claims)
    if jobs <= 1 or len(claims) <= 1:
        for c in claims:
            yield check_claim(c, method=method)
        return
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    tasks = [(i, c.id, method) for i, c in enumerate(claims)]
    done: dict[int, Verdict] = {}
    nxt = 0
    with ctx.Pool(processes=min(jobs, len(claims))) as pool:
        for index, verdict in pool.imap_unordered(_check_by_id, tasks, chunksize=1):
            done[index] = verdict
            while nxt in done:
                yield done.pop(nxt)
                nxt += 1


def check_claims(claims: Iterable[Claim], method: str = "auto", jobs: int = 1) -> list[Verdict]:
    """All verdicts of :func:`iter_verdicts`, as a list."""
    return list(iter_verdicts(claims, method=method, jobs=jobs))
