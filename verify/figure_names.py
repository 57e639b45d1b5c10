"""The bifurcation diagrams ``chaplygin bifurcation --figure`` draws, by name.

Kept apart from :mod:`.plots` so that building the command-line parser (which lists
them) does not import the numerical layer.
"""

from __future__ import annotations

__all__ = ["FIGURES"]

#: Bifurcation diagrams: name -> (system, default parameters, title).
FIGURES = {
    "k01-1": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1, "C": 0}, "K01 Fig. 1"),
    "k01-2": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1, "C": 1}, "K01 Fig. 2(a)"),
    "k01-3": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1, "C": 1}, "K01 Fig. 3"),
    "bkm12-2": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1}, "BKM12 Fig. 2"),
    "bkm12-3": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1}, "BKM12 Fig. 3"),
    "bkm12-5": (
        "spherical_support",
        {"I": (1, 1.5, 3), "D_iso": 0.5, "D_al": 0.3, "D_be": -0.2},
        "BKM12 Fig. 5",
    ),
}
