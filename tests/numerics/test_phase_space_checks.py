"""Inputs are checked against the constraints each model declares, not against names.

Each model ships its phase-space constraints as a generated routine (``constraints`` in the
numpy and mpmath modules: values, then scales) and declares how an omitted state group is
completed (``COMPLETION``); ``integrate`` refuses a state off the declared phase space
(issue 11, item 5).
"""

from __future__ import annotations

import glob
import os

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate, load_model_code
from reference import random_params, random_state

VARIANTS = sorted(
    os.path.basename(f)[: -len("_numpy.py")]
    for f in glob.glob(
        os.path.join(os.path.dirname(__file__), "..", "..", "generated", "*_numpy.py")
    )
)


def _code(variant):
    system, *effects = variant.split("__")
    return load_model_code(system, tuple(effects))


def _state(code, rng, p):
    """A random point of the phase space (the ball on a surface: x = sqrt(b) u, |u| = 1)."""
    if code.system != "ball_on_surface":
        return random_state(code, rng)
    b = np.array([p[code.params.index(f"b{i}")] for i in (1, 2, 3)])
    u = rng.normal(size=3)
    return np.concatenate([rng.normal(size=3), np.sqrt(b) * u / np.linalg.norm(u)])


@pytest.mark.parametrize("variant", VARIANTS)
def test_constraints_vanish_on_the_phase_space_and_not_off_it(variant):
    code = _code(variant)
    assert code.constraint_names, "every built-in model declares its phase space"
    rng = np.random.default_rng(11)
    p = np.abs(random_params(code, rng)) + 0.5
    y = _state(code, rng, p)
    k = len(code.constraint_names)
    values = np.asarray(code.numpy.constraints(0.0, y, p))
    assert np.all(np.abs(values[:k]) <= 64 * np.finfo(float).eps * values[k:])
    with mpmath.workdps(40):
        mp = code.mpmath.constraints(0, [mpmath.mpf(v) for v in y], [mpmath.mpf(v) for v in p])
        assert max(abs(float(a) - b) for a, b in zip(mp, values, strict=True)) <= 1e-13 * max(
            1.0, float(np.max(values[k:]))
        )
    # control: the same routine sees a state moved off the phase space
    off = y.copy()
    off[code.state.index(code.geometry[0][1][-1] + "1") if code.geometry else 3] += 1e-2
    assert np.max(np.abs(np.asarray(code.numpy.constraints(0.0, off, p))[:k])) > 1e-4


def test_a_ball_started_off_the_ellipsoid_is_refused():
    params = {"m": 1, "m_e": 0.4, "R": 0.3, "b": (1, 2, 3)}
    with pytest.raises(UserInputError, match="off the phase space of ball_on_surface"):
        integrate("ball_on_surface", {"omega": (0.7, -0.4, 0.5), "x": (0.5, 0.5, 0.5)}, 1, params)
    r = integrate("ball_on_surface", {"omega": (0.7, -0.4, 0.5), "x": (1, 0, 0)}, 1, params)
    assert r.success


def test_the_support_eigenframe_must_be_given():
    params = {"I": (1, 2, 3), "D_iso": 0.1, "D_al": 0.2, "D_be": 0.3}
    with pytest.raises(UserInputError, match=r'missing initial value of alpha: give y0\["alpha"\]'):
        integrate("spherical_support", {"M": (1, 2, 3), "gamma": (0, 0, 1)}, 1, params)


def test_the_ball_frame_is_completed_by_the_rule_its_effect_declares():
    code = load_model_code("chaplygin_ball", ("contact_point",))
    assert (("alpha", "beta"), "frame_bkm12_7") in code.completion
    r = integrate(
        "chaplygin_ball",
        {"M": (1, 2, 3), "gamma": (0, 0.6, 0.8)},
        1,
        {"I": (1, 2, 3), "D": 1, "b": 1},
        effects=["contact_point"],
    )
    y0 = dict(zip(r.state_names, r.y[:, 0], strict=True))
    M, g = np.array([1.0, 2, 3]), np.array([0, 0.6, 0.8])
    alpha = np.cross(M, g) / np.linalg.norm(np.cross(M, g))  # BKM12-7
    np.testing.assert_allclose([y0[f"alpha{i}"] for i in (1, 2, 3)], alpha, rtol=1e-15)
    assert y0["x"] == 0 and y0["y"] == 0
