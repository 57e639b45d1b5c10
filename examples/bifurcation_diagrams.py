"""Regenerate the bifurcation diagrams of K01 Figs. 1-3 and BKM12 Figs. 2, 3, 5.

Run from the repository root::

    python examples/bifurcation_diagrams.py

Each figure is the same as ``chaplygin bifurcation SYSTEM --figure NAME --out FILE``:
derived curves, stable families solid and unstable ones dashed (Floquet multipliers),
60 integrated random states as dots (the region of motion).
"""

from __future__ import annotations

from pathlib import Path

from chaplygin.verify.plots import FIGURES, bifurcation_figure


def main() -> None:
    out = Path(__file__).resolve().parent / "figures"
    out.mkdir(exist_ok=True)
    for name in FIGURES:
        path = out / f"bifurcation_{name}.png"
        figure, drift = bifurcation_figure(name, samples=60, seed=1)
        figure.savefig(path, dpi=110)
        print(f"{path}: drift of the samples {drift:.1e}")


if __name__ == "__main__":
    main()
