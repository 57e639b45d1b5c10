"""The turning of the contact trace per period on M || gamma and M + K || gamma (K01 §3.3, §4).

Run from the repository root::

    python examples/k01_turning.py

On these sets ``gamma`` is periodic and the trace over each period is the previous one turned
by ``psi``; it is bounded unless ``psi = 0 mod 2 pi``. ``Theta``, the turning of the trace's
tangent over one period, is a continuous lift of ``psi`` (numerics/ball/trace_geometry.py), so the
critical energies (unbounded traces, K01 Fig. 6f) are where ``Theta/2 pi`` is an integer.
Left: the ball, I = (1, 3, 5), C = D = 1; right: the ball with a gyroscope, K = (0.1, 0.1,
0.2) (K01 Fig. 7's), whose segment ``M + K = C gamma`` has five families of orbits (about
two minima, two maxima, and around the figure-eight of the two saddles); the orbits of each
family start on a line of steepest ascent or descent of the energy. The critical energies
next to the saddles (``h2`` for the ball) are infinitely many; the script prints the first
ones of each family (Brent on ``Theta - 2 pi m``) and writes
``examples/figures/k01-turning.png``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from chaplygin.numerics.ball.gyrostat_segment import (
    gradient_line,
    segment_equilibria,
    turning_critical_energy,
)
from chaplygin.numerics.ball.trace_geometry import trace_period
from matplotlib.figure import Figure

I, D, C = (1.0, 3.0, 5.0), 1.0, 1.0
K = (0.1, 0.1, 0.2)
FIG6 = {"a": 0.4993, "b": 0.1002, "c": 0.1674, "d": 0.16667, "f": 0.180278}
FIG7 = {"a": 0.1366, "b": 0.1415, "c": 0.1533}


def _grid(lo: float, hi: float, points: int, ends: str) -> np.ndarray:
    """``points`` energies in (lo, hi), dense (logarithmically) towards the saddle ends."""
    u = np.linspace(0, 1, points)
    log = 10 ** (-6 + 6 * u) * (1 - 1e-3)  # 1e-6 .. 0.999 of the range
    if ends == "lo":
        return lo + (hi - lo) * log
    if ends == "hi":
        return hi - (hi - lo) * log[::-1]
    return np.unique(np.r_[lo + (hi - lo) * log / 2, hi - (hi - lo) * log[::-1] / 2])


def _critical(h: np.ndarray, turns: np.ndarray, theta, count: int) -> list[tuple[int, float]]:
    """The first ``count`` energies where ``Theta/2 pi`` meets an integer, from the far end
    of the family towards the saddle (Brent on each sign change)."""
    out = []
    for k in range(len(h) - 1):
        a, b = turns[k], turns[k + 1]
        for m in range(math.floor(min(a, b)) + 1, math.floor(max(a, b)) + 1):
            out.append((m, theta(h[k], h[k + 1], m)))
    out.sort(key=lambda e: e[0])
    return out[:count]


def main(points: int = 40, count: int = 3, out: Path | None = None) -> dict:
    """Compute, print and draw; returns the critical energies found per family."""
    found: dict[str, list] = {}
    fig = Figure(figsize=(13, 5))
    ax_ball, ax_gyro = fig.subplots(1, 2)
    # the ball
    h3, h2, h1 = 0.1, 1 / 6, 0.5
    for name, (lo, hi) in {"h3..h2": (h3, h2), "h2..h1": (h2, h1)}.items():
        h = _grid(lo, hi, points, "both")
        turns = np.array([trace_period(I, D, v, C).turning / (2 * np.pi) for v in h])
        ax_ball.semilogx(np.abs(h - h2), turns, ".-", ms=3, label=f"h in ({name})")
        found[f"ball {name}"] = _critical(
            h, turns, lambda a, b, m: turning_critical_energy(None, I, D, None, C, (a, b), m), count
        )
    for key, v in FIG6.items():
        ax_ball.axvline(abs(v - h2), color="0.6", lw=0.6)
        ax_ball.text(abs(v - h2), ax_ball.get_ylim()[1], f"6{key}", fontsize=7, va="top")
    ax_ball.set_xlabel("|h - h2|  (h2 = 1/6; h3 = 0.1, h1 = 0.5)")
    ax_ball.set_ylabel("Theta/2 pi: turning of the trace per period of gamma")
    ax_ball.set_title("ball, M || gamma, I = (1, 3, 5), C = D = 1", fontsize=9)
    # the gyrostat
    eq = segment_equilibria(I, D, K, C)
    hs = [e["h"] for e in eq]
    up = gradient_line(I, D, K, C, eq[0]["gamma"], ascending=True)
    up_local = gradient_line(I, D, K, C, eq[1]["gamma"], ascending=True)
    down = gradient_line(I, D, K, C, eq[-1]["gamma"], ascending=False)
    families = {
        "about the least minimum": (up, hs[0], hs[2], "hi"),
        "about the other minimum": (up_local, hs[1], hs[2], "hi"),
        "around both saddles' loops": (up, hs[2], hs[3], "both"),
        "about the lower maximum": (up, hs[3], hs[4], "lo"),
        "about the upper maximum": (down, hs[3], hs[5], "lo"),
    }
    for name, (line, lo, hi, ends) in families.items():
        h = _grid(lo, hi, points, ends)

        def theta(a, b, m, line=line):
            return turning_critical_energy(line["at"], I, D, K, C, (a, b), m)

        turns = np.array(
            [trace_period(I, D, None, C, K, line["at"](v)).turning / (2 * np.pi) for v in h]
        )
        ax_gyro.plot(h, turns, ".-", ms=3, label=f"{name}, h in ({lo:.6f}, {hi:.6f})")
        found[f"gyrostat {name}"] = _critical(h, turns, theta, count)
    for e in eq:
        style = "--" if e["kind"] == "saddle" else ":"
        ax_gyro.axvline(e["h"], color="0.5", ls=style, lw=0.7)
    for key, v in FIG7.items():
        ax_gyro.axvline(v, color="tab:red", lw=0.6)
        ax_gyro.text(v, 1, f"7{key}", fontsize=7, color="tab:red")
    ax_gyro.set_ylim(0, 12)
    ax_gyro.set_xlabel("h on M + K = C gamma (dashed: saddles, dotted: extrema)")
    ax_gyro.set_title("ball with gyroscope, K = (0.1, 0.1, 0.2), M + K || gamma", fontsize=9)
    for ax in (ax_ball, ax_gyro):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        for m in range(1, 12):
            ax.axhline(m, color="k", lw=0.3)
    fig.suptitle(
        "critical energies (unbounded trace) where Theta/2 pi is an integer; they accumulate at "
        "every saddle",
        fontsize=10,
    )
    fig.tight_layout()
    out = out or Path(__file__).resolve().parent / "figures" / "k01-turning.png"
    fig.savefig(out, dpi=100)
    for name, roots in found.items():
        text = ", ".join(f"m = {m}: {h:.11f}" for m, h in roots) or "none"
        print(f"{name}: {text}")
    print(f"wrote {out}")
    return found


if __name__ == "__main__":
    main()
