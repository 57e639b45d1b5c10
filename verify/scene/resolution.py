"""Resolution: a scene made concrete, checked before any work.

:func:`resolve_scene` turns a :class:`~chaplygin.verify.scene.schema.Scene` into a
:class:`Resolved`: the model's code with the effects the scene and its outputs need (and why),
the parameters and the time span at the working precision, and the initial state. The initial
state is the system's: :func:`chaplygin.numerics.ball.initial_state.initial_state`, the one function
the API uses too (the same frame rule on ``M || gamma``); this module only names the key of the
scene at fault, with its line.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ...derive.errors import UserInputError
from ...derive.systems import SYSTEMS
from .errors import SceneError, did_you_mean
from .registry import OUTPUT_EFFECTS, needs_trajectory, requested

if TYPE_CHECKING:
    from .schema import Scene

__all__ = ["Resolved", "decimal_text", "quantity_names", "resolve_scene"]


@dataclass
class Resolved:
    """A scene made concrete: model code, effects with reasons, vectors at working precision.

    Attributes
    ----------
    code : ModelCode
    effects : dict of str to str
        Effect -> why it is on.
    params : dict of str to number
        Parameter symbol -> value at the working precision.
    y0 : list
        Initial state vector (model order) at the working precision.
    prescribed : dict of str to number
        Integral values asked for (by integrals only).
    residuals : dict of str to float
        ``F(y0) - prescribed`` with the model's generated integrals.
    how : str
        How the initial point was chosen.
    load_s : float
        Time to load (or derive and emit) the model code.
    t_span : (t0, t1)
        At the working precision.
    digits : int or None
        Working decimal digits (None in double precision).
    """

    code: Any
    effects: dict[str, str]
    params: dict[str, Any]
    y0: list
    prescribed: dict[str, Any] = field(default_factory=dict)
    residuals: dict[str, float] = field(default_factory=dict)
    how: str = "given by state"
    load_s: float = 0.0
    t_span: tuple = (0.0, 1.0)
    digits: int | None = None

    def state_by_name(self) -> dict[str, str]:
        """Initial state by component name, as decimal strings (every working digit).

        Returns
        -------
        dict of str to str
        """
        return {
            n: decimal_text(v, self.digits) for n, v in zip(self.code.state, self.y0, strict=True)
        }


def decimal_text(value: object, digits: int | None = None) -> str:
    """A number as decimal text: floats by their shortest repr, mpf with ``digits`` digits.

    Parameters
    ----------
    value : float, mpmath.mpf or object
    digits : int, optional
        Significant digits of an mpf (default 17).

    Returns
    -------
    str
    """
    import mpmath

    if isinstance(value, float | np.floating):
        return repr(float(value))
    if isinstance(value, mpmath.mpf):
        return mpmath.nstr(value, digits or 17, strip_zeros=False)
    return str(value)


def resolve_scene(scene: Scene) -> Resolved:
    """The model, parameters and initial state ``scene`` asks for, checked (:meth:`Scene.resolve`).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    Resolved

    Raises
    ------
    SceneError
        Anything the scene asks for that cannot be run, with its key path and line.
    """
    import warnings

    from ...numerics.code import load_model_code
    from ...numerics.inputs import Precision

    reasons = _effects_and_reasons(scene)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            code = load_model_code(scene.system, sorted(reasons))
        except UserInputError as exc:
            raise scene.key_error(str(exc), "effects") from None
    load_s = time.perf_counter() - start
    try:
        prec = Precision(scene.run_options.precision)
    except UserInputError as exc:
        raise scene.key_error(str(exc), "run", "precision") from None
    t_span = _time_span(scene, prec)
    _check_method(scene)
    p = _parameters(scene, code, prec)
    params = dict(zip(code.params, p, strict=True))
    start_state = _initial_state(scene, code, params, prec)
    if needs_trajectory(scene):
        _check_step_budget(scene, code, t_span, start_state.y0, p, prec)
    if scene.outputs.separatrix_delta is not None:
        from ..outputs.separatrix_delta import separatrix_delta_problem

        problem = separatrix_delta_problem(scene.system, code, params, start_state.y0)
        if problem:
            raise scene.key_error(problem, "outputs", "separatrix_delta")
    return Resolved(
        code,
        reasons,
        params,
        start_state.y0,
        start_state.prescribed,
        start_state.residuals,
        start_state.how,
        load_s,
        t_span,
        prec.digits,
    )


def _effects_and_reasons(scene: Scene) -> dict[str, str]:
    """The effects of the model: the scene's, and those its outputs need, each with why."""
    reasons = {e: "named in the scene" for e in scene.effects}
    for key, needs in OUTPUT_EFFECTS.items():
        if getattr(scene.outputs, key) is not None:
            for e in needs:
                reasons.setdefault(e, f"needed by outputs.{key}")
    for key, (analysis, _) in requested(scene.outputs).items():
        for e in analysis.effects:
            reasons.setdefault(e, f"needed by outputs.{key}")
    supported = SYSTEMS[scene.system].effects
    for e in reasons:
        if e not in supported:
            raise SceneError(
                f"{scene.system} does not support {e}, which outputs need", scene.source
            )
    return reasons


def _check_method(scene: Scene) -> None:
    method = scene.run_options.method
    if method is not None:
        from ...numerics.integrate import METHODS

        if method not in METHODS:
            raise scene.key_error(
                f"unknown method {method!r}; valid: {', '.join(METHODS)}"
                f"{did_you_mean(method, list(METHODS))}",
                "run",
                "method",
            )


def _parameters(scene: Scene, code: Any, prec: Any) -> list:
    """The parameter vector: exactly the model's groups, at the working precision."""
    from ...numerics.inputs import pack_params

    groups = code.parameter_groups
    for name in scene.parameters:
        if name not in groups:
            owner = _owner_effect(scene.system, name)
            hint = (
                f"; it belongs to effect {owner}, which is not on (add it to effects)"
                if owner
                else f"; valid: {', '.join(groups)}{did_you_mean(name, list(groups))}"
            )
            raise scene.key_error(
                f"{code.name} has no parameter {name!r}{hint}", "parameters", name
            )
    missing = [g for g in groups if g not in scene.parameters]
    if missing:
        desc = groups[missing[0]][2]
        raise scene.key_error(
            f"parameter {missing[0]!r} is missing ({desc})",
            "parameters",
            missing[0],
            line_at=("parameters",),
        )
    try:
        return pack_params(code, dict(scene.parameters), prec)
    except UserInputError as exc:
        raise scene.key_error(str(exc), "parameters") from None


def _initial_state(scene: Scene, code: Any, params: dict, prec: Any) -> Any:
    """:func:`chaplygin.numerics.ball.initial_state.initial_state` of ``[initial]``, its refusals
    naming the key (the outputs are checked after the keys, before anything is computed)."""
    from ...numerics.ball.initial_state import (
        InitialStateError,
        check_initial_request,
        initial_state,
    )

    request = {**dict(scene.initial), **(scene.initial.model_extra or {})}
    try:
        check_initial_request(code, request)
        _check_outputs(scene, code)
        expressions = {c.id: c.expression for c in scene.claims if c.kind == "integral"}
        return initial_state(code, params, request, prec, expressions)
    except InitialStateError as exc:
        loc = ("initial", exc.key) if exc.key else ("initial",)
        raise scene.key_error(str(exc), *loc) from None


def _time_span(scene: Scene, prec: Any) -> tuple:
    from ...numerics.inputs import working_number

    out = []
    if scene.run_options.t_end is None:
        if needs_trajectory(scene):
            raise scene.key_error(
                "run.t_end is required: this scene integrates a trajectory", "run", "t_end",
                line_at=("run",),
            )
        start = working_number(scene.run_options.t_start, prec)
        return (start, start + 1)  # analyses only: they choose their own spans
    for key in ("t_start", "t_end"):
        try:
            out.append(working_number(getattr(scene.run_options, key), prec))
        except UserInputError as exc:
            raise scene.key_error(str(exc), "run", key) from None
    if not out[1] > out[0]:
        raise scene.key_error(
            f"run.t_end must be after run.t_start ({decimal_text(out[0])})", "run", "t_end"
        )
    return tuple(out)


def _check_step_budget(scene: Scene, code: Any, t_span, y0, p, prec: Any) -> None:
    """Refuse, before any work, a span whose estimated steps exceed ``run.max_steps`` (as
    ``chaplygin integrate`` does: :mod:`chaplygin.numerics.step_budget`)."""
    from ...numerics.step_budget import DEFAULT_MAX_STEPS, estimated_steps, motion_rate

    run = scene.run_options
    budget = run.max_steps or DEFAULT_MAX_STEPS
    span = abs(float(t_span[1] - t_span[0]))
    rate = motion_rate(code, float(t_span[0]), y0, p) if math.isfinite(span) else 1.0
    steps = estimated_steps(span * rate, run.method, run.rtol, prec.is_double)
    if steps > budget:
        at = "" if rate == 1 else f" at a rate |f(y0)|/|y0| of {rate:.2g}"
        raise scene.key_error(
            f"a span of {span:.3g}{at} needs about {steps:.2g} steps, beyond the budget of "
            f"{budget:.3g}; shorten the span or raise run.max_steps (default "
            f"{DEFAULT_MAX_STEPS:.0e})",
            "run",
            "t_end",
        )


def quantity_names(code: Any) -> list[str]:
    """Names a series may show: state components, auxiliary quantities, integrals, ``I_i(t)``.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    list of str
    """
    extra = ["I1(t)", "I2(t)", "I3(t)"] if "I1" in code.params else []
    return [*code.state, *code.aux_names, *code.integral_names, *extra]


def _check_outputs(scene: Scene, code: Any) -> None:
    series = scene.outputs.series
    if series is not None:
        valid = quantity_names(code)
        for i, q in enumerate(series.quantities):
            if q not in valid:
                raise scene.key_error(
                    f"unknown quantity {q!r} for {code.name}; valid: {', '.join(valid)}"
                    f"{did_you_mean(q, valid)}",
                    "outputs",
                    "series",
                    "quantities",
                    i,
                )
    if scene.outputs.diagram is not None:
        from ..outputs.diagram import diagram_problem

        problem = diagram_problem(scene.system, code.effects, code.name)
        if problem:
            raise scene.key_error(problem, "outputs", "diagram")
    for analysis, spec in requested(scene.outputs).values():
        if analysis.check is not None:
            analysis.check(scene, code, spec)


def _owner_effect(system: str, parameter: str) -> str | None:
    """The effects of the smallest variant in ``generated/`` that has ``parameter`` (for
    messages; nothing is derived)."""
    from ...numerics.code import generated_manifest, load_model_code

    if parameter in load_model_code(system, ()).parameter_groups:
        return None
    variants = sorted(
        (tuple(sorted(entry.get("effects") or [])) for entry in generated_manifest().values()
         if entry.get("system") == system),
        key=lambda v: (len(v), v),
    )  # fmt: skip
    for effects in variants:
        if effects and parameter in load_model_code(system, effects).parameter_groups:
            return " + ".join(effects)
    return None
