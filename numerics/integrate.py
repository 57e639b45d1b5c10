"""The one integration entry point: :func:`integrate` reads the inputs and runs a method.

Every user number is rounded once to the working precision
(:func:`~chaplygin.numerics.inputs.working_number`); the initial state is checked against
the model's invariant relations; then a :class:`~chaplygin.numerics.integrators.Problem` is
handed to the chosen :class:`~chaplygin.numerics.integrators.Integrator`, whose ``run``
returns an :class:`~chaplygin.numerics.integrators.IntegrationResult` with its evidence.
"""

from __future__ import annotations

import itertools
import threading
import time
from collections.abc import Mapping, Sequence
from fractions import Fraction

import mpmath
import numpy as np

from ..derive.errors import UserInputError
from .code import ModelCode, load_model_code
from .inputs import UNIT_TOLERANCE, Precision, pack_params, pack_state, working_number
from .integrators import (
    METHODS,
    IntegrationResult,
    Integrator,
    ModelFlow,
    Problem,
    get_integrator,
)
from .step_budget import DEFAULT_MAX_STEPS, refuse_hopeless_span

__all__ = [
    "check_output_times",
    "prepare_problem",
    "IntegrationResult",
    "integrate",
    "METHODS",
    "Integrator",
    "get_integrator",
    "DEFAULT_MAX_WALL_S",
]

#: Default wall-time limit of one integration, in seconds (``max_wall_s``; None: none).
DEFAULT_MAX_WALL_S = 3600.0


def _check_relations(code: ModelCode, t0: float, y, p) -> None:
    """Refuse an initial state off the model's invariant relations (no twist ...).

    The relations are linear in the velocity-carrying state (the groups outside the model's
    Poisson geometry), ``r = L v``: each must vanish to :data:`UNIT_TOLERANCE` relative to
    ``|L| |v|``. The message gives the nearest state that satisfies them, ``v - L^T (L
    L^T)^-1 r`` (a least-squares projection), by group.
    """
    names = code.relation_names
    if not names:
        return
    idx = [code.integral_names.index(n) for n in names]
    bound = {n for _, group in code.geometry for n in group}
    free = [s for g, comps in code.state_groups.items() if g not in bound for s in comps]
    with mpmath.workdps(30):
        # the values the integration will use, exactly (a float is its binary value)
        yv = [mpmath.mpf(v) for v in y]
        pv = [mpmath.mpf(v) for v in p]
        t = mpmath.mpf(t0)

        def relations(state):
            values = code.mpmath.integrals(t, state, pv)
            return mpmath.matrix([values[i] for i in idx])

        r = relations(yv)
        columns = {}
        for s in free:
            k = code.state.index(s)
            e = list(yv)
            e[k] = yv[k] + 1
            col = relations(e) - r
            if any(col[i] for i in range(len(idx))):
                columns[k] = col
        keys = list(columns)
        L = mpmath.matrix(len(idx), len(keys))
        for j, k in enumerate(keys):
            for i in range(len(idx)):
                L[i, j] = columns[k][i]
        scale = mpmath.mnorm(L, "F") * mpmath.sqrt(sum(yv[k] ** 2 for k in keys))
        worst = max(abs(v) for v in r)
        if worst <= UNIT_TOLERANCE * max(scale, mpmath.mpf(1)):
            return
        shift = L.T * mpmath.lu_solve(L * L.T, r)
        fixed = {code.state[k]: yv[k] - shift[j] for j, k in enumerate(keys)}
    what = ", ".join(f"{n} = {mpmath.nstr(v, 6)}" for n, v in zip(names, r, strict=True))
    nearest = " ".join(
        f"{g}={','.join(mpmath.nstr(fixed[c], 15) for c in comps)}"
        for g, comps in code.state_groups.items()
        if all(c in fixed for c in comps)
    )
    raise UserInputError(
        f"the initial state is off the phase space of {code.name}: {what} must be 0 "
        f"(relative to {mpmath.nstr(scale, 6)}); the nearest admissible state has {nearest}"
    )


def _check_constraints(code: ModelCode, t0, y: Sequence, p: Sequence) -> None:
    """Refuse an initial state off the phase space the model declares.

    Every phase-space constraint of the model (its generated ``constraints`` routine:
    ``|gamma|^2 = 1``, the frame's orthonormality, the ellipsoid ``(x, B^-1 x) = 1`` ...)
    must hold to :data:`UNIT_TOLERANCE` relative to its scale (the sum of the absolute
    values of its terms), evaluated at 30 digits from the values the integration will use.

    Parameters
    ----------
    code : ModelCode
    t0 : number
        Initial time.
    y, p : sequence
        State and parameters at the working precision.

    Raises
    ------
    UserInputError
        The constraint that fails, its value, and what to do.
    """
    names = code.constraint_names
    if not names:
        return
    with mpmath.workdps(30):
        values = code.mpmath.constraints(
            mpmath.mpf(t0), [mpmath.mpf(v) for v in y], [mpmath.mpf(v) for v in p]
        )
        k = len(names)
        for name, value, scale in zip(names, values[:k], values[k:], strict=True):
            if not abs(value) <= UNIT_TOLERANCE * max(scale, mpmath.mpf(1)):
                raise UserInputError(
                    f"the initial state is off the phase space of {code.name}: {name} fails by "
                    f"{mpmath.nstr(value, 6)} (allowed {UNIT_TOLERANCE:g} relative to its "
                    f"scale {mpmath.nstr(scale, 6)}); give a state on it"
                )


def _tolerances(rtol, atol, precision: Precision) -> tuple[float, float]:
    """``rtol, atol`` as positive finite floats, the precision's defaults where None."""
    default_rtol, default_atol = precision.default_tolerances
    rtol = default_rtol if rtol is None else rtol
    atol = default_atol if atol is None else atol
    if isinstance(rtol, bool | str) or isinstance(atol, bool | str):
        raise UserInputError("rtol and atol must be positive finite numbers, not True/False/text")
    try:
        rtol, atol = float(rtol), float(atol)
    except (TypeError, ValueError, OverflowError):
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
    max_steps: int | None = None,
    max_wall_s: float | None = DEFAULT_MAX_WALL_S,
) -> IntegrationResult:
    """Integrate a model and report the drift of every first integral.

    Parameters
    ----------
    system : str or ModelCode
        ``"chaplygin_ball"`` (with ``effects``) or loaded code.
    y0 : mapping or sequence
        Initial state by group (``{"M": (0.7, -0.4, 0.5), "gamma": (...)}``; strings are
        parsed safely) or a full state vector in the model's order. Groups the model completes
        may be left out (:func:`~chaplygin.numerics.inputs.pack_state`: the contact point's
        ``alpha, beta`` by the one rule of :mod:`chaplygin.numerics.frame`, also on
        M || gamma).
    t_span : (t0, t1) or float
        A single number means ``(0, t1)``.
    params : mapping or sequence
        ``{"I": (1, 2, 3), "D": 1}`` or a vector in the model's parameter order.
    effects : sequence of str or str, optional
    method : str, Integrator class or instance, optional
        A key of :data:`METHODS`; default ``taylor`` (the generated Taylor integrator, the same
        bits on every machine) in every precision; scipy's ``DOP853``, ``RK45``, ``LSODA``,
        ``Radau``, ``BDF`` in double (their last bits depend on the BLAS kernel) and
        ``odefun`` (``mpmath.odefun``) for comparison.
    precision : "double", "quad" or int
        IEEE double, IEEE binary128 (``__float128``, 34 digits; Taylor in C) or a number
        of decimal digits (Taylor in C double-double up to 31 digits, quad-double up to 60,
        MPFR beyond; ``mpmath`` for ``odefun``).
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
    max_steps : int, optional
        Step limit (default: 10^7 for the Taylor method, 10^6 for the scipy methods, whose
        steps are counted as right-hand-side calls over the method's stages); past it the
        result has status -2 and says to raise the limit or shorten the span. Without it, a
        span whose estimated steps exceed 100 times the default limit is refused before any
        work (:func:`~chaplygin.numerics.step_budget.refuse_hopeless_span`).
    max_wall_s : float or None
        Wall-time limit in seconds (default :data:`DEFAULT_MAX_WALL_S`, one hour; None: no
        limit), checked between right-hand-side calls of the scipy methods and
        ``mpmath.odefun``, between steps of the Python Taylor loop and between blocks of
        steps of the compiled one; past it the result has status -6.

    Returns
    -------
    IntegrationResult

    Raises
    ------
    UserInputError
        Unknown system, effect, method, parameter or state name; wrong lengths;
        non-physical or non-finite values; a tolerance the precision cannot deliver (the
        message names a precision that can); output times outside the span; a span that
        could only end at the default step limit.

    Examples
    --------
    >>> r = integrate("chaplygin_ball", {"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")},
    ...               10.0, {"I": (1, 2, 3), "D": 1}, rtol=1e-12, atol=1e-12)
    >>> r.success and r.drift["H"] < 1e-10
    True
    """
    start = time.perf_counter()
    inputs = (system, y0, t_span, params, effects, method, precision, rtol, atol, t_eval,
              events, taylor_options, max_steps, max_wall_s)
    key = _call_key(inputs)
    prepared = _PREPARED.get(key) if key is not None else None
    if prepared is None:
        prepared = prepare_problem(
            system,
            y0,
            t_span,
            params,
            effects=effects,
            method=method,
            precision=precision,
            rtol=rtol,
            atol=atol,
            t_eval=t_eval,
            events=events,
            taylor_options=taylor_options,
            max_steps=max_steps,
            max_wall_s=max_wall_s,
        )
        _keep(key, prepared)
    else:
        result = _run_again(key, prepared, backend, start)
        if result is not None:
            return result
    integrator, problem = prepared
    return integrator.run(problem, backend, setup_s=time.perf_counter() - start)


def _keep(key: tuple | None, prepared: tuple) -> None:
    """Keep a call's checked problem for the same call again (the oldest forgotten first)."""
    if key is not None:
        with _STARTS_LOCK:
            if len(_PREPARED) >= _PREPARED_MAX:
                del _PREPARED[next(iter(_PREPARED))]
            _PREPARED[key] = prepared


def _run_again(key: tuple, prepared: tuple, backend: str, start: float
               ) -> IntegrationResult | None:
    """The result of a call made again, straight from its compiled loop (:func:`_session`),
    or None where the call needs the method's whole path (a step limit, events, the
    default outputs, dense output; not the Taylor method in double on the C backend)."""
    integrator, problem = prepared
    if problem.max_steps is not None or problem.t_eval is None:
        return None
    if problem.events or problem.dense_output:
        return None
    session = _session(key, prepared, backend)
    if session is None:
        return None
    setup_s = time.perf_counter() - start
    start = time.perf_counter()
    sol = session.solve(problem, problem.y0, problem.t_span, problem.t_eval)
    return integrator._result(problem, sol, "c", time.perf_counter() - start, setup_s)


#: Problems :func:`integrate` already read and checked, by its inputs as typed
#: (:func:`_call_key`): the same call again skips :func:`prepare_problem`, whose result
#: depends on those inputs only (and on mpmath's precision, part of the key). A problem is
#: never changed by a run (its lists are packed into C buffers or copied).
_PREPARED: dict[tuple, tuple] = {}
_PREPARED_MAX = 64


#: The compiled loops of calls made again (:func:`_session`), per thread: a loop's buffers are
#: its own while it runs, as :mod:`~chaplygin.numerics.taylor.c_run`'s.
_SESSIONS = threading.local()


def _session(key: tuple, prepared: tuple, backend: str):
    """The method's compiled session of a call made again (its parameters, tolerances and
    buffers converted once, as a :class:`~chaplygin.numerics.propagator.Propagator` keeps
    it: the same loop with the same arguments, so the same bits), or None where the call
    needs the method's whole path (not the Taylor method in double on the C backend)."""
    sessions = getattr(_SESSIONS, "by_key", None)
    if sessions is None:
        sessions = _SESSIONS.by_key = {}
    entry = sessions.get((key, backend))
    if entry is None:
        integrator, problem = prepared
        make = getattr(integrator, "session", None)
        if make is None or type(problem.system) is not ModelFlow:  # forward, a model's equations
            return None
        entry = (make(problem, integrator.prepare(problem, backend)),)
        if len(sessions) >= _PREPARED_MAX:
            del sessions[next(iter(sessions))]
        sessions[(key, backend)] = entry
    return entry[0]


def _call_key(inputs: tuple) -> tuple | None:
    """A hashable key of :func:`integrate`'s inputs as typed, or None when one of them is not
    memoised (a loaded model, an integrator object, events, NaN, other types)."""
    (system, y0, t_span, params, effects, method, precision, rtol, atol, t_eval, events,
     options, max_steps, max_wall_s) = inputs  # fmt: skip
    if not isinstance(system, str) or events is not None:
        return None
    if not (method is None or isinstance(method, str)):
        return None
    keys = [mpmath.mp.prec, system, method]
    for value in (y0, t_span, params, effects, precision, rtol, atol, t_eval, options,
                  max_steps, max_wall_s):  # fmt: skip
        key = ("none",) if value is None else _input_key(value)
        if key is None:
            return None
        keys.append(key)
    return tuple(keys)


def prepare_problem(
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
    t_eval: Sequence[float] | None = None,
    events: Sequence | None = None,
    taylor_options: Mapping[str, object] | None = None,
    max_steps: int | None = None,
    max_wall_s: float | None = DEFAULT_MAX_WALL_S,
) -> tuple[Integrator, Problem]:
    """Read and check the inputs of :func:`integrate` (all of its checks, nothing run).

    Parameters
    ----------
    system, y0, t_span, params, effects, method, precision, rtol, atol, t_eval, events, \
taylor_options, max_steps, max_wall_s
        As for :func:`integrate`.

    Returns
    -------
    (Integrator, Problem)
        The method and the problem, every number at the working precision.

    Raises
    ------
    UserInputError
        As :func:`integrate`.
    """
    if not isinstance(system, ModelCode):
        _refuse_bad_input_before_deriving(system, effects, y0, params, precision)
    code = system if isinstance(system, ModelCode) else load_model_code(system, effects)
    prec = Precision(precision)
    if method is None:
        method = prec.default_method
    integrator = get_integrator(method)
    rtol, atol = _tolerances(rtol, atol, prec)
    options = dict(taylor_options or {})
    integrator.check(prec, rtol, events, options)
    if options.get("step") is not None:
        options["step"] = working_number(options["step"], prec)
    t_span = _time_span(t_span, prec)
    if t_eval is not None:
        values = _sequence(t_eval, "t_eval")
        try:
            t_eval = [working_number(v, prec) for v in values]
        except UserInputError as exc:
            raise UserInputError(f"t_eval: {exc}") from None
        if not t_eval:  # the evidence compares the integrals at the outputs
            raise UserInputError("t_eval must name at least one output time (or be left out)")
        check_output_times(t_eval, t_span)
    if max_steps is not None and not (
        isinstance(max_steps, int) and not isinstance(max_steps, bool) and max_steps >= 1
    ):
        raise UserInputError(f"max_steps must be a positive integer, got {max_steps!r}")
    if max_steps is None and options.get("max_steps") is None:  # the default limit
        hopeless = refuse_hopeless_span(
            abs(float(t_span[1] - t_span[0])),
            integrator.name,
            rtol,
            prec.is_double,
            getattr(integrator, "default_max_steps", DEFAULT_MAX_STEPS),
        )
        if hopeless:
            raise UserInputError(hopeless)
    p, y = _read_start(code, y0, params, prec, t_span[0])
    if max_wall_s is not None:
        try:
            max_wall_s = float(max_wall_s)
        except (TypeError, ValueError):
            raise UserInputError(
                f"max_wall_s must be a positive number, got {max_wall_s!r}"
            ) from None
        if not max_wall_s > 0:
            raise UserInputError(f"max_wall_s must be a positive number, got {max_wall_s!r}")
    return integrator, Problem(
        system=code,
        y0=y,
        t_span=t_span,
        params=p,
        precision=prec,
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
        events=list(events) if events else None,
        options=options,
        max_steps=max_steps,
        max_wall_s=max_wall_s,
    )


#: Start states and parameters already read and checked (:func:`_read_start`), by input.
_STARTS: dict[tuple, tuple[tuple, tuple]] = {}
_STARTS_MAX = 256
_STARTS_LOCK = threading.Lock()


def _input_key(value: object) -> tuple | None:
    """A hashable key of an input as typed (its type and its exact value), or None for
    inputs that are not memoised (any other type, NaN: read anew every time)."""
    # the common inputs first (a key is made every call): numbers as text, floats, vectors,
    # groups by name; the exact built-in types without isinstance's checks
    kind = type(value)
    if kind is str or kind is int:
        return (kind.__name__, value)
    if kind is float:
        return ("float", value) if value == value else None
    if kind is tuple or kind is list:
        # a vector of floats (none NaN), the common input, keyed at once by its values
        floats = tuple([v for v in value if type(v) is float and v == v])
        if len(floats) == len(value):
            return ("floats", floats)
        keys = []
        for v in value:
            kv = type(v)
            key = (kv.__name__, v) if kv is str or kv is int else _input_key(v)
            if key is None:
                return None
            keys.append(key)
        return ("seq", tuple(keys))
    if kind is dict:
        items = []
        for k, v in value.items():
            key = _input_key(v)
            if type(k) is not str or key is None:
                return None
            items.append((k, key))
        return ("map", tuple(sorted(items)))
    if isinstance(value, str):
        return ("str", value)
    if isinstance(value, float):
        return ("float", value) if value == value else None
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "if":
            return None
        value = value.tolist()
        if type(value) is list:  # as the same numbers in a list
            return _input_key(value)
    if isinstance(value, list | tuple):
        # strings and integers, the common entries, keyed here (a call per entry is most of
        # the cost of a key)
        keys = tuple(
            ("str", v) if type(v) is str else ("int", v) if type(v) is int else _input_key(v)
            for v in value
        )
        return None if None in keys else ("seq", keys)
    if isinstance(value, Mapping):
        items = []
        for k, v in value.items():
            key = _input_key(v)
            if not isinstance(k, str) or key is None:
                return None
            items.append((k, key))
        return ("map", tuple(sorted(items)))
    if isinstance(value, bool):
        return None
    if isinstance(value, int | Fraction | mpmath.mpf):
        return (type(value).__name__, value)
    return None


def _read_start(code: ModelCode, y0, params, prec: Precision, t0) -> tuple[list, list]:
    """Parameters and initial state at the working precision, every check of the start
    passed (constraints, relations, finite right-hand side); the same inputs again are not
    read again (the strings of a separatrix state at a guard precision cost most of a short
    run's set-up): results are memoised by model, precision, start time and the inputs as
    typed."""
    key = (code.hash, repr(prec), mpmath.mp.prec, _input_key(t0), _input_key(y0),
           _input_key(params))
    hit = _STARTS.get(key) if None not in key else None
    if hit is not None:
        return list(hit[0]), list(hit[1])
    if isinstance(params, Mapping):
        p = pack_params(code, params, prec)
    else:
        # a vector gets the same checks as named groups: split it by the model's groups
        groups = {n: len(v[0]) for n, v in code.parameter_groups.items()}
        p = pack_params(code, _by_groups(params, groups, code.params, "parameter vector"), prec)
    if isinstance(y0, Mapping):
        y = pack_state(code, y0, prec)
    else:
        groups = {n: len(v) for n, v in code.state_groups.items()}
        y = pack_state(code, _by_groups(y0, groups, code.state, "state vector"), prec)
    _check_constraints(code, t0, y, p)
    _check_relations(code, t0, y, p)
    _check_finite_start(code, t0, y, p, prec)
    if None not in key:
        with _STARTS_LOCK:  # threads (a Dask worker's) may read starts at the same time
            if len(_STARTS) >= _STARTS_MAX:
                del _STARTS[next(iter(_STARTS))]
            _STARTS[key] = (tuple(p), tuple(y))
    return list(p), list(y)


def check_output_times(t_eval: Sequence, t_span: tuple) -> None:
    """Refuse output times outside the span or out of order for the direction of integration.

    Parameters
    ----------
    t_eval : sequence of numbers
        Output times at the working precision.
    t_span : (t0, t1)
        The span (``t1 < t0`` integrates backward).

    Raises
    ------
    UserInputError
        A time outside the span, or two consecutive times in the wrong order.
    """
    direction = 1 if t_span[1] > t_span[0] else -1
    lo, hi = min(t_span), max(t_span)
    for v in t_eval:
        if not lo <= v <= hi:
            raise UserInputError(
                f"t_eval must lie inside the span from {t_span[0]} to {t_span[1]}: {v} does not"
            )
    for a, b in itertools.pairwise(t_eval):
        if direction * (b - a) < 0:
            raise UserInputError(
                f"t_eval must be sorted in the direction of integration (from {t_span[0]} to "
                f"{t_span[1]}): {a} is followed by {b}"
            )


def _check_finite_start(code: ModelCode, t0, y: Sequence, p: Sequence, prec: Precision) -> None:
    """Refuse a start where the right-hand side or an integral is not finite.

    Evaluated in the working number type (double overflows where 30 digits do not: ``D =
    1e300``); a method started there would loop on NaN steps or report NaN evidence.

    Parameters
    ----------
    code : ModelCode
    t0 : number
    y, p : sequence
        State and parameters at the working precision.
    prec : Precision

    Raises
    ------
    UserInputError
        Which of the right-hand side and the integrals is not finite, and what to check.
    """
    if prec.is_double:
        # on Python floats (numpy's per-call cost on length-6 arrays is most of the time);
        # only finiteness is used
        with np.errstate(all="ignore"):
            yy, pp = [float(v) for v in y], [float(v) for v in p]
            try:
                parts = {
                    "right-hand side": np.asarray(code.numpy.rhs(float(t0), yy, pp), dtype=float),
                    "first integrals": np.asarray(
                        code.numpy.integrals(float(t0), yy, pp), dtype=float
                    ),
                }
            except (ZeroDivisionError, OverflowError, ValueError):  # float raises where
                parts = {"right-hand side or the first integrals": np.array([np.nan])}
        bad = [what for what, v in parts.items() if not np.all(np.isfinite(v))]
    else:
        bad = []
        with mpmath.workprec(prec.prec):
            for what, fn in (
                ("right-hand side", code.mpmath.rhs),
                ("first integrals", code.mpmath.integrals),
            ):
                try:
                    finite = all(mpmath.isfinite(v) for v in fn(t0, list(y), list(p)))
                except (ArithmeticError, ValueError):  # mpmath raises on 1/0
                    finite = False
                if not finite:
                    bad.append(what)
    if bad:
        raise UserInputError(
            f"the {' and the '.join(bad)} of {code.name} are not finite at the initial state "
            f"in {prec!r} precision (overflow or division by zero): check the parameters and "
            'state, or use a wider precision (precision="quad" or digits)'
        )


def _sequence(values, what: str) -> list:
    if isinstance(values, str | bytes) or not hasattr(values, "__len__"):
        raise UserInputError(f"{what} must be a sequence of numbers, got {values!r}")
    return list(values)


def _by_groups(values, groups: Mapping[str, int], order: Sequence[str], what: str) -> dict:
    """A flat vector in the model's order as ``{group: values}`` (for the groups' checks)."""
    vals = _sequence(values, f"the {what}")
    if len(vals) != len(order):
        raise UserInputError(f"the {what} needs {len(order)} entries, got {len(vals)}")
    out, i = {}, 0
    for name, n in groups.items():
        out[name] = tuple(vals[i : i + n])
        i += n
    return out


def _time_span(t_span, prec: Precision) -> tuple:
    """``(t0, t1)`` at the working precision; a single number means ``(0, t1)``."""
    if isinstance(t_span, str | bytes) or not hasattr(t_span, "__len__"):
        t_span = (0, t_span)
    items = list(t_span)
    if len(items) != 2:
        raise UserInputError(f"t_span must be (t0, t1) or a single end time, got {t_span!r}")
    try:
        t0, t1 = (working_number(v, prec) for v in items)
    except UserInputError as exc:
        raise UserInputError(f"t_span: {exc}") from None
    if t1 == t0:
        raise UserInputError("the time span must be finite and non-empty")
    return t0, t1


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
