"""The ``separatrix_delta`` output of a scene: Delta measured on the trace, marked and compared.

On ``M || gamma`` at ``h = h2`` (K01 §3.3) the contact point runs along two spirals whose
centres are ``Delta`` apart (K01 Fig. 4). The scene integrates forward and backward from its
initial point; :func:`chaplygin.numerics.ball.frame_turn.delta_from_traces` finds the two
asymptotic centres of the trace, and :func:`separatrix_delta_report` compares their distance
with the closed form ``pi b/ch(pi mu/2)`` (K01-3.7) and with the full equations and the
quadrature of :func:`chaplygin.numerics.ball.separatrix.delta_three_ways`.

**Tolerance.** The centre is read where two errors balance: the extrapolation leaves
``O(b exp(-3 lam t))`` and the separatrix's instability turns a deviation ``delta`` (the
run's ``rtol``, at least the unit roundoff of the float64 trace) into ``b delta exp(lam t)``;
they are equal at ``exp(lam t) = delta^(-1/4)``, where both are ``b delta^(3/4)``. That is the
tolerance of the comparison: ``tolerance = b max(rtol, eps)^(3/4)``.

References
----------
K01-3.6, K01-3.7, K01-Fig4 (FORMULAS.md).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ...arith import detlinalg, detmath

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "SEPARATRIX_DELTA_EFFECTS",
    "delta_tolerance",
    "separatrix_delta_problem",
    "separatrix_delta_report",
    "separatrix_delta_figure",
    "delta_agrees",
]

#: Effects with which the separatrix of K01 §3.3 and its Delta exist (the plain ball).
SEPARATRIX_DELTA_EFFECTS = frozenset({"contact_point"})

#: Digits of the reference values (closed form, full equations, quadrature).
REFERENCE_DIGITS = 20


def delta_tolerance(b: float, rtol: float) -> float:
    """``b max(rtol, eps)^(3/4)``: how far the measured Delta may be from the exact one.

    Parameters
    ----------
    b : float
        Radius of the ball.
    rtol : float
        Relative tolerance of the run.

    Returns
    -------
    float
    """
    return float(b) * max(float(rtol), float(np.finfo(float).eps)) ** 0.75


def delta_agrees(measured: float, reference: float, tolerance: float) -> bool:
    """The comparison of the output: ``|measured - reference| <= tolerance``.

    Parameters
    ----------
    measured, reference, tolerance : float

    Returns
    -------
    bool
    """
    return bool(abs(float(measured) - float(reference)) <= float(tolerance))


def _inertia(params: dict) -> list[float]:
    return [float(params[f"I{i}"]) for i in (1, 2, 3)]


def _C_of(code: Any, y0: list, params: dict) -> float:
    """``C = (M, gamma)`` at the start, from the model's generated integrals."""
    values = code.numpy.integrals(
        0.0, np.asarray([float(v) for v in y0]), np.asarray([float(v) for v in params.values()])
    )
    return float(np.asarray(values, float)[list(code.integral_names).index("(M,gamma)")])


def separatrix_delta_problem(system: str, code: Any, params: dict, y0: list) -> str | None:
    """Why a scene cannot have the ``separatrix_delta`` output, or None when it can.

    Parameters
    ----------
    system : str
    code : ModelCode
    params : dict of str to number
        The resolved parameters.
    y0 : list
        The resolved initial state.

    Returns
    -------
    str or None
    """
    if system != "chaplygin_ball" or set(code.effects) - SEPARATRIX_DELTA_EFFECTS:
        return (
            "the separatrix and its Delta (K01 §3.3) exist for chaplygin_ball with no effect but "
            f"contact_point; this model is {code.name}"
        )
    I = _inertia(params)
    if len(set(I)) < 3:
        return f"the separatrix needs three different moments of inertia, got I = {I}"
    if _C_of(code, y0, params) == 0:
        return "the separatrix on M || gamma needs C = (M, gamma) != 0"
    return None


def _trace(integration: Any) -> tuple[np.ndarray, np.ndarray]:
    names = list(integration.state_names)
    y = np.asarray(integration.y, dtype=float)
    t = np.asarray(integration.t, dtype=float)
    return t, y[names.index("x")] + 1j * y[names.index("y")]


def separatrix_delta_report(result: Any, rtol: float) -> dict:
    """Delta measured from the forward and backward traces, and three references.

    Parameters
    ----------
    result : SceneResult
        A run with ``backward`` set (the scene asked for ``separatrix_delta``).
    rtol : float
        The run's relative tolerance (the precision's default when the scene gave none).

    Returns
    -------
    dict
        ``measured``, ``closed_form`` (K01-3.7), ``full_equations`` and ``quadrature``
        (:func:`chaplygin.numerics.ball.separatrix.delta_three_ways`, 20 digits), ``mu``,
        ``differences`` (measured minus each), ``tolerance``, ``agrees`` (with the closed
        form), ``centre_forward``/``centre_backward`` (``[x, y]``), ``plateau_spread``,
        ``lambda_t_covered`` (``lam`` times each half of the span), ``energy_offset``
        (``h/h2 - 1`` at the start), ``parallel_offset`` (``|M x gamma|/|M|``) and ``status``
        (of the forward and the backward run); numbers
        as floats, the references also as decimal strings (``*_text``).
    """
    import mpmath

    from ...numerics.ball.frame_turn import delta_from_traces
    from ...numerics.ball.separatrix import delta_three_ways, separatrix_quantities

    res = result.resolved
    p = res.params
    I = sorted(_inertia(p))
    D, b = float(p["D"]), float(p["b"])
    C = _C_of(res.code, res.y0, p)
    with mpmath.workdps(REFERENCE_DIGITS + 10):
        lam = float(separatrix_quantities(I, D, C)["lam"])
        refs = delta_three_ways(I, D, b, REFERENCE_DIGITS, C=C)
    t_f, z_f = _trace(result.integration)
    t_b, z_b = _trace(result.backward)
    dt = abs(t_f[1] - t_f[0])
    lag = max(1, min(int(round(1 / (lam * dt))), (min(len(z_f), len(z_b)) - 1) // 3))
    m = delta_from_traces(z_f, z_b, lag)
    tol = delta_tolerance(b, rtol)
    values = {
        "closed_form": refs.closed,
        "full_equations": refs.ode,
        "quadrature": refs.quadrature,
    }
    y0 = {n: float(v) for n, v in zip(res.code.state, res.y0, strict=True)}
    M = np.array([y0["M1"], y0["M2"], y0["M3"]])
    g = np.array([y0["gamma1"], y0["gamma2"], y0["gamma3"]])
    h = float(
        np.asarray(
            res.code.numpy.integrals(
                0.0, np.asarray(list(y0.values())), np.asarray([float(v) for v in p.values()])
            ),
            float,
        )[list(res.code.integral_names).index("H")]
    )
    h2 = C**2 / (2 * I[1])
    span = float(t_f[-1] - t_f[0])
    report = {
        "measured": m["delta"],
        "mu": float(refs.mu),
        **{k: float(v) for k, v in values.items()},
        **{f"{k}_text": mpmath.nstr(v, REFERENCE_DIGITS) for k, v in values.items()},
        "differences": {k: m["delta"] - float(v) for k, v in values.items()},
        "tolerance": tol,
        "tolerance_rule": "b max(rtol, eps)^(3/4)",
        "rtol": float(rtol),
        "agrees": delta_agrees(m["delta"], float(refs.closed), tol),
        "centre_forward": [m["centre_forward"].real, m["centre_forward"].imag],
        "centre_backward": [m["centre_backward"].real, m["centre_backward"].imag],
        "plateau_spread": m["spread"],
        "read_at_t": [float(t_f[m["index_forward"]]), float(t_b[m["index_backward"]])],
        "status": [int(result.integration.status), int(result.backward.status)],
        "lambda": lam,
        "lambda_t_covered": lam * span,
        "energy_offset": h / h2 - 1,
        "parallel_offset": detlinalg.norm(np.cross(M, g)) / detlinalg.norm(M),
    }
    # the extrapolation needs exp(lam t) ~ rtol^(-1/4) on each side (see the module docstring)
    needed = 0.25 * detmath.log(1 / max(float(rtol), float(np.finfo(float).eps))) + 3
    if lam * span < needed:
        report["note"] = (
            f"lambda t reaches {lam * span:.3g} on each side, the centres need about "
            f"{needed:.3g}: give run.t_end - run.t_start >= {needed / lam:.4g}"
        )
    return report


def separatrix_delta_figure(result: Any, report: dict, title: str = "") -> Figure:
    """Both halves of the trace, their centres and Delta, with a zoom on the centres.

    Parameters
    ----------
    result : SceneResult
        A run with ``backward`` set.
    report : dict
        :func:`separatrix_delta_report`'s.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 6))
    ax = fig.subplots()
    _, z_f = _trace(result.integration)
    _, z_b = _trace(result.backward)
    cf = complex(*report["centre_forward"])
    cb = complex(*report["centre_backward"])
    label = (
        f"Delta measured = {report['measured']:.9g}\n"
        f"closed form pi b/ch(pi mu/2) = {report['closed_form']:.9g}\n"
        f"difference {report['differences']['closed_form']:.2e} "
        f"(tolerance {report['tolerance']:.1e})"
    )

    def draw(axis, lw):
        axis.plot(z_b.real, z_b.imag, lw=lw, color="tab:blue", label="t < t_start")
        axis.plot(z_f.real, z_f.imag, lw=lw, color="tab:red", label="t > t_start")
        axis.plot([cb.real], [cb.imag], "o", color="tab:blue", mfc="w", ms=7)
        axis.plot([cf.real], [cf.imag], "o", color="tab:red", mfc="w", ms=7)
        axis.annotate(
            "", xy=(cf.real, cf.imag), xytext=(cb.real, cb.imag),
            arrowprops={"arrowstyle": "<->", "color": "k", "lw": 1.2},
        )  # fmt: skip

    draw(ax, 0.8)
    ax.plot([], [], "o", color="k", mfc="w", label="centres (t -> -oo, +oo)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title(f"{title}\n{label}", fontsize=8)
    # zoom on the two centres: Delta can be small against the spirals (K01 Fig. 4a)
    mid, half = (cf + cb) / 2, max(abs(cf - cb), 1e-12) * 1.5
    inset = ax.inset_axes([0.62, 0.03, 0.36, 0.36])
    draw(inset, 0.6)
    inset.set_xlim(mid.real - half, mid.real + half)
    inset.set_ylim(mid.imag - half, mid.imag + half)
    inset.set_aspect("equal")
    inset.tick_params(labelsize=5)
    inset.set_title("zoom: Delta", fontsize=6)
    fig.tight_layout()
    return fig
