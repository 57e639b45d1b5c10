"""Figures: bifurcation diagrams, the separatrix figures of K01 §3.3 and the work-precision plot
(the scenes' figures are in :mod:`chaplygin.verify.outputs`).

Every function returns a :class:`matplotlib.figure.Figure` (or draws on a given ``ax``); the
caller saves or shows it. No backend is selected here and :mod:`matplotlib.pyplot` is never
imported: a :class:`~matplotlib.figure.Figure` made directly saves itself to PNG, and in a
notebook the figure is shown inline by the notebook's own backend. matplotlib is imported on
the first figure, not with this module, and so are the numerics (the command line builds its
parser from :data:`FIGURES` on every start).

The numbers come from :mod:`chaplygin.numerics` (:mod:`~chaplygin.numerics.ball.bifurcation`,
:mod:`~chaplygin.numerics.ball.separatrix`) and from the study of :mod:`chaplygin.verify.bench`.

References
----------
K01-Fig1, K01-Fig2, K01-Fig3, BKM12-24, BKM12-Fig3, BKM12-2.7c, BKM12-1.5stab8 (bifurcation
diagrams); K01-3.7, K01-Fig4, K01-Fig6 (separatrix figures).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import mpmath
import numpy as np

from ..derive.errors import UserInputError
from ..numerics.arguments import check_count, check_inertia_vector, check_real, check_vector
from .figure_names import FIGURES
from .figure_style import COLORS, new_figure, stability_legend, stability_style

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "FIGURES",
    "bifurcation_figure",
    "critical_traces_figure",
    "bifurcation_complex_figure",
    "delta_of_mu_figure",
    "separatrix_traces_figure",
    "work_precision_figure",
    "draw_k01_diagram",
]


#: Most random states :func:`bifurcation_figure` integrates.
MAX_SAMPLES = 100_000
#: Largest ``mu`` of :func:`delta_of_mu_figure` (``Delta ~ 2 pi b exp(-pi mu/2)``).
MAX_MU = 100.0


# ---------------------------------------------------------------------- bifurcation diagrams
def draw_k01_diagram(
    ax: Axes,
    I: tuple[float, float, float],
    D: float,
    C: float,
    samples: int,
    seed: int,
    traces: Axes | None = None,
) -> float:
    """K01's energy diagram on ``ax``, the (n, h) plane at ``C``: the steady rotations
    ``p_i: h = Sigma_i/2`` (solid where stable), the segment ``n = C^2`` (``M || gamma``) and
    ``samples`` integrated random states (their traces on ``traces``, if given).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    I : tuple of 3 floats
    D, C : float
    samples : int
    seed : int
        Of the random states.
    traces : matplotlib.axes.Axes, optional

    Returns
    -------
    float
        The largest relative drift of the integrals over the integrated states.
    """
    from ..numerics.ball.bifurcation import euler_stability, family_stability, sample_levels, sigma

    stab = family_stability(I, D, 1.0 + C**2, C)
    n_max = 3.0 if C == 0 else 3.0 * C**2
    n = np.linspace(C**2, n_max, 200)
    for i in range(3):
        h = sigma(i, n, C, I, D) / 2
        ax.plot(
            n,
            h,
            stability_style(stab[i][0]),
            color=COLORS[i],
            label=f"p{i + 1} (max|mu| = {stab[i][1]:.3g})",
        )
    if C != 0:
        hs = sorted(C**2 / (2 * np.asarray(I, float)))  # h_i = C^2/(2 I_i) on n = C^2
        Ep_mid = D * 2 * hs[1] / C**2
        for lo, hi in ((hs[0], hs[1]), (hs[1], hs[2])):
            Ep = D * (lo + hi) / C**2  # E' = 2 h D/C^2 at the arc's midpoint
            st, mu = euler_stability(I, D, Ep)
            ax.plot([C**2, C**2], [lo, hi], stability_style(st), color=COLORS[3], lw=2)
        ax.plot([], [], "-", color=COLORS[3], lw=2, label="n = C^2 (M || gamma)")
        ax.plot(
            [C**2],
            [hs[1]],
            "o",
            color=COLORS[3],
            mfc="w",
            label=f"unstable point E' = {Ep_mid:.3g}",
        )
    vals, drift, states = sample_levels(I, D, samples, seed, C_range=(C**2, n_max), Mg=C)
    ax.plot(vals[:, 0], vals[:, 2] / 2, ".", color="0.5", ms=3)
    ax.set_xlabel("n = (M, M)")
    ax.set_ylabel("h = (M, omega)/2")
    if traces is not None:
        _draw_traces(ax, traces, I, D, C, vals, states)
    return drift


def _draw_traces(ax: Axes, tax: Axes, I, D, C, vals, states) -> None:
    """K01 Fig. 3: contact-point traces of three states (above p2, below p2, near p2)."""
    from ..numerics import integrate
    from ..numerics.ball.bifurcation import ball_energy, sigma
    from ..numerics.ball.stability import critical_state

    h2 = sigma(1, vals[:, 0], C, I, D) / 2
    above = int(np.argmax(vals[:, 2] / 2 - h2 > 0.05))
    below = int(np.argmax(h2 - vals[:, 2] / 2 > 0.05))
    y2, _ = critical_state(I, D, 1, 1.0 + C**2, C)
    near = y2 + 1e-4 * np.array([1.0, -1.0, 0.5, 0.3, -0.2, 0.1])
    near[3:] /= np.linalg.norm(near[3:])
    picks = [("a", states[above]), ("b", states[below]), ("c (near p2)", near)]
    for k, (label, y) in enumerate(picks):
        M, g = y[:3], y[3:]
        r = integrate(
            "chaplygin_ball",
            {"M": tuple(M), "gamma": tuple(g)},
            150.0,
            {"I": tuple(I), "D": D, "b": 1.0},
            effects=("contact_point",),
            rtol=1e-10,
            atol=1e-12,
            t_eval=np.linspace(0, 150, 3000),
        )
        xs, ys = r.y[r.state_names.index("x")], r.y[r.state_names.index("y")]
        tax.plot(xs, ys, lw=0.8, color=COLORS[k], label=label)
        h_ = ball_energy(y[:6], I, D) / 2
        ax.annotate(label[0], (M @ M, h_), color=COLORS[k], fontsize=10, weight="bold")
    tax.grid(alpha=0.3)
    tax.set_xlabel("x (contact point, b = 1)")
    tax.set_ylabel("y")
    tax.legend(fontsize=7)
    tax.set_title("contact-point traces, t in [0, 150]", fontsize=9)


def _paper_order(I, D) -> np.ndarray:
    """Body axes in BKM12's order of Figs. 2 and 3: ``A1 < A2 < A3`` (``b_i = D A_i``), so the
    paper's ``Sigma_k`` is the steady rotation about body axis ``order[k - 1]``."""
    return np.argsort(1 / (np.asarray(I, float) + D), kind="stable")


def _draw_bkm12_2(ax: Axes, I, D, samples, seed) -> float:
    from ..numerics.ball.bifurcation import family_stability, sample_levels

    stab = family_stability(I, D, 1.0, 0.0)
    C = np.linspace(0, 1, 100)
    A = 1 / (np.asarray(I, float) + D)
    for k, i in enumerate(_paper_order(I, D)):
        ax.plot(
            C,
            A[i] * C,
            stability_style(stab[i][0]),
            color=COLORS[k],
            label=f"Sigma_{k + 1}: E = A{k + 1} C, A{k + 1} = {A[i]:.4g} (body axis e{i + 1}; "
            f"max|mu| = {stab[i][1]:.3g})",
        )
    vals, drift, states = sample_levels(I, D, samples, seed, C_range=(0.02, 1.0), Mg=0.0)
    ax.plot(vals[:, 0], vals[:, 2], ".", color="0.5", ms=3)
    ax.set_xlabel("C = (M, M)")
    ax.set_ylabel("E = (M, omega)")
    return drift


def _draw_bkm12_3(ax: Axes, I, D, samples, seed) -> float:
    from ..numerics.ball.bifurcation import euler_stability, family_stability, sample_levels, sigma

    b = D / (np.asarray(I, float) + D)
    g = np.linspace(-1, 1, 201)
    stab = family_stability(I, D, 1.0, 0.5)
    for k, i in enumerate(_paper_order(I, D)):
        Ep = sigma(i, 1.0, g, I, D) * D  # E' = E D/C at C = 1
        ax.plot(
            g,
            Ep,
            stability_style(stab[i][0]),
            color=COLORS[k],
            label=f"Sigma_{k + 1}: b{k + 1} = {b[i]:.4g} (body axis e{i + 1}; "
            f"max|mu| = {stab[i][1]:.3g})",
        )
    ends = sorted(b / (1 - b))
    for gv, k in ((1, 4), (-1, 5)):
        for lo, hi in ((ends[0], ends[1]), (ends[1], ends[2])):
            st, _ = euler_stability(I, D, (lo + hi) / 2)
            ax.plot([gv, gv], [lo, hi], stability_style(st), color=COLORS[3 if k == 4 else 4], lw=2)
        ax.plot(
            [], [], "-", color=COLORS[3 if k == 4 else 4], lw=2, label=f"Sigma_{k}: g = {gv:+d}"
        )
        ax.plot([gv], [ends[1]], "o", color="k", mfc="w")
    rng = np.random.default_rng(seed)
    gs = rng.uniform(-1, 1, samples)
    vals = []
    drift = 0.0
    for k, gv in enumerate(gs):
        v, d, _ = sample_levels(I, D, 1, seed + k, C_range=(1.0, 1.0), g=gv)
        vals.append((v[0, 1] / np.sqrt(v[0, 0]), v[0, 2] * D / v[0, 0]))
        drift = max(drift, d)
    vals = np.array(vals)
    ax.plot(vals[:, 0], vals[:, 1], ".", color="0.5", ms=3)
    ax.set_xlabel("g = M_gamma/sqrt(C)")
    ax.set_ylabel("E' = E D/C")
    return drift


def _draw_bkm12_5(fig: Figure, params, samples, seed) -> float:
    """Surfaces E'_i on the sphere of (g_al, g_be, g_ga), drawn over the (g_al, g_be) disc."""
    from matplotlib.patches import Circle

    from ..numerics.ball.bifurcation import support_sample, support_stability

    I, D_iso, D_al, D_be = params[:3], params[3], params[4], params[5]
    J = np.asarray(I, float) + D_iso
    stab = support_stability(params)
    t = np.linspace(-1, 1, 241)
    X, Y = np.meshgrid(t, t)
    R2 = X**2 + Y**2
    Zg = np.where(R2 <= 1, 1 - R2, np.nan)
    axes = fig.subplots(1, 4)
    for i in range(3):
        ax = axes[i]
        Ep = X**2 / (J[i] - D_al) + Y**2 / (J[i] - D_be) + Zg / J[i]
        cs = ax.contour(
            X, Y, Ep, levels=10, colors=COLORS[i], linestyles=stability_style(stab[i][0])
        )
        ax.clabel(cs, fontsize=6, fmt="%.2f")
        ax.set_title(
            f"E'_{i + 1} ({'stable' if stab[i][0] else 'unstable'}, max|mu| = {stab[i][1]:.3g})",
            fontsize=8,
        )
        ax.set_aspect("equal")
        ax.add_patch(Circle((0, 0), 1, fill=False, lw=0.5))
        ax.set_xlabel("g_al")
        ax.set_ylabel("g_be")
    # region of motion: random states, E' between the extreme surfaces at their (g_al, g_be, g_ga)
    pos, drift = support_sample(params, samples, seed)
    ax = axes[3]
    sc = ax.scatter(pos[:, 0], pos[:, 1], c=pos[:, 2], s=6, cmap="viridis", vmin=0, vmax=1)
    fig.colorbar(sc, ax=ax, fraction=0.046, label="(E' - min_i E'_i)/(max_i E'_i - min_i E'_i)")
    ax.set_aspect("equal")
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_title("integrated states", fontsize=8)
    ax.set_xlabel("g_al")
    return drift


def bifurcation_figure(
    figure: str, params: Mapping | None = None, samples: int = 60, seed: int = 1
) -> tuple[Figure, float]:
    """One bifurcation diagram of :data:`FIGURES`.

    The derived curves are drawn solid where their Floquet multipliers lie on the unit
    circle and dashed otherwise; ``samples`` seeded random states integrated for a short
    time are drawn as dots (the region of motion).

    Parameters
    ----------
    figure : str
        A key of :data:`FIGURES` (``"k01-1"``, ..., ``"bkm12-5"``).
    params : mapping, optional
        Overrides of the figure's default parameters (``I`` a triple, the others numbers).
    samples : int
        Number of integrated random states.
    seed : int
        Seed of the random states.

    Returns
    -------
    figure : matplotlib.figure.Figure
    drift : float
        Largest relative drift of the integrals over the integrated states.

    Raises
    ------
    UserInputError
        Unknown figure or inadmissible parameters.
    """
    if params is not None and not isinstance(params, Mapping):
        raise UserInputError(f"params = {params!r} must be a mapping of parameter names to values")
    params = dict(params or {})
    check_count(samples, "samples", 1, MAX_SAMPLES)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise UserInputError(f"seed = {seed!r} must be a non-negative integer")
    if not isinstance(figure, str) or figure not in FIGURES:
        raise UserInputError(f"unknown figure {figure!r}; valid: {', '.join(FIGURES)}")
    system, defaults, title = FIGURES[figure]
    p = {**defaults, **params}
    unknown = set(params) - set(defaults)
    if unknown:
        raise UserInputError(
            f"parameter(s) {', '.join(sorted(unknown))} not used by {figure}; "
            f"valid: {', '.join(defaults)}"
        )
    I = tuple(float(v) for v in check_vector(p["I"], "I", positive=True, double=True))
    for name in set(p) - {"I"}:
        check_real(p[name], name, double=True)
    if system == "chaplygin_ball" and float(p["D"]) <= 0:
        raise UserInputError(f"D must be positive, got {p['D']}")
    if samples < 1:
        raise UserInputError(f"--samples must be at least 1, got {samples}")
    if figure == "bkm12-5":
        params6 = (*I, float(p["D_iso"]), float(p["D_al"]), float(p["D_be"]))
        J = np.asarray(I) + params6[3]
        if params6[3] < 0 or min(J) <= max(params6[4], params6[5], 0):
            raise UserInputError(
                "need D_iso >= 0 and I_i + D_iso > D_al, D_be (a physical support)"
            )
        fig = new_figure(figsize=(16, 4.4))
        drift = _draw_bkm12_5(fig, params6, samples, seed)
        fig.suptitle(
            f"{title}: bifurcation surfaces E' = E/C on g_al^2 + g_be^2 + g_ga^2 = 1 "
            f"(I = {I}, D_iso = {params6[3]}, D_al = {params6[4]}, D_be = {params6[5]})"
        )
    else:
        D = float(p["D"])
        if figure == "k01-3":
            fig = new_figure(figsize=(13, 5))
            ax, tax = fig.subplots(1, 2)
        else:
            fig = new_figure(figsize=(7, 5))
            ax, tax = fig.subplots(), None
        if figure.startswith("k01"):
            C = float(p["C"])
            drift = draw_k01_diagram(ax, I, D, C, samples, seed, traces=tax)
            ax.set_title(f"{title}: I = {I}, D = {D}, C = (M, gamma) = {C}")
        elif figure == "bkm12-2":
            drift = _draw_bkm12_2(ax, I, D, samples, seed)
            ax.set_title(f"{title}: (M, gamma) = 0, I = {I}, D = {D} (A1 < A2 < A3)")
        else:
            drift = _draw_bkm12_3(ax, I, D, samples, seed)
            ax.set_title(f"{title}: normalised, I = {I}, D = {D} (b1 < b2 < b3)")
        handles, _ = ax.get_legend_handles_labels()
        ax.legend(handles=handles + stability_legend(), fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig, drift


# ------------------------------------------------------- BKM12 Figs. 2(b), 3(b): the complex
def bifurcation_complex_figure(
    I: Sequence[float] = (1.0, 1.5, 3.0),
    D: float = 1.0,
    gs: Sequence[float] = (0.0, 0.5),
    levels: int = 7,
) -> Figure:
    """The bifurcation complex over a line ``C = 1``, ``g = M_gamma/sqrt(C)`` fixed of the
    diagram (BKM12 Figs. 2(b), 3(b)), computed: for energies across both chambers, each
    connected component of the level set (a leaf:
    :func:`~chaplygin.numerics.ball.bifurcation.level_set_components`) is drawn at the mean of
    ``M`` along the axis of the stable family its chamber ends on (``e`` of ``A1`` below
    ``Sigma_2``, of ``A3`` above): the leaves run from the stable rotations (``|mean| -> 1``) to
    ``Sigma_2``, where the level set is one component and they meet.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    gs : sequence of float
        One panel per ``g`` (0: Fig. 2(b)).
    levels : int
        Energies per chamber.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    BKM12-Fig2b, BKM12-Fig3b (claims).
    """
    from ..numerics.ball.bifurcation import level_set_components, sigma

    I = tuple(float(v) for v in check_vector(I, "I", positive=True, double=True))
    order = np.argsort(1 / (np.asarray(I) + D))
    fig = new_figure(figsize=(6 * len(gs), 4.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(gs)))
    for ax, g in zip(axes, gs, strict=True):
        S = [float(sigma(int(i), 1.0, g, I, D)) for i in order]
        for chamber, (lo, hi, axis) in enumerate(((S[0], S[1], order[0]), (S[1], S[2], order[2]))):
            Es = lo + (hi - lo) * np.linspace(0.04, 0.96, levels)
            tracks: list[list] = [[], []]
            for E in Es:
                r = level_set_components(I, D, float(E), 1.0, float(g))
                along = sorted(r.mean_M[:, axis])
                for k, v in enumerate(along[:2]):
                    tracks[k].append((E, v, r.count))
            colour = COLORS[0 if chamber == 0 else 2]
            for k, track in enumerate(tracks):
                E_, v_, _ = (np.array(c) for c in zip(*track, strict=True))
                ax.plot(E_, v_, "o-", color=colour, ms=3,
                        label=(f"leaves over (Sigma_{chamber + 1}, Sigma_{chamber + 2}): along "
                               f"e{axis + 1}") if k == 0 else None)  # fmt: skip
                end = 0 if chamber == 1 else -1  # the end at Sigma_2: joined to its vertex
                ax.plot([E_[end], S[1]], [v_[end], 0.0], ":", color=colour, lw=1)
            edge = lo if chamber == 0 else hi  # the stable rotations the leaves end on
            ax.plot([edge, edge], [-1, 1], "s", color=colour, ms=6)
        r = level_set_components(I, D, S[1], 1.0, float(g))
        ax.axvline(S[1], color=COLORS[1], ls="--", lw=1)
        ax.plot([S[1]], [0], "o", color=COLORS[1], ms=8,
                label=f"Sigma_2: {r.count} component (the leaves glued)")  # fmt: skip
        ax.set_xlabel("E = (M, omega) at C = (M, M) = 1")
        ax.set_ylabel("mean over the leaf of M along its stable family's axis")
        ax.set_title(
            f"{'Fig. 2(b)' if g == 0 else 'Fig. 3(b)'}: g = {g:g}; squares: the stable "
            "rotations (+-e)",
            fontsize=9,
        )
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"BKM12: the bifurcation complex over C = 1, computed (I = {I}, D = {D:g})")
    return fig


# ------------------------------------------------ BKM12 §1.5: traces of critical solutions
def critical_traces_figure(
    I: Sequence[float] = (1.0, 1.5, 3.0),
    D: float = 1.0,
    C: float = 2.0,
    Mg: float = 0.5,
    b: float = 1.0,
    periods: float = 3.0,
) -> Figure:
    """Contact-point traces of BKM12's critical solutions: (a) the six families (25) at
    ``(M, gamma) = 0``, (b) the six rotations on ``Sigma_1..3`` at ``(M, gamma) = Mg``, (c)
    the Euler-top orbits ``M = +-sqrt(C) gamma`` (``Sigma_4``, ``Sigma_5``) on both arcs,
    (d) a separatrix of ``Sigma_2`` at ``(M, gamma) = 0``: from the rotation about the middle
    axis in one sense to the opposite one (BKM12-1.5sep).

    Parameters
    ----------
    I : sequence of 3 floats
    D, C, Mg, b : float
        ``D = m b^2``, ``(M, M)``, ``(M, gamma)`` of panel (b), the radius.
    periods : float
        Periods of each rotation drawn.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    BKM12-25.trace, BKM12-crit.trace, BKM12-Sigma45, BKM12-1.5sep (FORMULAS.md, claims).
    """
    from ..numerics import load_model_code
    from ..numerics.ball.bifurcation import critical_trace
    from ..numerics.ball.stability import critical_state, euler_state, monodromy

    I = tuple(float(v) for v in check_vector(I, "I", positive=True, double=True))
    A = 1 / (np.asarray(I) + D)
    order = list(np.argsort(A))  # BKM12's A1 < A2 < A3
    fig = new_figure(figsize=(15, 4.6), layout="constrained")
    axes = fig.subplots(1, 4)
    for ax, mg, name in ((axes[0], 0.0, "(a) (M, gamma) = 0: the families (25)"),
                         (axes[1], Mg, f"(b) (M, gamma) = {Mg:g}: Sigma_1..3")):  # fmt: skip
        for axis in range(3):
            k = order.index(axis)
            for branch, style in ((0, "-"), (1, "--")):
                y0, T = critical_state(I, D, axis, C, mg, branch)
                tr = critical_trace(y0, I, D, b, periods * T)
                # the horizontal frame is a free choice: each family is drawn turned by its own
                # angle so that the six straight lines do not overlap
                turn = np.pi * (2 * k + branch) / 6
                c, s_ = np.cos(turn), np.sin(turn)
                ax.plot(c * tr.x - s_ * tr.y, s_ * tr.x + c * tr.y, style, color=COLORS[k],
                        lw=1.2, label=f"Sigma_{k + 1} (e{axis + 1}), sense {branch}")  # fmt: skip
        ax.set_title(name + f", {periods:g} periods", fontsize=9)
    bs = np.sort(D * A)
    ends = bs / (1 - bs)
    for sign, name in ((1, "Sigma_4"), (-1, "Sigma_5")):
        for j, (lo, hi) in enumerate(((ends[0], ends[1]), (ends[1], ends[2]))):
            y0 = euler_state(I, D, C, (lo + hi) / 2, sign)
            tr = critical_trace(y0, I, D, b, 60.0)
            axes[2].plot(tr.x, tr.y, "-" if sign > 0 else "--", color=COLORS[3 + j % 2], lw=1,
                         label=f"{name}, E' = {(lo + hi) / 2:.3g}")  # fmt: skip
    axes[2].set_title("(c) M = +-sqrt(C) gamma (Sigma_4, 5), t in [0, 60]", fontsize=9)
    mid = order[1]
    y0, T = critical_state(I, D, mid, C, 0.0, 0)
    Phi, _ = monodromy(load_model_code("chaplygin_ball"), y0, T, [*I, D], 1e-12)
    w, V = np.linalg.eig(Phi)
    v = np.real(V[:, int(np.argmax(np.abs(w)))])
    tr = critical_trace(y0 + 1e-6 * v / np.linalg.norm(v), I, D, b, 12 * T, points=6001)
    axes[3].plot(tr.x, tr.y, color=COLORS[1], lw=1)
    axes[3].plot(tr.x[0], tr.y[0], "o", color="k", ms=4)
    axes[3].set_title(
        f"(d) separatrix of Sigma_2 (e{mid + 1}), offset 1e-6,\n"
        f"t in [0, {12 * T:.0f}] (y stretched)",
        fontsize=9,
    )
    for ax in axes[:3]:
        ax.set_aspect("equal", adjustable="datalim")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.set_xlabel(f"x (contact point, b = {b:g})")
        ax.set_ylabel("y")
    for ax in axes[:3]:
        ax.legend(fontsize=6)
    fig.suptitle(
        f"BKM12 §1.5: contact-point traces of the critical solutions, I = {I}, D = {D:g}, "
        f"(M, M) = {C:g}, b = {b:g}"
    )
    return fig


# ---------------------------------------------------------------------- separatrix, K01 §3.3
def delta_of_mu_figure(b: float = 1.0, mu_max: float = 6.0) -> Figure:
    """K01 Fig. 5: ``Delta(mu) = pi b/ch(pi mu/2)`` with quadrature points and Fig. 4's values.

    Parameters
    ----------
    b : float
        Radius of the ball.
    mu_max : float
        Right end of the ``mu`` axis.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels, linear and logarithmic ``Delta``.
    """
    from ..numerics.ball.separatrix import delta_closed_form, delta_quadrature, mu_of

    check_real(b, "b", positive=True, double=True)
    check_real(mu_max, "mu_max", positive=True, double=True)
    if mu_max > MAX_MU:
        raise UserInputError(f"mu_max = {mu_max} is beyond {MAX_MU} (Delta underflows there)")
    mus = np.linspace(0.0, mu_max, 400)
    closed = [float(delta_closed_form(m, b, 20)) for m in mus]
    pts = np.linspace(0.25, mu_max, 12)
    quad = [float(delta_quadrature(m, b, 15)) for m in pts]
    fig = new_figure(figsize=(10, 4))
    axes = fig.subplots(1, 2)
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
    return fig


def separatrix_traces_figure(
    inertias: Sequence = ((1, 3, 5), (1, 1.5, 2)),
    D: float = 1.0,
    b: float = 1.0,
    C: float = 1.0,
    offsets: Sequence[float] = (-1e-3, 1e-3),
    t_end: float = 120.0,
) -> Figure:
    """K01 Figs. 4 and 6: contact-point traces on and near the separatrix.

    Left: the trace along the separatrix itself (the displacement ``Delta``, K01 Fig. 4).
    Right: traces of the full equations (DOP853, compiled right-hand side) on ``M = C gamma``
    at ``h = h2 (1 + offset)`` for the first inertia (K01 Fig. 6 (d)-(e)): a spiral
    whose centres are displaced by about ``Delta`` per tumble.

    Parameters
    ----------
    inertias : sequence of triples
        Moments of inertia of the traces on the separatrix (the first also for the right panel).
    D, b, C : float
        ``D = m b^2``, the radius and ``C = (M, gamma)``.
    offsets : sequence of float
        Relative offsets of the energy from ``h2`` (right panel).
    t_end : float
        Integration time of the right panel.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..numerics.ball.frame_turn import near_separatrix_state, separatrix_trace
    from ..numerics.ball.separatrix import delta_closed_form, mu_of
    from ..numerics.integrate import integrate

    fig = new_figure(figsize=(11, 5))
    axes = fig.subplots(1, 2)
    ax = axes[0]
    for I in inertias:
        x, y = separatrix_trace(I, D, b, C)
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
    return fig


def separatrix_figures(
    I: Sequence = (1, 3, 5), D: float = 1.0, b: float = 1.0
) -> dict[str, Figure]:
    """K01 Figs. 4-6 for ``chaplygin delta --figures``: file name -> figure.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia of the traces (besides ``(1, 1.5, 2)``).
    D, b : float
        ``D = m b^2`` and the radius.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``delta_of_mu.png`` and ``separatrix_traces.png``.
    """
    from ..numerics.ball.separatrix import check_inertia

    check_inertia(I, D)
    check_inertia_vector(I, D, double=True)
    check_real(b, "b", positive=True, double=True)
    with mpmath.workdps(20):
        return {
            "delta_of_mu.png": delta_of_mu_figure(b),
            "separatrix_traces.png": separatrix_traces_figure((tuple(I), (1, 1.5, 2)), D, b),
        }


# ---------------------------------------------------------------------- work-precision study
def _check_study(study: object) -> None:
    """A work-precision study as :func:`chaplygin.verify.bench.run_study` returns it."""
    keys = {"problem", "method", "rhs", "precision", "median_s", "error"}
    rows = study.get("rows") if isinstance(study, Mapping) else None
    if not isinstance(rows, list) or not all(
        isinstance(r, Mapping)
        and keys <= set(r)
        and all(r[k] is None or isinstance(r[k], int | float) for k in ("median_s", "error"))
        for r in rows
    ):
        raise UserInputError(
            "study must be the result of chaplygin.verify.bench.run_study: a mapping whose "
            f"'rows' are mappings with {', '.join(sorted(keys))} (numbers or None for "
            "median_s and error)"
        )


def work_precision_figure(study: Mapping) -> Figure:
    """Log-log plot of final error against median wall time, one panel per problem.

    Parameters
    ----------
    study : mapping
        The result of :func:`chaplygin.verify.bench.run_study` (its ``rows`` and ``quick``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib import colormaps

    _check_study(study)
    rows = [r for r in study["rows"] if r["median_s"] is not None and r["error"] is not None]
    problems = list(dict.fromkeys(r["problem"] for r in study["rows"]))
    fig = new_figure(figsize=(6.5 * len(problems), 5))
    axes = fig.subplots(1, len(problems), squeeze=False)
    for ax, pname in zip(axes[0], problems, strict=True):
        groups: dict[str, list] = {}
        for r in rows:
            if r["problem"] == pname:
                groups.setdefault(f"{r['method']} {r['rhs']} {r['precision']}", []).append(r)
        markers = {"taylor": "o-", "heyoka": "D:", "odefun": "^-."}
        colours = colormaps["tab20"]
        for i, (label, rs) in enumerate(groups.items()):
            rs = sorted(rs, key=lambda r: r["median_s"])
            ax.loglog(
                [r["median_s"] for r in rs],
                [max(r["error"], 1e-120) for r in rs],
                markers.get(label.split()[0], "s--"),
                color=colours(i % 20),
                label=label,
                ms=5,
            )
        ax.set_xlabel("median wall time [s]")
        ax.set_ylabel("final error (max norm)")
        ax.set_title(pname + (" (quick)" if study.get("quick") else ""))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    return fig
