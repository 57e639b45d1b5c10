"""The ``periodic_orbits`` output of an autonomous model: a periodic orbit through a surface.

A scene of any autonomous model (a described system too) asks for::

    [outputs.periodic_orbits]
    section = "gamma2"        # the surface S(state) = 0, as for outputs.poincare
    direction = 1
    transient = 0             # crossings discarded before the period search
    max_period = 8            # crossings per period tried
    detect_tol = 1e-6

The return map to the surface (:class:`chaplygin.numerics.dynamics.poincare.EventSection`,
crossings located on the Taylor step polynomial) is iterated from the scene's initial state;
the smallest ``k`` whose crossings close within ``detect_tol`` (in the full state) is the
candidate, and the orbit through the last crossings is refined on the flow with its period
as an unknown (:func:`chaplygin.numerics.dynamics.flow_orbits.refine_flow_orbit`). The summary
gives the crossings per period, the period in model time, the Newton residual, the Floquet
multipliers and ``det Phi`` (1 where the model keeps an invariant density: Liouville).

With ``[outputs.periodic_orbits.continuation]`` (``parameter`` any of the model's, ``range =
[a, b]``, ``step``) the refined orbit is followed from the scene's value to ``a`` and to ``b``
in steps of ``step`` (at most ``max_points`` per direction:
:func:`chaplygin.numerics.dynamics.flow_orbits.continue_flow_orbit`, on the levels of the
integrals the start has at each value); the summary gives where each direction stopped and
between which values the stability changes, the arrays the branch (parameter, period,
multipliers), the figure the multipliers along it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...derive.errors import ComputationError, UserInputError
from ..scene.outputs import AnalysisResult

__all__ = ["check_flow_orbit", "run_flow_orbit"]


def _error(message: str, key: str = "section") -> UserInputError:
    return UserInputError(f"outputs.periodic_orbits.{key}: {message}")


def check_flow_orbit(scene: Any, code: Any, spec: Any) -> None:
    """Refuse what the route cannot do before anything runs.

    Parameters
    ----------
    scene : Scene
    code : ModelCode
    spec : PeriodicOrbitsOutput

    Raises
    ------
    UserInputError
        A time-periodic model, a model whose right-hand side depends on the time, a bad
        surface expression, a continuation in a parameter the model does not have.
    """
    from ...numerics.ball.map_coordinates import StateExpression

    if code.forcing is not None:
        raise _error(
            f"{code.name} is time-periodic: its periodic orbits are those of the stroboscopic "
            "map (leave section out)"
        )
    if spec.continuation is not None and spec.continuation.parameter not in code.params:
        raise _error(
            f"{code.name} has no parameter {spec.continuation.parameter!r} "
            f"({', '.join(code.params)})",
            "continuation.parameter",
        )
    try:
        StateExpression(spec.section, (*code.state, *code.aux_names))
    except UserInputError as exc:
        raise _error(str(exc)) from None


def _time_dependent(code: Any, params: list, y: np.ndarray) -> bool:
    """Whether the generated right-hand side changes with ``t`` at the start (a turntable
    whose rate is a function of time): a return map of such a flow has no periodic orbit
    of its own."""
    at = [np.asarray(code.numpy.rhs(t, y, np.asarray(params)), float) for t in (0.0, 1.7)]
    return not np.array_equal(at[0], at[1])


def run_flow_orbit(scene: Any, res: Any, spec: Any) -> AnalysisResult:
    """Iterate the return map, detect the period, refine it on the flow (see the module).

    Parameters
    ----------
    scene : Scene
    res : Resolved
    spec : PeriodicOrbitsOutput

    Returns
    -------
    AnalysisResult

    Raises
    ------
    UserInputError
        A model whose right-hand side depends on the time; a failed map or refinement.
    """
    from ...numerics.dynamics.flow_orbits import refine_flow_orbit
    from ...numerics.dynamics.periodic_orbits import detect_period
    from ...numerics.dynamics.poincare import EventSection

    code = res.code
    params = [float(res.params[k]) for k in code.params]
    y0 = np.array([float(v) for v in res.y0])
    if _time_dependent(code, params, y0):
        raise _error(f"{code.name} depends on the time: no autonomous return map")
    try:
        section = EventSection(
            code, params, spec.section, direction=spec.direction, rtol=spec.rtol, atol=spec.rtol
        )
        orbit = section.crossings(list(y0), 2 * spec.max_period + 1, spec.transient)
    except (UserInputError, ComputationError) as exc:
        raise _error(str(exc)) from None
    states = np.asarray(orbit.y, dtype=float)
    times = np.asarray(orbit.t, dtype=float)
    period = detect_period(states[1:], spec.max_period, spec.detect_tol)
    summary: dict[str, Any] = {
        "map": f"return map to {spec.section} = 0 (direction {spec.direction}), full state",
        "transient": spec.transient,
        "detect_tol": spec.detect_tol,
        "rtol": spec.rtol,
        "period": period,
    }
    arrays: dict[str, tuple] = {
        "crossings": (
            ("sample", "state"),
            states,
            {"long_name": f"crossings ({', '.join(code.state)})", "units": "model units"},
        )
    }
    if period is None:
        summary["message"] = (
            f"no period <= {spec.max_period} crossings closes within {spec.detect_tol:g} "
            f"after {spec.transient} crossings"
        )
        return AnalysisResult(summary=summary, arrays=arrays, figures={})
    start = len(states) - 1 - period
    try:
        found = refine_flow_orbit(
            code, params, states[start], times[start + period] - times[start], rtol=spec.rtol
        )
    except ComputationError as exc:
        raise _error(str(exc)) from None
    summary.update(
        {
            "period_time": f"{found.period:.15g}",
            "point": {n: f"{v:.15g}" for n, v in zip(code.state, found.point, strict=True)},
            "newton_steps": found.iterations,
            "converged": found.converged,
            "residual": found.residual,
            "tolerance": found.tolerance,
            "multipliers": [f"{m.real:.12g}{m.imag:+.12g}j" for m in found.multipliers],
            "max |multiplier|": float(np.max(np.abs(found.multipliers))),
            "det Phi": found.determinant,
        }
    )
    figures: dict[str, Any] = {}
    if spec.continuation is not None and found.converged:
        summary["continuation"], more, figures["multipliers"] = _continue(
            code, params, found, period, spec.continuation, spec.rtol
        )
        arrays.update(more)
    return AnalysisResult(summary=summary, arrays=arrays, figures=figures)


def _continue(code: Any, params: list, found: Any, crossings: int, cspec: Any, rtol: float):
    """Both directions of the branch from the scene's value: summary, arrays, figure."""
    import math
    from types import SimpleNamespace

    from ...numerics.dynamics.flow_orbits import continue_flow_orbit
    from .periodic_orbits_figure import multipliers_figure

    name = cspec.parameter
    value = float(params[code.params.index(name)])
    runs = []
    for end in cspec.range:
        if float(end) == value:
            continue
        steps = min(max(1, math.ceil(abs(float(end) - value) / float(cspec.step))),
                    cspec.max_points - 1)  # fmt: skip
        try:
            runs.append((float(end), continue_flow_orbit(code, params, found, name, float(end),
                                                        steps, rtol=rtol)))  # fmt: skip
        except UserInputError as exc:
            raise _error(str(exc), "continuation") from None
    par = np.concatenate([b.values for _, b in runs]) if runs else np.array([value])
    orbits = [o for _, b in runs for o in b.orbits] or [found]
    mul = np.array([o.multipliers for o in orbits])
    stable = np.concatenate([b.stable for _, b in runs]) if runs else np.array([True])
    changes = sorted(c for _, b in runs for c in b.changes)
    summary = {
        "parameter": name,
        "range": [float(v) for v in cspec.range],
        "branches": [
            {"to": end, "points": len(b.values), "reached": f"{b.values[-1]:.15g}",
             "stopped": b.stopped}
            for end, b in runs
        ],  # fmt: skip
        "stability changes": [
            {"between": [f"{a:.15g}", f"{b:.15g}"]} for a, b in changes
        ],
    }
    arrays = {
        "branch_parameter": (("branch_point",), par, {"long_name": name, "units": "1"}),
        "branch_period_time": (
            ("branch_point",),
            np.array([o.period for o in orbits]),
            {"long_name": "period", "units": "model time"},
        ),
        "branch_state": (
            ("branch_point", "state"),
            np.array([o.point for o in orbits]),
            {"long_name": f"a point of the orbit ({', '.join(code.state)})",
             "units": "model units"},  # fmt: skip
        ),
        "branch_stable": (
            ("branch_point",),
            stable.astype(np.int8),
            {"long_name": "1: every |multiplier| <= 1 + its tolerance", "units": "1"},
        ),
        "multiplier_abs": (("branch_point", "multiplier"), np.abs(mul),
                           {"long_name": "|Floquet multiplier|", "units": "1"}),
        "multiplier_arg": (("branch_point", "multiplier"), np.angle(mul),
                           {"long_name": "arg Floquet multiplier", "units": "rad"}),
    }  # fmt: skip
    events = [SimpleNamespace(kind="stability change", parameter=(a + b) / 2) for a, b in changes]

    def figure():
        return multipliers_figure(par, np.full(len(par), crossings), mul, events, name)

    return summary, arrays, figure
