"""Contact-point traces of BKM12's critical solutions (BKM12 §1.5).

Run from the repository root (about 10 s)::

    python examples/bkm12_traces.py

Writes ``examples/figures/bkm12-critical-traces.png``: (a) the six families (25) at
(M, gamma) = 0 roll along straight lines (claim BKM12-25.trace), (b) so do the rotations on
Sigma_1..3 at (M, gamma) = 0.5 (BKM12-crit.trace), (c) the orbits M = +-sqrt(C) gamma
(Sigma_4, Sigma_5) on both arcs, (d) a separatrix of Sigma_2 (BKM12-1.5sep). I = (1, 1.5, 3),
D = 1, b = 1, C = 2 (assumed: BKM12 draws no traces).
"""

from __future__ import annotations

from pathlib import Path

from chaplygin.verify.plots import critical_traces_figure


def main() -> None:
    out = Path(__file__).resolve().parent / "figures" / "bkm12-critical-traces.png"
    critical_traces_figure().savefig(out, dpi=100)
    print(out)


if __name__ == "__main__":
    main()
