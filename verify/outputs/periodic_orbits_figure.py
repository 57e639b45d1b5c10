"""The figure of the ``periodic_orbits`` output's continuation: the Floquet multipliers along
the branches (the stroboscopic map's, :mod:`.periodic_orbits`, and a flow's,
:mod:`.periodic_orbits_flow`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["multipliers_figure"]


def multipliers_figure(
    parameter: np.ndarray,
    period: np.ndarray,
    multipliers: np.ndarray,
    events: list,
    name: str,
) -> Figure:
    """|multipliers| and their arguments along the branches, with the events marked.

    Parameters
    ----------
    parameter : ndarray, shape (n,)
    period : ndarray, shape (n,)
        Period of the branch each point belongs to.
    multipliers : ndarray, shape (n, dim)
    events : list of BifurcationEvent
    name : str
        The parameter's name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 6.4), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    order = np.argsort(parameter, kind="stable")
    colours = {"period-doubling": "C3", "saddle-node": "C2", "neimark-sacker": "C4"}
    for k in np.unique(period):
        sel = order[period[order] == k]
        for j in range(multipliers.shape[1]):
            top.plot(
                parameter[sel],
                np.abs(multipliers[sel, j]),
                ".",
                ms=2.5,
                label=f"period {k}" if j == 0 else None,
                color=f"C{int(np.log2(k)) % 10}",
            )
            bottom.plot(
                parameter[sel],
                np.angle(multipliers[sel, j]),
                ".",
                ms=2.5,
                color=f"C{int(np.log2(k)) % 10}",
            )
    top.axhline(1.0, color="0.5", lw=0.8)
    for e in events:
        for ax in (top, bottom):
            ax.axvline(e.parameter, color=colours.get(e.kind, "k"), lw=0.8, ls="--")
        top.annotate(
            f"{e.kind}\n{e.parameter:.7g}",
            (e.parameter, top.get_ylim()[1]),
            fontsize=7,
            rotation=90,
            va="top",
            ha="right",
        )
    top.set_ylabel("|multiplier|")
    bottom.set_ylabel("arg multiplier (rad)")
    bottom.set_xlabel(name)
    top.legend(fontsize=8, loc="lower left")
    top.set_title("Floquet multipliers of the periodic orbit along its branch")
    return fig
