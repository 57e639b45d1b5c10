"""Pictures of sweep stores (``chaplygin sweep --plot``): a chart of regimes, a curve over one
axis, zeros found by the refinement.

Each function takes the store's xarray Dataset and returns a matplotlib Figure.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .output_folder import current_umask

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "sweep_figure",
    "period_chart_figure",
    "curve_figure",
    "status_figure",
    "save_figure",
]


def _title(ds: Any) -> str:
    """The store's title as matplotlib shows it literally (no mathtext)."""
    from .plots import literal_text

    return literal_text(str(ds.attrs.get("title", "")))


def period_chart_figure(ds: Any) -> Figure:
    """The chart of dynamical regimes: one colour per period 1..max, chaos (0) black, points
    not computed white (as BM20 Fig. 6).

    Parameters
    ----------
    ds : xarray.Dataset
        A store with ``period`` over two axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.figure import Figure

    period = np.asarray(ds["period"].values, dtype=float)
    y_name, x_name = ds["period"].dims
    top = max(int(np.nanmax(period)) if np.isfinite(period).any() else 1, 14)
    colours = ["black"] + [
        tuple(c) for c in __import__("matplotlib").colormaps["tab20"](np.arange(top) % 20)
    ]
    cmap = ListedColormap(colours)
    cmap.set_under("white")
    norm = BoundaryNorm(np.arange(-0.5, top + 1.5), cmap.N)
    fig = Figure(figsize=(7, 5))
    ax = fig.add_subplot()
    mesh = ax.pcolormesh(
        ds[x_name].values, ds[y_name].values, period, cmap=cmap, norm=norm, shading="nearest"
    )
    bar = fig.colorbar(mesh, ax=ax, ticks=range(top + 1))
    bar.set_label("period of the map's attractor (0: none up to max_period)")
    ax.set_xlabel(x_name)
    ax.set_ylabel(y_name)
    ax.set_title(_title(ds), fontsize=9)
    return fig


def curve_figure(ds: Any, names: list[str]) -> Figure:
    """Numbers over a single axis, with the refined zeros marked; a variable with an extra
    dimension (``final_state``, ``drift``) draws one line per component.

    Parameters
    ----------
    ds : xarray.Dataset
    names : list of str
        Variables to draw (over the grid's single dimension, with at most one more).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    dim = ds[names[0]].dims[0]
    x = ds[dim].values
    fig = Figure(figsize=(7, 4))
    ax = fig.add_subplot()
    logy = False
    for name in names:
        var = ds[name]
        label = var.attrs.get("long_name", name)
        if var.ndim == 1:
            ax.plot(x, var.values, ".-", ms=3, label=label)
            continue
        extra = var.dims[1]
        for i, component in enumerate(ds[extra].values):
            ax.plot(x, var.values[:, i], ".-", ms=3, label=f"{name} {component}")
        values = np.asarray(var.values, dtype=float)
        logy = logy or (name == "drift" and bool((values[np.isfinite(values)] > 0).all()))
    if logy and len(names) == 1:
        ax.set_yscale("log")
    for z in json.loads(ds.attrs.get("refined", "[]")):
        ax.axvline(float(z), color="red", lw=0.6)
    if not logy:
        ax.axhline(0, color="grey", lw=0.4)
    ax.set_xlabel(dim)
    ax.legend(fontsize=7)
    ax.set_title(_title(ds), fontsize=9)
    return fig


def status_figure(ds: Any) -> Figure:
    """Where the points of a 2-D grid exist: status 0 (a state was found and reduced), 1 (the
    scene finds no state there: outside the region of motion), 2 (failed).

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

    y_name, x_name = ds["status"].dims
    fig = Figure(figsize=(6, 5))
    ax = fig.add_subplot()
    cmap = ListedColormap(["tab:green", "whitesmoke", "tab:red"])
    ax.pcolormesh(
        ds[x_name].values,
        ds[y_name].values,
        ds["status"].values,
        cmap=cmap,
        vmin=-0.5,
        vmax=2.5,
        shading="nearest",
    )
    ax.set_xlabel(x_name)
    ax.set_ylabel(y_name)
    ax.set_title(f"{_title(ds)}\ngreen: a state exists; grey: none", fontsize=9)
    return fig


def sweep_figure(ds: Any) -> Figure:
    """The picture a store calls for: the period chart, Delta over mu (log scale), the frame
    turn with its zeros, or the first numbers per point over the first axis.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    matplotlib.figure.Figure
    """
    if "period" in ds and ds["period"].ndim == 2:
        return period_chart_figure(ds)
    if "delta_measured" in ds:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(7, 4))
        ax = fig.add_subplot()
        mu = ds["mu"].values
        ax.semilogy(mu, ds["delta_closed_form"].values, "-", label="pi b/ch(pi mu/2) (K01-3.7)")
        ax.semilogy(mu, ds["delta_measured"].values, "o", ms=3, label="full equations")
        ax.set_xlabel("mu = kap/lam")
        ax.set_ylabel("Delta / b")
        ax.legend(fontsize=8)
        ax.set_title(_title(ds), fontsize=9)
        return fig
    status = ds["status"]
    if status.ndim >= 3:  # the first two axes, at the first value of the others
        first = {d: 0 for d in status.dims[:-2]}
        sliced = ds.isel(first)
        sliced.attrs = {
            **ds.attrs,
            "title": f"{ds.attrs.get('title', '')} ("
            + ", ".join(f"{d} = {ds[d].values[0]:g}" for d in first)
            + ")",
        }
        return status_figure(sliced)
    if status.ndim == 2:
        return status_figure(ds)
    grid = status.dims
    own = [n for n, v in ds.data_vars.items() if v.dims[: len(grid)] == grid]
    own = [n for n in own if n not in ("status", "computed", "chunk_digest")]
    scalars = [n for n in own if ds[n].ndim == 1]
    if "frame_turn_phi" in ds:
        scalars = ["frame_turn_phi"]
    if scalars:
        return curve_figure(ds, scalars[:3])
    if own:  # numbers with a dimension of their own only (final_state, drift): the first
        return curve_figure(ds, own[:1])
    return curve_figure(ds, ["status"])


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> None:
    """Save ``fig`` to ``path`` beside it first, then move it into place (a failed drawing
    leaves the file that was there).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : str or Path
        Its suffix (any case) chooses the format: ``.png``, ``.svg``, ``.pdf``.
    dpi : int
    """
    import os
    import tempfile

    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=dpi, format=path.suffix[1:].lower())
        os.chmod(tmp, 0o666 & ~current_umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
