"""The right-hand side and its Jacobian written from the auxiliaries in order
(derive/emit/base.py, for models whose expanded right-hand side is too large to emit).

Reference: the expanded right-hand side and Jacobian of the model (sympy's substitution and
differentiation of the whole expression), evaluated exactly at a generic rational point; the
chained routine's temporaries are evaluated one after another at the same point (forward
differentiation through the auxiliaries: a different route). A wrong derivative is refuted by
the same comparison. The general ball on a support surface, whose expanded right-hand side
has some 10^6 operations per component, is emitted chained, and its code conserves the
energy and the support's level, routines emitted separately from the expanded integrals.
"""

from __future__ import annotations

import random

import pytest
import sympy as sp
from chaplygin.derive.emit import base
from chaplygin.derive.emit.base import CHAIN_OPS, ModelRoutines, Routine, expanded_size
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.systems import build_model


def _point(model, seed: int = 2027) -> dict:
    rng = random.Random(seed)
    value = lambda: sp.Rational(rng.randint(-97, 97) or 1, rng.randint(2, 89))  # noqa: E731
    return {s: value() for s in (*model.state, *model.params, model.time)}


def _run(routine: Routine, point: dict) -> list:
    values = dict(point)
    for symbol, expr in routine.temporaries:
        values[symbol] = sp.sympify(expr).xreplace(values)
    return [sp.sympify(e).xreplace(values) for e in routine.outputs]


@pytest.mark.parametrize(
    "system, effects", [("chaplygin_ball", ()), ("chaplygin_ball", ("rubber",))]
)
def test_the_chained_routines_are_the_expanded_ones(system, effects, monkeypatch):
    """BKM12's ball and the rubber ball (auxiliaries omega(M), the rubber multiplier): the
    chained right-hand side, Jacobian and both together equal the expanded ones exactly at a
    rational point; a Jacobian with one derivative of an auxiliary dropped differs."""
    model = build_model(system, effects)
    assert 0 < expanded_size(model) < CHAIN_OPS  # generated/ keeps its code
    point = _point(model)
    rhs = [e.xreplace(point) for e in model.rhs_expanded]
    jac = [e.xreplace(point) for e in model.jacobian_expanded]
    monkeypatch.setattr(base, "CHAIN_OPS", 0)
    routines = ModelRoutines(model)
    assert routines.chained
    assert _run(routines.rhs, point) == rhs
    assert _run(routines.jacobian, point) == jac
    assert _run(routines.rhs_jacobian, point) == rhs + jac
    wrong = routines.jacobian
    k = next(i for i, (_, e) in enumerate(wrong.temporaries) if i >= len(model.aux) and e != 0)
    temporaries = list(wrong.temporaries)
    temporaries[k] = (temporaries[k][0], sp.S.Zero)
    broken = Routine(wrong.name, tuple(temporaries), wrong.outputs, wrong.shape)
    assert _run(broken, point) != jac


GENERAL_BALL = dict(
    inertia=("I1", "I2", "I3"), mass="m", radius="b", centre_of_mass=(0, 0, "a"), gravity="g",
    support="surface", support_surface="p1**2/4 + p2**2 + p3**2/2.25 - 1",
)  # fmt: skip


@pytest.mark.slow  # about 30 s: the first use emits and compiles the 15-D model
def test_a_general_ball_on_a_support_surface_is_emitted_chained_and_keeps_its_integrals():
    """A ball off centre on an ellipsoidal support: expanded, some 10^6 operations per
    component (over CHAIN_OPS: chained, some 2 10^5 for the right-hand side and the whole
    Jacobian); integrated (DOP853 in C, rtol 1e-10) its
    energy and F keep their values to 1e3 rtol."""
    import chaplygin

    system = RollingSystem("chained_ball", **GENERAL_BALL)
    model = system.model()
    size = expanded_size(model)
    assert size > CHAIN_OPS
    routines = ModelRoutines(model)  # the whole Jacobian smaller than one expanded component
    assert routines.chained and routines.rhs_jacobian.operation_count < size // 3
    chaplygin.register_system(system)
    y0 = {"omega": (0.3, -0.2, 0.9), "p": (0, 0, 1.5), "e1": (1, 0, 0), "e2": (0, 1, 0),
          "e3": (0, 0, 1)}  # fmt: skip
    values = {"m": 1.3, "b": 0.2, "I1": 0.011, "I2": 0.013, "I3": 0.017, "a": 0.03, "g": 9.81}
    r = chaplygin.integrate("chained_ball", y0, 3.0, values, method="DOP853", rtol=1e-10,
                            atol=1e-10)  # fmt: skip
    assert r.success
    assert max(float(v) for v in r.drift.values()) < 1e3 * 1e-10
