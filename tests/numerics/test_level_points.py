"""``point = k`` on a described system: the level set's points, enumerated.

The system is a described balanced ball (principal moments 2, 3, 4 about its centre, mass 1,
radius 1: the Chaplygin ball with ``D = m b^2 = 1``). The references are typed from the
mechanics here, not taken from the derived model: the momentum about the contact point is
``M = I omega + m b^2 (omega - (omega, gamma) gamma)`` and the energy ``(M, omega)/2``. At
``gamma = e3`` this gives ``omega_i = M_i/(I_i + 1)`` (i = 1, 2) and ``omega_3 = M_3/I_3``, so
the level set ``(M, gamma) = C``, ``(M, M) = n``, ``H = h`` over ``M`` is the four points
``(+-a, +-b, C)`` with ``a^2 + b^2 = n - C^2`` and ``a^2/3 + b^2/4 = 2h - C^2/4``.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.systems import register_system
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.integral_levels import LevelRequest, state_on_levels
from chaplygin.numerics.level_points import level_points, point_on_levels
from chaplygin.numerics.precision import Precision
from chaplygin.verify.cli import main

INERTIA = (2, 3, 4)
BALL = RollingSystem("level_points_ball", inertia=INERTIA, mass=1, radius=1)
LEVEL = {"H": "0.17", "(M,M)": "1.2", "(M,gamma)": "0.5"}
DOUBLE = Precision("double")  # the solve runs at parse_dps + 10 = 40 digits


@pytest.fixture(scope="module")
def code():
    register_system(BALL)
    return load_model_code(BALL.name, ())


def _energy(M, gamma):
    """``(M, omega)/2`` from the mechanics: ``omega`` solved from the momentum's definition."""
    g = mpmath.matrix(gamma)
    II = mpmath.diag([mpmath.mpf(v) + 1 for v in INERTIA]) - g * g.T  # I + m b^2 (1 - g g^T)
    omega = mpmath.lu_solve(II, mpmath.matrix(M))
    return sum(m * w for m, w in zip(M, omega, strict=True)) / 2


def _closed_form(h, n, C) -> list[list]:
    """The four points of the level set at gamma = e3, in the documented order (M1, then M2)."""
    a2 = (2 * h - C * C / 4 - (n - C * C) / 4) / (mpmath.mpf(1) / 3 - mpmath.mpf(1) / 4)
    a, b = mpmath.sqrt(a2), mpmath.sqrt(n - C * C - a2)
    return [[sa * a, sb * b, C] for sa in (-1, 1) for sb in (-1, 1)]


def _request(point, **changes):
    fields = dict(given={"gamma": [0, 0, 1]}, free=["M"], targets=LEVEL, expressions={})
    fields.update(changes)
    return LevelRequest(point=point, **fields)


def test_the_points_of_a_ball_level_set_are_the_closed_form_in_order(code):
    found = level_points(code, {}, _request(0), DOUBLE)
    with mpmath.workdps(40):
        want = _closed_form(*(mpmath.mpf(LEVEL[k]) for k in ("H", "(M,M)", "(M,gamma)")))
        got = [[mpmath.mpf(v) for v in p["M"]] for p in found.points]
        assert len(got) == 4
        for g, w in zip(got, want, strict=True):
            assert max(abs(x - y) for x, y in zip(g, w, strict=True)) <= mpmath.mpf(10) ** -30
        assert all(p["gamma"] == found.points[0]["gamma"] for p in found.points)


def test_each_point_has_the_values_at_higher_digits_is_distinct_and_reproducible(code):
    """The model's integrals at 60 digits and the energy from the mechanics agree with the
    values to the solve's 40 digits; two calls give the same text; the points are apart."""
    first = level_points(code, {}, _request(0), DOUBLE)
    assert first.points == level_points(code, {}, _request(0), DOUBLE).points
    names = list(code.integral_names)
    with mpmath.workdps(60):
        for p in first.points:
            M, g = ([mpmath.mpf(v) for v in p[k]] for k in ("M", "gamma"))
            values = code.mpmath.integrals(mpmath.mpf(0), M + g, [])
            for name, want in LEVEL.items():
                assert abs(values[names.index(name)] - mpmath.mpf(want)) <= mpmath.mpf(10) ** -30
            assert abs(_energy(M, g) - mpmath.mpf(LEVEL["H"])) <= mpmath.mpf(10) ** -30
        points = [np.array([float(v) for v in p["M"]]) for p in first.points]
    gaps = [np.abs(a - b).max() for i, a in enumerate(points) for b in points[:i]]
    assert min(gaps) > 0.1


def _sphere_closed_form(G, C, h) -> list[list]:
    """The four points of the level set over gamma at ``M = (0, 0, G)``, in order.

    With ``J = diag(I_i + 1)`` the momentum's definition gives (Sherman-Morrison)
    ``(M, omega) = G^2/J3 + G^2 g3^2/(J3^2 (1 - s))``, ``s = sum g_i^2/J_i``: so ``g3 = C/G``,
    ``s`` follows from ``2 h``, and ``g1^2/J1 + g2^2/J2 = s - g3^2/J3``, ``g1^2 + g2^2 = 1 - g3^2``.
    """
    J = [mpmath.mpf(v) + 1 for v in INERTIA]
    g3 = C / G
    s = 1 - g3**2 / J[2] ** 2 / (2 * h / G**2 - 1 / J[2])
    rest = s - g3**2 / J[2]
    a2 = (rest - (1 - g3**2) / J[1]) / (1 / J[0] - 1 / J[1])
    a, b = mpmath.sqrt(a2), mpmath.sqrt(1 - g3**2 - a2)
    return [[sa * a, sb * b, g3] for sa in (-1, 1) for sb in (-1, 1)]


def test_a_free_unit_vector_is_a_point_of_its_sphere(code):
    """gamma free (two unknowns: H and (M, gamma)), M = (0, 0, 1.2) given: the four points
    are the closed form, in order, unit vectors with the values at 60 digits (the energy from
    the mechanics)."""
    M, targets = ["0", "0", "1.2"], {"H": "0.1538", "(M,gamma)": "0.6"}
    request = _request(0, given={"M": M}, free=["gamma"], targets=targets)
    found = level_points(code, {}, request, DOUBLE)
    assert "Fibonacci lattice of 64 points" in found.grid
    with mpmath.workdps(40):
        want = _sphere_closed_form(mpmath.mpf("1.2"), mpmath.mpf("0.6"), mpmath.mpf("0.1538"))
        got = [[mpmath.mpf(v) for v in p["gamma"]] for p in found.points]
        assert len(got) == 4
        for g, w in zip(got, want, strict=True):
            assert max(abs(x - y) for x, y in zip(g, w, strict=True)) <= mpmath.mpf(10) ** -30
    with mpmath.workdps(60):
        Mv = [mpmath.mpf(v) for v in M]
        for p in found.points:
            g = [mpmath.mpf(v) for v in p["gamma"]]
            assert abs(sum(v * v for v in g) - 1) <= mpmath.mpf(10) ** -35
            assert abs(_energy(Mv, g) - mpmath.mpf("0.1538")) <= mpmath.mpf(10) ** -30


def test_a_point_beyond_those_found_is_refused_with_their_number_and_grid(code):
    with pytest.raises(UserInputError, match=r"has 4 point\(s\) \(point = 0..3\) from the free "
                       "scalars on a lattice of the energy ellipsoid") as info:  # fmt: skip
        point_on_levels(code, {}, _request(4), DOUBLE)
    assert getattr(info.value, "key", None) == "point"


@pytest.mark.parametrize("point", [0, None])
def test_an_energy_above_the_level_s_range_is_refused_by_a_certificate(code, point):
    """With point = 0 (the enumeration) and without (Newton from the given M): H = 0.3
    exceeds the largest energy on (M, M) = 1.2, (M, gamma) = 0.5 at gamma = e3 (0.1896, from
    the closed form), and the refusal states a combination of the conditions that is positive;
    its multipliers, read from the message, give a positive-definite quadratic with a positive
    least value when the energy is the mechanics' (an independent check of the proof)."""
    with mpmath.workdps(40):
        top = (mpmath.mpf("0.95") / 3 + mpmath.mpf("0.25") / 4) / 2
    assert top < mpmath.mpf("0.3")
    given = {"M": [1, 0, 0], "gamma": [0, 0, 1]}
    request = _request(point, given=given, targets={**LEVEL, "H": "0.3"})
    with pytest.raises(UserInputError, match="never taken together") as info:
        (state_on_levels if point is None else point_on_levels)(code, {}, request, DOUBLE)
    text = str(info.value).split("the sum of ")[1].split(" is a positive")[0]
    lam = [float(term.split(" (")[0]) for term in text.split(", ")]
    assert len(lam) == 3 and "\n" not in str(info.value)
    # sum lam_i (F_i - v_i) over M = (x, y, z): F = (energy, |M|^2, z), energy from _energy
    Q = np.diag([lam[0] / 3 + 2 * lam[1], lam[0] / 4 + 2 * lam[1], lam[0] / 4 + 2 * lam[1]])
    g = np.array([0.0, 0.0, lam[2]])
    c = -0.3 * lam[0] - 1.2 * lam[1] - 0.5 * lam[2]
    assert float(_energy([1, 0, 0], [0, 0, 1])) == pytest.approx(1 / 6, rel=1e-15)
    assert np.all(np.linalg.eigvalsh(Q) > 0)
    assert c - g @ np.linalg.solve(Q, g) / 2 > 0.05


def test_the_default_is_still_newton_from_the_given_values(code):
    """Without point the state is the root Newton reaches from the given M (one of the four)."""
    given = {"M": ["0.7", "0.7", "0.5"], "gamma": [0, 0, 1]}
    values, _, how = state_on_levels(code, {}, _request(None, given=given), DOUBLE)
    assert "Newton from the given values" in how
    M = [float(v) for v in values["M"]]
    with mpmath.workdps(40):
        want = _closed_form(mpmath.mpf("0.17"), mpmath.mpf("1.2"), mpmath.mpf("0.5"))[3]
    assert np.allclose(M, [float(v) for v in want], rtol=0, atol=1e-15)


SCENE = """
title = "a described ball on a level set"
[system]
name = "level_points_ball"
inertia = [2, 3, 4]
mass = 1
radius = 1
[initial]
gamma = [0, 0, 1]
free = ["M"]
integrals = { H = 0.17, "(M,M)" = 1.2, "(M,gamma)" = 0.5 }
point = POINT
[run]
t_end = 1
"""


def test_a_scene_picks_the_point_and_refuses_one_beyond(tmp_path, capsys):
    from chaplygin.verify.scene import Scene

    path = tmp_path / "scene.toml"
    path.write_text(SCENE.replace("POINT", "2"))
    y = [float(v) for v in Scene.from_toml(path).resolve().y0]
    with mpmath.workdps(40):
        want = _closed_form(mpmath.mpf("0.17"), mpmath.mpf("1.2"), mpmath.mpf("0.5"))[2]
    assert np.allclose(y[:3], [float(v) for v in want], rtol=0, atol=1e-15)
    path.write_text(SCENE.replace("POINT", "7"))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "initial.point" in err and "4 point(s)" in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "free, targets, message",
    [
        # the energy on (M, gamma) = 0.6 at M = (0, 0, 1.2) lies in [0.15344, 0.15429]
        (["gamma"], {"H": "0.2", "(M,gamma)": "0.6"}, "has no point from gamma on the Fibonacci "
         "lattice of 64 points (64 starts) (not a proof that none exists)"),
        (["gamma1", "gamma2"], {"H": "0.15", "(M,gamma)": "0.6"}, "free a unit vector as a whole"),
        (["gamma"], {"H": "0.15"}, "1 integral value(s) need as many unknowns, 2 given"),
    ],
)  # fmt: skip
def test_requests_the_enumeration_cannot_meet_are_refused_in_one_line(code, free, targets, message):
    request = _request(0, given={"M": [0, 0, "1.2"], "gamma": [0, 0, 1]}, free=free,
                       targets=targets)  # fmt: skip
    with pytest.raises(UserInputError) as info:
        point_on_levels(code, {}, request, DOUBLE)
    assert message in str(info.value) and "\n" not in str(info.value), str(info.value)


def test_free_scalars_without_the_energy_start_on_the_stated_box(code):
    """(M, M), (M, gamma) and M1 (an expression) at gamma = e3: M = (0.3, +-sqrt(1.2 - 0.25 -
    0.09), 0.5), both inside the box [-1, 1]^3 about the M not given (zeros), found in order."""
    targets = {"(M,M)": "1.2", "(M,gamma)": "0.5", "first": "0.3"}
    request = _request(0, targets=targets, expressions={"first": "M1"})
    found = level_points(code, {}, request, DOUBLE)
    assert "box of half-width 1 + max |given|" in found.grid and found.starts == 64
    with mpmath.workdps(40):
        b = mpmath.sqrt(mpmath.mpf("1.2") - mpmath.mpf("0.25") - mpmath.mpf("0.09"))
        want = [[mpmath.mpf("0.3"), s * b, mpmath.mpf("0.5")] for s in (-1, 1)]
        got = [[mpmath.mpf(v) for v in p["M"]] for p in found.points]
        assert len(got) == 2
        for g, w in zip(got, want, strict=True):
            assert max(abs(x - y) for x, y in zip(g, w, strict=True)) <= mpmath.mpf(10) ** -30
