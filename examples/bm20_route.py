"""BM20's open question: the route to the Fig. 5 attractor (numbers of notes/periodic-README).

Run from the repository root (about 10 minutes of CPU)::

    python examples/bm20_route.py

Body of BM20 Fig. 5 (I = diag(4, 3, 2), K = (-6, -3, -9), J = 0, delta = 2, G = 3), start
z = 0.5, l = 1, g = 1, the stroboscopic map in Andoyer-Deprit (z, l, g):

1. the attractor's period at Omega = 1.06675, 1.0669, 1.07 (d = 4.385) and the multipliers of
   the period-7 orbit;
2. the period-7 orbit continued in Omega (d = 4.385) and in d (Omega = 1.06675) with its
   events;
3. a scan of Omega = 1.0671 ... 1.0700 for periodic attractors, and the period-28 orbit found at
   Omega = 1.0683 continued in Omega.
"""

from __future__ import annotations

import numpy as np
from chaplygin.numerics import load_model_code
from chaplygin.numerics.ball.bm20_map import bm20_map_with_jacobian, bm20_point, bm20_state
from chaplygin.numerics.dynamics.continuation import continue_periodic_orbit
from chaplygin.numerics.dynamics.periodic_orbits import detect_period, refine_periodic_orbit
from chaplygin.numerics.dynamics.reversibility import stroboscopic_samples

BODY = [4.0, 3.0, 2.0, 4.385, 0.0, 2.0, -6.0, -3.0, -9.0, 1.07]
RTOL = 1e-10


def attractor(code, d: float, omega: float, transient: int, n: int = 1200) -> np.ndarray:
    """``n`` map points (z, l, g) after ``transient`` iterations from the Fig. 5 start."""
    params = list(BODY)
    params[3], params[9] = d, omega
    start = bm20_state(np.array([0.5, 1.0, 1.0]), 3.0)
    states = stroboscopic_samples(code, params, start, n, transient=transient, rtol=RTOL)
    return np.array([bm20_point(y) for y in states])


def report_events(title: str, result) -> None:
    print(title)
    for b in result.branches:
        print(f"  period {b.period}: {len(b.parameters)} points, {b.message}")
    for e in result.events:
        mods = ", ".join(f"{abs(m):.4f}" for m in e.multipliers)
        print(f"  {e.kind} of period {e.period} at {e.parameter:.10f} (|mult| {mods})")


def main() -> None:
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    # 1. periods and multipliers
    seven = None
    for omega in (1.06675, 1.0669, 1.07):
        points = attractor(code, 4.385, omega, 14000)
        k = detect_period(points, 512, 1e-4, angles=(1, 2), window=600)
        line = f"Omega = {omega}: period {k}"
        if k is not None:
            smap = bm20_map_with_jacobian(BODY, 3.0, rtol=RTOL)
            orbit = refine_periodic_orbit(smap, points[-1], k, omega)
            mult = ", ".join(f"{abs(m):.4f} exp({np.angle(m):+.3f} i)" for m in orbit.multipliers)
            line += f"; {orbit.message}; multipliers {mult}"
            seven = orbit if omega == 1.06675 else seven
        print(line, flush=True)
    # 2. continuation of the period-7 orbit
    x7 = seven.points[0]
    by_omega = bm20_map_with_jacobian(BODY, 3.0, rtol=RTOL)
    for end in (1.0662, 1.0727):
        r = continue_periodic_orbit(by_omega, x7, 7, 1.06675, end, step=5e-4, max_points=300)
        report_events(f"period 7 in Omega, 1.06675 -> {end}:", r)
    body = list(BODY)
    body[9] = 1.06675
    by_d = bm20_map_with_jacobian(body, 3.0, vary="D", rtol=RTOL)
    for end in (4.37, 4.40):
        r = continue_periodic_orbit(by_d, x7, 7, 4.385, end, step=5e-4, max_points=300)
        report_events(f"period 7 in d at Omega = 1.06675, 4.385 -> {end}:", r)
    # 3. past the Neimark-Sacker
    for omega in np.linspace(1.0671, 1.0700, 30):
        points = attractor(code, 4.385, omega, 14000)
        k = detect_period(points, 512, 1e-4, angles=(1, 2), window=600)
        print(f"Omega = {omega:.4f}: period {k}", flush=True)
    points = attractor(code, 4.385, 1.0683, 14000)
    orbit = refine_periodic_orbit(by_omega, points[-1], 28, 1.0683)
    print(
        f"period 28 at Omega = 1.0683: {orbit.message}; |mult| "
        f"{[round(abs(m), 4) for m in orbit.multipliers]}"
    )
    for end in (1.0678, 1.0690):
        r = continue_periodic_orbit(
            by_omega, orbit.points[0], 28, 1.0683, end, step=1e-4, max_points=80
        )
        report_events(f"period 28 in Omega, 1.0683 -> {end}:", r)


if __name__ == "__main__":
    main()
