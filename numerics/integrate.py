"""The one integration entry point and the result object that carries its evidence."""

from __future__ import annotations

import time
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import mpmath
import numpy as np
from scipy.integrate import solve_ivp

from ..derive.errors import UserInputError
from .code import ModelCode, load_model_code
from .inputs import UNIT_TOLERANCE, Precision, pack_params, pack_state, working_number

__all__ = ["IntegrationResult", "integrate", "METHODS", "Integrator"]


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
        ``rtol``, ``atol``).
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
        return self.status == 0

    @property
    def y_final(self) -> dict[str, object]:
        """Final state by name."""
        return dict(zip(self.state_names, self.y[:, -1], strict=True))


class Integrator:
    """Base of the integration methods: the public call and the bookkeeping.

    Subclasses fill :meth:`_solve`, returning ``(t, y, nfev, njev, nsteps, status, msg)``;
    ``options`` holds ``precision`` (a :class:`~chaplygin.numerics.inputs.Precision`),
    ``events`` and ``info`` (a dict the method may fill with events and evidence).
    """

    name = ""
    precisions = ("double",)
    supports_events = False

    def _solve(self, code, y0, t_span, p, rtol, atol, backend, t_eval, **options):
        raise NotImplementedError  # pragma: no cover


class ScipyMethod(Integrator):
    """A ``scipy.integrate.solve_ivp`` method; implicit ones get the generated Jacobian."""

    implicit = False

    def __init__(self, name: str, implicit: bool = False):
        self.name = name
        self.implicit = implicit

    supports_events = True

    def _solve(self, code, y0, t_span, p, rtol, atol, backend, t_eval, **options):
        p = np.asarray(p, dtype=float)
        kwargs = {}
        events = options.get("events") or None
        if events is not None:
            kwargs["events"] = [_scipy_event(g) for g in events]
        if backend == "c":
            lib = code.compiled()
            fun, jac = lib.rhs, lib.jac
        else:
            fun, jac = code.numpy.rhs, code.numpy.jac
        if self.implicit:
            kwargs["jac"] = jac
        sol = solve_ivp(
            fun,
            t_span,
            np.asarray(y0, dtype=float),
            method=self.name,
            rtol=rtol,
            atol=atol,
            args=(p,),
            t_eval=t_eval,
            **kwargs,
        )
        msg = sol.message
        if events is not None:
            options["info"]["t_events"] = list(sol.t_events)
            options["info"]["y_events"] = list(sol.y_events)
        if sol.status != 0:
            msg += "; try a smaller rtol/atol, an implicit method (Radau, LSODA) or more digits"
        return sol.t, sol.y, sol.nfev, sol.njev, len(sol.t) - 1, sol.status, msg


def _scipy_event(g):
    """``g(t, y)`` as scipy calls events (with the ``args``), keeping terminal/direction."""

    def event(t, y, *args):
        return g(t, y)

    event.terminal = getattr(g, "terminal", False)
    event.direction = getattr(g, "direction", 0)
    return event


class MpmathOdefun(Integrator):
    """``mpmath.odefun``: mpmath's Taylor-series method at the working precision (baseline).

    Kept for comparison with :class:`TaylorMethod`; it ignores rtol/atol (it works to the
    full working precision) and supports no events.
    """

    name = "odefun"
    precisions = ("quad", "digits")

    def _solve(self, code, y0, t_span, p, rtol, atol, backend, t_eval, **options):
        counter = [0]
        rhs = code.mpmath.rhs

        def F(t, y):
            counter[0] += 1
            return rhs(t, y, p)

        t0, t1 = (mpmath.mpf(t_span[0]), mpmath.mpf(t_span[1]))
        solution = mpmath.odefun(F, t0, list(y0))
        times = list(t_eval) if t_eval is not None else list(mpmath.linspace(t0, t1, 11))
        ys = [solution(mpmath.mpf(t)) for t in times]
        y = np.array(ys, dtype=object).T
        return np.array(times, dtype=object), y, counter[0], 0, len(times) - 1, 0, "reached t_end"


class TaylorMethod(Integrator):
    """Taylor method generated from the model (:mod:`chaplygin.numerics.taylor`).

    Adaptive order and step (Jorba-Zou) from rtol/atol, dense output, event location.
    ``double`` and ``quad`` run in compiled C (``backend="numpy"`` or no compiler: the
    Python recurrences), digits in Python with MPFR numbers.
    """

    name = "taylor"
    precisions = ("double", "quad", "digits")
    supports_events = True

    def _solve(self, code, y0, t_span, p, rtol, atol, backend, t_eval, **options):
        from .taylor import taylor_solve

        prec = options["precision"]
        lib = None
        if backend == "numpy":
            lib = "float" if prec.is_double else "gmpy2"
        sol = taylor_solve(
            code,
            y0,
            t_span,
            p,
            precision=prec.kind,
            rtol=rtol,
            atol=atol,
            t_eval=t_eval,
            events=options.get("events"),
            lib=lib,
            **options.get("taylor", {}),
        )
        info = options["info"]
        info.update(
            t_events=sol.t_events,
            y_events=sol.y_events,
            order_min=sol.order_min,
            order_max=sol.order_max,
            taylor_backend=sol.backend,
            rtol=rtol,
            atol=atol,
        )
        msg = f"{sol.message}; orders {sol.order_min}..{sol.order_max} ({sol.backend})"
        return sol.t, sol.y, sol.nsteps, 0, sol.nsteps, sol.status, msg


METHODS: dict[str, Integrator] = {
    "RK45": ScipyMethod("RK45"),
    "DOP853": ScipyMethod("DOP853"),
    "LSODA": ScipyMethod("LSODA", implicit=True),
    "Radau": ScipyMethod("Radau", implicit=True),
    "BDF": ScipyMethod("BDF", implicit=True),
    "taylor": TaylorMethod(),
    "odefun": MpmathOdefun(),
}


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


def _drift(code: ModelCode, t: np.ndarray, y: np.ndarray, p, precision: Precision):
    if precision.is_double:
        # t has one entry per output point: integrals may depend on time explicitly
        values = np.asarray(
            code.numpy.integrals(np.asarray(t, dtype=float), y, np.asarray(p, dtype=float))
        )
        F0 = values[:, :1]
        change = np.max(np.abs(values - F0), axis=1)
        ref = np.abs(F0[:, 0])
    else:
        with mpmath.workdps(precision.digits):
            rows = [code.mpmath.integrals(t[j], list(y[:, j]), p) for j in range(y.shape[1])]
            F0 = rows[0]
            # NaN compares false: a non-finite value anywhere makes the change NaN
            change = [
                max(abs(r[i] - F0[i]) for r in rows)
                if all(mpmath.isfinite(r[i]) for r in rows)
                else mpmath.nan
                for i in range(len(F0))
            ]
            ref = [abs(v) for v in F0]
    # An integral whose initial value is zero to within the square root of the working
    # precision has no meaningful relative change: report its absolute change instead.
    zero = np.sqrt(np.finfo(float).eps) if precision.is_double else 10.0 ** (-precision.digits / 2)
    drift, absolute = {}, []
    for i, name in enumerate(code.integral_names):
        if ref[i] <= zero:
            drift[name] = float(change[i])
            absolute.append(name)
        else:
            drift[name] = float(change[i] / ref[i])
    return drift, tuple(absolute)


def integrate(
    system: str | ModelCode,
    y0: Mapping[str, object] | Sequence[float],
    t_span: tuple[float, float] | float,
    params: Mapping[str, object] | Sequence[float],
    *,
    effects: Sequence[str] | str | None = None,
    method: str | Integrator | None = None,
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
    method : str or Integrator, optional
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
    if not isinstance(system, ModelCode):
        _refuse_bad_input_before_deriving(system, effects, y0, params, precision)
    code = system if isinstance(system, ModelCode) else load_model_code(system, effects)
    prec = Precision(precision)
    if method is None:
        method = "DOP853" if prec.is_double else "taylor"
    integrator = method if isinstance(method, Integrator) else METHODS.get(method)
    if integrator is None:
        raise UserInputError(f"unknown method {method!r}; valid methods: {', '.join(METHODS)}")
    kind = prec.kind
    if kind not in integrator.precisions:
        raise UserInputError(
            f"method {integrator.name} works in "
            f"{' or '.join(integrator.precisions)} precision, not {prec!r}; "
            + ("use --method taylor" if kind != "double" else "use --precision double")
        )
    if events and not integrator.supports_events:
        raise UserInputError(f"method {integrator.name} does not locate events; use taylor")
    default_rtol, default_atol = (1e-10, 1e-12) if prec.is_double else (prec.min_rtol,) * 2
    rtol = default_rtol if rtol is None else rtol
    atol = default_atol if atol is None else atol
    try:
        rtol, atol = float(rtol), float(atol)
    except (TypeError, ValueError):
        raise UserInputError("rtol and atol must be positive finite numbers") from None
    if not (rtol > 0 and atol > 0 and np.isfinite(rtol) and np.isfinite(atol)):
        raise UserInputError("rtol and atol must be positive finite numbers")
    floor = prec.epsilon if isinstance(integrator, TaylorMethod) else prec.min_rtol
    if rtol < floor * (1 - 1e-9):  # slack: 10.0**-98 against 10 * 10.0**-99 rounding
        raise UserInputError(
            f"rtol={rtol:g} is below what {prec!r} precision can deliver with "
            f"{integrator.name} (about {floor:.1e}); ask for {_precision_for(rtol)}"
        )
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
    if backend not in ("auto", "c", "numpy"):
        raise UserInputError(f"unknown backend {backend!r}; valid: auto, c, numpy")
    chosen = "mpmath" if not prec.is_double else backend
    if prec.is_double and backend in ("auto", "c"):
        with warnings.catch_warnings():
            if backend == "auto":
                warnings.simplefilter("default")
            chosen = "c" if code.compiled() is not None else "numpy"
        if backend == "c" and chosen != "c":
            raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
    if isinstance(integrator, TaylorMethod) and backend == "numpy":
        chosen = "numpy"
    options = {
        "precision": prec,
        "events": list(events) if events else None,
        "info": {},
        "taylor": dict(taylor_options or {}),
    }
    if options["taylor"].get("step") is not None:
        options["taylor"]["step"] = working_number(options["taylor"]["step"], prec)
    if options["taylor"] and not isinstance(integrator, TaylorMethod):
        raise UserInputError("taylor_options apply to method taylor only")
    unknown = set(options["taylor"]) - {"order", "step", "max_steps"}
    if unknown:
        raise UserInputError(f"unknown taylor option(s) {sorted(unknown)}; valid: order, step")
    if isinstance(integrator, TaylorMethod) and chosen != "numpy" and kind != "digits":
        from .taylor import load_taylor_library

        load_taylor_library(code, kind)  # compile or load now: set-up, not wall time
    setup = time.perf_counter() - start
    t0 = time.perf_counter()
    if prec.is_double:
        t, ys, nfev, njev, nsteps, status, msg = integrator._solve(
            code, y, t_span, p, rtol, atol, chosen, t_eval, **options
        )
    else:
        with mpmath.workdps(prec.digits):
            t, ys, nfev, njev, nsteps, status, msg = integrator._solve(
                code, y, t_span, p, rtol, atol, chosen, t_eval, **options
            )
    if isinstance(integrator, TaylorMethod):
        chosen = options["info"]["taylor_backend"]
    wall = time.perf_counter() - t0
    if not _all_finite(ys):
        status, msg = -1, "the solution became NaN or infinite; check the parameters and state"
    drift, absolute = _drift(code, t, ys, p, prec)
    bad = [name for name, v in drift.items() if not np.isfinite(v)]
    if bad and status == 0:
        status = -5
        msg = (
            f"the error evidence is not finite (drift of {', '.join(bad)}): the result cannot "
            "be trusted; check the parameters and state"
        )
    return IntegrationResult(
        status=int(status),
        message=str(msg),
        t=np.asarray(t),
        y=ys,
        state_names=code.state,
        drift=drift,
        drift_absolute=absolute,
        nfev=int(nfev),
        njev=int(njev),
        nsteps=int(nsteps),
        wall_s=wall,
        setup_s=setup,
        precision=repr(prec),
        method=integrator.name,
        backend=chosen,
        model=code.name,
        params=dict(zip(code.params, p, strict=True)),
        t_events=list(options["info"].pop("t_events", [])),
        y_events=list(options["info"].pop("y_events", [])),
        info=options["info"],
    )


def _refuse_bad_input_before_deriving(system, effects, y0, params, precision) -> None:
    """Check parameters and initial state of a variant not in generated/ against its
    signature (derive.systems.variant_signature, no derivation) before deriving it.

    Parameters
    ----------
    system : str
    effects : iterable of str or str or None
    y0, params : mapping or sequence
    precision : str or int

    Raises
    ------
    UserInputError
        Unknown system or effect, conflicting effects, a missing or unknown parameter
        or state group, a bad value.
    """
    from ..derive.systems import builtin_variants, get_system, parse_effects, variant_signature

    chosen = parse_effects(effects, get_system(system).effects)
    if (system, chosen) in builtin_variants():
        return  # its code is generated: nothing to derive
    signature = variant_signature(system, chosen)
    if signature is None:
        return
    prec = Precision(precision)
    if isinstance(params, Mapping):
        pack_params(signature, params, prec)
    if isinstance(y0, Mapping):
        pack_state(signature, y0, prec)


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
