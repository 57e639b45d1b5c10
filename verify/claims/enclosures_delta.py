"""K01 §3.3, (3.7): Delta from the full equations enclosed, proved to contain the closed form.

For the bodies of K01 Fig. 4 (``I = (1, 1.5, 2)`` and ``(1, 3, 5)``, ``D = b = C = 1``) the
displacement ``Delta`` of the contact point along the separatrix is enclosed by
:func:`~chaplygin.numerics.ball.separatrix_enclosure.enclose_delta`: the separatrix point
(K01-3.4, proved symbolically: the solution through it is the separatrix) in Arb balls, the
flow of the 14-dimensional ``chaplygin_ball__contact_point`` model enclosed by the validated
Taylor integrator forward and backward to ``lam t = +-L``, and the two tails from
``x' = nu cos(kap t)/ch(lam t)`` (K01-3.5, proved symbolically) summed as a series with a
bound of its rest. The claim holds when the Arb enclosure of ``pi b/ch(pi mu/2)`` (K01-3.7)
lies inside the enclosure of ``Delta``; it is refuted when the two are disjoint. The control
``pi b/ch(pi mu)`` (the reading of K01-3.7/control-ch(pi xi)) is refuted by the same
computation.
"""

from __future__ import annotations

from functools import cache

from .base import Computed, ComputedClaim, register

BALL = "chaplygin_ball"
S33 = "K01 §3.3, eq. (3.7), Fig. 4"
#: The settings of the enclosures: L = lam T, the tails' series terms, bits, order, tol.
SETTINGS = {"L": 14.0, "terms": 2, "prec": 128, "order": 24, "tol": 1e-24}
#: The bodies of K01 Fig. 4 (I as typed), D = b = C = 1.
BODIES = {"1": ("1", "1.5", "2"), "2": ("1", "3", "5")}


@cache
def _floating_seconds(key: str) -> float:
    """Wall time of the floating-point route on the same problem (:func:`~chaplygin.numerics.
    ball.separatrix.delta_ode` at 30 digits): the cost the enclosure is compared with, not part
    of the proof."""
    import time

    from chaplygin.numerics.ball.separatrix import delta_ode

    started = time.perf_counter()
    delta_ode([float(v) for v in BODIES[key]], 1, 1, 30)
    return time.perf_counter() - started


@cache
def _enclosure(key: str):  # noqa: ANN202 - a DeltaEnclosure
    """The enclosure of Delta for a body; an ``EnclosureError`` (the flow's enclosure blew
    up) leaves the claim ``numeric`` with where it grew (:mod:`chaplygin.verify.verdict`)."""
    from chaplygin.numerics.ball.separatrix_enclosure import enclose_delta

    return enclose_delta(BODIES[key], 1, 1, 1, **SETTINGS)


def _delta_rule(key: str, half: bool = True):  # noqa: ANN202 - returns the claim's compute
    def run() -> Computed:
        from chaplygin.numerics.ball.separatrix_enclosure import delta_closed_form_ball
        from chaplygin.numerics.validated.lohner import working_precision

        I = ", ".join(BODIES[key])
        form = "pi b/ch(pi mu/2) (K01-3.7)" if half else "pi b/ch(pi mu) (the control)"
        r = _enclosure(key)
        with working_precision(r.prec):
            closed = r.closed if half else delta_closed_form_ball(r.mu, 1, half=False)  # b = 1
        floating = _floating_seconds(key)
        if r.delta.contains(closed):
            decided = "proved"
        elif not r.delta.overlaps(closed):
            decided = "refuted"
        else:
            decided = "undecided"
        return Computed(
            error=0.0,
            bound=0.0,
            decided=decided,
            what=(
                f"I = ({I}), D = b = C = 1: Delta = |x(+oo) - x(-oo)| enclosed from the full "
                "equations (chaplygin_ball__contact_point, 14-D): the separatrix point of "
                "K01-3.4 in Arb, the flow to lam t = +-L by the validated Taylor integrator "
                f"(order {SETTINGS['order']}, {r.prec} bits, Lohner QR, forward and backward; "
                f"{r.steps} steps, L = {r.L:g}, T = {r.T:.6g}), the tails from x' = nu "
                f"cos(kap t)/ch(lam t) (K01-3.5) as {r.terms} terms of 1/ch = 2 sum (-1)^n "
                f"exp(-(2n+1) lam t) and a bound {r.tail_bound:.1e} of the rest; enclosure "
                f"{r.delta.str(16)} (width {r.width:.2e}, relative "
                f"{r.width / float(r.delta.mid()):.1e}); {form} = {closed.str(16)} "
                f"{'inside' if decided == 'proved' else 'not inside'} it; {r.seconds:.0f} s "
                f"(the floating route delta_ode at 30 digits: {floating:.2f} s, ratio "
                f"{r.seconds / floating:.0f})"
            ),
            values={
                "Delta (enclosed)": r.delta.str(20),
                "width": f"{r.width:.3e}",
                "x(T) - x(-T) width": f"{r.flow_width:.3e}",
                "tails (enclosed)": r.tail.str(12),
                "tail bound (omitted terms)": f"{r.tail_bound:.3e}",
                form: closed.str(20),
                "y(+oo) - y(-oo) (enclosed)": r.y_shift.str(5),
                "mu": r.mu.str(16),
                "L = lam T": f"{r.L:g}",
                "steps": str(r.steps),
                "seconds": f"{r.seconds:.1f}",
                "floating route (delta_ode, 30 digits)": f"{floating:.2f} s",
            },
        )

    return run


register(
    ComputedClaim(
        id="K01-Fig4.delta-enclosed-1",
        source=S33,
        kind="value",
        statement="I = (1, 1.5, 2), D = b = C = 1: Delta from the full equations (the separatrix "
        "flow and its tails) lies in an enclosure that contains pi b/ch(pi mu/2) "
        "(0.0028586033...)",
        system=BALL,
        compute=_delta_rule("1"),
        rigorous=True,
    ),
    ComputedClaim(
        id="K01-Fig4.delta-enclosed-2",
        source=S33,
        kind="value",
        statement="I = (1, 3, 5), D = b = C = 1: Delta from the full equations lies in an "
        "enclosure that contains pi b/ch(pi mu/2) (0.4118294225...)",
        system=BALL,
        compute=_delta_rule("2"),
        rigorous=True,
    ),
    ComputedClaim(
        id="K01-3.7.enclosed/control-ch(pi mu)",
        source=f"{S33} (negative control)",
        kind="value",
        statement="(wrong) I = (1, 3, 5), D = b = C = 1: the enclosure of Delta from the full "
        "equations contains pi b/ch(pi mu) (the factor 1/2 dropped)",
        system=BALL,
        compute=_delta_rule("2", half=False),
        rigorous=True,
        expected="fails",
    ),
)
