"""The evidence of many orbits at once: every orbit's status and integral drifts, from arrays.

:meth:`~chaplygin.numerics.integrators.base.Integrator._result` gives one orbit its evidence:
the outputs must be finite (else status -1), and every first integral's drift over the outputs
(relative, or absolute where the integral starts below the precision's ``zero``) must be
finite (else status -5). For a run on the C backend with at most
:data:`~chaplygin.numerics.integrators.base._POINTWISE_COMPILED` outputs the integrals are the
compiled model's, point by point. :func:`ensemble_evidence` computes the same for ``N``
orbits at once: the compiled integrals of all orbits at one output time in one call of the
model's batch routine (``integrals_many``: the same compiled function, called once per state
with its orbit's parameters, so the same bits), the largest change over each orbit's own
outputs with NaN kept (as the point-by-point loop keeps it), the same quotient. An orbit with
more outputs than that, or none, gets ``_result``'s own evidence through ``single`` (so every
orbit's numbers are ``integrate()``'s, bit for bit).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from .code import ModelCode
from .integrators.base import _POINTWISE_COMPILED

__all__ = ["ensemble_evidence"]


def ensemble_evidence(code: ModelCode, compiled: Any, t: np.ndarray, y: np.ndarray,
                      done: np.ndarray, status: np.ndarray, params: np.ndarray,
                      zero: float, single: Callable[[int], Any]) -> tuple:  # fmt: skip
    """Every orbit's status and drifts, as its ``IntegrationResult`` would have them.

    Parameters
    ----------
    code : ModelCode
    compiled : CompiledModel
        The compiled model (double, C backend).
    t : ndarray, shape (m,)
        The output times.
    y : ndarray, shape (N, n_state, m)
        The outputs (orbit ``j``'s first ``done[j]`` are its own).
    done : ndarray of int, shape (N,)
    status : ndarray of int, shape (N,)
        The integrator's status (before the evidence).
    params : ndarray, shape (N, n_param)
        Each orbit's parameters (rows).
    zero : float
        The precision's ``zero`` (an integral starting below it drifts absolutely).
    single : callable
        ``j -> IntegrationResult`` of orbit ``j`` (its evidence computed alone).

    Returns
    -------
    (ndarray of int, dict of str to ndarray)
        The status after the evidence, and the drift of every integral per orbit.
    """
    N, names = len(y), code.integral_names
    m = int(done[0]) if N else 0
    if 1 <= m <= _POINTWISE_COMPILED and bool((done == m).all()):
        return _every_output(compiled, t, y, m, status, params, zero, names)
    status = np.array(status, dtype=np.int64)
    drift: dict[str, np.ndarray] = {}
    alone = (done < 1) | (done > _POINTWISE_COMPILED)
    rows = np.flatnonzero(~alone)
    if len(rows):
        m = int(done[rows].max())
        V = np.empty((len(rows), m, len(names)))
        P = params[rows].T
        for k in range(m):  # the compiled integrals of every orbit at output k
            V[:, k, :] = compiled.integrals_many(float(t[k]), y[rows, :, k].T, P).T
        with np.errstate(invalid="ignore"):
            upto = np.arange(m)[None, :] < done[rows][:, None]
            change = np.where(upto[:, :, None], np.abs(V - V[:, :1, :]), 0.0).max(axis=1)
            finite = np.where(upto[:, None, :], np.isfinite(y[rows, :, :m]), True).all(
                axis=(1, 2)
            )
            ref = np.abs(V[:, 0, :])
            rel = np.where(ref <= zero, change, change / np.where(ref <= zero, 1.0, ref))
        code_rows = np.where(finite, status[rows], -1)
        bad = ~np.isfinite(rel).all(axis=1)
        status[rows] = np.where(bad & (code_rows == 0), -5, code_rows)
        for i, name in enumerate(names):
            drift.setdefault(name, np.full(N, np.nan))[rows] = rel[:, i]
    for name in names:
        drift.setdefault(name, np.full(N, np.nan))
    for j in np.flatnonzero(alone):
        result = single(int(j))
        status[j] = result.status
        for name in names:
            drift[name][j] = result.drift.get(name, np.nan)
    return status, drift


def _every_output(compiled: Any, t: np.ndarray, y: np.ndarray, m: int, status: np.ndarray,
                  params: np.ndarray, zero: float, names: Any) -> tuple:  # fmt: skip
    """:func:`ensemble_evidence` where every orbit reached all its ``m`` outputs (the common
    case): the same numbers without masks, one integral per row (``(n_integrals, N)``, as the
    batch routine gives them), the largest change taken output by output (``np.maximum``
    keeps NaN as ``max`` does)."""
    P = params.T
    first = compiled.integrals_many(float(t[0]), y[:, :, 0].T, P)
    with np.errstate(invalid="ignore"):
        change = np.abs(first - first)  # 0, or NaN where an integral starts not finite
        for k in range(1, m):  # the compiled integrals of every orbit at output k
            d = compiled.integrals_many(float(t[k]), y[:, :, k].T, P)
            d -= first
            np.maximum(change, np.abs(d, out=d), out=change)
        ref = np.abs(first)
        small = ref <= zero
        if small.any():  # an integral starting below zero: its absolute change
            rel = np.where(small, change, change / np.where(small, 1.0, ref))
        else:
            rel = change / ref
    finite = np.isfinite(y[:, :, :m]).all(axis=(1, 2))
    kept = np.isfinite(rel).all(axis=0)
    status = np.array(status, dtype=np.int64)
    if not (finite.all() and kept.all()):  # -1: outputs not finite; -5: a drift not finite
        status = np.where(finite, status, -1)
        status = np.where(~kept & (status == 0), -5, status)
    return status, dict(zip(names, rel, strict=True))
