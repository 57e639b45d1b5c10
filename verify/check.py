"""``chaplygin.check``: decide claims from Python (the API behind ``chaplygin verify``)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from ..derive.errors import UserInputError
from .claims import select_claims
from .verdict import Verdict, check_claim, check_claims

__all__ = ["check"]

_GLOB = set("*?[")


def check(
    claims: str | Iterable[str],
    *,
    method: str = "auto",
    jobs: int = 1,
    timeout: float | None = None,
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
    jobs : int
        Worker processes; 1 decides in this process (a check that hangs then blocks).
    timeout : float, optional
        Seconds per claim (``jobs > 1`` only: a claim past it gets the verdict ``timeout``).

    Returns
    -------
    Verdict or list of Verdict

    Raises
    ------
    UserInputError
        ``claims`` neither text nor a list of text, no claim matches, an unknown method,
        ``jobs < 1`` or a timeout that is not a positive number.

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
    if not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 1:
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
    if jobs == 1:
        return [check_claim(c, method=method) for c in selected]
    return check_claims(selected, method=method, jobs=jobs, timeout=timeout)
