"""The figures of a scene's trajectory outputs: the contact point's trace in the plane and on the
ball, time series of quantities, and the drift of the integrals. Each returns a
:class:`matplotlib.figure.Figure` (no backend is selected)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ...derive.errors import UserInputError
from ..figure_style import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "contact_trace_figure",
    "sphere_trace_figure",
    "body_trace_figure",
    "series_figure",
    "drift_figure",
]


def contact_trace_figure(
    x: np.ndarray, y: np.ndarray, title: str = "", aspect: str = "equal"
) -> Figure:
    """The contact point's trace ``(x, y)`` in the plane (K01 Figs. 3, 4, 6, 7).

    Parameters
    ----------
    x, y : ndarray
        Coordinates along the space-fixed ``alpha``, ``beta``.
    title : str
    aspect : {"equal", "auto"}
        ``equal``: one scale for both axes (the trace's true shape); ``auto``: each axis
        spans the picture, so that a small oscillation about a long drift (K01 Fig. 3) is
        seen; the axis labels then say that the scales differ.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if aspect not in ("equal", "auto"):
        raise UserInputError(f"aspect = {aspect!r}: 'equal' or 'auto'")
    fig = new_figure(figsize=(6, 6) if aspect == "equal" else (9, 4.5))
    ax = fig.subplots()
    ax.plot(x, y, lw=0.6)
    ax.plot([x[0]], [y[0]], "o", color="tab:green", ms=4, label="start")
    ax.plot([x[-1]], [y[-1]], "s", color="tab:red", ms=4, label="end")
    scales = ""
    if aspect == "equal":
        ax.set_aspect("equal", adjustable="datalim")
    else:
        scales = " (x and y to different scales)"
    ax.set_xlabel("x (along alpha)" + scales)
    ax.set_ylabel("y (along beta)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _trace_on_sphere(points: np.ndarray, radius: float | None, axes: tuple, title: str,
                     ends: bool) -> Figure:  # fmt: skip
    """A 3-D trace, over a sphere's wireframe when ``radius`` is given."""
    fig = new_figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    if radius is not None:
        u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 40), np.linspace(0, np.pi, 20))
        R = float(radius)
        ax.plot_wireframe(R * np.cos(u) * np.sin(v), R * np.sin(u) * np.sin(v), R * np.cos(v),
                          color="0.85", lw=0.4)  # fmt: skip
    p = np.asarray(points, float)
    ax.plot(p[0], p[1], p[2], lw=0.8)
    if ends:
        ax.plot([p[0, 0]], [p[1, 0]], [p[2, 0]], "o", color="tab:green", ms=4, label="start")
        ax.plot([p[0, -1]], [p[1, -1]], [p[2, -1]], "s", color="tab:red", ms=4, label="end")
        ax.legend(fontsize=7)
    ax.set_xlabel(axes[0])
    ax.set_ylabel(axes[1])
    ax.set_zlabel(axes[2])
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(title, fontsize=9)
    return fig


def sphere_trace_figure(points: np.ndarray, radius: float, title: str = "") -> Figure:
    """The contact point's trace on a fixed sphere (its centre at the origin), in the fixed
    frame ``alpha, beta, zeta``, over the sphere's wireframe.

    Parameters
    ----------
    points : ndarray, shape (3, n)
        The contact point in the fixed frame.
    radius : float
        The sphere's radius.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    return _trace_on_sphere(points, radius, ("alpha", "beta", "zeta"), title, ends=True)


def body_trace_figure(points: np.ndarray, b: float | None = None, title: str = "") -> Figure:
    """The contact point on the body's surface in the body frame (K01 Fig. 2b).

    Parameters
    ----------
    points : ndarray, shape (3, n)
        The contact point in body axes: ``-b gamma`` on a ball, ``r`` (from the centre of
        mass) on a convex body.
    b : float, optional
        The ball's radius: its sphere is drawn as a wireframe (none for a convex body).
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    return _trace_on_sphere(points, b, ("e1", "e2", "e3"), title, ends=False)


def series_figure(t: np.ndarray, series: Mapping[str, np.ndarray], title: str = "") -> Figure:
    """Time series of named quantities on one axis (BM20 Fig. 3: ``I_i(t)``).

    Parameters
    ----------
    t : ndarray
    series : mapping of str to ndarray
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = new_figure(figsize=(8, 4))
    ax = fig.subplots()
    for name, values in series.items():
        ax.plot(t, values, lw=0.9, label=name)
    ax.set_xlabel("t")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def drift_figure(t: np.ndarray, change: Mapping[str, np.ndarray], title: str = "") -> Figure:
    """Change of the first integrals over time, log scale (zeros drawn at the floor).

    Parameters
    ----------
    t : ndarray
    change : mapping of str to ndarray
        ``|F(t) - F(0)|`` (relative where ``F(0)`` is not ~0), per integral.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = new_figure(figsize=(8, 4))
    ax = fig.subplots()
    floor = 1e-18
    for name, values in change.items():
        ax.semilogy(t, np.maximum(np.asarray(values, float), floor), lw=0.8, label=name)
    ax.set_xlabel("t")
    ax.set_ylabel("|F(t) - F(0)| (relative)")
    ax.set_title(f"drift of the integrals: {title}", fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
