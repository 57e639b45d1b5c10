"""``chaplygin bifurcation``: bifurcation diagrams of K01 Figs. 1-3 and BKM12 Figs. 2, 3, 5.

The curves are the derived ones (``derive/bifurcation.py``, proved in
``verify/claims/bifurcation.py``); each family is drawn solid when its Floquet multipliers
(``numerics/stability.py``, computed here at a sample point of the family) lie on the
unit circle and dashed otherwise. Random seeded initial states on the levels are
integrated for a short time and their integral values drawn as dots: the region of
motion (BKM12-Fig2region).

References
----------
K01-Fig1, K01-Fig2, K01-Fig3, BKM12-24, BKM12-Fig3, BKM12-2.7c, BKM12-1.5stab8.
"""

from __future__ import annotations

import argparse
from functools import cache, lru_cache

import numpy as np
import sympy as sp

from ..derive.bifurcation import bifurcation_curve
from ..derive.errors import UserInputError
from ..derive.systems import build_model

__all__ = [
    "add_parser",
    "FIGURES",
    "draw",
    "sample_levels",
    "family_stability",
    "support_stability",
    "sigma",
]

#: figure -> (system, default parameters, title)
FIGURES = {
    "k01-1": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1, "C": 0}, "K01 Fig. 1"),
    "k01-2": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1, "C": 1}, "K01 Fig. 2b"),
    "k01-3": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1, "C": 1}, "K01 Fig. 3"),
    "bkm12-2": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1}, "BKM12 Fig. 2"),
    "bkm12-3": ("chaplygin_ball", {"I": (1, 1.5, 3), "D": 1}, "BKM12 Fig. 3"),
    "bkm12-5": (
        "spherical_support",
        {"I": (1, 1.5, 3), "D_iso": 0.5, "D_al": 0.3, "D_be": -0.2},
        "BKM12 Fig. 5",
    ),
}
COLORS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange")


@cache
def _sigma_functions():
    """Derived ``E = Sigma_i(C, M_gamma)`` of the ball, lambdified (I1, I2, I3, D)."""
    model = build_model("chaplygin_ball", ())
    C, Mg = sp.Symbol("C", real=True), sp.Symbol("M_gamma", real=True)
    return [
        sp.lambdify([C, Mg, *model.params], bifurcation_curve(model, i), "numpy") for i in range(3)
    ]


def sigma(i: int, C, Mg, I, D):
    """Energy ``E = 2h`` on the derived curve ``Sigma_i`` (BKM12-Sigma_i, K01-3.2c)."""
    return _sigma_functions()[i](C, Mg, *I, D)


def family_stability(I, D, C: float = 1.0, Mg: float = 0.0) -> list[tuple[bool, float]]:
    """(stable, max |multiplier|) of the steady rotations about e_1, e_2, e_3."""
    from ..numerics.stability import steady_rotation_floquet

    return [(r.stable, r.max_abs) for r in steady_rotation_floquet(tuple(I), D, C, Mg)]


def euler_stability(I, D, Ep: float) -> tuple[bool, float]:
    """(stable, max |multiplier|) of the orbit M = sqrt(C) gamma at E' (Sigma_4)."""
    from ..numerics.stability import euler_floquet

    r = euler_floquet(tuple(I), D, Ep)
    return r.stable, r.max_abs


@lru_cache(maxsize=16)
def support_stability(params) -> list[tuple[bool, float]]:
    """(stable, max |multiplier|) of the support's steady rotations (a generic frame)."""
    from ..numerics.stability import floquet, support_steady_state

    c, s = np.cos(0.7), np.sin(0.7)
    R1 = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    R2 = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    frame = R1 @ R2
    out = []
    for i in range(3):
        y0, T = support_steady_state(params, i, 1.0, frame)
        r = floquet(None, None, y0, T, system="spherical_support", params=params)
        out.append((r.stable, r.max_abs))
    return out


def _random_unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1)[:, None]


def sample_levels(
    I,
    D,
    n: int,
    seed: int,
    C_range=(0.05, 1.0),
    Mg=None,
    g=None,
    t_end: float = 2.0,
):
    """Random seeded ball states, integrated to ``t_end``: their ``(C, M_gamma, E)``.

    ``Mg`` fixes ``(M, gamma)``; ``g`` fixes ``M_gamma/sqrt(C)`` (normalised diagram);
    otherwise ``(M, gamma)`` is random. Returns an array of shape (n, 3) with the values
    at ``t_end``, the largest relative drift of the integrals and the final states
    (shape (n, 6)).
    """
    from ..numerics import integrate

    rng = np.random.default_rng(seed)
    gam = _random_unit(rng, n)
    out, drift, states = [], 0.0, []
    for k in range(n):
        C = rng.uniform(*C_range)
        perp = rng.normal(size=3)
        perp -= perp.dot(gam[k]) * gam[k]
        perp /= np.linalg.norm(perp)
        if Mg is not None:
            mg = Mg
        elif g is not None:
            mg = g * np.sqrt(C)
        else:
            mg = rng.uniform(-1, 1) * np.sqrt(C)
        M = mg * gam[k] + np.sqrt(max(C - mg**2, 0.0)) * perp
        r = integrate(
            "chaplygin_ball",
            {"M": tuple(M), "gamma": tuple(gam[k])},
            t_end,
            {"I": tuple(I), "D": D},
            rtol=1e-10,
            atol=1e-12,
        )
        y = r.y[:, -1]
        Mv, gv = y[:3], y[3:]
        code = _ball_code()
        E = 2 * float(code.numpy.integrals(0.0, y, [*I, D])[0])
        out.append((Mv @ Mv, Mv @ gv, E))
        states.append(y)
        drift = max(drift, max(r.drift.values()))
    return np.array(out), drift, np.array(states)


@cache
def _ball_code():
    from ..numerics.code import load_model_code

    return load_model_code("chaplygin_ball")


def _style(stable: bool) -> str:
    return "-" if stable else "--"


def _legend_stab(ax):
    from matplotlib.lines import Line2D

    handles = [
        Line2D([], [], color="k", ls="-", label="stable (|multipliers| = 1)"),
        Line2D([], [], color="k", ls="--", label="unstable"),
        Line2D([], [], color="0.5", marker=".", ls="", label="integrated states"),
    ]
    return handles


def _draw_kilin(ax, I, D, C, samples, seed, traces=None):
    """(n, h) plane: p_i: h = Sigma_i/2, and the segment n = C^2 (M || gamma)."""
    stab = family_stability(I, D, 1.0 + C**2, C)
    n_max = 3.0 if C == 0 else 3.0 * C**2
    n = np.linspace(C**2, n_max, 200)
    for i in range(3):
        h = sigma(i, n, C, I, D) / 2
        ax.plot(
            n,
            h,
            _style(stab[i][0]),
            color=COLORS[i],
            label=f"p{i + 1} (max|mu| = {stab[i][1]:.3g})",
        )
    if C != 0:
        hs = sorted(C**2 / (2 * np.asarray(I, float)))  # h_i = C^2/(2 I_i) on n = C^2
        Ep_mid = D * 2 * hs[1] / C**2
        for lo, hi in ((hs[0], hs[1]), (hs[1], hs[2])):
            Ep = D * (lo + hi) / C**2  # E' = 2 h D/C^2 at the arc's midpoint
            st, mu = euler_stability(I, D, Ep)
            ax.plot([C**2, C**2], [lo, hi], _style(st), color=COLORS[3], lw=2)
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
        _draw_traces(ax, traces, I, D, C, vals, states, stab)
    return drift


def _draw_traces(ax, tax, I, D, C, vals, states, stab):
    """K01 Fig. 3: contact-point traces of three states (above p2, below p2, near p2)."""
    from ..numerics import integrate
    from ..numerics.stability import critical_state

    h2 = sigma(1, vals[:, 0], C, I, D) / 2
    above = int(np.argmax(vals[:, 2] / 2 - h2 > 0.05))
    below = int(np.argmax(h2 - vals[:, 2] / 2 > 0.05))
    y2, _ = critical_state(I, D, 1, 1.0 + C**2, C)
    near = y2 + 1e-4 * np.array([1.0, -1.0, 0.5, 0.3, -0.2, 0.1])
    near[3:] /= np.linalg.norm(near[3:])
    picks = [("a", states[above]), ("b", states[below]), ("c (near p2)", near)]
    for k, (label, y) in enumerate(picks):
        M, g = y[:3], y[3:]
        n_, h_ = M @ M, None
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
        E = 2 * float(_ball_code().numpy.integrals(0.0, y[:6], [*I, D])[0])
        h_ = E / 2
        ax.annotate(label[0], (n_, h_), color=COLORS[k], fontsize=10, weight="bold")
    tax.grid(alpha=0.3)
    tax.set_xlabel("x (contact point, b = 1)")
    tax.set_ylabel("y")
    tax.legend(fontsize=7)
    tax.set_title("contact-point traces, t in [0, 150]", fontsize=9)


def _draw_bkm12_2(ax, I, D, samples, seed):
    stab = family_stability(I, D, 1.0, 0.0)
    C = np.linspace(0, 1, 100)
    A = 1 / (np.asarray(I, float) + D)
    for i in range(3):
        ax.plot(
            C,
            A[i] * C,
            _style(stab[i][0]),
            color=COLORS[i],
            label=f"E = A{i + 1} C (max|mu| = {stab[i][1]:.3g})",
        )
    vals, drift, states = sample_levels(I, D, samples, seed, C_range=(0.02, 1.0), Mg=0.0)
    ax.plot(vals[:, 0], vals[:, 2], ".", color="0.5", ms=3)
    ax.set_xlabel("C = (M, M)")
    ax.set_ylabel("E = (M, omega)")
    return drift


def _draw_bkm12_3(ax, I, D, samples, seed):
    b = D / (np.asarray(I, float) + D)
    g = np.linspace(-1, 1, 201)
    stab = family_stability(I, D, 1.0, 0.5)
    for i in range(3):
        Ep = sigma(i, 1.0, g, I, D) * D  # E' = E D/C at C = 1
        ax.plot(
            g,
            Ep,
            _style(stab[i][0]),
            color=COLORS[i],
            label=f"Sigma_{i + 1} (max|mu| = {stab[i][1]:.3g})",
        )
    ends = sorted(b / (1 - b))
    for gv, k in ((1, 4), (-1, 5)):
        for lo, hi in ((ends[0], ends[1]), (ends[1], ends[2])):
            st, _ = euler_stability(I, D, (lo + hi) / 2)
            ax.plot([gv, gv], [lo, hi], _style(st), color=COLORS[3 if k == 4 else 4], lw=2)
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


def _draw_bkm12_5(fig, params, samples, seed):
    """Surfaces E'_i on the sphere of (g_al, g_be, g_ga), drawn over the (g_al, g_be) disc."""
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
        cs = ax.contour(X, Y, Ep, levels=10, colors=COLORS[i], linestyles=_style(stab[i][0]))
        ax.clabel(cs, fontsize=6, fmt="%.2f")
        ax.set_title(
            f"E'_{i + 1} ({'stable' if stab[i][0] else 'unstable'}, max|mu| = {stab[i][1]:.3g})",
            fontsize=8,
        )
        ax.set_aspect("equal")
        ax.add_patch(
            __import__("matplotlib.patches", fromlist=["Circle"]).Circle(
                (0, 0), 1, fill=False, lw=0.5
            )
        )
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


def support_sample(params, n: int, seed: int, t_end: float = 1.0):
    """Random support states integrated to ``t_end``: ``(g_al, g_be, position)``.

    ``position`` is ``(E' - min_i E'_i)/(max_i E'_i - min_i E'_i)`` with ``E'_i`` the
    surfaces of BKM12-2.7c at the state's ``g``: in ``[0, 1]`` inside the region of motion.
    """
    from ..numerics import integrate
    from ..numerics.code import load_model_code

    rng = np.random.default_rng(seed)
    code = load_model_code("spherical_support")
    I, D_iso, D_al, D_be = params[:3], params[3], params[4], params[5]
    J = np.asarray(I, float) + D_iso
    out, drift = [], 0.0
    for _ in range(n):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        w, x, y, z = q
        R = np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
            ]
        )
        M = rng.normal(size=3)
        y0 = {"M": tuple(M), "alpha": tuple(R[0]), "beta": tuple(R[1]), "gamma": tuple(R[2])}
        p = {"I": tuple(I), "D_iso": D_iso, "D_al": D_al, "D_be": D_be}
        r = integrate("spherical_support", y0, t_end, p, rtol=1e-10, atol=1e-12)
        yv = r.y[:, -1]
        Mv, al, be, ga = yv[:3], yv[3:6], yv[6:9], yv[9:12]
        C = Mv @ Mv
        gx = np.array([Mv @ al, Mv @ be, Mv @ ga]) / np.sqrt(C)
        E = 2 * float(code.numpy.integrals(0.0, yv, [*I, D_iso, D_al, D_be])[0])
        surf = [
            gx[0] ** 2 / (J[i] - D_al) + gx[1] ** 2 / (J[i] - D_be) + gx[2] ** 2 / J[i]
            for i in range(3)
        ]
        lo, hi = min(surf), max(surf)
        out.append((gx[0], gx[1], (E / C - lo) / (hi - lo)))
        drift = max(drift, max(r.drift.values()))
    return np.array(out), drift


def draw(figure: str, out: str, params: dict, samples: int = 60, seed: int = 1) -> dict:
    """Draw one figure into ``out`` (PNG); returns a summary (drift of the samples).

    Raises
    ------
    UserInputError
        Unknown figure or inadmissible parameters.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if figure not in FIGURES:
        raise UserInputError(f"unknown figure {figure!r}; valid: {', '.join(FIGURES)}")
    system, defaults, title = FIGURES[figure]
    p = {**defaults, **params}
    unknown = set(params) - set(defaults)
    if unknown:
        raise UserInputError(
            f"parameter(s) {', '.join(sorted(unknown))} not used by {figure}; "
            f"valid: {', '.join(defaults)}"
        )
    I = tuple(float(v) for v in p["I"])
    if len(I) != 3 or min(I) <= 0:
        raise UserInputError(f"I needs three positive values, got {p['I']}")
    if system == "chaplygin_ball" and float(p["D"]) <= 0:
        raise UserInputError(f"D must be positive, got {p['D']}")
    if samples < 1:
        raise UserInputError(f"--samples must be at least 1, got {samples}")
    if figure == "bkm12-5":
        fig = plt.figure(figsize=(16, 4.4))
        params6 = (*I, float(p["D_iso"]), float(p["D_al"]), float(p["D_be"]))
        J = np.asarray(I) + params6[3]
        if params6[3] < 0 or min(J) <= max(params6[4], params6[5], 0):
            raise UserInputError(
                "need D_iso >= 0 and I_i + D_iso > D_al, D_be (a physical support)"
            )
        drift = _draw_bkm12_5(fig, params6, samples, seed)
        fig.suptitle(
            f"{title}: bifurcation surfaces E' = E/C on g_al^2 + g_be^2 + g_ga^2 = 1 "
            f"(I = {I}, D_iso = {params6[3]}, D_al = {params6[4]}, D_be = {params6[5]})"
        )
    else:
        D = float(p["D"])
        if figure == "k01-3":
            fig, (ax, tax) = plt.subplots(1, 2, figsize=(13, 5))
        else:
            fig, ax = plt.subplots(figsize=(7, 5))
            tax = None
        if figure.startswith("k01"):
            C = float(p["C"])
            drift = _draw_kilin(ax, I, D, C, samples, seed, traces=tax)
            ax.set_title(f"{title}: I = {I}, D = {D}, C = (M, gamma) = {C}")
        elif figure == "bkm12-2":
            drift = _draw_bkm12_2(ax, I, D, samples, seed)
            ax.set_title(f"{title}: (M, gamma) = 0, I = {I}, D = {D}")
        else:
            drift = _draw_bkm12_3(ax, I, D, samples, seed)
            ax.set_title(f"{title}: normalised diagram, I = {I}, D = {D}")
        handles, _ = ax.get_legend_handles_labels()
        ax.legend(handles=handles + _legend_stab(ax), fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return {"figure": figure, "out": out, "samples": samples, "drift": drift}


def _parse_params(items) -> dict:
    from ..numerics.inputs import parse_number

    out: dict[str, object] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name or not value.strip():
            raise UserInputError(f"--param expects NAME=VALUE[,VALUE...], got {item!r}")
        if name in out:
            raise UserInputError(f"--param {name} given twice")
        try:
            vals = [float(parse_number(v.strip())) for v in value.split(",")]
        except (ValueError, TypeError, ZeroDivisionError) as exc:
            raise UserInputError(f"--param {name}: {exc}") from None
        if not all(np.isfinite(vals)):
            raise UserInputError(f"--param {name}: values must be finite, got {value}")
        out[name] = tuple(vals) if name == "I" else vals[0]
        if name != "I" and len(vals) != 1:
            raise UserInputError(f"--param {name} takes one value, got {len(vals)}")
    return out


def _default_figure(system: str, params: dict) -> str:
    if system == "spherical_support":
        return "bkm12-5"
    if system == "chaplygin_ball":
        return "k01-1" if float(params.get("C", 1) or 0) == 0 else "k01-2"
    raise UserInputError(
        f"no bifurcation diagram for system {system!r}; valid: chaplygin_ball, spherical_support"
    )


def _cmd(args) -> int:
    params = _parse_params(args.param)
    figure = args.figure or _default_figure(args.system, params)
    if figure not in FIGURES:
        raise UserInputError(f"unknown figure {figure!r}; valid: {', '.join(FIGURES)}")
    if FIGURES[figure][0] != args.system:
        raise UserInputError(
            f"figure {figure} is a diagram of {FIGURES[figure][0]}, not {args.system}"
        )
    if not args.out.lower().endswith(".png"):
        raise UserInputError(f"--out must name a .png file, got {args.out!r}")
    summary = draw(figure, args.out, params, samples=args.samples, seed=args.seed)
    print(
        f"wrote {summary['out']} ({figure}; {summary['samples']} integrated states, "
        f"largest relative drift of their integrals {summary['drift']:.1e})"
    )
    return 0


def add_parser(sub) -> None:
    """Register ``chaplygin bifurcation``."""
    p = sub.add_parser(
        "bifurcation", help="draw a bifurcation diagram (K01 Figs. 1-3, BKM12 Figs. 2, 3, 5)"
    )
    p._sub = "bifurcation"
    p.add_argument("system", help="chaplygin_ball or spherical_support")
    p.add_argument(
        "--param",
        action="append",
        metavar="NAME=VALUE[,VALUE...]",
        help="I=1,1.5,3 D=1 C=1 (ball; C = (M, gamma) for K01 figures); "
        "I, D_iso, D_al, D_be (support)",
    )
    p.add_argument("--figure", default=None, help=", ".join(FIGURES))
    p.add_argument("--out", required=True, help="PNG file to write")
    p.add_argument("--samples", type=int, default=60, help="integrated random states (default 60)")
    p.add_argument("--seed", type=int, default=1)
    p.set_defaults(func=_cmd)
    _ = argparse  # the parser class comes from the caller
