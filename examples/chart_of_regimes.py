"""A chart of dynamical regimes in the (d, Omega) plane, as BM20 Fig. 6 (coarse).

Run from the repository root (a few minutes)::

    python examples/chart_of_regimes.py [n_d n_Omega [Omega_min Omega_max]]

For each (d, Omega) the stroboscopic map of BM20 Fig. 5's body (I = diag(4, 3, 2),
K = (-6, -3, -9), J = 0, delta = 2, G = 3) is iterated from z = 0.5, l = 1, g = 1; after a
transient of 6000 iterations the smallest period <= 64 that closes within 1e-4 (in z, l, g)
is the point's colour (0: none, chaotic or quasi-periodic). These are candidate periods, as in
a chart of regimes; the scene output ``periodic_orbits`` confirms one by Newton's method.
Writes ``examples/figures/dynamics/bm20-chart.png`` and ``bm20-chart.npz``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from chaplygin.numerics import load_model_code
from chaplygin.numerics.periodic_orbits import bm20_point, bm20_state, detect_period
from chaplygin.numerics.reversibility import stroboscopic_samples
from matplotlib.figure import Figure

D_RANGE, OMEGA_RANGE = (4.37, 4.39), (1.060, 1.075)


def main(n_d: int = 11, n_omega: int = 11, omega_range: tuple[float, float] = OMEGA_RANGE) -> None:
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    start = bm20_state(np.array([0.5, 1.0, 1.0]), 3.0)
    ds, omegas = np.linspace(*D_RANGE, n_d), np.linspace(*omega_range, n_omega)
    periods = np.zeros((n_omega, n_d), dtype=int)
    for i, omega in enumerate(omegas):
        for j, d in enumerate(ds):
            params = [4, 3, 2, d, 0, 2, -6, -3, -9, omega]
            states = stroboscopic_samples(code, params, start, 128, transient=6000, rtol=1e-9)
            points = np.array([bm20_point(y) for y in states])
            periods[i, j] = detect_period(points, 64, 1e-4, angles=(1, 2)) or 0
            print(f"d = {d:.4f}, Omega = {omega:.5f}: period {periods[i, j]}", flush=True)
    out = Path(__file__).resolve().parent / "figures" / "dynamics"
    out.mkdir(parents=True, exist_ok=True)
    np.savez(out / "bm20-chart.npz", d=ds, Omega=omegas, period=periods)
    fig = Figure(figsize=(6.5, 5), layout="constrained")
    ax = fig.subplots()
    mesh = ax.pcolormesh(ds, omegas, periods, cmap="tab20", vmin=0, vmax=20, shading="nearest")
    for i, omega in enumerate(omegas):
        for j, d in enumerate(ds):
            ax.text(d, omega, str(periods[i, j]), ha="center", va="center", fontsize=6)
    fig.colorbar(mesh, ax=ax, label="period (0: none <= 64)")
    ax.set_xlabel("d")
    ax.set_ylabel("Omega")
    ax.set_title(
        "Periods of the stroboscopic map (BM20 Fig. 5 body, start z=0.5, l=g=1)", fontsize=9
    )
    fig.savefig(out / "bm20-chart.png", dpi=110)


if __name__ == "__main__":
    sizes = [int(a) for a in sys.argv[1:3]]
    omega_range = tuple(float(a) for a in sys.argv[3:5]) or OMEGA_RANGE
    main(*sizes, omega_range=omega_range)
