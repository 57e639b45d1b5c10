"""How the study times a call: enough runs that a short one is not the machine's noise
(:data:`SHORT_RUN_BUDGET_S`), the same for our rows and the peers'; and which peers are
installed."""

from __future__ import annotations

import importlib.util
import statistics
from collections.abc import Callable

__all__ = [
    "SHORT_RUN_BUDGET_S",
    "SHORT_RUNS_MAX",
    "median_run",
    "peers_available",
    "run_count",
    "timed_runs",
]
# --------------------------------------------------------------------------- measuring


#: Runs shorter than this in all are repeated until their total reaches it (at most
#: :data:`SHORT_RUNS_MAX` runs): a median of 5 calls of 10 us is mostly the machine's noise.
#: Applied alike to our rows and the peers'.
SHORT_RUN_BUDGET_S = 0.05
SHORT_RUNS_MAX = 500


def run_count(first_s: float, repeats: int) -> int:
    """How many runs to time when one takes ``first_s`` (at least ``repeats``; exactly one
    when one is asked for).

    Parameters
    ----------
    first_s : float
    repeats : int

    Returns
    -------
    int
    """
    if first_s <= 0 or repeats <= 1:  # one run asked for (--quick, --repeats 1): one run
        return repeats
    return max(repeats, min(SHORT_RUNS_MAX, int(SHORT_RUN_BUDGET_S / first_s)))


def timed_runs(fn: Callable[[], object], repeats: int) -> tuple[list[float], object]:
    """The wall times of ``fn()`` (its set-up outside: ``fn`` times itself and returns
    ``(seconds, value)``), as many runs as :func:`run_count` says; and the last value.

    Parameters
    ----------
    fn : callable
    repeats : int

    Returns
    -------
    (list of float, object)
    """
    wall, last = fn()
    times = [wall]
    for _ in range(run_count(wall, repeats) - 1):
        wall, last = fn()
        times.append(wall)
    return times, last


def median_run(fn: Callable[[], tuple[float, object]], repeats: int) -> tuple[float, object, int]:
    """The median of :func:`timed_runs`, the last value and the number of runs.

    Parameters
    ----------
    fn : callable
    repeats : int

    Returns
    -------
    (float, object, int)
    """
    times, last = timed_runs(fn, repeats)
    return statistics.median(times), last, len(times)


def peers_available() -> dict[str, bool]:
    """Whether the optional peers (``pip install chaplygin[peers]``) are importable.

    Returns
    -------
    dict of str to bool
        ``{"heyoka": ..., "jitcode": ...}``.
    """
    return {name: importlib.util.find_spec(name) is not None for name in ("heyoka", "jitcode")}
