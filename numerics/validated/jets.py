"""First-order jets over Arb balls: a value and its gradient, both enclosed.

The generated Taylor recurrences (``taylor_coefficients(t0, y, p, order, lib)``, see
:mod:`chaplygin.derive.emit.taylor`) work with any number type that has ``+ - * /`` and a
namespace ``lib`` of ``mpf, sqrt, exp, sin, cos``. Run on :class:`ArbJet` numbers seeded with
the unit gradients of the state, they give every Taylor coefficient of the solution *and* its
derivative with respect to the initial state, each as an Arb ball (python-flint) that
contains the exact value for every point of the input balls: what the validated integrator
(:mod:`~chaplygin.numerics.validated.lohner`) needs for the flow and its derivative (C^1).

The gradient is a 1 x n ``arb_mat`` row (one C call per operation on the whole gradient).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from flint import arb, arb_mat

__all__ = [
    "ArbJet",
    "ARB_LIB",
    "JET_LIB",
    "jet_atan2",
    "jet_gradient",
    "jet_value",
    "jets_from_matrix",
    "seed_jets",
]


class ArbJet:
    """A value ``v`` and its gradient ``g`` (a 1 x n ``arb_mat``) with respect to n seeds.

    Parameters
    ----------
    v : arb
        The value (a ball).
    g : arb_mat or None
        The gradient; ``None`` for a constant (gradient zero), which keeps constants cheap.
    """

    __slots__ = ("v", "g")

    def __init__(self, v: Any, g: arb_mat | None = None) -> None:
        self.v = v
        self.g = g

    # ---------------------------------------------------------------- helpers
    @staticmethod
    def _split(x: Any) -> tuple[Any, arb_mat | None]:
        if isinstance(x, ArbJet):
            return x.v, x.g
        return x, None

    @staticmethod
    def _scaled(g: arb_mat | None, c: Any) -> arb_mat | None:
        return None if g is None else g * c

    @staticmethod
    def _plus(g: arb_mat | None, h: arb_mat | None) -> arb_mat | None:
        if g is None:
            return h
        if h is None:
            return g
        return g + h

    # ---------------------------------------------------------------- arithmetic
    def __add__(self, other: Any) -> ArbJet:
        if type(other) is ArbJet:
            g, h = self.g, other.g
            if g is None:
                return ArbJet(self.v + other.v, h)
            return ArbJet(self.v + other.v, g if h is None else g + h)
        return ArbJet(self.v + other, self.g)

    __radd__ = __add__

    def __sub__(self, other: Any) -> ArbJet:
        w, h = self._split(other)
        return ArbJet(self.v - w, self._plus(self.g, None if h is None else -h))

    def __rsub__(self, other: Any) -> ArbJet:
        w, h = self._split(other)
        return ArbJet(w - self.v, self._plus(h, None if self.g is None else -self.g))

    def __neg__(self) -> ArbJet:
        return ArbJet(-self.v, None if self.g is None else -self.g)

    def __mul__(self, other: Any) -> ArbJet:
        v, g = self.v, self.g
        if type(other) is ArbJet:
            w, h = other.v, other.g
            if g is None:
                return ArbJet(v * w, None if h is None else h * v)
            return ArbJet(v * w, g * w if h is None else g * w + h * v)
        return ArbJet(v * other, None if g is None else g * other)

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> ArbJet:
        w, h = self._split(other)
        q = self.v / w
        if h is None:
            return ArbJet(q, self._scaled(self.g, arb(1) / w))  # 1/w for an int w is a float
        # (u/w)' = (u' - q w') / w
        return ArbJet(q, self._scaled(self._plus(self.g, -(h * q)), 1 / w))

    def __rtruediv__(self, other: Any) -> ArbJet:
        w, h = self._split(other)
        q = w / self.v
        g = self._plus(h, None if self.g is None else -(self.g * q))
        return ArbJet(q, self._scaled(g, 1 / self.v))

    def __pow__(self, r: Any) -> ArbJet:
        r_v = r.v if isinstance(r, ArbJet) else r
        if isinstance(r, ArbJet) and r.g is not None:
            raise TypeError("a jet exponent with a gradient is not supported")
        p = self.v**r_v
        return ArbJet(p, self._scaled(self.g, r_v * self.v ** (r_v - 1)))

    def __repr__(self) -> str:
        return f"ArbJet({self.v}, {self.g})"


def _lift(fn_value, fn_derivative):  # noqa: ANN001, ANN202 - internal factory
    def f(x: Any) -> Any:
        if not isinstance(x, ArbJet):
            return fn_value(arb(x) if not isinstance(x, arb) else x)
        v = fn_value(x.v)
        return ArbJet(v, None if x.g is None else x.g * fn_derivative(x.v, v))

    return f


def _sqrt(x: Any) -> Any:
    return x.sqrt()


def _exp(x: Any) -> Any:
    return x.exp()


def _sin(x: Any) -> Any:
    return x.sin()


def _cos(x: Any) -> Any:
    return x.cos()


#: ``lib`` for the generated recurrences on plain Arb balls.
ARB_LIB = SimpleNamespace(mpf=arb, sqrt=_sqrt, exp=_exp, sin=_sin, cos=_cos)


_ZERO = arb(0)


class _Stacks:
    """The Taylor coefficients of one recurrence's series, stacked as matrices for the
    convolutions: for a coefficient list ``a`` (the generated code's ``a7`` ...), the column
    ``V`` of the values and the matrix ``G`` whose row ``j`` is the gradient of ``a[j]``,
    filled as the recurrence computes them. A convolution is then three matrix products in
    Arb (one C call each) instead of ``k`` jet products in Python.

    Lists are recognised by identity and kept referenced while cached (so an identity is
    never reused by another list); the generated code writes ``a[j]`` once per call, before
    any convolution reads it, so a filled row never changes. The cache is emptied when it
    holds more than :attr:`LIMIT` lists (a few calls' worth).
    """

    LIMIT = 1024

    def __init__(self) -> None:
        self.stacks: dict[int, list] = {}
        self.rows: dict[tuple[int, int], list] = {}

    def get(self, a: list, upto: int) -> tuple[list, arb_mat, arb_mat | None]:
        """``(values, V, G)`` of ``a`` with the rows ``0..upto`` filled (``G`` None while no
        entry has a gradient; ``values`` the filled values as a list)."""
        entry = self.stacks.get(id(a))
        if entry is None or entry[0] is not a:
            if len(self.stacks) >= self.LIMIT:
                self.stacks.clear()
            entry = [a, arb_mat(len(a), 1), None, []]
            self.stacks[id(a)] = entry
        _, V, G, values = entry
        for j in range(len(values), upto + 1):
            x = a[j]
            if type(x) is not ArbJet:
                V[j, 0] = x
                values.append(x)
                continue
            V[j, 0] = x.v
            values.append(x.v)
            g = x.g
            if g is not None:
                if G is None:  # the first gradient: the rows before it are zero
                    G = entry[2] = arb_mat(len(a), g.ncols())
                for c in range(g.ncols()):
                    G[j, c] = g[0, c]
        return values, V, G

    def conv(self, a: list, b: list, lo: int, hi: int, k: int, weighted: bool = False) -> Any:
        """``sum(w_j a[j] b[k - j] for j in lo..hi)``, ``w_j = j`` when weighted, else 1:
        the value ``ra V_a`` and the gradient ``ra G_a + rb G_b`` with the rows
        ``ra[j] = w_j b[k - j]`` and ``rb[k - j] = w_j a[j]`` (values)."""
        va, Va, Ga = self.get(a, hi)
        vb, _, Gb = self.get(b, k - lo)
        b_rev = vb[k - lo : (k - hi - 1 if k > hi else None) : -1]  # b[k - j], j = lo..hi
        a_rev = va[hi : (lo - 1 if lo else None) : -1]  # a[j], j = hi..lo
        if weighted:
            b_rev = [w * x for w, x in zip(range(lo, hi + 1), b_rev, strict=True)]
            a_rev = [w * x for w, x in zip(range(hi, lo - 1, -1), a_rev, strict=True)]
        row_a = self._row(0, len(a), lo, b_rev)
        value = (row_a * Va)[0, 0]
        if Ga is None and Gb is None:
            return value
        if Gb is None:
            return ArbJet(value, row_a * Ga)
        grad = self._row(1, len(b), k - hi, a_rev) * Gb
        return ArbJet(value, grad if Ga is None else row_a * Ga + grad)

    def _row(self, which: int, size: int, first: int, entries: list) -> arb_mat:
        """A ``1 x size`` row holding ``entries`` from position ``first`` and zeros elsewhere:
        one of two rows kept per size, whose entries outside the last use's are zero, so
        that only the entries that change are set (a row built afresh converts every zero)."""
        key = (which, size)
        kept = self.rows.get(key)
        if kept is None:
            kept = self.rows[key] = [arb_mat(1, size), 0, 0]  # the row, its nonzero range
        row, start, stop = kept
        end = first + len(entries)
        zero = _ZERO
        for j in range(start, min(stop, first)):
            row[0, j] = zero
        for j in range(max(start, end), stop):
            row[0, j] = zero
        for j, x in enumerate(entries, first):
            row[0, j] = x
        kept[1], kept[2] = first, end
        return row


def _convolutions() -> tuple[Any, Any]:
    stacks = _Stacks()

    def conv(a: list, b: list, lo: int, hi: int, k: int) -> Any:
        return stacks.conv(a, b, lo, hi, k)

    def wconv(a: list, b: list, lo: int, hi: int, k: int) -> Any:
        return stacks.conv(a, b, lo, hi, k, weighted=True)

    return conv, wconv


_CONV, _WCONV = _convolutions()

#: ``lib`` for the generated recurrences on :class:`ArbJet` numbers (``conv`` and ``wconv``:
#: the convolutions as matrix products, see :class:`_Stacks`).
JET_LIB = SimpleNamespace(
    mpf=arb,
    sqrt=_lift(_sqrt, lambda v, s: 1 / (2 * s)),
    exp=_lift(_exp, lambda v, e: e),
    sin=_lift(_sin, lambda v, s: v.cos()),
    cos=_lift(_cos, lambda v, c: -v.sin()),
    conv=_CONV,
    wconv=_WCONV,
)


def seed_jets(values: list) -> list[ArbJet]:
    """Jets for the state components: component i has the gradient e_i.

    Parameters
    ----------
    values : list of arb
        The state's balls.

    Returns
    -------
    list of ArbJet
    """
    n = len(values)
    out = []
    for i, v in enumerate(values):
        row = [0] * n
        row[i] = 1
        out.append(ArbJet(v, arb_mat([row])))
    return out


def jet_value(x: Any) -> Any:
    """The value of a jet (or the number itself).

    Parameters
    ----------
    x : ArbJet or arb

    Returns
    -------
    arb
    """
    return x.v if isinstance(x, ArbJet) else x


def jet_gradient(x: Any, n: int) -> list:
    """The gradient of a jet as a list of n balls (zeros for a constant).

    Parameters
    ----------
    x : ArbJet or arb
    n : int
        The number of seeds.

    Returns
    -------
    list of arb
    """
    if isinstance(x, ArbJet) and x.g is not None:
        return [x.g[0, j] for j in range(n)]
    return [arb(0)] * n


def jet_atan2(y: Any, x: Any) -> Any:
    """``atan2(y, x)`` of balls or jets (the angle of ``(x, y)``; the balls must not meet the
    branch cut ``x <= 0, y = 0``, where Arb returns an indeterminate ball).

    Parameters
    ----------
    y, x : ArbJet or arb

    Returns
    -------
    ArbJet or arb
        A jet when either argument has a gradient.
    """
    yv, xv = jet_value(y), jet_value(x)
    v = arb.atan2(yv, xv)
    gy = y.g if isinstance(y, ArbJet) else None
    gx = x.g if isinstance(x, ArbJet) else None
    if gy is None and gx is None:
        return v
    r2 = xv * xv + yv * yv
    g = ArbJet._plus(ArbJet._scaled(gy, xv / r2), ArbJet._scaled(gx, -yv / r2))
    return ArbJet(v, g)


def jets_from_matrix(values: list, gradient: arb_mat) -> list[ArbJet]:
    """Jets with the given values and the rows of ``gradient`` as their gradients.

    Parameters
    ----------
    values : list of arb
    gradient : arb_mat
        One row per value.

    Returns
    -------
    list of ArbJet
    """
    k = gradient.ncols()
    return [ArbJet(v, arb_mat([[gradient[i, j] for j in range(k)]])) for i, v in enumerate(values)]
