"""The bench's section on proofs by computation (issue 27): what an enclosure costs beside
the floating-point run of the same problem, and the BM20 7-cycle proof's wall time.

One forcing period of BM20 Fig. 7A's model from the 7-cycle's point: the validated
integrator (Arb, 128 bits, order 28, remainder per step 1e-20) from the point and over a box
of half-width 1e-13 with the derivative (C^1), against ``integrate()`` on the same problem in
double (Taylor, rtol 1e-15) and at 30 digits (MPFR Taylor, tolerance 1e-30); medians of
``repeats`` runs, the ratios, and the enclosures' widths.
"""

from __future__ import annotations

import statistics
import time
from typing import Any

__all__ = ["enclosure_cost"]

#: BM20 Fig. 7A's cycle point (z, l, g) at 30 digits (bm20_orbit_guess("1.06675")).
FIG7A_POINT = (
    "-0.913250392820383617255795987835",
    "1.82298161216255763880019362677",
    "1.4951524295160417195881065507",
)


def _median_time(fn, repeats: int) -> tuple[float, Any]:  # noqa: ANN001
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def _steady_rotation_cost(repeats: int) -> dict[str, Any]:
    """BKM12's steady rotation about the middle axis (I = (1, 1.5, 3), D = C = 1): the
    monodromy over one period enclosed (the proof of BKM12-1.5stab.enclosed) against
    :func:`~chaplygin.numerics.ball.stability.floquet` in double (DOP853, rtol 1e-12)."""
    from ..numerics.ball.stability import critical_state, floquet
    from ..numerics.ball.steady_enclosure import prove_steady_rotation_stability

    def enclosed() -> Any:
        return prove_steady_rotation_stability(("1", "1.5", "3"), "1", 1, order=20, tol=1e-20)

    def double() -> Any:
        y0, T = critical_state((1.0, 1.5, 3.0), 1.0, 1, 1.0)
        return floquet((1.0, 1.5, 3.0), 1.0, y0, T, rtol=1e-12)

    t_enclosed, r = _median_time(enclosed, repeats)
    t_double, f = _median_time(double, repeats)
    trace = float(r.trace.mid())
    return {
        "steady rotation e_2, monodromy enclosed (s)": t_enclosed,
        "steady rotation e_2, monodromy in double (s)": t_double,
        "ratio monodromy enclosure / double": t_enclosed / t_double,
        "steady rotation e_2, width of tr Phi - 4": 2 * float(r.trace.rad()),
        "steady rotation e_2, |double - enclosed| of tr Phi - 4": abs(
            float(sum(f.nontrivial).real) - trace
        ),
    }


def enclosure_cost(repeats: int = 3, proof: bool = True) -> dict[str, Any]:
    """Seconds of one BM20 forcing period enclosed (from a point; over a box with C^1) and
    integrated in floating point, their ratios, and (``proof``) the 7-cycle proof's time.

    Parameters
    ----------
    repeats : int, optional
        Runs per measurement (the median is reported).
    proof : bool, optional
        Also run :func:`~chaplygin.numerics.ball.bm20_enclosure.prove_bm20_periodic_orbit` at
        ``Omega = 1.06675`` once (about two minutes).

    Returns
    -------
    dict
        ``name -> seconds`` (floats), ratios and widths.
    """
    from flint import arb

    from ..numerics import load_model_code
    from ..numerics.ball.bm20_enclosure import (
        BM20_FIG5_BODY,
        bm20_chart,
        prove_bm20_periodic_orbit,
    )
    from ..numerics.ball.bm20_map import BM20_EFFECTS
    from ..numerics.integrate import integrate
    from ..numerics.validated import enclose_flow, to_ball, working_precision

    code = load_model_code("chaplygin_ball", BM20_EFFECTS)
    params = [*BM20_FIG5_BODY, "1.06675"]
    with working_precision(128):
        y0 = [v.mid() for v in bm20_chart([to_ball(v) for v in FIG7A_POINT], arb(3))]
        box = [v + arb(0, 1e-13) for v in y0]
        period = 2 * arb.pi() / to_ball("1.06675")
    start = [float(v) for v in y0]
    T = float(period)
    t_point, e_point = _median_time(lambda: enclose_flow(code, params, y0, 0, period), repeats)
    t_box, e_box = _median_time(
        lambda: enclose_flow(code, params, box, 0, period, jacobian=True, order=20, tol=1e-16),
        repeats,
    )
    body = [float(v) for v in params]
    t_double, _ = _median_time(
        lambda: integrate("chaplygin_ball", start, T, body, effects=BM20_EFFECTS,
                          method="taylor", rtol=1e-15, atol=1e-15),
        repeats,
    )  # fmt: skip
    t_digits, _ = _median_time(
        lambda: integrate("chaplygin_ball", start, T, body, effects=BM20_EFFECTS,
                          method="taylor", precision=30, rtol=1e-30, atol=1e-30),
        repeats,
    )  # fmt: skip
    out: dict[str, Any] = {
        "one period, enclosure from a point (s)": t_point,
        "one period, enclosure over a 1e-13 box with C^1 (s)": t_box,
        "one period, double Taylor rtol 1e-15 (s)": t_double,
        "one period, 30-digit Taylor (s)": t_digits,
        "ratio point enclosure / double": t_point / t_double,
        "ratio point enclosure / 30 digits": t_point / t_digits,
        "ratio box C^1 enclosure / double": t_box / t_double,
        "width from the point": e_point.max_width,
        "width over the box": e_box.max_width,
        "steps from the point": e_point.steps,
    }
    out.update(_steady_rotation_cost(repeats))
    if proof:
        t = time.perf_counter()
        r = prove_bm20_periodic_orbit("1.06675", FIG7A_POINT)
        out["BM20 7-cycle proof at Omega = 1.06675 (s, target <= 120)"] = time.perf_counter() - t
        out["BM20 7-cycle proof verdicts"] = f"{r.exists}; multipliers {r.attracting}"
    return out
