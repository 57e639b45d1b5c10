"""Pictures of sweep stores (verify/sweep_plots.py): every period present has its own colour
and is named on the colour bar (a colour map wrapped at 20 drew period 28 in period 8's
colour); the regime chart shows both carry directions and where they differ."""

from __future__ import annotations

import numpy as np
import pytest

xr = pytest.importorskip("xarray")

from chaplygin.numerics.ball.regimes import REGIMES  # noqa: E402
from chaplygin.verify.sweep_plots import (  # noqa: E402
    period_chart_figure,
    period_colours,
    regime_chart_figure,
    sweep_figure,
)


def _cell_colours(mesh, shape):
    """The colour each cell is drawn in (the mesh's colour map and norm on its data)."""
    return np.asarray(mesh.cmap(mesh.norm(mesh.get_array()))).reshape(*shape, 4)


def test_every_period_present_has_its_own_colour_and_label():
    periods = np.array([[0, 7, 8, 28], [27, 8, 48, 7], [1, 2, 3, 20]])
    ds = xr.Dataset(
        {"period": (("Omega", "D"), periods)},
        coords={"Omega": [1.0, 1.1, 1.2], "D": [4.37, 4.38, 4.39, 4.40]},
    )
    fig = period_chart_figure(ds)
    ax, bar = fig.axes
    colours = _cell_colours(ax.collections[0], periods.shape)
    by_period = {}
    for p in np.unique(periods):
        cells = colours[periods == p]
        assert (cells == cells[0]).all()  # one colour per period
        by_period[int(p)] = tuple(cells[0])
    assert len(set(by_period.values())) == len(by_period)  # 8 and 28 differ, 7 and 27 ...
    assert by_period[0] == (0.0, 0.0, 0.0, 1.0)
    labels = [t.get_text() for t in bar.get_yticklabels()]
    present = (1, 2, 3, 7, 8, 20, 27, 28, 48)
    assert labels == ["0: none up to max_period"] + [str(p) for p in present]


def test_colours_stay_distinct_beyond_the_palettes():
    colours = period_colours(list(range(1, 121)))
    assert len(set(colours)) == 120
    greys = [c for c in colours if c[0] == c[1] == c[2]]
    assert not greys  # grey and black are kept for the regimes without a period


def test_regime_chart_names_periods_and_marks_where_the_directions_differ():
    shape = (2, 2, 3)  # carry x Omega x D
    regime = np.full(shape, REGIMES["quasi-periodic"], dtype="int8")
    period = np.zeros(shape, dtype="int16")
    regime[0, 0, 0] = regime[1, 0, 0] = REGIMES["chaotic"]
    regime[0, 1, 2], period[0, 1, 2] = REGIMES["periodic"], 28
    regime[1, 1, 2], period[1, 1, 2] = REGIMES["periodic"], 8  # differs: coexistence
    regime[1, 0, 1] = REGIMES["contracting"]  # differs from forward's quasi-periodic
    lam = np.where(regime == REGIMES["periodic"], np.nan, 0.01)
    ds = xr.Dataset(
        {
            "regime": (("carry", "Omega", "D"), regime),
            "period": (("carry", "Omega", "D"), period),
            "lyapunov_max_per_iteration": (("carry", "Omega", "D"), lam),
            "symmetric_copy": (("carry", "Omega", "D"), np.zeros(shape, "int8")),
        },
        coords={"carry": ["forward", "backward"], "Omega": [1.0, 1.1], "D": [4.37, 4.38, 4.39]},
    )
    fig = sweep_figure(ds)
    assert fig is not None
    titles = [a.get_title() for a in fig.axes]
    assert any("differ in regime or period (2 points)" in t for t in titles)
    bars = [a for a in fig.axes if a.get_yticklabels() and "period 8" in
            [t.get_text() for t in a.get_yticklabels()]]  # fmt: skip
    labels = [t.get_text() for t in bars[0].get_yticklabels()]
    assert labels == ["period 8", "period 28", "quasi-periodic", "chaotic", "contracting"]
    assert regime_chart_figure(ds.isel(carry=0, drop=True)) is not None  # one direction


def test_a_search_over_more_axes_shows_the_most_irregular_regime():
    shape = (2, 3, 2)  # Omega x J x start
    regime = np.full(shape, REGIMES["periodic"], dtype="int8")
    regime[0, 1, 1] = REGIMES["chaotic"]
    regime[1, 2, 0] = REGIMES["quasi-periodic"]
    lam = np.where(regime == REGIMES["periodic"], np.nan, 0.002)
    lam[0, 1, 1] = 0.05
    dims = ("Omega", "J_off", "z")
    ds = xr.Dataset(
        {"regime": (dims, regime), "period": (dims, np.ones(shape, "int16")),
         "lyapunov_max_per_iteration": (dims, lam)},
        coords={"Omega": [0.1, 4.0], "J_off": [-1.0, 0.0, 1.0], "z": [0.7, -0.6]},
    )  # fmt: skip
    fig = sweep_figure(ds)
    cells = _cell_colours(fig.axes[0].collections[0], (2, 3))
    (labels,) = [
        [t.get_text() for t in ax.get_yticklabels()]
        for ax in fig.axes
        if "periodic" in [t.get_text() for t in ax.get_yticklabels()]
    ]
    assert labels == ["periodic", "quasi-periodic", "chaotic"]
    assert tuple(cells[0, 1]) == (0.0, 0.0, 0.0, 1.0)  # chaotic at one start: black
    assert tuple(cells[0, 0]) != tuple(cells[1, 2]) != tuple(cells[0, 1])
    assert fig.axes[0].get_yscale() == "log"  # Omega over decades


def test_lyapunov_chart_draws_the_exponent_and_the_chaotic_points():
    """A 2-D lyapunov_max store: the exponent on a diverging scale centred at 0 (the largest
    magnitude at either end), its units in the title, and the chaotic points counted and drawn
    in their own colour (a non-chaotic point in the other)."""
    from chaplygin.verify.sweep_plots import lyapunov_chart_figure

    lam = np.array([[0.21, -0.03, 0.004], [0.0, 0.11, -0.12]])
    chaotic = np.array([[1, 0, 0], [0, 1, 0]], dtype="int8")
    ds = xr.Dataset(
        {
            "lyapunov_max_per_iteration": (("Omega", "D"), lam, {"units": "per iteration"}),
            "chaotic": (("Omega", "D"), chaotic),
            "status": (("Omega", "D"), np.zeros_like(chaotic)),
        },
        coords={"Omega": [1.06, 1.07], "D": [4.37, 4.38, 4.39]},
    )
    fig = sweep_figure(ds)
    assert fig.axes[0].get_title().endswith("per iteration")
    mesh = fig.axes[0].collections[0]
    assert mesh.norm.vmin == -0.21 and mesh.norm.vmax == 0.21
    right = [ax for ax in fig.axes if "chaotic:" in ax.get_title()]
    assert len(right) == 1 and right[0].get_title().startswith("chaotic: 2 of 6 points")
    colours = _cell_colours(right[0].collections[0], lam.shape)
    assert (colours[chaotic == 1] == colours[0, 0]).all()
    assert not (colours[0, 1] == colours[0, 0]).all()
    assert lyapunov_chart_figure(ds).axes[0].get_title() == fig.axes[0].get_title()
