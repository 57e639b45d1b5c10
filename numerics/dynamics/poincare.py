"""Poincaré maps: the stroboscopic map of a time-periodic model and the section of a flow by
a surface.

:class:`StroboscopicMap` samples a model whose parameters vary with period ``2 pi/Omega``
(BM20: ``chaplygin_ball`` with ``variable_inertia``, ``variable_gyrostat``) at ``t0 + k tau``;
the sampling times are computed at 10 guard digits above the working precision and rounded
once, and the states come from one integration with dense output at those times (the Taylor
method by default: its step polynomial is evaluated at each time, in double, quad or digits).

:class:`EventSection` records where an orbit crosses a surface ``S(state) = 0`` (an expression
of the state, :class:`~chaplygin.numerics.ball.map_coordinates.StateExpression`, or a callable) in
a chosen direction: the crossings are located on the Taylor integrator's step polynomial to
the working precision (:func:`chaplygin.numerics.taylor.taylor_solve`).

Both discard ``transient`` iterations on request and return a :class:`MapOrbit`, which carries
its evidence: the integrals at every point and their drift, the work done and the wall time.

References
----------
BM20-map (section ``t = 0`` mod ``tau``), BM20-3.7; K01 Fig. 2a (section on an energy level).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import mpmath
import numpy as np

from ...derive.errors import ComputationError, UserInputError
from ..code import ModelCode
from ..inputs import Precision, pack_params, pack_state, working_number
from ..integrate import integrate
from .state_expression import StateExpression

__all__ = ["MapOrbit", "StroboscopicMap", "EventSection", "integral_drift"]


@dataclass
class MapOrbit:
    """Points of a Poincaré map with their evidence.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times of the points (float64, or object/mpf at higher precision).
    y : ndarray, shape (n, n_state)
        States at those times.
    state_names : tuple of str
    integrals : ndarray, shape (n, n_integrals)
        The model's first integrals at every point (float64).
    integral_names : tuple of str
    drift : dict of str to float
        ``max |F_k - F_0|`` relative to ``|F_0|`` (absolute where ``|F_0| < 1e-8``) over the
        points, for every integral.
    transient : int
        Iterations (or crossings) discarded before the first point.
    nsteps : int
        Integrator steps taken.
    wall_s : float
    precision : str
    method : str
    """

    t: np.ndarray
    y: np.ndarray
    state_names: tuple[str, ...]
    integrals: np.ndarray
    integral_names: tuple[str, ...]
    drift: dict[str, float]
    transient: int
    nsteps: int
    wall_s: float
    precision: str
    method: str
    info: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.t)

    def component(self, name: str) -> np.ndarray:
        """One state component at every point.

        Parameters
        ----------
        name : str
            A state name (``"M1"``).

        Returns
        -------
        ndarray, shape (n,)

        Raises
        ------
        UserInputError
            Not a state name.
        """
        if name not in self.state_names:
            raise UserInputError(f"no state {name!r}; valid: {', '.join(self.state_names)}")
        return self.y[:, self.state_names.index(name)]


def integral_drift(
    code: ModelCode, t: np.ndarray, y: np.ndarray, p: Sequence, bits: int = 53
) -> tuple:
    """The model's integrals at the points ``(t_k, y_k)`` and their drift.

    Parameters
    ----------
    code : ModelCode
    t : ndarray, shape (n,)
    y : ndarray, shape (n, n_state)
    p : sequence
        Parameters at the working precision.
    bits : int
        Working precision in bits (mpmath evaluates the integrals of mpf states at it).

    Returns
    -------
    values : ndarray, shape (n, n_integrals)
    drift : dict of str to float
        ``max_k |F_k - F_0|`` relative to ``|F_0|`` (absolute where ``|F_0| < 1e-8``).
    """
    names = code.integral_names
    if len(t) == 0:
        return np.empty((0, len(names))), {n: 0.0 for n in names}
    exact = np.asarray(y).dtype == object
    rows = []
    with mpmath.workprec(bits):
        for tk, yk in zip(t, y, strict=True):
            if exact:
                v = code.mpmath.integrals(tk, list(yk), list(p))
            else:
                v = code.numpy.integrals(float(tk), np.asarray(yk, float), np.asarray(p, float))
            rows.append([v[i] for i in range(len(names))])
    if exact:
        F0 = [mpmath.mpf(v) for v in rows[0]]
        drift = {}
        for i, n in enumerate(names):
            change = max(abs(mpmath.mpf(r[i]) - F0[i]) for r in rows)
            scale = abs(F0[i]) if abs(F0[i]) >= 1e-8 else 1
            drift[n] = float(change / scale)
        return np.array([[float(v) for v in r] for r in rows]), drift
    values = np.array(rows, dtype=float)
    F0 = values[0]
    scale = np.where(np.abs(F0) >= 1e-8, np.abs(F0), 1.0)
    change = np.max(np.abs(values - F0), axis=0) / scale
    return values, {n: float(c) for n, c in zip(names, change, strict=True)}


class _MapBase:
    """Parameters, precision and tolerances shared by the two kinds of map."""

    def __init__(
        self,
        code: ModelCode,
        params: Mapping[str, object] | Sequence,
        *,
        precision: str | int = "double",
        rtol: float | None = None,
        atol: float | None = None,
        method: str | None = None,
        backend: str = "auto",
    ):
        self.code = code
        self.precision = Precision(precision)
        if isinstance(params, Mapping):
            self.params = pack_params(code, params, self.precision)
        else:
            if len(params) != len(code.params):
                raise UserInputError(
                    f"{code.name} has {len(code.params)} parameters ({', '.join(code.params)}), "
                    f"got {len(params)}"
                )
            self.params = [working_number(v, self.precision) for v in params]
        self.rtol, self.atol = rtol, atol
        self.method = method or "taylor"
        self.backend = backend

    def _state(self, y: Mapping | Sequence) -> list:
        if isinstance(y, Mapping):
            return pack_state(self.code, y, self.precision)
        y = list(np.asarray(y, dtype=object).ravel())
        if len(y) != len(self.code.state):
            raise UserInputError(
                f"a state of {self.code.name} has {len(self.code.state)} components "
                f"({', '.join(self.code.state)}), got {len(y)}"
            )
        return [working_number(v, self.precision) for v in y]

    def _array(self, rows: Sequence) -> np.ndarray:
        dtype = float if self.precision.is_double else object
        return np.array(rows, dtype=dtype).reshape(len(rows), len(self.code.state))

    def _integrate(self, y, t_span, **kw):
        r = integrate(
            self.code,
            list(y),
            t_span,
            list(self.params),
            method=self.method,
            precision=self.precision,
            rtol=self.rtol,
            atol=self.atol,
            backend=self.backend,
            max_wall_s=None,
            **kw,
        )
        if not r.success:
            raise ComputationError(f"the map's integration failed at t = {r.t[-1]}: {r.message}")
        return r


class StroboscopicMap(_MapBase):
    """The period map ``y(t0) -> y(t0 + tau)``, ``tau = 2 pi/Omega``, of a time-periodic model.

    Parameters
    ----------
    code : ModelCode
        A model with the parameter ``Omega`` (BM20's ``variable_inertia``/``variable_gyrostat``).
    params : mapping or sequence
        ``{"I": (4, 3, 2), "D": 4.385, ...}`` or a vector in the model's order; rounded once to
        the working precision.
    precision : "double", "quad" or int
    rtol, atol : float, optional
        Tolerances of the integration (the precision's defaults where None).
    method : str, optional
        Integration method (default ``"taylor"``).
    backend : {"auto", "c", "numpy"}
    backward : bool
        The inverse map ``y(t0) -> y(t0 - tau)`` (a repeller of the map is an attractor of
        its inverse).

    Attributes
    ----------
    period : float or mpmath.mpf
        ``2 pi/Omega`` at the working precision (``-2 pi/Omega`` for the inverse map).

    Raises
    ------
    UserInputError
        The model has no ``Omega``; bad parameters.

    References
    ----------
    BM20-map.
    """

    def __init__(
        self,
        code: ModelCode,
        params: Mapping[str, object] | Sequence,
        *,
        backward: bool = False,
        **options: Any,
    ):
        self._sign = -1 if backward else 1
        if code.forcing is None:
            raise UserInputError(
                f"{code.name} is not time-periodic (no parameter Omega): a stroboscopic map needs "
                "the effects variable_inertia or variable_gyrostat; use a section by a surface"
            )
        super().__init__(code, params, **options)
        self._omega = self.params[code.params.index(code.forcing)]
        if not self._omega > 0:
            raise UserInputError("Omega must be positive for a stroboscopic map")
        self.period = self.time(1)

    def time(self, k: int, t0: object = 0) -> float | mpmath.mpf:
        """``t0 + k tau`` (``t0 - k tau`` for the inverse map) computed with 10 guard digits and
        rounded once to the working precision.

        Parameters
        ----------
        k : int
        t0 : number

        Returns
        -------
        float or mpmath.mpf
        """
        with mpmath.workdps(self.precision.parse_dps + 10):
            value = mpmath.mpf(t0) + self._sign * k * 2 * mpmath.pi / mpmath.mpf(self._omega)
            return working_number(value, self.precision)

    def step(self, y: Mapping | Sequence, t0: object = 0) -> np.ndarray:
        """The state one period later.

        Parameters
        ----------
        y : mapping or sequence
            State at ``t0``.
        t0 : number
            Phase of the section (default 0).

        Returns
        -------
        ndarray, shape (n_state,)
        """
        return self.orbit(y, 2, t0=t0).y[1]

    def orbit(self, y0: Mapping | Sequence, n: int, transient: int = 0, t0: object = 0) -> MapOrbit:
        """``n`` points ``P^(transient + k)(y0)``, ``k = 0 .. n-1`` (``y0`` itself first when
        ``transient = 0``).

        Parameters
        ----------
        y0 : mapping or sequence
        n : int
            Number of points (>= 1).
        transient : int
            Iterations discarded first.
        t0 : number

        Returns
        -------
        MapOrbit

        Raises
        ------
        UserInputError
            ``n < 1`` or ``transient < 0``.
        ComputationError
            The integration failed.
        """
        if not (isinstance(n, int) and n >= 1 and isinstance(transient, int) and transient >= 0):
            raise UserInputError("a map orbit needs n >= 1 points and transient >= 0")
        start = time.perf_counter()
        y = self._state(y0)
        t0 = working_number(t0, self.precision)
        times = [self.time(k, t0) for k in range(transient, transient + n)]
        end = times[-1]
        if end == t0:
            rows, nsteps = [y], 0
        else:
            r = self._integrate(y, (t0, end), t_eval=times)
            rows = list(r.y.T[-n:])
            nsteps = r.nsteps
        Y = self._array(rows)
        T = np.array(times, dtype=float if self.precision.is_double else object)
        values, drift = integral_drift(self.code, T, Y, self.params, self.precision.prec)
        return MapOrbit(
            t=T, y=Y, state_names=self.code.state, integrals=values,
            integral_names=self.code.integral_names, drift=drift, transient=transient,
            nsteps=nsteps, wall_s=time.perf_counter() - start,
            precision=str(self.precision), method=self.method,
            info={"period": self.period},
        )  # fmt: skip


class EventSection(_MapBase):
    """Crossings of an orbit with the surface ``S(state) = 0`` in one direction.

    Parameters
    ----------
    code : ModelCode
    params : mapping or sequence
    surface : str or callable
        An expression of the state (``"M2*gamma1 - M1*gamma2"``; names: the state components
        and the model's auxiliary quantities, :class:`StateExpression`) or ``S(t, y)``.
    direction : {1, -1, 0}
        Crossings where ``S`` increases (1), decreases (-1) or both (0).
    precision, rtol, atol, backend : see :class:`StroboscopicMap`
    chunk : float
        Time span integrated per call while crossings are collected.

    Raises
    ------
    UserInputError
        A bad surface expression (the message says what is allowed), a bad direction.

    References
    ----------
    K01 Fig. 2a.
    """

    def __init__(
        self,
        code: ModelCode,
        params: Mapping[str, object] | Sequence,
        surface: str | Callable,
        *,
        direction: int = 1,
        chunk: float = 50.0,
        **options: Any,
    ):
        options.setdefault("method", "taylor")
        if options["method"] != "taylor":
            raise UserInputError(
                "a section by a surface locates its crossings on the Taylor polynomial: "
                "method must be 'taylor'"
            )
        super().__init__(code, params, **options)
        if direction not in (-1, 0, 1) or isinstance(direction, bool):
            raise UserInputError(f"direction must be 1, -1 or 0, got {direction!r}")
        if not (isinstance(chunk, int | float) and chunk > 0):
            raise UserInputError(f"chunk must be a positive time span, got {chunk!r}")
        self.direction, self.chunk = direction, chunk
        if callable(surface):
            self.surface_text = getattr(surface, "__name__", "callable")
            self._g = surface
        else:
            names = (*code.state, *code.aux_names)
            expr = StateExpression(surface, names)
            self.surface_text = surface
            self._g = self._expression_event(expr)

    def _expression_event(self, expr: StateExpression) -> Callable:
        code, p, state = self.code, self.params, self.code.state
        needs_aux = any(a in expr.text for a in code.aux_names)
        exact = not self.precision.is_double

        def g(t, y):
            values = dict(zip(state, y, strict=True))
            if needs_aux:
                aux = (
                    code.mpmath.aux(t, list(y), list(p))
                    if exact
                    else code.numpy.aux(float(t), np.asarray(y, float), np.asarray(p, float))
                )
                values.update(zip(code.aux_names, aux, strict=True))
            return expr.evaluate(values)

        return g

    def orbit_in_surface(
        self, y: Mapping | Sequence, t_end: float = 20.0, points: int = 200, tol: float = 1e-9
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The orbit of ``y`` sampled at ``points`` times over ``[0, t_end]`` when the surface
        function vanishes all along it (to ``tol`` of the state's squared size), else None.

        Such an orbit lies in the section and has no crossings to find (K01's rotation about
        ``e3`` lies in the section ``g = 0``).

        Parameters
        ----------
        y : mapping or sequence
            The start.
        t_end : float
        points : int
        tol : float

        Returns
        -------
        (t, states) or None
            The times and the states (one row per time) when the orbit stays in the surface.
        """
        t = np.linspace(0.0, t_end, points)
        r = self._integrate(self._state(y), (0.0, t_end), t_eval=list(t))
        states = np.asarray(r.y, float).T
        values = np.array([float(self._g(tk, row)) for tk, row in zip(t, states, strict=True)])
        scale = max(1.0, float(np.max(np.sum(states**2, axis=1))))
        if np.max(np.abs(values)) > tol * scale:
            return None
        return t, states

    def crossings(
        self,
        y0: Mapping | Sequence,
        n: int,
        transient: int = 0,
        t0: object = 0,
        t_max: object = None,
    ) -> MapOrbit:
        """The ``n`` crossings after ``transient`` discarded ones.

        Parameters
        ----------
        y0 : mapping or sequence
        n : int
            Crossings to record (>= 1).
        transient : int
            Crossings discarded first.
        t0 : number
        t_max : number, optional
            Give up at this time (default ``t0 + 10^4 chunk``); fewer points are returned.

        Returns
        -------
        MapOrbit
            ``info["complete"]`` is False when ``t_max`` came first; ``info["crossings"]``
            counts every crossing located, the transient ones included.

        Raises
        ------
        UserInputError
            ``n < 1`` or ``transient < 0``.
        ComputationError
            The integration failed.
        """
        if not (isinstance(n, int) and n >= 1 and isinstance(transient, int) and transient >= 0):
            raise UserInputError("a section needs n >= 1 crossings and transient >= 0")
        start = time.perf_counter()
        g = self._g
        direction = self.direction

        def event(t, y):
            return g(t, y)

        event.direction = direction  # type: ignore[attr-defined]
        y = self._state(y0)
        t = working_number(t0, self.precision)
        if t_max is None:
            stop = t + 10_000 * self.chunk
        else:
            stop = working_number(t_max, self.precision)
        ts: list = []
        ys: list = []
        nsteps = 0
        while len(ts) < transient + n and t < stop:
            t1 = min(t + working_number(self.chunk, self.precision), stop)
            r = self._integrate(y, (t, t1), t_eval=[t1], events=[event])
            nsteps += r.nsteps
            ts.extend(r.t_events[0])
            ys.extend(list(row) for row in r.y_events[0])
            t, y = t1, list(r.y[:, -1])
        found = min(len(ts), transient + n)  # up to the last one kept (chunks overshoot)
        ts, ys = ts[transient : transient + n], ys[transient : transient + n]
        T = np.array(ts, dtype=float if self.precision.is_double else object)
        Y = self._array(ys) if ys else np.empty((0, len(self.code.state)))
        values, drift = integral_drift(self.code, T, Y, self.params, self.precision.prec)
        return MapOrbit(
            t=T, y=Y, state_names=self.code.state, integrals=values,
            integral_names=self.code.integral_names, drift=drift, transient=transient,
            nsteps=nsteps, wall_s=time.perf_counter() - start,
            precision=str(self.precision), method=self.method,
            info={"complete": len(ts) == n, "crossings": found,
                  "surface": self.surface_text, "direction": direction},
        )  # fmt: skip
