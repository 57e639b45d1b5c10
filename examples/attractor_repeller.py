"""The attractor-repeller pair of BM20 Fig. 5 (claim BM20-3.3pair), as a picture.

Run from the repository root::

    python examples/attractor_repeller.py

Samples the Fig. 5 attractor A of the stroboscopic map, a repeller (the attractor of the
inverse map, from an unrelated start) and the image R1(A) of A under BM20's involution
(3.3) ``(M, gamma) -> (-M, gamma)``, in BM20's coordinates (l, z) (BM20-3.7); writes
``examples/figures/dynamics/bm20-fig5-pair.png`` and prints the distances of the claim, and
the same distances for ``J_off = 0.3`` and ``-0.5``, where the involutions do not exist, with
the mean of ``log|det DP|`` on each attractor (the sum of its Lyapunov exponents per
iteration; BM20's three exponents sum to -0.037 for ``J_off = 0``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from chaplygin.verify.claims.bm20 import _FIG5, _pair
from matplotlib.figure import Figure


def main() -> None:
    r = _pair(0.0)
    out = Path(__file__).resolve().parent / "figures" / "dynamics"
    out.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(11, 3.8), layout="constrained")
    axes = fig.subplots(1, 3, sharey=True)
    R1 = np.array([-1.0, -1, -1, 1, 1, 1])
    sets = (
        ("attractor A (forward map)", r.attractor),
        ("R1(A), R1: (M, gamma) -> (-M, gamma)", R1 * r.attractor),
        ("repeller (inverse map, other start)", r.repeller),
    )
    for ax, (title, pts) in zip(axes, sets, strict=True):
        M = pts[:, :3]  # M/G
        ax.plot(np.arctan2(M[:, 0], M[:, 1]), M[:, 2], ",", color="k", alpha=0.6)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("l")
        ax.set_xlim(-np.pi, np.pi)
    axes[0].set_ylabel("z = M3/G")
    fig.suptitle(
        "BM20 Fig. 5 (Omega = 1.07, d = 4.385, J = 0): median (0.5-quantile) Hausdorff distances "
        f"d(R1 A, rep) = {r.image_distance['R1 (M, gamma) -> (-M, gamma)']:.3f}, "
        f"d(A, A') = {r.sampling_distance:.3f}, d(A, rep) = {r.attractor_distance:.3f}",
        fontsize=9,
    )
    path = out / "bm20-fig5-pair.png"
    fig.savefig(path, dpi=110)
    print(path)
    # where the involutions do not exist (J_off != 0, BM20-3.4J): the same distances
    for J_off in (0.0, 0.3, -0.5):
        q = _pair(J_off)
        images = ", ".join(
            f"d({k.split()[0]} A, rep) = {v:.3f}" for k, v in q.image_distance.items()
        )
        mean, err = mean_log_det(J_off, q.attractor[::8])
        print(
            f"J_off = {J_off:+.1f}: d(A, A') = {q.sampling_distance:.3f}, "
            f"d(A, rep) = {q.attractor_distance:.3f}, {images}; mean log|det DP| on A = "
            f"{mean:.4f} +- {err:.4f} per iteration"
        )


def mean_log_det(J_off: float, points: np.ndarray) -> tuple[float, float]:
    """Mean of log|det DP| (the phase-volume change per iteration; along an orbit it is the
    sum of the Lyapunov exponents) at points of the attractor (M/G, gamma), with its
    standard error."""
    from chaplygin.numerics.ball.bm20_map import bm20_map_with_jacobian, bm20_point

    params = list(_FIG5)
    params[4] = J_off
    smap = bm20_map_with_jacobian(params, 3.0, rtol=1e-9)
    logs = []
    for y in points:
        x = bm20_point(np.concatenate([3.0 * y[:3], y[3:]]))
        logs.append(np.log(abs(np.linalg.det(smap.df(x, params[9])[1]))))
    return float(np.mean(logs)), float(np.std(logs) / np.sqrt(len(logs)))


if __name__ == "__main__":
    main()
