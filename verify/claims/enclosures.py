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
"""

from __future__ import annotations

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
