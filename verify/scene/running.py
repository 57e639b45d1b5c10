"""Running a resolved scene: its trajectory (when an output needs one) and its analyses."""

from __future__ import annotations

import sys
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from ...derive.errors import UserInputError
from .errors import SceneError
from .registry import needs_trajectory, requested
from .result import SceneResult

if TYPE_CHECKING:
    from .resolution import Resolved
    from .schema import Scene

__all__ = ["integrate_trajectory", "run_resolved"]


def _progress_event(t0: float, t1: float, enabled: bool):
    """An event function that never fires and moves a tqdm bar (shown after 2 s)."""
    if not enabled:
        return None, None
    from tqdm import tqdm

    total = abs(float(t1) - float(t0))
    bar = tqdm(
        total=total,
        delay=2.0,
        file=sys.stderr,
        leave=False,
        mininterval=0.5,
        bar_format="{l_bar}{bar}| t = {n:.6g} of {total:.6g} [{elapsed}<{remaining}]",
    )
    state = {"last": float(t0)}

    def event(t, y):
        now = float(t)
        step = abs(now - state["last"])
        if step > 0:
            bar.update(min(step, total - bar.n))
            state["last"] = now
        return 1.0

    return event, bar


def run_resolved(scene: Scene, res: Resolved, progress: bool) -> SceneResult:
    """Integrate a resolved scene.

    Parameters
    ----------
    scene : Scene
    res : Resolved
        What :meth:`Scene.resolve` returned.
    progress : bool
        Show a tqdm bar on stderr (after 2 s).

    Returns
    -------
    SceneResult

    Raises
    ------
    SceneError
        The integrator refused the run settings.
    """
    started = time.perf_counter()
    result = backward = None
    if needs_trajectory(scene):
        result, backward = integrate_trajectory(scene, res, progress)
    done = {}
    for key, (analysis, spec) in requested(scene.outputs).items():
        done[key] = analysis.run(scene, res, spec, progress)
    wall = time.perf_counter() - started
    return SceneResult(scene, res, result, wall, done, backward)


def integrate_trajectory(scene: Scene, res: Resolved, progress: bool) -> tuple[Any, Any]:
    """The scene's trajectory, and with ``outputs.separatrix_delta`` the run mirrored about
    ``t_start`` (else None).

    Parameters
    ----------
    scene : Scene
    res : Resolved
    progress : bool
        Show a tqdm bar on stderr (after 2 s).

    Returns
    -------
    (IntegrationResult, IntegrationResult or None)

    Raises
    ------
    SceneError
        The integrator refused the run settings.
    """
    import mpmath

    from ...numerics.inputs import Precision
    from ...numerics.integrate import integrate
    from ...numerics.step_budget import DEFAULT_MAX_STEPS

    prec = Precision(scene.run_options.precision)
    t0, t1 = res.t_span
    n = scene.run_options.points or int(min(max(20 * float(t1 - t0) + 1, 2001), 200_001))
    if prec.is_double:
        t_eval = list(np.linspace(t0, t1, n))
    else:
        with mpmath.workprec(prec.prec):
            t_eval = [t0 + (t1 - t0) * mpmath.mpf(i) / (n - 1) for i in range(n)]
    method = scene.run_options.method
    event, bar = _progress_event(t0, t1, progress and method != "odefun")

    def run_over(t_end, times, events=None):
        return integrate(
            res.code,
            res.y0,
            (t0, t_end),
            [res.params[k] for k in res.code.params],
            method=method,
            precision=scene.run_options.precision,
            rtol=scene.run_options.rtol,
            atol=scene.run_options.atol,
            backend=scene.run_options.backend,
            t_eval=times,
            events=events,
            max_steps=scene.run_options.max_steps or DEFAULT_MAX_STEPS,  # the budget checked
        )

    try:
        result = run_over(t1, t_eval, [event] if event else None)
    except UserInputError as exc:
        raise SceneError(str(exc), scene.source, "run") from None
    finally:
        if bar is not None:
            bar.close()
    backward = None
    if scene.outputs.separatrix_delta is not None and result.success:
        # the same run mirrored about t_start: the trace's other asymptotic centre
        t_back = [2 * t0 - t for t in t_eval]
        backward = run_over(t_back[-1], t_back)
    return result, backward
