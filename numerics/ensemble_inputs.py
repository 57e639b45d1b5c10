"""Many double-precision starts read at once (:func:`~chaplygin.numerics.ensemble.integrate_many`).

``integrate`` reads and checks one start in Python: every number through the safe parser,
the phase-space constraints at 30 digits, the right-hand side and the integrals finite. For
``N`` starts given as numbers (an array, or lists of floats and integers) in double precision
the same checks run here on all of them at once, on the model's numpy code (its routines take
a column per start), and a start that passes gets the problem of the first start with its own
numbers: the floats ``integrate`` would read (a float is its own double; an integer is exact).

The unit vectors of the model's geometry (``gamma``) are renormalised as ``integrate`` does it
-- ``x/|x|`` at the guard precision (30 digits), then rounded once to double -- by
:func:`unit_rows`: ``x/|x|`` in double-double (Dekker's exact products, no FMA: the same bits
everywhere), within about ``2^-100`` of the exact quotient, as the 30-digit one is; where the
double-double value lies within ``2^-95`` of a point halfway between two doubles the two
roundings could differ, and that start goes to ``integrate``'s route.

A start is accepted here only with a margin: every constraint within a quarter of
:data:`~chaplygin.numerics.inputs.UNIT_TOLERANCE` of its scale (the numpy value differs from
the 30-digit one by a few units of the last place of the scale, far below that margin), every
value of the right-hand side and of the integrals finite and below ``1e300``. Any other start
-- a text, a mapping, a constraint near its tolerance, a model with invariant relations (their
check projects at 30 digits) -- is read by ``integrate``'s own route, which accepts it or says
what is wrong with it. So what is accepted here is accepted there, and the integration is the
same.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .code import ModelCode
from .inputs import UNIT_TOLERANCE

__all__ = ["ReadStarts", "numeric_rows", "read_starts", "unit_rows"]

#: Largest magnitude of a right-hand side or integral value accepted here.
FINITE_BOUND = 1e300


def numeric_rows(rows: Sequence[Any] | None, width: int) -> np.ndarray | None:
    """``rows`` as an ``(N, width)`` float64 array when every entry is a real number (float,
    integer, numpy number; no text, no bool), else None.

    Parameters
    ----------
    rows : sequence of sequences, or None
    width : int

    Returns
    -------
    ndarray or None
    """
    if rows is None:
        return None
    if isinstance(rows, np.ndarray):
        if rows.ndim != 2 or rows.shape[1] != width or rows.dtype.kind not in "fi":
            return None
        return rows.astype(np.float64)
    if set(map(type, rows)) <= {list, tuple} and set(map(len, rows)) == {width}:
        # lists of Python numbers (the common case) checked in C-speed passes
        if set(map(type, itertools.chain.from_iterable(rows))) <= {float, int}:
            try:
                return np.array(rows, dtype=np.float64)
            except OverflowError:  # an integer beyond the doubles: integrate's route says so
                return None
    for row in rows:
        if isinstance(row, np.ndarray):
            if row.dtype.kind not in "fi" or row.shape != (width,):
                return None
            continue
        if isinstance(row, str) or not isinstance(row, Sequence) or len(row) != width:
            return None
        if not all(type(v) in (float, int) or isinstance(v, np.floating | np.integer)
                   for v in row):  # fmt: skip
            return None
    try:
        return np.array(rows, dtype=np.float64)
    except OverflowError:
        return None


@dataclass
class ReadStarts:
    """Starts read at once: the rows ``integrate`` would read, and which passed.

    Attributes
    ----------
    first : Problem
        The first start's problem (read by ``integrate``'s route).
    Y : ndarray, shape (N, n_state)
        The starts, unit vectors renormalised (where ``ok``).
    P : ndarray, shape (N, n_param), or None
        Each start's parameters; None: the first problem's for all.
    ok : ndarray of bool, shape (N,)
        Which starts passed the checks with their margin (the others: ``integrate``'s route).
    """

    first: Any
    Y: np.ndarray
    P: np.ndarray | None
    ok: np.ndarray

    def problem(self, j: int) -> Any:
        """Start ``j``'s problem (``ok[j]`` must hold): the first's with its own numbers.

        Parameters
        ----------
        j : int

        Returns
        -------
        Problem
        """
        y = [float(v) for v in self.Y[j]]
        p = self.first.params if self.P is None else [float(v) for v in self.P[j]]
        return dataclasses.replace(self.first, y0=y, params=p)


def read_starts(code: ModelCode, first: Any, Y: np.ndarray, P: np.ndarray | None,
                compiled: Any = None) -> ReadStarts:  # fmt: skip
    """The starts ``Y`` (rows) with parameters ``P`` (rows; None: the first problem's) read at
    once: which pass the checks with their margin (see the module); the others must be read
    by ``integrate``'s route.

    Parameters
    ----------
    code : ModelCode
    first : Problem
        The first start's problem, read and checked by ``integrate``'s route (double).
    Y : ndarray, shape (N, n_state)
    P : ndarray, shape (N, n_param), or None
    compiled : CompiledModel, optional
        The compiled model: the right-hand side and the integrals by its batch routines
        (else the numpy module's).

    Returns
    -------
    ReadStarts
    """
    N = len(Y)
    none = ReadStarts(first, Y, P, np.zeros(N, dtype=bool))
    if code.relation_names or (P is not None and len(P) != N):
        return none
    if code.completion or any(kind != "unit_vector" for kind, _ in code.geometry):
        return none  # frames and completed groups: integrate's route
    Y, ok = Y.copy(), np.ones(N, dtype=bool)
    for _, (group,) in code.geometry:
        index = [code.state.index(s) for s in code.state_groups[group]]
        Y[:, index], fine = unit_rows(Y[:, index])
        ok &= fine
    t0 = float(first.t_span[0])
    params = [float(v) for v in first.params] if P is None else list(P.T)
    ok &= np.isfinite(Y).all(axis=1)
    if P is not None:
        ok &= np.isfinite(P).all(axis=1)
    with np.errstate(all="ignore"):
        Z = np.where(ok[:, None], Y, 0.0).T  # a column per start (bad ones zeroed)
        columns = list(Z)
        if code.constraint_names:
            k = len(code.constraint_names)
            values = _stacked(code.numpy.constraints(t0, columns, params), N)
            scale = np.maximum(np.abs(values[k:]), 1.0)
            ok &= (np.abs(values[:k]) <= 0.25 * UNIT_TOLERANCE * scale).all(axis=0)
        if compiled is not None:  # the compiled batch routines (the margin covers roundings)
            PZ = np.asarray(params, dtype=float) if P is None else np.ascontiguousarray(P.T)
            outs = [compiled.rhs_many(t0, Z, PZ), compiled.integrals_many(t0, Z, PZ)]
        else:
            outs = [_stacked(routine(t0, columns, params), N)
                    for routine in (code.numpy.rhs, code.numpy.integrals)]  # fmt: skip
        for out in outs:
            ok &= (np.abs(out) < FINITE_BOUND).all(axis=0)
    return ReadStarts(first, Y, P, ok)


def _stacked(values: Sequence[Any], N: int) -> np.ndarray:
    """A routine's outputs (arrays over the starts, or constants) as an ``(m, N)`` array."""
    return np.array([np.broadcast_to(np.asarray(v, dtype=float), (N,)) for v in values])


#: Veltkamp's splitter for double precision (2^27 + 1).
_SPLIT = 134217729.0

#: How close (relative) to a point halfway between two doubles a double-double quotient may be
#: before its rounding is left to ``integrate``'s 30-digit route (both are within 2^-100).
_TIE_MARGIN = 2.0**-95


def _split(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    c = _SPLIT * a
    hi = c - (c - a)
    return hi, a - hi


def _two_prod(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``a b = p + e`` exactly (Dekker), without a fused multiply-add."""
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def unit_rows(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every row ``x`` of ``X`` as ``x/|x|`` rounded to double, as ``integrate`` renormalises
    a unit vector (see the module), and which rows that is certain for: ``|x|`` within
    :data:`~chaplygin.numerics.inputs.UNIT_TOLERANCE` of 1 with a margin, every quotient away
    from a rounding tie.

    Parameters
    ----------
    X : ndarray, shape (N, k)

    Returns
    -------
    (ndarray, ndarray of bool)
        The rows renormalised (where certain; else as given), and where that is certain.
    """
    with np.errstate(all="ignore"):
        P, E = _two_prod(X, X)  # every component's square, exactly, at once
        sh, sl = np.zeros(len(X)), np.zeros(len(X))
        for j in range(X.shape[1]):  # the sum of squares in double-double, in column order
            s, t = _two_sum(sh, P[:, j])
            sh, sl = _two_sum(s, t + sl + E[:, j])
        r = np.sqrt(sh)  # |x| in double-double: one Newton correction of the square root
        p, e = _two_prod(r, r)
        nh, nl = _two_sum(r, (((sh - p) - e) + sl) / (2 * r))
        ok = np.isfinite(nh) & (np.abs(nh - 1) <= UNIT_TOLERANCE * (1 - 1e-6))
        nh, nl = nh[:, None], nl[:, None]
        q1 = X / nh  # every quotient at once, with its double-double correction
        p, e = _two_prod(q1, np.broadcast_to(nh, X.shape))
        qh, ql = _two_sum(q1, (((X - p) - e) - q1 * nl) / nh)
        half = np.abs(np.nextafter(qh, np.where(ql >= 0, np.inf, -np.inf)) - qh) / 2
        exact_zero = X == 0  # 0/|x| is 0 in both routes
        fine = exact_zero | ((np.abs(np.abs(ql) - half) > _TIE_MARGIN * np.abs(qh))
                             & (np.abs(ql) <= half))  # fmt: skip
        ok &= fine.all(axis=1)
        out = np.where(ok[:, None], qh, X)
    return out, ok
