"""How long the main job takes: ``chaplygin verify`` as a user runs it, in its own process
(issue 26's row: <= 60 s warm on 2 cores, <= 3 minutes from a fresh clone)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

from ..derive.errors import ComputationError

__all__ = ["verify_time"]


def verify_time(claims: str | None = None, jobs: int | None = None) -> dict[str, object]:
    """Wall time of ``chaplygin verify --json`` (all claims, or ``claims``) in a fresh process
    with this machine's caches as they are (warm after a first run), and what it decided.

    Parameters
    ----------
    claims : str, optional
        ``--claims`` globs (default: every claim).
    jobs : int, optional
        ``--jobs`` (default: the command's, the CPUs available).

    Returns
    -------
    dict
        ``wall_s`` (the process, start-up included), ``checking_s`` (the sum of the claims'
        own times), ``claims``, the count of each verdict, ``unexpected`` and the load
        average before and after.

    Raises
    ------
    ComputationError
        The command failed (exit status other than 0 or 1, or output that is not its JSON).
    """
    argv = [sys.executable, "-m", "chaplygin.verify.cli", "verify", "--json"]
    if claims:
        argv += ["--claims", claims]
    if jobs:
        argv += ["--jobs", str(int(jobs))]
    load_before = os.getloadavg()[0]
    start = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    try:
        rows = json.loads(done.stdout)
    except json.JSONDecodeError:
        rows = None
    if done.returncode not in (0, 1) or not isinstance(rows, list):
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise ComputationError(f"chaplygin verify failed (exit {done.returncode}): {last}")
    counts: dict[str, int] = {}
    for row in rows:
        counts[row["verdict"]] = counts.get(row["verdict"], 0) + 1
    return {
        "wall_s": wall,
        "checking_s": float(sum(float(row["seconds"]) for row in rows)),
        "claims": len(rows),
        "verdicts": counts,
        "unexpected": sum(1 for row in rows if not row["ok"]),
        "load_before": load_before,
        "load_after": os.getloadavg()[0],
    }
