"""The ``poincare`` scene output: a Poincaré map (stroboscopic or by a surface) of the scene's
model from its initial state (and more starts on request), in Andoyer-Deprit, cylindrical or
user coordinates, with 2-D projections and the 3-D map (BM20 Fig. 5 style).

The numbers come from :mod:`chaplygin.numerics.dynamics.poincare`; this module reads the scene's
table, checks it (every problem a :class:`~chaplygin.verify.scene.SceneError` naming the key path),
runs the map and returns an :class:`~chaplygin.verify.scene.outputs.AnalysisResult`: summary numbers
(points, orbits, time span, the integrals' drift along the map), ``poincare.nc`` (coordinates
and states by orbit and point) and figures.

References
----------
BM20-map, BM20-3.7 (coordinates); K01 Fig. 2a, BM20 Figs. 2, 4, 5, 7 (example scenes).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ...derive.errors import ComputationError, UserInputError
from ..scene.outputs import Analysis, AnalysisResult, SceneError, register_analysis
from .poincare_table import PoincareOutput

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["PoincareOutput", "ANALYSIS", "map_points"]


def _fail(scene: Any, message: str, *loc: Any) -> SceneError:
    return scene.key_error(message, "outputs", "poincare", *loc)


def _coordinate_names(spec: PoincareOutput) -> tuple[str, ...]:
    from ...numerics.ball.map_coordinates import COORDINATE_SYSTEMS

    if isinstance(spec.coordinates, str):
        return COORDINATE_SYSTEMS[spec.coordinates]
    return tuple(spec.coordinates)


def _check(scene: Any, code: Any, spec: PoincareOutput) -> None:
    """Refuse a ``poincare`` table before anything runs (the message names the key path)."""
    from ...numerics.ball.map_coordinates import StateExpression

    names = (*code.state, *code.aux_names)
    if spec.section == "stroboscopic":
        if "Omega" not in code.params:
            raise _fail(
                scene,
                f"a stroboscopic map needs a time-periodic model (parameter Omega: effects "
                f"variable_inertia or variable_gyrostat); {code.name} is autonomous: give a "
                'surface, e.g. section = "M2*gamma1 - M1*gamma2"',
                "section",
            )
    else:
        try:
            StateExpression(spec.section, names)
        except UserInputError as exc:
            raise _fail(scene, str(exc), "section") from None
    if isinstance(spec.coordinates, list):
        for i, text in enumerate(spec.coordinates):
            try:
                StateExpression(text, names)
            except UserInputError as exc:
                raise _fail(scene, str(exc), "coordinates", i) from None
    elif not {"M", "gamma"} <= set(code.state_groups):
        raise _fail(
            scene,
            f"{code.name} has no M and gamma for the {spec.coordinates} coordinates: give two "
            f"expressions of its state, e.g. coordinates = [{code.state[0]!r}, {code.state[-1]!r}]",
            "coordinates",
        )
    coords = _coordinate_names(spec)
    for i, pair in enumerate(spec.projections or []):
        for j, name in enumerate(pair):
            if name not in coords:
                raise _fail(
                    scene,
                    f"{name!r} is not a coordinate of this map; valid: {', '.join(coords)}",
                    "projections",
                    i,
                    j,
                )
    if spec.plot3d and len(coords) < 3:
        raise _fail(scene, "plot3d needs three coordinates", "plot3d")
    want = (
        {"andoyer": 3, "cylindrical": 2}.get(spec.coordinates)
        if isinstance(spec.coordinates, str)
        else None
    )
    for i, start in enumerate(spec.starts):
        if want is None:
            raise _fail(
                scene, "starts are given in 'andoyer' or 'cylindrical' coordinates only", "starts"
            )
        if len(start) != want:
            raise _fail(scene, f"a start has {want} numbers ({', '.join(coords)})", "starts", i)
    for key in spec.vary:
        if key not in type(scene.initial).model_fields:
            raise _fail(scene, f"{key!r} is not a key of [initial]", "vary", key)
    if spec.mark_rotations and (
        scene.system != "chaplygin_ball" or set(code.effects) - {"contact_point"}
        or scene.initial.h is None or scene.initial.C is None
    ):  # fmt: skip
        raise _fail(
            scene,
            "mark_rotations needs chaplygin_ball without time-dependent effects and an initial "
            "state given by h and C",
            "mark_rotations",
        )


def map_points(orbit: Any, spec_coordinates: Any, code: Any, params: list) -> dict[str, np.ndarray]:
    """The map coordinates of the points of a
    :class:`~chaplygin.numerics.dynamics.poincare.MapOrbit`.

    Parameters
    ----------
    orbit : MapOrbit
    spec_coordinates : "andoyer", "cylindrical" or list of str
    code : ModelCode
    params : list
        Parameters in the model's order.

    Returns
    -------
    dict of str to ndarray (float64)
        Coordinate name -> values.
    """
    from ...numerics.ball.map_coordinates import StateExpression, andoyer_deprit, cylindrical

    y = np.asarray(orbit.y, dtype=float)
    idx = {n: i for i, n in enumerate(code.state)}
    if spec_coordinates == "andoyer":
        M = [y[:, idx[f"M{i}"]] for i in (1, 2, 3)]
        g = [y[:, idx[f"gamma{i}"]] for i in (1, 2, 3)]
        _, z, l_, g_ = andoyer_deprit(M, g)
        return {"z": np.asarray(z), "l": np.asarray(l_), "g": np.asarray(g_)}
    if spec_coordinates == "cylindrical":
        z, l_ = cylindrical([y[:, idx[f"gamma{i}"]] for i in (1, 2, 3)])
        return {"z": np.asarray(z), "l": np.asarray(l_)}
    values = {n: y[:, i] for n, i in idx.items()}
    if any(a in " ".join(spec_coordinates) for a in code.aux_names):
        p = np.asarray(params, float)
        aux = np.array(
            [code.numpy.aux(float(t), row, p) for t, row in zip(orbit.t, y, strict=True)]
        )
        values.update({a: aux[:, k] for k, a in enumerate(code.aux_names)})
    return {
        text: np.asarray(StateExpression(text, tuple(values)).evaluate(values), float)
        * np.ones(len(y))
        for text in spec_coordinates
    }


def _starts(scene: Any, res: Any, spec: PoincareOutput) -> list[tuple[str, list]]:
    """The initial states: the scene's, then ``starts``, then ``level_points``."""
    import mpmath

    from ...numerics.ball.map_coordinates import from_andoyer_deprit, from_cylindrical
    from ...numerics.inputs import Precision, working_number

    out = [("initial", list(res.y0))]
    prec = Precision(scene.run_options.precision)
    code = res.code
    idx = {n: i for i, n in enumerate(code.state)}
    dps = prec.parse_dps
    for i, start in enumerate(spec.starts):
        with mpmath.workdps(dps):
            try:
                values = [mpmath.mpf(working_number(v, Precision(dps))) for v in start]
            except UserInputError as exc:
                raise _fail(scene, str(exc), "starts", i) from None
            if not -1 <= values[0] <= 1:
                raise _fail(scene, "z must lie in [-1, 1]", "starts", i, 0)
            y = [mpmath.mpf(v) for v in res.y0]
            if spec.coordinates == "andoyer":
                G = mpmath.sqrt(sum(y[idx[f"M{k}"]] ** 2 for k in (1, 2, 3)))
                M, g = from_andoyer_deprit(G, *values)
            else:
                M, g = [mpmath.mpf(0)] * 3, from_cylindrical(*values)
            for k in range(3):
                y[idx[f"M{k + 1}"]], y[idx[f"gamma{k + 1}"]] = M[k], g[k]
            if "alpha" in idx:
                raise _fail(scene, "starts need a model without the contact point", "starts")
        out.append((f"start {i + 1}", [working_number(v, prec) for v in y]))
    for k in range(1, spec.level_points + 1):
        other = scene.with_initial(point=k)
        try:
            out.append((f"level point {k}", list(other.resolve().y0)))
        except UserInputError as exc:
            raise _fail(scene, f"level point {k}: {exc}", "level_points") from None
    for key, values in spec.vary.items():
        for k, value in enumerate(values):
            other = scene.with_initial(**{key: value})
            try:
                out.append((f"{key} = {value}", list(other.resolve().y0)))
            except UserInputError as exc:
                raise _fail(scene, str(exc), "vary", key, k) from None
    return out


def _rotation_marks(scene: Any, res: Any, section: Any, spec: PoincareOutput) -> dict:
    """Where the steady rotations p1, p2, p3 (K01 (3.2)) at the scene's C and h cross the
    section: n is solved from the energy h along each branch; axes without a rotation at
    (C, h) are left out."""
    import mpmath

    from ...numerics.ball.initial_state import state_near_rotation
    from ...numerics.inputs import parse_number

    code = res.code
    dps = 30
    C = parse_number(scene.initial.C, dps)
    h = parse_number(scene.initial.h, dps)
    params = {k: mpmath.mpf(v) for k, v in res.params.items()}
    p = [params[k] for k in code.params]
    energy_index = code.integral_names.index("H")
    marks = {}
    for axis in (1, 2, 3):
        J = params[f"I{axis}"] + params["D"]

        def energy_gap(n, axis=axis):
            s = state_near_rotation(code, params, axis, C, n)
            y = [mpmath.mpf(v) for g in ("M", "gamma") for v in s.values[g]]
            return code.mpmath.integrals(0, y, p)[energy_index] - h

        try:
            with mpmath.workdps(dps):
                n = mpmath.findroot(energy_gap, (2 * h * J, 2.2 * h * J), solver="secant")
                s = state_near_rotation(code, params, axis, C, n)
        except (UserInputError, ValueError, ZeroDivisionError):
            continue
        y = [float(v) for g in ("M", "gamma") for v in s.values[g]]
        # (M, gamma, t) -> (-M, -gamma, -t) maps solutions to solutions and keeps C, n, h:
        # the opposite rotation about the same axis (marked with a prime)
        for label, state in ((f"p{axis}", y), (f"p{axis}'", [-v for v in y])):
            try:
                curve = _in_surface(section, state)
                if curve is not None:  # S = 0 all along it: drawn as a curve, not a point
                    marks[label] = {**map_points(curve, spec.coordinates, code, p), "in": True}
                    continue
                orbit = section.crossings(state, 4, t_max=200)
            except (UserInputError, ComputationError):
                continue
            if len(orbit):
                marks[label] = map_points(orbit, spec.coordinates, code, p)
    return marks


def _in_surface(section: Any, y: list) -> Any:
    """The orbit of ``y`` sampled at 200 points over 20 time units when the surface function
    vanishes all along it (to 1e-9 of the state's squared size), else None: K01's rotation
    about e3 lies in the section g = 0 (``M`` and ``gamma`` have parallel horizontal parts)."""
    from types import SimpleNamespace

    found = section.orbit_in_surface(y, 20.0, 200, 1e-9)
    return None if found is None else SimpleNamespace(t=found[0], y=found[1])


def _run(scene: Any, res: Any, spec: PoincareOutput, progress: bool) -> AnalysisResult:
    from ...numerics.dynamics.poincare import EventSection, StroboscopicMap

    code = res.code
    params = [res.params[k] for k in code.params]
    options = {
        "precision": scene.run_options.precision,
        "rtol": scene.run_options.rtol,
        "atol": scene.run_options.atol,
        "backend": scene.run_options.backend,
    }
    if scene.run_options.method is not None:
        options["method"] = scene.run_options.method
    t0 = res.t_span[0]
    try:
        if spec.section == "stroboscopic":
            section: Any = StroboscopicMap(code, params, **options)

            def run_one(y):
                return section.orbit(y, spec.iterations, spec.transient, t0=t0)
        else:
            section = EventSection(code, params, spec.section, direction=spec.direction, **options)

            def run_one(y):
                return section.crossings(y, spec.iterations, spec.transient, t0=t0)
    except UserInputError as exc:
        raise _fail(scene, str(exc), "section") from None
    starts = _starts(scene, res, spec)
    coords = _coordinate_names(spec)
    orbits, labels = [], []
    for label, y in starts:
        try:
            orbits.append(run_one(y))
        except (UserInputError, ComputationError) as exc:
            raise _fail(scene, f"{label}: {exc}", "section") from None
        labels.append(label)
    copies = _name_copies(spec, code, orbits, labels)
    if spec.copies == "canonical" and copies:
        orbits = [_as_canonical(o, code, c) for o, c in zip(orbits, copies, strict=True)]
    points = [map_points(o, spec.coordinates, code, params) for o in orbits]
    marks = _rotation_marks(scene, res, section, spec) if spec.mark_rotations else {}
    n_max = max(len(o) for o in orbits)

    def padded(rows: list[np.ndarray]) -> np.ndarray:
        out = np.full((len(rows), n_max), np.nan)
        for i, r in enumerate(rows):
            out[i, : len(r)] = np.asarray(r, float)
        return out

    arrays: dict[str, tuple] = {}
    for name in coords:
        arrays[name if name.isidentifier() else f"q{coords.index(name) + 1}"] = (
            ("orbit", "point"),
            padded([p[name] for p in points]),
            {"long_name": f"map coordinate {name}", "units": "1"},
        )
    arrays["t"] = (("orbit", "point"), padded([o.t for o in orbits]), {"long_name": "time",
                   "units": "model time"})  # fmt: skip
    for k, sname in enumerate(code.state):
        arrays[sname] = (
            ("orbit", "point"),
            padded([np.asarray(o.y[:, k], float) for o in orbits]),
            {"long_name": f"state {sname} at the map points", "units": "model units"},
        )
    drift = {n: max(o.drift[n] for o in orbits) for n in code.integral_names}
    summary: dict[str, Any] = {
        "section": spec.section,
        "coordinates": list(coords),
        "orbits": len(orbits),
        "points": int(sum(len(o) for o in orbits)),
        "iterations": spec.iterations,
        "transient": spec.transient,
        "complete": all(len(o) == spec.iterations for o in orbits),
        "integrator_steps": int(sum(o.nsteps for o in orbits)),
        "wall_s": round(sum(o.wall_s for o in orbits), 4),
        "drift_max": drift,
        "precision": str(section.precision),
    }
    if spec.section == "stroboscopic":
        summary["period"] = f"{section.period}"
        summary["time_span"] = [
            f"{section.time(spec.transient, t0)}",
            f"{section.time(spec.transient + spec.iterations - 1, t0)}",
        ]
    else:
        # crossings located, the discarded transient ones included
        summary["crossings"] = int(sum(o.info["crossings"] for o in orbits))
        first = [o.t[0] for o in orbits if len(o)]
        last = [o.t[-1] for o in orbits if len(o)]
        summary["time_span"] = [f"{min(first)}", f"{max(last)}"] if last else None
    if copies:
        summary["symmetric_copies"] = {
            label: c.summary() for label, c in zip(labels, copies, strict=True)
        }
        summary["copies_drawn"] = spec.copies
    elif spec.section == "stroboscopic":
        summary["symmetric_copies"] = "not named: the model has no symmetry that keeps t"
    else:
        summary["symmetric_copies"] = (
            "not named: a section by a surface (the symmetry need not map it onto itself)"
        )
    if marks:
        summary["rotation_marks"] = {
            k: {c: [round(float(x), 10) for x in v[c]] for c in coords}
            for k, v in marks.items()
            if "in" not in v
        }
        summary["rotations_in_section"] = [k for k, v in marks.items() if "in" in v]
    projections = (
        [tuple(p) for p in spec.projections] if spec.projections else _default_pairs(spec, coords)
    )
    from ..figure_style import literal_text

    title = literal_text(scene.title or code.name)
    figures = {}
    if spec.plot:
        figures["poincare"] = lambda: poincare_figure(points, labels, projections, marks, title)
    if spec.plot3d:
        figures["poincare_3d"] = lambda: poincare_3d_figure(points, coords[:3], title)
    return AnalysisResult(summary=summary, arrays=arrays, figures=figures)


def _name_copies(spec: PoincareOutput, code: Any, orbits: list, labels: list) -> list:
    """The copy each orbit of a stroboscopic map reached under the ball's symmetry
    (:func:`chaplygin.numerics.ball.symmetry.name_copy` on its states); empty when not named."""
    from ...numerics.ball.symmetry import name_copy, symmetries_of

    if spec.section != "stroboscopic" or not symmetries_of(code):
        return []
    from ...numerics.ball.regimes import closing_period, map_points_scaled

    out = []
    for orbit in orbits:
        y = np.asarray(orbit.y, dtype=float)
        # a periodic orbit (closing to 1e-9 in (M/G, gamma)) is named from one period of it
        period = closing_period(map_points_scaled(y, code.state), min(64, len(y) // 2), 1e-9)
        if period:
            out.append(name_copy(y[-period:], code.state, periodic=True, tol=1e-9 * 10))
        else:
            out.append(name_copy(y, code.state))
    return out


def _as_canonical(orbit: Any, code: Any, copy: Any) -> Any:
    """The orbit as its canonical copy: ``gamma -> -gamma`` applied when it reached the mirror
    (at the orbit's own precision)."""
    import dataclasses

    if copy.copy != "mirror":
        return orbit
    y = np.array(orbit.y, copy=True)
    for i, name in enumerate(code.state):
        if name in ("gamma1", "gamma2", "gamma3"):
            y[:, i] = -y[:, i]
    return dataclasses.replace(orbit, y=y)


def _default_pairs(spec: PoincareOutput, coords: tuple[str, ...]) -> list[tuple[str, str]]:
    if spec.coordinates == "andoyer":
        return [("l", "z"), ("l", "g")]
    if spec.coordinates == "cylindrical":
        return [("l", "z")]
    return [(coords[0], coords[1])] if len(coords) > 1 else [(coords[0], coords[0])]


_ANGLES = {"l", "g"}


def poincare_figure(
    points: list[dict[str, np.ndarray]],
    labels: list[str],
    projections: list[tuple[str, str]],
    marks: dict[str, dict[str, np.ndarray]],
    title: str = "",
) -> Figure:
    """2-D projections of a Poincaré map: one panel per pair of coordinates.

    Parameters
    ----------
    points : list of dict of str to ndarray
        Per orbit, coordinate name -> values.
    labels : list of str
        One per orbit.
    projections : list of (str, str)
        ``(x, y)`` coordinate names per panel.
    marks : dict of str to dict of str to ndarray
        Marked points (steady rotations) by label; those with a key ``"in"`` lie in the
        section and are drawn as dashed curves.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..figure_style import new_figure

    fig = new_figure(figsize=(5.2 * len(projections), 5))
    axes = np.atleast_1d(fig.subplots(1, len(projections)))
    size = 0.6 if sum(len(next(iter(p.values()))) for p in points) > 2000 else 3
    for ax, (x, y) in zip(axes, projections, strict=True):
        for pts, label in zip(points, labels, strict=True):
            # a few distinct points (fixed points, cycles reached after a transient): visible
            distinct = len(np.unique(np.round(np.column_stack([pts[x], pts[y]]), 6), axis=0))
            ax.scatter(pts[x], pts[y], s=size if distinct > 100 else 30, lw=0,
                       label=label if len(points) <= 8 else None)  # fmt: skip
        for name, pts in marks.items():
            if "in" in pts:  # lies in the section: a curve
                ax.plot(pts[x], pts[y], "k--", lw=0.8, zorder=5)
            else:
                ax.scatter(pts[x], pts[y], s=60, marker="x", color="k", zorder=5)
            ax.annotate(name, (float(pts[x][0]), float(pts[y][0])), fontsize=9,
                        xytext=(4, 4), textcoords="offset points")  # fmt: skip
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        for axis, name in ((ax.set_xlim, x), (ax.set_ylim, y)):
            if name in _ANGLES:
                axis(-np.pi, np.pi)
        ax.grid(alpha=0.3)
        if len(points) > 1 and len(points) <= 8:
            ax.legend(fontsize=7, markerscale=3)
    fig.suptitle(f"Poincaré map: {title}", fontsize=9)
    fig.tight_layout()
    return fig


def poincare_3d_figure(
    points: list[dict[str, np.ndarray]], coords: tuple[str, ...], title: str = ""
) -> Figure:
    """The 3-D Poincaré map (BM20 Fig. 5 style): points in three coordinates.

    Parameters
    ----------
    points : list of dict of str to ndarray
    coords : three coordinate names (x, y, z of the plot)
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..figure_style import new_figure

    fig = new_figure(figsize=(6.5, 6))
    ax = fig.add_subplot(projection="3d")
    a, b, c = coords
    for pts in points:
        ax.scatter(pts[b], pts[c], pts[a], s=0.8, lw=0, depthshade=False)
    ax.set_xlabel(b)
    ax.set_ylabel(c)
    ax.set_zlabel(a)
    ax.set_title(f"3-D Poincaré map: {title}", fontsize=9)
    return fig


ANALYSIS = register_analysis(
    Analysis(
        key="poincare",
        run=_run,
        check=_check,
        description="Poincaré map (stroboscopic or a section by a surface) in Andoyer-Deprit, "
        "cylindrical or user coordinates",
    )
)
