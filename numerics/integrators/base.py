"""The integrator protocol: the one door every integration of the project goes through.

A :class:`Problem` is one integration of any right-hand side the project generates (a
model's equations, its reversed flow, its variational equations, a batch of copies:
:mod:`~chaplygin.numerics.integrators.flows`) at one explicit
:class:`~chaplygin.numerics.precision.Precision`. An :class:`Integrator` names the flows and
precisions it integrates; :meth:`Integrator.solve` chooses the backend, enters the
precision's context and calls the ``_prepare`` and ``_solve`` hooks a method fills in (scipy
``integrate/_ivp/base.py``); :meth:`Integrator.run` adds the evidence of a model's run (timing,
the finiteness check, the drift of every first integral).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import mpmath
import numpy as np

from ...derive.errors import UserInputError
from ..code import ModelCode
from ..precision import Precision
from .flows import Flow, ModelFlow, ReversedFlow
from .result import IntegrationResult, shown_at

__all__ = [
    "BACKENDS",
    "Problem",
    "Solution",
    "Integrator",
]

#: Backends a caller may ask for.
BACKENDS = ("auto", "c", "numpy")


# --------------------------------------------------------------------------- evidence

#: Up to this many output points the integrals are evaluated point by point on Python floats
#: (numpy's per-call cost on short arrays is most of a short run's evidence otherwise).
_POINTWISE_INTEGRALS = 4

#: The same for a run on the C backend, whose compiled integrals cost far less per point: 11
#: outputs (the Taylor method's default) 10 us point by point against 39 us in one numpy call.
_POINTWISE_COMPILED = 16


def _integral_change_numpy(code: ModelCode, t, y, p, compiled=None) -> tuple:
    # t has one entry per output point: integrals may depend on time explicitly
    if compiled is not None and len(t) <= _POINTWISE_COMPILED:
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


# --------------------------------------------------------------------------- protocol


@dataclass(frozen=True)
class Problem:
    """One integration, every number already at the working precision.

    Attributes
    ----------
    system : Flow or ModelCode
        What is integrated (:mod:`~chaplygin.numerics.integrators.flows`); a model's code
        stands for its :class:`~chaplygin.numerics.integrators.flows.ModelFlow`.
    y0 : list, length n_state (a batch: array of shape (N, n_state))
    t_span : (t0, t1)
        (A batch: None; its output times are ``t_eval``.)
    params : list, length n_param (a batch: array of shape (N, n_param))
    precision : Precision
    rtol, atol : float
    t_eval : list, StroboscopicTimes or None
        Output times (default: the method's); a batch's
        :class:`~chaplygin.numerics.integrators.flows.StroboscopicTimes`.
    events : list of callables or None
    options : dict
        Method options (``taylor_options``), validated by :meth:`Integrator.check`; the
        variational equations' ``renormalise``
        (:class:`~chaplygin.numerics.integrators.flows.Renormalisation`), a batch's
        ``lockstep``.
    max_steps : int or None
        Step limit (None: the method's default).
    max_wall_s : float or None
        Wall-time limit in seconds (None: none).
    dense_output : bool
        Keep the solution between the outputs (``Solution.dense``; the Taylor method in
        double precision).
    """

    system: Flow | ModelCode
    y0: Any
    t_span: tuple | None
    params: Any
    precision: Precision
    rtol: float
    atol: float
    t_eval: Any = None
    events: list | None = None
    options: dict = field(default_factory=dict)
    max_steps: int | None = None
    max_wall_s: float | None = None
    dense_output: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.system, ModelCode):
            object.__setattr__(self, "system", ModelFlow(self.system))

    @property
    def code(self) -> ModelCode:
        """The generated code of the model the flow is made from."""
        return self.system.code


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
    """What :meth:`Integrator.solve` returns; :meth:`Integrator.run` adds the evidence.

    ``y`` has one column per output time (a batch: shape ``(N, count, n_state)``, its
    points' own status and work counters in ``info``). ``backend`` (when not None) replaces
    the one ``_prepare`` chose (the Taylor method reports the library it ran on). ``dense``
    is the solution between the outputs when the problem asked for it.
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
    dense: Any = None


class Integrator:
    """Base of the integration methods: the public call and the bookkeeping.

    A method sets the class attributes and fills :meth:`_solve` (and :meth:`_prepare`
    when it has compiled parts); :meth:`solve` and :meth:`run` do the rest.

    Attributes
    ----------
    name : str
        Key in :data:`INTEGRATORS` (and :data:`METHODS` when it integrates a model's own
        equations).
    flows : tuple of Flow subclasses
        The right-hand sides it integrates.
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
    flows: ClassVar[tuple[type[Flow], ...]] = (ModelFlow,)
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
                f'not {precision!r}; use method="{precision.default_method}" or '
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

    def check_problem(self, problem: Problem, backend: str = "auto") -> None:
        """Refuse a flow or backend this method does not integrate on.

        Parameters
        ----------
        problem : Problem
        backend : {"auto", "c", "numpy"}

        Raises
        ------
        UserInputError
            An unknown backend, or a flow outside :attr:`flows`.
        """
        if backend not in BACKENDS:
            raise UserInputError(f"unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
        if not isinstance(problem.system, self.flows):
            raise UserInputError(
                f"method {self.name} does not integrate {problem.system.what}; it integrates "
                + ", ".join(flow.what for flow in self.flows)
            )

    def prepare(self, problem: Problem, backend: str = "auto") -> str:
        """Check the problem's flow and compile or load what the method runs on.

        Parameters
        ----------
        problem : Problem
        backend : {"auto", "c", "numpy"}
            Where the right-hand side runs: compiled C, numpy, or C when it is available.

        Returns
        -------
        str
            The backend chosen.

        Raises
        ------
        UserInputError
            As :meth:`check_problem`; ``backend="c"`` without a compiler.
        """
        self.check_problem(problem, backend)
        with warnings.catch_warnings():
            if backend == "auto":  # say once that the compiled code is unavailable
                warnings.simplefilter("default")
            return self._prepare(problem, backend)

    def solve(self, problem: Problem, backend: str = "auto", *, chosen: str | None = None
              ) -> Solution:
        """Integrate ``problem``: the door every integration of the project goes through.

        Parameters
        ----------
        problem : Problem
            The flow, initial state, span, parameters, precision and tolerances.
        backend : {"auto", "c", "numpy"}
            Where the right-hand side runs (:meth:`prepare`).
        chosen : str, optional
            A backend :meth:`prepare` already chose for this problem (no second check).

        Returns
        -------
        Solution
            The outputs, status and message, work counters and method-specific ``info``.

        Raises
        ------
        UserInputError
            As :meth:`prepare`.
        """
        if chosen is None:
            chosen = self.prepare(problem, backend)
        with problem.precision.context():
            sol = self._solve(problem, chosen)
        if sol.backend is None:
            sol.backend = chosen
        return sol

    def run(
        self, problem: Problem, backend: str = "auto", setup_s: float = 0.0
    ) -> IntegrationResult:
        """Integrate a model's equations and return the result with its evidence.

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
            An unknown ``backend``; a flow other than a model's equations (forward or
            reversed: the evidence is the drift of the model's integrals).
        """
        start = time.perf_counter()
        if not isinstance(problem.system, ModelFlow | ReversedFlow):
            raise UserInputError(
                f"run() gives the evidence of a model's run; integrate {problem.system.what} "
                "with solve()"
            )
        chosen = self.prepare(problem, backend)
        setup_s += time.perf_counter() - start
        start = time.perf_counter()
        sol = self.solve(problem, chosen=chosen)
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
        # mpf values show themselves at the run's precision, not at the global mp.dps
        shown = (lambda v: v) if prec.is_double else (lambda v: shown_at(v, prec.prec))
        return IntegrationResult(
            status=status,
            message=message,
            t=shown(np.asarray(sol.t)),
            y=shown(sol.y),
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
            params={k: shown(v) for k, v in zip(code.params, p, strict=True)},
            t_events=[shown(te) for te in sol.t_events],
            y_events=[shown(ye) for ye in sol.y_events],
            info=sol.info,
            rtol=float(problem.rtol),
            atol=float(problem.atol),
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
    integral_change = _integral_change_numpy if precision.is_double else _integral_change_mpmath
    with precision.context():
        change, ref = integral_change(code, t, y, p, compiled)
    zero = precision.zero
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
