"""Pictures of sweep stores (``chaplygin sweep --plot``): a chart of periods or of dynamical
regimes, a curve over one axis, zeros found by the refinement.

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
    "period_colours",
    "regime_chart_figure",
    "regime_codes",
    "regime_search_figure",
    "curve_figure",
    "status_figure",
    "save_figure",
]


def _title(ds: Any) -> str:
    """The store's title as matplotlib shows it literally (no mathtext)."""
    from .figure_style import literal_text

    return literal_text(str(ds.attrs.get("title", "")))


def period_colours(periods: Any) -> list:
    """One distinguishable colour per period, in the order given: the qualitative palettes
    tab10, tab20b and tab20c without their greys (45 colours), then evenly spaced hues; never
    black, white or grey (kept for the regimes without a period). No two periods share a
    colour however many there are (a colour map wrapped at its length would draw period 28
    in period 8's colour).

    Parameters
    ----------
    periods : sequence of int
        The periods present, each once.

    Returns
    -------
    list of RGBA tuples
    """
    import matplotlib

    cmaps = matplotlib.colormaps
    palette = [
        (*c[:3], 1.0)
        for name in ("tab10", "tab20b", "tab20c")
        for c in cmaps[name].colors
        if not c[0] == c[1] == c[2]  # tab10's grey, tab20c's four greys
    ]
    n = len(periods)
    if n > len(palette):
        hues = cmaps["hsv"](np.linspace(0, 1, n - len(palette), endpoint=False))
        palette += [tuple(c) for c in hues]
    return palette[:n]


def _category_mesh(
    ax: Any, fig: Any, x: Any, y: Any, codes: np.ndarray, labels: list, colours: list, title: str
) -> None:
    """Draw integer category codes 0..n-1 (NaN: white) with a colour bar naming each."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    cmap = ListedColormap(colours).with_extremes(bad="white")
    norm = BoundaryNorm(np.arange(-0.5, len(colours) + 0.5), cmap.N)
    mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(codes), cmap=cmap, norm=norm, shading="nearest")
    bar = fig.colorbar(mesh, ax=ax, ticks=range(len(colours)))
    bar.ax.set_yticklabels(labels, fontsize=7)
    ax.set_title(title, fontsize=9)


def period_chart_figure(ds: Any) -> Figure:
    """The chart of periods: one colour per period present (:func:`period_colours`), 0 (no
    period up to max_period) black, points not computed white; the colour bar names every
    period present.

    Parameters
    ----------
    ds : xarray.Dataset
        A store with ``period`` over two axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    period = np.asarray(ds["period"].values, dtype=float)
    y_name, x_name = ds["period"].dims
    present = sorted(int(v) for v in np.unique(period[np.isfinite(period) & (period > 0)]))
    labels = ["0: none up to max_period"] + [str(p) for p in present]
    colours = [(0.0, 0.0, 0.0, 1.0)] + period_colours(present)
    codes = np.full(period.shape, np.nan)
    codes[period == 0] = 0
    for k, p in enumerate(present, start=1):
        codes[period == p] = k
    fig = Figure(figsize=(7, 5))
    ax = fig.add_subplot()
    _category_mesh(
        ax, fig, ds[x_name].values, ds[y_name].values, codes, labels, colours,
        _title(ds),
    )  # fmt: skip
    ax.set_xlabel(x_name)
    ax.set_ylabel(y_name)
    return fig


#: Colours of the regimes without a period (:data:`chaplygin.numerics.ball.regimes.REGIMES`).
REGIME_COLOURS = {
    "quasi-periodic": (0.78, 0.78, 0.78, 1.0),
    "undecided": (1.0, 0.8, 0.8, 1.0),
    "chaotic": (0.0, 0.0, 0.0, 1.0),
    "contracting": (0.45, 0.45, 0.45, 1.0),
}


def regime_codes(regime: np.ndarray, period: np.ndarray) -> tuple[np.ndarray, list, list]:
    """Categories of a regime chart: each period present, then quasi-periodic, undecided,
    chaotic and contracting (only those present).

    Parameters
    ----------
    regime, period : ndarray
        The store's ``regime`` and ``period`` (same shape).

    Returns
    -------
    codes : ndarray of float
        Category index per point (NaN: not classified).
    labels : list of str
    colours : list of RGBA tuples
    """
    from ..numerics.ball.regimes import REGIMES

    regime = np.asarray(regime, dtype=float)
    period = np.asarray(period, dtype=float)
    periodic = regime == REGIMES["periodic"]
    present = sorted(int(v) for v in np.unique(period[periodic]))
    labels = [f"period {p}" for p in present]
    colours = period_colours(present)
    codes = np.full(regime.shape, np.nan)
    for k, p in enumerate(present):
        codes[periodic & (period == p)] = k
    for name, colour in REGIME_COLOURS.items():
        where = regime == REGIMES[name]
        if where.any():
            codes[where] = len(labels)
            labels.append(name)
            colours.append(colour)
    return codes, labels, colours


def _mark(ax: Any, x: Any, y: Any, where: np.ndarray, colour: str) -> None:
    """Draw the points where ``where`` holds in ``colour`` on white."""
    from matplotlib.colors import ListedColormap

    cmap = ListedColormap(["white", colour])
    ax.pcolormesh(x, y, where.astype(float), cmap=cmap, vmin=0, vmax=1, shading="nearest")


def regime_chart_figure(ds: Any) -> Figure:
    """The chart of dynamical regimes: per carry direction, one colour per period present,
    light grey quasi-periodic, pink undecided, dark grey contracting and black chaotic; below,
    the largest Lyapunov exponent per map iteration; with both directions, where they differ
    (coexisting attractors).

    Parameters
    ----------
    ds : xarray.Dataset
        A store with ``regime`` and ``period`` over two axes, or three with the leading
        dimension ``carry``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    dims = ds["regime"].dims
    both = dims[0] == "carry"
    y_name, x_name = dims[-2:]
    x, y = ds[x_name].values, ds[y_name].values
    regime = np.asarray(ds["regime"].values, dtype=float)
    period = np.asarray(ds["period"].values, dtype=float)
    regime[regime < 0] = np.nan
    codes, labels, colours = regime_codes(regime, period)
    lam = np.asarray(ds["lyapunov_max_per_iteration"].values, dtype=float)
    panels = [str(v) for v in ds["carry"].values] if both else [None]
    cols = len(panels) + (1 if both else 0)
    fig = Figure(figsize=(6.2 * cols, 9.5), layout="constrained")
    axes = np.asarray(fig.subplots(2, cols, squeeze=False))
    finite = lam[np.isfinite(lam)]
    top = float(np.max(np.abs(finite))) if finite.size else 1.0
    for j, name in enumerate(panels):
        sel = (j,) if both else ()
        _category_mesh(
            axes[0, j], fig, x, y, codes[sel], labels, colours,
            "regime" + (f", starts carried {name}" if name else ""),
        )  # fmt: skip
        mesh = axes[1, j].pcolormesh(
            x, y, lam[sel], cmap="RdBu_r", vmin=-top, vmax=top, shading="nearest"
        )
        fig.colorbar(mesh, ax=axes[1, j], label="largest Lyapunov exponent per map iteration")
        axes[1, j].set_title(
            "largest Lyapunov exponent (white: periodic, not measured)", fontsize=9
        )
    if both:
        differ = (codes[0] != codes[1]) & np.isfinite(codes[0]) & np.isfinite(codes[1])
        copy = np.asarray(ds["symmetric_copy"].values, dtype=float)
        mirror = (copy[0] != copy[1]) & (np.minimum(copy[0], copy[1]) >= 0) & ~differ
        for ax, where, colour, text in (
            (axes[0, -1], differ, "tab:red", "red: the directions differ in regime or period"),
            (axes[1, -1], mirror, "tab:blue", "blue: same regime, mirror copies (gamma -> -gamma)"),
        ):
            _mark(ax, x, y, where, colour)
            ax.set_title(f"{text} ({int(where.sum())} points)", fontsize=9)
    for ax in axes.ravel():
        ax.set_xlabel(x_name)
        ax.set_ylabel(y_name)
    fig.suptitle(_title(ds), fontsize=10)
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


def regime_search_figure(ds: Any) -> Figure:
    """A regime store over more than two axes (a search): over the first two, the most
    irregular regime met along the others (chaotic before undecided before quasi-periodic
    before contracting before periodic) and the largest Lyapunov exponent met.

    Parameters
    ----------
    ds : xarray.Dataset
        A store with ``regime`` over three or more axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    from ..numerics.ball.regimes import REGIMES

    y_name, x_name, *rest = ds["regime"].dims
    regime = np.asarray(ds["regime"].values, dtype=float)
    regime[regime < 0] = np.nan
    rank = {REGIMES["periodic"]: 0, REGIMES["contracting"]: 1, REGIMES["quasi-periodic"]: 2,
            REGIMES["undecided"]: 3, REGIMES["chaotic"]: 4}  # fmt: skip
    ranked = np.full(regime.shape, np.nan)
    for code, r in rank.items():
        ranked[regime == code] = r
    axes_rest = tuple(range(2, regime.ndim))
    with np.errstate(all="ignore"):
        worst = np.where(np.all(np.isnan(ranked), axis=axes_rest), np.nan,
                         np.nanmax(np.nan_to_num(ranked, nan=-1), axis=axes_rest))  # fmt: skip
        worst[worst < 0] = np.nan
        lam = np.asarray(ds["lyapunov_max_per_iteration"].values, dtype=float)
        top = np.nanmax(np.where(np.isnan(lam), -np.inf, lam), axis=axes_rest)
        top[~np.isfinite(top)] = np.nan
    names = ["periodic", "contracting", "quasi-periodic", "undecided", "chaotic"]
    present = [k for k in range(len(names)) if (worst == k).any()]
    codes = np.full(worst.shape, np.nan)
    for j, k in enumerate(present):
        codes[worst == k] = j
    colours = [period_colours([1])[0], *(REGIME_COLOURS[n] for n in names[1:])]
    fig = Figure(figsize=(13, 5), layout="constrained")
    a, b = fig.subplots(1, 2)
    x, y = ds[x_name].values, ds[y_name].values
    _category_mesh(a, fig, x, y, codes, [names[k] for k in present],
                   [colours[k] for k in present],
                   f"the most irregular regime over {', '.join(rest)}")  # fmt: skip
    mesh = b.pcolormesh(x, y, top, cmap="viridis", shading="nearest")
    fig.colorbar(mesh, ax=b, label="largest Lyapunov exponent met, per map iteration")
    b.set_title("largest Lyapunov exponent met (blank: all periodic)", fontsize=9)
    for ax in (a, b):
        ax.set_xlabel(x_name)
        ax.set_ylabel(y_name)
        if np.all(y > 0) and y.max() / y.min() > 20:  # a range over decades
            ax.set_yscale("log")
    fig.suptitle(_title(ds), fontsize=10)
    return fig


def lyapunov_chart_figure(ds: Any) -> Figure:
    """The largest Lyapunov exponent over two axes (per map iteration, with its units), and
    where it says chaos (``chaotic``: above ``ln(N)/N`` by 3 error bars).

    Parameters
    ----------
    ds : xarray.Dataset
        A store with ``lyapunov_max_per_iteration`` and ``chaotic`` over two axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    y_name, x_name = ds["lyapunov_max_per_iteration"].dims
    x, y = ds[x_name].values, ds[y_name].values
    lam = np.asarray(ds["lyapunov_max_per_iteration"].values, dtype=float)
    chaotic = np.asarray(ds["chaotic"].values, dtype=float)
    chaotic[chaotic < 0] = np.nan
    fig = Figure(figsize=(13, 5), layout="constrained")
    a, b = fig.subplots(1, 2)
    finite = lam[np.isfinite(lam)]
    top = float(np.max(np.abs(finite))) if finite.size else 1.0
    mesh = a.pcolormesh(x, y, lam, cmap="RdBu_r", vmin=-top, vmax=top, shading="nearest")
    units = ds["lyapunov_max_per_iteration"].attrs.get("units", "per map iteration")
    fig.colorbar(mesh, ax=a, label="per map iteration")
    a.set_title(f"largest Lyapunov exponent, {units}", fontsize=8)
    _category_mesh(b, fig, x, y, chaotic, ["not chaotic", "chaotic"],
                   ["tab:blue", "tab:red"],
                   f"chaotic: {int(np.nansum(chaotic))} of {int(np.isfinite(chaotic).sum())} "
                   "points (exponent - 3 errors > ln(N)/N)")  # fmt: skip
    for ax in (a, b):
        ax.set_xlabel(x_name)
        ax.set_ylabel(y_name)
    fig.suptitle(_title(ds), fontsize=10)
    return fig


def sweep_figure(ds: Any) -> Figure:
    """The picture a store calls for: the period chart, the Lyapunov chart, Delta over mu (log
    scale), the frame turn with its zeros, or the first numbers per point over the first axis.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    matplotlib.figure.Figure
    """
    if "regime" in ds and ds["regime"].ndim >= 2:
        grid = [d for d in ds["regime"].dims if d != "carry"]
        return regime_chart_figure(ds) if len(grid) == 2 else regime_search_figure(ds)
    if "period" in ds and ds["period"].ndim == 2:
        return period_chart_figure(ds)
    if "lyapunov_max_per_iteration" in ds and ds["lyapunov_max_per_iteration"].ndim == 2:
        return lyapunov_chart_figure(ds)
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
