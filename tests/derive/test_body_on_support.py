"""A convex body on a support surface F(p) = 0 (derive/body_on_support.py) against routes
that share no formula with its contact kinematics: the general ball on a support
(derive/ball_on_support_general.py: the contact through the ball's centre, (Id + s b dnu/dp)
p' = b omega x n) for a spherical body, and the body-frame convex body on a fixed plane
(derive/body_on_sphere.py with curvature 0: (dn/dr + n n^T) r' = n x omega) for F = p3.

The points are exact and consistent: the frame Q a rational rotation (an integer
quaternion), p chosen, r where the body's outward normal is -s Q^T nu(p) (the surfaces
through p and r are level sets of F and f: every level is kept by the flow)."""

from __future__ import annotations

import dataclasses
import random
import re
from pathlib import Path

import pytest
import sympy as sp
from chaplygin.derive.ball_on_support_general import AXES
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.geometry import FRAME, PoissonGroup
from chaplygin.derive.phase_space import sample_point
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.vectors import vector
from chaplygin.verify.chained import rate_at
from chaplygin.verify.user_claims import claims_of_file
from chaplygin.verify.verdict import check_claim

R_ = sp.Rational
M, G = R_(13, 10), R_(49, 5)
INERTIA = sp.Matrix(
    [[R_(3, 10), R_(1, 20), 0], [R_(1, 20), R_(2, 5), R_(-1, 30)], [0, R_(-1, 30), R_(1, 2)]]
)
ROTOR = sp.Matrix([R_(1, 7), 0, R_(1, 3)])
OMEGA = sp.Matrix([R_(3, 10), R_(-7, 10), R_(11, 10)])
E = sp.eye(3)


def _rotation(seed: int) -> sp.Matrix:
    """A proper rotation with rational entries (an integer quaternion's, the frame
    sampler's), its columns the body axes."""
    axes = PoissonGroup(FRAME, AXES).sample_rational(random.Random(seed))
    return sp.Matrix([axes[name] for name in AXES]).T


Q = _rotation(7)


def _system(name: str, **fields) -> RollingSystem:
    base = dict(inertia=INERTIA.tolist(), mass=M, gyrostat=list(ROTOR), gravity=G)
    return RollingSystem(name, **{**base, **fields})


def _rates(model, values: dict[str, sp.Matrix]) -> dict[str, sp.Matrix]:
    """Every state group's rate at the point (groups by name, exact, through the
    auxiliaries in order)."""
    names = {x.name: x for x in model.state}
    point = {names[f"{g}{i + 1}"]: v[i] for g, v in values.items() for i in range(3)}
    assert all(sp.expand(c.xreplace(point)) == 0 for c in model.constraints)
    for symbol, expr in model.aux:  # in order: each at the values of those before it
        point[symbol] = sp.radsimp(expr.xreplace(point))
    rates = dict(zip(model.state, model.rhs, strict=True))
    out = {}
    for g in {x.name.rstrip("123") for x in model.state}:  # (e1_1 .. in the group e1_)
        group = [x for x in model.state if x.name.rstrip("123") == g]
        out[g] = sp.Matrix([sp.radsimp(rates[x].xreplace(point)) for x in group])
    return out


def _frame(Q: sp.Matrix) -> dict[str, sp.Matrix]:
    return {f"e{j + 1}_": Q[:, j] for j in range(3)}


def _zero(v: sp.Matrix) -> bool:
    return v.applyfunc(lambda x: sp.simplify(sp.radsimp(x))) == sp.zeros(*v.shape)


ELLIPSOID = (R_(4), R_(9, 4), R_(1))
SUPPORTS = {
    # an ellipsoid, at p = (c_i u_i), |u| = 1: grad F = 2 u, a rational normal
    "ellipsoid": (
        " + ".join(f"p{i + 1}**2/({c})" for i, c in enumerate(ELLIPSOID)) + " - 1",
        sp.Matrix([ELLIPSOID[i] * x for i, x in enumerate((R_(2, 7), R_(3, 7), R_(6, 7)))]),
    ),
    # a convex quartic (not a quadric), its linear terms chosen so that grad F = (2, 3, 6)
    # at the point: a rational normal, the numbers stay rational
    "quartic": (
        "p1**4 + 2*p2**4 + p3**4/3 - 2*p1 + 2*p2 + 14*p3/3 - 5",
        sp.Matrix([1, R_(1, 2), 1]),
    ),
}


@pytest.mark.parametrize("support", sorted(SUPPORTS))
@pytest.mark.parametrize("side", ["outside", "inside"])
def test_a_spherical_body_moves_as_the_general_ball(support, side):
    """f = |x - a0|^2 - b^2 with the centre of mass off the sphere's centre, a product of
    inertia and a rotor, on an ellipsoid and on a quartic, outside and inside: omega', p'
    and e_i' equal the general ball's (centre of mass a = c - a0 from the ball's centre)
    at the consistent point, r = -a + b nu_b, nu_b = -s Q^T nu(p). The controls (the
    support's curvature of the wrong sign, the body's dropped) give other p' and omega'."""
    F, p = SUPPORTS[support]
    s = 1 if side == "outside" else -1
    b, a0 = R_(7, 10), sp.Matrix([R_(1, 5), R_(-1, 10), R_(1, 20)])
    c = sp.Matrix([R_(1, 4), R_(-3, 20), R_(-3, 20)])  # the centre of mass
    shape = " + ".join(f"(x{i + 1} - ({a0[i]}))**2" for i in range(3)) + f" - ({b})**2"
    body = _system("sphere_body", surface=shape, centre_of_mass=list(c), support="surface",
                   support_surface=F, side=side).model()  # fmt: skip
    ball = _system("ball", radius=b, centre_of_mass=list(c - a0), support="surface",
                   support_surface=F, side=side).model()  # fmt: skip
    P = vector("p", real=True)
    grad = sp.Matrix([sp.diff(body.details.support, x) for x in P])
    grad = grad.xreplace(dict(zip(P, p, strict=True)))
    nu = grad / sp.sqrt(grad.dot(grad))
    r = -(c - a0) + b * (-s * Q.T * nu)
    theirs = _rates(ball, {"omega": OMEGA, "p": p, **_frame(Q)})
    ours = _rates(body, {"omega": OMEGA, "p": p, "r": r, **_frame(Q)})
    for group in ("omega", "p", "e1_", "e2_", "e3_"):
        assert _zero(ours[group] - theirs[group]), group
    assert _zero(ours["r"] - Q.T * ours["p"])  # the contact slides with one velocity
    assert not _zero(ours["p"]) and not _zero(ours["omega"])
    for wrong in ("support", "body"):  # the controls: the contact's system changed
        bad = _rates(_mutated(body, wrong), {"omega": OMEGA, "p": p, "r": r, **_frame(Q)})
        assert not _zero(bad["p"] - theirs["p"]) and not _zero(bad["omega"] - theirs["omega"])


BODY = "x1**2/(3/2) + x2**2 + x3**2/(1/3) + x1*x2/5 - 1"  # a tilted ellipsoid
CENTRE = sp.Matrix([R_(1, 10), R_(-1, 20), R_(1, 15)])


@pytest.mark.parametrize("agrees", [True, False])
def test_on_the_plane_F_p3_it_moves_as_the_convex_body_on_a_plane(agrees):
    """F = p3 with an ellipsoid (a product term, the centre of mass off its centre) against
    the body-frame convex body on a fixed plane (state omega_b, r; with the contact trace
    x, y in the fixed axes alpha, beta): omega' = Q omega_b', r' and the trace's rate
    agree exactly at omega_b = Q^T omega and the same r; the control moves the plane
    route's centre of mass."""
    new = _system("on_plane_surface", surface=BODY, centre_of_mass=list(CENTRE),
                  support="surface", support_surface="p3").model()  # fmt: skip
    moved = CENTRE if agrees else CENTRE + sp.Matrix([0, 0, R_(1, 30)])
    plane = _system("on_plane", surface=BODY, centre_of_mass=list(moved)).model(
        ("contact_point",)
    )
    x = vector("x", real=True)
    f = parse_body(BODY, x)
    d = -Q.T * E[:, 2]  # the body's outward normal at the contact: down
    H = sp.hessian(f, list(x))
    r = H.LUsolve(R_(3, 2) * d - sp.Matrix([sp.diff(f, v) for v in x]).subs(
        dict.fromkeys(x, 0))) - CENTRE  # fmt: skip
    ours = _rates(new, {"omega": OMEGA, "p": sp.Matrix([R_(1, 3), R_(2, 3), 0]), "r": r,
                        **_frame(Q)})  # fmt: skip
    theirs = _rates(plane, {"omega": Q.T * OMEGA, "r": r, "alpha": Q.T * E[:, 0],
                            "beta": Q.T * E[:, 1]})  # fmt: skip
    assert _zero(ours["omega"] - Q * theirs["omega"]) is agrees
    if agrees:  # kinematics: no mass enters; p' is the trace's rate
        assert _zero(ours["r"] - theirs["r"])
        assert _zero(ours["p"] - sp.Matrix([theirs["x"][0], theirs["y"][0], 0]))


def parse_body(text: str, x: sp.Matrix) -> sp.Expr:
    return sp.sympify(text, locals={f"x{i + 1}": x[i] for i in range(3)})


EGG = dict(
    inertia=[["A", "D", 0], ["D", "B", 0], [0, 0, "C"]], centre_of_mass=(0, 0, "a"),
    gyrostat=(0, 0, "k"), gravity="g", surface="x1**2/a1 + x2**2/a2 + x3**2/a3 - 1",
    support="surface", support_surface="p1**2/c1 + p2**2/c2 + p3**2/c3 + p1*p2/c4 - 1",
)  # fmt: skip


def _alignment(model) -> sp.Matrix:
    """``Q grad f(r) x grad F(p)``: zero on the phase space."""
    d = model.details
    P, r = (sp.Matrix(model.vectors[n]) for n in ("p", "r"))
    grad_f = sp.Matrix([sp.diff(d.surface, x) for x in r])
    grad_F = sp.Matrix([sp.diff(d.support, x) for x in P])
    return (d.rotation * grad_f).cross(grad_F)


def _mutated(model, wrong: str):
    """The model with its contact system changed (the controls): the support's curvature
    of the wrong sign, or the body's curvature dropped."""
    s = model.details.side
    Dnu = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Dnu{i + 1}{j + 1}", real=True))
    C = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Cf{i + 1}{j + 1}", real=True))
    nu = sp.Matrix(sp.symbols("nu1:4", real=True))
    change = -2 * s * Dnu if wrong == "support" else -(sp.eye(3) - nu * nu.T) * C
    aux = []
    for x, e in model.aux:
        if x.name.startswith("Ac"):
            i, j = int(x.name[2]) - 1, int(x.name[3]) - 1
            e = sp.expand(e + change[i, j])
        aux.append((x, e))
    return dataclasses.replace(model, aux=tuple(aux))


@pytest.mark.slow  # about 10 s a side: exact numbers with the normal's square root
@pytest.mark.parametrize("side", ["outside", "inside"])
def test_the_integrals_and_the_alignment_are_kept_and_the_controls_are_not(side):
    """An ellipsoid with symbolic axes, inertia with a product, offset and rotor on a
    tilted ellipsoid with symbolic axes: at exact points the model's sampler draws (random
    rational parameters and frame, the normals aligned), the rates of H, F, f and of the
    alignment Q grad f x grad F (a generic combination) are exactly zero (the chain rule
    through the auxiliaries, as the verifier evaluates them). Controls: the energy with the
    centre of mass's height (p + rho)_3 replaced by rho_3 alone, the support's curvature of
    the wrong sign and the body's curvature dropped (the alignment is lost)."""
    model = RollingSystem("egg_on_egg", side=side, **EGG).model()
    assert [n for n, _ in model.integrals] == ["H", "F", "f"]
    names = {x.name: x for x in model.params}
    wrong_height = model.integral("H") - names["m"] * names["g"] * model.vectors["p"][2]
    alignment = _alignment(model)
    # one generic combination of the three components (zero on the phase space): its rate
    # is the same combination of theirs
    aligned = (sp.Matrix([[R_(3, 7), R_(-5, 11), R_(2, 13)]]) * alignment)[0]
    point = sample_point(model, random.Random(24), model.state)
    assert sp.expand(alignment.xreplace(point)) == sp.zeros(3, 1)
    for _, expr in model.integrals:
        assert rate_at(model, expr, point) == 0
    assert rate_at(model, aligned, point) == 0
    assert rate_at(model, wrong_height, point) != 0
    for wrong in ("support", "body"):
        assert rate_at(_mutated(model, wrong), aligned, point) != 0


def test_what_is_not_derived_is_refused_on_one_line():
    """A line contact for a convex body on a support surface is refused before any work,
    in one line, and so are a parameter named as an auxiliary and a body and a support
    neither of which is a quadric (rubber contact, a potential, K(t) and I(t) are derived:
    test_a_potential_rubber_contact_k_t_and_i_t_move_it_as_the_plane_route)."""
    base = dict(inertia=("A", "B", "C"), surface="x1**2 + x2**2/2 + x3**2/3 - 1",
                support="surface", support_surface="p3")  # fmt: skip
    refused = (
        ({"contact": "line"}, "contact 'line'"),
        ({"centre_of_mass": (0, 0, "Ac11")}, "['Ac11'] are the derivation's auxiliaries"),
    )
    for fields, message in refused:
        with pytest.raises(UserInputError, match=re.escape(message)):
            RollingSystem("bad", **{**base, **fields})
    assert RollingSystem("good", **base).effects_taken == ()
    # neither surface a quadric: the verifier has no exact points with the normals aligned
    # (it would refute f at points off them), so the description is refused
    quartics = dict(base, surface="x1**4 + x2**2 + x3**2 + x1**2 - 1",
                    support_surface="p1**4 + p2**2 + p3**2 - 1")  # fmt: skip
    with pytest.raises(UserInputError, match="the body or the support to be a quadric"):
        RollingSystem("bad", **quartics)
    RollingSystem("good", **dict(quartics, support_surface="p1**2 + p2**2 + p3**2 - 1"))


EXAMPLE = Path(__file__).resolve().parents[2] / "examples/systems/ellipsoid_on_ellipsoid.toml"


@pytest.mark.slow  # about 7 s: the verifier's chained sampling of the shipped integrals
def test_the_example_files_claims_are_exact_sampled_and_its_control_refuted():
    """examples/systems/ellipsoid_on_ellipsoid.toml through the verifier's claims: the
    derived H, F and f exact-sampled (through the auxiliaries, at aligned points of the
    model's sampler), the file's control refuted with a witness, and the Kane claim
    (verify/kane_body_support.py) agreeing."""
    claims = {c.id.split(":")[-1]: c for c in claims_of_file(EXAMPLE)}
    assert set(claims) == {"H", "F", "f", "kane", "ELLIPSOID-ON-ELLIPSOID/control"}
    for name in ("H", "F", "f"):
        result = check_claim(claims[name])
        assert (result.verdict, result.ok) == ("exact-sampled", True), name
    kane = check_claim(claims["kane"])
    assert kane.ok and kane.verdict == "numeric", kane
    control = check_claim(claims["ELLIPSOID-ON-ELLIPSOID/control"])
    assert (control.verdict, control.ok) == ("refuted", True) and control.witness


#: The fields a convex body on a support surface takes beyond gravity and a constant rotor,
#: written for the support route (a potential of p and the body axes) and for the plane
#: route on F = p3 (where the upward normal in body axes is gamma_i = e{i}_3), and each
#: with its control (the same field wrong).
_R3 = [0, "-1/30", "1/2"]
FIELDS = {
    "potential": ({"potential": "k*(e3_3*e1_3 + e2_3**2)"},
                  {"potential": "k*(gamma3*gamma1 + gamma2**2)"},
                  {"potential": "2*k*(gamma3*gamma1 + gamma2**2)"}),
    "rubber": ({"contact": "rubber"}, {"contact": "rubber"}, {"contact": "rolling"}),
    "K(t)": ({"gyrostat": ("1/7", "t/3", "1/3")}, {"gyrostat": ("1/7", "t/3", "1/3")},
             {"gyrostat": ("1/7", "t/4", "1/3")}),
    "I(t)": ({"inertia": [["3/10", "1/20", 0], ["1/20", "2/5 + t**2/5", "-1/30"], _R3]},
             {"inertia": [["3/10", "1/20", 0], ["1/20", "2/5 + t**2/5", "-1/30"], _R3]},
             {"inertia": [["3/10", "1/20", 0], ["1/20", "2/5 + t**2/7", "-1/30"], _R3]}),
}  # fmt: skip


@pytest.mark.parametrize("field", sorted(FIELDS))
def test_a_potential_rubber_contact_k_t_and_i_t_move_it_as_the_plane_route(field):
    """On F = p3 the body with a potential of its axes, rubber contact, K(t) or I(t) moves
    exactly as the body-frame convex body on a fixed plane with the same field (its own
    potential torque n x dV/dn, no-twist reaction, rotor and inertia rates: no formula
    shared with the support route's tau = -d(dV/dt)/d omega, mu nu, Q K', Q I' Q^T), at a
    symbolic time t and parameter k; the plane route with the field wrong (twice the
    potential, rolling for rubber, another law of K or I) is refuted by the same
    comparison. With a rubber contact omega is taken on (omega, e3) = 0."""
    ours_fields, plane_fields, wrong_fields = FIELDS[field]
    name = {"K(t)": "kt", "I(t)": "it"}.get(field, field)
    new = _system(f"fs_{name}", surface=BODY, centre_of_mass=list(CENTRE), support="surface",
                  support_surface="p3", **ours_fields).model()  # fmt: skip
    x = vector("x", real=True)
    f = parse_body(BODY, x)
    d = -Q.T * E[:, 2]
    H = sp.hessian(f, list(x))
    r = H.LUsolve(R_(3, 2) * d - sp.Matrix([sp.diff(f, v) for v in x]).subs(
        dict.fromkeys(x, 0))) - CENTRE  # fmt: skip
    omega = OMEGA - E[:, 2] * OMEGA[2] if field == "rubber" else OMEGA
    ours = _rates(new, {"omega": omega, "p": sp.Matrix([R_(1, 3), R_(2, 3), 0]), "r": r,
                        **_frame(Q)})  # fmt: skip
    for fields, agrees in ((plane_fields, True), (wrong_fields, False)):
        plane = _system(f"fp_{name}_{agrees}", surface=BODY, centre_of_mass=list(CENTRE),
                        **fields).model()  # fmt: skip
        theirs = _rates(plane, {"omega": Q.T * omega, "r": r})
        assert _zero(ours["omega"] - Q * theirs["omega"]) is agrees, (field, agrees)
        if agrees:
            assert _zero(ours["r"] - theirs["r"])
