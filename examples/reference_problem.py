"""The reference problem of BKM12 §1.1 through the Python API.

Integrates the Chaplygin ball with I = (1, 2, 3), D = 1 from M0 = (0.7, -0.4, 0.5),
gamma0 = (0.2, 0.3, sqrt(0.87)) in double precision (DOP853) and at 40 digits (mpmath
Taylor), and prints the drift of every first integral: the error evidence each result
carries. Run: ``python examples/reference_problem.py [T]``.
"""

from __future__ import annotations

import sys

from chaplygin.numerics import integrate

PARAMS = {"I": (1, 2, 3), "D": 1}
Y0 = {"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")}


def main(t_end: float = 1000.0) -> None:
    double = integrate("chaplygin_ball", Y0, t_end, PARAMS, method="DOP853", rtol=1e-12, atol=1e-12)
    print(
        f"DOP853, T = {t_end:g}: {double.nsteps} steps, {double.wall_s:.3f} s, "
        f"backend {double.backend}"
    )
    for name, drift in double.drift.items():
        print(f"  drift {name:<14} {drift:.2e}")
    short = min(t_end, 5.0)
    precise = integrate("chaplygin_ball", Y0, short, PARAMS, precision=40)
    print(f"mpmath Taylor, 40 digits, T = {short:g}: {precise.wall_s:.2f} s")
    for name, drift in precise.drift.items():
        print(f"  drift {name:<14} {drift:.2e}")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 1000.0)
