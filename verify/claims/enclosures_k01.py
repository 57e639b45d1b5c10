"""K01 §3.3, Fig. 6(f): the critical energies where the contact point's trace becomes unbounded,
proved by computation.

For ``I = (1, 3, 5)``, ``C = D = b = 1`` on the segment ``M = C gamma``, the frame turn
``Phi(h)`` per period of ``gamma`` is enclosed by the rigorous section map (the return to
``gamma2 = 0``, :mod:`chaplygin.numerics.ball.frame_turn_enclosure`) with its derivative in the
energy; the interval Newton test on ``Phi`` proves one and only one critical energy
(``Phi = 0``) in a neighbourhood ``N`` of half-width 1e-7, inside an interval of width at most
1e-12, with ``Phi`` enclosed at that interval's ends (opposite signs). The floating-point route
(Brent on the double-precision frame turn) gives the starting energy and the period's window;
the proof does not depend on it. The control reads Fig. 6(f)'s printed energy 0.180278 as a
critical energy: refuted by the same computation (no zero in its neighbourhood).

FORMULAS.md lists 0.171990 as a third resonance in ``(h2, h1)``: there the double-precision
turn jumps from ``+pi`` to ``-pi`` (Brent found ``atan2``'s branch cut, not a zero); the
enclosures give ``cos Phi < 0`` over its neighbourhood (``Phi = pi`` mod ``2 pi``): the trace's
copies alternate and stay bounded. That reading is refuted, as expected.
"""

from __future__ import annotations

from .base import Computed, ComputedClaim, register

BALL = "chaplygin_ball"
S33 = "K01 §3.3, Fig. 6(f)"
I135 = (1.0, 3.0, 5.0)
#: The critical energies the double-precision sweep finds in (h2, h1) (K01-Fig6f.circle's
#: statement and FORMULAS.md), each bracketed +- 2e-6 for Brent.
SWEEP = {"1": 0.1803189, "2": 0.293688, "pi": 0.171990}


def _critical(key: str | None, printed: str | None = None):  # noqa: ANN202 - the compute
    def run() -> Computed:
        from chaplygin.numerics.ball.frame_turn import critical_energy, frame_turn
        from chaplygin.numerics.ball.frame_turn_enclosure import prove_critical_energy

        if printed is None:
            x = SWEEP[key]
            guess = repr(critical_energy(I135, 1.0, (x - 2e-6, x + 2e-6)))
        else:
            guess = printed
        period, _ = frame_turn(I135, 1.0, float(guess))
        r = prove_critical_energy(("1", "3", "5"), "1", guess, period)
        # the claim: a critical energy in N (for the control: near the printed energy)
        decided = {"unique zero": "proved", "no zero": "refuted"}.get(r.verdict, "undecided")
        width = 2 * float(r.energy.rad())
        ends = ", ".join(e.str(3) for e in r.ends) if r.ends else "(not evaluated)"
        return Computed(
            error=0.0,
            bound=0.0,
            decided=decided,
            what=(
                f"I = (1, 3, 5), C = D = b = 1, M = C gamma: the frame turn Phi(h) per period of "
                f"gamma by the validated section map (return to gamma2 = 0, Taylor order 20, "
                f"128 bits), Phi' over N = {guess} +- 1e-7: {r.slope.str(8)} (0 excluded: Phi "
                f"monotone on N); cos Phi over N {r.cosine.str(5)}; Phi({guess}) = "
                f"{r.turn_at_centre.str(3)}; interval Newton: "
                f"{r.verdict} in N, in {r.energy.str(15)} (width {width:.2g}); Phi at its ends "
                f"{ends}; {r.seconds:.0f} s"
            ),
            values={
                "critical energy": r.energy.str(15),
                "width": f"{width:.2g}",
                "Phi' over N": r.slope.str(8),
                "Newton test": r.verdict,
            },
        )

    return run


register(
    ComputedClaim(
        id="K01-Fig6f.critical",
        source=f"{S33} (computed)",
        kind="value",
        statement="I = (1, 3, 5), C = D = b = 1, M || gamma: the frame turn per period vanishes "
        "(the trace is unbounded) at exactly one energy within 1e-7 of 0.1803189, enclosed in "
        "an interval of width <= 1e-12, across which the turn changes sign",
        system=BALL,
        compute=_critical("1"),
        rigorous=True,
    ),
    ComputedClaim(
        id="K01-Fig6f.critical-2",
        source=f"{S33} (computed)",
        kind="value",
        statement="the same at exactly one energy within 1e-7 of 0.293688",
        system=BALL,
        compute=_critical("2"),
        rigorous=True,
    ),
    ComputedClaim(
        id="K01-Fig6f.critical/resonance-0.171990",
        source="FORMULAS.md's K01-Fig6f (a sign change of the double-precision turn)",
        kind="value",
        statement="(wrong) the frame turn also vanishes within 1e-7 of 0.171990 (there it is "
        "pi mod 2 pi: atan2's branch cut)",
        system=BALL,
        compute=_critical("pi"),
        rigorous=True,
        expected="fails",
    ),
    ComputedClaim(
        id="K01-Fig6f.critical/control-printed",
        source="control (Fig. 6(f)'s printed energy read as the critical one)",
        kind="value",
        statement="(wrong) the printed h = 0.180278 is a critical energy: the frame turn "
        "vanishes within 1e-7 of it",
        system=BALL,
        compute=_critical(None, "0.180278"),
        rigorous=True,
        expected="fails",
    ),
)
