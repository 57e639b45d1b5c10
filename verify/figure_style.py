"""What every figure shares: a Figure made without pyplot (no backend is selected), the colours,
the line styles of stable and unstable branches, and user text shown literally."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["COLORS", "literal_text", "new_figure", "stability_legend", "stability_style"]

#: Colours of the branches (axis 1, 2, 3, then the M || gamma segment and more).
COLORS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange")


def literal_text(text: str) -> str:
    """User text (a scene's title) as matplotlib shows it literally: ``$`` escaped, so that
    ``"cost $5$"`` is not read as mathtext (and a malformed formula cannot fail the drawing).

    Parameters
    ----------
    text : str

    Returns
    -------
    str

    Examples
    --------
    >>> literal_text("$x^$")
    '\\$x^\\$'
    """
    return text.replace("$", r"\$")


def new_figure(**kwargs: object) -> Figure:
    """A :class:`~matplotlib.figure.Figure` not managed by pyplot (no backend is chosen).

    Parameters
    ----------
    **kwargs
        Passed to :class:`~matplotlib.figure.Figure`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def stability_style(stable: bool) -> str:
    """The line style of a branch: solid where stable, dashed where not.

    Parameters
    ----------
    stable : bool

    Returns
    -------
    str
    """
    return "-" if stable else "--"


def stability_legend() -> list:
    """Legend entries for :func:`stability_style` and the integrated states' dots.

    Returns
    -------
    list of matplotlib.lines.Line2D
    """
    from matplotlib.lines import Line2D

    return [
        Line2D([], [], color="k", ls="-", label="stable (|multipliers| = 1)"),
        Line2D([], [], color="k", ls="--", label="unstable"),
        Line2D([], [], color="0.5", marker=".", ls="", label="integrated states"),
    ]
