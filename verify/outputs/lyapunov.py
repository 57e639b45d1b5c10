"""The ``lyapunov`` scene output: Lyapunov spectra of the scene's orbit (an analysis).

.. code-block:: toml

    [outputs.lyapunov]
    iterations = 8000        # renormalisation intervals averaged per initial state
    transient = 500          # intervals discarded first
    # interval = 5.87        # time between QRs (default: the forcing period 2 pi/Omega)
    spectrum = "both"        # "level_set", "full" or "both"
    states = 3               # initial states for the error bar (the scene's and neighbours)
    windows = 10             # batch-means windows
    plot = true              # the convergence plot

The numbers (``summary.json`` under ``analyses.lyapunov``, and ``--json``): per spectrum the
exponents with error bars **per map iteration** (per forcing period ``2 pi/Omega``, for
time-periodic models) and **per unit time**, each block naming its units; the sum of the
exponents against the time-averaged divergence of the vector field and their difference
(and ``-d/dt log rho`` where the model has an invariant density). ``lyapunov.nc`` holds the
running estimates behind the convergence plot. The integration uses ``[run] rtol``/``atol``
(default 1e-10/1e-12) in double precision (DOP853 with the variational equations in C).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..scene.outputs import Analysis, AnalysisResult, SceneError, register_analysis
from .lyapunov_table import LyapunovOutput

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ...numerics.dynamics.lyapunov import LyapunovSpectrum

__all__ = ["LyapunovOutput", "convergence_figure", "run_lyapunov"]


def _check(scene: Any, code: Any, spec: LyapunovOutput) -> None:
    if str(scene.run_options.precision) != "double":
        raise SceneError(
            "the lyapunov output runs in double precision (DOP853 with the variational "
            f"equations in C); got precision {scene.run_options.precision!r}",
            scene.source,
            "run.precision",
        )
    if spec.interval is None and "Omega" not in code.params:
        raise SceneError(
            f"{code.name} is autonomous: give outputs.lyapunov.interval (a time)",
            scene.source,
            "outputs.lyapunov.interval",
        )
    if spec.iterations < spec.windows:
        raise SceneError(
            f"iterations ({spec.iterations}) must be at least windows ({spec.windows})",
            scene.source,
            "outputs.lyapunov.iterations",
        )


def convergence_figure(spectra: dict[str, LyapunovSpectrum], title: str = "") -> Figure:
    """Running estimates of the exponents against the number of intervals, per initial state.

    Parameters
    ----------
    spectra : dict of str to LyapunovSpectrum
        ``"level_set"`` and/or ``"full"``.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
        One panel per spectrum; per map iteration for time-periodic models, else per unit
        time; the final estimates with their error bars as bands.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 3.6 * len(spectra)))
    axes = fig.subplots(len(spectra), 1, squeeze=False)[:, 0]
    for ax, (kind, sp) in zip(axes, spectra.items(), strict=True):
        per_iter = sp.period is not None
        scale = sp.period if per_iter else 1.0
        units = "per iteration" if per_iter else "per unit time"
        x = sp.convergence_iterations
        for j in range(sp.exponents.size):
            color = f"C{j % 10}"
            for s in range(sp.convergence.shape[0]):
                ax.plot(x, sp.convergence[s, :, j] * scale, color=color, lw=0.8,
                        alpha=1.0 if s == 0 else 0.45,
                        label=f"λ{j + 1} = {sp.exponents[j] * scale:.4f} ± "
                        f"{sp.errors[j] * scale:.4f}" if s == 0 else None)  # fmt: skip
            lo = (sp.exponents[j] - sp.errors[j]) * scale
            hi = (sp.exponents[j] + sp.errors[j]) * scale
            ax.axhspan(lo, hi, color=color, alpha=0.15)
        ax.axhline(0, color="k", lw=0.5)
        final = sp.exponents * scale
        width = max(0.5 * float(np.ptp(final)), 5 * float(sp.errors.max()) * scale, 1e-3)
        ax.set_ylim(float(final.min()) - width, float(final.max()) + width)
        ax.set_xscale("log")
        ax.set_xlabel("renormalisation intervals" + (" (map iterations)" if per_iter else ""))
        ax.set_ylabel(f"exponent ({units})")
        ax.set_title(
            f"{kind.replace('_', ' ')} spectrum: {sp.per_state.shape[0]} initial states, "
            f"{sp.transient} intervals of transient discarded; bands: final value ± error",
            fontsize=9,
        )
        ax.legend(fontsize=7, loc="lower right")
        ax.grid(alpha=0.3)
    fig.suptitle(f"Lyapunov exponents: {title}", fontsize=10)
    fig.tight_layout()
    return fig


def run_lyapunov(scene: Any, resolved: Any, spec: LyapunovOutput, progress: bool) -> AnalysisResult:
    """Compute the spectra a scene asks for.

    Parameters
    ----------
    scene : chaplygin.verify.scene.Scene
    resolved : chaplygin.verify.scene.Resolved
    spec : LyapunovOutput
    progress : bool
        Unused (the runs are in C).

    Returns
    -------
    AnalysisResult
        Summary per spectrum (exponents per iteration and per unit time with error bars, the
        sum against the average divergence), running estimates, the convergence figure.

    Raises
    ------
    SceneError
        Settings the computation refuses (the message says which).
    """
    from ...derive.errors import UserInputError
    from ...numerics.dynamics.lyapunov import lyapunov_spectrum
    from ...numerics.dynamics.variational import VariationalSystem
    code = resolved.code
    params = [float(resolved.params[name]) for name in code.params]
    y0 = [float(v) for v in resolved.y0]
    run = scene.run_options
    rtol = float(run.rtol) if run.rtol is not None else 1e-10
    atol = float(run.atol) if run.atol is not None else 1e-12
    kinds = ("level_set", "full") if spec.spectrum == "both" else (spec.spectrum,)
    spectra: dict[str, LyapunovSpectrum] = {}
    try:
        system = VariationalSystem(code, params, rtol=rtol, atol=atol)
        for kind in kinds:
            spectra[kind] = lyapunov_spectrum(
                code, params, y0, spectrum=kind, intervals=spec.iterations,
                transient=spec.transient, interval=spec.interval, t0=float(resolved.t_span[0]),
                states=spec.states, spread=spec.spread, windows=spec.windows, system=system,
            )  # fmt: skip
    except UserInputError as exc:
        raise SceneError(str(exc), scene.source, "outputs.lyapunov") from None
    summary: dict[str, Any] = {kind: sp.summary() for kind, sp in spectra.items()}
    arrays: dict[str, tuple[tuple[str, ...], np.ndarray, dict]] = {}
    for kind, sp in spectra.items():
        arrays[f"{kind}_iterations"] = (
            (f"{kind}_checkpoint",),
            sp.convergence_iterations.astype(np.int32),
            {"long_name": "renormalisation intervals averaged", "units": "1"},
        )
        arrays[f"{kind}_running"] = (
            ("state", f"{kind}_checkpoint", f"{kind}_exponent"),
            sp.convergence,
            {"long_name": f"running {kind} Lyapunov exponent estimates", "units": "1/time"},
        )
        arrays[f"{kind}_exponents"] = (
            (f"{kind}_exponent",),
            sp.exponents,
            {"long_name": f"{kind} Lyapunov exponents", "units": "1/time"},
        )
        arrays[f"{kind}_errors"] = (
            (f"{kind}_exponent",),
            sp.errors,
            {"long_name": "standard errors of the exponents", "units": "1/time"},
        )
    from ..figure_style import literal_text

    title = literal_text(scene.title or code.name)
    figures = {"lyapunov": lambda: convergence_figure(spectra, title)}
    if not math.isfinite(sum(sp.sum_of_exponents for sp in spectra.values())):
        raise SceneError("the exponents are not finite", scene.source, "outputs.lyapunov")
    return AnalysisResult(summary=summary, arrays=arrays, figures=figures)


LYAPUNOV = register_analysis(
    Analysis(
        key="lyapunov",
        run=run_lyapunov,
        check=_check,
        description="Lyapunov spectra (Benettin/QR on the variational equations in C): "
        "exponents per map iteration and per unit time with error bars, sum vs mean divergence",
    )
)
