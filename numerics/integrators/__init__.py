"""Integration methods behind one small base class (scipy ``integrate/_ivp``).

A method is mostly data: its name, the precisions it works in, its tolerance floor per
precision, whether it locates events, its options and backends; it fills the ``_prepare``
and ``_solve`` hooks of :class:`Integrator`, whose :meth:`~Integrator.run` does the rest.
:data:`METHODS` maps names to classes; :func:`get_integrator` also takes a class or an
instance.
"""

from __future__ import annotations

from ...derive.errors import UserInputError
from .base import BACKENDS, NUMBER_TYPES, Integrator, NumberType, Problem, Solution
from .odefun import MpmathOdefun
from .result import IntegrationResult
from .scipy_methods import BDF, DOP853, LSODA, RK45, Radau, ScipyMethod
from .taylor_method import TaylorMethod

__all__ = [
    "BACKENDS",
    "NUMBER_TYPES",
    "NumberType",
    "Problem",
    "Solution",
    "Integrator",
    "IntegrationResult",
    "ScipyMethod",
    "RK45",
    "DOP853",
    "LSODA",
    "Radau",
    "BDF",
    "TaylorMethod",
    "MpmathOdefun",
    "METHODS",
    "get_integrator",
]

#: Integration methods by name (scipy ``ivp.METHODS``).
METHODS: dict[str, type[Integrator]] = {
    cls.name: cls for cls in (RK45, DOP853, LSODA, Radau, BDF, TaylorMethod, MpmathOdefun)
}


def get_integrator(method: str | Integrator | type[Integrator]) -> Integrator:
    """An integrator by name (a key of :data:`METHODS`), class or instance.

    Parameters
    ----------
    method : str, Integrator subclass or Integrator

    Returns
    -------
    Integrator

    Raises
    ------
    UserInputError
        An unknown name; the message lists the valid ones.
    """
    if isinstance(method, Integrator):
        return method
    if isinstance(method, type) and issubclass(method, Integrator):
        return method()
    if isinstance(method, str) and method in METHODS:
        return METHODS[method]()
    raise UserInputError(f"unknown method {method!r}; valid methods: {', '.join(METHODS)}")
