"""A Taylor-series integrator at any precision, recorded from a model's generated code.

The generated mpmath right-hand side (``generated/<variant>_mpmath.py``, plain ``+ - * /``
and integer powers for the ball) is run once on tracer objects: this records a tape of
elementary operations (parameters fold to constants). The Taylor coefficients of the
solution are then computed order by order with the automatic-differentiation recurrences
(product: Cauchy sum; quotient: ``q_k = (a_k - sum_{j<k} q_j b_{k-j})/b_0``), in
``gmpy2.mpfr`` arithmetic at the requested number of bits (gmpy2's own context; mpmath's
precision is not touched). Order and step follow Jorba & Zou (2005): ``N = ceil(-ln(eps)/2)
+ 1``, ``h = rho/e^2`` with ``rho = min_{k=N-1,N} (max(1, |y|)/|y_k|)^(1/k)``.

This is a purpose-built integrator for the separatrix (``numerics/separatrix.py``); a generic
generated Taylor integrator (issue 5 §1) can replace it behind :func:`taylor_flow`.
"""

from __future__ import annotations

import math
import operator
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import gmpy2

__all__ = ["Tape", "record", "TaylorFlowResult", "taylor_flow"]

_mul = operator.mul


class _Tracer:
    __slots__ = ("tape", "idx")

    def __init__(self, tape: Tape, idx: int):
        self.tape, self.idx = tape, idx

    def __add__(self, o):
        return self.tape.binary("add", self, o)

    def __radd__(self, o):
        return self.tape.binary("add", o, self)

    def __sub__(self, o):
        return self.tape.binary("sub", self, o)

    def __rsub__(self, o):
        return self.tape.binary("sub", o, self)

    def __mul__(self, o):
        return self.tape.binary("mul", self, o)

    def __rmul__(self, o):
        return self.tape.binary("mul", o, self)

    def __truediv__(self, o):
        return self.tape.binary("div", self, o)

    def __rtruediv__(self, o):
        return self.tape.binary("div", o, self)

    def __neg__(self):
        return self.tape.binary("mul", -1, self)

    def __pos__(self):
        return self

    def __pow__(self, n):
        if not isinstance(n, int):
            raise TypeError("the jet tape supports integer powers only")
        if n == 0:
            return 1
        if n < 0:
            return self.tape.binary("div", 1, self ** (-n))
        out = None
        base = self
        while n:
            if n & 1:
                out = base if out is None else out * base
            n >>= 1
            if n:
                base = self.tape.unary_sqr(base)
        return out


class Tape:
    """Elementary operations of a right-hand side on ``n`` state variables.

    Node kinds: ``var`` (state ``i``), ``add``, ``sub``, ``mul``, ``div``, ``sqr`` on two
    nodes, and ``cadd``, ``csub``, ``rsub``, ``cmul``, ``cdiv`` with a constant.
    """

    def __init__(self, n: int):
        self.ops: list[tuple] = [("var", i) for i in range(n)]
        self.n = n
        self.outputs: list = []

    def _push(self, op) -> _Tracer:
        self.ops.append(op)
        return _Tracer(self, len(self.ops) - 1)

    def unary_sqr(self, a: _Tracer) -> _Tracer:
        return self._push(("sqr", a.idx))

    def binary(self, kind, a, b):
        ta, tb = isinstance(a, _Tracer), isinstance(b, _Tracer)
        if not ta and not tb:
            return {"add": operator.add, "sub": operator.sub, "mul": _mul, "div": operator.truediv}[
                kind
            ](a, b)
        if ta and tb:
            if kind == "mul" and a.idx == b.idx:
                return self._push(("sqr", a.idx))
            return self._push((kind, a.idx, b.idx))
        c = gmpy2.mpfr(b if ta else a)
        node = a.idx if ta else b.idx
        if kind == "add":
            return self._push(("cadd", node, c))
        if kind == "sub":
            return self._push(("cadd", node, -c) if ta else ("rsub", node, c))
        if kind == "mul":
            return self._push(("cmul", node, c))
        # division
        return self._push(("cmul", node, 1 / c) if ta else ("cdiv", node, c))


def record(rhs: Callable, n: int, params: Sequence) -> Tape:
    """Run ``rhs(t, y, p)`` on tracers; ``params`` are numbers (folded into constants)."""
    tape = Tape(n)
    out = rhs(0, [_Tracer(tape, i) for i in range(n)], list(params))
    for o in out:
        tape.outputs.append(("node", o.idx) if isinstance(o, _Tracer) else ("const", o))
    return tape


def _coefficient(tape: Tape, C: list, k: int) -> None:
    """Order ``k`` of every non-variable node (orders < k and the variables known)."""
    for i in range(tape.n, len(tape.ops)):
        op = tape.ops[i]
        kind = op[0]
        if kind == "mul":
            A, B = C[op[1]], C[op[2]]
            v = sum(map(_mul, A[: k + 1], B[k::-1]))
        elif kind == "cmul":
            v = op[2] * C[op[1]][k]
        elif kind == "add":
            v = C[op[1]][k] + C[op[2]][k]
        elif kind == "sub":
            v = C[op[1]][k] - C[op[2]][k]
        elif kind == "sqr":
            A = C[op[1]]
            h = (k + 1) // 2
            v = 2 * sum(map(_mul, A[:h], A[k : k - h : -1])) if h else 0
            if k % 2 == 0:
                v = v + A[k // 2] ** 2
        elif kind == "div":
            A, B, Q = C[op[1]], C[op[2]], C[i]
            s = A[k] - sum(map(_mul, Q[:k], B[k:0:-1])) if k else A[0]
            v = s / B[0]
        elif kind == "cadd":
            v = C[op[1]][k] + op[2] if k == 0 else C[op[1]][k]
        elif kind == "rsub":
            v = op[2] - C[op[1]][0] if k == 0 else -C[op[1]][k]
        elif kind == "cdiv":
            B, Q = C[op[1]], C[i]
            s = op[2] - sum(map(_mul, Q[:k], B[k:0:-1])) if k else op[2]
            v = s / B[0]
        else:  # pragma: no cover
            raise ValueError(kind)
        C[i].append(v)


def _series(tape: Tape, y0: list, order: int) -> list[list]:
    C: list[list] = [[v] for v in y0] + [[] for _ in range(len(tape.ops) - tape.n)]
    zero = gmpy2.mpfr(0)
    for k in range(order):
        _coefficient(tape, C, k)
        for i, (kind, o) in enumerate(tape.outputs):
            f_k = C[o][k] if kind == "node" else (gmpy2.mpfr(o) if k == 0 else zero)
            C[i].append(f_k / (k + 1))
    return C[: tape.n]


@dataclass
class TaylorFlowResult:
    """Endpoint of :func:`taylor_flow`.

    Attributes
    ----------
    t_end : gmpy2.mpfr
    y : list of gmpy2.mpfr
    steps, order : int
    bits : int
    wall_s : float
    """

    t_end: object
    y: list
    steps: int
    order: int
    bits: int
    wall_s: float


def taylor_flow(
    rhs: Callable,
    y0: Sequence,
    params: Sequence,
    t_end,
    digits: int,
    max_steps: int = 100000,
) -> TaylorFlowResult:
    """Integrate ``y' = rhs(t, y, p)`` (autonomous) from 0 to ``t_end`` at ``digits``.

    Parameters
    ----------
    rhs : callable
        A generated mpmath ``rhs(t, y, p)`` (arithmetic only).
    y0, params : sequence of numbers or decimal strings
    t_end : number or str
        Negative for a backward integration.
    digits : int
        Working precision (decimal digits); the local tolerance is ``10^-digits``.

    Returns
    -------
    TaylorFlowResult
    """
    start = time.perf_counter()
    bits = int(math.ceil(digits * math.log2(10))) + 16
    with gmpy2.context(gmpy2.get_context(), precision=bits):
        mp = gmpy2.mpfr
        y = [mp(v) for v in y0]
        p = [mp(v) for v in params]
        tape = record(rhs, len(y), p)
        T = mp(t_end)
        direction = 1 if T >= 0 else -1
        order = int(math.ceil(digits * math.log(10) / 2)) + 1
        t = mp(0)
        steps = 0
        e2 = gmpy2.exp(mp(2))
        while direction * (T - t) > 0:
            if steps >= max_steps:
                raise RuntimeError(f"taylor_flow: more than {max_steps} steps")
            C = _series(tape, y, order)
            scale = max(mp(1), max(abs(v) for v in y))
            rho = None
            for k in (order - 1, order):
                size = max(abs(c[k]) for c in C)
                if size > 0:
                    r = (scale / size) ** (mp(1) / k)
                    rho = r if rho is None else min(rho, r)
            h = abs(T - t) if rho is None else min(rho / e2, abs(T - t))
            h = direction * h
            y = [_horner(c, h) for c in C]
            t = T if abs(T - (t + h)) <= abs(h) * mp(2) ** (-bits // 2) else t + h
            steps += 1
        return TaylorFlowResult(t, y, steps, order, bits, time.perf_counter() - start)


def _horner(c: list, h):
    v = c[-1]
    for a in reversed(c[:-1]):
        v = v * h + a
    return v
