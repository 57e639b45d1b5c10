"""Checking claims: the Verdict object and the runner."""

from __future__ import annotations

import faulthandler
import html
import multiprocessing
import multiprocessing.connection
import os
import time
import traceback
from collections.abc import Callable, Iterable, Iterator
from dataclasses import asdict, dataclass

from .chained import decide_along_flow
from .claims import REGISTRY, Claim, ComputedClaim
from .claims.base import PROVED_BY_COMPUTATION, Computed
from .identity import Domain, decide
from .latex import plain_to_latex

__all__ = [
    "Verdict",
    "check_claim",
    "check_claims",
    "iter_verdicts",
    "claim_families",
    "default_jobs",
    "registered_claim",
    "FAILURES",
]


#: Verdicts that are not decisions: the check raised, its worker died or ran out of time.
FAILURES = ("error", "timeout")


@dataclass
class Verdict:
    """Outcome of checking one claim.

    Attributes
    ----------
    id, statement, source, kind : str
        From the claim.
    verdict : str
        One of ``"proved"``, ``"proved by computation"``, ``"exact-sampled"``,
        ``"numeric"``, ``"refuted"``, ``"error"``, ``"timeout"``.
        ``"error"`` and ``"timeout"`` are not decisions: the check raised, its worker
        died or it ran out of time (the method says which); they are never ``ok``.
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
    expected_verdict : str, optional
        The verdict the claim must get (:meth:`Claim.expected_verdict`): ``"refuted"``
        for a claim expected to fail; ``"proved"``, or the method its check or the caller
        chose, for one that holds. Default: ``"refuted"`` or ``"proved"``.
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
    expected_verdict: str | None = None

    def __post_init__(self) -> None:
        if self.expected_verdict is None:
            self.expected_verdict = "refuted" if self.expected == "fails" else "proved"

    @property
    def problem(self) -> str:
        """Why the verdict is not the expected one (empty when it is).

        Strict: the verdict must be the expected one (a proof where a proof is expected,
        not a sampled or numeric check), a proof or an exact sampling has the residual
        ``0`` and a refutation carries its witness.
        """
        if self.verdict in FAILURES:
            return f"{self.verdict}: {self.method}"
        if self.verdict != self.expected_verdict:
            return f"{self.verdict}, expected {self.expected_verdict}"
        if self.verdict == "refuted" and not self.witness:
            return "refuted without a witness"
        if self.verdict in ("proved", "exact-sampled") and self.residual != "0":
            return f"{self.verdict} with the residual {self.residual} (not 0)"
        return ""

    @property
    def ok(self) -> bool:
        """True when the verdict is the expected one (see :attr:`problem`)."""
        return not self.problem

    @property
    def latex(self) -> str:
        """The claim's statement in LaTeX (the claim's own, or translated from the text)."""
        claim = REGISTRY.get(self.id)
        return (claim.latex if claim is not None else "") or plain_to_latex(self.statement)

    def to_json(self) -> dict[str, object]:
        """The fields as a JSON-ready dict, with ``ok`` (no ``witness`` when there is none).

        Returns
        -------
        dict of str to object
            ``dataclasses.asdict`` of the verdict plus ``"ok"``; the key ``"witness"``
            only when there is a witness.
        """
        out = asdict(self)
        out["ok"] = self.ok
        if out["witness"] is None:
            del out["witness"]
        return out

    def __repr__(self) -> str:
        mark = "" if self.ok else f" UNEXPECTED ({self.problem})"
        return f"<Verdict {self.id}: {self.verdict}{mark}, {self.seconds:.3g} s>"

    def _repr_latex_(self) -> str:
        ident = self.id.replace("_", r"\_")
        return rf"$\text{{{ident}}}:\ {self.latex}\quad\text{{({self.verdict})}}$"

    def _repr_html_(self) -> str:
        mark = "" if self.ok else f" <b>unexpected: {html.escape(self.problem)}</b>"
        evidence = f"residual {html.escape(str(self.residual))}"
        if self.witness:
            evidence += " at " + html.escape(
                ", ".join(f"{k} = {v}" for k, v in self.witness.items())
            )
        return (
            f"<p><b>{html.escape(self.id)}</b> ({html.escape(self.source)}): "
            f"${html.escape(self.latex)}$<br>{html.escape(self.verdict)}{mark}: "
            f"{html.escape(self.method)}; {evidence}; {self.seconds:.3g} s</p>"
        )


def _computed(claim: ComputedClaim) -> Computed:
    """The claim's computation. Where a proof by computation cannot enclose the flow (a long
    chaotic run, wrapping past the limit), nothing is decided: the verdict stays ``numeric``
    and the report says where the enclosure grew and how wide it got."""
    if not claim.rigorous:
        return claim.compute()
    from ..numerics.validated.lohner import EnclosureError

    try:
        return claim.compute()
    except EnclosureError as exc:
        values = {"why undecided": str(exc)}
        widths, times = exc.widths, exc.times
        if widths:
            k = max(range(len(widths)), key=widths.__getitem__)
            values["widest enclosure"] = f"{widths[k]:.3g} at t = {times[k]:.6g}"
        return Computed(
            error=float("nan"),
            bound=0.0,
            what=f"the enclosure blew up, so nothing is proved: {exc}",
            values=values,
            decided="undecided",
        )


def check_claim(claim: Claim, method: str = "auto", points: int = 8) -> Verdict:
    """Build the claim's model and residuals and decide them.

    Parameters
    ----------
    claim : Claim
        A :class:`ComputedClaim` runs its computation (no model is derived).
    method : {"auto", "symbolic", "exact-sampled", "numeric"}
    points : int
        Sample points for the sampled methods.

    Returns
    -------
    Verdict
        With the verdict the claim must get (:meth:`Claim.expected_verdict`).
    """
    if isinstance(claim, ComputedClaim):
        start = time.perf_counter()
        result = _computed(claim)
        holds = result.holds
        if result.decided is not None:
            verdict = {"proved": PROVED_BY_COMPUTATION, "refuted": "refuted"}.get(
                result.decided, "numeric"
            )
            how = f"computed in ball arithmetic ({result.decided}): {result.what}"
        else:
            verdict = "numeric" if holds else "refuted"
            how = f"computed: {result.what}; error {result.error:.3g}, bound {result.bound:.3g}"
        return _verdict(
            claim,
            verdict,
            how,
            time.perf_counter() - start,
            residual=f"{result.error:.6g}",
            witness=None if holds else dict(result.values),
        )
    model = claim.model()
    start = time.perf_counter()
    check = claim.build(model)
    expected_verdict = claim.expected_verdict(check, method)
    while True:
        if check.along_flow:  # through the auxiliaries: exact sampling whatever was asked
            outcome = decide_along_flow(model, check.exprs, points=min(points, 4))
            break
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
    return _verdict(
        claim,
        outcome.verdict,
        outcome.method,
        time.perf_counter() - start,
        residual=outcome.residual,
        witness=outcome.witness,
        expected_verdict=expected_verdict,
    )


def _verdict(
    claim: Claim,
    verdict: str,
    method: str,
    seconds: float,
    residual: str | None = None,
    witness: dict | None = None,
    expected_verdict: str | None = None,
) -> Verdict:
    """The verdict on ``claim`` (its ID, statement, source, kind and expectation copied)."""
    return Verdict(
        id=claim.id,
        statement=claim.statement,
        source=claim.source,
        kind=claim.kind,
        verdict=verdict,
        method=method,
        seconds=seconds,
        residual=residual,
        witness=witness,
        expected=claim.expected,
        expected_verdict=expected_verdict or claim.expected_verdict(),
    )


def default_jobs() -> int:
    """Worker processes for a verification: the CPUs this process may use.

    Returns
    -------
    int
        The size of the process's CPU affinity set (``os.cpu_count()`` where that is
        not available), at least 1.
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover  (not Linux)
        return max(1, os.cpu_count() or 1)


def _check_or_error(claim: Claim, method: str) -> Verdict:
    start = time.perf_counter()
    try:
        return check_claim(claim, method=method)
    except Exception as exc:  # a bug in one check must not hide the other verdicts
        detail = "".join(traceback.format_exception_only(exc)).strip()
        return _verdict(claim, "error", f"the check raised {detail}", time.perf_counter() - start)


def registered_claim(claim_id: str) -> Claim:
    """The registered claim with this ID (how worker processes find their claims).

    Parameters
    ----------
    claim_id : str

    Returns
    -------
    Claim
        From :data:`REGISTRY` (which loads the claim modules on first use).
    """
    return REGISTRY[claim_id]


def _worker(conn, method: str, lookup) -> None:  # pragma: no cover  (a child process)
    """Decide the claims the parent sends, one at a time, until it sends None."""
    faulthandler.enable()  # a crash in compiled code leaves a traceback on stderr
    while True:
        task = conn.recv()
        if task is None:
            return
        index, claim_id = task
        conn.send((index, _check_or_error(lookup(claim_id), method)))


class _Slot:
    """One worker process and the claim it is deciding."""

    def __init__(self, ctx, method: str, lookup):
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=_worker, args=(child, method, lookup), daemon=True)
        self.process.start()
        child.close()
        self.task: tuple[int, str] | None = None
        self.since = 0.0
        #: the claims of the family it is deciding that are still to come
        self.queue: list[tuple[int, str]] = []

    def send(self, task: tuple[int, str]) -> None:
        self.task, self.since = task, time.perf_counter()
        self.conn.send(task)

    def stop(self, kill: bool = False) -> None:
        if kill:
            self.process.kill()
        else:
            try:
                self.conn.send(None)
            except OSError:
                pass
        self.process.join(timeout=10)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()


def claim_families(claims: list[Claim]) -> list[list[tuple[int, str]]]:
    """The claims as families, ``(index, ID)`` lists in the order of their first claim: a
    claim with the part of its ID before the first ``/`` (``BM20-Lyap`` and
    ``BM20-Lyap/control-sign``). A worker process decides a whole family, so that a control
    finds the work its claim shares with it (a Groebner basis, a derived model, a run)
    already done in that process.

    Parameters
    ----------
    claims : list of Claim

    Returns
    -------
    list of list of (int, str)
    """
    families: dict[str, list[tuple[int, str]]] = {}
    for index, claim in enumerate(claims):
        families.setdefault(claim.id.split("/")[0], []).append((index, claim.id))
    return list(families.values())


def iter_verdicts(
    claims: Iterable[Claim],
    method: str = "auto",
    jobs: int = 1,
    timeout: float | None = None,
    lookup: Callable[[str], Claim] = registered_claim,
) -> Iterator[Verdict]:
    """Check claims, yielding the verdicts in the order of ``claims``.

    A check that raises gives the verdict ``"error"`` (with the exception) instead of
    stopping the run.

    Parameters
    ----------
    claims : iterable of Claim
        Registered claims (workers look them up by ID).
    method : {"auto", "symbolic", "exact-sampled", "numeric"}
    jobs : int
        Worker processes. With more than one, the claims are decided in parallel by
        fresh (spawned) processes, each deriving or loading the models it needs once, a
        family of claims (:func:`claim_families`: a claim and its controls) in one process; a
        verdict is the same whichever process decides it (the sampler is seeded).
    timeout : float, optional
        Seconds a single claim may take. With a timeout the claims are always decided
        in worker processes (one when ``jobs`` is 1): a worker that exceeds it is
        stopped and the claim gets the verdict ``"timeout"``; a worker that dies gives
        ``"error"`` with its exit code. The other claims go on in a new worker.
    lookup : callable, optional
        How a worker process finds a claim by its ID: a picklable function (default
        :func:`registered_claim`).

    Yields
    ------
    Verdict
        One per claim, in the order of ``claims`` (as soon as it and all before it are
        decided).
    """
    claims = list(claims)
    if (jobs <= 1 and timeout is None) or not claims:
        for c in claims:
            yield _check_or_error(c, method)
        return
    ctx = multiprocessing.get_context("spawn")  # no fork of a parent with locks or threads
    # the families with a proof in ball arithmetic (minutes each) are handed out first, so
    # that the short claims fill the other workers meanwhile; verdicts keep the claims' order
    families = claim_families(claims)
    heavy = [f for f in families if any(getattr(claims[i], "rigorous", False) for i, _ in f)]
    pending = (heavy + [f for f in families if f not in heavy])[::-1]
    slots = [_Slot(ctx, method, lookup) for _ in range(max(1, min(jobs, len(pending))))]
    done: dict[int, Verdict] = {}
    nxt = 0

    def send_next(slot: _Slot) -> None:
        """The slot's next claim: the rest of its family first, else a new family."""
        if not slot.queue and pending:
            slot.queue = pending.pop()
        if slot.queue:
            slot.send(slot.queue.pop(0))

    try:
        for slot in slots:
            send_next(slot)
        while nxt < len(claims):
            busy = [s for s in slots if s.task is not None]
            ready = multiprocessing.connection.wait(
                [s.conn for s in busy] + [s.process.sentinel for s in busy],
                timeout=None if timeout is None else 1.0,
            )
            for i, slot in enumerate(slots):
                if slot.task is None:
                    continue
                index, claim_id = slot.task
                claim = claims[index]
                elapsed = time.perf_counter() - slot.since
                result: Verdict | None = None
                replace = False
                if slot.conn in ready:
                    try:
                        _, result = slot.conn.recv()
                    except (EOFError, OSError):
                        result = None
                if result is None and (slot.conn in ready or slot.process.sentinel in ready):
                    slot.process.join(timeout=5)
                    code = slot.process.exitcode
                    result = _verdict(
                        claim, "error", f"its worker process died (exit code {code})", elapsed
                    )
                    replace = True
                elif result is None and timeout is not None and elapsed > timeout:
                    result = _verdict(
                        claim, "timeout", f"stopped after {timeout:g} s (--timeout)", elapsed
                    )
                    replace = True
                if result is None:
                    continue
                done[index] = result
                slot.task = None
                if replace:
                    slot.stop(kill=True)
                    queue = slot.queue
                    slot = slots[i] = _Slot(ctx, method, lookup)
                    slot.queue = queue
                send_next(slot)
            while nxt in done:
                yield done.pop(nxt)
                nxt += 1
    finally:
        for slot in slots:
            slot.stop(kill=slot.task is not None)


def check_claims(
    claims: Iterable[Claim], method: str = "auto", jobs: int = 1, timeout: float | None = None
) -> list[Verdict]:
    """All verdicts of :func:`iter_verdicts`, as a list.

    Parameters
    ----------
    claims : iterable of Claim
        Registered claims.
    method : {"auto", "symbolic", "exact-sampled", "numeric"}
        How to decide them (see :func:`iter_verdicts`).
    jobs : int
        Worker processes.
    timeout : float, optional
        Seconds a single claim may take (see :func:`iter_verdicts`).

    Returns
    -------
    list of Verdict
        One per claim, in the order of ``claims``.
    """
    return list(iter_verdicts(claims, method=method, jobs=jobs, timeout=timeout))
