"""A described system through the scene's dynamics: Poincaré sections and Lyapunov spectra.

Routh's sphere (``examples/systems/routh_sphere.toml``: moments A, A, C, centre of mass on the
axis at ``a`` from the centre, gravity) is integrable: the energy, Jellett's integral and
Routh's integral hold, so a section lies on their common level and every Lyapunov exponent of
a generic orbit is zero. The references are typed from the mechanics here, not taken from the
derived model: ``M = I omega + m r x (omega x r)`` is the momentum about the contact point,
``r = a e3 + b gamma`` runs from the contact to the centre of mass, and

* the energy ``T + V = (omega, I omega)/2 + m |omega x r|^2/2 + m g a gamma3`` (+ const),
* Jellett's integral ``(I omega, r) = (M, r)``,
* Routh's integral ``omega3 sqrt(A C + m A b^2 (gamma1^2 + gamma2^2) + m C (a + b gamma3)^2)``

(Routh 1884; Borisov & Mamaev, RCD 7, 2002). At rest with the centre of mass on top
(``gamma = e3``, ``a > 0``) the body is an inverted pendulum rolling about its contact point:
a tilt ``theta`` has ``I_P theta'' = m g a theta`` with ``I_P = A + m (a + b)^2``, so the
two largest exponents are ``sqrt(m g a / I_P)`` per unit time.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from chaplygin.verify.cli import main

ROOT = Path(__file__).resolve().parents[2]
ROUTH = ROOT / "examples" / "systems" / "routh_sphere.toml"

#: The example's parameter values (its [parameters] table).
VALUES = dict(m=1.0, b=1.0, A=0.4, C=0.55, a=0.3, g=1.0)


def _omega(M: np.ndarray, gamma: np.ndarray, p: dict) -> np.ndarray:
    r = np.array([0.0, 0.0, p["a"]]) + p["b"] * gamma
    II = np.diag([p["A"], p["A"], p["C"]]) + p["m"] * (r @ r * np.eye(3) - np.outer(r, r))
    return np.linalg.solve(II, M)


def routh_integrals(state: np.ndarray, p: dict = VALUES) -> np.ndarray:
    """Energy, Jellett's and Routh's integrals of a state (M, gamma), from the mechanics."""
    M, gamma = state[:3], state[3:6]
    A, C, m, a, b, g = (p[k] for k in ("A", "C", "m", "a", "b", "g"))
    r = np.array([0.0, 0.0, a]) + b * gamma
    w = _omega(M, gamma, p)
    energy = 0.5 * w @ (np.array([A, A, C]) * w) + 0.5 * m * np.cross(w, r) @ np.cross(w, r)
    energy += m * g * a * gamma[2]
    jellett = M @ r
    routh = w[2] * math.sqrt(A * C + m * A * b**2 * (gamma[0] ** 2 + gamma[1] ** 2)
                             + m * C * (a + b * gamma[2]) ** 2)  # fmt: skip
    return np.array([energy, jellett, routh])


def _scene(tmp_path: Path, outputs: str, initial: str | None = None) -> Path:
    text = ROUTH.read_text().split("[outputs]")[0].replace("t_end = 60", "t_end = 1")
    if initial is not None:
        head, tail = text.split("[initial]")
        text = head + "[initial]\n" + initial + "\n[run]" + tail.split("[run]")[1]
    path = tmp_path / "scene.toml"
    path.write_text(text + outputs)
    return path


def _run(tmp_path: Path, scene: Path) -> dict:
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    return json.loads((tmp_path / "out" / "summary.json").read_text())


def test_a_section_of_a_described_system_lies_on_the_level_of_its_integrals(tmp_path):
    """[outputs.poincare] with the section gamma1 = 0: every point has gamma1 = 0 and the
    energy, Jellett's and Routh's integrals of the start (evaluated from the mechanics, above);
    the balanced ball's (M, gamma), not an integral here, is refuted by the same comparison."""
    xr = pytest.importorskip("xarray")
    scene = _scene(
        tmp_path,
        '[outputs.poincare]\nsection = "gamma1"\ndirection = 1\niterations = 12\nplot = false\n',
    )
    summary = _run(tmp_path, scene)
    section = summary["analyses"]["poincare"]
    assert section["complete"] and section["points"] == 12
    names = ["M1", "M2", "M3", "gamma1", "gamma2", "gamma3"]
    with xr.open_dataset(tmp_path / "out" / "poincare.nc") as ds:
        points = np.stack([ds[n].values[0] for n in names], axis=1)
    start = np.array([float(v) for v in summary["resolved"]["initial"].values()])
    rtol = 1e-12  # the example's run.rtol
    # the crossings are located on the step polynomial to the working precision; a
    # tolerance-controlled run's global error grows about linearly over its ~10^3 steps
    bound = 1e3 * rtol
    assert np.abs(points[:, 3]).max() <= bound
    levels = np.array([routh_integrals(y) for y in points])
    reference = routh_integrals(start)
    assert (np.abs(levels - reference) <= bound * (1 + np.abs(reference))).all(), levels
    area = np.sum(points[:, :3] * points[:, 3:], axis=1)
    assert np.ptp(area) > 1e6 * bound  # control: not an integral of Routh's sphere


def _spectrum_bound(block: dict, intervals: int, interval: float) -> np.ndarray:
    """What a zero exponent may show after ``intervals`` QR intervals: the growth of a
    tangent vector on a torus is linear (a shear), ln(N T)/(N T) per unit time, plus three
    standard errors of the run."""
    T = intervals * interval
    return math.log(T) / T + 3 * np.array(block["errors"])


def test_lyapunov_spectra_of_a_described_system_zero_on_a_torus_and_the_rolling_pendulum(
    tmp_path,
):
    """A generic orbit of the integrable Routh's sphere: every exponent of both spectra is
    zero within the run's bound (units: per unit time). At rest with the centre of mass on
    top: the two largest are sqrt(m g a / (A + m (a + b)^2)) (the rolling inverted pendulum),
    within the same bound, which refutes zero there."""
    intervals, interval = 200, 1.0
    lyapunov = (
        f"[outputs.lyapunov]\niterations = {intervals}\ntransient = 5\ninterval = {interval}\n"
        'spectrum = "both"\nstates = 2\nwindows = 4\nplot = false\n'
    )
    analyses = _run(tmp_path, _scene(tmp_path, lyapunov))["analyses"]["lyapunov"]
    for spectrum in ("level_set", "full"):
        block = analyses[spectrum]["per_unit_time"]
        assert block["units"] == "per unit time"
        exponents = np.array(block["exponents"])
        assert (np.abs(exponents) <= _spectrum_bound(block, intervals, interval)).all(), block
    assert len(analyses["full"]["per_unit_time"]["exponents"]) == 6
    rest = lyapunov.replace('"both"', '"full"').replace("states = 2", "states = 1")
    scene = _scene(tmp_path, rest, initial="M = [0, 0, 0]\ngamma = [0, 0, 1]\n")
    block = _run(tmp_path, scene)["analyses"]["lyapunov"]["full"]["per_unit_time"]
    p = VALUES
    rate = math.sqrt(p["m"] * p["g"] * p["a"] / (p["A"] + p["m"] * (p["a"] + p["b"]) ** 2))
    exponents, bound = np.array(block["exponents"]), _spectrum_bound(block, intervals, interval)
    assert (np.abs(exponents[:2] - rate) <= bound[:2]).all(), (exponents, rate)
    assert (np.abs(exponents[:2]) > bound[:2]).all()  # zero refuted by the same bound


#: Values of the energy and of two of the file's [[claims]] (Jellett's, Routh's squared).
LEVELS = {"H": "1.3", "ROUTH-jellett": "0.4", "ROUTH-routh-squared": "0.2"}


def _level_scene(tmp_path: Path, free: str, integrals: dict) -> Path:
    """The example file (its claims kept, its outputs left out) with the initial state by
    integral values."""
    table = ", ".join(f'"{k}" = {v}' for k, v in integrals.items())
    initial = (
        'M = [0.3, -0.2, 0.9]\ngamma = [0.28, 0.3, "sqrt(1 - 0.28**2 - 0.3**2)"]\n'
        f"free = {free}\nintegrals = {{ {table} }}\n"
    )
    text = ROUTH.read_text()
    text = text.split("[outputs]")[0] + "[discover]" + text.split("[discover]")[1]  # no trace
    head, rest = text.split("[initial]\n")
    path = tmp_path / "levels.toml"
    path.write_text(head + "[initial]\n" + initial + "\n[run]" + rest.split("[run]", 1)[1])
    return path


@pytest.mark.parametrize(
    "free, integrals",
    [('["M"]', LEVELS), ('["M1", "M3"]', {"H": "0.9", "ROUTH-jellett": "-0.35"})],
)
def test_an_initial_state_by_the_values_of_the_files_integrals(tmp_path, free, integrals):
    """[initial] integrals = {...} with free components: the state the scene resolves has
    those values of the energy, Jellett's and Routh's integrals, evaluated from the mechanics
    (above, not with the model's generated integrals), and the other components as given."""
    from chaplygin.verify.scene import Scene

    res = Scene.from_toml(_level_scene(tmp_path, free, integrals)).resolve()
    y = np.array([float(v) for v in res.y0])
    values = dict(zip(("H", "ROUTH-jellett", "ROUTH-routh"), routh_integrals(y), strict=True))
    values["ROUTH-routh-squared"] = values.pop("ROUTH-routh") ** 2
    eps = np.finfo(float).eps  # the state is rounded once to double
    for name, want in integrals.items():
        assert abs(values[name] - float(want)) <= 100 * eps * (1 + abs(float(want))), name
    kept = [1] if free == '["M1", "M3"]' else []
    assert np.allclose(y[3:], [0.28, 0.3, math.sqrt(1 - 0.28**2 - 0.3**2)], rtol=0, atol=eps)
    assert all(y[k] == [0.3, -0.2, 0.9][k] for k in kept)


@pytest.mark.parametrize(
    "free, integrals, message",
    [
        # the energy's least value over M3 (M1, M2, gamma as given) is 0.3056
        ('["M3"]', {"H": "0.1"}, "no real state with the other components as given has H"),
        ('["M"]', {"H": "1.3", "jellett": "0.4"}, "has no integral 'jellett'"),
        ('["M1"]', LEVELS, "3 integral value(s) need as many free components, 1 given"),
        ('["q1", "M2", "M3"]', LEVELS, "no state component 'q1'"),
    ],
)
def test_integral_values_no_state_has_are_one_line_exit_2(
    tmp_path, capsys, free, integrals, message
):
    scene = _level_scene(tmp_path, free, integrals)
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()


def _routh_level_points(gamma: np.ndarray, H: float, J: float, R2: float) -> list:
    """Every M with the energy H, Jellett's J and Routh's R^2 at ``gamma``, from the mechanics:
    M = Theta omega, omega3 = +-sqrt(R^2/k), Jellett's (Theta omega, r) = J a line in
    (omega1, omega2), and the energy a quadratic along it: at most two points per sign."""
    A, C, m, a, b, g = (VALUES[k] for k in ("A", "C", "m", "a", "b", "g"))
    r = np.array([0.0, 0.0, a]) + b * gamma
    theta = np.diag([A, A, C]) + m * (r @ r * np.eye(3) - np.outer(r, r))
    k = A * C + m * A * b**2 * (gamma[0] ** 2 + gamma[1] ** 2) + m * C * (a + b * gamma[2]) ** 2
    out = []
    for w3 in (math.sqrt(R2 / k), -math.sqrt(R2 / k)):
        u = theta @ r  # (Theta omega, r) = (omega, Theta r)
        base = np.array([0.0, (J - u[2] * w3) / u[1], w3])
        along = np.array([u[1], -u[0], 0.0])
        # H(base + t along) = c2 t^2 + c1 t + c0
        c2 = along @ theta @ along / 2
        c1 = along @ theta @ base
        c0 = base @ theta @ base / 2 + m * g * a * gamma[2] - H
        disc = c1 * c1 - 4 * c2 * c0
        if disc >= 0:
            roots = [(-c1 + s * math.sqrt(disc)) / (2 * c2) for s in (-1, 1)]
            out += [theta @ (base + t * along) for t in roots]
    return sorted(out, key=lambda M: tuple(M))


def test_the_points_of_a_level_set_of_routh_s_sphere_are_the_mechanics(tmp_path, capsys):
    """point = k on the example's level set (H, Jellett, Routh^2 with gamma given, M free):
    the enumeration finds exactly the points the mechanics gives (above: two here, the other
    sign of omega3 misses the energy), in the order of M1, and refuses point = 2."""
    from chaplygin.verify.scene import Scene

    scene = _level_scene(tmp_path, '["M"]', LEVELS)
    gamma = np.array([0.28, 0.3, math.sqrt(1 - 0.28**2 - 0.3**2)])
    want = _routh_level_points(gamma, 1.3, 0.4, 0.2)
    assert len(want) == 2
    text = scene.read_text().replace('free = ["M"]', 'free = ["M"]\npoint = POINT')
    for k, M in enumerate(want):
        scene.write_text(text.replace("POINT", str(k)))
        y = np.array([float(v) for v in Scene.from_toml(scene).resolve().y0])
        assert np.abs(y[:3] - M).max() <= 1e-13, (k, y[:3], M)
    scene.write_text(text.replace("POINT", "2"))
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "has 2 point(s) (point = 0..1)" in err and err.count("\n") == 1, err


def test_the_least_energy_a_refusal_states_is_the_mechanics_least(tmp_path, capsys):
    """The refusal of H = 0.1 with M3 free is a proof: the energy from the mechanics is a
    parabola in M3 (M1, M2, gamma as given) whose least value is the one the message states,
    above 0.1."""
    scene = _level_scene(tmp_path, '["M3"]', {"H": "0.1"})
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    stated = float(capsys.readouterr().err.rsplit("least ", 1)[1])
    gamma = [0.28, 0.3, math.sqrt(1 - 0.28**2 - 0.3**2)]
    e = [routh_integrals(np.array([0.3, -0.2, m3, *gamma]))[0] for m3 in (-1.0, 0.0, 1.0)]
    curvature, slope = e[0] + e[2] - 2 * e[1], (e[2] - e[0]) / 2
    least = e[1] - slope**2 / (2 * curvature)
    assert curvature > 0 and least > 0.1
    assert abs(stated - least) <= 1e-9 * least  # the message prints 10 digits


def test_explain_shows_a_described_state_solved_by_its_integrals(tmp_path, capsys):
    """``--explain`` of a described system (no effect combination in generated/ to compare
    with: it failed on ``max()`` of none) shows how the state was solved and the residuals."""
    scene = _level_scene(tmp_path, '["M"]', LEVELS)
    assert main(["run", str(scene), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "M1, M2, M3 solved for the integral values H, ROUTH-jellett" in out
    residuals = [float(x.split(": ")[1]) for x in out.splitlines() if "residual of" in x]
    assert len(residuals) == 3 and max(map(abs, residuals)) <= 1e-14
    assert "right-hand side:" in out and "largest effect combination" not in out


def _rolling_over_period(energy: float, p: dict = VALUES) -> float:
    """The period of Routh's sphere rolling over in the plane of its axis (omega along e1,
    gamma = (0, sin phi, cos phi)): a one-degree-of-freedom motion with the energy
    (A + m |r|^2) phi'^2 / 2 + m g a cos phi, |r|^2 = a^2 + b^2 + 2 a b cos phi (the contact
    point is the instantaneous axis), so T = int_0^2pi sqrt(I_P / (2 (h - V))) dphi (mpmath's
    quadrature, 30 digits)."""
    import mpmath

    A, m, a, b, g = (mpmath.mpf(p[k]) for k in ("A", "m", "a", "b", "g"))
    with mpmath.workdps(30):

        def integrand(phi):
            inertia = A + m * (a * a + b * b + 2 * a * b * mpmath.cos(phi))
            return mpmath.sqrt(inertia / (2 * (energy - m * g * a * mpmath.cos(phi))))

        return float(mpmath.quad(integrand, [0, mpmath.pi, 2 * mpmath.pi]))


def test_a_periodic_orbit_of_a_described_system_has_the_quadrature_s_period(tmp_path):
    """[outputs.periodic_orbits] with a section (an autonomous model): from a start rolling
    over in the plane of the axis, the return map to gamma2 = 0 closes after one crossing
    and the orbit refined on the flow has the period of the one-degree-of-freedom quadrature
    (above) at its energy, to the run's accuracy; det Phi = 1 (Routh's sphere keeps an
    invariant density: Liouville). The plane pendulum's period of the same energy with the
    inertia about the centre of mass only (A + m a^2) is refuted by the same comparison."""
    outputs = (
        '[outputs.periodic_orbits]\nsection = "gamma2"\ntransient = 0\nmax_period = 3\n'
        "detect_tol = 1e-6\nrtol = 1e-12\n"
    )
    scene = _scene(tmp_path, outputs, initial="M = [1.5, 0, 0]\ngamma = [0, 0, -1]\n")
    found = _run(tmp_path, scene)["analyses"]["periodic_orbits"]
    assert found["period"] == 1 and found["converged"], found
    point = np.array([float(v) for v in found["point"].values()])
    energy = routh_integrals(point)[0]
    T, reference = float(found["period_time"]), _rolling_over_period(energy)
    bound = 1e3 * 1e-12 * reference  # the flow's error over ~10^3 steps at rtol 1e-12
    assert abs(T - reference) <= bound, (T, reference)
    assert abs(found["det Phi"] - 1) <= 1e3 * 1e-12 * found["max |multiplier|"]
    wrong = _rolling_over_period(energy, {**VALUES, "b": 0.0})  # no rolling: A + m a^2
    assert abs(T - wrong) > 1e6 * bound


def test_newton_on_the_flow_corrects_a_wrong_period():
    """refine_flow_orbit from a state on the rolling-over orbit with its period off by 1%:
    Newton converges onto an orbit of the family whose period is the quadrature's at its own
    energy."""
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.dynamics.flow_orbits import refine_flow_orbit
    from chaplygin.verify.scene import Scene

    Scene.from_toml(ROUTH)  # registers the described system
    code = load_model_code("routh_sphere", ())
    y0 = [1.5, 0.0, 0.0, 0.0, 0.0, -1.0]
    start = _rolling_over_period(routh_integrals(np.array(y0))[0])
    params = [VALUES[k] for k in code.params]
    found = refine_flow_orbit(code, params, y0, start * (1 + 1e-2), rtol=1e-12)
    assert found.converged and found.iterations >= 1
    reference = _rolling_over_period(routh_integrals(found.point)[0])
    assert abs(found.period - reference) <= 1e3 * 1e-12 * reference


@pytest.mark.parametrize(
    "table, message",
    [
        ('section = "gamma2"\n[outputs.periodic_orbits.continuation]\nrange = [0, 1]\nstep = 0.1\n',
         "routh_sphere has no parameter 'Omega'"),
        ('section = "open(1)"\n', "outputs.periodic_orbits.section"),
        ("max_period = 3\n", "or a section"),
    ],
)  # fmt: skip
def test_a_periodic_orbit_table_the_flow_route_cannot_run_is_one_line_exit_2(
    tmp_path, capsys, table, message
):
    scene = _scene(tmp_path, "[outputs.periodic_orbits]\n" + table)
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()


def test_the_dynamics_example_file_runs_on_its_integral_values(tmp_path):
    """examples/systems/routh_sphere_dynamics.toml, shortened: the state it solves for has
    its three integral values (from the mechanics) and its section points keep them."""
    xr = pytest.importorskip("xarray")
    path = ROUTH.parent / "routh_sphere_dynamics.toml"
    shorter = ["outputs.poincare.iterations=6", "outputs.lyapunov.iterations=20"]
    argv = ["run", str(path), "--out", str(tmp_path / "out"), "--quiet"]
    assert main(argv + [a for s in shorter for a in ("--set", s)]) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    start = np.array([float(v) for v in summary["resolved"]["initial"].values()])
    want = np.array([1.3, 0.4, math.sqrt(0.2)])
    assert np.abs(routh_integrals(start) - want).max() <= 100 * np.finfo(float).eps
    names = ["M1", "M2", "M3", "gamma1", "gamma2", "gamma3"]
    with xr.open_dataset(tmp_path / "out" / "poincare.nc") as ds:
        points = np.stack([ds[n].values[0] for n in names], axis=1)
    levels = np.array([routh_integrals(y) for y in points])
    assert np.abs(levels - want).max() <= 1e3 * 1e-12 * 2  # rtol 1e-12 over ~10^3 steps


def test_the_rolling_over_orbit_continued_in_g_keeps_the_quadrature_s_period(tmp_path):
    """[outputs.periodic_orbits.continuation] with a section: the rolling-over orbit followed
    in the gravity g from 1 to 0.8 and to 1.23: at every point of the branch the period is the
    quadrature's at that point's energy and g (the mechanics, above), to the run's accuracy;
    the quadrature at the start's g is refuted at the ends by the same comparison. The orbit
    stays stable (its multipliers on the unit circle: an integrable family)."""
    xr = pytest.importorskip("xarray")
    outputs = (
        '[outputs.periodic_orbits]\nsection = "gamma2"\ntransient = 0\nmax_period = 3\n'
        "detect_tol = 1e-6\nrtol = 1e-12\n[outputs.periodic_orbits.continuation]\n"
        'parameter = "g"\nrange = [0.8, 1.23]\nstep = 0.1\n'
    )
    scene = _scene(tmp_path, outputs, initial="M = [1.5, 0, 0]\ngamma = [0, 0, -1]\n")
    found = _run(tmp_path, scene)["analyses"]["periodic_orbits"]
    branches = found["continuation"]["branches"]
    assert [b["stopped"] for b in branches] == ["reached", "reached"]
    assert [float(b["reached"]) for b in branches] == [0.8, 1.23]
    with xr.open_dataset(tmp_path / "out" / "periodic_orbits.nc") as ds:
        g = ds["branch_parameter"].values
        periods, states = ds["branch_period_time"].values, ds["branch_state"].values
        stable = ds["branch_stable"].values
    assert len(g) == 2 + 2 + 3  # the start twice, 2 steps down, 3 up (0.1 at most each)
    for value, T, state in zip(g, periods, states, strict=True):
        p = {**VALUES, "g": float(value)}
        reference = _rolling_over_period(routh_integrals(state, p)[0], p)
        assert abs(T - reference) <= 1e3 * 1e-12 * reference, (value, T, reference)
        if abs(value - 1.0) > 0.1:
            wrong = _rolling_over_period(routh_integrals(state, p)[0], VALUES)
            assert abs(T - wrong) > 1e6 * 1e-12 * reference
    assert stable.all() and found["continuation"]["stability changes"] == []

