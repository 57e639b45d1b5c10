"""Figures of K01 §3.3: Delta(mu) (Fig. 5) and contact-point traces near the separatrix
(Figs. 4, 6), drawn with matplotlib's Agg backend.

References
----------
K01-3.7, K01-Fig4, K01-Fig6 (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import mpmath
import numpy as np

from .separatrix import delta_closed_form, delta_quadrature, mu_of, separatrix_quantities

__all__ = ["plot_delta_of_mu", "plot_traces", "near_separatrix_state", "write_figures"]


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_delta_of_mu(path: str | Path, b: float = 1.0, mu_max: float = 6.0) -> Path:
    """K01 Fig. 5: ``Delta(mu) = pi b/ch(pi mu/2)`` with quadrature points and Fig. 4's values.

    Returns the path written.
    """
    plt = _pyplot()
    mus = np.linspace(0.0, mu_max, 400)
    closed = [float(delta_closed_form(m, b, 20)) for m in mus]
    pts = np.linspace(0.25, mu_max, 12)
    quad = [float(delta_quadrature(m, b, 15)) for m in pts]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, log in zip(axes, (False, True), strict=True):
        ax.plot(mus, closed, "-", label=r"closed form $\pi b/\cosh(\pi\mu/2)$")
        ax.plot(pts, quad, "o", mfc="none", label="quadrature of (3.7)")
        for I, printed in (((1, 1.5, 2), 0.002858), ((1, 3, 5), 0.411829)):
            mu = float(mu_of(I, 1))
            ax.plot([mu], [printed], "x", ms=9, color="C3")
            ax.annotate(
                f"Fig. 4: I={I}",
                (mu, printed),
                textcoords="offset points",
                xytext=(5, 5),
                fontsize=8,
            )
        ax.set_xlabel(r"$\mu = \xi = \kappa/\lambda = 1/(J_2\sqrt{a_{21}a_{32}})$")
        ax.set_ylabel(r"$\Delta$" + (" (log scale)" if log else ""))
        if log:
            ax.set_yscale("log")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"Displacement of the contact point per tumble (K01 Fig. 5), b = {b:g}")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def near_separatrix_state(I: Sequence, D: float, h: float, C: float = 1.0) -> np.ndarray:
    """A state on ``M = C gamma`` with energy ``h`` in ``[C^2/(2 I3), C^2/(2 I1)]``.

    ``gamma = (cos psi, 0, sin psi)`` with ``(gamma, A gamma) = 1/(D + C^2/(2h))``
    (K01-3.3seg), ``alpha = e2``, ``beta = gamma x alpha``; ``x = y = 0``.
    """
    J1, _, J3 = (float(v) + D for v in I)
    g = 1.0 / (D + C**2 / (2 * h))
    c2 = (g - 1 / J3) / (1 / J1 - 1 / J3)
    if not 0 <= c2 <= 1:
        raise ValueError(f"h = {h} is not on the segment n = C^2")
    gamma = np.array([np.sqrt(c2), 0.0, np.sqrt(1 - c2)])
    alpha = np.array([0.0, 1.0, 0.0])
    beta = np.cross(gamma, alpha)
    return np.concatenate([C * gamma, gamma, alpha, beta, [0.0, 0.0]])


def _separatrix_trace(I, D, b, C=1.0, n=2001):
    """``x(t), y(t)`` on the separatrix: cumulative integrals of K01-3.5 (nu = -b lam)."""
    from scipy.integrate import cumulative_simpson

    Q = separatrix_quantities(I, D, C)
    lam, kap = float(Q["lam"]), float(Q["kap"])
    s = np.linspace(-25, 25, n)  # s = lam t
    nu = -b * lam
    xr = nu * np.cos(kap / lam * s) / np.cosh(s) / lam
    yr = nu * np.sin(kap / lam * s) / np.cosh(s) / lam
    return cumulative_simpson(xr, x=s, initial=0), cumulative_simpson(yr, x=s, initial=0)


def plot_traces(
    path: str | Path,
    inertias: Sequence = ((1, 3, 5), (1, 1.5, 2)),
    D: float = 1.0,
    b: float = 1.0,
    C: float = 1.0,
    offsets: Sequence[float] = (-1e-3, 1e-3),
    t_end: float = 120.0,
) -> Path:
    """K01 Figs. 4 and 6: contact-point traces on and near the separatrix.

    Left: the trace along the separatrix itself (the displacement ``Delta``, K01 Fig. 4).
    Right: traces of the full equations (DOP853, compiled right-hand side) on ``M = C gamma``
    at ``h = h2 (1 + offset)`` for the first inertia (K01 Fig. 6 (d)-(e)): a spiral
    whose centres are displaced by about ``Delta`` per tumble.
    """
    from .integrate import integrate

    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 5))
    ax = axes[0]
    for I in inertias:
        x, y = _separatrix_trace(I, D, b, C)
        mu = float(mu_of(I, D))
        d = float(delta_closed_form(mu, b, 15))
        ax.plot(x, y, label=f"I = {tuple(I)}, mu = {mu:.4f}, Delta = {d:.6f}")
        ax.plot([x[0], x[-1]], [y[0], y[-1]], "k.", ms=4)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (along alpha)")
    ax.set_ylabel("y (along beta)")
    ax.set_title("on the separatrix, h = h2 (K01 Fig. 4)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[1]
    I = inertias[0]
    h2 = C**2 / (2 * I[1])
    for off in offsets:
        y0 = near_separatrix_state(I, D, h2 * (1 + off), C)
        r = integrate(
            "chaplygin_ball",
            list(y0),
            (0.0, t_end),
            params=list(I) + [D, b],
            effects=("contact_point",),
            rtol=1e-11,
            atol=1e-12,
            t_eval=np.linspace(0, t_end, 6000),
        )
        names = list(r.state_names)
        x, y = r.y[names.index("x")], r.y[names.index("y")]
        ax.plot(x, y, lw=0.8, label=f"h = h2 (1 {off:+.0e}) = {h2 * (1 + off):.6f}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(f"near the separatrix, I = {tuple(I)}, t <= {t_end:g} (K01 Fig. 6)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.suptitle(f"contact-point traces on M = C gamma, D = {D:g}, b = {b:g}, C = {C:g}")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_figures(directory: str | Path, I=(1, 3, 5), D: float = 1.0, b: float = 1.0) -> list[Path]:
    """Write ``delta_of_mu.png`` and ``separatrix_traces.png`` into ``directory``."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    with mpmath.workdps(20):
        return [
            plot_delta_of_mu(out / "delta_of_mu.png", b),
            plot_traces(out / "separatrix_traces.png", (tuple(I), (1, 1.5, 2)), D, b),
        ]
