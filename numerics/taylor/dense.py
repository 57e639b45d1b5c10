"""The double-precision Taylor solution as a function of time (dense output):
:func:`taylor_dense` and :class:`TaylorDense`."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ...derive.errors import UserInputError
from .control import MAX_STEPS, run_orders
from .library import load_taylor_library
from .solution import _MESSAGES
from .stepper import _Stepper

if TYPE_CHECKING:
    from ..code import ModelCode

__all__ = ["TaylorDense", "taylor_dense", "DENSE_CHUNK"]


def _compensated_eval(C: np.ndarray, s: Any, y_lo: Any) -> tuple[np.ndarray, np.ndarray]:
    """State at offset ``s`` from the coefficients ``C`` (``(..., n, p + 1)``) of a step and
    the compensation ``y_lo`` carried into it, with the new compensation: the operations of
    the C loop's ``taylor_eval_compensated`` (``derive/templates/taylor.c``) on float64,
    bit for bit (each numpy operation is one IEEE operation, never fused, and the C is
    built with ``-ffp-contract=off``)."""
    p = C.shape[-1] - 1
    v = C[..., p]
    for k in range(p - 1, 0, -1):
        v = v * s + C[..., k]
    d = v * s + y_lo
    c0 = C[..., 0]
    y = c0 + d
    bb = y - c0  # TwoSum: c0 + d = y + error exactly
    return y, (c0 - (y - bb)) + (d - bb)


def _horner_rows(C: np.ndarray, s: Any) -> np.ndarray:
    """State at offset ``s`` from the coefficients ``C`` (``(..., n, p + 1)``): Horner, the
    operations of :func:`_eval_poly` (the Python loop, uncompensated)."""
    p = C.shape[-1] - 1
    v = C[..., p]
    for k in range(p - 1, -1, -1):
        v = v * s + C[..., k]
    return v


#: Times evaluated together by :meth:`TaylorDense.__call__` (bounds the gathered
#: coefficients' memory; the values do not depend on it).
DENSE_CHUNK = 8192


class TaylorDense:
    """The double-precision Taylor solution as a function of time (dense output).

    Made by :func:`taylor_dense`. Every step keeps its Taylor polynomial, so the state is
    known at any time of the span: ``sol(t)`` evaluates the polynomial of the step that holds
    ``t`` by Horner's rule, the operations of the integrator's own output, so that the values
    are those :func:`taylor_solve` gives at the same output times, bit for bit (the compiled
    loop carries the rounding error of the state from step to step, ``y_lo``, and so does
    this solution; the Python recurrences carry none, and neither does it then). Steps and
    polynomials are IEEE operations in a fixed order (the C library, or Python floats): the
    same bits on every machine.

    Attributes
    ----------
    t : ndarray, shape (nsteps + 1,)
        Step times: ``t[0] = t0``, ``t[-1]`` the time reached.
    orders : ndarray of int, shape (nsteps,)
        Order of each step.
    coefficients : list of ndarray
        Step ``j``: shape ``(n_state, orders[j] + 1)``, the normalised Taylor coefficients at
        ``t[j]``: ``y(t[j] + s) = sum_k c[:, k] s^k + y_lo[j]``.
    y_lo : ndarray, shape (nsteps, n_state)
        The compensation carried into each step (zeros without the compiled loop).
    y_end : ndarray, shape (n_state,)
        The state at ``t[-1]``.
    status : int
        0 (the end was reached), -1 (the state became NaN or infinite), -2 (more than
        ``max_steps`` steps), -3 (step size underflow).
    message, backend : str
    compensated : bool
        Whether ``y_lo`` is carried (the compiled loop's update).
    """

    def __init__(self, stepper: _Stepper, t0: float, y0: np.ndarray, max_steps: int):
        self._stepper = stepper
        self.backend = stepper.backend
        self.compensated = stepper.clib is not None
        self.max_steps = max_steps
        self.n = len(y0)
        self._y0 = np.array(y0, dtype=float)
        self._t: list[float] = [float(t0)]
        self._orders: list[int] = []
        self._coeffs: list[np.ndarray] = []
        self._ylo: list[np.ndarray] = []
        self._y = self._y0.copy()
        self._y_lo = np.zeros(self.n)
        self.direction = 0
        self.status = 0
        self.message = _MESSAGES[0]
        self._groups_cache: tuple | None = None

    # ------------------------------------------------------------------ the steps
    def extend(self, t1: float) -> TaylorDense:
        """Integrate on from the time reached to ``t1`` (in the direction of the span),
        exactly as one integration would go on from there (state and compensation).

        Parameters
        ----------
        t1 : float
            The new end.

        Returns
        -------
        TaylorDense
            ``self``; ``status`` says whether ``t1`` was reached.

        Raises
        ------
        UserInputError
            ``t1`` not a finite number, or not beyond the time reached in the direction
            of integration.
        """
        from ..arguments import check_real

        check_real(t1, "t1", double=True)
        t1 = float(t1)
        t = self._t[-1]
        direction = 1 if t1 > t else -1
        if t1 == t or (self.direction and direction != self.direction):
            raise UserInputError(
                f"the solution goes on from t = {t!r} "
                + ("forward" if self.direction >= 0 else "backward")
                + f": t1 = {t1!r} is not beyond it"
            )
        self.direction = direction
        if self.status:
            return self
        self._groups_cache = None
        stepper, y, y_lo = self._stepper, self._y, self._y_lo
        status = 0
        while direction * (t1 - t) > 0:
            if len(self._orders) >= self.max_steps:
                status = -2
                break
            t_new, y_next, coefficients, h, p, step_status = stepper.step(t, y, t1)
            h, t_new = float(h), float(t_new)
            if h == 0 or t + h == t:
                status = -3
                break
            C = np.array(coefficients(), dtype=float)
            if self.compensated:
                y_new, y_lo_new = _compensated_eval(C, h, y_lo)
            else:
                y_new, y_lo_new = np.array(y_next, dtype=float), y_lo
            self._coeffs.append(C)
            self._orders.append(int(p))
            self._ylo.append(y_lo)
            self._t.append(t_new)
            t, y, y_lo = t_new, y_new, y_lo_new
            if step_status or not np.all(np.isfinite(y)):
                status = -1
                break
        self._y, self._y_lo = y, y_lo
        self.status = status
        self.message = _MESSAGES.get(status, "failed")
        return self

    @property
    def t(self) -> np.ndarray:
        return np.array(self._t)

    @property
    def orders(self) -> np.ndarray:
        return np.array(self._orders, dtype=int)

    @property
    def coefficients(self) -> list[np.ndarray]:
        return list(self._coeffs)

    @property
    def y_lo(self) -> np.ndarray:
        return np.array(self._ylo).reshape(len(self._ylo), self.n)

    @property
    def y_end(self) -> np.ndarray:
        return self._y.copy()

    @property
    def nsteps(self) -> int:
        return len(self._orders)

    @property
    def order_min(self) -> int:
        return min(self._orders, default=0)

    @property
    def order_max(self) -> int:
        return max(self._orders, default=0)

    # ------------------------------------------------------------------ evaluation
    def _start_value(self) -> np.ndarray:
        # the C loop's output at t0 is y + y_lo (y_lo = 0 there); the Python loop's is y
        return self._y0 + 0.0 if self.compensated else self._y0.copy()

    def _at_step(self, j: int, s: float) -> np.ndarray:
        """State at ``t[j] + s`` on step ``j``'s polynomial."""
        C = self._coeffs[j]
        if self.compensated:
            return _compensated_eval(C, s, self._ylo[j])[0]
        return _horner_rows(C, s)

    def _groups(self) -> tuple[np.ndarray, dict[int, tuple[np.ndarray, np.ndarray]]]:
        """Each step's place in the stack of the steps of its order, and the stacks."""
        if self._groups_cache is None:
            orders = np.array(self._orders, dtype=int)
            place = np.zeros(len(orders), dtype=int)
            stacks = {}
            for p in np.unique(orders):
                steps = np.flatnonzero(orders == p)
                place[steps] = np.arange(len(steps))
                stacks[int(p)] = (
                    np.stack([self._coeffs[j] for j in steps]),
                    np.stack([self._ylo[j] for j in steps]),
                )
            self._groups_cache = (place, stacks)
        return self._groups_cache

    def _check_times(self, t: Any) -> tuple[np.ndarray, bool]:
        try:
            times = np.asarray(t)
        except (TypeError, ValueError):
            times = np.asarray(None)
        if times.dtype.kind not in "iuf":
            raise UserInputError(f"times must be real numbers, got {t!r}")
        times = times.astype(float)
        if times.ndim > 1:
            raise UserInputError(f"times must be a number or a 1-D sequence, got shape "
                                 f"{times.shape}")  # fmt: skip
        lo, hi = min(self._t[0], self._t[-1]), max(self._t[0], self._t[-1])
        inside = (times >= lo) & (times <= hi)
        if not np.all(inside):
            bad = float(np.atleast_1d(times)[~np.atleast_1d(inside)][0])
            raise UserInputError(
                f"t = {bad!r} is outside the span [{lo!r}, {hi!r}] of the solution"
            )
        return np.atleast_1d(times), times.ndim == 0

    def __call__(self, t: Any) -> np.ndarray:
        """The state at ``t`` (a number or a 1-D sequence of times in the span).

        A time ``t[j] < t <= t[j + 1]`` (forward) is evaluated on step ``j`` at offset
        ``t - t[j]``, as the integrator's output at that time.

        Parameters
        ----------
        t : float or array_like, shape (m,)

        Returns
        -------
        ndarray
            Shape ``(n_state,)`` for a number, ``(n_state, m)`` for a sequence (as
            scipy's ``OdeSolution``).

        Raises
        ------
        UserInputError
            Times that are not numbers, not finite or outside the span.
        """
        times, scalar = self._check_times(t)
        out = np.empty((self.n, times.size))
        steps = np.array(self._t)
        key = self.direction * steps  # increasing
        index = np.searchsorted(key[1:], self.direction * times, side="left")
        index = np.minimum(index, max(self.nsteps - 1, 0))
        start = times == steps[0]
        if self.nsteps:
            place, stacks = self._groups()
            orders = np.array(self._orders, dtype=int)[index]
            for a in range(0, times.size, DENSE_CHUNK):
                chunk = slice(a, a + DENSE_CHUNK)
                for p, (stack, lo_stack) in stacks.items():
                    sel = np.flatnonzero((orders[chunk] == p) & ~start[chunk]) + a
                    if sel.size == 0:
                        continue
                    rows = place[index[sel]]
                    C = stack[rows]
                    s = (times[sel] - steps[index[sel]])[:, None]
                    if self.compensated:
                        values = _compensated_eval(C, s, lo_stack[rows])[0]
                    else:
                        values = _horner_rows(C, s)
                    out[:, sel] = values.T
        out[:, start] = self._start_value()[:, None]
        return out[:, 0] if scalar else out

    def crossings(
        self, g: Callable[[float, np.ndarray], float], direction: int = 0, samples: int = 4
    ) -> tuple[np.ndarray, np.ndarray]:
        """Where ``g(t, y)`` changes sign along the solution (event location).

        ``g`` is sampled at ``samples`` equal parts of every step; each sign change between
        two samples is located on that step's polynomial by Brent's method
        (:func:`scipy.optimize.brentq`, scalar code: the same bits everywhere) to a few
        units in the last place of ``t``. A change at a sample counts once, where ``g``
        reaches 0 from a nonzero value.

        Parameters
        ----------
        g : callable
            ``g(t, y) -> float``.
        direction : {0, 1, -1}
            Every crossing, only those where ``g`` increases (1), or decreases (-1), along
            the direction of integration.
        samples : int
            Samples per step (>= 1): sign changes between them are found.

        Returns
        -------
        t : ndarray, shape (m,)
            The crossing times in the order of integration.
        y : ndarray, shape (m, n_state)
            The states there.

        Raises
        ------
        UserInputError
            A bad ``direction`` or ``samples``.
        """
        from scipy.optimize import brentq

        if direction not in (-1, 0, 1) or isinstance(direction, bool):
            raise UserInputError(f"direction must be 1, -1 or 0, got {direction!r}")
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise UserInputError(f"samples must be a positive integer, got {samples!r}")
        steps = self._t
        eps = 2.0**-52
        found_t: list[float] = []
        found_y: list[np.ndarray] = []
        g_prev = float(g(steps[0], self._start_value()))
        for j in range(self.nsteps):
            a, b = steps[j], steps[j + 1]
            h = b - a
            t_prev = a
            for k in range(1, samples + 1):
                tk = b if k == samples else a + h * k / samples
                gk = float(g(tk, self._at_step(j, tk - a)))
                crossing = (g_prev < 0 < gk) or (g_prev > 0 > gk) or (gk == 0 and g_prev != 0)
                if crossing and (direction == 0 or (direction > 0) == (gk > g_prev)):
                    if gk == 0:
                        root = tk
                    else:
                        lo, hi = min(t_prev, tk), max(t_prev, tk)
                        root = float(brentq(
                            lambda x, j=j, a=a: float(g(x, self._at_step(j, x - a))),
                            lo, hi, rtol=4 * eps, maxiter=200,
                            xtol=4 * eps * max(abs(lo), abs(hi), np.finfo(float).tiny),
                        ))  # fmt: skip
                    found_t.append(root)
                    found_y.append(self._at_step(j, root - a))
                g_prev, t_prev = gk, tk
        y = np.array(found_y).reshape(len(found_y), self.n)
        return np.array(found_t, dtype=float), y


def taylor_dense(
    code: ModelCode,
    y0: Sequence[float],
    t_span: tuple[float, float],
    p: Sequence[float],
    *,
    rtol: float,
    atol: float,
    max_steps: int = MAX_STEPS,
    lib: str | None = None,
) -> TaylorDense:
    """Integrate in double precision with the Taylor method and keep every step's polynomial.

    The steps are those of :func:`taylor_solve` (the compiled C loop's order, step and
    compensated state update; the Python recurrences on floats without a compiler or with
    ``lib="float"``), so :meth:`TaylorDense.__call__` at any time gives what
    ``taylor_solve(..., t_eval=...)`` gives there, bit for bit, and the same bits on every
    machine.

    Parameters
    ----------
    code : ModelCode
        The model (:func:`chaplygin.numerics.code.load_model_code`).
    y0 : sequence of float
        Initial state (``n_state`` finite numbers).
    t_span : (t0, t1)
        Start and end; ``t1 < t0`` integrates backward.
    p : sequence of float
        Parameters in the model's order.
    rtol, atol : float
        Local tolerances of the Jorba-Zou control (at least the unit roundoff ``2^-52``).
    max_steps : int
        Largest number of steps (status -2 beyond it).
    lib : {None, "c", "float"}
        The compiled double library (default, with the Python recurrences as fallback
        when there is no compiler) or the Python recurrences on floats.

    Returns
    -------
    TaylorDense
        Its ``status`` is 0 when ``t1`` was reached.

    Raises
    ------
    UserInputError
        States, parameters, span or tolerances that are not finite numbers of the right
        count, an empty span, tolerances below the unit roundoff, a bad ``max_steps`` or
        ``lib``.

    Examples
    --------
    >>> from chaplygin.numerics.code import load_model_code
    >>> code = load_model_code("chaplygin_ball")
    >>> sol = taylor_dense(code, [0.7, -0.4, 0.5, 0.6, 0.0, 0.8], (0.0, 2.0),
    ...                    [1.0, 2.0, 3.0, 1.0], rtol=1e-12, atol=1e-12)
    >>> sol.status, sol(1.0).shape, sol([0.5, 1.5]).shape
    (0, (6,), (6, 2))
    """
    from ..arguments import check_real, check_vector

    n, m = len(code.state), len(code.params)
    y = [float(v) for v in _checked_values(check_vector, y0, "y0", n)]
    params = [float(v) for v in _checked_values(check_vector, p, "p", m)]
    t0, t1 = (float(v) for v in _checked_values(check_vector, t_span, "t_span", 2))
    if t0 == t1:
        raise UserInputError("t_span must be non-empty (t1 != t0)")
    tolerances = []
    for value, name in ((rtol, "rtol"), (atol, "atol")):
        check_real(value, name, positive=True, double=True)
        if float(value) < 2.0**-52:
            raise UserInputError(
                f"{name} = {float(value)!r} is below the unit roundoff of double precision "
                "(2^-52): use precision='quad' or digits with chaplygin.numerics.integrate"
            )
        tolerances.append(float(value))
    rtol, atol = tolerances
    if isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 1:
        raise UserInputError(f"max_steps must be a positive integer, got {max_steps!r}")
    if lib not in (None, "c", "float"):
        raise UserInputError(f"lib must be None, 'c' or 'float', got {lib!r}")
    clib = load_taylor_library(code, "double", run_orders(rtol, atol)) if lib != "float" else None
    stepper = _Stepper(code, "float", params, rtol, atol, None, None, clib)
    return TaylorDense(stepper, t0, np.array(y), max_steps).extend(t1)


def _checked_values(check_vector: Callable, values: Any, name: str, count: int) -> list:
    """``values`` as given (floats kept exactly), after ``check_vector``'s checks."""
    check_vector(values, name, count, double=True)
    return list(values)
