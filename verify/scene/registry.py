"""Scene outputs by name: which outputs a scene asks for, and the modules that compute them.

Trajectory outputs (:data:`TRAJECTORY_OUTPUTS`) are drawn from the scene's one trajectory by
:class:`~chaplygin.verify.scene.result.SceneResult`. Analyses are found by their output key in
:data:`ANALYSIS_MODULES` and imported by name when a scene needs them; each module registers its
:class:`~chaplygin.verify.scene.outputs.Analysis` through :mod:`chaplygin.verify.scene.outputs`,
the only part of the scene package it imports.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Any

from .outputs import Analysis, registered_analyses

__all__ = [
    "ANALYSIS_MODULES",
    "OUTPUT_EFFECTS",
    "TRAJECTORY_OUTPUTS",
    "analyses",
    "needs_trajectory",
    "requested",
]

#: Analysis outputs: key in ``[outputs]`` -> the module that registers it. Analyses run, and
#: their results are written and summarised, in this order.
ANALYSIS_MODULES: dict[str, str] = {
    "poincare": "chaplygin.verify.outputs.poincare",
    "lyapunov": "chaplygin.verify.outputs.lyapunov",
    "periodic_orbits": "chaplygin.verify.outputs.periodic_orbits",
}

#: Outputs drawn from the scene's trajectory.
TRAJECTORY_OUTPUTS = (
    "contact_trace",
    "body_trace",
    "series",
    "drift",
    "diagram",
    "separatrix_delta",
)

#: Effects a trajectory output needs: output key -> effects (an analysis declares its own).
OUTPUT_EFFECTS: dict[str, tuple[str, ...]] = {
    "contact_trace": ("contact_point",),
    "body_trace": ("contact_point",),
    "separatrix_delta": ("contact_point",),
}


def analyses() -> Mapping[str, Analysis]:
    """Every analysis, by output key in the order of :data:`ANALYSIS_MODULES` (their modules
    imported first).

    Returns
    -------
    Mapping of str to Analysis
    """
    for module in ANALYSIS_MODULES.values():
        importlib.import_module(module)
    registered = registered_analyses()
    missing = [key for key in ANALYSIS_MODULES if key not in registered]
    if missing:  # pragma: no cover - a module that does not register its key
        raise RuntimeError(f"{ANALYSIS_MODULES[missing[0]]} registers no analysis {missing[0]!r}")
    return {key: registered[key] for key in ANALYSIS_MODULES}


def requested(outputs: Any) -> dict[str, tuple[Analysis, Any]]:
    """The analyses a scene's ``[outputs]`` asks for.

    Parameters
    ----------
    outputs : chaplygin.verify.scene.schema.Outputs

    Returns
    -------
    dict of str to (Analysis, spec)
    """
    found = {}
    for key, analysis in analyses().items():
        spec = getattr(outputs, key, None)
        if spec is not None:
            found[key] = (analysis, spec)
    return found


def needs_trajectory(scene: Any) -> bool:
    """Whether a run integrates the scene's trajectory: a trajectory output is asked for, or
    ``[outputs.trajectory]`` is given, or the scene asks for no analysis.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    bool
    """
    outputs = scene.outputs
    if "trajectory" in outputs.model_fields_set or not requested(outputs):
        return True
    return any(getattr(outputs, key) is not None for key in TRAJECTORY_OUTPUTS)
