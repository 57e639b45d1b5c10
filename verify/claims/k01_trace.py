"""K01 §3.3, Remark 2, §4 and Fig. 7(f): the contact point's trace, computed.

The statements are qualitative limits and shapes ("the radius of the envelope tends to
zero", "the number of wreaths becomes 1", "the trajectory remains bounded", "near the
elliptic fixed point"); each is turned into a number measured on the full equations
(:mod:`chaplygin.numerics.ball.trace_geometry`, :mod:`chaplygin.numerics.ball.gyrostat_diagram`) and
compared with a bound derived from the computation or stated with the claim. The motions
are integrable (``gamma`` periodic, the trace a chain of turned copies of one period), so
no check rests on where a chaotic orbit goes. Where the paper's statement and the
computation disagree, the claim states what the computation shows and a ``/literal`` claim
the paper's reading, refuted by the same numbers; every family has a control.

Reference body (K01 Figs. 6, 7): ``I = (1, 3, 5)``, ``C = 1``, ``D = b = 1`` (assumed; the
paper omits them); ``h1 = 1/2``, ``h2 = 1/6``, ``h3 = 1/10`` (K01-3.3seg).
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from ...arith import detcomplex, detlinalg, detmath
from .base import Computed, ComputedClaim, register

BALL = "chaplygin_ball"
I135, D1, C1 = (1.0, 3.0, 5.0), 1.0, 1.0
H1, H2, H3 = 0.5, 1.0 / 6.0, 0.1
K7 = (0.1, 0.1, 0.2)
RTOL = 1e-12
#: The printed energy of K01 Fig. 6(f).
H_FIG6F = 0.180278
#: Periods of the full equations behind K01-Fig6f.circle.
FIG6F_PERIODS = 64
S33 = "K01 §3.3"


def _tp(h: float):
    from chaplygin.numerics.ball.trace_geometry import trace_period

    return trace_period(I135, D1, h, C1, rtol=RTOL)


# ------------------------------------------------------------- Fig. 6(f) at the printed h
@cache
def _fig6f_run() -> dict:
    """One period at the printed energy, and ``FIG6F_PERIODS`` periods of the full
    equations sampled at ``t = k T``."""
    from chaplygin.numerics import integrate

    tp = _tp(H_FIG6F)
    k = np.arange(FIG6F_PERIODS + 1)
    r = integrate(
        BALL,
        tp.y0,
        float(k[-1] * tp.period),
        {"I": I135, "D": D1, "b": 1.0},
        effects=("contact_point",),
        rtol=RTOL,
        atol=RTOL,
        t_eval=k * tp.period,
    )
    z = detcomplex.make(r.y[r.state_names.index("x")], r.y[r.state_names.index("y")])
    d = tp.displacement
    # z0 + d (1 - q^k)/(1 - q), q = exp(i psi); q^k = exp(i k psi)
    circle = z[0] + detcomplex.div(
        detcomplex.mul(d, 1 - detcomplex.cis(k * tp.turn)), 1 - detcomplex.cis(tp.turn)
    )
    line = z[0] + detcomplex.make(k * d.real, k * d.imag)  # the unbounded reading: a drift
    return {"tp": tp, "z": z, "circle": circle, "line": line, "drift": max(r.drift.values())}


def _fig6f_bound(tp) -> float:
    """The integration's error over ``N T``: ``rtol`` per unit time on a state of size
    ``|d|`` per period, accumulated over ``N`` periods, with a margin of 10^4 (a bound
    on the relative error of the positions, 1e-6 here)."""
    return 1e4 * RTOL * FIG6F_PERIODS * tp.period


def _fig6f_circle(literal: bool):
    def run() -> Computed:
        out = _fig6f_run()
        tp, z = out["tp"], out["z"]
        reference = out["line"] if literal else out["circle"]
        step = detcomplex.absolute(tp.displacement)
        scale = FIG6F_PERIODS * step
        error = float(np.max(detcomplex.absolute(z - reference)) / scale)
        return Computed(
            error=error,
            bound=_fig6f_bound(tp),
            what=(
                f"contact point at t = k T, k <= {FIG6F_PERIODS}, on the full equations (Taylor, "
                f"rtol {RTOL:g}) at the printed h = {H_FIG6F}, I = (1, 3, 5), C = D = b = 1, "
                + (
                    "against the straight drift z0 + k d"
                    if literal
                    else "against the circle z0 + d (1 - q^k)/(1 - q), q = exp(i psi)"
                )
                + f"; largest difference over {FIG6F_PERIODS} |d|"
            ),
            values={
                "T": f"{tp.period:.10f}",
                "psi (turn per period, rad)": f"{tp.turn:.10f}",
                "|d| per period": f"{step:.10f}",
                "R = |d|/(2 |sin(psi/2)|)": f"{tp.radius:.6f}",
                "envelope radii (inner, outer)": f"{tp.inner:.6f}, {tp.outer:.6f}",
                "periods to close (2 pi/|psi|)": f"{2 * math.pi / abs(tp.turn):.2f}",
                "time to close": f"{2 * math.pi / abs(tp.turn) * tp.period:.1f}",
                "|z(NT) - z0|": f"{detcomplex.absolute(z[-1] - z[0]):.6f}",
                "largest drift of an integral": f"{out['drift']:.1e}",
            },
        )

    return run


register(
    ComputedClaim(
        id="K01-Fig6f.circle",
        source=f"{S33}, Fig. 6f (computed)",
        kind="value",
        statement="I = (1, 3, 5), C = D = 1, M || gamma, at the printed h = 0.180278 the trace is "
        "bounded: each period of gamma it turns by psi = 0.0097947 rad, so the points z(kT) lie on "
        "the circle of radius R = |d|/(2 sin(psi/2)) = 84.22 and the trace closes after 2 pi/psi "
        "= 641.5 periods (t = 27056); the critical energy (psi = 0) is 0.18031891515",
        system=BALL,
        compute=_fig6f_circle(False),
    )
)
register(
    ComputedClaim(
        id="K01-Fig6f/literal",
        source=f"{S33}, Fig. 6f as printed",
        kind="value",
        statement="at the printed h = 0.180278 the contact point's motion is infinite: it moves "
        "away by d each period of gamma along a straight line",
        system=BALL,
        compute=_fig6f_circle(True),
        expected="fails",
    )
)


# --------------------------------------------------- §3.3: envelope near h1 and near h3
#: Distances from h1 and h3 at which the limits are measured.
DELTAS = (1e-3, 1e-4, 1e-5)


@cache
def _near(end: float) -> list:
    """Trace periods at ``end -+ delta`` (inside the segment)."""
    sign = -1.0 if end == H1 else 1.0
    return [_tp(end + sign * d) for d in DELTAS]


def _slopes(values) -> list[float]:
    """``d log(value)/d log(delta)`` between consecutive deltas."""
    return [
        detmath.log(values[i + 1] / values[i]) / detmath.log(DELTAS[i + 1] / DELTAS[i])
        for i in range(len(values) - 1)
    ]


#: The bound on a measured exponent: the next order of the expansion in ``delta`` changes
#: the slope between ``delta`` and ``delta/10`` by ``O(delta/(h1 - h3))``, 2.5e-3 at the
#: largest ``delta``; the bound allows 4 times that.
SLOPE_BOUND = 1e-2


def _envelope(end: float, laws: dict[str, float], claim_end: float | None = None):
    """Exponents ``p`` of ``quantity ~ delta^p`` near ``end`` against the stated ``laws``."""

    def run() -> Computed:
        tps = _near(end)
        measured = {
            "outer": [tp.outer for tp in tps],
            "radius": [tp.radius for tp in tps],
            "width": [tp.outer - tp.inner for tp in tps],
            "speed": [tp.speed for tp in tps],
        }
        errors, values = [], {}
        for name, p in laws.items():
            s = _slopes(measured[name])
            errors += [abs(v - p) for v in s]
            values[f"{name} at delta = {DELTAS}"] = ", ".join(f"{v:.6g}" for v in measured[name])
            values[f"exponent of {name}"] = ", ".join(f"{v:.5f}" for v in s)
        where = "h1 - delta" if end == H1 else "h3 + delta"
        return Computed(
            error=max(errors),
            bound=SLOPE_BOUND,
            what=(
                f"envelope of the trace at h = {where}, delta = {DELTAS} (I = (1, 3, 5), C = D = "
                "b = 1; one period of the full equations each, Taylor rtol 1e-12): exponents "
                "d log q/d log delta against "
                + ", ".join(f"{k} ~ delta^{v:g}" for k, v in laws.items())
            ),
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="K01-3.3q.envelope-h1",
        source=f"{S33}, Fig. 6a",
        kind="value",
        statement="near h = h1 the trace is quasi-periodic and the radius of its envelope tends to "
        "zero as h -> h1: outer radius ~ (h1 - h)^(1/2) (I = (1, 3, 5))",
        system=BALL,
        compute=_envelope(H1, {"outer": 0.5, "radius": 0.5}),
    )
)
register(
    ComputedClaim(
        id="K01-3.3q.envelope-h1/control-h3",
        source="control",
        kind="value",
        statement="(wrong for I = (1, 3, 5)) the envelope's radius tends to zero as h -> h3 "
        "as well",
        system=BALL,
        compute=_envelope(H3, {"outer": 0.5, "radius": 0.5}),
        expected="fails",
    )
)
register(
    ComputedClaim(
        id="K01-3.3q.envelope-h3",
        source=f"{S33}, Fig. 6b",
        kind="value",
        statement="near h = h3 (I = (1, 3, 5)) the envelope's radius grows without bound, "
        "~ (h - h3)^(-1/2), while the difference of the envelope radii and the speed of the drift "
        "along them tend to zero, ~ (h - h3)^(1/2)",
        system=BALL,
        compute=_envelope(H3, {"radius": -0.5, "width": 0.5, "speed": 0.5}),
    )
)
register(
    ComputedClaim(
        id="K01-3.3q.envelope-h3/control-bounded",
        source="control",
        kind="value",
        statement="(wrong) near h = h3 the envelope's radius stays bounded (exponent 0)",
        system=BALL,
        compute=_envelope(H3, {"radius": 0.0}),
        expected="fails",
    )
)


# --------------------------------------------------- §3.3: spiral centres near h2
#: Offsets from h2 at which the spiral centres are measured.
CENTRE_DELTAS = (1e-4, -1e-4, 1e-5, -1e-5, 1e-6, -1e-6)


@cache
def _centres() -> list[dict]:
    from chaplygin.numerics.ball.trace_geometry import spiral_centres

    return [spiral_centres(I135, D1, H2 + d, C1, RTOL) for d in CENTRE_DELTAS]


@cache
def _delta_135() -> float:
    from chaplygin.numerics.ball.separatrix import delta_closed_form, mu_of

    return float(delta_closed_form(mu_of(I135, D1), 1.0))


def _centre_claim(literal: bool):
    """``chord/Delta - 1`` (corrected) or ``radius/(Delta/2) - 1`` (literal) against
    ``|h - h2|/h2`` at each offset."""

    def run() -> Computed:
        Delta = _delta_135()
        errors, values = [], {}
        for d, sc in zip(CENTRE_DELTAS, _centres(), strict=True):
            q = sc["radius"] / (Delta / 2) if literal else sc["chord"] / Delta
            errors.append(abs(q - 1) / (abs(d) / H2))
            values[f"h2 {d:+.0e}"] = (
                f"chord {sc['chord']:.12f}, half turn {sc['half_turn']:+.5f}, radius "
                f"{sc['radius']:.6f} = chord/(2|sin(half turn/2)|) "
                f"{sc['chord'] / (2 * abs(detmath.sin(sc['half_turn'] / 2))):.6f}"
            )
        values["Delta (K01-3.7)"] = f"{Delta:.12f}"
        return Computed(
            error=max(errors),
            bound=1.0,
            what=(
                "spiral centres of the trace at h = h2 + delta, delta = "
                f"{', '.join(f'{d:+.0e}' for d in CENTRE_DELTAS)} (I = (1, 3, 5), C = D = b = 1): "
                "three samples 1/lam apart at each passage by +-e2 give the centre of the "
                "linearised passage s + P exp((lam + i kap) t) + Q exp((-lam + i kap) t) "
                "(K01-3.5); "
                + (
                    "|radius of the centres' circle/(Delta/2) - 1|"
                    if literal
                    else "|distance of consecutive centres/Delta - 1|"
                )
                + " in units of |delta|/h2 (-> 0 with delta)"
            ),
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="K01-3.3q.centres",
        source=f"{S33}, Figs. 4, 6c, 6d",
        kind="value",
        statement="as h -> h2 consecutive spiral centres of the trace are Delta apart "
        "(|distance/Delta - 1| <= |h - h2|/h2), and they move on a circle of radius "
        "distance/(2 |sin(psi'/2)|), psi' the turn of the trace between passages",
        system=BALL,
        compute=_centre_claim(False),
    )
)
register(
    ComputedClaim(
        id="K01-3.3q.centres/literal",
        source=f"{S33} as printed",
        kind="value",
        statement="the radius along which the centre of the spiral moves tends to Delta/2 as "
        "h -> h2",
        system=BALL,
        compute=_centre_claim(True),
        expected="fails",
    )
)


# ----------------------------------------------------------- §3.3: wreaths of the spirals
#: Offsets from h2 (both sides) for the growth of the wreaths, and the points near h1, h3.
WREATH_DELTAS = (1e-4, 1e-5, 1e-6)
WREATH_ENDS = (H1 - 1e-4, H3 + 1e-4)


@cache
def _wreaths() -> dict:
    above = [_tp(H2 + d).turning / (4 * math.pi) for d in WREATH_DELTAS]
    below = [_tp(H2 - d).turning / (4 * math.pi) for d in WREATH_DELTAS]
    ends = [_tp(h).turning / (4 * math.pi) for h in WREATH_ENDS]
    from chaplygin.numerics.ball.separatrix import mu_of

    xi = float(mu_of(I135, D1))
    rate = xi * detmath.log(10.0) / (2 * math.pi)
    return {"above": above, "below": below, "ends": ends, "per_decade": rate}


def _wreath_claim(literal: bool):
    def run() -> Computed:
        w = _wreaths()
        rate = w["per_decade"]
        steps = [
            b - a for side in ("above", "below") for a, b in zip(w[side], w[side][1:], strict=False)
        ]
        floors = [math.floor(v) for v in w["ends"]]
        values = {
            "W at h2 + (1e-4, 1e-5, 1e-6)": ", ".join(f"{v:.6f}" for v in w["above"]),
            "W at h2 - (1e-4, 1e-5, 1e-6)": ", ".join(f"{v:.6f}" for v in w["below"]),
            "W at h1 - 1e-4, h3 + 1e-4": ", ".join(f"{v:.6f}" for v in w["ends"]),
            "xi ln(10)/(2 pi)": f"{rate:.6f}",
        }
        if literal:  # the count of full wreaths is 1 at both ends
            error, bound = float(sum(abs(f - 1) for f in floors)), 0.0
            what = "full wreaths floor(W) near h1 and near h3, against 1 at both"
        else:  # the growth law, and floor(W) = 0 near h1, 1 near h3
            error = max(abs(s - rate) / rate for s in steps)
            error = error if floors == [0, 1] else math.inf
            bound = 1e-2
            what = (
                "wreaths per passage W = Theta/(4 pi) (Theta: turning of the trace's tangent per "
                "period) at h2 +- delta: its growth per decade against xi ln(10)/(2 pi), "
                "relative (the remainder of the logarithmic law is O(delta ln delta)); and "
                "floor(W) near h1, h3 against 0, 1"
            )
        return Computed(
            error=error,
            bound=bound,
            what=what + " (I = (1, 3, 5), C = D = b = 1, Taylor rtol 1e-12)",
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="K01-3.3q.wreaths",
        source=f"{S33}, Figs. 6c-6e",
        kind="value",
        statement="the wreaths of the spiral per passage by the middle axis, W = Theta/(4 pi), "
        "grow like (xi/(2 pi)) ln(1/|h - h2|) as h -> h2 (xi = kap/lam of K01-3.7): finite near "
        "h2 and infinitely many critical energies (Theta in 2 pi Z) accumulate there; away from h2 "
        "they fall to one full wreath near h3 and to none near h1 (W < 1 above the critical energy "
        "0.18031891515 of Fig. 6f)",
        system=BALL,
        compute=_wreath_claim(False),
    )
)
register(
    ComputedClaim(
        id="K01-3.3q.wreaths/literal",
        source=f"{S33} as printed",
        kind="value",
        statement="as h moves away from h2 the number of wreaths of the spiral decreases and "
        "becomes equal to 1 (on both sides of h2)",
        system=BALL,
        compute=_wreath_claim(True),
        expected="fails",
    )
)


# ----------------------------------------------------------------- Remark 2: loxodrome
#: Half-width of the window on the separatrix, in units of 1/lam.
LOX_WINDOW = 6.0


def _meridian_angles(off: float) -> tuple[np.ndarray, float]:
    """Angle between the body trace ``gamma'`` and the meridians of the poles ``+-e2``.

    ``off = 0``: the separatrix (K01-3.4's point at ``t = 0``), forward and backward over
    ``|lam t| <= LOX_WINDOW`` on the full equations; ``off > 0``: the orbit at
    ``h = h2 (1 + off)``, one period (of
    :func:`~chaplygin.numerics.ball.trace_geometry.trace_period`,
    whose start is the same). Dense Taylor solutions, sampled at 2001 times per span.
    """
    from chaplygin.numerics.ball.separatrix import separatrix_quantities, separatrix_state
    from chaplygin.numerics.ball.trace_geometry import dense_solution
    from chaplygin.numerics.code import load_model_code

    code = load_model_code(BALL, ("contact_point",))
    p = np.array([*I135, D1, 1.0])
    lam = float(separatrix_quantities(I135, D1, C1)["lam"])
    if off == 0:
        y0 = np.array([float(v) for v in separatrix_state(I135, D1, C1)])
        runs = [
            (dense_solution(code, y0, span, p, RTOL), span)
            for span in ((0.0, LOX_WINDOW / lam), (0.0, -LOX_WINDOW / lam))
        ]
    else:
        tp = _tp(H2 * (1 + off))
        runs = [(tp.sol, (0.0, tp.period))]
    angles = []
    for sol, span in runs:
        y = sol(np.linspace(*span, 2001))
        g = y[3:6]
        dg = code.numpy.rhs(0.0, y, p)[3:6]
        e2 = np.array([0.0, 1.0, 0.0])[:, None]
        meridian = e2 - g * np.sum(g * e2, axis=0)
        meridian /= np.linalg.norm(meridian, axis=0)  # element-wise along axis 0
        parallel = np.cross(g, meridian, axis=0)
        a = detmath.atan2(np.sum(dg * parallel, axis=0), np.sum(dg * meridian, axis=0))
        angles.append(a)
    return np.concatenate(angles), lam


def _loxodrome(off: float):
    def run() -> Computed:
        a, lam = _meridian_angles(off)
        # a direction along the meridian towards either pole: fold the angle into [0, pi/2]
        folded = np.abs(detmath.atan2(detmath.sin(2 * a), detmath.cos(2 * a))) / 2
        spread = float(np.max(folded) - np.min(folded))
        return Computed(
            error=spread,
            bound=10 * 2 * RTOL * detmath.exp(2 * LOX_WINDOW),
            what=(
                "angle between the contact point's path on the ball (gamma', body frame) and the "
                "meridians of the poles +-e2, on the full equations (Taylor, rtol 1e-12) "
                + (
                    f"along the separatrix at h = h2 for |lam t| <= {LOX_WINDOW:g}"
                    if off == 0
                    else f"over one period at h = h2 (1 + {off:g})"
                )
                + "; spread of the angle (bound: the deviation rtol exp(lam |t|) over the "
                "distance sech(lam t) to the pole, times 10)"
            ),
            values={
                "angle range (rad)": f"[{folded.min():.3e}, {folded.max():.3e}]",
                "lam": f"{lam:.10f}",
            },
        )

    return run


register(
    ComputedClaim(
        id="K01-Rem2",
        source="K01 §3.3, Remark 2",
        kind="solution",
        statement="at h = h2 the contact point moves on the sphere at a constant angle to the "
        "meridians (poles +-e2, the middle axis): the angle is 0, the path is one meridian from "
        "pole to pole, a degenerate loxodrome",
        system=BALL,
        compute=_loxodrome(0.0),
    )
)
register(
    ComputedClaim(
        id="K01-Rem2/control-off-h2",
        source="control",
        kind="solution",
        statement="(wrong) at h = h2 (1 + 1e-3) the angle to the meridians of +-e2 is constant too",
        system=BALL,
        compute=_loxodrome(1e-3),
        expected="fails",
    )
)


# ------------------------------------------------------------------------- Fig. 7(f)
#: The energy of K01 Fig. 7(f) and the level n assumed for it.
H_FIG7F, N_FIG7F, N_FIG7F_BEFORE = 0.3, 2.7, 2.0
FIG7F_T = 300.0


@cache
def fig7f_rotation() -> dict:
    """The steady rotation with ``lam`` nearest ``J3`` and ``h = 0.3`` at ``C = 1``.

    Returns
    -------
    dict
        ``lam``, ``n``, ``state`` (``M, gamma``), ``omega`` and its Floquet result
        ``floquet``.
    """
    from chaplygin.numerics.ball.gyrostat_diagram import (
        level_integrals,
        steady_rotation_stability,
        steady_rotation_states,
    )
    from scipy.optimize import brentq

    J = np.asarray(I135) + D1

    def at(lam):
        lam = np.atleast_1d(np.asarray(lam, float))
        omega = np.asarray(K7)[:, None] / (lam[None, :] - J[:, None])
        states, exists = steady_rotation_states(I135, D1, K7, C1, omega, lam)
        vals = level_integrals(np.nan_to_num(states), I135, D1, K7)
        h = np.where(exists, vals["h"], np.nan)
        return states, vals["n"], h, omega

    # the family with lam nearest J3 (between the middle of J2, J3 and J3), where it exists
    grid = np.linspace((J[1] + J[2]) / 2, J[2], 2001)[:-1]
    excess = at(grid)[2] - H_FIG7F
    k = int(np.flatnonzero(np.isfinite(excess[:-1]) & (excess[:-1] * excess[1:] < 0))[0])
    lam = brentq(lambda v: float(at(v)[2][0]) - H_FIG7F, grid[k], grid[k + 1], xtol=1e-15)
    states, n, _, omega = at(lam)
    state, n, omega = states[:, 0], float(n[0]), omega[:, 0]
    return {
        "lam": lam,
        "n": n,
        "state": state,
        "omega": omega,
        "floquet": steady_rotation_stability(I135, D1, K7, state, RTOL),
    }


def _orbit_distance(states: np.ndarray, rotation: dict) -> np.ndarray:
    """Distance of states ``(M, gamma)`` (shape (6, N)) to the closed orbit of a steady
    rotation (4096 points of the orbit, :func:`_orbit_points`; elementwise sums, no BLAS)."""
    orbit = _orbit_points(rotation, 4096)
    out = np.empty(states.shape[1])
    for a in range(0, states.shape[1], 256):
        chunk = states[:, a : a + 256]
        d2 = sum((chunk[i][:, None] - orbit[i][None, :]) ** 2 for i in range(6))
        out[a : a + 256] = np.sqrt(np.min(d2, axis=1))
    return out


def _orbit_points(rotation: dict, count: int = 2048) -> np.ndarray:
    """Points ``(M, gamma)`` (shape (6, count)) of a steady rotation's closed orbit:
    ``gamma`` turns about the constant ``omega`` (Rodrigues) and ``M = J omega - D s gamma``
    with ``s = (omega, gamma)`` constant."""
    omega = np.asarray(rotation["omega"], float)
    e = omega / detlinalg.norm(omega)
    g0 = np.asarray(rotation["state"][3:], float)
    phi = np.linspace(0, 2 * np.pi, count, endpoint=False)
    c, s = detmath.cos(phi), detmath.sin(phi)
    g = np.outer(g0, c) + np.outer(np.cross(e, g0), s) + np.outer(e * detlinalg.dot(e, g0), 1 - c)
    Jw = (np.asarray(I135) + D1) * omega
    return np.vstack([Jw[:, None] - D1 * detlinalg.dot(omega, g0) * g, g])


@cache
def _fig7f_run(n: float, use_rotation_gamma: bool) -> dict:
    """The island of the elliptic rotation at h = 0.3 in n, and the trajectory of the level
    ``n`` (from the rotation's gamma, or point 0 of the level)."""
    from chaplygin.numerics import integrate
    from chaplygin.numerics.ball.gyrostat_diagram import steady_rotations_at_energy

    from ..scene import Scene

    rotation = fig7f_rotation()
    n_e = rotation["n"]
    at_energy = steady_rotations_at_energy(I135, D1, K7, C1, H_FIG7F, RTOL)
    # the critical levels of n at this energy: the rotations and the segment n = C^2
    critical = sorted({C1 * C1, *(r["n"] for r in at_energy)} - {n_e}, key=lambda v: v - n_e)
    side = [v for v in critical if (v - n_e) * (n - n_e) > 0]
    edge = min(side, key=lambda v: abs(v - n_e))
    bounding = [r for r in at_energy if r["n"] == edge]
    island = (
        float(np.min(_orbit_distance(_orbit_points(bounding[0]), rotation)))
        if bounding
        else math.inf
    )
    initial = {"C": C1, "n": n, "h": str(H_FIG7F)}
    if use_rotation_gamma:
        initial["gamma"] = [float(v) for v in rotation["state"][3:]]
    scene = Scene.from_dict(
        {
            "system": BALL,
            "effects": ["gyrostat"],
            "parameters": {"I": list(I135), "D": D1, "K": list(K7)},
            "initial": initial,
            "run": {"t_end": FIG7F_T},
        }
    )
    y0 = np.array([float(v) for v in scene.resolve().y0])
    r = integrate(BALL, y0, FIG7F_T, {"I": I135, "D": D1, "K": K7}, effects=("gyrostat",),
                  rtol=RTOL, atol=RTOL, t_eval=np.linspace(0, FIG7F_T, 1501))  # fmt: skip
    distance = _orbit_distance(r.y[:6], rotation)
    return {
        "fraction": abs(n - n_e) / abs(edge - n_e),
        "edge": edge,
        "island": island,
        "distance": float(np.max(distance)),
        "start": float(distance[0]),
        "at_energy": at_energy,
    }


def _fig7f(n: float, use_rotation_gamma: bool):
    def run() -> Computed:
        rotation = fig7f_rotation()
        out = _fig7f_run(n, use_rotation_gamma)
        fl = rotation["floquet"]
        values = {
            "elliptic rotation at h = 0.3": (
                f"n_e = {rotation['n']:.10f}, lam = {rotation['lam']:.10f}, nontrivial "
                "multipliers' moduli "
                + ", ".join(f"{detcomplex.absolute(m):.12f}" for m in fl.nontrivial)
            ),
            "steady rotations at h = 0.3": "; ".join(
                f"n = {r['n']:.6f} {'stable' if r['stable'] else 'unstable'} "
                f"(max|mu| {r['max_abs']:.4g})"
                for r in out["at_energy"]
            ),
            "island edge (next critical n)": f"{out['edge']:.6f}",
            "fraction |n - n_e|/|edge - n_e|": f"{out['fraction']:.6f}",
            "distance to the elliptic orbit: start, largest": (
                f"{out['start']:.6f}, {out['distance']:.6f}"
            ),
            "distance elliptic - bounding orbit": f"{out['island']:.6f}",
        }
        inside = out["distance"] < out["island"] / 2
        return Computed(
            error=out["fraction"] if fl.stable and inside else math.inf,
            bound=0.1,
            what=(
                f"K01 Fig. 7(f): I = (1, 3, 5), K = (0.1, 0.1, 0.2), C = D = 1, h = 0.3: the "
                "elliptic steady rotation (Floquet multipliers on the unit circle) at n_e, the "
                "island of tori about it up to the next critical level of n at h = 0.3 (a "
                f"rotation or n = C^2), and the level n = {n:g}: its place in the island, "
                "|n - n_e|/|edge - n_e|, against 'near' = the inner tenth; the trajectory "
                + ("from the rotation's gamma" if use_rotation_gamma else "from point 0")
                + f" (t <= {FIG7F_T:g}, Taylor rtol 1e-12) must stay within half the distance to "
                "the bounding rotation"
            ),
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="K01-Fig7f",
        source="K01 §4, Fig. 7f",
        kind="value",
        statement="I = (1, 3, 5), K = (0.1, 0.1, 0.2), C = 1 (D = 1 assumed): at h = 0.3 the "
        "steady rotation with lam between J2 and J3 is elliptic at n = 2.7075016, and at the "
        "assumed n = 2.7 the level is a torus about it, 0.02 of the way to the separatrix (the "
        "hyperbolic rotation at n = 2.334)",
        system=BALL,
        compute=_fig7f(N_FIG7F, True),
    )
)
register(
    ComputedClaim(
        id="K01-Fig7f/control-n2",
        source="control",
        kind="value",
        statement="(wrong: the assumption replaced) at n = 2, h = 0.3 the trajectory is near an "
        "elliptic fixed point",
        system=BALL,
        compute=_fig7f(N_FIG7F_BEFORE, False),
        expected="fails",
    )
)


# ------------------------------------------------- §4: M + K || gamma, bounded or not
#: Offsets from the saddle energies for the logarithmic law of the turning.
SADDLE_DELTAS = (1e-4, 1e-5)
#: The energies of K01 Fig. 7(a)-(c).
FIG7_ENERGIES = (0.1366, 0.1415, 0.1533)


@cache
def _segment_turning() -> dict:
    """The turning ``Theta(h)`` on ``M + K = C gamma`` next to each saddle and at Fig. 7's
    energies, along the line of steepest ascent from the least energy."""
    from chaplygin.numerics.ball.gyrostat_segment import gradient_line, segment_equilibria
    from chaplygin.numerics.ball.trace_geometry import trace_period

    eq = segment_equilibria(I135, D1, K7, C1)
    line = gradient_line(I135, D1, K7, C1, eq[0]["gamma"], ascending=True)

    def theta(h):
        return trace_period(I135, D1, None, C1, K7, line["at"](h), RTOL).turning

    sides = []
    for e in (e for e in eq if e["kind"] == "saddle"):
        for sign in (-1, 1):
            # orbits next to a saddle pass it once per period on the side of one loop of
            # its separatrix figure, twice on the side that encloses both loops
            turns = [theta(e["h"] + sign * d) / (2 * math.pi) for d in SADDLE_DELTAS]
            sides.append({"saddle": e, "sign": sign, "turns": turns})
    fig7 = {h: theta(h) / (2 * math.pi) for h in FIG7_ENERGIES}
    return {"equilibria": eq, "sides": sides, "fig7": fig7}


def _bounded_claim(literal: bool):
    def run() -> Computed:
        out = _segment_turning()
        errors, crossed, values = [], 0, {}
        for side in out["sides"]:
            e, turns = side["saddle"], side["turns"]
            step = turns[1] - turns[0]
            law = e["spin"] * detmath.log(10.0) / (2 * math.pi * e["rate"])
            k = round(step / law)
            errors.append(abs(step - k * law) / (k * law) if k in (1, 2) else math.inf)
            crossed += math.floor(max(turns)) - math.floor(min(turns))
            values[f"h_s {'-' if side['sign'] < 0 else '+'} (1e-4, 1e-5), h_s = {e['h']:.9f}"] = (
                f"Theta/2pi = {turns[0]:.6f}, {turns[1]:.6f}; per decade {step:.6f} = "
                f"{k} x sigma ln10/(2 pi lam_s) = {k} x {law:.6f}"
            )
        near_integer = min(abs(v - round(v)) for v in out["fig7"].values())
        values["Theta/2pi at Fig. 7(a)-(c)"] = ", ".join(
            f"h = {h}: {v:.6f}" for h, v in out["fig7"].items()
        )
        values["equilibria on the segment"] = "; ".join(
            f"{e['h']:.9f} {e['kind']}" for e in out["equilibria"]
        )
        if literal:
            return Computed(
                error=float(crossed),
                bound=0.0,
                what="critical energies (Theta/2pi crossing an integer) between h_s +- 1e-4 and "
                "h_s +- 1e-5 next to the saddles of M + K = C gamma, counted",
                values=values,
            )
        return Computed(
            error=max(errors) if near_integer > 1e-6 else math.inf,
            bound=1e-2,
            what=(
                "turning Theta of the trace per period of gamma on M + K = C gamma (I = (1, 3, 5), "
                "K = (0.1, 0.1, 0.2), C = D = b = 1) at h_s +- 1e-4, 1e-5 next to each saddle: "
                "growth per decade against k sigma ln(10)/(2 pi lam_s) (k passages, sigma = "
                "(omega, gamma) and lam_s the saddle's rate), relative; and Fig. 7(a)-(c) not "
                "critical (Theta/2pi at least 1e-6 from an integer)"
            ),
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="K01-4.3bounded",
        source="K01 §4 (computed)",
        kind="value",
        statement="on M + K = C gamma (I = (1, 3, 5), K = (0.1, 0.1, 0.2), C = 1, D = 1 assumed) "
        "the trace is bounded except at critical energies (Theta in 2 pi Z), which accumulate at "
        "the saddle energies 0.145017 and 0.207543: Theta grows by k sigma ln(10)/lam_s per decade "
        "of |h - h_s|; the energies of Fig. 7(a)-(c) are not critical",
        system=BALL,
        compute=_bounded_claim(False),
    )
)
register(
    ComputedClaim(
        id="K01-4.3bounded/literal",
        source="K01 §4 as printed",
        kind="value",
        statement="on M + K = C gamma the trajectory of the contact point remains bounded (at "
        "every energy)",
        system=BALL,
        compute=_bounded_claim(True),
        expected="fails",
    )
)
