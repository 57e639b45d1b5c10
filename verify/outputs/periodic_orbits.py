"""The ``periodic_orbits`` scene output: the period of the stroboscopic map's attractor,
its Newton refinement and Floquet multipliers, and (optionally) its continuation in a
parameter with the bifurcations met. (An autonomous model, a described system too, names a
``section`` instead: :mod:`chaplygin.verify.outputs.periodic_orbits_flow`.)

A scene of BM20's model (time-periodic ``I(t)``, ``k(t)``; ``(M, gamma) = 0``) asks for::

    [outputs.periodic_orbits]
    transient = 12000        # map iterations discarded before the period search
    max_period = 64
    [outputs.periodic_orbits.continuation]
    parameter = "Omega"
    range = [1.0662, 1.075]
    step = 2e-4

The map is the stroboscopic map ``t -> t + 2 pi/Omega`` from ``t = 0`` in BM20's
Andoyer–Deprit coordinates ``(z, l, g)`` (BM20-3.7) on the level ``|M| = G`` of the scene's
initial state; its Jacobian comes from the variational equations with the generated
Jacobian (:func:`chaplygin.numerics.dynamics.periodic_orbits.bm20_map_with_jacobian`). A period is
a candidate when the orbit closes within ``detect_tol``; it counts only once Newton's
method has refined it to ``10 k`` times the map's accuracy (``100 rtol``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...arith import detlinalg
from ...derive.errors import UserInputError
from ..scene.outputs import Analysis, AnalysisResult, register_analysis
from .periodic_orbits_figure import multipliers_figure
from .periodic_orbits_table import ContinuationSpec, PeriodicOrbitsOutput

__all__ = ["PeriodicOrbitsOutput", "ContinuationSpec", "PERIODIC_ORBITS", "multipliers_figure"]

#: The parameters the stroboscopic map's orbits are continued in.
MAP_PARAMETERS = ("Omega", "D", "delta", "J_off")


def _scene_error(message: str, path: str) -> Exception:
    # a UserInputError naming the key path, without the file and line (the messages of this
    # output have always read so)
    return UserInputError(f"{path}: {message}")


def _check(scene: Any, code: Any, spec: PeriodicOrbitsOutput) -> None:
    if spec.section is not None:
        from .periodic_orbits_flow import check_flow_orbit

        return check_flow_orbit(scene, code, spec)
    if "Omega" not in code.numpy.PARAMS:
        raise _scene_error(
            "periodic_orbits needs a time-periodic model (effects variable_inertia and/or "
            "variable_gyrostat: the stroboscopic map has period 2 pi/Omega), or a section "
            '(section = "gamma2": the return map of an autonomous model)',
            "outputs.periodic_orbits",
        )
    if spec.continuation is not None and spec.continuation.parameter not in MAP_PARAMETERS:
        raise _scene_error(
            f"the stroboscopic map is continued in one of {', '.join(MAP_PARAMETERS)}, not "
            f"{spec.continuation.parameter!r}",
            "outputs.periodic_orbits.continuation.parameter",
        )
    if tuple(code.numpy.STATE) != ("M1", "M2", "M3", "gamma1", "gamma2", "gamma3"):
        raise _scene_error(
            "periodic_orbits works in BM20's coordinates (z, l, g): a model with state "
            "(M, gamma) only (no contact_point)",
            "outputs.periodic_orbits",
        )


def _param_vector(res: Any) -> list[float]:
    return [float(res.params[n]) for n in res.code.numpy.PARAMS]


def _complex_text(m: complex) -> str:
    return f"{m.real:.12g}{m.imag:+.12g}j"


def _run(scene: Any, res: Any, spec: PeriodicOrbitsOutput, progress: Any) -> AnalysisResult:
    if spec.section is not None:
        from .periodic_orbits_flow import run_flow_orbit

        return run_flow_orbit(scene, res, spec)
    from ...derive.errors import ComputationError
    from ...numerics.ball.bm20_map import bm20_map_with_jacobian, bm20_point
    from ...numerics.dynamics.continuation import continue_periodic_orbit
    from ...numerics.dynamics.periodic_orbits import detect_period, refine_periodic_orbit
    from ...numerics.dynamics.reversibility import stroboscopic_samples

    y0 = np.array([float(v) for v in res.y0])
    M, gamma = y0[:3], y0[3:]
    G = detlinalg.norm(M)
    if G == 0 or abs(detlinalg.dot(M, gamma)) > 1e-9 * G:
        raise _scene_error(
            "periodic_orbits needs (M, gamma) = 0 and |M| = G > 0 (BM20's level set); give "
            "the initial state by G, z, l, g",
            "initial",
        )
    params = _param_vector(res)
    samples = stroboscopic_samples(
        res.code, params, y0, 2 * spec.max_period, transient=spec.transient, rtol=spec.rtol
    )
    points = np.array([bm20_point(y) for y in samples])
    period = detect_period(points, spec.max_period, spec.detect_tol, angles=(1, 2))
    summary: dict[str, Any] = {
        "map": "stroboscopic, t = 0 mod 2 pi/Omega, coordinates (z, l, g) (BM20-3.7)",
        "level G": f"{G:.15g}",
        "transient": spec.transient,
        "detect_tol": spec.detect_tol,
        "rtol": spec.rtol,
        "period": period,
    }
    arrays: dict[str, tuple] = {
        "attractor": (
            ("sample", "coordinate"),
            points,
            {"long_name": "map points after the transient (z, l, g)", "units": "1, rad, rad"},
        )
    }
    figures: dict = {}
    if period is None:
        summary["message"] = (
            f"no period <= {spec.max_period} closes within {spec.detect_tol:g} after "
            f"{spec.transient} iterations (chaotic, quasi-periodic or a longer transient)"
        )
        return AnalysisResult(summary=summary, arrays=arrays, figures=figures)
    vary = spec.continuation.parameter if spec.continuation else "Omega"
    smap = bm20_map_with_jacobian(params, G, vary=vary, rtol=spec.rtol)
    value = float(res.params[vary])
    try:
        orbit = refine_periodic_orbit(smap, points[-1], period, value)
    except ComputationError as exc:
        raise _scene_error(f"periodic_orbits: {exc}", "outputs.periodic_orbits") from None
    summary.update(
        {
            "newton": orbit.message,
            "converged": orbit.converged,
            "residual": orbit.residual,
            "tolerance": orbit.tolerance,
            "multipliers": [_complex_text(complex(m)) for m in orbit.multipliers],
            "max |multiplier|": orbit.max_abs_multiplier,
            "multiplier_tolerance": orbit.multiplier_tolerance,
            "stable": orbit.stable,
            **_canonical_orbit(orbit, G),
        }
    )
    if spec.continuation is not None and orbit.converged:
        summary["continuation"], arrays_c, fig = _continue(
            smap, orbit, vary, value, spec.continuation, progress, continue_periodic_orbit
        )
        arrays.update(arrays_c)
        figures["periodic_orbits_multipliers"] = fig
    return AnalysisResult(summary=summary, arrays=arrays, figures=figures)


def _canonical_orbit(orbit: Any, G: float) -> dict[str, Any]:
    """The refined cycle as its canonical copy under ``gamma -> -gamma`` (in (z, l, g):
    ``g -> g + pi``), starting at a fixed point of the cycle, with the copy reached named
    (:mod:`chaplygin.numerics.ball.symmetry`): two runs that land on mirror copies, or on the
    cycle at different points, print the same orbit."""
    from ...numerics.ball.bm20_map import BM20_STATE, bm20_point, bm20_state
    from ...numerics.ball.symmetry import canonical_cycle, name_copy
    from ...numerics.dynamics.periodic_orbits import as_numpy_points

    states = np.array([bm20_state(x, G) for x in as_numpy_points(orbit)])
    tol = max(float(orbit.residual), float(orbit.tolerance)) * max(1.0, G)
    copy = name_copy(states, BM20_STATE, periodic=True, tol=tol)
    canonical = canonical_cycle(states, BM20_STATE, copy)
    return {
        "orbit (z, l, g)": [[f"{v:.15g}" for v in bm20_point(y)] for y in canonical],
        "orbit_copy": "canonical" if copy.copy != "self" else "self-symmetric",
        **copy.summary(),
    }


def _continue(smap, orbit, vary, value, cspec, progress, continue_periodic_orbit):
    say = (lambda m: print(f"periodic_orbits: {m}", flush=True)) if progress else None
    # start from the point of the cycle farthest from the poles z = +-1 of the reduced
    # coordinates, where l is undefined and the corrections are ill-conditioned (which of the
    # points comes first depends on where the transient ended)
    start = max(orbit.points, key=lambda x: 1 - abs(float(x[0])))
    runs = []
    for end in cspec.range:
        if float(end) == value:
            continue
        runs.append(
            continue_periodic_orbit(
                smap,
                start,
                orbit.period,
                value,
                float(end),
                step=float(cspec.step),
                max_points=cspec.max_points,
                follow_doublings=cspec.follow_doublings,
                progress=say,
            )
        )
    branches = [b for r in runs for b in r.branches]
    events = [e for r in runs for e in r.events]
    doublings = sorted(e.parameter for e in events if e.kind == "period-doubling")
    out: dict[str, Any] = {
        "parameter": vary,
        "range": [float(v) for v in cspec.range],
        "events": [
            {
                "kind": e.kind,
                "parameter": f"{e.parameter:.15g}",
                "uncertainty": e.uncertainty,
                "period": e.period,
                "multipliers": [_complex_text(complex(m)) for m in e.multipliers],
            }
            for e in events
        ],
        "branches": [
            {"period": b.period, "points": len(b.parameters), "message": b.message}
            for b in branches
        ],
    }
    if len(doublings) >= 3:
        d = np.diff(doublings)
        out["doubling ratios"] = [f"{r:.6g}" for r in d[:-1] / d[1:]]
        out["feigenbaum delta"] = "4.669201609102990"
    par = np.concatenate([b.parameters for b in branches])
    per = np.concatenate([np.full(len(b.parameters), b.period) for b in branches])
    mul = np.concatenate([b.multipliers for b in branches])
    arrays = {
        "branch_parameter": (("branch_point",), par, {"long_name": vary, "units": "1"}),
        "branch_period": (("branch_point",), per, {"long_name": "period", "units": "1"}),
        "multiplier_abs": (
            ("branch_point", "multiplier"),
            np.abs(mul),
            {"long_name": "|Floquet multiplier|", "units": "1"},
        ),
        "multiplier_arg": (
            ("branch_point", "multiplier"),
            np.angle(mul),
            {"long_name": "arg Floquet multiplier", "units": "rad"},
        ),
    }

    def figure():
        return multipliers_figure(par, per, mul, events, vary)

    return out, arrays, figure


PERIODIC_ORBITS = register_analysis(
    Analysis(
        key="periodic_orbits",
        run=_run,
        check=_check,
        description="period of the stroboscopic map's attractor, Newton refinement, Floquet "
        "multipliers; continuation in a parameter with period-doubling, saddle-node and "
        "Neimark-Sacker events",
    )
)
