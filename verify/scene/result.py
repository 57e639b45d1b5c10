"""What a scene run returns (:class:`SceneResult`: arrays, figures, ``summary.json``) and how
its files are written (into a checked output folder, atomically)."""

from __future__ import annotations

import html
import json
import math
import platform
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...arith import detmath
from .errors import SceneError, did_you_mean
from .outputs import AnalysisResult
from .resolution import Resolved, decimal_text, quantity_names

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .schema import Scene

__all__ = [
    "SceneResult",
    "package_version",
    "prepare_output",
    "software_versions",
    "write_atomically",
]


@dataclass
class SceneResult:
    """What :meth:`Scene.run` returns: the arrays, the drift, figures and the summary.

    Attributes
    ----------
    scene : Scene
    resolved : Resolved
    integration : IntegrationResult or None
        The scene's trajectory; None when its outputs are analyses only
        (:func:`needs_trajectory`).
    wall_s : float
        Wall time of the whole run (set-up included).
    analyses : dict of str to AnalysisResult
        The analyses' results by output key (:mod:`chaplygin.verify.scene.outputs`).
    backward : IntegrationResult or None
        With ``outputs.separatrix_delta``: the run from ``t_start`` back to
        ``2 t_start - t_end``.
    """

    scene: Scene
    resolved: Resolved
    integration: Any
    wall_s: float
    analyses: dict[str, AnalysisResult] = field(default_factory=dict)

    def _trajectory(self) -> Any:
        if self.integration is None:
            raise SceneError(
                "this run integrated no trajectory (its outputs are analyses only); "
                "add [outputs.trajectory] to the scene to get one",
                self.scene.source,
                "outputs",
            )
        return self.integration

    backward: Any = None
    _delta_report: dict | None = field(default=None, repr=False)

    # ------------------------------------------------------------------- arrays
    @property
    def t(self) -> np.ndarray:
        """Output times (float64)."""
        return np.asarray(self._trajectory().t, dtype=float)

    @property
    def y(self) -> dict[str, np.ndarray]:
        """State components by name (float64 arrays)."""
        arr = np.asarray(self._trajectory().y, dtype=float)
        return dict(zip(self.integration.state_names, arr, strict=True))

    @property
    def drift(self) -> dict[str, float]:
        """Largest relative change of every integral (absolute where its start is ~0)."""
        return dict(self._trajectory().drift)

    @property
    def success(self) -> bool:
        """True when the trajectory reached ``t_end`` (True without a trajectory)."""
        return self.integration is None or self.integration.success

    def _p(self) -> np.ndarray:
        return np.asarray([float(v) for v in self.resolved.params.values()])

    def quantity(self, name: str) -> np.ndarray:
        """A state component, auxiliary quantity (``omega1``), integral or ``I1(t)``..``I3(t)``.

        Parameters
        ----------
        name : str

        Returns
        -------
        ndarray

        Raises
        ------
        SceneError
            An unknown name (the message lists the valid ones).
        """
        code = self.resolved.code
        y = np.asarray(self._trajectory().y, dtype=float)
        if name in code.state:
            return y[code.state.index(name)]
        if name in code.aux_names:
            return np.asarray(code.numpy.aux(self.t, y, self._p()))[code.aux_names.index(name)]
        if name in code.integral_names:
            values = code.numpy.integrals(self.t, y, self._p())
            return np.asarray(values)[code.integral_names.index(name)] * np.ones_like(self.t)
        m = re.fullmatch(r"I([123])\(t\)", name)
        if m and "I1" in code.params:
            p = self.resolved.params
            base = float(p[f"I{m.group(1)}"])
            if m.group(1) == "2" or "J_off" not in p:
                return base * np.ones_like(self.t)
            off = float(p["J_off"]) + float(p["delta"]) * detmath.sin(
                float(p["Omega"]) * np.asarray(self.t, dtype=float)
            )
            return base + off**2
        valid = self.quantity_names()
        raise SceneError(
            f"unknown quantity {name!r}; valid: {', '.join(valid)}{did_you_mean(name, valid)}",
            self.scene.source,
            "outputs.series.quantities",
        )

    def quantity_names(self) -> list[str]:
        """Every name :meth:`quantity` accepts.

        Returns
        -------
        list of str
        """
        return quantity_names(self.resolved.code)

    def integral_change(self) -> dict[str, np.ndarray]:
        """``|F(t) - F(0)|``, relative to ``|F(0)|`` where that is not ~0, per integral.

        Returns
        -------
        dict of str to ndarray
        """
        code = self.resolved.code
        values = np.asarray(
            code.numpy.integrals(self.t, np.asarray(self.integration.y, float), self._p()), float
        )
        values = values * np.ones((len(values), len(self.t)))
        out = {}
        for i, name in enumerate(code.integral_names):
            ref = abs(values[i, 0])
            change = np.abs(values[i] - values[i, 0])
            out[name] = change / ref if name not in self.integration.drift_absolute else change
        return out

    # ------------------------------------------------------------------ figures
    def contact_trace_figure(self) -> Figure:
        """The contact point in the plane (``x, y``); on a fixed sphere, on the sphere (the
        point ``+-R ((gamma, alpha), (gamma, beta), (gamma, zeta))``, fixed frame).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..outputs.trajectory_figures import contact_trace_figure, sphere_trace_figure

        y = self.y
        if "x" not in y and "alpha1" in y and "zeta1" in y:  # on a fixed sphere
            system = self.scene._described.rolling_system()  # (only a description has it)
            R = self._value(system._parsed["support_radius"])
            normal = self._sphere_normal(system) * (-R if system.side == "inside" else R)
            axes = [np.array([y[f"{n}{i}"] for i in (1, 2, 3)]) for n in ("alpha", "beta", "zeta")]
            points = np.array([(normal * a).sum(axis=0) for a in axes])  # inside: at -R n
            return sphere_trace_figure(points, R, self._title())
        spec = self.scene.outputs.contact_trace
        aspect = spec.aspect if spec is not None else "equal"
        return contact_trace_figure(y["x"], y["y"], self._title(), aspect)

    def _value(self, expr: Any) -> float:
        """A description's expression at the run's parameter values."""
        params = self.resolved.params
        return float(expr.xreplace({s: params[s.name] for s in expr.free_symbols
                                    if s.name in params}))  # fmt: skip

    def _sphere_normal(self, system: Any) -> np.ndarray:
        """The sphere's unit normal at the contact along the run, body axes: ``gamma`` of a
        spherical body, ``-grad f(r)/|grad f(r)|`` of a convex one."""
        y = self.y
        if "gamma1" in y:
            return np.array([y[f"gamma{i}"] for i in (1, 2, 3)])
        import sympy as sp

        surface = system._parsed["surface"]
        r = sp.symbols("r1:4", real=True)
        params = self.resolved.params
        grad = [sp.diff(surface, x) for x in r]
        grad = [g.xreplace({s: params[s.name] for s in g.free_symbols if s.name in params})
                for g in grad]  # fmt: skip
        at = sp.lambdify(r, grad, modules="numpy")(*(np.asarray(y[f"r{i}"]) for i in (1, 2, 3)))
        grad = np.array([np.broadcast_to(np.asarray(g, float), np.shape(y["r1"])) for g in at])
        return -grad / np.linalg.norm(grad, axis=0)

    def body_trace_figure(self) -> Figure:
        """The contact point on the body's surface, in the body frame: ``-b gamma`` on a
        ball, the state ``r`` (from the centre of mass) on a convex body.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..outputs.trajectory_figures import body_trace_figure

        y = self.y
        if "r1" in y and "gamma1" not in y:  # a described convex body
            points = np.array([y["r1"], y["r2"], y["r3"]])
            return body_trace_figure(points, None, self._title())
        b = self._ball_radius()
        gamma = np.array([y["gamma1"], y["gamma2"], y["gamma3"]])
        return body_trace_figure(-b * gamma, b, self._title())

    def _ball_radius(self) -> float:
        """The ball's radius: the parameter ``b``, or a described ball's number."""
        params = self.resolved.params
        if "b" in params:
            return float(params["b"])
        table = self.scene._described
        radius = table.rolling_system()._parsed["radius"] if table is not None else None
        if radius is None:  # no radius anywhere: the unit sphere (gamma itself)
            return 1.0
        return self._value(radius)

    def series_figure(self, quantities: Sequence[str] | None = None) -> Figure:
        """Time series of ``quantities`` (default: those of ``outputs.series``).

        Parameters
        ----------
        quantities : sequence of str, optional

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..outputs.trajectory_figures import series_figure

        if quantities is None:
            series = self.scene.outputs.series
            quantities = series.quantities if series else ["H"]
        return series_figure(self.t, {q: self.quantity(q) for q in quantities}, self._title())

    def drift_figure(self) -> Figure:
        """Change of every integral over time (log scale).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..outputs.trajectory_figures import drift_figure

        return drift_figure(self.t, self.integral_change(), self._title())

    def diagram_figure(self) -> Figure:
        """The energy diagram (n, h) at this ``C`` with the scene's point.

        K01's diagram for the ball (``C = (M, gamma)``, ``n = (M, M)``); with the gyrostat the
        diagram at ``C = (M + K, gamma)``, ``n = (M + K, M + K)``
        (:func:`chaplygin.verify.outputs.diagram.gyrostat_diagram_figure`); BKM12 Fig. 5's for
        the spherical support (:func:`chaplygin.verify.outputs.diagram.support_diagram_figure`).

        Returns
        -------
        matplotlib.figure.Figure

        Raises
        ------
        SceneError
            A model without a diagram (the message lists those that have one).
        """
        from ..outputs.diagram import (
            diagram_kind,
            diagram_problem,
            gyrostat_diagram_figure,
            scene_diagram_figure,
            support_diagram_figure,
        )

        code = self.resolved.code
        kind = diagram_kind(self.scene.system, code.effects)
        if kind is None:
            raise SceneError(
                diagram_problem(self.scene.system, code.effects, code.name),
                self.scene.source,
                "outputs.diagram",
            )
        names = code.integral_names
        F0 = np.asarray(
            code.numpy.integrals(
                self.t[:1], np.asarray(self.integration.y, float)[:, :1], self._p()
            ),
            float,
        )[:, 0]
        p = self.resolved.params
        I = [float(p[f"I{i}"]) for i in (1, 2, 3)]
        h = F0[names.index("H")]
        if kind == "gyrostat":
            C, n = F0[names.index("(M+K,gamma)")], F0[names.index("(M+K,M+K)")]
            K = [float(p[f"K{i}"]) for i in (1, 2, 3)]
            return gyrostat_diagram_figure(I, float(p["D"]), K, C, n, h, self._title())
        if kind == "support":
            C = F0[names.index("(M,M)")]
            g = [F0[names.index(f"(M,{v})")] / np.sqrt(C) for v in ("alpha", "beta", "gamma")]
            params = [float(v) for v in p.values()]
            return support_diagram_figure(params, g, 2 * h / C, self._title())
        C, n = F0[names.index("(M,gamma)")], F0[names.index("(M,M)")]
        return scene_diagram_figure(I, float(p["D"]), C, n, h, self._title())

    def separatrix_delta(self) -> dict:
        """Delta measured between the trace's two asymptotic centres, against K01-3.7.

        See :func:`chaplygin.verify.outputs.separatrix_delta.separatrix_delta_report`
        (computed once).

        Returns
        -------
        dict

        Raises
        ------
        SceneError
            The scene did not ask for ``separatrix_delta`` or its run failed.
        """
        if self.backward is None:
            raise SceneError(
                "Delta needs outputs.separatrix_delta and a run that reached its end",
                self.scene.source,
                "outputs.separatrix_delta",
            )
        if self._delta_report is None:
            from ...numerics.inputs import Precision
            from ..outputs.separatrix_delta import separatrix_delta_report

            rtol = self.scene.run_options.rtol
            if rtol is None:
                prec = Precision(self.scene.run_options.precision)
                rtol = prec.default_tolerances[0]
            self._delta_report = separatrix_delta_report(self, float(rtol))
        return self._delta_report

    def separatrix_delta_figure(self) -> Figure:
        """Both halves of the separatrix trace with their centres and Delta marked.

        Returns
        -------
        matplotlib.figure.Figure

        Raises
        ------
        SceneError
            As :meth:`separatrix_delta`.
        """
        from ..outputs.separatrix_delta import separatrix_delta_figure

        return separatrix_delta_figure(self, self.separatrix_delta(), self._title())

    def figures(self) -> dict:
        """The figures the scene asks for (``outputs.* .plot = true``).

        Returns
        -------
        dict of str to matplotlib.figure.Figure
        """
        makers = {
            "contact_trace": self.contact_trace_figure,
            "body_trace": self.body_trace_figure,
            "series": self.series_figure,
            "drift": self.drift_figure,
            "diagram": self.diagram_figure,
            "separatrix_delta": self.separatrix_delta_figure,
        }
        out = {}
        for key, make in makers.items():
            spec = getattr(self.scene.outputs, key)
            if key == "separatrix_delta" and self.backward is None:
                continue  # the forward run failed: there is no Delta to draw
            if spec is not None and spec.plot:
                out[key] = make()
        for key, done in self.analyses.items():
            if getattr(getattr(self.scene.outputs, key), "plot", True):
                for name, make in done.figures.items():
                    out[name] = make()
        return out

    def _title(self) -> str:
        from ..figure_style import literal_text

        return literal_text(self.scene.title or self.resolved.code.name)

    # ------------------------------------------------------------------ summary and files
    def summary(self, outputs: Sequence[str] = ()) -> dict:
        """Everything that identifies and qualifies the run (``summary.json``).

        Parameters
        ----------
        outputs : sequence of str
            Files written (relative names).

        Returns
        -------
        dict
        """

        from ...numerics.precision import Precision

        r, res = self.integration, self.resolved
        digits = res.digits
        summary = {
            "title": self.scene.title,
            "source": self.scene.source,
            "scene": self.scene.given,
            "resolved": {
                "system": self.scene.system,
                "model": res.code.name,
                "effects": res.effects,
                "parameters": {k: decimal_text(v, digits) for k, v in res.params.items()},
                "initial": res.state_by_name(),
                "initial_how": res.how,
                "prescribed": {k: decimal_text(v, digits) for k, v in res.prescribed.items()},
                "residuals": res.residuals,
            },
            "system": self.scene.system,
            "model": res.code.name,
            "effects": sorted(res.effects),
            "states": list(res.code.state),
            "model_hash": res.code.hash,
            "code_origin": res.code.origin,
            "code_load_s": res.load_s,
            **({"code_note": res.code.note} if res.code.note else {}),
            "precision": Precision(self.scene.run_options.precision).to_json(),
            "rtol": self.scene.run_options.rtol,
            "atol": self.scene.run_options.atol,
            "wall_s": self.wall_s,
            "versions": software_versions(),
            **(
                {"separatrix_delta": self.separatrix_delta()}
                if self.scene.outputs.separatrix_delta is not None and self.backward is not None
                else {}
            ),
        }
        if r is not None:
            summary.update(
                {
                    "y": {k: decimal_text(v, digits) for k, v in r.y_final.items()},
                    "t_end": decimal_text(r.t[-1], digits),
                    "drift": {k: (v if math.isfinite(v) else None) for k, v in r.drift.items()},
                    "drift_absolute": list(r.drift_absolute),
                    "status": r.status,
                    "message": r.message,
                    "method": r.method,
                    "backend": r.backend,
                    "steps": r.nsteps,
                    "nfev": r.nfev,
                    "integration_wall_s": r.wall_s,
                    "setup_s": r.setup_s,
                }
            )
        if self.analyses:
            summary["analyses"] = {key: done.summary for key, done in self.analyses.items()}
        summary["outputs"] = list(outputs)
        return summary

    def write(self, folder: str | Path) -> list[str]:
        """Write the outputs into an existing empty ``folder``.

        Parameters
        ----------
        folder : str or Path

        Returns
        -------
        list of str
            The files written (names relative to ``folder``), ``summary.json`` last.
        """
        from ..outputs.trajectory import write_dataset

        folder = Path(folder)
        written = []
        fmt = self.scene.outputs.trajectory.format if self.integration is not None else None
        if fmt in ("netcdf", "both"):
            self._write_netcdf(folder / "trajectory.nc")
            written.append("trajectory.nc")
        if fmt in ("csv", "both"):
            self._write_csv(folder / "trajectory.csv")
            written.append("trajectory.csv")
        for key, done in self.analyses.items():
            if done.arrays:
                attrs = {"title": self.scene.title or "", "model": self.resolved.code.name}
                write_dataset(folder / f"{key}.nc", done.arrays, attrs)
                written.append(f"{key}.nc")
        for key, fig in self.figures().items():
            for ext in ("png", "svg"):
                fig.savefig(folder / f"{key}.{ext}", dpi=120)
                written.append(f"{key}.{ext}")
        written.append("summary.json")
        (folder / "summary.json").write_text(
            json.dumps(self.summary(written), indent=2, allow_nan=False, default=str) + "\n"
        )
        return written

    def _columns(self) -> list[tuple[str, np.ndarray, str, str]]:
        from ..outputs.trajectory import trajectory_columns

        code = self.resolved.code
        return trajectory_columns(self.t, self.integration.y, code.state, code.state_groups)

    def _write_netcdf(self, path: Path) -> None:
        from ...numerics.precision import Precision
        from ..outputs.trajectory import run_attributes, write_trajectory

        code = self.resolved.code
        attrs = run_attributes(
            self.integration, code, Precision(self.scene.run_options.precision),
            software_versions(), title=self.scene.title or "", system=self.scene.system,
            effects=self.resolved.effects,
        )  # fmt: skip
        write_trajectory(path, self._columns(), attrs)

    def _write_csv(self, path: Path) -> None:
        from ..outputs.trajectory import write_trajectory

        write_trajectory(path, self._columns())

    # ------------------------------------------------------------------ display
    def __repr__(self) -> str:
        if self.integration is None:
            return (
                f"<SceneResult {self.resolved.code.name}: analyses "
                f"{', '.join(self.analyses)}, {self.wall_s:.3g} s>"
            )
        worst = max(self.drift.values(), default=0.0)
        return (
            f"<SceneResult {self.resolved.code.name}: t = {self.t[-1]:g}, "
            f"{len(self.t)} points, {self.integration.nsteps} steps, max drift {worst:.2e}, "
            f"status {self.integration.status}>"
        )

    def _repr_html_(self) -> str:
        if self.integration is None:
            return f"<pre>{html.escape(repr(self))}</pre>"
        rows = "".join(
            f"<tr><td>{html.escape(k)}</td><td>{v:.3e}</td></tr>" for k, v in self.drift.items()
        )
        return (
            f"<b>{html.escape(self.scene.title or self.resolved.code.name)}</b><br>"
            f"model {html.escape(self.resolved.code.name)}, t = {self.t[-1]:g}, "
            f"{self.integration.nsteps} steps, status {self.integration.status}"
            f"<table><tr><th>integral</th><th>drift</th></tr>{rows}</table>"
        )


def package_version() -> str:
    """The installed chaplygin's version (``"unknown"`` from an uninstalled tree).

    Returns
    -------
    str
    """
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("chaplygin")
    except PackageNotFoundError:  # pragma: no cover
        return "unknown"


def software_versions() -> dict[str, str]:
    """The versions a result depends on: chaplygin, Python, numpy, scipy, sympy, mpmath.

    Returns
    -------
    dict of str to str
    """
    import mpmath
    import scipy
    import sympy

    return {
        "chaplygin": package_version(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "sympy": sympy.__version__,
        "mpmath": mpmath.__version__,
    }


# ------------------------------------------------------------------------- output folder
def prepare_output(out: str | Path) -> Any:
    """Check, before any work, that a run may write into ``out``: a new folder, an empty one,
    or a folder of a previous run (its marker lists the files we wrote, each unchanged).

    See :mod:`chaplygin.verify.output_folder`.

    Parameters
    ----------
    out : str or Path

    Returns
    -------
    chaplygin.verify.output_folder.OutputFolder

    Raises
    ------
    UserInputError
        Anything else (a non-empty folder that is not ours, a changed file of ours, a folder
        where nothing can be created); nothing is touched.
    """
    from ..output_folder import OutputFolder

    return out if isinstance(out, OutputFolder) else OutputFolder.check(out)


def write_atomically(result: SceneResult, out: Any) -> list[str]:
    """Write the outputs beside the folder's files and move them into place at the end,
    replacing only the files of our previous run (see :func:`prepare_output`).

    Parameters
    ----------
    result : SceneResult
    out : str, Path or OutputFolder
        Checked by :func:`prepare_output` (again, if a path).

    Returns
    -------
    list of str
        Files written (relative to ``out``).
    """
    return prepare_output(out).write(result.write)
