"""The ``diagram`` output of a scene for every model that has an energy diagram.

* ``chaplygin_ball`` (with or without ``contact_point``): K01's (n, h) diagram at
  ``C = (M, gamma)`` (:func:`scene_diagram_figure`, K01 Figs. 2, 3);
* ``chaplygin_ball`` with ``gyrostat`` (and optionally ``contact_point``): the (n, h) diagram at
  ``C = (M + K, gamma)`` of :mod:`chaplygin.numerics.ball.gyrostat_diagram` (the steady rotations
  ``J omega + K = lam omega``, solid where their Floquet multipliers lie on the unit circle and
  dashed elsewhere, the segment ``M + K || gamma`` and the region of motion; the setting of
  K01 Fig. 7);
* ``spherical_support``: BKM12 Fig. 5's surfaces ``E'_i = E/C`` over the sphere of
  ``g = ((M, alpha), (M, beta), (M, gamma))/sqrt(C)``, ``C = (M, M)``
  (:func:`chaplygin.verify.plots.bifurcation_figure`), with the scene's ``g`` marked.

Any other model has no diagram here (its energy is not conserved, or no bifurcation code
exists for it): :func:`diagram_problem` says so and lists those that have one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "DIAGRAMS",
    "diagram_kind",
    "diagram_problem",
    "gyrostat_diagram_figure",
    "scene_diagram_figure",
    "support_diagram_figure",
]

#: Effect sets (besides contact_point, which leaves the energy diagram unchanged) that have
#: a diagram: system -> {frozenset of effects: kind}.
DIAGRAMS = {
    "chaplygin_ball": {frozenset(): "ball", frozenset({"gyrostat"}): "gyrostat"},
    "spherical_support": {frozenset(): "support"},
}


def diagram_kind(system: str, effects: Sequence[str]) -> str | None:
    """``"ball"``, ``"gyrostat"``, or None when the model has no diagram here.

    Parameters
    ----------
    system : str
    effects : sequence of str
        The model's effects.

    Returns
    -------
    str or None
    """
    return DIAGRAMS.get(system, {}).get(frozenset(effects) - {"contact_point"})


def diagram_problem(system: str, effects: Sequence[str], name: str) -> str | None:
    """Why a model has no diagram (None when it has one): the message lists those that do.

    Parameters
    ----------
    system : str
    effects : sequence of str
    name : str
        The model's variant name (for the message).

    Returns
    -------
    str or None
    """
    if diagram_kind(system, effects) is not None:
        return None
    have = "; ".join(
        f"{s} with effects [{', '.join(sorted(e)) or 'none'}]"
        + (" (contact_point allowed)" if s == "chaplygin_ball" else "")
        for s, kinds in DIAGRAMS.items()
        for e in kinds
    )
    return f"no energy diagram exists for {name}; diagrams exist for: {have}"


def support_diagram_figure(
    params: Sequence[float], g: Sequence[float], Ep: float, title: str = ""
) -> Figure:
    """BKM12 Fig. 5's diagram of the spherical support with the scene's point marked.

    Parameters
    ----------
    params : sequence of 6 floats
        ``(I1, I2, I3, D_iso, D_al, D_be)``.
    g : sequence of 3 floats
        ``((M, alpha), (M, beta), (M, gamma))/sqrt((M, M))`` of the scene's state.
    Ep : float
        ``E' = E/C = 2 h/(M, M)`` of the scene's state.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..plots import bifurcation_figure

    I = tuple(float(v) for v in params[:3])
    D_iso, D_al, D_be = (float(v) for v in params[3:6])
    fig, _ = bifurcation_figure(
        "bkm12-5", {"I": I, "D_iso": D_iso, "D_al": D_al, "D_be": D_be}, samples=60, seed=1
    )
    J = [v + D_iso for v in I]
    surfaces = [g[0] ** 2 / (Ji - D_al) + g[1] ** 2 / (Ji - D_be) + g[2] ** 2 / Ji for Ji in J]
    for ax in fig.axes[:4]:
        ax.plot([g[0]], [g[1]], "*", color="k", ms=12)
    fig.suptitle(
        f"{title}: BKM12 Fig. 5's surfaces E'_i at the scene's g = "
        f"({g[0]:.4g}, {g[1]:.4g}, {g[2]:.4g}) (star): E' = {Ep:.6g}, E'_i there = "
        + ", ".join(f"{v:.6g}" for v in surfaces),
        fontsize=9,
    )
    return fig


def gyrostat_diagram_figure(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    C: float,
    n: float,
    h: float,
    title: str = "",
    samples: int = 3000,
) -> Figure:
    """The (n, h) diagram of the ball with a gyrostat at ``C = (M + K, gamma)``, one point marked.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
    n, h : float
        The scene's ``(M + K, M + K)`` and energy.
    title : str
    samples : int
        Random states of the level drawn as dots (the region of motion).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    from ...numerics.ball.gyrostat_diagram import (
        branch_stability,
        level_samples,
        parallel_segment,
        steady_rotation_branches,
    )
    from ..figure_style import COLORS, stability_legend, stability_style

    I = tuple(float(v) for v in I)
    K = tuple(float(v) for v in K)
    D, C, n, h = float(D), float(C), float(n), float(h)
    n_max = max(3.0 * C**2, 1.1 * n, C**2 + 1.0)
    fig = Figure(figsize=(7, 5))
    ax = fig.subplots()
    cloud = level_samples(I, D, K, C, n_max, samples)
    ax.plot(cloud["n"], cloud["h"], ".", color="0.6", ms=2, label="random states on the level C")
    worst: dict[int, float] = {}
    for branch in steady_rotation_branches(I, D, K, C, n_max, samples=20000):
        axis = branch["axis"]
        for start, stop, stable, max_abs in branch_stability(I, D, K, C, branch):
            stop = min(stop + 1, len(branch["n"]))  # pieces meet at their common sample
            ax.plot(
                branch["n"][start:stop], branch["h"][start:stop], stability_style(stable),
                color=COLORS[axis], lw=1.4,
            )  # fmt: skip
            worst[axis] = max(worst.get(axis, 0.0), max_abs)
    for axis in sorted(worst):
        ax.plot(
            [], [], "-", color=COLORS[axis], lw=1.4,
            label=f"steady rotations, lam near J{axis + 1} (max|mu| = {worst[axis]:.3g})",
        )  # fmt: skip
    lo, hi = parallel_segment(I, D, K, C)
    ax.plot([C**2, C**2], [lo, hi], "-", color=COLORS[3], lw=2.5, label="n = C^2 (M + K || gamma)")
    ax.plot([n], [h], "*", color="k", ms=12, label=f"scene: n = {n:.6g}, h = {h:.6g}")
    ax.set_xlim(C**2 - 0.05 * (n_max - C**2), n_max)
    ax.set_xlabel("n = (M + K, M + K)")
    ax.set_ylabel("h = (M, omega)/2")
    ax.grid(alpha=0.3)
    handles, _ = ax.get_legend_handles_labels()
    ax.legend(handles=handles + stability_legend()[:2], fontsize=7, loc="best")
    ax.set_title(
        f"{title}\nball with gyrostat: I = {I}, D = {D:g}, K = {K}, C = (M + K, gamma) = {C:.6g}"
        "\n(steady rotations J omega + K = lam omega; stability by Floquet multipliers)",
        fontsize=8,
    )
    fig.tight_layout()
    return fig


def scene_diagram_figure(
    I: Sequence[float], D: float, C: float, n: float, h: float, title: str = "", samples: int = 30
) -> Figure:
    """K01's energy diagram in the (n, h) plane at ``C = (M, gamma)`` with one point marked.

    Parameters
    ----------
    I : sequence of 3 floats
    D, C : float
    n, h : float
        The scene's ``(M, M)`` and energy.
    title : str
    samples : int
        Integrated random states drawn as dots.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import numpy as np

    from ..figure_style import COLORS, new_figure
    from ..plots import draw_k01_diagram

    fig = new_figure(figsize=(7, 5))
    ax = fig.subplots()
    I = tuple(float(v) for v in I)
    draw_k01_diagram(ax, I, float(D), float(C), samples, 1)
    n_max = 3.0 if C == 0 else 3.0 * C**2  # where draw_k01_diagram stops
    if n > n_max:  # continue the branches to the scene's point (dotted)
        from ...numerics.ball.bifurcation import sigma

        ext = np.linspace(n_max, 1.1 * n, 50)
        for i in range(3):
            ax.plot(ext, sigma(i, ext, C, I, D) / 2, ":", color=COLORS[i])
    ax.plot([n], [h], "*", color="k", ms=12, label=f"scene: n = {n:.6g}, h = {h:.6g}")
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"{title}\nI = {tuple(I)}, D = {D:g}, C = {C:.6g}", fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
