"""Claims proved by computation: statements about computed objects decided by enclosures in
Arb ball arithmetic (the validated integrator of :mod:`chaplygin.numerics.validated` on the
generated Taylor recurrences, the Krawczyk and Schur-Cohn tests).

BM20 §3.2, Figs. 6-7: at ``d = 4.385`` the attractor of the stroboscopic map is a period-7
cycle at ``Omega = 1.06675`` (Fig. 7A) and ``1.0669`` (Fig. 7B), and not at ``1.07``
(Fig. 7C, past the cycle's Neimark-Sacker bifurcation near ``Omega = 1.06707`` found by the
continuation). The floating-point route finds the cycle (attractor, Newton at 30 digits,
continuation in ``Omega``); the proof does not depend on how the point was found: parallel
shooting over the 7 forcing periods, each period's map and its derivative enclosed over a
box of half-width 1e-13 around its point, the Krawczyk test on the 21-dimensional system
(one and only one cycle through the boxes) and the Schur-Cohn test on the enclosed product
of the derivatives (every multiplier strictly inside the unit circle, or one outside). The
control at ``Omega = 1.07`` is refuted by the same computation: the continued cycle exists
(Krawczyk) and has a multiplier of modulus at least 1 (Schur-Cohn).

BKM12 §1.5, Figs. 2-3: the steady rotations about the axes of the extreme ``A_i`` are stable,
about the middle one unstable. Each rotation is a closed-form periodic solution; its monodromy
is enclosed over one period and ``tr Phi - 4`` decides (see
:mod:`chaplygin.numerics.ball.steady_enclosure`: the integrals BKM12-5 and the invariant density
BKM12-4 make the characteristic polynomial ``(l - 1)^4 (l^2 - t l + 1)``).
"""

from __future__ import annotations

from functools import cache

from .base import Computed, ComputedClaim, register

BALL = "chaplygin_ball"
S32 = "BM20 §3.2, Figs. 6-7"


def _cycle(omega: str, period: int = 7):  # noqa: ANN202 - returns the claim's compute
    def run() -> Computed:
        from chaplygin.numerics.ball.bm20_enclosure import (
            bm20_orbit_guess,
            prove_bm20_periodic_orbit,
        )

        guess = bm20_orbit_guess(omega, period)
        r = prove_bm20_periodic_orbit(omega, guess, period)
        if r.exists == "unique zero" and r.attracting == "inside":
            decided = "proved"
        elif r.exists == "unique zero" and r.attracting == "not inside":
            decided = "refuted"
        else:
            decided = "undecided"
        moduli = ", ".join(f"{abs(m):.10f}" for m in r.multipliers)
        return Computed(
            error=0.0,
            bound=0.0,
            decided=decided,
            what=(
                f"BM20 Fig. 5 body, d = 4.385, G = 3, Omega = {omega} (enclosed as typed): "
                f"period-{period} cycle of the stroboscopic map by parallel shooting, "
                f"validated Taylor integrator (order 28, 128 bits, Lohner QR, C^1) in "
                f"{r.steps} steps; Krawczyk on the {3 * period}-dimensional system: "
                f"{r.exists} (K inside X with relative margin {r.margin:.3g}); Schur-Cohn on "
                f"the enclosed derivative of the {period}-fold map: multipliers {r.attracting}"
                f" the unit circle (midpoint moduli {moduli}); residual {r.residual:.2g}; "
                f"{r.seconds:.0f} s"
            ),
            values={
                "Omega": omega,
                "box z": str(r.box[0]),
                "box l": str(r.box[1]),
                "box g": str(r.box[2]),
                "Krawczyk": r.exists,
                "multipliers": f"{r.attracting} the unit circle",
                "|multipliers| (midpoint)": moduli,
                "widest state enclosure": f"{max(r.widths):.3g}",
            },
        )

    return run


register(
    ComputedClaim(
        id="BM20-Fig7A.cycle",
        source=f"{S32} (Fig. 7A)",
        kind="solution",
        statement="at Omega = 1.06675, d = 4.385 the stroboscopic map has an attracting "
        "period-7 cycle (the attractor of Fig. 7A): it exists and is unique in the stated box "
        "and all its multipliers lie strictly inside the unit circle",
        system=BALL,
        compute=_cycle("1.06675"),
        rigorous=True,
    ),
    ComputedClaim(
        id="BM20-Fig7B.cycle",
        source=f"{S32} (Fig. 7B)",
        kind="solution",
        statement="at Omega = 1.0669, d = 4.385 the period-7 cycle continued from Fig. 7A "
        "exists, is unique in the stated box and attracts",
        system=BALL,
        compute=_cycle("1.0669"),
        rigorous=True,
    ),
    ComputedClaim(
        id="BM20-Fig7C.cycle/control",
        source="control (Fig. 7C: no period-7 attractor at Omega = 1.07)",
        kind="solution",
        statement="(wrong) at Omega = 1.07, d = 4.385 the period-7 cycle continued from Fig. "
        "7A attracts",
        system=BALL,
        compute=_cycle("1.07"),
        rigorous=True,
        expected="fails",
    ),
)


# ------------------------------------------------- BKM12 §1.5: steady rotations, multipliers
S15 = "BKM12 §1.5"
#: BKM12 Fig. 2's reference body, as typed (I1, I2, I3), D; C = 1.
BKM12_BODY = (("1", "1.5", "3"), "1")


@cache
def _steady(Mg: str, axis: int, branch: int):  # noqa: ANN202 - a SteadyRotationProof
    from chaplygin.numerics.ball.steady_enclosure import prove_steady_rotation_stability

    I, D = BKM12_BODY
    return prove_steady_rotation_stability(I, D, axis, "1", Mg, branch, order=20, tol=1e-20)


def _steady_rule(Mg: str, axes: tuple[int, ...], stable: tuple[bool, ...]):  # noqa: ANN202
    """Decide 'the rotations about ``axes`` are stable (elliptic) where ``stable`` says so,
    unstable (hyperbolic) elsewhere', both senses of rotation."""

    def run() -> Computed:
        runs = [_steady(Mg, a, b) for a in axes for b in (0, 1)]
        want = [("elliptic" if s else "hyperbolic") for s in stable for _ in (0, 1)]
        got = [r.verdict for r in runs]
        if got == want:
            decided = "proved"
        elif any(g != w and g != "undecided" for g, w in zip(got, want, strict=True)):
            decided = "refuted"
        else:
            decided = "undecided"
        values = {}
        for r in runs:
            key = f"e_{r.axis + 1} w{'<' if r.branch == 0 else '>'}0"
            values[f"{key}: t = tr Phi - 4"] = r.trace.str(12, radius=False) + (
                f" +/- {float(r.trace.rad()):.1e}"
            )
            values[f"{key}: max |multiplier|"] = (
                "1 (exp(+-i theta), theta = " + (r.trace / 2).acos().str(10, radius=False) + ")"
                if r.verdict == "elliptic"
                else r.multiplier.str(10, radius=False)
            )
        return Computed(
            error=0.0,
            bound=0.0,
            decided=decided,
            what=(
                f"steady rotations about {', '.join(f'e_{a + 1}' for a in axes)} (both senses) "
                f"of the body I = (1, 1.5, 3), D = 1 on C = (M, M) = 1, M_gamma = {Mg} (closed "
                "form orbits, BKM12-crit): monodromy over one period enclosed by the validated "
                f"Taylor integrator (order 20, {runs[0].prec} bits, Lohner QR, C^1; widest "
                f"entry {max(r.width for r in runs):.1e}, y(T) - y0 encloses 0); the "
                "characteristic polynomial is (l - 1)^4 (l^2 - t l + 1), t = tr Phi - 4, by the "
                "integrals BKM12-5.F0/F1/F2 (their gradients' rank 3 proved by a 3 x 3 minor) "
                "and the invariant density BKM12-4 (det Phi = 1; enclosed: "
                f"{runs[0].det.str(6)}): |t| < 2 proves every multiplier of modulus 1, |t| > 2 a "
                f"real multiplier above 1; verdicts {got}; "
                f"{sum(r.steps for r in runs)} steps, {sum(r.seconds for r in runs):.0f} s"
            ),
            values=values,
        )

    return run


def _steady_claim(cid: str, figure: str, Mg: str, statement: str) -> ComputedClaim:
    return ComputedClaim(
        id=cid,
        source=f"{S15}, {figure}",
        kind="solution",
        statement=statement,
        system=BALL,
        compute=_steady_rule(Mg, (0, 1, 2), (True, False, True)),
        rigorous=True,
    )


register(
    _steady_claim(
        "BKM12-1.5stab.enclosed",
        "Fig. 2",
        "0",
        "steady rotations at (M, gamma) = 0, I = (1, 1.5, 3), D = C = 1: about e_1 and e_3 every "
        "Floquet multiplier has modulus 1 (the nontrivial pair exp(+-i theta), theta not 0 or "
        "pi), about e_2 one is real and above 1; both senses of rotation",
    ),
    _steady_claim(
        "BKM12-1.5stab8.enclosed",
        "Fig. 3",
        "0.5",
        "M_gamma = 0.5, I = (1, 1.5, 3), D = C = 1: the steady rotations on Sigma_1 and Sigma_3 "
        "(about e_1, e_3; four families) are stable (every multiplier of modulus 1), on Sigma_2 "
        "(about e_2) unstable (a real multiplier above 1)",
    ),
    ComputedClaim(
        id="BKM12-1.5stab.enclosed/control-middle-stable",
        source="control",
        kind="solution",
        statement="(wrong) at (M, gamma) = 0 the steady rotations about the middle axis e_2 "
        "are stable too (every multiplier of modulus 1)",
        system=BALL,
        compute=_steady_rule("0", (1,), (True,)),
        rigorous=True,
        expected="fails",
    ),
)
