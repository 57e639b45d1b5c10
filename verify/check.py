"""``chaplygin.check``: decide claims from Python (the API behind ``chaplygin verify``)."""

from __future__ import annotations

import sys
from collections.abc import Iterable, Mapping

from ..derive.errors import UserInputError
from .claims import select_claims
from .verdict import Verdict, check_claim, default_jobs, iter_verdicts

__all__ = ["check"]

_GLOB = set("*?[")


def check(
    claims: str | Iterable[str],
    *,
    method: str = "auto",
    jobs: int | None = None,
    timeout: float | None = None,
    progress: bool | None = None,
) -> Verdict | list[Verdict]:
    """Decide one claim, or a selection of claims, and return the verdicts.

    Parameters
    ----------
    claims : str or iterable of str
        One claim ID (``"BKM12-4"``: returns its :class:`Verdict`) or glob patterns, as a
        comma-separated string or an iterable (``"BKM12-*,K01-2.2"``: returns a list in the
        registry's order).
    method : {"auto", "symbolic", "exact-sampled", "numeric"}
        Force a cheaper method (as ``chaplygin verify --method``).
    jobs : int, optional
        Worker processes; 1 decides in this process (a check that hangs then blocks). The
        default: in an interactive session (a notebook, the REPL, ``python -c``) a selection
        runs in the verifier's pool as ``chaplygin verify`` does (one worker per CPU this
        process may use); in a script, in this process, since spawned workers re-import the
        script (a script asking for ``jobs > 1`` needs ``if __name__ == "__main__":``).
    timeout : float, optional
        Seconds per claim (``jobs > 1`` only: a claim past it gets the verdict ``timeout``).
    progress : bool, optional
        A progress bar of a selection's claims on stderr (tqdm); the default shows it when
        stderr is a terminal, ``False`` never.

    Returns
    -------
    Verdict or list of Verdict

    Raises
    ------
    UserInputError
        ``claims`` neither text nor a list of text, no claim matches, an unknown method,
        ``jobs < 1`` or a timeout that is not a positive number.

    Notes
    -----
    ``chaplygin.check("BKM12-4*")`` decides 18 claims (the claim and its controls); in the
    pool the families of claims run side by side.

    Examples
    --------
    >>> import chaplygin
    >>> chaplygin.check("BKM12-4").verdict  # doctest: +SKIP
    'proved'
    """
    if method not in ("auto", "symbolic", "exact-sampled", "numeric"):
        raise UserInputError(
            f"unknown method {method!r}; valid: auto, symbolic, exact-sampled, numeric"
        )
    if jobs is not None and (not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 1):
        raise UserInputError(f"jobs must be a positive integer, got {jobs!r}")
    if timeout is not None and (
        isinstance(timeout, bool)
        or not isinstance(timeout, int | float)
        or not 0 < timeout < float("inf")
    ):
        raise UserInputError(f"timeout must be a positive number of seconds, got {timeout!r}")
    if not isinstance(claims, str) and (
        isinstance(claims, bytes | Mapping) or not isinstance(claims, Iterable)
    ):
        raise UserInputError(
            f"claims must be a claim ID or pattern (text) or a list of them, got {claims!r}"
        )
    single = isinstance(claims, str) and "," not in claims and not (_GLOB & set(claims))
    if isinstance(claims, str):
        patterns = [p.strip() for p in claims.split(",") if p.strip()]
    else:
        patterns = [str(p).strip() for p in claims]
    if not patterns:
        raise UserInputError("no claim given: name an ID such as 'BKM12-4' or a pattern")
    selected = select_claims(patterns)
    if not selected:
        raise UserInputError(
            f"no claim matches {', '.join(patterns)}; chaplygin.claims() lists the claims "
            "(IDs as in FORMULAS.md, e.g. 'BKM12-4', 'K01-2.*')"
        )
    if single:
        return check_claim(selected[0], method=method)
    if jobs is None:
        jobs = default_jobs() if _interactive() else 1
    from tqdm import tqdm

    shown = sys.stderr.isatty() if progress is None else bool(progress)
    verdicts = []
    with tqdm(total=len(selected), desc="claims", unit="claim", file=sys.stderr,
              disable=not shown) as bar:  # fmt: skip
        for verdict in iter_verdicts(selected, method=method, jobs=jobs, timeout=timeout):
            verdicts.append(verdict)
            bar.set_postfix_str(f"{verdict.id}: {verdict.verdict}", refresh=False)
            bar.update()
    return verdicts


def _interactive() -> bool:
    """Whether the main module is no file (a notebook, the REPL, ``python -c``): spawned
    worker processes then have no script to re-import."""
    main = sys.modules.get("__main__")
    return getattr(main, "__file__", None) is None
