"""Analyses: scene outputs that are computations of their own (Poincaré maps, Lyapunov spectra,
periodic orbits, ...), plugged into :mod:`chaplygin.verify.scene`.

A trajectory output (``contact_trace``, ``drift``, ...) is drawn from the scene's one trajectory.
An *analysis* runs its own integrations (map iterations, variational equations) and returns an
:class:`AnalysisResult`: numbers for ``summary.json``, arrays for ``<key>.nc`` and figures. A scene
whose outputs are only analyses integrates no trajectory unless it asks for one
(``[outputs.trajectory]``).

To add an analysis: a module of :mod:`chaplygin.verify` that defines an :class:`Analysis`
(its scene table is a pydantic model) and calls :func:`register_analysis` at import; its name in
:data:`ANALYSIS_MODULES`; a field of that table's type in :class:`chaplygin.verify.scene.Outputs`.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "ANALYSIS_MODULES",
    "Analysis",
    "AnalysisResult",
    "analyses",
    "register_analysis",
]

#: Modules of chaplygin.verify that register an analysis when imported.
ANALYSIS_MODULES: tuple[str, ...] = ("poincare_output", "lyapunov_output", "periodic_output")

_REGISTRY: dict[str, Analysis] = {}


@dataclass
class AnalysisResult:
    """What an analysis returns.

    Attributes
    ----------
    summary : dict
        JSON-able numbers (decimal strings for working-precision values), stored in
        ``summary.json`` under ``analyses.<key>`` and printed by ``--json``.
    arrays : dict of str to (tuple of str, numpy.ndarray, dict)
        Variables written to ``<key>.nc``: ``name -> (dimensions, values, attributes)``;
        attributes should give ``long_name`` and ``units``.
    figures : dict of str to callable
        ``name -> function returning a matplotlib Figure`` (called only when written or asked).
    """

    summary: dict = field(default_factory=dict)
    arrays: dict[str, tuple[tuple[str, ...], np.ndarray, dict]] = field(default_factory=dict)
    figures: dict[str, Callable[[], Figure]] = field(default_factory=dict)


@dataclass(frozen=True)
class Analysis:
    """One analysis output of scenes.

    Attributes
    ----------
    key : str
        Its key in the scene's ``[outputs]`` table.
    run : callable
        ``run(scene, resolved, spec, progress) -> AnalysisResult``; raises
        :class:`~chaplygin.verify.scene.SceneError` for settings it cannot use.
    check : callable or None
        ``check(scene, code, spec) -> None``: refuse a spec before anything runs (raise
        :class:`~chaplygin.verify.scene.SceneError` with the key path).
    effects : tuple of str
        Effects of the model that it needs (added to the scene's, and reported).
    description : str
        One line for ``--explain``.
    """

    key: str
    run: Callable[..., AnalysisResult]
    check: Callable[..., None] | None = None
    effects: tuple[str, ...] = ()
    description: str = ""


def register_analysis(analysis: Analysis) -> Analysis:
    """Make ``analysis`` known to scenes (called by its module at import).

    Parameters
    ----------
    analysis : Analysis

    Returns
    -------
    Analysis
        The same object.
    """
    _REGISTRY[analysis.key] = analysis
    return analysis


def analyses() -> Mapping[str, Analysis]:
    """Every registered analysis, by output key (importing :data:`ANALYSIS_MODULES` first).

    Returns
    -------
    Mapping of str to Analysis
    """
    for name in ANALYSIS_MODULES:
        importlib.import_module(f"{__package__}.{name}")
    return dict(_REGISTRY)


def requested(outputs: Any) -> dict[str, tuple[Analysis, Any]]:
    """The analyses a scene's ``[outputs]`` asks for.

    Parameters
    ----------
    outputs : chaplygin.verify.scene.Outputs

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
