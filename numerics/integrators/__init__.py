"""Integration methods behind one small base class (scipy ``integrate/_ivp``): the one door.

Every integration of the project is a :class:`Problem` (a right-hand side of
:mod:`~chaplygin.numerics.integrators.flows`, its start, span, parameters, an explicit
:class:`~chaplygin.numerics.precision.Precision` and tolerances) solved by an
:class:`Integrator` of :data:`INTEGRATORS`: the generated Taylor method, scipy's methods,
``mpmath.odefun`` and DOP853 in C (the variational equations and the batches). No module
outside this package calls a solver (``tests/verify/test_layers.py``).

A method is mostly data: its name, the flows and precisions it integrates, its tolerance
floor per precision, whether it locates events, its options and backends; it fills the
``_prepare`` and ``_solve`` hooks of :class:`Integrator`, whose :meth:`~Integrator.solve` and
:meth:`~Integrator.run` do the rest. :data:`METHODS` are the ones that integrate a model's own
equations (what ``integrate(method=...)`` takes); :func:`get_integrator` also takes a class or
an instance.
"""

from __future__ import annotations

from ...derive.errors import UserInputError
from .base import BACKENDS, Integrator, Problem, Solution
from .dop853_c import CompiledDOP853
from .flows import (
    Batch,
    Flow,
    ModelFlow,
    Renormalisation,
    ReversedFlow,
    StroboscopicTimes,
    VariationalBatch,
    VariationalFlow,
)
from .odefun import MpmathOdefun
from .result import IntegrationResult
from .scipy_methods import BDF, DOP853, LSODA, RK45, Radau, ScipyMethod
from .taylor_method import TaylorMethod

__all__ = [
    "BACKENDS",
    "Problem",
    "Solution",
    "Integrator",
    "IntegrationResult",
    "Flow",
    "ModelFlow",
    "ReversedFlow",
    "VariationalFlow",
    "Batch",
    "StroboscopicTimes",
    "Renormalisation",
    "VariationalBatch",
    "ScipyMethod",
    "RK45",
    "DOP853",
    "LSODA",
    "Radau",
    "BDF",
    "TaylorMethod",
    "MpmathOdefun",
    "CompiledDOP853",
    "INTEGRATORS",
    "METHODS",
    "get_integrator",
]

#: Every integrator of the project by name: the one registry.
INTEGRATORS: dict[str, type[Integrator]] = {
    cls.name: cls
    for cls in (RK45, DOP853, LSODA, Radau, BDF, TaylorMethod, MpmathOdefun, CompiledDOP853)
}

#: The integrators of a model's own equations by name (scipy ``ivp.METHODS``): what
#: ``integrate(method=...)``, ``--method`` and a scene's ``method`` take.
METHODS: dict[str, type[Integrator]] = {
    name: cls for name, cls in INTEGRATORS.items() if ModelFlow in cls.flows
}


def get_integrator(
    method: str | Integrator | type[Integrator],
    registry: dict[str, type[Integrator]] | None = None,
) -> Integrator:
    """An integrator by name, class or instance.

    Parameters
    ----------
    method : str, Integrator subclass or Integrator
        A key of ``registry``, a class or an instance.
    registry : dict, optional
        Where names are looked up: :data:`METHODS` (default, the users' names) or
        :data:`INTEGRATORS`.

    Returns
    -------
    Integrator

    Raises
    ------
    UserInputError
        An unknown name; the message lists the valid ones.
    """
    registry = METHODS if registry is None else registry
    if isinstance(method, Integrator):
        return method
    if isinstance(method, type) and issubclass(method, Integrator):
        return method()
    if isinstance(method, str) and method in registry:
        return registry[method]()
    raise UserInputError(f"unknown method {method!r}; valid methods: {', '.join(registry)}")
