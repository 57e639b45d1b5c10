"""A body in a spherical support of balls described by its mechanics (``support="balls"``).

Four balls in exact, non-orthogonal directions with non-dyadic moments and ratios: the
described model is the N-ball model of the same support after substitution
(``n_ball_model(4, space_directions=...)``) and the closed model (BKM12-32..34) with the
support parameters and the eigenframe of :func:`support_parameters`, on the phase space:
the fields are the same expressions of the state and ``omega``, and the reference's
``omega`` gives the described momentum ``M = II omega`` (Groebner normal forms modulo
the frame's relations). The integrals and the density the description ships are proved by
the verifier. A wrong ratio and swapped ``D_al, D_be`` are refuted by the same
comparisons; every refusal is one line.
"""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.model import Model
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.spherical_support import (
    build_spherical_support,
    n_ball_model,
    support_parameters,
)
from chaplygin.verify.identity import Domain, decide, lie_derivative

R = sp.Rational
#: Four balls: (moment, ratio); balls 3 and 4 have the same weight lambda/r^2 = 25/21.
BALLS = ((R(3, 7), R(5, 11)), (R(4, 13), R(2, 3)), (R(3, 7), R(3, 5)), (R(100, 189), R(2, 3)))
#: Their directions, not normalised: e_a = (2, 3, 6)/7, e_b = (3, -6, 2)/7 and (4 e_a +- 3
#: e_g)/5 with e_g = e_a x e_b: the support tensor is diagonal in (e_a, e_b, e_g), its
#: eigenvalues rational (the closed model's frame is exact).
EIGEN_DIRECTIONS = ((2, 3, 6), (3, -6, 2), (26, 18, 15), (10, -6, -33))
#: Four rational unit directions in no special position (for the N-ball comparison).
DIRECTIONS = ((R(1, 3), R(2, 3), R(2, 3)), (2, -3, 6), (-4, 4, 7), ("6/7", "2/7", "-3/7"))


def _described(directions, balls=BALLS, **fields) -> RollingSystem:
    tables = [
        {"moment": m, "ratio": r, "direction": d}
        for (m, r), d in zip(balls, directions, strict=True)
    ]
    return RollingSystem(
        "four_balls", inertia=("I1", "I2", "I3"), support="balls", balls=tables, **fields
    )


def _proved_zero(expr: sp.Expr, model: Model) -> bool:
    return decide([sp.together(expr)], Domain(model), method="symbolic").verdict == "proved"


def _mismatch(reference: Model, described: Model, sub: dict) -> list[str]:
    """The reference's states whose rate, written in ``omega``, the described flow does
    not give (``d sub[y]/dt`` along it, at ``M = II omega``, on the phase space), and
    ``"omega"`` when the reference's ``omega`` does not give the described ``M = II
    omega`` on the phase space."""
    at_M = dict(zip(described.group("M"), described.momentum_of_omega, strict=True))
    bad = []
    for i, y in enumerate(reference.state):
        flow = zip(described.state, described.rhs, strict=True)
        ours = sum((sp.diff(sub[y], x) * f for x, f in flow), 0)
        if not _proved_zero((ours - reference.rhs[i].xreplace(sub)).xreplace(at_M), described):
            bad.append(y.name)
    theirs = reference.expand_aux(reference.omega).xreplace(sub)
    momentum = described.momentum_of_omega.xreplace(dict(zip(described.omega, theirs, strict=True)))
    if not all(_proved_zero(e, described) for e in momentum - described.group("M")):
        bad.append("omega")
    return bad


def _names(model: Model) -> dict[str, sp.Symbol]:
    return {s.name: s for s in (*model.state, *model.params)}


# ------------------------------------------------------------------ against N balls
def _n_ball_substitution(reference: Model, described: Model, balls=BALLS) -> dict:
    ours = _names(described)
    sub = {s: ours[s.name] for s in reference.state}
    sub.update({s: ours[s.name] for s in reference.params if s.name.startswith("I")})
    for k, (moment, ratio) in enumerate(balls, start=1):
        sub[_names(reference)[f"lambda{k}"]] = moment
        sub[_names(reference)[f"r{k}"]] = ratio
    return sub


def test_four_balls_are_the_n_ball_model_of_their_support():
    """The N-ball model's derived rate (in omega and the frame, modulo the unit
    directions) against the description's ``(M + K) x omega``, at the same numbers; a
    wrong ratio of ball 2 (3/4 for 2/3) is refuted."""
    described = _described(DIRECTIONS).model()
    reference = n_ball_model(4, space_directions=DIRECTIONS)
    assert _mismatch(reference, described, _n_ball_substitution(reference, described)) == []
    balls = (*BALLS[:1], (R(4, 13), R(3, 4)), *BALLS[2:])
    wrong = _n_ball_substitution(reference, described, balls)
    assert "omega" in _mismatch(reference, described, wrong)


# ------------------------------------------------------------------ the closed model
def _closed_substitution(reference: Model, described: Model, params, swap=False) -> dict:
    """The closed model's state and parameters in the description's: ``M`` is ``M``, the
    eigenvector ``e`` (space components ``c``) has body components ``c1 alpha + c2 beta +
    c3 gamma``; ``D_iso, D_al, D_be`` the numbers of :func:`support_parameters`."""
    ours, theirs = _names(described), _names(reference)
    frame = [sp.Matrix(described.group(n)) for n in ("alpha", "beta", "gamma")]
    sub = {theirs[f"M{i}"]: ours[f"M{i}"] for i in (1, 2, 3)}
    for row, name in enumerate(("alpha", "beta", "gamma")):
        body = sum((params.frame[row, j] * frame[j] for j in range(3)), sp.zeros(3, 1))
        sub.update({theirs[f"{name}{i + 1}"]: body[i] for i in range(3)})
    D_al, D_be = (params.D_be, params.D_al) if swap else (params.D_al, params.D_be)
    sub.update({theirs["D_iso"]: params.D_iso, theirs["D_al"]: D_al, theirs["D_be"]: D_be})
    sub.update({theirs[f"I{i}"]: ours[f"I{i}"] for i in (1, 2, 3)})
    sub.update({theirs[f"K{i}"]: ours[f"K{i}"] for i in (1, 2, 3) if f"K{i}" in theirs})
    return sub


@pytest.mark.parametrize("gyrostat", [False, True], ids=["plain", "gyrostat"])
def test_four_balls_are_the_closed_model_in_the_eigenframe(gyrostat):
    """BKM12-33/34 with D_iso, D_al, D_be and the eigenframe of the support tensor
    (support_parameters, exact here): the same field on the phase space; swapped D_al,
    D_be refuted."""
    fields = {"gyrostat": ("K1", "K2", "K3")} if gyrostat else {}
    described = _described(EIGEN_DIRECTIONS, **fields).model()
    reference = build_spherical_support(["gyrostat"] if gyrostat else [])
    params = support_parameters([m for m, _ in BALLS], [r for _, r in BALLS], EIGEN_DIRECTIONS)
    assert params.exact
    assert _mismatch(reference, described, _closed_substitution(reference, described, params)) == []
    swapped = _closed_substitution(reference, described, params, swap=True)
    assert _mismatch(reference, described, swapped) == ["omega"]


# ------------------------------------------------------------------ integrals, density
def _in_omega(model: Model, expr: sp.Expr) -> sp.Expr:
    """``expr`` at ``M = II omega``: a polynomial of ``omega`` and the frame (not expanded
    here: the verifier expands it exactly in its polynomial ring)."""
    at_M = dict(zip(model.group("M"), model.momentum_of_omega, strict=True))
    return expr.xreplace(at_M)


def _energy_rate(model: Model, energy: sp.Expr) -> sp.Expr:
    """``dH/dt`` for ``H = (M, II^-1 M)/2 + c(M)`` written in ``omega``: ``(omega, M') -
    (omega, II' omega)/2 + (dc/dM, M')`` (``d II^-1 = -II^-1 dII II^-1``), the flow's
    rates in ``omega`` (the model's ``rhs``); ``energy`` is ``H`` with ``omega`` kept."""
    w, M = sp.Matrix(model.omega), model.group("M")
    rate = dict(zip(model.state, model.rhs, strict=True))
    II = model.inertia_operator
    II_rate = II.applyfunc(lambda e: sum((sp.diff(e, y) * rate[y] for y in model.state), 0))
    M_rate = sp.Matrix([rate[m] for m in M])
    rest = energy - (M.T * w)[0] / 2  # the part without omega
    out = (w.T * M_rate)[0] - (w.T * II_rate * w)[0] / 2 + (rest.diff(M).T * M_rate)[0]
    return _in_omega(model, out)


def _liouville(model: Model, power: sp.Expr) -> sp.Expr:
    """``det(II)`` times the Liouville residual of ``det(II)^-power`` in ``(M, frame)``,
    written in ``omega``: ``d omega/dM_i = II^-1 e_i``, ``d omega/dx = -II^-1 (dII/dx)
    omega`` for a frame component ``x`` (``II^-1 = adj/det``)."""
    w, M = sp.Matrix(model.omega), model.group("M")
    II = model.inertia_operator
    adj, det = II.adjugate(), II.det()
    rate = dict(zip(model.state, model.rhs, strict=True))
    frame = [y for y in model.state if y not in set(M)]
    out = -power * sum((sp.diff(det, x) * rate[x] for x in frame), 0)
    for i, y in enumerate(model.state):
        d_omega = adj[:, i] if y in set(M) else -adj * II.diff(y) * w
        out += det * sp.diff(rate[y], y) + sum((sp.diff(rate[y], wk) * d_omega[k]
                                                for k, wk in enumerate(w)), 0)  # fmt: skip
    return _in_omega(model, out)


@pytest.mark.slow
def test_the_shipped_integrals_and_density_are_proved_and_controls_refuted():
    """BKM12-35..38, Rem2, 2.3 for four balls in general position with a rotor (symbolic
    I, K): each integral but H has a Lie derivative free of ``omega`` (kept: a proof for
    its true value); H's rate and the density's Liouville residual are written in
    ``omega`` (``M = II omega``, ``II^-1 = adj/det``): polynomials, Groebner normal form 0
    modulo the frame's relations. Controls: ``H + (K, M)`` and the density ``det(II)^-1``
    are refuted."""
    model = _described(DIRECTIONS, gyrostat=("K1", "K2", "K3")).model()
    domain = Domain(model)
    names = [n for n, _ in model.integrals]
    assert names[:5] == ["H", "(M+K,alpha)", "(M+K,beta)", "(M+K,gamma)", "(M+K,M+K)"]
    w, M = sp.Matrix(model.omega), model.group("M")
    K = sp.Matrix(sp.symbols("K1:4", real=True))
    for name, expr in model.integrals[1:]:
        lie = lie_derivative(expr, model, keep=tuple(w))
        assert decide([lie], domain, "symbolic").verdict == "proved", name
    H = dict(model.integrals)["H"]
    assert H == (M.T * w)[0] / 2
    assert decide([_energy_rate(model, H)], domain, "symbolic").verdict == "proved"
    shifted = H + (K.T * M)[0]  # (K, M) is not conserved: K turns with the body, M does not
    assert decide([_energy_rate(model, shifted)], domain, "symbolic").verdict == "refuted"
    II = model.inertia_operator
    assert sp.expand(model.expand_aux(model.density) ** -2 - II.det()) == 0
    assert decide([_liouville(model, R(1, 2))], domain, "symbolic").verdict == "proved"
    assert decide([_liouville(model, 1)], domain, "symbolic").verdict == "refuted"


# ------------------------------------------------------------------ bad input
GOOD = {"moment": "lambda1", "ratio": "r1", "direction": (0, 0, 1)}


@pytest.mark.parametrize(
    "fields, message",
    [
        ({"centre_of_mass": (0, 0, "a")}, "does not take a centre of mass off"),
        ({"gravity": "g"}, "does not take gravity"),
        ({"potential": "gamma3"}, "does not take a potential"),
        ({"contact": "line"}, "does not take rolling along a line"),
        ({"gyrostat": ("sin(t)", 0, 0)}, "does not take a prescribed rotor"),
        ({"inertia": ("I1 + t", "I2", "I3")}, "does not take a time-dependent inertia"),
        ({"support_radius": 2}, "support_radius is given but the support is a balls"),
        ({"rotation_rate": 1}, "rotation_rate is given but the support is a balls"),
        ({"balls": None}, "support 'balls' needs balls"),
        ({"balls": []}, "support 'balls' needs balls"),
        ({"balls": "lambda1"}, "balls: expected a list of balls"),
        ({"balls": [{"moment": 1, "ratio": 1}]}, "ball 1: expected a table with the keys"),
        ({"balls": [GOOD, {**GOOD, "spin": 0}]}, "ball 2: expected a table with the keys"),
        ({"balls": [{**GOOD, "direction": (0, 0, 0)}]}, "direction n_1 is the zero vector"),
        ({"balls": [{**GOOD, "direction": (0, 1)}]}, "direction n_1 must be three real numbers"),
        ({"balls": [{**GOOD, "direction": "0, 0, 1"}]}, "the direction must be three numbers"),
        ({"balls": [{**GOOD, "direction": (0, "c", 1)}]}, "ball 1 direction"),
        ({"balls": [{**GOOD, "moment": -1}]}, "ball 1: the moment must be positive"),
        ({"balls": [{**GOOD, "ratio": 0}]}, "ball 1: the ratio must be positive"),
        ({"support": "plane"}, "balls are given but the support is a plane"),
    ],
)
def test_each_refusal_is_one_line(fields, message):
    values = {"inertia": ("I1", "I2", "I3"), "support": "balls", "balls": [GOOD], **fields}
    with pytest.raises(UserInputError, match=message) as err:
        RollingSystem("bad_balls", **values)
    assert "\n" not in str(err.value)


def test_a_general_inertia_tensor_and_names_become_parameters():
    """A non-diagonal inertia tensor goes through the multi-body reduction (T generic);
    the balls' names are positive parameters, the body's mass and radius are not."""
    system = RollingSystem(
        "tilted", inertia=[[2, "c", 0], ["c", 3, 0], [0, 0, 4]], support="balls",
        balls=[{"moment": "mu", "ratio": "rho_1", "direction": (1, 1, 1)}, {**GOOD, "moment": 1}],
    )  # fmt: skip
    assert system.parameter_names == ("c", "mu", "rho_1", "r1")
    model = system.model()
    assert all(s.is_positive for s in model.params if s.name != "c")
    II = model.inertia_operator
    assert II.is_symmetric() and II[0, 1].has(_names(model)["c"])
