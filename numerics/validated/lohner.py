"""A validated Taylor integrator on the generated model: enclosures of the flow and of its
derivative (C^1), with Lohner's QR method against the wrapping effect.

Every number is an Arb ball (python-flint): the result contains the exact solution of the
model's equations for every initial state and parameter in the input balls.

One step from ``t_k`` to ``t_k + h`` (Lohner 1987; Nedialkov, Jackson and Corliss 1999):

1. The Taylor coefficients ``c_i(t_k, X)`` of order ``n`` and their derivatives with respect
   to the state (:mod:`~chaplygin.numerics.validated.jets`, run through the generated
   recurrences) over the current box ``X``, and ``c_i(t_k, x^)`` at its centre.
2. An a-priori enclosure ``Z`` of every solution over ``[t_k, t_k + h]``: the high-order
   inclusion test ``sum_(i<n) c_i(t_k, X) [0, h]^i + [0, h]^n c_n(T, Z) ⊆ int Z``
   (``T = [t_k, t_k + h]``; Nedialkov, Jackson and Pryce 2001) proves that the solutions
   exist on the step and stay in ``Z``; the step is halved until the test passes.
3. The Lagrange remainder ``R = h^(n+1) c_(n+1)(T, Z)``; the new set
   ``x^' + (S A) r + (u - x^')`` with ``u = T_n(t_k, x^; h) + R`` and ``S = D_x T_n(t_k, X; h)``
   (mean-value form); the new basis ``A'`` is the Q of a QR factorisation of ``mid(S A)``
   (columns sorted by size), ``r' = (A'^-1 S A) r + A'^-1 (u - x^')`` with ``A'^-1`` enclosed.
4. C^1: the flow's derivative over the step is in ``S + h^(n+1) D_x c_(n+1)(T, Z) W`` where
   ``W`` encloses the variational solution on the step (``|V - Id|_inf <= exp(h L) - 1`` with
   ``L >= |D_x f(T, Z)|_inf``, Gronwall); the product with the derivative so far is kept in
   the same Lohner form (centre matrix, orthogonal basis, interval coefficients).

The QR factorisations use :func:`chaplygin.arith.detlinalg.qr` (no BLAS), so the enclosures
have the same bits on every machine.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from flint import arb, arb_mat, ctx

from ...arith import detlinalg
from ...derive.errors import ComputationError, UserInputError
from .jets import ARB_LIB, JET_LIB, jet_gradient, jet_value, seed_jets

__all__ = [
    "FlowEnclosure",
    "EnclosureError",
    "enclose_flow",
    "to_ball",
    "working_precision",
]


class EnclosureError(ComputationError):
    """The validated integrator could not enclose the flow (the a-priori enclosure failed at
    the smallest step allowed, or the enclosure grew past the limit given).

    Attributes
    ----------
    widths, times : list of float
        The widest component after each step and the time it reached (empty when the
        failure is not a growth): where the wrapping grew.
    """

    def __init__(self, message: str, widths: list | None = None, times: list | None = None):
        super().__init__(message)
        self.widths = list(widths or [])
        self.times = list(times or [])


@contextmanager
def working_precision(bits: int) -> Iterator[None]:
    """Arb's working precision set to ``bits`` inside the block, restored after it.

    Parameters
    ----------
    bits : int
        Binary digits (53 = double; 128 by default in :func:`enclose_flow`).

    Returns
    -------
    context manager
    """
    old = ctx.prec
    ctx.prec = int(bits)
    try:
        yield
    finally:
        ctx.prec = old


def to_ball(x: Any) -> arb:
    """An Arb ball containing ``x`` exactly: a float (exact), an int, a decimal string (the
    ball of the decimal at the working precision), a ``Fraction``, an ``mpmath.mpf`` (exact),
    a pair ``(lo, hi)`` (the interval), or an ``arb`` (kept).

    Parameters
    ----------
    x : float, int, str, Fraction, mpf, tuple or arb

    Returns
    -------
    arb

    Raises
    ------
    UserInputError
        Not a finite number or interval.
    """
    if isinstance(x, arb):
        ball = x
    elif isinstance(x, tuple) and len(x) == 2:
        lo, hi = to_ball(x[0]), to_ball(x[1])
        ball = lo.union(hi)
    elif isinstance(x, str):
        try:
            ball = arb(x.strip())
        except (ValueError, TypeError) as exc:
            raise UserInputError(f"not a number: {x!r}") from exc
    elif hasattr(x, "numerator") and hasattr(x, "denominator") and not isinstance(x, float):
        ball = arb(int(x.numerator)) / int(x.denominator)
    elif hasattr(x, "_mpf_"):
        ball = arb(x)
    else:
        try:
            ball = arb(float(x)) if not isinstance(x, int) else arb(x)
        except (TypeError, ValueError) as exc:
            raise UserInputError(f"not a number: {x!r}") from exc
    if not ball.is_finite():
        raise UserInputError(f"not a finite number: {x!r}")
    return ball


@dataclass
class FlowEnclosure:
    """The result of :func:`enclose_flow`.

    Attributes
    ----------
    t0, t1 : arb
        The times.
    state : list of arb
        Encloses ``phi(t1; t0, x0)`` for every ``x0`` in the initial balls.
    jacobian : list of list of arb or None
        Encloses ``d phi / d x0`` over the initial balls (when asked for).
    steps : int
        Steps taken.
    order : int
        Taylor order.
    prec : int
        Arb working precision (bits).
    max_width : float
        The widest component (diameter) of ``state``.
    widths : list of float
        The widest component of the enclosure after each step (where wrapping grew).
    times : list of float
        The time reached by each step (``widths[i]`` is the width at ``times[i]``).
    seconds : float
        Wall time.
    parameter_jacobian : list of list of arb or None
        Encloses ``d phi / d p`` for the parameters carried as states (``carry``).
    """

    t0: arb
    t1: arb
    state: list
    jacobian: list | None
    steps: int
    order: int
    prec: int
    max_width: float
    widths: list = field(default_factory=list)
    times: list = field(default_factory=list)
    seconds: float = 0.0
    parameter_jacobian: list | None = None

    def contains(self, y: Sequence) -> bool:
        """Whether every component of ``y`` lies in the enclosure.

        Parameters
        ----------
        y : sequence
            Floats, ``mpf``, decimal strings or balls (a ball must lie in it whole).

        Returns
        -------
        bool
        """
        return all(b.contains(to_ball(v)) for b, v in zip(self.state, y, strict=True))


# ------------------------------------------------------------------ small ball utilities
def _width(b: arb) -> float:
    return 2 * float(b.rad())


def _mat(rows: Sequence[Sequence[Any]]) -> arb_mat:
    return arb_mat([list(r) for r in rows])


def _entries(m: arb_mat) -> list[list[arb]]:
    return [[m[i, j] for j in range(m.ncols())] for i in range(m.nrows())]


def _column(v: Sequence[arb]) -> arb_mat:
    return arb_mat([[x] for x in v])


def _mid_float_matrix(m: arb_mat) -> np.ndarray:
    return np.array([[float(m[i, j].mid()) for j in range(m.ncols())] for i in range(m.nrows())])


def _hull_interval(h: arb) -> arb:
    """A ball containing ``[0, h]`` (``[h, 0]`` for a backward step ``h < 0``)."""
    return arb(0).union(h)


# ------------------------------------------------------------------ the set in Lohner form
@dataclass
class _LohnerSet:
    """``centre + basis @ coeffs`` (centre: columns of thin balls; basis: point matrix with an
    enclosed inverse; coeffs: interval columns), for a vector (one column) or a matrix."""

    centre: arb_mat
    basis: arb_mat
    coeffs: arb_mat

    def hull(self) -> arb_mat:
        return self.centre + self.basis * self.coeffs

    def advance(self, U: arb_mat, S: arb_mat) -> _LohnerSet:
        """The set ``U + S basis coeffs`` in Lohner form again (``U``: an enclosure of the
        image of the centre): centre' = mid(U), basis' = Q of mid(S basis) with pivoting,
        coeffs' = (basis'^-1 S basis) coeffs + basis'^-1 (U - centre')."""
        centre = arb_mat([[U[i, j].mid() for j in range(U.ncols())] for i in range(U.nrows())])
        SB = S * self.basis
        B = _mid_float_matrix(SB)
        size = np.array(
            [
                np.linalg.norm(B[:, j])
                * max(float(self.coeffs[j, c].rad()) for c in range(self.coeffs.ncols()))
                for j in range(B.shape[1])
            ]
        )
        order = np.argsort(-size, kind="stable")
        Q, _ = detlinalg.qr(B[:, order])
        if not np.all(np.isfinite(Q)) or abs(np.linalg.det(Q)) < 0.5:
            Q = np.eye(B.shape[0])
        basis = arb_mat(Q.tolist())
        inv = basis.inv()
        coeffs = (inv * SB) * self.coeffs + inv * (U - centre)
        return _LohnerSet(centre, basis, coeffs)


def _identity(n: int) -> arb_mat:
    return arb_mat([[1 if i == j else 0 for j in range(n)] for i in range(n)])


# ------------------------------------------------------------------ one step
@dataclass
class _Problem:
    taylor: Callable
    params: list
    n: int
    order: int
    want_jacobian: bool
    invariants: list = field(default_factory=list)
    #: the largest remainder of the flow's derivative per step (C^1): the step control's
    derivative_tol: float = math.inf


def _carrying(taylor: Callable, n: int, carry: list[int]) -> Callable:
    """The Taylor recurrences of the model extended by the carried parameters as constant
    states (their series ``p, 0, 0, ...``), which the recurrences read as parameters."""

    def coefficients(t0: Any, y: list, p: list, order: int, lib: Any) -> list:
        p = list(p)
        for k, index in enumerate(carry):
            p[index] = y[n + k]
        zero = lib.mpf(0)
        constant = [[y[n + k]] + [zero] * order for k in range(len(carry))]
        return [*taylor(t0, y[:n], p, order, lib), *constant]

    return coefficients


def _horner(coeffs: Sequence[Any], h: Any) -> Any:
    acc = coeffs[-1]
    for c in reversed(coeffs[:-1]):
        acc = acc * h + c
    return acc


def _step_size(c: list[list], order: int, tol: float) -> float:
    """Jorba-Zou's step from the last two coefficients at the centre: ``|c_k| h^k <= tol``."""
    h = math.inf
    for k in (order - 1, order):
        m = max(float(abs(ci[k]).upper()) for ci in c)
        if m > 0:
            h = min(h, (tol / m) ** (1.0 / k))
    return 0.9 * h if math.isfinite(h) else 1.0


def _apriori(prob: _Problem, t: arb, cX: list, h: arb) -> list | None:
    """An enclosure ``Z`` of every solution from the box over ``[t, t + h]``, or None
    (``cX``: the Taylor coefficients over the box)."""
    n, order = prob.n, prob.order
    H = _hull_interval(h)
    T = t + H
    poly = [_horner([cX[i][k] for k in range(order)], H) for i in range(n)]
    # the guess: the polynomial's range with a margin of the last term and of itself
    Z = []
    for i in range(n):
        last = cX[i][order] * H**order
        r = float((poly[i] + last).rad()) * 0.5 + float(abs(last).upper()) * 4 + 1e-30
        Z.append(poly[i] + last + arb(0, r))
    for _ in range(4):
        cZ = prob.taylor(T, Z, prob.params, order, ARB_LIB)
        N = [poly[i] + cZ[i][order] * H**order for i in range(n)]
        if all(Z[i].contains_interior(N[i]) for i in range(n)):
            return N
        Z = [N[i] + arb(0, 2 * float(N[i].rad()) + 1e-30) for i in range(n)]
    return None


def _series_gradients(prob: _Problem, t: arb, X: list, order: int) -> tuple[list, list]:
    """The Taylor coefficients over the balls ``X`` and their derivatives in the initial
    state: ``n`` lists of ``order + 1`` balls, and ``n`` matrices ``(order + 1) x n`` (row
    ``k``: the gradient of coefficient ``k``). The compiled kernel writes the matrices
    (:meth:`~chaplygin.numerics.validated.arb_kernel.ArbTaylorKernel.gradient_series`);
    otherwise the recurrences run on jets seeded with the unit vectors."""
    direct = getattr(prob.taylor, "gradient_series", None)
    got = direct(t, X, prob.params, order) if direct is not None else None
    if got is not None:
        return got
    n = prob.n
    jets = prob.taylor(t, seed_jets(X), prob.params, order, JET_LIB)
    values = [[jet_value(x) for x in row] for row in jets]
    return values, [arb_mat([jet_gradient(x, n) for x in row]) for row in jets]


def _gradient_polynomial(grads: list, n: int, order: int, h: arb) -> arb_mat:
    """``S = sum_k D_x c_k h^k`` (``n x n``): row ``i`` is the row of the powers of ``h``
    times component ``i``'s matrix of gradients (one Arb call per row)."""
    powers = [arb(1)]
    for _ in range(order):
        powers.append(powers[-1] * h)
    P = arb_mat([powers])
    rows = []
    for i in range(n):
        r = P * grads[i]
        rows.append([r[0, j] for j in range(n)])
    return _mat(rows)


def _step(
    prob: _Problem, t: arb, box: list, c: list, h: arb, box_jets: tuple | None = None
) -> dict | None:
    """One step of size ``h`` from the box: the pieces of the update, or None when the
    a-priori enclosure fails (``box_jets``: :func:`_series_gradients` of ``t`` and the box,
    when known)."""
    n, order = prob.n, prob.order
    cX, grads = _series_gradients(prob, t, box, order) if box_jets is None else box_jets
    Z = _apriori(prob, t, cX, h)
    if Z is None:
        return None
    H = _hull_interval(h)
    T = t + H
    if prob.want_jacobian:
        cZ, gZ = _series_gradients(prob, T, Z, order + 1)
    else:
        cZ = prob.taylor(T, Z, prob.params, order + 1, ARB_LIB)
    hp = h ** (order + 1)
    R = [cZ[i][order + 1] * hp for i in range(n)]
    u = [_horner(c[i], h) + R[i] for i in range(n)]
    out = {"u": u, "R": R, "S": _gradient_polynomial(grads, n, order, h), "Z": Z}
    if prob.want_jacobian:
        Df = [[gZ[i][1, j] for j in range(n)] for i in range(n)]
        # a float sum of 6 upper bounds, rounded up by far more than its rounding error
        L = max(sum(float(abs(x).upper()) for x in row) for row in Df) * (1 + 2**-40)
        e = math.expm1(float(abs(h * L).upper()) * (1 + 2**-40)) * (1 + 2**-40)
        W = _identity(n) + arb_mat([[arb(0, e)] * n for _ in range(n)])
        G = _mat([[gZ[i][order + 1, j] for j in range(n)] for i in range(n)])
        out["DR"] = (G * W) * hp
    return out


# ------------------------------------------------------------------ the integrator
def enclose_flow(
    code: Any,
    params: Sequence,
    state: Sequence,
    t0: Any,
    t1: Any,
    *,
    jacobian: bool = False,
    order: int = 20,
    prec: int = 128,
    tol: float = 1e-20,
    max_steps: int = 100000,
    max_width: float = 1.0,
    derivative_tol: float | None = None,
    carry: Sequence[int] = (),
    invariants: Sequence[Callable[[list], list]] = (),
    basis: Sequence[Sequence] | None = None,
    coefficients: Sequence | None = None,
) -> FlowEnclosure:
    """Enclose the flow of a generated model from ``t0`` to ``t1`` (and its derivative).

    Parameters
    ----------
    code : ModelCode
        The model's generated code (:func:`chaplygin.numerics.load_model_code`); its Taylor
        recurrences are run on Arb balls.
    params : sequence
        Parameters in the model's order: floats (exact), decimal strings (enclosed at the
        working precision), ``Fraction``, ``mpf``, ``(lo, hi)`` intervals or ``arb`` balls.
    state : sequence
        The initial state, the same kinds of numbers: a ball or interval per component
        encloses every initial state in the box.
    t0, t1 : number, str or arb
        Start and end time (``t1 < t0``: backward, negative steps). ``t1`` may be a ball, e.g.
        a period ``2 pi/Omega``, or an interval ``(t_a, t_b)`` on one side of ``t0``: the
        result then encloses the flow at every time in it.
    jacobian : bool, optional
        Also enclose ``d phi / d x0`` over the initial box (C^1).
    order : int, optional
        Taylor order (default 20).
    prec : int, optional
        Arb working precision in bits (default 128).
    tol : float, optional
        Step-size control: the last two Taylor terms at the centre below ``tol``.
    max_steps : int, optional
    max_width : float, optional
        Stop with :class:`EnclosureError` when a component's enclosure gets wider than this.
    derivative_tol : float, optional
        With ``jacobian``: the derivative's Lagrange remainder per step (default ``tol``);
        looser, the state's accuracy sets the steps and the derivative widens by about this.
    carry : sequence of int, optional
        Indices of parameters carried as constant states (``p' = 0``) in the Lohner set:
        a parameter interval then moves the enclosure through the flow's derivative in
        it, instead of widening every Taylor coefficient (which wraps: the width would be
        added again at each step). The state and ``jacobian`` stay those of
        the model's state; ``parameter_jacobian`` encloses ``d phi/d p`` for the carried
        parameters when ``jacobian`` is asked for.
    invariants : sequence of callable, optional
        Relations the flow keeps, as tightenings ``box -> box`` (e.g.
        :func:`~chaplygin.numerics.validated.constraints.unit_norm` for ``|gamma| = 1``),
        applied to the state's box after each step. The intersection assumes the relation:
        give only relations proved to be kept; the result then encloses the flow of the
        initial states in the box that meet them.
    basis, coefficients : optional
        An initial set in Lohner's form: ``{state + basis r : r in coefficients}`` with
        ``basis`` an invertible ``n x n`` matrix of floats and ``coefficients`` ``n`` balls or
        intervals (the widths of ``state`` are added). A thin set that is not a box (the image
        of a small box of a chart) then does not start as the box around it, whose wrapping
        would widen every later step.

    Returns
    -------
    FlowEnclosure

    Raises
    ------
    UserInputError
        Wrong number of parameters or state components, ``t1 = t0``, a bad order.
    EnclosureError
        The flow could not be enclosed (blow-up, a step too small, too many steps).

    Examples
    --------
    >>> from chaplygin.numerics import load_model_code
    >>> code = load_model_code("chaplygin_ball")
    >>> body, start = ["1.1", "1.7", "2.3", "0.9"], ["0.3", "-0.2", "0.5", "0.6", "0", "0.8"]
    >>> e = enclose_flow(code, body, start, 0, 1)
    >>> e.max_width < 2**-52  # narrower than one rounding of a double
    True
    """
    started = time.perf_counter()
    n = len(code.state)
    carry = _check_arguments(code, params, state, order, carry)
    with working_precision(prec):
        P = [to_ball(p) for p in params]
        X0 = [to_ball(x) for x in state] + [P[k] for k in carry]
        ta, tb = to_ball(t0), to_ball(t1)
        if tb.mid() == ta.mid():  # (t1 may be a ball reaching t0: a step interval holds 0)
            raise UserInputError(f"t1 must differ from t0 (got {t0!r}, {t1!r})")
        taylor = _recurrences(code)
        taylor = taylor if not carry else _carrying(taylor, n, carry)
        prob = _Problem(taylor, P, n + len(carry), order, jacobian, list(invariants),
                        _derivative_tol(tol, derivative_tol))  # fmt: skip
        start = _initial_set(X0, n, basis, coefficients)
        result = _integrate(prob, start, ta, tb, tol, max_steps, max_width)
    jac = result["jacobian"]
    return FlowEnclosure(
        t0=ta,
        t1=tb,
        state=result["state"][:n],
        jacobian=None if jac is None else [row[:n] for row in jac[:n]],
        parameter_jacobian=None if jac is None or not carry else [row[n:] for row in jac[:n]],
        steps=result["steps"],
        order=order,
        prec=prec,
        max_width=max(_width(b) for b in result["state"][:n]),
        widths=result["widths"],
        times=result["times"],
        seconds=time.perf_counter() - started,
    )


def _recurrences(code: Any) -> Callable:
    """The model's Taylor recurrences on balls and jets: the compiled Arb kernel when it can
    be built (:func:`~chaplygin.numerics.validated.arb_kernel.arb_kernel`), else the
    generated Python module's."""
    from .arb_kernel import arb_kernel

    kernel = arb_kernel(code)
    return kernel if kernel is not None else code.taylor.taylor_coefficients


def _derivative_tol(tol: float, derivative_tol: float | None) -> float:
    """The derivative's remainder bound per step (``tol`` unless given; positive, finite)."""
    d = tol if derivative_tol is None else derivative_tol
    if isinstance(d, bool) or not isinstance(d, int | float) or not 0 < d < math.inf:
        raise UserInputError(f"derivative_tol must be a positive number, got {derivative_tol!r}")
    return float(d)


def _check_arguments(code: Any, params: Sequence, state: Sequence, order: Any, carry: Any) -> list:
    """Refuse wrong counts, orders and carried indices; the carried indices as a list."""
    n = len(code.state)
    if len(state) != n or len(params) != len(code.params):
        raise UserInputError(
            f"{code.name} needs {n} state components and {len(code.params)} parameters, "
            f"got {len(state)} and {len(params)}"
        )
    if not (isinstance(order, int) and 2 <= order <= 60):
        raise UserInputError(f"order must be an integer in 2..60, got {order!r}")
    carry = list(carry)
    if any(not isinstance(k, int) or not 0 <= k < len(params) for k in carry) or len(
        set(carry)
    ) != len(carry):
        raise UserInputError(f"carry must be distinct parameter indices, got {carry!r}")
    return carry


def _initial_set(X0: list, n: int, basis: Any, coefficients: Any) -> tuple[_LohnerSet, list]:
    """The initial state in Lohner's form: the box ``X0``, or ``mid(X0) + B r`` with ``r`` in
    ``coefficients`` plus ``B^-1 (X0 - mid(X0))`` (the first ``n`` components; carried
    parameters keep their own axes)."""
    m = len(X0)
    centre = _column([x.mid() for x in X0])
    offsets = _column([x - x.mid() for x in X0])
    if basis is None and coefficients is None:
        return _LohnerSet(centre, _identity(m), offsets), list(X0)
    if basis is None or coefficients is None or len(basis) != n or len(coefficients) != n:
        raise UserInputError(f"basis (n x n) and coefficients (n) go together, n = {n}")
    rows = [[to_ball(v) for v in row] for row in basis]
    if any(len(r) != n for r in rows):
        raise UserInputError(f"basis must be {n} x {n}")
    B = _identity(m)
    for i in range(n):
        for j in range(n):
            B[i, j] = rows[i][j]
    try:
        inv = B.inv()
    except ZeroDivisionError:
        raise UserInputError("basis must be invertible") from None
    r = [to_ball(c) for c in coefficients] + [arb(0)] * (m - n)
    start = _LohnerSet(centre, B, _column(r) + inv * offsets)
    hull = start.hull()
    return start, [hull[i, 0] for i in range(m)]


def _integrate(
    prob: _Problem, start: tuple, ta: arb, tb: arb, tol: float, max_steps: int,
    max_width: float,
) -> dict:  # fmt: skip
    n = prob.n
    x_set, X0 = start
    j_set = _LohnerSet(_identity(n), _identity(n), arb_mat(n, n)) if prob.want_jacobian else None
    run = {"x": x_set, "j": j_set, "box": list(X0), "widths": [], "times": []}
    # backward (sign -1): the same steps with h < 0 (Taylor's formula and the Lagrange
    # remainder hold on [t + h, t]); the loop runs on sign * t
    sign = 1 if tb.mid() > ta.mid() else -1
    # an end time that is an interval: steps to its near end, then one step over all of it
    interval_end = float(tb.rad()) > 2.0 ** (20 - ctx.prec) * (1 + float(abs(tb).upper()))
    stop = arb(tb.lower() if sign > 0 else tb.upper()) if interval_end else tb
    t, scale = ta, 1.0
    while sign * (stop.mid() - t.mid()) > 0 and (not interval_end or sign * (stop - t) > 0):
        centre = [run["x"].centre[i, 0] for i in range(n)]
        c = prob.taylor(t, centre, prob.params, prob.order, ARB_LIB)
        h_try = _step_size(c, prob.order, tol)
        piece, h, last, w = _take_step(prob, t, run["box"], c, sign * h_try * scale, stop - t,
                                       tol)  # fmt: skip
        if not last:  # the next step from this one's remainder (about h^(order + 1))
            scale = min(1.0, _growth(w, prob.order) * abs(float(h.mid())) / h_try)
        _apply(prob, run, piece, t + h, max_width)
        t = t + h
        if last:
            break
        if len(run["widths"]) >= max_steps:
            raise EnclosureError(f"{max_steps} steps were not enough")
    if interval_end:
        centre = [run["x"].centre[i, 0] for i in range(n)]
        c = prob.taylor(t, centre, prob.params, prob.order, ARB_LIB)
        piece = _step(prob, t, run["box"], c, tb - t)
        if piece is None:
            raise EnclosureError(
                f"the end-time interval {tb} is too long for one Taylor step from "
                f"t = {float(t.mid()):.6g}: split it"
            )
        _apply(prob, run, piece, tb, max_width)
    jac = None if run["j"] is None else _entries(run["j"].hull())
    return {
        "state": run["box"],
        "jacobian": jac,
        "steps": len(run["widths"]),
        "widths": run["widths"],
        "times": run["times"],
    }


def _apply(prob: _Problem, run: dict, piece: dict, t_new: arb, max_width: float) -> None:
    """Carry the sets (and the box) over one accepted step."""
    x_set = run["x"]
    S, U = piece["S"], _column(piece["u"])
    new_set = x_set.advance(U, S)
    hull = new_set.hull()
    direct = U + S * (x_set.basis * x_set.coeffs)
    run["box"] = [_tighter(hull[i, 0], direct[i, 0]) for i in range(prob.n)]
    for tighten in prob.invariants:
        run["box"] = tighten(run["box"])
    if run["j"] is not None:
        SJ = S + piece["DR"]
        run["j"] = run["j"].advance(SJ * run["j"].centre, SJ)
    run["x"] = new_set
    run["widths"].append(max(_width(b) for b in run["box"]))
    run["times"].append(float(t_new.mid()))
    if run["widths"][-1] > max_width or not all(b.is_finite() for b in run["box"]):
        raise EnclosureError(
            _growth_report(run["widths"], run["times"], max_width), run["widths"], run["times"]
        )


def _growth_report(widths: list, times: list, limit: float) -> str:
    """Where the enclosure grew: its width at the start, when it passed 10^3 and 10^6 times
    that, and where it passed the limit (or stopped being finite)."""
    start = widths[0]
    marks = []
    for factor in (1e3, 1e6):
        k = next((i for i, w in enumerate(widths) if w > factor * start), None)
        if k is not None:
            marks.append(f"x{factor:.0e} by t = {times[k]:.6g}")
    end = f"{widths[-1]:.3g}" if math.isfinite(widths[-1]) else "not finite"
    return (
        f"the enclosure grew past {limit:.3g} (width {end} at t = {times[-1]:.6g}, step "
        f"{len(widths)}; width {start:.3g} after the first step"
        + "".join(", " + m for m in marks)
        + "): the flow cannot be enclosed this far at this precision (a chaotic orbit's "
        "enclosure grows like its largest exponent)"
    )


def _remainder_width(prob: _Problem, piece: dict, tol: float) -> float:
    """The largest Lagrange remainder of the step relative to its tolerance (the state's:
    ``tol``; for C^1 the derivative's: ``prob.derivative_tol``): what the step control
    bounds to 1 (not the width the state already has, e.g. from a parameter ball)."""
    w = max(float(abs(r).upper()) for r in piece["R"]) / tol
    if "DR" in piece:
        DR = piece["DR"]
        d = max(float(abs(DR[i, j]).upper()) for i in range(DR.nrows()) for j in range(DR.ncols()))
        w = max(w, d / prob.derivative_tol)
    return w


#: The safety factor and the largest growth of the next step over the last accepted one.
STEP_SAFETY, STEP_GROWTH = 0.9, 1.1


def _growth(w: float, order: int) -> float:
    """How much longer the next step may be than the last, whose remainder was ``w`` times
    its tolerance: ``STEP_SAFETY w^(-1/(order + 1))``, at most ``STEP_GROWTH``."""
    if not w > 0:
        return STEP_GROWTH
    return min(STEP_GROWTH, STEP_SAFETY * w ** (-1.0 / (order + 1)))


def _take_step(
    prob: _Problem, t: arb, box: list, c: list, h_try: float, remaining: arb, tol: float
) -> tuple[dict, arb, bool, float]:
    """The step from ``t``: the first of ``h_try``, ``remaining`` (the last step) or smaller
    steps whose a-priori enclosure exists and whose remainder is at most ``tol`` wide (three
    shrinkings at most on the remainder; the a-priori test may halve the step 30 times).
    ``h_try`` and ``remaining`` have the sign of the direction of integration. Returns the
    step's pieces, its size, whether it is the last, and its remainder over its tolerance
    (:func:`_remainder_width`, which sets the next step: :func:`_growth`)."""
    last = abs(h_try) >= float(abs(remaining).lower())
    h = remaining if last else arb(h_try)
    box_jets = _series_gradients(prob, t, box, prob.order)  # the same for every trial step
    for attempt in range(33):
        piece = _step(prob, t, box, c, h, box_jets)
        if piece is None:
            h, last = arb(float(h.mid()) / 2), False
            continue
        w = _remainder_width(prob, piece, tol)
        if w <= 1 or attempt >= 3:
            return piece, h, last, w
        h, last = arb(float(h.mid()) * 0.9 * w ** (-1.0 / (prob.order + 1))), False
    raise EnclosureError(f"no a-priori enclosure at t = {float(t.mid()):.6g} even with h = {h}")


def _tighter(a: arb, b: arb) -> arb:
    """The intersection of two balls that both contain the exact value."""
    try:
        return a.intersection(b)
    except ValueError:  # disjoint: cannot happen for two enclosures of one value
        raise EnclosureError("two enclosures of one value are disjoint") from None
