"""Cost per forcing period per point of BM20's stroboscopic map (issue 14 §4), side by side
with heyoka (one point at a time, and its batch mode with 4 points), in one run: our Taylor
integrator (one point per call) and our compiled batch map (DOP853 in C, N points per call,
:class:`chaplygin.numerics.dynamics.batch_map.BatchStroboscopicMap`). The measurement is
:func:`chaplygin.verify.bench_map.map_throughput` (also a section of ``chaplygin bench``).

BM20 Fig. 5's system: I = diag(4, 3, 2), K = (-6, -3, -9), d = 4.385, J = 0, delta = 2,
Omega = 1.07, G = 3 (z = 0.5, l = g = 1); double precision, rtol = 1e-12; the map is sampled at
every period (as the sweep's ``period`` reducer does). heyoka gets the same right-hand side
(the model's sympy expressions through ``heyoka.from_sympy``); the first periods of each are
compared with the Taylor run (the attractor is chaotic: they part later, at the rate of the
largest exponent).

Run: ``python examples/bench/sweep_map_throughput.py [PERIODS [REPEATS]]`` (heyoka optional:
``pip install heyoka``; never needed by the tests).
"""

from __future__ import annotations

import json
import sys

from chaplygin.verify.bench_map import map_throughput


def main() -> None:
    periods = int(sys.argv[1]) if len(sys.argv) > 1 else 700
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    print(json.dumps(map_throughput(periods, repeats), indent=1))


if __name__ == "__main__":
    main()
