"""The types of the sweep's reducers: :class:`Variable`, :class:`PointContext`,
:class:`Reducer` and the registry :data:`REDUCERS` with :func:`register_reducer`. The reducers
themselves are in :mod:`~chaplygin.verify.sweep_reducers` and
:mod:`~chaplygin.verify.sweep_reducers_maps`."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ..derive.errors import UserInputError

__all__ = ["REDUCERS", "Reducer", "Variable", "PointContext", "register_reducer"]


# ------------------------------------------------------------------------------- reducers
@dataclass(frozen=True)
class Variable:
    """One stored result of a reducer.

    Attributes
    ----------
    dims : tuple of str
        Extra dimensions after the grid's (``("state",)``), empty for a number per point.
    dtype : str
        ``"float64"``, ``"int16"`` or ``"int8"``.
    attrs : dict
        ``long_name`` and ``units``.
    """

    dims: tuple[str, ...] = ()
    dtype: str = "float64"
    attrs: dict = field(default_factory=dict)

    @property
    def fill(self) -> float | int:
        """The value of a point not (yet) computed: NaN, or -1 for integers."""
        return math.nan if self.dtype.startswith("float") else -1


@dataclass
class PointContext:
    """What a reducer sees of one point.

    Attributes
    ----------
    scene : chaplygin.verify.scene.Scene
        The scene with the point's keys replaced.
    resolved : chaplygin.verify.scene.Resolved
    sweep : chaplygin.verify.sweep_table.Sweep
        The sweep table (reducer options).
    start : sequence or None
        With ``carry``: the state the previous point of the grid line ended on (the point's
        reducers start there instead of at the scene's state).
    end : sequence or None
        Set by a reducer that carries (:attr:`Reducer.carries`): the state to start the next
        point from.
    """

    scene: Any
    resolved: Any
    sweep: Any
    _trajectory: Any = None
    batched: dict[str, Any] = field(default_factory=dict)
    #: A start carried from the previous point of the grid line (``carry``), else None.
    start: Any = None
    #: The state a reducer ended on (on the attractor), carried to the next point.
    end: Any = None

    def trajectory(self) -> Any:
        """The scene's trajectory (integrated once, shared by the reducers).

        Returns
        -------
        chaplygin.numerics.integrate.IntegrationResult
        """
        if self._trajectory is None:
            from .scene import integrate_trajectory

            self._trajectory, _ = integrate_trajectory(self.scene, self.resolved, False)
        return self._trajectory

    def param(self, name: str) -> Any:
        """A parameter's value at the working precision.

        Parameters
        ----------
        name : str

        Returns
        -------
        number

        Raises
        ------
        UserInputError
            The model has no such parameter.
        """
        try:
            return self.resolved.params[name]
        except KeyError:
            raise UserInputError(
                f"the model {self.resolved.code.name} has no parameter {name!r}"
            ) from None


@dataclass(frozen=True)
class Reducer:
    """One way to reduce a point to numbers.

    Attributes
    ----------
    name : str
        Its name in ``reduce = [...]``.
    variables : callable
        ``variables(code, sweep) -> dict name -> Variable``.
    run : callable
        ``run(context) -> dict name -> value`` (arrays shaped by the variable's dims).
    coords : callable or None
        ``coords(code) -> dict dim -> list of labels`` for its extra dimensions.
    description : str
    batch : callable or None
        ``batch(contexts) -> list`` for all resolved points of a chunk at once: per point the
        values (as from ``run``), an exception (raised for that point alone) or None (that
        point goes through ``run``).
    carries : bool
        ``run`` starts at ``context.start`` when given and sets ``context.end``: usable with
        the sweep's ``carry``.
    """

    name: str
    variables: Callable[[Any, Any], dict[str, Variable]]
    run: Callable[[PointContext], dict[str, Any]]
    coords: Callable[[Any], dict[str, list]] | None = None
    description: str = ""
    batch: Callable[[list[PointContext]], list[Any]] | None = None
    carries: bool = False


#: Reducers by name (see :func:`register_reducer`).
REDUCERS: dict[str, Reducer] = {}


def register_reducer(reducer: Reducer) -> Reducer:
    """Make a reducer available to ``reduce = [...]``.

    Parameters
    ----------
    reducer : Reducer

    Returns
    -------
    Reducer
        The same object.
    """
    REDUCERS[reducer.name] = reducer
    return reducer
