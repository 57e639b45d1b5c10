"""Continuation of periodic orbits of an autonomous flow (numerics/dynamics/flow_orbits.py)
against closed forms: the Chaplygin ball's steady rotations about a principal axis
(BKM12-crit with M_gamma = 0: M = (I_1 + D) w e_1, gamma turning about e_1, period
2 pi (I_1 + D)/|M|), stable about an extreme axis and unstable about the middle one
(BKM12-1.5stab, the middle-axis rule). Generic non-dyadic parameters."""

from __future__ import annotations

import math

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.flow_orbits import continue_flow_orbit, refine_flow_orbit

I2, I3, D, M = 2.03, 2.97, 1.13, 0.83


def _branch():
    code = load_model_code("chaplygin_ball")
    start = [1.41, I2, I3, D]
    y0 = [M, 0.0, 0.0, 0.0, 0.6, 0.8]
    period = 2 * math.pi * (start[0] + D) / M
    orbit = refine_flow_orbit(code, start, y0, period * 1.001)
    assert orbit.converged
    return code, continue_flow_orbit(code, start, orbit, "I1", 2.63, 11)


def test_the_branch_follows_the_closed_form_and_finds_the_middle_axis():
    """Eleven steps in I_1 from 1.41 to 2.63 through I_2 = 2.03: every period is the closed
    form's within what Newton's acceptance allows (10 times its residual tolerance over the
    flow's speed); the control (the period without D) is refuted by the same comparison; the
    rotation is stable while e_1 is the extreme axis (I_1 < I_2) and unstable once it is the
    middle one (I_2 < I_1 < I_3): one change of stability, between the two values around
    I_2; det Phi = 1 (the invariant density, BKM12-4)."""
    code, branch = _branch()
    assert branch.stopped == "reached" and len(branch.values) == 12
    assert branch.values[-1] == 2.63
    p = np.array([0.0, I2, I3, D])
    for value, orbit in zip(branch.values, branch.orbits, strict=True):
        p[0] = value
        speed = float(np.linalg.norm(code.numpy.rhs(0.0, orbit.point, p)))
        bound = 10 * orbit.tolerance / speed
        assert abs(orbit.period - 2 * math.pi * (value + D) / M) <= bound
        assert abs(orbit.period - 2 * math.pi * value / M) > 1e6 * bound  # the control
    assert branch.stable.tolist() == [v < I2 for v in branch.values]
    assert len(branch.changes) == 1
    a, b = branch.changes[0]
    assert a < I2 < b
    for orbit, unit in zip(branch.orbits, branch.unit_tol, strict=True):
        assert abs(orbit.determinant - 1) <= unit
    unstable = [o for o, s in zip(branch.orbits, branch.stable, strict=True) if not s]
    assert all(np.max(np.abs(o.multipliers)) > 1.5 for o in unstable[1:])


def test_continuation_refuses_bad_settings():
    code, branch = _branch()
    start = [1.41, I2, I3, D]
    with pytest.raises(UserInputError, match="no parameter"):
        continue_flow_orbit(code, start, branch.orbits[0], "Omega", 2.0, 4)
    with pytest.raises(UserInputError, match="steps"):
        continue_flow_orbit(code, start, branch.orbits[0], "I1", 2.0, 0)
