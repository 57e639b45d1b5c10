"""The public interface of scene outputs: what an output module may import of the scene package.

A trajectory output (``contact_trace``, ``drift``, ...) is drawn from the scene's one trajectory.
An *analysis* runs its own integrations (map iterations, variational equations) and returns an
:class:`AnalysisResult`: numbers for ``summary.json``, arrays for ``<key>.nc`` and figures. A scene
whose outputs are only analyses integrates no trajectory unless it asks for one
(``[outputs.trajectory]``).

To add an analysis: a module (in :mod:`chaplygin.verify.outputs`) that defines an
:class:`Analysis` (its scene table is a pydantic model) and calls :func:`register_analysis` at
import; its key and module in :data:`chaplygin.verify.scene.registry.ANALYSIS_MODULES`; a field of
that table's type in :class:`chaplygin.verify.scene.schema.Outputs`. The module imports from the
scene package only this module's public names (``tests/verify/test_layers.py`` checks it): the scene
reaches its outputs by name, through the registry, and never the other way round, so there is no
import cycle. It receives the scene and its resolved state as arguments and uses their public
attributes and methods (``scene.key_error``, ``scene.with_initial``, ``resolved.y0``, ...).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .errors import SceneError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "Analysis",
    "AnalysisResult",
    "SceneError",
    "register_analysis",
    "registered_analyses",
]

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
        :class:`SceneError` for settings it cannot use.
    check : callable or None
        ``check(scene, code, spec) -> None``: refuse a spec before anything runs (raise
        :class:`SceneError` with the key path).
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


def registered_analyses() -> Mapping[str, Analysis]:
    """The analyses registered so far, by output key (see
    :func:`chaplygin.verify.scene.registry.analyses`, which imports their modules first).

    Returns
    -------
    Mapping of str to Analysis
    """
    return dict(_REGISTRY)
