"""The ``diagram`` output of a scene for every model that has an energy diagram.

* ``chaplygin_ball`` (with or without ``contact_point``): K01's (n, h) diagram at
  ``C = (M, gamma)`` (:func:`chaplygin.verify.plots.scene_diagram_figure`, K01 Figs. 2, 3);
* ``chaplygin_ball`` with ``gyrostat`` (and optionally ``contact_point``): the (n, h) diagram at
  ``C = (M + K, gamma)`` of :mod:`chaplygin.numerics.gyrostat_diagram` (the steady rotations
  ``J omega + K = lam omega``, the segment ``M + K || gamma`` and the region of motion; the
  setting of K01 Fig. 7).

Any other model has no diagram here (its energy is not conserved, or no bifurcation code
exists for it): :func:`diagram_problem` says so and lists those that have one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["DIAGRAMS", "diagram_kind", "diagram_problem", "gyrostat_diagram_figure"]

#: Effect sets (besides contact_point, which leaves the energy diagram unchanged) that have
#: a diagram: system -> {frozenset of effects: kind}.
DIAGRAMS = {
    "chaplygin_ball": {frozenset(): "ball", frozenset({"gyrostat"}): "gyrostat"},
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
        f"{s} with effects [{', '.join(sorted(e)) or 'none'}] (contact_point allowed)"
        for s, kinds in DIAGRAMS.items()
        for e in kinds
    )
    return f"no energy diagram exists for {name}; diagrams exist for: {have}"


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

    from ..numerics.gyrostat_diagram import (
        level_samples,
        parallel_segment,
        steady_rotation_branches,
    )
    from .plots import COLORS

    I = tuple(float(v) for v in I)
    K = tuple(float(v) for v in K)
    D, C, n, h = float(D), float(C), float(n), float(h)
    n_max = max(3.0 * C**2, 1.1 * n, C**2 + 1.0)
    fig = Figure(figsize=(7, 5))
    ax = fig.subplots()
    cloud = level_samples(I, D, K, C, n_max, samples)
    ax.plot(cloud["n"], cloud["h"], ".", color="0.6", ms=2, label="random states on the level C")
    labelled = set()
    for branch in steady_rotation_branches(I, D, K, C, n_max, samples=20000):
        axis = branch["axis"]
        label = None
        if axis not in labelled:
            label = f"steady rotations, lam near J{axis + 1}"
            labelled.add(axis)
        ax.plot(branch["n"], branch["h"], "-", color=COLORS[axis], lw=1.4, label=label)
    lo, hi = parallel_segment(I, D, K, C)
    ax.plot([C**2, C**2], [lo, hi], "-", color=COLORS[3], lw=2.5, label="n = C^2 (M + K || gamma)")
    ax.plot([n], [h], "*", color="k", ms=12, label=f"scene: n = {n:.6g}, h = {h:.6g}")
    ax.set_xlim(C**2 - 0.05 * (n_max - C**2), n_max)
    ax.set_xlabel("n = (M + K, M + K)")
    ax.set_ylabel("h = (M, omega)/2")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax.set_title(
        f"{title}\nball with gyrostat: I = {I}, D = {D:g}, K = {K}, C = (M + K, gamma) = {C:.6g}"
        "\n(steady rotations J omega + K = lam omega; their stability is not computed)",
        fontsize=8,
    )
    fig.tight_layout()
    return fig
