"""Hamiltonisation and separation of variables of the Chaplygin ball (K01 §2.2, BKM12 §1.2).

The time change and the momentum ``L = rho M`` (K01-2.7) are applied to the *derived*
ball model; the Hamiltonian (2.8), the nonlinear bracket (2.9) and its Casimirs (2.10)
are compared with it. Sphero-conical coordinates (2.11)-(2.12), the momentum map
(2.13)-(2.14) and the separated Hamiltonian (2.15)-(2.16) are checked with ``q1, q2`` as
independent variables: the ranges ``a3 < q2 < a2 < q1 < a1`` are written with positive
symbols (``u1 = a1 - q1``, ``v1 = q1 - a2``, ``u2 = a2 - q2``, ``v2 = q2 - a3``), so the
square roots of the components of ``gamma`` (positive octant) are products of square
roots of distinct linear forms in positive symbols, which the verifier splits exactly.
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive import hamiltonisation as hz
from chaplygin.derive.algebra import seeded_factor
from chaplygin.derive.vectors import cross, dot

from .base import Check, Claim, register
from .notation import ball_notation

BALL = "chaplygin_ball"
S22 = "K01 §2.2"
S12 = "BKM12 §1.2"

# ------------------------------------------------------------------ shared variables
_L = sp.Matrix(sp.symbols("L1:4", real=True))
_g = sp.Matrix(sp.symbols("g1:4", real=True))  # bracket coordinates (not the model's gamma)
_q1, _q2, _p1, _p2 = sp.symbols("q1 q2 p1 p2", real=True)
_a = sp.symbols("a1:4", positive=True)
_u1, _v1, _u2, _v2, _a3 = sp.symbols("u1 v1 u2 v2 a3", positive=True)
_lam1, _lam2 = sp.symbols("lam1 lam2", real=True)
_x = sp.Symbol("x", real=True)
# the ranges a3 < q2 < a2 < q1 < a1 in positive symbols
_OCTANT = {
    _q1: _a3 + _v2 + _u2 + _v1,
    _q2: _a3 + _v2,
    _a[0]: _a3 + _v2 + _u2 + _v1 + _u1,
    _a[1]: _a3 + _v2 + _u2,
    _a[2]: _a3,
}


def _split_radicals(e: sp.Expr) -> sp.Expr:
    """Factor every radicand: square roots of products of positive linear forms split."""
    return e.replace(
        lambda x: x.is_Pow and x.exp.is_Rational and x.exp.q == 2,
        lambda x: seeded_factor(x.base) ** x.exp,
    )


_PIECES = "gamma_i = sqrt(gamma_i^2(q)) split off exactly, by the parity of their powers"


def _in_ranges(exprs):
    """Write expressions in ``q, a`` with the positive range symbols (radicals split)."""
    return [_split_radicals(sp.sympify(e).xreplace(_OCTANT)) for e in exprs]


def _k01_params(model: Model):
    n = ball_notation(model)
    return n, list(n.I), n.D


def _tensor_coords():
    return list(_L) + list(_g)


# ------------------------------------------------------------------ K01-2.7 … 2.10
def _flow(d_sign: int = -1):
    """``{x, H}`` in tau at ``L = rho M`` against ``rho^-1`` times the model's rate."""

    def build(model: Model) -> Check:
        n, I, D = _k01_params(model)
        f = model.rhs_expanded
        fM, fg = sp.Matrix(f[:3]), sp.Matrix(f[3:])
        rho = hz.k01_multiplier(n.gamma, I, D)
        dL, dg = hz.rescaled_flow(fM, fg, n.M, n.gamma, rho)
        P = hz.poisson_tensor(_L, _g, I, D, d_sign=d_sign)
        H = hz.hamiltonian(_L, _g, I, D)
        X = hz.hamiltonian_flow(H, _tensor_coords(), P)
        at = dict(zip(_L, rho * n.M, strict=True)) | dict(zip(_g, n.gamma, strict=True))
        X = X.xreplace(at)
        exprs = list(X[:3, :] - dL) + list(X[3:, :] - dg)
        return Check(exprs, everywhere=True, note="on the whole phase space, any (M, gamma)")

    return build


def _energy(model: Model) -> Check:
    n, I, D = _k01_params(model)
    rho = hz.k01_multiplier(n.gamma, I, D)
    H = hz.hamiltonian(n.M * rho, n.gamma, I, D)
    return Check([H - model.expand_aux(model.integral("H"))])


def _jacobi(d_sign: int = -1):
    def build(model: Model) -> Check:
        _, I, D = _k01_params(model)
        P = hz.poisson_tensor(_L, _g, I, D, d_sign=d_sign)
        return Check(
            hz.jacobi_residuals(P, _tensor_coords()),
            free=_tensor_coords(),
            note="all 20 triples, identically in R^6 (off the sphere too)",
        )

    return build


def _casimir(which: str, d_sign: int = -1):
    """{F, x} = 0 for every coordinate; the model's M, gamma serve as L, gamma (sphere)."""

    def build(model: Model) -> Check:
        n, I, D = _k01_params(model)
        L, g = n.M, n.gamma
        coords = list(L) + list(g)
        P = hz.poisson_tensor(L, g, I, D, d_sign=d_sign)
        if which == "C":
            F = hz.area_casimir(L, g, I, D)
        elif which == "(L,gamma)":
            F = dot(L, g)
        else:
            F = dot(g, g)
        exprs = [hz.bracket(F, x, coords, P) for x in coords]
        if which == "C":  # its value at L = rho M is the constant of areas
            rho = hz.k01_multiplier(g, I, D)
            exprs.append(F.xreplace(dict(zip(L, rho * L, strict=True))) - dot(L, g))
        return Check(exprs)

    return build


def _n_integral(model: Model) -> Check:
    n, I, D = _k01_params(model)
    coords = _tensor_coords()
    P = hz.poisson_tensor(_L, _g, I, D)
    H = hz.hamiltonian(_L, _g, I, D)
    N = dot(_L, _L) * hz.multiplier_inverse_square(_g, I, D)
    rho = hz.k01_multiplier(n.gamma, I, D)
    at = dict(zip(_L, rho * n.M, strict=True)) | dict(zip(_g, n.gamma, strict=True))
    return Check([hz.bracket(N, H, coords, P), N.xreplace(at) - dot(n.M, n.M)], free=coords)


def _e3_leaf(model: Model) -> Check:
    """At (L, gamma) = 0 the bracket is e(3): {L_i, L_j} = -eps_ijk L_k."""
    n, I, D = _k01_params(model)
    P = hz.poisson_tensor(n.M, n.gamma, I, D)  # the model's M plays L here
    exprs = []
    for i in range(3):
        for j in range(3):
            e3 = -sum((sp.LeviCivita(i, j, k) * n.M[k] for k in range(3)), sp.S.Zero)
            exprs.append(P[i, j] - e3)
    return Check(exprs, on=[dot(n.M, n.gamma)], note="on (L, gamma) = 0")


# ------------------------------------------------------------------ K01-2.11 … 2.14
def _gamma_octant():
    return sp.Matrix([sp.sqrt(e) for e in hz.spheroconical_gamma_squared(_q1, _q2, _a)])


_G = sp.Matrix(sp.symbols("G1:4", real=True))  # gamma_i on the sphere, gamma_i^2 = G_i(q)


def _G_squared():
    return hz.spheroconical_gamma_squared(_q1, _q2, _a)


class _Octant:
    """Exact algebra of ``sum_S A_S prod_{i in S} G_i`` with ``G_i^2 = gamma_i^2(q)``.

    ``A_S`` are elements of the field of rational functions in ``q, p, a, D, ...``
    (sympy's sparse fraction field, fast and canonical); multiplication reduces even
    powers of ``G_i`` with ``gamma_i^2(q)`` of (2.12).
    """

    def __init__(self, symbols):
        from sympy.polys.fields import field

        self.symbols = list(symbols)
        self.K, *gens = field(self.symbols, sp.QQ)
        self.gens = dict(zip(self.symbols, gens, strict=True))
        self.sq = [self.K.from_expr(e) for e in _G_squared()]

    def convert(self, e, known: dict | None = None) -> dict:
        """A sympy expression in G and the symbols as {parity: field element}.

        ``known`` maps further symbols to elements (``gamma'`` ...).
        """
        e = sp.sympify(e)
        if known and e in known:
            return known[e]
        if e in set(_G):
            i = list(_G).index(e)
            return {tuple(int(k == i) for k in range(3)): self.K.one}
        if e.is_Number:
            return {(0, 0, 0): self.K.from_expr(e)} if e != 0 else {}
        if e.is_Symbol:
            return {(0, 0, 0): self.gens[e]}
        if e.is_Add:
            out: dict = {}
            for arg in e.args:
                out = self.add(out, self.convert(arg, known))
            return out
        if e.is_Mul:
            out = {(0, 0, 0): self.K.one}
            for arg in e.args:
                out = self.mul(out, self.convert(arg, known))
            return out
        if e.is_Pow and e.exp.is_Integer:
            base = self.convert(e.base, known)
            n = int(e.exp)
            if n < 0:
                base, n = self.inverse(base), -n
            out = {(0, 0, 0): self.K.one}
            for _ in range(n):
                out = self.mul(out, base)
            return out
        raise ValueError(f"cannot convert {e}")

    @staticmethod
    def add(x: dict, y: dict) -> dict:
        out = dict(x)
        for k, v in y.items():
            out[k] = out[k] + v if k in out else v
        return {k: v for k, v in out.items() if v}

    def mul(self, x: dict, y: dict) -> dict:
        out: dict = {}
        for kx, vx in x.items():
            for ky, vy in y.items():
                c = vx * vy
                for i in range(3):
                    if kx[i] and ky[i]:
                        c = c * self.sq[i]
                k = tuple((kx[i] + ky[i]) % 2 for i in range(3))
                out[k] = out[k] + c if k in out else c
        return {k: v for k, v in out.items() if v}

    def inverse(self, x: dict) -> dict:
        if len(x) == 1:
            ((k, v),) = x.items()
            c = 1 / v
            for i in range(3):
                if k[i]:
                    c = c / self.sq[i]
            return {k: c}
        raise ValueError("inverse of a sum with odd parts")

    def diff(self, x: dict, q: sp.Symbol) -> dict:
        """d/dq with dG_i/dq = G_i (d gamma_i^2/dq)/(2 gamma_i^2)."""
        g = self.gens[q]
        out: dict = {}
        for k, v in x.items():
            c = v.diff(g)
            for i in range(3):
                if k[i]:
                    c = c + v * self.sq[i].diff(g) / (2 * self.sq[i])
            if c:
                out[k] = c
        return out

    def pieces(self, x: dict) -> list[sp.Expr]:
        """The coefficients A_S as sympy expressions (each must vanish)."""
        return [v.as_expr() for v in x.values()]


def _octant_pieces(e: sp.Expr, symbols) -> list[sp.Expr]:
    """``e = sum_S A_S G^S = 0`` iff every ``A_S = 0``: ``G1, G2, G3`` and their products
    are square roots of rational functions none of whose products is a square (the
    exact splitting the verifier does for square roots, done on the structure)."""
    alg = _Octant(symbols)
    return alg.pieces(alg.convert(e))


def _momentum_map_G():
    """(2.13) with gamma = G, in the closed form it reduces to (K01-2.13 proves it equal).

    ``f'(q1) = (q1 - q2)/prod_m (a_m - q1)`` (partial fractions), so
    ``(dq1/dgamma x gamma)_i = -2 (a_i - q1)(a_j - a_l) gamma_j gamma_l/(q1 - q2)`` for
    ``(i, j, l)`` cyclic, and the same with ``q1 <-> q2``.
    """
    out = []
    for i in range(3):
        j, l = (i + 1) % 3, (i + 2) % 3
        c = 2 * (_a[j] - _a[l]) * _G[j] * _G[l] / (_q1 - _q2)
        out.append(c * ((_a[i] - _q1) * _p1 - (_a[i] - _q2) * _p2))
    return sp.Matrix(out)


def _spheroconical_zeros(model: Model) -> Check:
    g2 = hz.spheroconical_gamma_squared(_q1, _q2, _a)
    G = sp.Matrix([sp.sqrt(e) for e in g2])
    exprs = [hz.spheroconical_function(_q1, G, _a), hz.spheroconical_function(_q2, G, _a)]
    return Check(_in_ranges(exprs), free=[_q1, _q2])


def _spheroconical_inverse(model: Model) -> Check:
    """(2.12): sum gamma_i^2 = 1 and sum_i gamma_i^2 prod_{j!=i}(a_j - x) = (x - q1)(x - q2)."""
    g2 = hz.spheroconical_gamma_squared(_q1, _q2, _a)
    G = sp.Matrix([sp.sqrt(e) for e in g2])
    poly = hz.spheroconical_polynomial(_x, G, _a) - (_x - _q1) * (_x - _q2)
    exprs = [sum(g2) - 1] + sp.Poly(sp.expand(sp.together(poly) * 1), _x).all_coeffs()
    return Check(_in_ranges(exprs), free=[_x])


def _bkm12_spheroconical(model: Model) -> Check:
    """BKM12's a_i = D/I_i: the coordinates are D times K01's (a_i = 1/I_i)."""
    n = ball_notation(model)
    I, D = list(n.I), n.D
    aK = [1 / Ii for Ii in I]
    aB = [D / Ii for Ii in I]
    q1, q2 = sp.symbols("qK1 qK2", real=True)
    g2K = hz.spheroconical_gamma_squared(q1, q2, aK)
    g2B = hz.spheroconical_gamma_squared(D * q1, D * q2, aB)
    G = sp.Matrix([sp.sqrt(e) for e in g2B])
    exprs = [x - y for x, y in zip(g2K, g2B, strict=True)]
    exprs += [sum(g2B) - 1]
    exprs += [sp.together(hz.spheroconical_function(D * q, G, aB) * 1) for q in (q1, q2)]
    return Check(exprs, free=[q1, q2])


def _momentum_map_closed_form(model: Model) -> Check:
    """(2.13) equals its closed form (used by the other checks); (M, gamma) = 0."""
    alg = _Octant([_q1, _q2, _p1, _p2, *_a])
    Mg = _momentum_map_G()
    general = hz.momentum_map((_p1, _p2), (_q1, _q2), _G, _a)
    exprs = [p for e in general - Mg for p in alg.pieces(alg.convert(e))]
    exprs += alg.pieces(alg.convert(dot(Mg, _G)))
    return Check(exprs, free=[_q1, _q2, _p1, _p2, *_a], note=_PIECES)


def _momentum_map_poisson(model: Model) -> Check:
    """(2.13): canonical (q, p) -> (M, gamma) preserves the e(3) brackets."""
    alg = _Octant([_q1, _q2, _p1, _p2, *_a])
    Mg = _momentum_map_G()
    exprs: list[sp.Expr] = []
    M = [alg.convert(e) for e in Mg]
    G = [alg.convert(e) for e in _G]
    neg = {(0, 0, 0): -alg.K.one}

    def br(F, H):
        out: dict = {}
        for qk, pk in ((_q1, _p1), (_q2, _p2)):
            out = alg.add(out, alg.mul(alg.diff(F, qk), alg.diff(H, pk)))
            out = alg.add(out, alg.mul(neg, alg.mul(alg.diff(F, pk), alg.diff(H, qk))))
        return out

    for i in range(3):
        for j in range(3):
            for V, W in ((M, M), (M, G)):
                if V is W and i >= j:  # antisymmetric
                    continue
                e = br(V[i], W[j])
                for k in range(3):
                    if sp.LeviCivita(i, j, k):
                        e = alg.add(
                            e, alg.mul({(0, 0, 0): alg.K(int(sp.LeviCivita(i, j, k)))}, W[k])
                        )
                exprs += alg.pieces(e)
    return Check(exprs, free=[_q1, _q2, _p1, _p2, *_a], note=_PIECES)


def _momentum_components(model: Model) -> Check:
    G = _gamma_octant()
    M13 = hz.momentum_map((_p1, _p2), (_q1, _q2), G, _a)
    M14 = hz.momentum_components((_p1, _p2), (_q1, _q2), _a)
    return Check(_in_ranges(list(M13 - M14)), free=[_p1, _p2])


def _qp_integral(which: str, printed: bool):
    """(2.15)/(2.16) against (2.8)/(2.10) at M(q, p), gamma(q); I_i = 1/a_i."""

    def build(model: Model) -> Check:
        D = ball_notation(model).D
        I = [1 / ai for ai in _a]
        M = _momentum_map_G()
        if which == "H":
            paper = hz.hamiltonian_qp((_p1, _p2), (_q1, _q2), _a, D, printed=printed)
            ours = hz.hamiltonian(M, _G, I, D)
        else:
            paper = hz.integral_n_qp((_p1, _p2), (_q1, _q2), _a, D, printed=printed)
            ours = dot(M, M) * hz.multiplier_inverse_square(_G, I, D)
        pieces = _octant_pieces(ours - paper, [_q1, _q2, _p1, _p2, D, *_a])
        return Check(pieces, free=[_q1, _q2, _p1, _p2, D, *_a], note=_PIECES)

    return build


# ------------------------------------------------------------------ K01-2.17 … 2.22
def _p_squared(q, a, D):
    """p_i^2 on the level (lam1, lam2): (4/K) p^2 q f(q) = 2 lam1 + q lam2 (K01-2.17)."""
    return hz.k01_K(a, D) / 4 * (2 * _lam1 + q * _lam2) / (q * hz.k01_f(q, a, D))


def _hamilton_jacobi(which: str):
    def build(model: Model) -> Check:
        D = ball_notation(model).D
        p = (sp.sqrt(_p_squared(_q1, _a, D)), sp.sqrt(_p_squared(_q2, _a, D)))
        if which == "H":  # (2.17): H(q, dS/dq) = lam1
            e = hz.hamiltonian_qp(p, (_q1, _q2), _a, D) - _lam1
        else:  # (2.18): n = 2 D lam1 - lam2
            e = hz.integral_n_qp(p, (_q1, _q2), _a, D) - (2 * D * _lam1 - _lam2)
        # only p_i^2 enters: the square roots square away
        return Check([sp.together(e)], free=[_q1, _q2, _lam1, _lam2, *_a])

    return build


def _abel_jacobi(model: Model) -> Check:
    """(2.22) along the flow of (2.15): sum q_i^k q_i'/sqrt(R(q_i)) = c0 delta_k0.

    ``sqrt(R(q_i))`` is taken with the sign of ``p_i`` (the ``+-`` of K01):
    ``sqrt(R(q_i)) = (2 lam1 + q_i lam2) sqrt(K)/(2 p_i)``, lam from H and n of (q, p);
    ``c0 = 2/sqrt(K)`` for the time of (2.7).
    """
    D = ball_notation(model).D
    q, p = (_q1, _q2), (_p1, _p2)
    H = hz.hamiltonian_qp(p, q, _a, D)
    N = hz.integral_n_qp(p, q, _a, D)
    lam1, lam2 = hz.separation_constants(H, N, D)
    K = hz.k01_K(_a, D)
    qdot = hz.quadrature_derivatives(q, p, _a, D)
    sqrtR = [(2 * lam1 + qi * lam2) * sp.sqrt(K) / (2 * pi) for qi, pi in zip(q, p, strict=True)]
    # the branch is a square root of R: check it
    exprs = [
        sp.together(sqrtR[i] ** 2 - hz.separation_polynomial(q[i], lam1, lam2, _a, D))
        for i in range(2)
    ]
    c0 = 2 / sp.sqrt(K)
    exprs.append(sp.together(qdot[0] / sqrtR[0] + qdot[1] / sqrtR[1] - c0))
    exprs.append(sp.together(q[0] * qdot[0] / sqrtR[0] + q[1] * qdot[1] / sqrtR[1]))
    return Check(exprs, free=[_q1, _q2, _p1, _p2, *_a])


# ------------------------------------------------------------------ BKM12 §1.2
def _bkm12_8(model: Model) -> Check:
    n = ball_notation(model)
    Mw = model.momentum_of_omega
    return Check([dot(Mw, n.gamma) - dot(sp.diag(*n.I) * n.omega, n.gamma)], free=list(n.omega))


def _bkm12_10(model: Model) -> Check:
    n = ball_notation(model)
    w = model.expand_aux(n.omega)
    gdot = cross(n.gamma, w)
    exprs = list(w - hz.omega_from_gamma(n.gamma, gdot, list(n.I)))
    exprs += list(n.M - hz.momentum_from_gamma(n.gamma, gdot, list(n.I), n.D))
    return Check(exprs, on=[dot(n.M, n.gamma)], note="on (M, gamma) = 0")


def _chart_forms(model: Model):
    """2H = (M, omega) and F1 = (M, M) on (M, gamma) = 0 as quadratic forms in gamma'.

    ``M`` and ``omega`` from BKM12-10 (proved against the model); ``gamma'`` tangent.
    """
    n = ball_notation(model)
    I, D = list(n.I), n.D
    gd = sp.Matrix(sp.symbols("gd1:4", real=True))
    w = hz.omega_from_gamma(n.gamma, gd, I)
    M = hz.momentum_from_gamma(n.gamma, gd, I, D)
    return n, gd, dot(M, w), dot(M, M)


def _bkm12_12b(which: str):
    """BKM12-1.2b in sphero-conical coordinates (positive octant), a_i = D/I_i."""

    def build(model: Model) -> Check:
        n = ball_notation(model)
        D = n.D
        d1, d2 = sp.symbols("qd1 qd2", real=True)
        alg = _Octant([_q1, _q2, d1, d2, D, *_a])
        G = [alg.convert(g) for g in _G]
        gd = sp.Matrix(sp.symbols("gd1:4", real=True))
        known = {
            gd[i]: alg.add(
                alg.mul(alg.diff(G[i], _q1), alg.convert(d1)),
                alg.mul(alg.diff(G[i], _q2), alg.convert(d2)),
            )
            for i in range(3)
        }
        I = [D / ai for ai in _a]
        w = hz.omega_from_gamma(_G, gd, I)
        M = hz.momentum_from_gamma(_G, gd, I, D)
        if which == "H":
            e = dot(M, w) / 2 - hz.bkm12_energy_q((_q1, _q2), (d1, d2), _a, D)
        else:
            e = dot(M, M) - hz.bkm12_F1_q((_q1, _q2), (d1, d2), _a, D)
        return Check(alg.pieces(alg.convert(e, known)), free=[d1, d2, _q1, _q2, *_a], note=_PIECES)

    return build


def _bkm12_11(model: Model) -> Check:
    D = ball_notation(model).D
    E, C = sp.symbols("E C", real=True)
    d1s, d2s = hz.bkm12_quadratures((_q1, _q2), _a, D, E, C)
    d1, d2 = sp.sqrt(d1s), sp.sqrt(d2s)  # only squares enter
    H = hz.bkm12_energy_q((_q1, _q2), (d1, d2), _a, D)
    F1 = hz.bkm12_F1_q((_q1, _q2), (d1, d2), _a, D)
    return Check([sp.together(2 * H - E), sp.together(F1 - C)], free=[E, C, _q1, _q2, *_a])


def _eisenhart(model: Model) -> Check:
    """B1 B2^-1 in the chart (gamma1', gamma2'): trace and determinant are those of
    diag(q_i/(2 D (1 + q_i))), q_i the sphero-conical coordinates (a_i = D/I_i)."""
    n, gd, twoH, F1 = _chart_forms(model)
    g = n.gamma
    x1, x2 = sp.symbols("x1 x2", real=True)
    tangent = {gd[0]: x1, gd[1]: x2, gd[2]: -(g[0] * x1 + g[1] * x2) / g[2]}
    H = (twoH / 2).xreplace(tangent)
    F = F1.xreplace(tangent)
    B1 = sp.hessian(H, (x1, x2)) / 2
    B2 = sp.hessian(F, (x1, x2)) / 2
    aB = [n.D / Ii for Ii in n.I]
    s = sum((g[i] ** 2 * (aB[(i + 1) % 3] + aB[(i + 2) % 3]) for i in range(3)), sp.S.Zero)
    p = sum((g[i] ** 2 * aB[(i + 1) % 3] * aB[(i + 2) % 3] for i in range(3)), sp.S.Zero)
    # lam_i = q_i/(2D(1+q_i)): lam1 + lam2 and lam1 lam2 from q1 + q2 = s, q1 q2 = p
    trace = (s + 2 * p) / (2 * n.D * (1 + s + p))
    det = p / (4 * n.D**2 * (1 + s + p))
    # tr(B1 B2^-1) det B2 = tr(B1 adj B2), det(B1 B2^-1) det B2 = det B1
    adj = sp.Matrix([[B2[1, 1], -B2[0, 1]], [-B2[1, 0], B2[0, 0]]])
    dB2 = B2[0, 0] * B2[1, 1] - B2[0, 1] * B2[1, 0]
    dB1 = B1[0, 0] * B1[1, 1] - B1[0, 1] * B1[1, 0]
    return Check(
        [(B1 * adj).trace() - trace * dB2, dB1 - det * dB2],
        note="in the chart (gamma1', gamma2')",
    )


def _claims():
    yield Claim(
        id="K01-2.7",
        source=S22,
        kind="transformation",
        statement="d tau = rho dt, L = rho M, rho = (1 - D (gamma, J^-1 gamma))^-1/2: dx/dtau = "
        "{x, H} "
        "with H of (2.8) and the bracket (2.9) equals rho^-1 times the ball's flow "
        "(on the whole phase space, not only at (M, gamma) = 0)",
        system=BALL,
        effects=(),
        build=_flow(-1),
        note="the ball's right-hand side as derived by the engine; x' = {x, H}",
    )
    yield Claim(
        id="K01-2.7/control-sign",
        source=f"{S22} (negative control)",
        kind="transformation",
        statement="the same with the D-term of (2.9) of the opposite sign (+D (L, gamma) rho^2 "
        "J^-1 gamma)",
        system=BALL,
        effects=(),
        build=_flow(+1),
        expected="fails",
    )
    yield Claim(
        id="K01-2.8",
        source=S22,
        kind="equation",
        statement="H = (1 - D (gamma, J^-1 gamma)) (L, J^-1 L)/2 + D (gamma, J^-1 L)^2/2 at L = "
        "rho M "
        "is the ball's energy (M, omega)/2",
        system=BALL,
        effects=(),
        build=_energy,
    )
    yield Claim(
        id="K01-2.9",
        source=S22,
        kind="equation",
        statement="{L_i, L_j} = -eps_ijk (L_k - D (L, gamma) rho^2 (J^-1 gamma)_k), "
        "{L_i, gamma_j} = -eps_ijk gamma_k, {gamma_i, gamma_j} = 0 satisfies the Jacobi identity",
        system=BALL,
        effects=(),
        build=_jacobi(-1),
    )
    yield Claim(
        id="K01-2.9.e3",
        source=S22,
        kind="equation",
        statement="at (L, gamma) = 0 the bracket (2.9) is e(3): {L_i, L_j} = -eps_ijk L_k",
        system=BALL,
        effects=(),
        build=_e3_leaf,
    )
    yield Claim(
        id="K01-2.10.C",
        source=S22,
        kind="integral",
        statement="C = (L, gamma)/rho is a Casimir of (2.9); at L = rho M it is the constant of "
        "areas "
        "(M, gamma)",
        system=BALL,
        effects=(),
        build=_casimir("C"),
    )
    yield Claim(
        id="K01-2.10.gamma",
        source=S22,
        kind="integral",
        statement="(gamma, gamma) is a Casimir of (2.9)",
        system=BALL,
        effects=(),
        build=_casimir("gamma"),
    )
    yield Claim(
        id="K01-2.10.n",
        source=S22,
        kind="integral",
        statement="n = L^2/rho^2 is an integral of (2.8)-(2.9), {n, H} = 0, and equals (M, M) at L "
        "= rho M",
        system=BALL,
        effects=(),
        build=_n_integral,
    )
    yield Claim(
        id="K01-2.10/control-(L,gamma)",
        source=f"{S22} (negative control)",
        kind="integral",
        statement="(L, gamma) (without 1/rho) is a Casimir of (2.9)",
        system=BALL,
        effects=(),
        build=_casimir("(L,gamma)"),
        expected="fails",
    )
    yield Claim(
        id="K01-2.10/control-sign",
        source=f"{S22} (negative control)",
        kind="integral",
        statement="(L, gamma)/rho is a Casimir of the bracket with the D-term's sign reversed",
        system=BALL,
        effects=(),
        build=_casimir("C", d_sign=+1),
        expected="fails",
    )
    yield Claim(
        id="K01-2.11",
        source=S22,
        kind="definition",
        statement="q1, q2 are the zeros of f(q) = sum gamma_i^2/(a_i - q), a_i = 1/I_i, "
        "a3 < q2 < a2 < q1 < a1 (gamma_i^2 of (2.12))",
        system=BALL,
        effects=(),
        build=_spheroconical_zeros,
    )
    yield Claim(
        id="K01-2.12",
        source=S22,
        kind="definition",
        statement="gamma_i^2 = (a_i - q1)(a_i - q2)/prod_{j!=i}(a_i - a_j): sum gamma_i^2 = 1 and "
        "sum_i gamma_i^2 prod_{j!=i}(a_j - x) = (x - q1)(x - q2)",
        system=BALL,
        effects=(),
        build=_spheroconical_inverse,
    )
    yield Claim(
        id="BKM12-1.2a",
        source=S12,
        kind="definition",
        statement="sphero-conical coordinates with a_i = D/I_i: q_BKM = D q_K01 (same gamma_i^2, "
        "zeros "
        "of sum gamma_i^2/(a_i - x))",
        system=BALL,
        effects=(),
        build=_bkm12_spheroconical,
    )
    yield Claim(
        id="K01-2.13",
        source=S22,
        kind="transformation",
        statement="M = p1 (dq1/dgamma x gamma) + p2 (dq2/dgamma x gamma) lies on the leaf (M, "
        "gamma) = 0; "
        "M_i = 2 (a_j - a_l) gamma_j gamma_l ((a_i - q1) p1 - (a_i - q2) p2)/(q1 - q2), "
        "(i, j, l) cyclic",
        system=BALL,
        effects=(),
        build=_momentum_map_closed_form,
    )
    yield Claim(
        id="K01-2.13.poisson",
        source=S22,
        kind="transformation",
        statement="(q, p) -> (M, gamma) of (2.13) is a Poisson map from the canonical bracket onto "
        "e(3): "
        "{M_i, M_j} = -eps_ijk M_k, {M_i, gamma_j} = -eps_ijk gamma_k",
        system=BALL,
        effects=(),
        build=_momentum_map_poisson,
    )
    yield Claim(
        id="K01-2.14",
        source=S22,
        kind="equation",
        statement="the components (2.14) of M(q, p), F(q1, q2) = 2/(q1 - q2) sqrt(...), equal "
        "(2.13) "
        "(gamma in the positive octant)",
        system=BALL,
        effects=(),
        build=_momentum_components,
    )
    for which, eq, name in (("H", "2.15", "H"), ("n", "2.16", "n")):
        form = (
            "H = (4/K)/2 (q2^-1 - q1^-1)^-1 (-p1^2 f(q1) + p2^2 f(q2))"
            if which == "H"
            else "n = (4/K) (-p1^2 f(q1) q1 (1 + D q2) + p2^2 f(q2) q2 (1 + D q1))/(q1 - q2)"
        )
        target = "(2.8)" if which == "H" else "L^2/rho^2 of (2.10)"
        yield Claim(
            id=f"K01-{eq}",
            source=S22,
            kind="equation",
            statement=f"{form}, f(q) = q^-1 (q - a1)(q - a2)(q - a3)(1 + D q), K = prod_i (1 + D "
            f"a_i): "
            f"equals {target} at M(q, p) of (2.13)",
            system=BALL,
            effects=(),
            build=_qp_integral(which, printed=False),
        )
        yield Claim(
            id=f"K01-{eq}/literal",
            source=f"{S22} (literal reading)",
            kind="equation",
            statement=f"{name} as printed (without the factor 4/K) equals {target} at M(q, p) of "
            f"(2.13)",
            system=BALL,
            effects=(),
            build=_qp_integral(which, printed=True),
            expected="fails",
        )
    yield Claim(
        id="K01-2.17",
        source=S22,
        kind="solution",
        statement="S = sum_i int sqrt(K)/2 (2 lam1 + q lam2)/sqrt(R(q)) dq_i, R(q) = (2 lam1 + q "
        "lam2)"
        "(q - a1)(q - a2)(q - a3)(1 + D q), solves H(q, dS/dq) = lam1 (K01's S in the "
        "normalisation where (2.15) holds)",
        system=BALL,
        effects=(),
        build=_hamilton_jacobi("H"),
    )
    yield Claim(
        id="K01-2.18",
        source=S22,
        kind="equation",
        statement="lam1 = H, lam2 = 2 D H - n: n(q, dS/dq) = 2 D lam1 - lam2",
        system=BALL,
        effects=(),
        build=_hamilton_jacobi("n"),
    )
    yield Claim(
        id="K01-2.22",
        source=S22,
        kind="equation",
        statement="Abel-Jacobi: dq1/sqrt(R(q1)) + dq2/sqrt(R(q2)) = c0 d tau, "
        "q1 dq1/sqrt(R(q1)) + q2 dq2/sqrt(R(q2)) = 0 along (2.15), c0 = 2/sqrt(K), "
        "sqrt(R(q_i)) with the sign of p_i",
        system=BALL,
        effects=(),
        build=_abel_jacobi,
    )
    yield Claim(
        id="BKM12-8",
        source=S12,
        kind="equation",
        statement="M_gamma = (M, gamma) = (I omega, gamma)",
        system=BALL,
        effects=(),
        build=_bkm12_8,
    )
    yield Claim(
        id="BKM12-10",
        source=S12,
        kind="equation",
        statement="on (M, gamma) = 0: omega = k gamma' x I gamma, M = k I (gamma' x I gamma) - "
        "D gamma x gamma', k^-1 = (gamma, I gamma)",
        system=BALL,
        effects=(),
        build=_bkm12_10,
    )
    yield Claim(
        id="BKM12-1.2b.H",
        source=S12,
        kind="equation",
        statement="H = Delta D (q1 - q2)/2 (q1'^2/(q2 Phi(q1)) - q2'^2/(q1 Phi(q2))), "
        "Delta = (1 + q1)(1 + q2)/4, Phi(x) = (1 + x)(a1 - x)(a2 - x)(a3 - x), a_i = D/I_i",
        system=BALL,
        effects=(),
        build=_bkm12_12b("H"),
    )
    yield Claim(
        id="BKM12-1.2b.F1",
        source=S12,
        kind="equation",
        statement="F1 = Delta D^2 (q1 - q2)((1 + q2) q1'^2/(q2^2 Phi(q1)) - (1 + q1) q2'^2/(q1^2 "
        "Phi(q2)))",
        system=BALL,
        effects=(),
        build=_bkm12_12b("F1"),
    )
    yield Claim(
        id="BKM12-11",
        source=S12,
        kind="equation",
        statement="on 2H = E, F1 = C: q1'^2 = q2^2 Phi(q1)(C q1 - E D (1 + q1))/(Delta D^2 (q1 - "
        "q2)^2), "
        "q2'^2 = q1^2 Phi(q2)(C q2 - E D (1 + q2))/(Delta D^2 (q1 - q2)^2)",
        system=BALL,
        effects=(),
        build=_bkm12_11,
    )
    yield Claim(
        id="BKM12-RemEis",
        source=f"{S12}, Remark",
        kind="equation",
        statement="H = (x', B1 x'), F1 = (x', B2 x') in a chart: the eigenvalues of B1 B2^-1 are "
        "q_i/(2 D (1 + q_i)), one function of each sphero-conical coordinate",
        system=BALL,
        effects=(),
        build=_eisenhart,
    )


register(*_claims())
