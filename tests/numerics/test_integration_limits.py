"""Integration refuses a non-finite start, stops on non-finite results, and has step and
wall-time limits a user can raise (issue 11, item 4)."""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.numerics.integrators import Integrator
from chaplygin.numerics.integrators.base import Solution

Y0 = {"M": ("-0.3", "0.8", "0.45"), "gamma": ("0.36", "0.48", "0.8")}
P = {"I": ("1.1", "2.3", "3.7"), "D": "0.9"}


@pytest.mark.parametrize("precision", ["double", 30])
def test_a_start_where_the_equations_overflow_is_refused(precision):
    with pytest.raises(UserInputError, match="not finite at the initial state"):
        integrate("chaplygin_ball", Y0, 1, {"I": (1, 2, 3), "D": "1e300"}, precision=precision)


def test_the_same_parameters_are_fine_where_the_precision_holds_them():
    r = integrate("chaplygin_ball", Y0, 1, {"I": (1, 2, 3), "D": "1e30"}, precision=30)
    assert r.success


@pytest.mark.parametrize(
    ("method", "precision"),
    [("DOP853", "double"), ("RK45", "double"), ("taylor", "double"), ("taylor", 30)],
)
def test_the_step_limit_stops_with_a_status_that_says_what_to_do(method, precision):
    r = integrate("chaplygin_ball", Y0, 500, P, method=method, precision=precision, max_steps=20)
    assert r.status == -2 and "max_steps" in r.message
    full = integrate(
        "chaplygin_ball", Y0, 500, P, method=method, precision=precision, max_steps=10**6
    )
    assert full.success  # the same run with the limit raised goes through


@pytest.mark.parametrize(("method", "precision"), [("DOP853", "double"), ("taylor", 30)])
def test_the_wall_time_limit_stops_with_its_own_status(method, precision):
    r = integrate(
        "chaplygin_ball", Y0, 1e7, P, method=method, precision=precision, max_wall_s=0.05,
        max_steps=10**9,  # (without a limit of its own, a span this long is refused at once)
    )
    assert r.status == -6 and "max_wall_s" in r.message


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"max_steps": 0}, "max_steps must be"),
        ({"max_steps": 2.5}, "max_steps must be"),
        ({"max_wall_s": -1}, "max_wall_s must be"),
        ({"max_wall_s": "soon"}, "max_wall_s must be"),
    ],
)
def test_bad_limits_are_refused(kwargs, match):
    with pytest.raises(UserInputError, match=match):
        integrate("chaplygin_ball", Y0, 1, P, **kwargs)


class _Blowup(Integrator):
    """A method whose solution turns NaN: the bookkeeping must flag it, whatever the method."""

    name = "blowup"
    precisions = ("double",)
    rtol_floor = {"double": 100.0}
    backends = ("numpy",)

    def _solve(self, problem, backend):
        y0 = np.asarray(problem.y0, dtype=float)
        y = np.column_stack([y0, np.full_like(y0, np.nan)])
        return Solution(t=np.array([0.0, 1.0]), y=y, status=0, message="done", nfev=2)


def test_a_solution_that_becomes_nan_is_a_failure_not_a_result():
    r = integrate("chaplygin_ball", Y0, 1, P, method=_Blowup)
    assert r.status == -1 and not r.success
    assert "NaN or infinite" in r.message


@pytest.mark.parametrize(("method", "precision"), [("DOP853", "double"), ("taylor", 30)])
def test_a_span_that_could_only_end_at_the_default_limit_is_refused_at_once(method, precision):
    with pytest.raises(UserInputError, match="could only end at the step limit"):
        integrate("chaplygin_ball", Y0, 1e12, P, method=method, precision=precision)
    # with a limit of its own the run is the user's to bound: it stops there
    r = integrate("chaplygin_ball", Y0, 1e12, P, method=method, precision=precision,
                  max_steps=20)
    assert r.status == -2
