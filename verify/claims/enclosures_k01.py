"""K01 §3.3, Fig. 6(f): the critical energies where the contact point's trace becomes unbounded,
proved by computation.

For ``I = (1, 3, 5)``, ``C = D = b = 1`` on the segment ``M = C gamma``, the frame turn
``Phi(h)`` per period of ``gamma`` is enclosed by the rigorous section map (the return to
``gamma2 = 0``, :mod:`chaplygin.numerics.ball.frame_turn_enclosure`) with its derivative in the
energy; the interval Newton test on ``Phi`` proves one and only one critical energy
(``Phi = 0``) in a neighbourhood ``N`` around Brent's zero (half-width 3e-7 and 2e-6, as wide
as the enclosure of ``Phi'`` over it allows; checked to cover the statement's neighbourhood of
the printed energy), inside an interval of width at most 1e-12, with ``Phi`` enclosed at that
interval's ends (opposite signs). The floating-point route (Brent on the double-precision frame
turn) gives the starting energy and the period's window; the proof does not depend on it.
The control reads Fig. 6(f)'s printed energy 0.180278 as a critical energy: refuted by the same
computation (no zero in its neighbourhood).

FORMULAS.md lists 0.171990 as a third resonance in ``(h2, h1)``: there the double-precision
turn jumps from ``+pi`` to ``-pi`` (Brent found ``atan2``'s branch cut, not a zero); the
enclosures give ``cos Phi < 0`` over ``0.171990 +- 1e-7`` (``Phi = pi`` mod ``2 pi``): the trace's
copies alternate and stay bounded. That reading is refuted, as expected.
"""

from __future__ import annotations

from typing import Any

from .base import Computed, ComputedClaim, register

BALL = "chaplygin_ball"
S33 = "K01 §3.3, Fig. 6(f)"
I135 = (1.0, 3.0, 5.0)
#: The critical energies the double-precision sweep finds in (h2, h1) (K01-Fig6f.circle's
#: statement and FORMULAS.md), each bracketed +- 2e-6 for Brent: the energy, the half-width
#: of the stated neighbourhood around it and the radius of ``N`` around Brent's zero (large
#: enough to cover the stated neighbourhood, small enough for ``Phi'`` over ``N`` to exclude 0).
SWEEP = {
    "1": ("0.1803189", 2e-7, 3e-7),
    "2": ("0.293688", 1e-6, 2e-6),
}


def _critical(key: str | None, printed: str | None = None):  # noqa: ANN202 - the compute
    def run() -> Computed:
        from chaplygin.numerics.ball.frame_turn import critical_energy, frame_turn
        from chaplygin.numerics.ball.frame_turn_enclosure import prove_critical_energy
        from chaplygin.numerics.validated import to_ball, working_precision
        from flint import arb

        if printed is None:
            x, half, radius = SWEEP[key]
            guess = repr(critical_energy(I135, 1.0, (float(x) - 2e-6, float(x) + 2e-6)))
        else:
            x, half, radius = printed, 1e-7, 1e-7
            guess = printed
        period, _ = frame_turn(I135, 1.0, float(guess))
        # Phi' over N at a looser step control (its width is N's, not the steps')
        r = prove_critical_energy(
            ("1", "3", "5"), "1", guess, period, radius=radius, slope_tol=1e-12
        )
        with working_precision(128):  # N covers the statement's neighbourhood x +- half
            stated = to_ball(x) + arb(0, half)
            covered = r.neighbourhood.contains(stated)
            # 'exactly one within half of x': the one zero of N must lie in x +- half too
            inside = r.verdict != "unique zero" or stated.contains(r.energy)
        # the claim: a critical energy in N (for the controls: near the printed energy)
        decided = {"unique zero": "proved", "no zero": "refuted"}.get(r.verdict, "undecided")
        decided = decided if covered and inside else "undecided"
        width = 2 * float(r.energy.rad())
        ends = ", ".join(e.str(3) for e in r.ends) if r.ends else "(not evaluated)"
        monotone = "0 excluded: Phi monotone on N" if not r.slope.contains(0) else "contains 0"
        if r.cosine < 0:  # the branch cut: the verdict from cos Phi alone
            test = "cos Phi < 0 over N: no zero of Phi mod 2 pi in N"
        elif r.verdict == "no zero" and r.energy is r.neighbourhood:
            test = "0 < cos Phi and 0 not in Phi over N: no zero of Phi mod 2 pi in N"
        else:
            test = f"interval Newton: {r.verdict} in N, in {r.energy.str(15)} (width {width:.2g})"
        return Computed(
            error=0.0,
            bound=0.0,
            decided=decided,
            what=(
                f"I = (1, 3, 5), C = D = b = 1, M = C gamma: the frame turn Phi(h) per period of "
                f"gamma by the validated section map (return to gamma2 = 0, Taylor order 20, "
                f"128 bits, step tolerance 1e-20; 1e-12 for Phi' over N), Phi' over "
                f"N = {guess} +- {radius:g} (covers {x} +- {half:g}: {covered}): "
                f"[{_bound(r.slope.lower())}, {_bound(r.slope.upper())}] ({monotone}); "
                f"cos Phi over N {r.cosine.str(5)}; Phi at {guess} (over N when that "
                f"decides) {r.turn_at_centre.str(3)}; {test}; Phi at its ends {ends}; "
                f"{r.seconds:.0f} s"
            ),
            values={
                "critical energy": r.energy.str(15),
                "width": f"{width:.2g}",
                "N": f"{guess} +- {radius:g}",
                "Phi' over N": r.slope.str(8),
                "Newton test": r.verdict,
            },
        )

    return run


def _bound(v: Any) -> str:
    """An interval's end (an exact binary ``arb``), to 6 digits, for the report."""
    return v.str(6, radius=False)


register(
    ComputedClaim(
        id="K01-Fig6f.critical",
        source=f"{S33} (computed)",
        kind="value",
        statement="I = (1, 3, 5), C = D = b = 1, M || gamma: the frame turn per period vanishes "
        "(the trace is unbounded) at exactly one energy within 2e-7 of 0.1803189, enclosed in "
        "an interval of width <= 1e-12, across which the turn changes sign",
        system=BALL,
        compute=_critical("1"),
        rigorous=True,
    ),
    ComputedClaim(
        id="K01-Fig6f.critical-2",
        source=f"{S33} (computed)",
        kind="value",
        statement="the same at exactly one energy within 1e-6 of 0.293688",
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
        compute=_critical(None, "0.171990"),
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
