"""The integrator protocol: a base class that owns the public call, and the precision table.

:meth:`Integrator.run` does the bookkeeping (backend choice and set-up, the precision's
context, timing, the finiteness check, the drift of every first integral) and calls the
``_prepare`` and ``_solve`` hooks a method fills in (scipy ``integrate/_ivp/base.py``).
Everything that depends on the precision is one row of :data:`NUMBER_TYPES` (heyoka's
``fp_type``).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, field
from typing import Any, ClassVar

import mpmath
import numpy as np

from ...derive.errors import UserInputError
from ..code import ModelCode
from ..inputs import Precision
from .result import IntegrationResult

__all__ = [
    "BACKENDS",
    "NumberType",
    "NUMBER_TYPES",
    "Problem",
    "Solution",
    "Integrator",
]

#: Backends a caller may ask for.
BACKENDS = ("auto", "c", "numpy")


# --------------------------------------------------------------------------- precisions


_SQRT_EPS_DOUBLE = float(np.sqrt(np.finfo(float).eps))

#: Up to this many output points the integrals are evaluated point by point on Python floats
#: (numpy's per-call cost on short arrays is most of a short run's evidence otherwise).
_POINTWISE_INTEGRALS = 4


def _integral_change_numpy(code: ModelCode, t, y, p, compiled=None) -> tuple:
    # t has one entry per output point: integrals may depend on time explicitly
    if compiled is not None and len(t) <= _POINTWISE_INTEGRALS:
        # a run on the C backend: its evidence from the same expressions compiled (the
        # compiled model's call costs 0.1 us where the numpy module's costs 8 us per point)
        pa = np.asarray(p, dtype=float)
        rows = np.ascontiguousarray(np.asarray(y, dtype=float).T)
        points = [compiled.integrals(float(tj), rows[j], pa).tolist() for j, tj in enumerate(t)]
        first = points[0]
        # on Python floats (numpy's per-call cost is most of the work for a few points); a
        # value that is not finite makes the change NaN, as numpy's max would
        change = [0.0 if math.isfinite(f) else math.nan for f in first]
        for v in points[1:]:
            for i, f in enumerate(first):
                d = abs(v[i] - f)
                if d > change[i] or d != d:
                    change[i] = d
        return change, [abs(f) for f in first]
    elif len(t) <= _POINTWISE_INTEGRALS:
        pf = [float(v) for v in p]
        values = np.array(
            [code.numpy.integrals(float(tj), y[:, j].tolist(), pf) for j, tj in enumerate(t)],
            dtype=float,
        ).T.reshape(len(code.integral_names), len(t))
    else:
        values = np.asarray(
            code.numpy.integrals(np.asarray(t, dtype=float), y, np.asarray(p, dtype=float))
        )
    F0 = values[:, :1]
    return np.max(np.abs(values - F0), axis=1), np.abs(F0[:, 0])


def _integral_change_mpmath(code: ModelCode, t, y, p, compiled=None) -> tuple:
    rows = [code.mpmath.integrals(t[j], list(y[:, j]), p) for j in range(y.shape[1])]
    F0 = rows[0]
    # NaN compares false: a non-finite value anywhere makes the change NaN
    change = [
        max(abs(r[i] - F0[i]) for r in rows)
        if all(mpmath.isfinite(r[i]) for r in rows)
        else mpmath.nan
        for i in range(len(F0))
    ]
    return change, [abs(v) for v in F0]


@dataclass(frozen=True)
class NumberType:
    """What :func:`integrate` does differently in one kind of precision.

    Attributes
    ----------
    kind : {"double", "quad", "digits"}
        :attr:`Precision.kind`.
    default_method : str
        Key of :data:`METHODS` used when no method is given.
    default_tolerances : callable
        ``Precision -> (rtol, atol)``.
    context : callable
        ``Precision -> context manager`` in which the method runs and the drift is
        evaluated (the mpmath working precision).
    integral_change : callable
        ``(code, t, y, p, compiled=None) -> (max |F(t) - F(0)|, |F(0)|)`` per integral
        (``compiled``: the compiled model, for runs on the C backend; used in double).
    zero : callable
        ``Precision -> float``: an integral whose initial value is below it has no
        meaningful relative change (the square root of the working precision).
    """

    kind: str
    default_method: str
    default_tolerances: Callable[[Precision], tuple[float, float]]
    context: Callable[[Precision], AbstractContextManager]
    integral_change: Callable[..., tuple]
    zero: Callable[[Precision], float]


def _mpmath_type(kind: str) -> NumberType:
    return NumberType(
        kind=kind,
        default_method="taylor",
        default_tolerances=lambda prec: (prec.min_rtol, prec.min_rtol),
        context=lambda prec: mpmath.workdps(prec.digits),
        integral_change=_integral_change_mpmath,
        zero=lambda prec: 10.0 ** (-prec.digits / 2),
    )


#: One row per precision kind (heyoka's ``fp_type``).
NUMBER_TYPES: dict[str, NumberType] = {
    "double": NumberType(
        kind="double",
        # the generated Taylor integrator: its bits do not depend on the machine (scipy's
        # methods sum their stages with BLAS, whose kernels differ by processor)
        default_method="taylor",
        default_tolerances=lambda prec: (1e-10, 1e-12),
        context=lambda prec: nullcontext(),
        integral_change=_integral_change_numpy,
        zero=lambda prec: _SQRT_EPS_DOUBLE,
    ),
    "quad": _mpmath_type("quad"),
    "digits": _mpmath_type("digits"),
}


# --------------------------------------------------------------------------- protocol


@dataclass(frozen=True)
class Problem:
    """One integration, every number already at the working precision.

    Attributes
    ----------
    code : ModelCode
    y0 : list, length n_state
    t_span : (t0, t1)
    params : list, length n_param
    precision : Precision
    rtol, atol : float
    t_eval : list or None
    events : list of callables or None
    options : dict
        Method options (``taylor_options``), validated by :meth:`Integrator.check`.
    max_steps : int or None
        Step limit (None: the method's default).
    max_wall_s : float or None
        Wall-time limit in seconds (None: none).
    """

    code: ModelCode
    y0: list
    t_span: tuple
    params: list
    precision: Precision
    rtol: float
    atol: float
    t_eval: list | None = None
    events: list | None = None
    options: dict = field(default_factory=dict)
    max_steps: int | None = None
    max_wall_s: float | None = None


class BudgetExceeded(Exception):
    """Raised inside a wrapped right-hand side when a step or wall-time limit is reached."""

    def __init__(self, status: int, message: str):
        super().__init__(message)
        self.status, self.message = status, message


class Budget:
    """Counts right-hand-side calls and watches the clock for one integration.

    Parameters
    ----------
    max_calls : int or None
        Calls allowed (None: no limit).
    max_wall_s : float or None
        Seconds allowed from now (None: no limit).
    what : str
        How the limit is named in the message (``"max_steps=1000000"``).
    """

    def __init__(self, max_calls: int | None, max_wall_s: float | None, what: str):
        self.max_calls, self.max_wall_s, self.what = max_calls, max_wall_s, what
        self.calls = 0
        self.deadline = None if max_wall_s is None else time.perf_counter() + max_wall_s

    def tick(self) -> None:
        """Count one call; raise :class:`BudgetExceeded` past a limit (the clock is read
        every 256 calls)."""
        self.calls += 1
        if self.max_calls is not None and self.calls > self.max_calls:
            raise BudgetExceeded(
                -2,
                f"too many steps ({self.what}): raise max_steps, shorten the span or loosen "
                "the tolerance",
            )
        if self.deadline is not None and not self.calls & 255:
            if time.perf_counter() > self.deadline:
                raise BudgetExceeded(
                    -6,
                    f"the wall-time limit max_wall_s={self.max_wall_s:g} was reached: raise "
                    "max_wall_s (None: no limit) or shorten the span",
                )

    def wrap(self, fun: Callable) -> Callable:
        """``fun`` with a :meth:`tick` before every call.

        Parameters
        ----------
        fun : callable

        Returns
        -------
        callable
        """

        def counted(*args):
            self.tick()
            return fun(*args)

        return counted


@dataclass
class Solution:
    """What an integrator's ``_solve`` hook returns; :meth:`Integrator.run` adds the evidence.

    ``backend`` (when not None) replaces the one ``_prepare`` chose (the Taylor method
    reports the library it ran on).
    """

    t: Any
    y: np.ndarray
    status: int
    message: str
    nfev: int
    njev: int = 0
    nsteps: int = 0
    backend: str | None = None
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)
    info: dict = field(default_factory=dict)


class Integrator:
    """Base of the integration methods: the public call and the bookkeeping.

    A method sets the class attributes and fills :meth:`_solve` (and :meth:`_prepare`
    when it has compiled parts); :meth:`run` does the rest.

    Attributes
    ----------
    name : str
        Key in :data:`METHODS`.
    precisions : tuple of str
        Precision kinds it works in (``double``, ``quad``, ``digits``).
    rtol_floor : mapping of str to float
        Smallest ``rtol`` it delivers, in units of the precision's unit roundoff.
    supports_events : bool
    options : tuple of str
        Names it accepts in ``taylor_options``.
    backends : tuple of str
        What it runs on, preferred first (``c``: compiled, ``numpy``: numpy or Python
        numbers, ``mpmath``); :meth:`_prepare` picks one for the requested ``backend``.
    """

    name: ClassVar[str] = ""
    precisions: ClassVar[tuple[str, ...]] = ("double",)
    backends: ClassVar[tuple[str, ...]] = ("mpmath",)
    rtol_floor: ClassVar[Mapping[str, float]] = {"double": 100.0}
    supports_events: ClassVar[bool] = False
    options: ClassVar[tuple[str, ...]] = ()

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"

    def floor(self, precision: Precision) -> float:
        """Smallest relative tolerance this method delivers in ``precision``.

        Parameters
        ----------
        precision : Precision
            The working precision.

        Returns
        -------
        float
            ``rtol_floor[precision.kind]`` times the precision's unit roundoff.
        """
        return self.rtol_floor[precision.kind] * precision.epsilon

    def check(
        self,
        precision: Precision,
        rtol: float,
        events: Sequence[Callable] | Callable | None,
        options: Mapping[str, Any],
    ) -> None:
        """Refuse a precision, tolerance, events or options this method cannot honour.

        Parameters
        ----------
        precision : Precision
            The requested precision.
        rtol : float
            The requested relative tolerance (at least :meth:`floor`).
        events : callable or sequence of callables or None
            Event functions ``g(t, y)``; any needs a method that locates events.
        options : mapping
            ``taylor_options`` (keys among :attr:`options`).

        Raises
        ------
        UserInputError
            The message names what works instead.
        """
        kind = precision.kind
        if kind not in self.precisions:
            raise UserInputError(
                f"method {self.name} works in {' or '.join(self.precisions)} precision, "
                f'not {precision!r}; use method="{NUMBER_TYPES[kind].default_method}" or '
                + " or ".join(f'precision="{p}"' for p in self.precisions)
            )
        if events and not self.supports_events:
            raise UserInputError(f'method {self.name} does not locate events; use method="taylor"')
        floor = self.floor(precision)
        if rtol < floor * (1 - 1e-9):  # slack: 10.0**-98 against 10 * 10.0**-99 rounding
            raise UserInputError(
                f"rtol={rtol:g} is below what {precision!r} precision can deliver with "
                f"{self.name} (about {floor:.1e}); ask for {_precision_for(rtol)}"
            )
        if options and not self.options:
            raise UserInputError("taylor_options apply to method taylor only")
        unknown = set(options) - set(self.options)
        if unknown:
            raise UserInputError(
                f"unknown taylor option(s) {sorted(unknown)}; valid: {', '.join(self.options)}"
            )

    def run(
        self, problem: Problem, backend: str = "auto", setup_s: float = 0.0
    ) -> IntegrationResult:
        """Integrate ``problem`` and return the result with its evidence.

        Chooses the backend and prepares compiled parts (set-up time), runs :meth:`_solve`
        in the precision's context (wall time), flags a non-finite solution or drift and
        measures the drift of every first integral.

        Parameters
        ----------
        problem : Problem
            Model code, initial state, span, parameters, precision and tolerances.
        backend : {"auto", "c", "numpy"}
            Where the right-hand side runs: compiled C, numpy, or C when it is available.
        setup_s : float
            Set-up time already spent (reading the inputs), added to ``setup_s``.

        Returns
        -------
        IntegrationResult
            Solution, status and message (status -1 for a non-finite solution, -5 for a
            non-finite drift), the drift of every first integral, work counters and times.

        Raises
        ------
        UserInputError
            An unknown ``backend``.
        """
        start = time.perf_counter()
        if backend not in BACKENDS:
            raise UserInputError(f"unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
        prec = problem.precision
        number_type = NUMBER_TYPES[prec.kind]
        with warnings.catch_warnings():
            if backend == "auto":  # say once that the compiled code is unavailable
                warnings.simplefilter("default")
            chosen = self._prepare(problem, backend)
        setup_s += time.perf_counter() - start
        start = time.perf_counter()
        with number_type.context(prec):
            sol = self._solve(problem, chosen)
        return self._result(problem, sol, chosen, time.perf_counter() - start, setup_s)

    def _result(
        self, problem: Problem, sol: Solution, chosen: str, wall: float, setup_s: float
    ) -> IntegrationResult:
        """The result of a solve with its evidence: the finiteness check and the drift of
        every first integral over the outputs (what :meth:`run` returns)."""
        prec = problem.precision
        status, message = int(sol.status), str(sol.message)
        if not _all_finite(sol.y):
            status = -1
            message = "the solution became NaN or infinite; check the parameters and state"
        code, p = problem.code, problem.params
        # the evidence of a run on the C backend from the compiled model (double)
        compiled = code.compiled() if prec.is_double and chosen == "c" else None
        drift, absolute = _drift(code, sol.t, sol.y, p, prec, compiled)
        bad = [name for name, v in drift.items() if not math.isfinite(v)]
        if bad and status == 0:
            status = -5
            message = (
                f"the error evidence is not finite (drift of {', '.join(bad)}): the result "
                "cannot be trusted; check the parameters and state"
            )
        return IntegrationResult(
            status=status,
            message=message,
            t=np.asarray(sol.t),
            y=sol.y,
            state_names=code.state,
            drift=drift,
            drift_absolute=absolute,
            nfev=int(sol.nfev),
            njev=int(sol.njev),
            nsteps=int(sol.nsteps),
            wall_s=wall,
            setup_s=setup_s,
            precision=repr(prec),
            method=self.name,
            backend=sol.backend or chosen,
            model=code.name,
            params=dict(zip(code.params, p, strict=True)),
            t_events=list(sol.t_events),
            y_events=list(sol.y_events),
            info=sol.info,
        )

    # ---------------------------------------------------------------- hooks
    def _prepare(self, problem: Problem, backend: str) -> str:
        """Compile or load what the method runs on; return the backend's name.

        The default: the method's first backend, whatever was requested (``mpmath.odefun``
        has only one).
        """
        return self.backends[0]

    def _solve(self, problem: Problem, backend: str) -> Solution:
        raise NotImplementedError  # pragma: no cover


def _drift(code: ModelCode, t, y: np.ndarray, p, precision: Precision, compiled=None):
    """Largest change of every first integral over the output (relative, or absolute where
    the integral starts at zero to within the square root of the working precision);
    ``compiled`` (the compiled model, runs on the C backend) evaluates them in double."""
    number_type = NUMBER_TYPES[precision.kind]
    with number_type.context(precision):
        change, ref = number_type.integral_change(code, t, y, p, compiled)
    zero = number_type.zero(precision)
    drift, absolute = {}, []
    for i, name in enumerate(code.integral_names):
        if ref[i] <= zero:
            drift[name] = float(change[i])
            absolute.append(name)
        else:
            drift[name] = float(change[i] / ref[i])
    return drift, tuple(absolute)


def _precision_for(rtol: float) -> str:
    """A precision that delivers ``rtol`` with any method (for error messages).

    ``quad`` (Taylor) when its unit roundoff suffices, else ``d`` digits with
    ``10**(2 - d) <= rtol``: both the Taylor floor (eps) and odefun's (10 eps) are met.
    """
    if rtol >= Precision("quad").epsilon * (1 - 1e-9):
        return 'precision="quad" (method="taylor")'
    return f"precision={max(int(np.ceil(-np.log10(rtol) - 1e-9)) + 2, 16)}"


def _all_finite(ys) -> bool:
    arr = np.asarray(ys)
    if arr.dtype != object:
        if arr.size <= 64:  # a few outputs: on Python floats (numpy's call costs more)
            return all(map(math.isfinite, arr.ravel().tolist()))
        return bool(np.isfinite(arr).all())
    return all(mpmath.isfinite(v) for v in arr.ravel())
