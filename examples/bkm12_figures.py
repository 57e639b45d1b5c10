"""BKM12 §1.5 computed: the bifurcation complex of Figs. 2(b), 3(b) and the contact-point
traces of the critical solutions.

Run from the repository root (about a minute)::

    python examples/bkm12_figures.py

Writes ``examples/figures/bkm12-complex.png``: over C = 1 at g = M_gamma/sqrt(C) = 0 (Fig. 2(b))
and 0.5 (Fig. 3(b)), each connected component of the level sets (a leaf) at the mean of M along
the axis of the stable family it ends on: four leaves, from the stable rotations of Sigma_1 and
Sigma_3 to Sigma_2, where they are glued (claims BKM12-Fig2b, BKM12-Fig3b.*); and
``examples/figures/bkm12-critical-traces.png``: (a) the six families (25) at (M, gamma) = 0 roll
along straight lines (BKM12-25.trace), (b) so do the rotations on Sigma_1..3 at (M, gamma) = 0.5
(BKM12-crit.trace), (c) the orbits M = +-sqrt(C) gamma (Sigma_4, Sigma_5) on both arcs, (d) a
separatrix of Sigma_2 (BKM12-1.5sep). I = (1, 1.5, 3), D = 1, b = 1, C = 2 for the traces
(assumed: BKM12 gives no body and draws no traces).
"""

from __future__ import annotations

from pathlib import Path

from chaplygin.verify.plots import bifurcation_complex_figure, critical_traces_figure


def main() -> None:
    out = Path(__file__).resolve().parent / "figures"
    for name, figure in (("bkm12-complex.png", bifurcation_complex_figure),
                         ("bkm12-critical-traces.png", critical_traces_figure)):  # fmt: skip
        figure().savefig(out / name, dpi=100)
        print(out / name)


if __name__ == "__main__":
    main()
