"""The one integration entry point: a driver over integrator classes, and its result.

:func:`integrate` reads the user's inputs at the working precision and hands a
:class:`Problem` to an :class:`Integrator`. The base class owns the public call
(:meth:`Integrator.run`: backend choice and set-up, the precision context, timing, the
finiteness check and the drift of every first integral) and a method fills in the
``_prepare`` and ``_solve`` hooks; a method is mostly data: its name, the precisions it
works in, its tolerance floor per precision, whether it locates events, the options it
takes (scipy ``integrate/_ivp``: ``OdeSolver`` and ``RK45``). :data:`METHODS` maps names to
classes; ``method`` may also be a class or an instance.

Everything that depends on the precision (default method and tolerances, the mpmath
context, how integrals are evaluated, when an integral counts as zero) is one row of
:data:`NUMBER_TYPES` (heyoka's ``fp_type``), not a branch.
"""

from __future__ import annotations

import html
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, field
from typing import Any, ClassVar

import mpmath
import numpy as np
from scipy.integrate import solve_ivp

from ..derive.errors import UserInputError
from .code import ModelCode, load_model_code
from .inputs import UNIT_TOLERANCE, Precision, pack_params, pack_state, working_number

__all__ = [
    "IntegrationResult",
    "integrate",
    "METHODS",
    "NUMBER_TYPES",
    "NumberType",
    "Integrator",
    "Problem",
    "Solution",
    "ScipyMethod",
    "RK45",
    "DOP853",
    "LSODA",
    "Radau",
    "BDF",
    "TaylorMethod",
    "MpmathOdefun",
    "get_integrator",
]

BACKENDS = ("auto", "c", "numpy")


def _short(value: object, digits: int = 6) -> str:
    """A number in a few significant digits (float or mpmath.mpf)."""
    if isinstance(value, mpmath.mpf):
        return mpmath.nstr(value, digits)
    try:
        return f"{float(value):.{digits}g}"
    except (TypeError, ValueError):
        return repr(value)


def _short_array(values: Sequence, edge: int = 2) -> str:
    """``[a b ... y z] (n)``: the first and last ``edge`` entries of a 1-d sequence."""
    items = list(values)
    if len(items) <= 2 * edge + 1:
        return "[" + " ".join(_short(v) for v in items) + "]"
    shown = [_short(v) for v in items[:edge]] + ["..."] + [_short(v) for v in items[-edge:]]
    return "[" + " ".join(shown) + f"] ({len(items)})"


@dataclass
class IntegrationResult:
    """Outcome of :func:`integrate`, with its error evidence.

    Attributes
    ----------
    status : int
        0: reached the end; negative: failed (see ``message``).
    message : str
        What happened and, on failure, what to do.
    t : ndarray, shape (n_points,)
    y : ndarray, shape (n_state, n_points)
        ``float64`` in double precision, ``object`` (mpmath.mpf) at higher precision.
    state_names : tuple of str
    drift : dict of str to float
        ``max_t |F(t) - F(0)| / |F(0)|`` over the output points, for every first integral
        of the model; where ``|F(0)|`` is below the square root of the working precision
        (``(alpha, beta) = 0``) the absolute change, and the name is in ``drift_absolute``.
    nfev, njev, nsteps : int
        Work counters.
    wall_s : float
        Wall time of the integration (compilation and set-up excluded, see ``setup_s``).
    precision : str
    method, backend : str
    t_events, y_events : list
        For each event function, the times (array) and states (rows) where it fired.
    info : dict
        Method-specific evidence (the Taylor method: ``order_min``, ``order_max``,
        ``rtol``, ``atol``, ``taylor_backend``).
    """

    status: int
    message: str
    t: np.ndarray
    y: np.ndarray
    state_names: tuple[str, ...]
    drift: dict[str, float]
    drift_absolute: tuple[str, ...]
    nfev: int
    njev: int
    nsteps: int
    wall_s: float
    setup_s: float
    precision: str
    method: str
    backend: str
    model: str
    params: dict[str, object] = field(default_factory=dict)
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)
    info: dict[str, object] = field(default_factory=dict)

    @property
    def success(self) -> bool:
        """``status == 0``."""
        return self.status == 0

    @property
    def y_final(self) -> dict[str, object]:
        """Final state by name."""
        return dict(zip(self.state_names, self.y[:, -1], strict=True))

    def _summary(self) -> list[tuple[str, str]]:
        """``(key, short text)`` rows shared by ``__repr__`` and ``_repr_html_``."""
        message = self.message if len(self.message) <= 72 else self.message[:69] + "..."
        final = self.y_final if self.y.shape[-1] else {}
        shown = list(final.items())[:4]
        more = f", ... ({len(final)})" if len(final) > len(shown) else ""
        rows = [
            ("model", f"{self.model}: {self.method} ({self.backend}), {self.precision}"),
            ("success", f"{self.success} (status {self.status}): {message}"),
            ("t", _short_array(self.t)),
            ("y_final", ", ".join(f"{k}={_short(v)}" for k, v in shown) + more),
            ("drift", ", ".join(f"{k} {_short(v, 2)}" for k, v in self.drift.items())),
            (
                "work",
                f"nfev {self.nfev}, njev {self.njev}, nsteps {self.nsteps}; "
                f"wall {self.wall_s:.3g} s, setup {self.setup_s:.3g} s",
            ),
        ]
        if self.t_events:
            rows.append(("t_events", ", ".join(f"{len(te)} times" for te in self.t_events)))
        return rows

    def __repr__(self) -> str:
        width = max(len(k) for k, _ in self._summary())
        lines = [f"{k.rjust(width)}: {v}" for k, v in self._summary()]
        return "IntegrationResult(\n  " + "\n  ".join(lines) + "\n)"

    def _repr_html_(self) -> str:
        cells = "".join(
            f"<tr><th style='text-align:right'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(v)}</td></tr>"
            for k, v in self._summary()
        )
        return f"<table><caption>IntegrationResult</caption>{cells}</table>"


# --------------------------------------------------------------------------- precisions


def _integral_change_numpy(code: ModelCode, t, y, p) -> tuple:
    # t has one entry per output point: integrals may depend on time explicitly
    values = np.asarray(
        code.numpy.integrals(np.asarray(t, dtype=float), y, np.asarray(p, dtype=float))
    )
    F0 = values[:, :1]
    return np.max(np.abs(values - F0), axis=1), np.abs(F0[:, 0])


def _integral_change_mpmath(code: ModelCode, t, y, p) -> tuple:
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
        ``(code, t, y, p) -> (max |F(t) - F(0)|, |F(0)|)`` per integral.
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
        default_method="DOP853",
        default_tolerances=lambda prec: (1e-10, 1e-12),
        context=lambda prec: nullcontext(),
        integral_change=_integral_change_numpy,
        zero=lambda prec: float(np.sqrt(np.finfo(float).eps)),
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

        Returns
        -------
        float
        """
        return self.rtol_floor[precision.kind] * precision.epsilon

    def check(self, precision: Precision, rtol: float, events, options: Mapping) -> None:
        """Refuse a precision, tolerance, events or options this method cannot honour.

        Parameters
        ----------
        precision : Precision
        rtol : float
        events : sequence or None
        options : mapping

        Raises
        ------
        UserInputError
            The message names what works instead.
        """
        kind = precision.kind
        if kind not in self.precisions:
            raise UserInputError(
                f"method {self.name} works in {' or '.join(self.precisions)} precision, "
                f"not {precision!r}; use --method {NUMBER_TYPES[kind].default_method} or "
                f"--precision {' or '.join(self.precisions)}"
            )
        if events and not self.supports_events:
            raise UserInputError(f"method {self.name} does not locate events; use taylor")
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

    def run(self, problem: Problem, backend: str = "auto", setup_s: float = 0.0):
        """Integrate ``problem`` and return the result with its evidence.

        Chooses the backend and prepares compiled parts (set-up time), runs :meth:`_solve`
        in the precision's context (wall time), flags a non-finite solution or drift and
        measures the drift of every first integral.

        Parameters
        ----------
        problem : Problem
        backend : {"auto", "c", "numpy"}
        setup_s : float
            Set-up time already spent (reading the inputs), added to ``setup_s``.

        Returns
        -------
        IntegrationResult
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
        wall = time.perf_counter() - start
        status, message = int(sol.status), str(sol.message)
        if not _all_finite(sol.y):
            status = -1
            message = "the solution became NaN or infinite; check the parameters and state"
        code, p = problem.code, problem.params
        drift, absolute = _drift(code, sol.t, sol.y, p, prec)
        bad = [name for name, v in drift.items() if not np.isfinite(v)]
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


# --------------------------------------------------------------------------- methods


def _scipy_event(g):
    """``g(t, y)`` as scipy calls events (with the ``args``), keeping terminal/direction."""

    def event(t, y, *args):
        return g(t, y)

    event.terminal = getattr(g, "terminal", False)
    event.direction = getattr(g, "direction", 0)
    return event


class ScipyMethod(Integrator):
    """A ``scipy.integrate.solve_ivp`` method in double precision, on the generated C or
    numpy right-hand side; implicit methods get the generated Jacobian."""

    implicit: ClassVar[bool] = False
    supports_events = True
    backends = ("c", "numpy")

    def _prepare(self, problem: Problem, backend: str) -> str:
        if backend == "numpy":
            return "numpy"
        chosen = "c" if problem.code.compiled() is not None else "numpy"
        if backend == "c" and chosen != "c":
            raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
        return chosen

    def _solve(self, problem: Problem, backend: str) -> Solution:
        code = problem.code
        kwargs = {}
        if problem.events:
            kwargs["events"] = [_scipy_event(g) for g in problem.events]
        lib = code.compiled() if backend == "c" else code.numpy
        if self.implicit:
            kwargs["jac"] = lib.jac
        sol = solve_ivp(
            lib.rhs,
            problem.t_span,
            np.asarray(problem.y0, dtype=float),
            method=self.name,
            rtol=problem.rtol,
            atol=problem.atol,
            args=(np.asarray(problem.params, dtype=float),),
            t_eval=problem.t_eval,
            **kwargs,
        )
        message = sol.message
        if sol.status != 0:
            message += "; try a smaller rtol/atol, an implicit method (Radau, LSODA) or more digits"
        return Solution(
            t=sol.t,
            y=sol.y,
            status=sol.status,
            message=message,
            nfev=sol.nfev,
            njev=sol.njev,
            nsteps=len(sol.t) - 1,
            t_events=list(sol.t_events) if problem.events else [],
            y_events=list(sol.y_events) if problem.events else [],
        )


class RK45(ScipyMethod):
    """scipy's explicit Runge-Kutta 5(4) (Dormand-Prince)."""

    name = "RK45"


class DOP853(ScipyMethod):
    """scipy's explicit Runge-Kutta 8(5,3) (Hairer's DOP853)."""

    name = "DOP853"


class LSODA(ScipyMethod):
    """scipy's LSODA (Adams/BDF switching), with the generated Jacobian."""

    name = "LSODA"
    implicit = True


class Radau(ScipyMethod):
    """scipy's implicit Runge-Kutta Radau IIA of order 5, with the generated Jacobian."""

    name = "Radau"
    implicit = True


class BDF(ScipyMethod):
    """scipy's variable-order BDF, with the generated Jacobian."""

    name = "BDF"
    implicit = True


class MpmathOdefun(Integrator):
    """``mpmath.odefun``: mpmath's Taylor-series method at the working precision (baseline).

    Kept for comparison with :class:`TaylorMethod`; it ignores rtol/atol (it works to the
    full working precision) and supports no events.
    """

    name = "odefun"
    precisions = ("quad", "digits")
    rtol_floor = {"quad": 10.0, "digits": 10.0}

    def _solve(self, problem: Problem, backend: str) -> Solution:
        counter = [0]
        rhs, p = problem.code.mpmath.rhs, problem.params

        def F(t, y):
            counter[0] += 1
            return rhs(t, y, p)

        t0, t1 = (mpmath.mpf(v) for v in problem.t_span)
        solution = mpmath.odefun(F, t0, list(problem.y0))
        t_eval = problem.t_eval
        times = list(t_eval) if t_eval is not None else list(mpmath.linspace(t0, t1, 11))
        y = np.array([solution(mpmath.mpf(t)) for t in times], dtype=object).T
        return Solution(
            t=np.array(times, dtype=object),
            y=y,
            status=0,
            message="reached t_end",
            nfev=counter[0],
            nsteps=len(times) - 1,
        )


class TaylorMethod(Integrator):
    """Taylor method generated from the model (:mod:`chaplygin.numerics.taylor`).

    Adaptive order and step (Jorba-Zou) from rtol/atol, dense output, event location.
    ``double`` and ``quad`` run in compiled C (``backend="numpy"`` or no compiler: the
    Python recurrences), digits in Python with MPFR numbers. Its step control works to
    the unit roundoff: the tolerance floor is 1 eps in every precision.
    """

    name = "taylor"
    precisions = ("double", "quad", "digits")
    rtol_floor = {"double": 1.0, "quad": 1.0, "digits": 1.0}
    supports_events = True
    options = ("order", "step", "max_steps")
    backends = ("c", "numpy", "mpmath")

    #: precision kinds with a compiled C integrator (``double``, ``__float128``)
    compiled: ClassVar[tuple[str, ...]] = ("double", "quad")
    #: number library of the Python recurrences, per precision kind (``backend="numpy"``)
    python_libs: ClassVar[Mapping[str, str]] = {
        "double": "float",
        "quad": "gmpy2",
        "digits": "gmpy2",
    }

    def _prepare(self, problem: Problem, backend: str) -> str:
        from .taylor import load_taylor_library

        kind = problem.precision.kind
        if backend == "numpy":
            return "numpy"
        if kind not in self.compiled:  # MPFR in Python: nothing to compile
            return "mpmath"
        # compile or load now: set-up, not wall time
        if load_taylor_library(problem.code, kind) is None and backend == "c":
            raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
        return "c"

    def _solve(self, problem: Problem, backend: str) -> Solution:
        from .taylor import taylor_solve

        kind = problem.precision.kind
        sol = taylor_solve(
            problem.code,
            problem.y0,
            problem.t_span,
            problem.params,
            precision=kind,
            rtol=problem.rtol,
            atol=problem.atol,
            t_eval=problem.t_eval,
            events=problem.events,
            lib=self.python_libs[kind] if backend == "numpy" else None,
            **problem.options,
        )
        return Solution(
            t=sol.t,
            y=sol.y,
            status=sol.status,
            message=f"{sol.message}; orders {sol.order_min}..{sol.order_max} ({sol.backend})",
            nfev=sol.nsteps,
            nsteps=sol.nsteps,
            backend=sol.backend,
            t_events=sol.t_events,
            y_events=sol.y_events,
            info={
                "order_min": sol.order_min,
                "order_max": sol.order_max,
                "taylor_backend": sol.backend,
                "rtol": problem.rtol,
                "atol": problem.atol,
            },
        )


#: Integration methods by name (scipy ``ivp.METHODS``).
METHODS: dict[str, type[Integrator]] = {
    cls.name: cls for cls in (RK45, DOP853, LSODA, Radau, BDF, TaylorMethod, MpmathOdefun)
}


def get_integrator(method: str | Integrator | type[Integrator]) -> Integrator:
    """An integrator by name (a key of :data:`METHODS`), class or instance.

    Parameters
    ----------
    method : str, Integrator subclass or Integrator

    Returns
    -------
    Integrator

    Raises
    ------
    UserInputError
        An unknown name; the message lists the valid ones.
    """
    if isinstance(method, Integrator):
        return method
    if isinstance(method, type) and issubclass(method, Integrator):
        return method()
    if isinstance(method, str) and method in METHODS:
        return METHODS[method]()
    raise UserInputError(f"unknown method {method!r}; valid methods: {', '.join(METHODS)}")


# --------------------------------------------------------------------------- driver


def _check_relations(code: ModelCode, t0: float, y, p) -> None:
    """Refuse an initial state off the model's invariant relations (no twist ...).

    A relation ``(omega, e) = 0`` must hold to :data:`UNIT_TOLERANCE` relative to
    ``|omega|``. The message gives the nearest momentum that satisfies it: the
    relations are linear in ``M``, so the correction is a least-squares projection.
    """
    names = code.relation_names
    if not names:
        return
    idx = [code.integral_names.index(n) for n in names]
    with mpmath.workdps(30):
        # the values the integration will use, exactly (a float is its binary value)
        yv = [mpmath.mpf(v) for v in y]
        pv = [mpmath.mpf(v) for v in p]
        t = mpmath.mpf(t0)

        def relations(state):
            values = code.mpmath.integrals(t, state, pv)
            return mpmath.matrix([values[i] for i in idx])

        aux = code.mpmath.aux(t, yv, pv)
        omega = [aux[code.aux_names.index(f"omega{i}")] for i in (1, 2, 3)]
        scale = mpmath.sqrt(sum(w**2 for w in omega))
        r = relations(yv)
        worst = max(abs(v) for v in r)
        if worst <= UNIT_TOLERANCE * max(scale, mpmath.mpf(1)):
            return
        M = [code.state.index(f"M{i}") for i in (1, 2, 3)]
        L = mpmath.matrix(len(idx), 3)
        for j, k in enumerate(M):
            e = list(yv)
            e[k] = yv[k] + 1
            col = relations(e) - r
            for i in range(len(idx)):
                L[i, j] = col[i]
        shift = L.T * mpmath.lu_solve(L * L.T, r)
        fixed = [yv[k] - shift[j] for j, k in enumerate(M)]
    what = ", ".join(f"{n} = {mpmath.nstr(v, 6)}" for n, v in zip(names, r, strict=True))
    raise UserInputError(
        f"the initial state is off the phase space of {code.name}: {what} must be 0 "
        f"(|omega| = {mpmath.nstr(scale, 6)}); the nearest admissible momentum is "
        f"M={','.join(mpmath.nstr(v, 15) for v in fixed)}"
    )


def _drift(code: ModelCode, t, y: np.ndarray, p, precision: Precision):
    """Largest change of every first integral over the output (relative, or absolute where
    the integral starts at zero to within the square root of the working precision)."""
    number_type = NUMBER_TYPES[precision.kind]
    with number_type.context(precision):
        change, ref = number_type.integral_change(code, t, y, p)
    zero = number_type.zero(precision)
    drift, absolute = {}, []
    for i, name in enumerate(code.integral_names):
        if ref[i] <= zero:
            drift[name] = float(change[i])
            absolute.append(name)
        else:
            drift[name] = float(change[i] / ref[i])
    return drift, tuple(absolute)


def _tolerances(rtol, atol, precision: Precision) -> tuple[float, float]:
    """``rtol, atol`` as positive finite floats, the precision's defaults where None."""
    default_rtol, default_atol = NUMBER_TYPES[precision.kind].default_tolerances(precision)
    rtol = default_rtol if rtol is None else rtol
    atol = default_atol if atol is None else atol
    try:
        rtol, atol = float(rtol), float(atol)
    except (TypeError, ValueError):
        raise UserInputError("rtol and atol must be positive finite numbers") from None
    if not (rtol > 0 and atol > 0 and np.isfinite(rtol) and np.isfinite(atol)):
        raise UserInputError("rtol and atol must be positive finite numbers")
    return rtol, atol


def integrate(
    system: str | ModelCode,
    y0: Mapping[str, object] | Sequence[float],
    t_span: tuple[float, float] | float,
    params: Mapping[str, object] | Sequence[float],
    *,
    effects: Sequence[str] | str | None = None,
    method: str | Integrator | type[Integrator] | None = None,
    precision: str | int = "double",
    rtol: float | None = None,
    atol: float | None = None,
    backend: str = "auto",
    t_eval: Sequence[float] | None = None,
    events: Sequence | None = None,
    taylor_options: Mapping[str, object] | None = None,
) -> IntegrationResult:
    """Integrate a model and report the drift of every first integral.

    Parameters
    ----------
    system : str or ModelCode
        ``"chaplygin_ball"`` (with ``effects``) or loaded code.
    y0 : mapping or sequence
        Initial state by group (``{"M": (0.7, -0.4, 0.5), "gamma": (...)}``; strings are
        parsed safely) or a full state vector in the model's order.
    t_span : (t0, t1) or float
        A single number means ``(0, t1)``.
    params : mapping or sequence
        ``{"I": (1, 2, 3), "D": 1}`` or a vector in the model's parameter order.
    effects : sequence of str or str, optional
    method : str, Integrator class or instance, optional
        A key of :data:`METHODS`; default ``DOP853`` in double precision and ``taylor``
        (the generated Taylor integrator) in quad and digits; ``odefun`` is
        ``mpmath.odefun`` (for comparison).
    precision : "double", "quad" or int
        IEEE double, IEEE binary128 (``__float128``, 34 digits; Taylor in C) or a number
        of decimal digits (mpmath/MPFR).
    rtol, atol : float, optional
        Tolerances. Default 1e-10 and 1e-12 in double; in quad and digits both default to
        the smallest the precision delivers (:attr:`Precision.min_rtol`: 10 eps).
    backend : {"auto", "c", "numpy"}
        Compiled C (``auto`` falls back to Python/numpy, with a warning, when there is no C
        compiler) or numpy/Python.
    t_eval : sequence of float, optional
        Output times (default: every step for scipy in double, else 11 points).
    events : sequence of callables, optional
        ``g(t, y)``: sign changes are located (Taylor: on the dense output to the working
        precision; scipy: its own root finder); scipy attributes ``terminal`` and
        ``direction`` are honoured. Times and states in ``t_events``, ``y_events``.
    taylor_options : mapping, optional
        ``order`` and/or ``step`` (fixed order, fixed step) or ``max_steps`` for the Taylor
        method.

    Returns
    -------
    IntegrationResult

    Raises
    ------
    UserInputError
        Unknown system, effect, method, parameter or state name; wrong lengths;
        non-physical or non-finite values; a tolerance the precision cannot deliver (the
        message names a precision that can).

    Examples
    --------
    >>> r = integrate("chaplygin_ball", {"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")},
    ...               10.0, {"I": (1, 2, 3), "D": 1}, rtol=1e-12, atol=1e-12)
    >>> r.success and r.drift["H"] < 1e-10
    True
    """
    start = time.perf_counter()
    code = system if isinstance(system, ModelCode) else load_model_code(system, effects)
    prec = Precision(precision)
    if method is None:
        method = NUMBER_TYPES[prec.kind].default_method
    integrator = get_integrator(method)
    rtol, atol = _tolerances(rtol, atol, prec)
    options = dict(taylor_options or {})
    integrator.check(prec, rtol, events, options)
    if options.get("step") is not None:
        options["step"] = working_number(options["step"], prec)
    t_span = _time_span(t_span, prec)
    if t_eval is not None:
        t_eval = [working_number(v, prec) for v in _sequence(t_eval, "t_eval")]
    if isinstance(params, Mapping):
        p = pack_params(code, params, prec)
    else:
        p = _vector(params, len(code.params), "parameter vector", prec)
    if isinstance(y0, Mapping):
        y = pack_state(code, y0, prec)
    else:
        y = _vector(y0, len(code.state), "state vector", prec)
    _check_relations(code, t_span[0], y, p)
    problem = Problem(
        code=code,
        y0=y,
        t_span=t_span,
        params=p,
        precision=prec,
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
        events=list(events) if events else None,
        options=options,
    )
    return integrator.run(problem, backend, setup_s=time.perf_counter() - start)


def _precision_for(rtol: float) -> str:
    """A precision that delivers ``rtol`` with any method (for error messages).

    ``quad`` (Taylor) when its unit roundoff suffices, else ``d`` digits with
    ``10**(2 - d) <= rtol``: both the Taylor floor (eps) and odefun's (10 eps) are met.
    """
    if rtol >= Precision("quad").epsilon * (1 - 1e-9):
        return "--precision quad (--method taylor)"
    return f"--precision {max(int(np.ceil(-np.log10(rtol) - 1e-9)) + 2, 16)}"


def _sequence(values, what: str) -> list:
    if isinstance(values, str | bytes) or not hasattr(values, "__len__"):
        raise UserInputError(f"{what} must be a sequence of numbers, got {values!r}")
    return list(values)


def _vector(values, n: int, what: str, prec: Precision) -> list:
    vals = _sequence(values, f"the {what}")
    if len(vals) != n:
        raise UserInputError(f"the {what} needs {n} entries, got {len(vals)}")
    return [working_number(v, prec) for v in vals]


def _time_span(t_span, prec: Precision) -> tuple:
    """``(t0, t1)`` at the working precision; a single number means ``(0, t1)``."""
    if isinstance(t_span, str | bytes) or not hasattr(t_span, "__len__"):
        t_span = (0, t_span)
    items = list(t_span)
    if len(items) != 2:
        raise UserInputError(f"t_span must be (t0, t1) or a single end time, got {t_span!r}")
    t0, t1 = (working_number(v, prec) for v in items)
    if t1 == t0:
        raise UserInputError("the time span must be finite and non-empty")
    return t0, t1


def _all_finite(ys) -> bool:
    arr = np.asarray(ys)
    if arr.dtype != object:
        return bool(np.all(np.isfinite(arr)))
    return all(mpmath.isfinite(v) for v in arr.ravel())
