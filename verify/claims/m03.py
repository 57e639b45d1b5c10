"""Claims of Mamaev 2003 (M03): §1 a homogeneous ball on a surface, §2 a body on a sphere.

The equations are derived by :mod:`chaplygin.derive.ball_on_surface` (fixed-frame
Lagrange–d'Alembert, multipliers eliminated by projection); every check below compares
that derivation with the formula the paper prints, written here from the paper in the
model's symbols.

Claims about an arbitrary surface (M03-1.1, 1.2, 1.3, 1.3g, 1Y, 1.4) are checked on the
*generic* model, in which the surface ``f`` and the potential ``U`` are undefined sympy
Functions: the verifier treats ``f``, ``U`` and their partial derivatives at a point as
independent generators, so a proof holds for every smooth ``f, U`` at every point with
``grad f != 0``, i.e. on every level set of ``f`` (the flow preserves each; ``f = 0``
itself cannot be imposed on an undefined ``f``). The Joachimsthal-type integrals
(M03-1.5, 1.7) are proved on the ellipsoid ``(x, B^-1 x) = 1`` modulo its equation.

§2 (:mod:`chaplygin.derive.body_on_sphere`, the body-frame engine): the equations of
motion (M03-2.1, 2.3) and the energy are proved for an *arbitrary* rate ``r'`` of the
contact point (free variables: they do not depend on the shape), the kinematics (M03-2.2)
for a generic body surface; the densities (M03-2.2rho, 2.5) for an ellipsoidal body
``(r, B^-1 r) = 1`` (every ``B``), modulo its equation.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.algebra import seeded_factor
from chaplygin.derive.ball_on_surface import generic_surface_model
from chaplygin.derive.m03_bodies import ellipsoid_body_model, generic_body_model
from chaplygin.derive.vectors import cross, dot

from ..identity import Domain, Residuals, lie_derivative, measure_residual
from .base import Check, Claim, register

__all__ = [
    "SurfaceClaim",
    "BodyClaim",
    "density_flux_residual",
    "SLOW_CLAIMS",
    "joachimsthal_first_term",
    "potential_term",
    "solve_potential_factor",
    "stated_potential_factor",
]

SYSTEM = "ball_on_surface"
POTENTIAL = ("potential",)
S1 = "M03 §1"
S2 = "M03 §2"
BODY = "body_on_sphere"


@lru_cache(maxsize=2)
def _generic(with_potential: bool) -> Model:
    return generic_surface_model(with_potential)


@dataclass(frozen=True, kw_only=True)
class SurfaceClaim(Claim):
    """A claim about an arbitrary surface: checked on the generic-surface model.

    Parameters
    ----------
    with_potential : bool
        ``F = -grad U`` with ``U`` an undefined Function (else ``F = 0``).
    """

    with_potential: bool = True

    def model(self) -> Model:
        """The generic-surface ball model (cached).

        Returns
        -------
        Model
            The ball on an arbitrary surface, with or without the potential force.
        """
        return _generic(self.with_potential)


# ------------------------------------------------------------ the paper's objects
@dataclass
class _Paper:
    omega: sp.Matrix
    x: sp.Matrix
    m: sp.Symbol
    m_e: sp.Symbol
    R: sp.Symbol
    f: sp.Expr
    U: sp.Expr
    grad_f: sp.Matrix
    n: sp.Matrix  # grad f/|grad f|, typed from M03-1.2
    F: sp.Matrix  # -grad U
    x_rate: sp.Matrix  # the model's x'
    omega_rate: sp.Matrix  # the model's omega'


def _paper(model: Model) -> _Paper:
    x, omega = model.group("x"), model.group("omega")
    f, U = model.details.surface, model.details.potential
    grad_f = sp.Matrix([sp.diff(f, s) for s in x])
    f_rhs = model.rhs_expanded
    return _Paper(
        omega=omega,
        x=x,
        m=model.param_group("m")[0],
        m_e=model.param_group("m_e")[0],
        R=model.param_group("R")[0],
        f=f,
        U=U,
        grad_f=grad_f,
        n=grad_f / sp.sqrt(dot(grad_f, grad_f)),
        F=-sp.Matrix([sp.diff(U, s) for s in x]),
        omega_rate=f_rhs[:3, :],
        x_rate=f_rhs[3:, :],
    )


def _lie(vec: sp.Matrix, model: Model) -> sp.Matrix:
    return sp.Matrix([lie_derivative(e, model) for e in vec])


# ---------------------------------------------------------------- generic surface
def _m03_1_1(model: Model) -> Check:
    """(m + m_e) omega' = m (omega, n) n' + (1/R) n x F, x' = R omega x n.

    Three parts: the model's right-hand side (F = -grad U) with ``n' = d/dt n(x(t))``
    taken by the verifier along the flow; the fixed-frame derivation itself for an
    arbitrary force ``F`` (free variables), with ``n(x)`` put in; and the same
    equations with the multipliers solved for instead of projected out.
    """
    p = _paper(model)
    n_rate = _lie(p.n, model)
    exprs = list(
        (p.m + p.m_e) * p.omega_rate - p.m * dot(p.omega, p.n) * n_rate - cross(p.n, p.F) / p.R
    )
    exprs += list(p.x_rate - p.R * cross(p.omega, p.n))
    # the derivation with an arbitrary force: nu -> n(x), nudot -> (dn/dx) x'
    der = model.details.derivation
    Fs = sp.Matrix(sp.symbols("F1:4", real=True))
    x_rate = p.R * cross(p.omega, p.n)
    nudot = p.n.jacobian(p.x) * x_rate
    subs = {
        **dict(zip(der.nu, p.n, strict=True)),
        **dict(zip(der.nudot, nudot, strict=True)),
        **dict(zip(der.force, Fs, strict=True)),
    }
    w = der.omega_rate.xreplace(subs)
    exprs += list((p.m + p.m_e) * w - p.m * dot(p.omega, p.n) * nudot - cross(p.n, Fs) / p.R)
    # Newton–Euler with the contact reaction, solved directly (no projection)
    exprs += list(_newton_euler_omega_rate(der).xreplace(subs) - w)
    return Check(exprs, free=list(Fs))


def _newton_euler_omega_rate(der) -> sp.Matrix:
    """``omega'`` from the equations with multipliers and the differentiated no-slip.

    Unknowns ``omega', v'`` and the multipliers; the reactions are not unique (the
    normal constraint repeats a no-slip row) but ``omega'`` is.
    """
    v = der.v.xreplace(der.velocity_map)
    v_dot = v.jacobian(der.omega) * der.omega_dot + v.jacobian(der.nu) * der.nudot
    equations = [*der.with_multipliers.xreplace(der.velocity_map), *(der.v_dot - v_dot)]
    unknowns = [*der.omega_dot, *der.v_dot, *der.multipliers]
    (solution,) = sp.linsolve(equations, unknowns)
    return sp.Matrix(solution[:3])


def _m03_1_2(model: Model) -> Check:
    """n = grad f/|grad f|; n_i' = (f_ij - f_i f_k f_kj/|grad f|^2) x_j'/|grad f|."""
    p = _paper(model)
    q = sp.sqrt(dot(p.grad_f, p.grad_f))
    hess = p.grad_f.jacobian(p.x)
    formula = (hess - p.grad_f * (p.grad_f.T * hess) / q**2) * p.x_rate / q
    exprs = list(model.details.normal - p.n)
    exprs += list(_lie(p.n, model) - formula)
    exprs += list(model.expand_aux(sp.Matrix(model.details.normal_rate_symbols)) - formula)
    return Check(exprs)


def _paper_energy(p: _Paper) -> sp.Expr:
    I = p.m_e * p.R**2  # the paper's name
    w2 = dot(p.omega, p.omega)
    return (I + p.m * p.R**2) * w2 / 2 - p.m * p.R**2 * dot(p.omega, p.n) ** 2 / 2 + p.U


def _m03_1_3(model: Model) -> Check:
    """H = (I + m R^2) omega^2/2 - m R^2 (omega, n)^2/2 + U: the derived energy, conserved."""
    p = _paper(model)
    H = _paper_energy(p)
    return Check([model.expand_aux(model.integral("H")) - H, lie_derivative(H, model)])


def _m03_1_3g(model: Model) -> Check:
    """f(x) is conserved (every level set), (n, n) = 1 and stays so."""
    p = _paper(model)
    nn = dot(p.n, p.n)
    return Check([lie_derivative(p.f, model), nn - 1, lie_derivative(nn, model)])


def _density(kind: str):
    def build(model: Model) -> Check:
        p = _paper(model)
        q = sp.sqrt(dot(p.grad_f, p.grad_f))
        rho = {"grad": q, "inverse": 1 / q}[kind]
        return Check([measure_residual(rho, model)])

    return build


def _m03_1_4(model: Model) -> Check:
    """Hermans' form in v = x' = R omega x n and u = R (omega, n)."""
    p = _paper(model)
    v = p.R * cross(p.omega, p.n)
    u = p.R * dot(p.omega, p.n)
    n_rate = _lie(p.n, model)
    total = p.m + p.m_e
    v_rate = (
        -dot(v, n_rate) * p.n
        + p.m_e / total * u * cross(p.n, n_rate)
        + (p.F - dot(p.F, p.n) * p.n) / total
    )
    exprs = list(_lie(v, model) - v_rate)
    exprs.append(lie_derivative(u, model) - dot(cross(n_rate, p.n), v))
    exprs += list(p.x_rate - v)
    # (v, u) are coordinates: omega = (n x v)/R + (u/R) n
    exprs += list((cross(p.n, v) + u * p.n) / p.R - p.omega)
    return Check(exprs)


# ------------------------------------------------------------------- ellipsoid
def _ellipsoid(model: Model) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """``B``, ``B^-1`` and the paper's unit normal ``n = B^-1 x/|B^-1 x|`` of the centre."""
    b = model.param_group("b")
    x = model.group("x")
    B = sp.diag(*b)
    Binv = sp.diag(*[1 / bi for bi in b])
    g = Binv * x
    return B, Binv, g / sp.sqrt(dot(g, g))


def joachimsthal_first_term(model: Model, denominator: str = "B") -> sp.Expr:
    """``(n x omega, B^-1 (n x omega))/(n, B^{+-1} n)`` on the model's ellipsoid.

    Parameters
    ----------
    model : Model
        A ball-on-ellipsoid model (centre ``x``, axes ``b``, state ``omega``).
    denominator : {"B", "Binv"}
        ``(n, B n)`` (corrected) or ``(n, B^-1 n)`` (the extraction's literal reading).

    Returns
    -------
    sympy.Expr
        The term, in the model's symbols.

    References
    ----------
    M03-1.5, M03-1.7
    """
    B, Binv, n = _ellipsoid(model)
    w = cross(n, model.group("omega"))
    D = {"B": B, "Binv": Binv}[denominator]
    return dot(w, Binv * w) / dot(n, D * n)


def potential_term(model: Model) -> sp.Expr:
    """``(x, B^-2 x) [k - (x, B^-1 x)^-1 sum_i c_i/(b_i x_i^2)]`` (M03-1.7).

    Parameters
    ----------
    model : Model
        A ball-on-ellipsoid model with the potential of M03-1.6 (parameters ``k``, ``c``).

    Returns
    -------
    sympy.Expr
        The term, without its prefactor.

    References
    ----------
    M03-1.6, M03-1.7
    """
    _, Binv, _ = _ellipsoid(model)
    x, b = model.group("x"), model.param_group("b")
    k, c = model.param_group("k")[0], model.param_group("c")
    bracket = k - sum((c[i] / (b[i] * x[i] ** 2) for i in range(3)), sp.S.Zero) / dot(x, Binv * x)
    return dot(x, Binv * Binv * x) * bracket


def stated_potential_factor(model: Model) -> sp.Expr:
    """The factor of the potential term in M03-1.7 found here: ``-1/((m + m_e) R^2)``.

    Parameters
    ----------
    model : Model
        A ball-on-ellipsoid model (parameters ``m``, ``m_e``, ``R``).

    Returns
    -------
    sympy.Expr
        The factor in the model's parameters.

    References
    ----------
    M03-1.7
    """
    m, m_e, R = (model.param_group(s)[0] for s in ("m", "m_e", "R"))
    return -1 / ((m + m_e) * R**2)


def solve_potential_factor(model: Model) -> sp.Expr | None:
    """The constant ``c`` with ``d/dt [first term + c potential_term] = 0`` on the ellipsoid.

    The Lie derivative is affine in ``c``; the Groebner normal forms (modulo the
    ellipsoid) of its exact numerator pieces are polynomials in the phase-space
    variables and the ellipsoid's ``b_i`` whose coefficients are affine in ``c``,
    ``A + c B``, with ``A, B`` polynomials in the other parameters (``m, m_e, R, k, c_i``:
    absent from the ellipsoid's equation, so multiplying by them commutes with the
    reduction). Every coefficient must vanish: ``c = -A/B`` from one of them, and
    ``A B' - A' B = 0`` for all the others (exact ring arithmetic).

    Parameters
    ----------
    model : Model
        A ball-on-ellipsoid model with the potential of M03-1.6.

    Returns
    -------
    sympy.Expr or None
        ``c`` in the parameters, or None when no constant (or not a unique one) works.

    References
    ----------
    M03-1.7
    """
    c = sp.Dummy("c")
    K = joachimsthal_first_term(model) + c * potential_term(model)
    res = Residuals([lie_derivative(K, model)], Domain(model))
    in_constraints = set().union(*(sp.sympify(e).free_symbols for e in model.constraints))
    coefficients = {c} | (set(model.params) - in_constraints)
    variables = [i for i, s in enumerate(res.symbols) if s not in coefficients]
    ic = res.symbols.index(c)
    ring = res.builder.ring
    groups: dict[tuple[int, ...], list] = {}
    for form in res.normal_forms():
        for monom, coeff in form.iterterms():
            key = tuple(monom[i] for i in variables)
            rest = list(monom)
            for i in variables:
                rest[i] = 0
            power, rest[ic] = rest[ic], 0
            if power > 1:  # pragma: no cover - K is affine in c
                return None
            pair = groups.setdefault(key, [ring.zero, ring.zero])
            pair[power] += ring({tuple(rest): coeff})
    pivots = [(a, b) for a, b in groups.values() if b]
    if not pivots:
        return None  # c does not enter: no constant, or any constant, works
    a0, b0 = pivots[0]
    if any(a * b0 - a0 * b for a, b in groups.values()):
        return None
    return seeded_factor(-a0.as_expr() / b0.as_expr())


def _m03_1_5(denominator: str):
    def build(model: Model) -> Check:
        K = joachimsthal_first_term(model, denominator)
        exprs = [lie_derivative(K, model)]
        if denominator == "B":
            # on the ellipsoid 1/(n, B n) = (x, B^-2 x): the Joachimsthal form
            _, Binv, n = _ellipsoid(model)
            x, w = model.group("x"), cross(n, model.group("omega"))
            exprs.append(K - dot(x, Binv * Binv * x) * dot(w, Binv * w))
        return Check(exprs)

    return build


def _m03_1_7(which: str):
    def build(model: Model) -> Check:
        if which == "literal":
            K = joachimsthal_first_term(model, "Binv") - 4 * potential_term(model)
        else:
            c = stated_potential_factor(model)
            K = joachimsthal_first_term(model) + c * potential_term(model)
        return Check([lie_derivative(K, model)])

    return build


def _m03_1_7_factor(model: Model) -> Check:
    c = solve_potential_factor(model)
    if c is None:
        return Check([sp.S.One])  # no constant factor makes K an integral: refuted
    return Check([c - stated_potential_factor(model)])


# ------------------------------------------------------------------- registry
_GENERIC = [
    SurfaceClaim(
        id="M03-1.1",
        source=f"{S1}, eq. (1.1)",
        kind="equation",
        statement="(m + m_e) omega' = m (omega, n) n' + (1/R) n x F, x' = R omega x n, I = m_e R^2",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_1,
        note="generic f and U; also the fixed-frame derivation for an arbitrary force F, "
        "and the Newton–Euler equations with the contact reaction solved directly",
    ),
    SurfaceClaim(
        id="M03-1.2",
        source=f"{S1}, eq. (1.2)",
        kind="equation",
        statement="n = grad f/|grad f|, n_i' = (1/|grad f|)(f_ij - f_i f_k f_kj/|grad f|^2) x_j'",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_2,
        note="n' along the flow and the model's auxiliary ndot against the formula",
    ),
    SurfaceClaim(
        id="M03-1.3",
        source=f"{S1}, eq. (1.3)",
        kind="integral",
        statement="H = (I + m R^2) omega^2/2 - m R^2 (omega, n)^2/2 + U(x) is conserved for F = "
        "-grad U",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_3,
        note="the derived energy equals the paper's H; dH/dt = 0 for generic f, U",
    ),
    SurfaceClaim(
        id="M03-1.3g",
        source=f"{S1}, after eq. (1.3)",
        kind="integral",
        statement="geometric integral f(x) = const, (n, n) = 1",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_3g,
    ),
    SurfaceClaim(
        id="M03-1Y",
        source=f"{S1} (Yaroshchuk)",
        kind="measure",
        statement="invariant measure rho d omega dx, rho = |grad f|, for F = -grad U",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_density("grad"),
        note="div(rho f) = 0 in (omega, x) for generic f, U",
    ),
    SurfaceClaim(
        id="M03-1Y/control-inverse",
        source=f"{S1} (negative control)",
        kind="measure",
        statement="rho = 1/|grad f| is an invariant density (wrong exponent)",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_density("inverse"),
        expected="fails",
    ),
    SurfaceClaim(
        id="M03-1.4",
        source=f"{S1}, Remark 1, eq. (1.4) (Hermans)",
        kind="equation",
        statement="v' = -(v, n') n + m_e/(m_e + m) u n x n' + (F - (F, n) n)/(m_e + m), "
        "u' = (n' x n, v), x' = v; v = R omega x n, u = R (omega, n)",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_4,
    ),
]

_ELLIPSOID = [
    Claim(
        id="M03-1.5/literal",
        source=f"{S1}, eq. (1.5) as extracted",
        kind="integral",
        statement="K = (n x omega, B^-1 (n x omega))/(n, B^-1 n) is conserved on (x, B^-1 x) = 1, "
        "F = 0",
        system=SYSTEM,
        effects=(),
        build=_m03_1_5("Binv"),
        expected="fails",
        note="the extracted denominator (n, B^-1 n)",
    ),
    Claim(
        id="M03-1.5",
        source=f"{S1}, eq. (1.5), corrected",
        kind="integral",
        statement="K = (n x omega, B^-1 (n x omega))/(n, B n) = (x, B^-2 x)(n x omega, B^-1 (n x "
        "omega)) "
        "is conserved on (x, B^-1 x) = 1, F = 0",
        system=SYSTEM,
        effects=(),
        build=_m03_1_5("B"),
    ),
    Claim(
        id="M03-1.7/literal",
        source=f"{S1}, eq. (1.7) as extracted",
        kind="integral",
        statement="K = (n x omega, B^-1 (n x omega))/(n, B^-1 n) "
        "- 4 (x, B^-2 x)[k - (x, B^-1 x)^-1 sum c_i/(b_i x_i^2)], U of (1.6)",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_7("literal"),
        expected="fails",
    ),
    Claim(
        id="M03-1.7",
        source=f"{S1}, eq. (1.7), corrected",
        kind="integral",
        statement="K = (n x omega, B^-1 (n x omega))/(n, B n) "
        "- (x, B^-2 x)[k - (x, B^-1 x)^-1 sum c_i/(b_i x_i^2)]/((m + m_e) R^2), "
        "U = k x^2/2 + sum c_i/(2 x_i^2)",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_7("corrected"),
    ),
    Claim(
        id="M03-1.7.factor",
        source=f"{S1}, eq. (1.7): the overall factor of the potential term",
        kind="value",
        statement="the only c with d/dt[(n x omega, B^-1 (n x omega))/(n, B n) + c (x, B^-2 x)"
        "[k - (x, B^-1 x)^-1 sum c_i/(b_i x_i^2)]] = 0 is c = -1/((m + m_e) R^2)",
        system=SYSTEM,
        effects=POTENTIAL,
        build=_m03_1_7_factor,
        note="solved from the normal forms of the Lie derivative, affine in c",
    ),
]


# ======================================================== §2: a body on a sphere
@lru_cache(maxsize=8)
def _body(kind: str) -> Model:
    if kind == "generic":
        return generic_body_model()
    # (2.2rho) holds on every level set of the scalar-inertia ellipsoid: no constraint
    return ellipsoid_body_model(kind, on_surface=kind != "scalar")


@dataclass(frozen=True, kw_only=True)
class BodyClaim(Claim):
    """A claim about a body rolling on a sphere (M03 §2), on one of its models.

    Parameters
    ----------
    body : {"generic", "scalar", "special", "general", "double"}
        Generic surface with ``I = mu Id``, or the ellipsoid with ``I = mu Id`` (every
        level set), or on the ellipsoid with ``mu Id + m B``, ``diag(I1, I2, I3)`` or
        ``mu Id + 2 m B``.
    """

    body: str = "generic"

    def model(self) -> Model:
        """The body-on-sphere model of kind ``body`` (cached).

        Returns
        -------
        Model
            :func:`~chaplygin.derive.m03_bodies.generic_body_model` or an
            ellipsoid body model.
        """
        return _body(self.body)


@dataclass
class _Body:
    omega: sp.Matrix
    r: sp.Matrix
    r_rate: sp.Matrix  # abstract r' symbols
    m: sp.Symbol
    k: sp.Symbol
    I: sp.Matrix  # the paper's name
    I_Q: sp.Matrix  # typed from the paper: I + m r^2 Id - m r ⊗ r
    q: sp.Expr
    n: sp.Matrix  # -grad f/|grad f|
    V: sp.Matrix  # -q^-1 (Id - n ⊗ n) Psi
    Psi: sp.Matrix
    omega_rate: sp.Matrix  # derived, in the abstract r'
    model_r_rate: sp.Matrix  # the model's r' (state only)


def _body_notation(model: Model) -> _Body:
    eq = model.details.equations
    r, omega = model.group("r"), model.group("omega")
    m, k = model.param_group("m")[0], model.param_group("k")[0]
    I = model.details.inertia
    f = model.details.surface
    grad = sp.Matrix([sp.diff(f, s) for s in r])
    q = sp.sqrt(sp.factor_terms(dot(grad, grad)))  # 2 sqrt((r, B^-2 r)) on the ellipsoid
    n = -grad / q
    Psi = grad.jacobian(r)
    return _Body(
        omega=omega,
        r=r,
        r_rate=eq.r_rate_symbols,
        m=m,
        k=k,
        I=I,
        I_Q=I + m * dot(r, r) * sp.eye(3) - m * r * r.T,
        q=q,
        n=n,
        V=-(sp.eye(3) - n * n.T) * Psi / q,
        Psi=Psi,
        omega_rate=eq.omega_rate,
        model_r_rate=model.expand_aux(sp.Matrix(model.rhs[3:])),
    )


def _m03_2_1(model: Model) -> Check:
    """(mu + m r^2) omega' = m (omega, r)(r' + omega x r) - m (r, r') omega; kinematics."""
    b = _body_notation(model)
    mu = model.param_group("mu")[0]
    w, r, rd = b.omega, b.r, b.r_rate
    paper = b.m * dot(w, r) * (rd + cross(w, r)) - b.m * dot(r, rd) * w
    exprs = list((mu + b.m * dot(r, r)) * b.omega_rate - paper)
    exprs.append(dot(r, b.omega_rate))  # found along the way: (r, omega') = 0
    # the kinematics along the flow: n' = d/dt n(r(t)) by the verifier
    n_rate = sp.Matrix([lie_derivative(e, model) for e in b.n])
    exprs += list(b.k * b.model_r_rate + n_rate - cross(b.n, w))
    return Check(exprs, free=list(rd))


def _m03_2_2(which: str):
    def build(model: Model) -> Check:
        b = _body_notation(model)
        V = b.V
        if which == "literal":
            V = -(sp.eye(3) + b.n * b.n.T) * b.Psi / b.q
        exprs = list((b.k * sp.eye(3) + V) * b.model_r_rate - cross(b.n, b.omega))
        if which != "literal":
            exprs += list(b.n.jacobian(b.r) - V)  # V is dn/dr
        return Check(exprs)

    return build


def _m03_2_3(model: Model) -> Check:
    """I_Q omega' = (I_Q omega) x omega - m r x (omega x r'); (omega, I_Q omega)/2 conserved."""
    b = _body_notation(model)
    eq = model.details.equations
    w, r, rd = b.omega, b.r, b.r_rate
    exprs = list(b.I_Q * b.omega_rate - cross(b.I_Q * w, w) + b.m * cross(r, cross(w, rd)))
    exprs += list(eq.inertia_operator - b.I_Q)
    E = dot(w, b.I_Q * w) / 2
    exprs.append(eq.energy - E)
    exprs.append(
        sum(
            (sp.diff(E, w[i]) * b.omega_rate[i] + sp.diff(E, r[i]) * rd[i] for i in range(3)),
            sp.S.Zero,
        )
    )
    return Check(exprs, free=list(rd))


def _adjugate(A: sp.Matrix) -> tuple[sp.Matrix, sp.Expr]:
    def cofactor(i: int, j: int) -> sp.Expr:
        (a, b), (c, d) = ([A[p, q] for q in range(3) if q != j] for p in range(3) if p != i)
        return (-1) ** (i + j) * (a * d - b * c)

    cof = sp.Matrix(3, 3, cofactor)
    return cof.T, sum((A[0, j] * cof[0, j] for j in range(3)), sp.S.Zero)


def density_flux_residual(model: Model) -> sp.Expr:
    """``div(rho f)/rho1`` for ``rho = rho1 det(I_Q) det(k Id + V)``, ``rho1 = q/sqrt(mu + m r^2)``.

    ``rho f`` is written without the denominators ``det(I_Q)`` (of ``omega'``) and
    ``Delta = det(k Id + V)`` (of ``r'``): the derived momentum balance is
    ``I_Q omega' = h0 + H r'`` and M03-2.2 gives ``K r' = c`` (``K = k Id + V``,
    ``c = n x omega``), so ``det(I_Q) Delta f = X`` with
    ``X = (adj(I_Q) (Delta h0 + H adj(K) c), det(I_Q) adj(K) c)`` (``K adj(K) = Delta Id``),
    ``rho f = rho1 X`` and ``div(rho f)/rho1 = div X + (X, grad log rho1)``.

    Parameters
    ----------
    model : Model
        A body-on-sphere model with scalar inertia ``mu Id`` (parameter ``mu``).

    Returns
    -------
    sympy.Expr
        The residual in ``omega, r`` and the abstract rates ``r'``; zero on the phase
        space exactly when ``rho`` is an invariant density.

    References
    ----------
    M03-2.2rho, M03-2.5
    """
    b = _body_notation(model)
    eq = model.details.equations
    w, r, rd = b.omega, b.r, b.r_rate
    mu = model.param_group("mu")[0]
    II_rate = b.I_Q.applyfunc(lambda e: sum(sp.diff(e, r[i]) * rd[i] for i in range(3)))
    h = (eq.reduced.momentum_rate - II_rate * w).applyfunc(sp.expand)
    h0, H = h.xreplace(dict.fromkeys(rd, 0)), h.jacobian(rd)
    adjK, Delta = _adjugate(b.k * sp.eye(3) + b.V)
    adjI, detI = _adjugate(b.I_Q)
    c = cross(b.n, w)
    X = [*(adjI * (Delta * h0 + H * adjK * c)), *(detI * adjK * c)]
    log_rho1 = sp.expand_log(sp.log(b.q / sp.sqrt(mu + b.m * dot(r, r))), force=True)
    y = [*w, *r]
    return sum(sp.diff(X[i], y[i]) + X[i] * sp.diff(log_rho1, y[i]) for i in range(6))


def _density_2(model: Model) -> Check:
    return Check([density_flux_residual(model)])


def _m03_2_5to2_2(model: Model) -> Check:
    """det(I_Q) = mu (mu + m r^2)^2 for I = mu Id: (2.5) is mu times (2.2rho)."""
    b = _body_notation(model)
    mu = model.param_group("mu")[0]
    return Check([b.I_Q.det() - mu * (mu + b.m * dot(b.r, b.r)) ** 2])


_BODY = [
    BodyClaim(
        id="M03-2.1",
        source=f"{S2}, eq. (2.1)",
        kind="equation",
        statement="k r' + n' = n x omega, (mu + m r^2) omega' = m (omega, r)(r' + omega x r) "
        "- m (r, r') omega, I = mu Id, n = -grad f/|grad f|",
        system=BODY,
        effects=("scalar",),
        build=_m03_2_1,
        note="omega' for every rate r' of the contact point; also (r, omega') = 0; "
        "the kinematics along the flow for a generic body surface f",
        body="generic",
    ),
    BodyClaim(
        id="M03-2.2",
        source=f"{S2}, eq. (2.2), corrected",
        kind="equation",
        statement="(k Id + V) r' = n x omega, V = -q^-1 (Id - n ⊗ n) Psi, Psi = d2f/dr dr, q = "
        "|grad f|",
        system=BODY,
        effects=("scalar",),
        build=_m03_2_2("corrected"),
        note="generic body surface f; V = dn/dr",
        body="generic",
    ),
    BodyClaim(
        id="M03-2.2/literal",
        source=f"{S2}, eq. (2.2) as extracted",
        kind="equation",
        statement="(k Id + V) r' = n x omega with V = -q^-1 (Id + n ⊗ n) Psi",
        system=BODY,
        effects=("scalar",),
        build=_m03_2_2("literal"),
        expected="fails",
        body="generic",
    ),
    BodyClaim(
        id="M03-2.2rho",
        source=f"{S2}, after eq. (2.2) (Yaroshchuk)",
        kind="measure",
        statement="invariant measure rho d omega dr, rho = (mu + m r^2)^(3/2) q det(k Id + V), I = "
        "mu Id",
        system=BODY,
        effects=("scalar",),
        build=_density_2,
        note="ellipsoidal body (r, B^-1 r) = 1, every B; rho = mu^-1 x the (2.5) form",
        body="scalar",
    ),
    BodyClaim(
        id="M03-2.3",
        source=f"{S2}, eq. (2.3)",
        kind="equation",
        statement="I_Q omega' = (I_Q omega) x omega - m r x (omega x r'), I_Q = I + m r^2 Id - m r "
        "⊗ r; "
        "energy (omega, I_Q omega)/2 conserved",
        system=BODY,
        effects=("general",),
        build=_m03_2_3,
        note="general central inertia; for every rate r' (any body surface)",
        body="general",
    ),
    BodyClaim(
        id="M03-2.5to2.2",
        source=f"{S2}, (2.5) for I = mu Id",
        kind="definition",
        statement="det(I_Q) = mu (mu + m r^2)^2 for I = mu Id, so (2.5) reduces to (2.2rho)",
        system=BODY,
        effects=("scalar",),
        build=_m03_2_5to2_2,
        body="scalar",
    ),
]

#: The slowest checks of the registry (about 7 s each on the development machine).
SLOW_CLAIMS = [
    BodyClaim(
        id="M03-2.5",
        source=f"{S2}, eqs. (2.4), (2.5)",
        kind="measure",
        statement="for I = mu Id + m B the ellipsoid (r, B^-1 r) = 1 on a sphere has the invariant "
        "density rho = (mu + m r^2)^(-1/2) det(I_Q) q det(k Id + V)",
        system=BODY,
        effects=("special",),
        build=_density_2,
        note="div(rho f) = 0 modulo the ellipsoid; rho f written without denominators",
        body="special",
    ),
    BodyClaim(
        id="M03-2.5/control-2mB",
        source=f"{S2}, eq. (2.5) (negative control)",
        kind="measure",
        statement="the density (2.5) is invariant for I = mu Id + 2 m B (not the special "
        "distribution)",
        system=BODY,
        effects=("double",),
        build=_density_2,
        expected="fails",
        note="M03-2.4: the special mass distribution is needed",
        covers=("M03-2.4",),
        body="double",
    ),
]

register(*_GENERIC, *_ELLIPSOID, *_BODY, *SLOW_CLAIMS)
