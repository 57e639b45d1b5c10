"""Described systems end to end: discovery finds and proves, the verifier proves a model's
integrals and refutes its controls, scenes and ``verify --system`` run.

Kane's cross-checks of described systems are in ``test_described_kane_bodies.py`` and
``test_described_kane_supports.py`` (split from this module so that, under ``--dist
loadfile``, no worker carries them all). Jellett's integral ``(I omega, a + b gamma)``
(Routh's sphere) is typed from the literature, not taken from the search.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.cli import main
from chaplygin.verify.discover import discover
from chaplygin.verify.identity import Domain, decide, lie_derivative, measure_residual

ROOT = Path(__file__).resolve().parents[2]
SYSTEMS = ROOT / "examples" / "systems"


def test_routh_sphere_jellett_integral_and_density_are_found_and_proved():
    system = RollingSystem(
        "routh_found", inertia=("A", "A", "C"), centre_of_mass=(0, 0, "a"), gravity="g"
    )
    found = discover(
        system, degree=1, coefficient_degree=1, momentum="omega", in_parameters=True,
        densities=True,
    )  # fmt: skip
    assert found.all_proved
    (F,) = found.search.integrals
    assert found.search.rank == found.search.unknowns - 1  # no other in the class
    A, C, b = (sp.Symbol(n, positive=True) for n in ("A", "C", "b"))
    a = sp.Symbol("a", real=True)
    w = sp.Matrix(sp.symbols("omega1:4", real=True))
    gamma = sp.Matrix(sp.symbols("gamma1:4", real=True))
    jellett = (sp.diag(A, A, C) * w).dot(sp.Matrix([0, 0, a]) + b * gamma)
    assert sp.cancel(F / jellett).is_number  # the same integral up to a constant factor
    assert found.densities.found and found.density_proof.verdict == "proved"
    # negative control: the inverse power is refuted by the same decision procedure
    from chaplygin.derive.systems import build_model

    routh = build_model("routh_found")
    wrong = 1 / found.densities.density()
    assert decide([measure_residual(wrong, routh)], Domain(routh)).verdict == "refuted"


def test_chaplygin_top_has_the_energy_and_no_density_in_the_family():
    system = RollingSystem(
        "top_found", inertia=("0.4", "0.5", "0.6"), mass=1, radius=1,
        centre_of_mass=(0, 0, "a"), gravity=1,
    )  # fmt: skip
    found = discover(
        system, degree=2, coefficient_degree=2, momentum="omega", in_parameters=True,
        densities=True,
    )  # fmt: skip
    assert found.all_proved and len(found.search.integrals) == 1
    assert found.search.rank == found.search.unknowns - 1
    assert not found.densities.found
    assert found.densities.augmented_rank == found.densities.rank + 1  # the certificate


def _cli(*args, cache):
    env = {"CHAPLYGIN_CACHE_DIR": str(cache), "PATH": "/usr/bin:/bin"}
    return subprocess.run(
        [sys.executable, "-m", "chaplygin.verify.cli", *args],
        capture_output=True, text=True, env=env, timeout=600,
    )  # fmt: skip


def test_discover_reads_a_description_file(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    argv = [
        "discover", str(SYSTEMS / "routh_sphere.toml"), "--degree", "1",
        "--coefficient-degree", "1", "--momentum", "omega", "--in-parameters", "--json",
    ]  # fmt: skip
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert [i["verdict"] for i in data["integrals"]] == ["proved"]
    assert data["dimension"] == 1


@pytest.mark.parametrize(
    "table, message",
    [
        ('name = "bad"\ninertia = [[1, 0, 0], [0, 1, 0], [0, 0, 0]]', "singular"),
        ('name = "bad"\ninertia = [1, 1, 1]\npotential = "open(1)"', "not allowed"),
        ('name = "chaplygin_ball"\ninertia = [1, 1, 1]', "taken by a built-in"),
        (
            'name = "bad"\ninertia = [1, 2, 1]\nsupport = "surface"\n'
            'support_surface = "p1**2 + p3"\ncontact = "line"',
            "not contact 'line'",
        ),
        ('name = "bad"\ninertia = [1, 1, 1]\nsupport = "sphere"', "needs support_radius"),
    ],
)
def test_bad_system_tables_are_one_line_exit_2_and_cache_nothing(
    tmp_path, table, message, capsys, monkeypatch
):
    scene = tmp_path / "bad.toml"
    scene.write_text(
        f"[system]\n{table}\n\n[initial]\nM = [0, 0, 1]\ngamma = [0, 0, 1]\n\n[run]\nt_end = 1\n"
    )
    cache = tmp_path / "cache"
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(cache))
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert "Traceback" not in err
    assert not (tmp_path / "out").exists()
    assert not cache.exists() or not any(p.is_file() for p in cache.rglob("*"))


def test_a_scene_with_a_system_table_runs(tmp_path):
    """The Routh sphere example, shortened, on the numpy backend (no compiler needed)."""
    scene = SYSTEMS / "routh_sphere.toml"
    out = _cli(
        "run", str(scene), "--out", str(tmp_path / "out"), "--set", "run.t_end=3",
        "--set", "run.backend=numpy", "--set", "run.method=DOP853", "--json",
        cache=tmp_path / "cache",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    assert max(abs(float(v)) for v in drift.values()) < 1e-8
    assert (tmp_path / "out" / "contact_trace.png").stat().st_size > 0


def test_verify_system_checks_the_models_and_the_files_claims(tmp_path):
    """The derived model's integrals and its Kane cross-check, the finds of the file's
    [discover] class and its dimension (the search run again, exactly), the file's three
    claims proved and its control refuted by the same decision procedure (exit 0: every
    verdict the expected one)."""
    # the energy's proof (6 s) and Routh's integral squared (2 s) are left to the example
    # run of the README; the others cover every kind of claim the file makes
    claims = (
        "routh_sphere:kane,routh_sphere:found-*,routh_sphere:(gamma*,ROUTH-jellett*,ROUTH-density"
    )
    out = _cli(
        "verify", "--system", str(SYSTEMS / "routh_sphere.toml"), "--jobs", "1", "--json",
        "--claims", claims, cache=tmp_path / "cache",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    verdicts = {v["id"]: v["verdict"] for v in json.loads(out.stdout)}
    assert verdicts == {
        "routh_sphere:(gamma,gamma)": "proved",
        "routh_sphere:kane": "numeric",  # KanesMethod agrees at 40 digits
        "routh_sphere:found-F1": "proved",  # [discover]: Jellett's integral, found
        "routh_sphere:found-class-integrals": "proved",  # its dimension, searched again
        "routh_sphere:found-density": "proved",
        "ROUTH-jellett": "proved",
        "ROUTH-density": "proved",
        "ROUTH-jellett/control-balanced": "refuted",
    }


def test_a_wrong_claim_expected_to_hold_fails_the_run(tmp_path, capsys, monkeypatch):
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[discover]")[0]
    bad = tmp_path / "wrong.toml"
    bad.write_text(
        text + '[[claims]]\nid = "W"\nkind = "integral"\nexpression = "M1*gamma1 + M2*gamma2"\n'
    )
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "c"))
    assert main(["verify", "--system", str(bad), "--jobs", "1", "--claims", "W"]) == 1
    assert "UNEXPECTED: W" in capsys.readouterr().out


@pytest.mark.parametrize(
    "entry, message",
    [
        ('id = "X"\nkind = "integral"\nexpression = "__import__(1)"', "not allowed"),
        ('id = "X"\nkind = "integral"\nexpression = "q1*gamma1"', "unknown name 'q1'"),
        ('id = "X"\nkind = "theorem"\nexpression = "gamma1"', "kind"),
    ],
)
def test_bad_claims_are_one_line_exit_2(tmp_path, entry, message, capsys, monkeypatch):
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[discover]")[0]
    bad = tmp_path / "bad.toml"
    bad.write_text(text + "[[claims]]\n" + entry + "\n")
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "c"))
    assert main(["verify", "--system", str(bad), "--jobs", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


@pytest.mark.slow
def test_a_homogeneous_ball_in_a_spherical_bowl_swings_as_a_pendulum_of_length_7_5_r():
    """A homogeneous ball (I = 2/5 m b^2) rolling in a vertical plane inside a fixed sphere
    of radius R: the energy m (R - b)^2 theta'^2 (1 + 2/5)/2 - m g (R - b) cos theta (the
    centre's speed (R - b) theta', the spin (R - b) theta'/b) makes the centre a pendulum of
    length 7/5 (R - b), period 4 K(sin^2(theta0/2)) sqrt(7 (R - b)/(5 g)) from rest at
    theta0 (written here, not derived by chaplygin). After that period the state returns;
    after half of it the ball is at rest on the other side, and the period of the
    point-mass pendulum of length R - b is the control."""
    import math

    import chaplygin
    import mpmath
    import numpy as np

    system = RollingSystem(
        "ball_in_bowl", inertia=("2/5*m*b**2",) * 3, gravity="g", support="sphere",
        support_radius="R", side="inside",
    )  # fmt: skip
    chaplygin.register_system(system)
    m, b, R, g, theta0, rtol = 1.3, 0.7, 2.9, 9.81, 0.6, 1e-11
    L = (R - b) * 7 / 5
    period = float(4 * mpmath.ellipk(math.sin(theta0 / 2) ** 2) * mpmath.sqrt(L / g))
    control = float(4 * mpmath.ellipk(math.sin(theta0 / 2) ** 2) * mpmath.sqrt((R - b) / g))
    # the body axes start as the space axes: gamma points from the contact to the centre
    gamma = (-math.sin(theta0), 0.0, math.cos(theta0))
    times = [0.0, period / 2, control, period]  # control = period/sqrt(7/5)
    run = chaplygin.integrate(
        "ball_in_bowl", {"M": (0.0, 0.0, 0.0), "gamma": gamma, "zeta": (0.0, 0.0, 1.0)},
        (0, period), {"m": m, "b": b, "R": R, "g": g}, method="DOP853", backend="numpy",
        rtol=rtol, atol=rtol, t_eval=times,
    )  # fmt: skip
    y = np.asarray(run.y, dtype=float)
    names = list(map(str, run.state_names))
    M = y[[names.index(f"M{i}") for i in (1, 2, 3)], :]
    height = sum(  # (gamma, zeta): the cosine of the swing
        y[names.index(f"gamma{i}"), :] * y[names.index(f"zeta{i}"), :] for i in (1, 2, 3)
    )
    # about 10^3 steps: the global error of a tolerance-controlled run grows about linearly
    bound = 1e3 * rtol
    assert abs(height[3] - height[0]) <= bound and abs(height[1] - height[0]) <= bound
    scale = m * b * math.sqrt(2 * g * (R - b) * (1 - math.cos(theta0)))  # |M| at the bottom
    assert np.abs(M[:, 3]).max() <= bound * scale and np.abs(M[:, 1]).max() <= bound * scale
    assert abs(height[2] - height[0]) > 1e6 * bound  # the point mass's period: not back


def test_a_prescribed_gyrostat_keeps_the_total_momentum_s_integrals_and_loses_the_energy():
    """A balanced body with rotors set to K(t) on a fixed plane: P = M + K(t) obeys P' = P
    x omega (the support's reaction passes through the centre), so (P, P) and (P, gamma)
    are integrals although they depend on time — proved by the verifier with the explicit
    time derivative; (M, M) and the energy of the frozen rotors are refuted by the same
    machinery."""
    system = RollingSystem(
        "motor_ball", inertia=("I1", "I2", "I3"), gyrostat=("k*cos(w*t)", "k*sin(w*t)", "K3")
    )
    model = system.model()
    names = [n for n, _ in model.integrals]
    assert "H" not in names and "(M+K,M+K)" in names and "(M+K,gamma)" in names
    for name, expr in model.integrals:
        assert decide([lie_derivative(expr, model)], Domain(model)).verdict == "proved", name
    M = sp.Matrix(model.group("M"))
    assert decide([lie_derivative(M.dot(M), model)], Domain(model)).verdict == "refuted"
    constant = RollingSystem("frozen_ball", inertia=("I1", "I2", "I3"), gyrostat=("k", 0, "K3"))
    energy = dict(constant.model().integrals)["H"]
    assert decide([lie_derivative(energy, model)], Domain(model)).verdict == "refuted"


def test_a_ball_with_a_time_dependent_inertia_keeps_the_momentum_integrals_not_the_energy():
    """A balanced ball whose inertia changes, I(t) = diag(I1 (1 + e t^2), I2, I3): the
    momentum about the contact point still obeys M' = M x omega, so (M, M) and (M, gamma)
    are integrals (as for BM20's ball) — proved by the verifier with the explicit time
    derivative. The energy (M, omega)/2 is refuted by the same machinery (at numbers: the
    symbolic refutation costs 15 s of expansion)."""
    system = RollingSystem("breathing_ball", inertia=("I1*(1 + e*t**2)", "I2", "I3"))
    model = system.model()
    names = [n for n, _ in model.integrals]
    assert "H" not in names and {"(M,M)", "(M,gamma)"} <= set(names)
    for name, expr in model.integrals:
        assert decide([lie_derivative(expr, model)], Domain(model)).verdict == "proved", name
    numbers = RollingSystem(
        "breathing_numbers", inertia=("31/100*(1 + 7/100*t**2)", "43/100", "57/100"),
        mass="13/10", radius="7/10",
    ).model()  # fmt: skip
    energy = sp.Matrix(numbers.group("M")).dot(numbers.omega) / 2
    assert decide([lie_derivative(energy, numbers)], Domain(numbers)).verdict == "refuted"
    assert "H" in dict(RollingSystem("frozen", inertia=("I1", "I2", "I3")).model().integrals)


def test_the_ball_over_a_sphere_keeps_the_plane_s_density_and_loses_the_area_integral():
    """The Chaplygin ball over a fixed sphere (examples/systems/chaplygin_ball_on_sphere.toml
    at numbers): in the class of degree <= 2 in omega with coefficients of degree <= 2 in
    gamma only the energy and (M, M) (rank = the proof); the density found is BKM12-4's
    (1/D - (gamma, A gamma))^-1/2 of the plane, written here from the paper."""
    numbers = dict(I1="0.31", I2="0.43", I3="0.57", m="1.3", b="0.7", R="2.3")
    system = RollingSystem(
        "ball_over_sphere", inertia=(numbers["I1"], numbers["I2"], numbers["I3"]),
        mass=numbers["m"], radius=numbers["b"], support="sphere", support_radius=numbers["R"],
    )  # fmt: skip
    found = discover(system, degree=2, coefficient_degree=2, momentum="omega", densities=True)
    assert found.all_proved and len(found.search.integrals) == 2
    assert found.search.rank == found.search.unknowns - 2
    assert found.densities.found and found.density_proof.verdict == "proved"
    I = [sp.Rational(numbers[k]) for k in ("I1", "I2", "I3")]
    D = sp.Rational(numbers["m"]) * sp.Rational(numbers["b"]) ** 2
    gamma = sp.symbols("gamma1:4", real=True)
    paper = 1 / D - sum((gamma[i] ** 2 / (I[i] + D) for i in range(3)), sp.S.Zero)
    rho = found.densities.density()
    assert sp.cancel(rho**-2 / paper).is_number  # the same up to a constant factor
    # the plane's area integral (M, gamma) is refuted by the same decision procedure
    from chaplygin.derive.systems import build_model

    model = build_model("ball_over_sphere")
    M, g = model.group("M"), model.group("gamma")
    area = sum((M[i] * g[i] for i in range(3)), sp.S.Zero)
    assert decide([lie_derivative(area, model)], Domain(model)).verdict == "refuted"


@pytest.mark.slow
def test_a_homogeneous_ball_on_a_turntable_returns_after_seven_halves_of_its_turn():
    """Earnshaw (1844; Routh, Advanced Rigid Dynamics): a homogeneous ball (I = 2/5 m b^2)
    on a plane turning at Omega rolls so that its centre describes a circle uniformly in
    7/2 of the plane's period, 7 pi/Omega. The distance |rho| of the contact point from the
    axis is invariant under rotations, so |rho|^2 has that period; the plane's own period
    2 pi/Omega is the control. An integrable, not chaotic, motion."""
    import math

    import chaplygin
    import numpy as np

    system = RollingSystem(
        "earnshaw_ball", inertia=("2/5*m*b**2",) * 3, support="rotating_plane",
        rotation_rate="Omega",
    )  # fmt: skip
    chaplygin.register_system(system)
    Omega, rtol = 0.37, 1e-11
    period = 7 * math.pi / Omega
    gamma = np.array([2.0, 3.0, 6.0]) / 7
    seed = np.array([5 / 7, -3 / 11, 2 / 13])
    rho = seed - seed.dot(gamma) * gamma  # horizontal: (rho, gamma) = 0
    times = [0.0, 2 * math.pi / Omega, 0.5 * period, period]
    run = chaplygin.integrate(
        "earnshaw_ball", {"M": (0.3, -0.7, 1.1), "gamma": tuple(gamma), "rho": tuple(rho)},
        (0, period), {"m": 1.3, "b": 0.7, "Omega": Omega}, method="DOP853", backend="numpy",
        rtol=rtol, atol=rtol, t_eval=times,
    )  # fmt: skip
    y = np.asarray(run.y, dtype=float)
    at = [list(map(str, run.state_names)).index(f"rho{i}") for i in (1, 2, 3)]
    d2 = (y[at, :] ** 2).sum(axis=0)
    # a tolerance-controlled run's global error grows about linearly over its ~10^3 steps
    bound = 1e3 * rtol * d2.max()
    assert abs(d2[3] - d2[0]) <= bound
    assert abs(d2[1] - d2[0]) > 1e6 * bound  # not the plane's period
    assert abs(d2[2] - d2[0]) > 1e6 * bound  # not a constant


def test_on_a_turntable_the_fixed_frame_trace_is_the_carried_position():
    """With the contact_point effect (the fixed frame alpha, beta and the trace x, y): x -
    (rho, alpha) and y - (rho, beta) are first integrals (the trace drawn in the fixed frame
    is the contact point the plane carries), proved by the verifier; x + (rho, alpha) is
    refuted by the same machinery."""
    system = RollingSystem(
        "turntable_trace", inertia=("I1", "I2", "I3"), support="rotating_plane",
        rotation_rate="Omega",
    )  # fmt: skip
    model = system.model(("contact_point",))
    groups = dict(model.state_groups)
    rho, alpha, beta = (sp.Matrix(groups[n]) for n in ("rho", "alpha", "beta"))
    x, y = groups["x"][0], groups["y"][0]
    for carried in (x - rho.dot(alpha), y - rho.dot(beta)):
        assert decide([lie_derivative(carried, model)], Domain(model)).verdict == "proved"
    wrong = x + rho.dot(alpha)
    assert decide([lie_derivative(wrong, model)], Domain(model)).verdict == "refuted"


def test_a_plane_moving_uniformly_gives_the_fixed_plane_s_motion():
    """Galilean invariance: on a plane moving at a constant velocity the motion relative to
    the plane is the fixed plane's, so the rates of M and gamma are equal at any point
    (exact), although the momentum about the contact differs by m r x V."""
    fields = dict(inertia=("I1", "I2", "I3"), centre_of_mass=(0, "a2", "a3"), gravity="g")
    moving = RollingSystem("uniform", support="moving_plane", plane_velocity=("V1", "V2"), **fields)
    fixed = RollingSystem("fixed", **fields)
    mm, fm = moving.model(), fixed.model(("contact_point",))  # the fixed plane with its frame
    names = {s.name: s for s in (*mm.state, *mm.params)}
    fnames = {s.name: s for s in (*fm.state, *fm.params)}
    frame = {"gamma": (2, 3, 6), "alpha": (3, -6, 2), "beta": (6, 2, -3)}  # orthonormal / 7
    values = {f"{n}{i + 1}": sp.Rational(v[i], 7) for n, v in frame.items() for i in range(3)}
    values.update({f"M{i}": sp.Rational(3 * i - 7, 11) for i in (1, 2, 3)})
    values.update(m=sp.Rational(13, 10), b=sp.Rational(7, 10), I1=sp.Rational(3, 7))
    values.update(I2=sp.Rational(5, 9), I3=sp.Rational(8, 11), a2=sp.Rational(-1, 9))
    values.update(a3=sp.Rational(2, 13), g=sp.Rational(49, 5), V1=sp.Rational(4, 3))
    values.update(V2=sp.Rational(-5, 6))
    for group in ("M", "gamma"):
        for s in mm.group(group):
            ours = mm.rhs_expanded[mm.state.index(s)].xreplace(
                {names[k]: v for k, v in values.items() if k in names}
            )
            theirs = fm.rhs_expanded[fm.state.index(fnames[s.name])].xreplace(
                {fnames[k]: v for k, v in values.items() if k in fnames}
            )
            assert sp.simplify(ours - theirs) == 0, s
    # the momentum about the contact differs: the state leaves out m r x V
    P0 = mm.details.gyrostatic_momentum.xreplace(
        {names[k]: v for k, v in values.items() if k in names}
    )
    assert not P0.applyfunc(sp.simplify).is_zero_matrix


def test_a_convex_body_keeps_its_contact_on_its_surface():
    """A heavy ellipsoid off centre: the level of f (the contact point stays on the body's
    surface) is proved an integral by the verifier; the kinetic energy alone is refuted
    by the same machinery (gravity does work on it)."""
    system = RollingSystem(
        "heavy_ellipsoid", inertia=("I1", "I2", "I3"),
        surface="x1**2/0.81 + x2**2/0.49 + x3**2/0.25 - 1", centre_of_mass=(0, 0, "0.1"),
        gravity="g",
    )  # fmt: skip
    model = system.model()
    assert [n for n, _ in model.integrals] == ["H", "f"]
    proof = decide([lie_derivative(model.integral("f"), model)], Domain(model))
    assert proof.verdict == "proved"
    omega = sp.Matrix(model.group("omega"))
    I = sp.diag(*sp.symbols("I1:4", positive=True))
    kinetic = (omega.T * I * omega)[0] / 2
    assert decide([lie_derivative(kinetic, model)], Domain(model)).verdict == "refuted"


@pytest.mark.expensive  # 27 s: derives Routh's sphere, searches its symmetries twice (5 s each)
def test_symmetries_and_relations_of_a_file_become_claims(tmp_path, capsys, monkeypatch):
    """Routh's sphere (moments A, A, C, centre of mass on the axis) is symmetric about its
    axis: the rotation (omega2, -omega1, 0, gamma2, -gamma1, 0) in (omega, gamma) is found
    and proved a symmetry; the class's dimension (1) is a claim, searched again exactly; the
    linear class with a cofactor of degree <= 1 holds no invariant relation: a claim too."""
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[discover]")[0]
    path = tmp_path / "routh_linear.toml"
    path.write_text(
        text + '[discover]\ndegree = 1\ncoefficient_degree = 0\nmomentum = "omega"\n'
        "relations = true\nsymmetries = true\n"
    )
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "c"))
    argv = ["verify", "--system", str(path), "--jobs", "1", "--json", "--claims", "*:found-*"]
    assert main(argv) == 0
    verdicts = {v["id"]: v for v in json.loads(capsys.readouterr().out)}
    assert {k: v["verdict"] for k, v in verdicts.items()} == {
        "routh_sphere:found-class-integrals": "proved",
        "routh_sphere:found-X1": "proved",
        "routh_sphere:found-class-symmetries": "proved",
        "routh_sphere:found-class-relations": "proved",
    }
    assert "gamma2, -gamma1, 0" in verdicts["routh_sphere:found-X1"]["statement"]
    assert (
        "exactly 0 independent invariant"
        in (verdicts["routh_sphere:found-class-relations"]["statement"])
    )


@pytest.mark.slow
def test_a_described_system_takes_the_dynamics_outputs(tmp_path):
    """Routh's sphere from its description file with a Poincaré section (gamma1 = 0, the
    Taylor integrator locates the crossings) and the full Lyapunov spectrum (variational
    equations from the generated Jacobian): every requested crossing is found, and the sum
    of the six exponents equals the mean divergence of the field (Liouville: log det of the
    flow's derivative), both per unit time. The default cache (first use compiles)."""
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[outputs]")[0]
    text = text.replace("t_end = 60", "t_end = 1")
    text += (
        "[outputs.lyapunov]\niterations = 20\ntransient = 2\ninterval = 1.0\n"
        'spectrum = "full"\nstates = 1\nwindows = 2\nplot = false\n\n'
        '[outputs.poincare]\nsection = "gamma1"\niterations = 5\nplot = false\n'
    )
    scene = tmp_path / "routh_dynamics.toml"
    scene.write_text(text)
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 0
    analyses = json.loads((tmp_path / "out" / "summary.json").read_text())["analyses"]
    section = analyses["poincare"]
    assert section["complete"] and section["crossings"] == section["points"] == 5
    full = analyses["lyapunov"]["full"]["per_unit_time"]
    assert full["units"] == "per unit time" and len(full["exponents"]) == 6
    scale = max(abs(x) for x in full["exponents"])
    # the two integrate the same log det to the run's rtol 1e-12 over ~10^2..10^3 steps
    assert abs(full["sum_of_exponents"] - full["mean_divergence"]) <= 1e3 * 1e-12 * scale


def test_an_ellipsoid_on_a_sphere_keeps_its_energy_and_its_surface():
    """An ellipsoid rolling inside a fixed sphere (M03 §2's stage): the energy and the
    level of f are proved integrals by the verifier; (omega, omega) is refuted by the same
    machinery (a tumbling body's spin changes)."""
    system = RollingSystem(
        "egg_in_bowl", inertia=("31/100", "43/100", "57/100"), mass="13/10",
        surface="x1**2/(7/10)**2 + x2**2/(3/5)**2 + x3**2/(1/2)**2 - 1", support="sphere",
        support_radius="29/10", side="inside",
    )  # fmt: skip
    model = system.model()
    assert [n for n, _ in model.integrals] == ["H", "f"]
    for name, expr in model.integrals:
        assert decide([lie_derivative(expr, model)], Domain(model)).verdict == "proved", name
    w = model.omega
    assert decide([lie_derivative(w.dot(w), model)], Domain(model)).verdict == "refuted"


@pytest.mark.slow  # 30 s under load: the normal's square root in every decision
def test_a_ball_on_an_ellipsoidal_hill_keeps_its_energy_and_the_support_s_level():
    """A homogeneous heavy ball outside a fixed ellipsoid (support_surface, the contact
    point p in the fixed frame): the energy and the level of F are proved integrals; the
    kinetic energy alone (the energy less m g times the centre's height p3 + b nu3) is
    refuted by the same machinery."""
    system = RollingSystem(
        "ball_on_hill", inertia=("2/5*m*(7/10)**2",) * 3, radius="7/10", gravity="49/5",
        support="surface", support_surface="p1**2/4 + p2**2/(9/4) + p3**2 - 1",
    )  # fmt: skip
    model = system.model()
    assert [n for n, _ in model.integrals] == ["H", "F"]
    for name, expr in model.integrals:
        assert decide([lie_derivative(expr, model)], Domain(model)).verdict == "proved", name
    p3 = model.group("p")[2]
    kinetic = model.integral("H") - sp.Rational(49, 5) * (p3 + sp.Rational(7, 10) * model.aux[2][0])
    assert decide([lie_derivative(kinetic, model)], Domain(model)).verdict == "refuted"


CONVEX_SCENE = """title = "a heavy ellipsoid on a turntable, traced"
[system]
name = "traced_ellipsoid"
inertia = ["0.31", "0.43", "0.57"]
mass = 1
surface = "x1**2/0.81 + x2**2/0.49 + x3**2/0.25 - 1"
centre_of_mass = [0, 0, "0.1"]
gravity = "g"
support = "rotating_plane"
rotation_rate = "Omega"

[parameters]
g = 9.81
Omega = 0.37

[initial]
omega = [0.3, -0.2, 0.9]
r = [0, 0, -0.6]
rho = [1.2, 0.3, 0]
alpha = [1, 0, 0]
beta = [0, 1, 0]
x = 1.2
y = 0.3

[run]
t_end = 3
rtol = 1e-11
atol = 1e-11
backend = "numpy"
method = "DOP853"

[outputs]
contact_trace = { plot = true }
body_trace = { plot = true }
"""


def test_a_convex_body_on_a_turntable_draws_its_traces_from_a_scene(tmp_path):
    """A described convex body asks for both traces: the contact_point effect is added for
    them, both figures are written, and along the run the trace stays rho's projection on
    the fixed axes (x - (rho, alpha) keeps its initial value 0 to the run's tolerance: the
    shipped integral, a different formula from x' = (alpha, u)). A described ball whose
    radius is a number draws its body trace too (no parameter b)."""
    scene = tmp_path / "traced.toml"
    scene.write_text(CONVEX_SCENE)
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out)]) == 0
    assert (out / "contact_trace.png").stat().st_size > 0
    assert (out / "body_trace.png").stat().st_size > 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["effects"] == ["contact_point"]
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    scale = 1.2  # |x(0)|: the integral's values are O(1), its drift absolute
    assert abs(float(drift["x-(rho,alpha)"])) < 1e3 * 1e-11 * scale
    ball = tmp_path / "ball.toml"
    ball.write_text(
        'title = "top"\n[system]\nname = "numeric_radius_top"\ninertia = ["0.4", "0.5", '
        '"0.6"]\nmass = 1\nradius = "0.7"\ncentre_of_mass = [0, 0, "0.2"]\ngravity = 1\n'
        '[initial]\nM = [0.3, -0.2, 0.9]\ngamma = [0.28, 0.3, "sqrt(1 - 0.28**2 - 0.3**2)"]\n'
        '[run]\nt_end = 1\nbackend = "numpy"\nmethod = "DOP853"\n'
        "[outputs]\nbody_trace = { plot = true }\n"
    )
    assert main(["run", str(ball), "--out", str(tmp_path / "ball")]) == 0
    assert (tmp_path / "ball" / "body_trace.png").stat().st_size > 0


def test_a_ball_on_an_ellipsoid_named_by_its_centre_s_surface_runs_from_a_scene(tmp_path):
    """M03's ball whose centre moves on (x, B^-1 x) = 1 as a [system] table (centre_surface,
    a potential of the centre; the built-in ball_on_surface's description): the scene gives
    the centre x as three numbers; the energy and the level of the centre's surface keep
    their values to the run's tolerance (their drifts are the evidence)."""
    scene = tmp_path / "ellipsoid_ball.toml"
    scene.write_text(
        'title = "ball on an ellipsoid"\n[system]\nname = "scene_ellipsoid_ball"\n'
        'inertia = ["m_e*R**2", "m_e*R**2", "m_e*R**2"]\nradius = "R"\nsupport = "surface"\n'
        'centre_surface = "x1**2/b1 + x2**2/b2 + x3**2/b3 - 1"\n'
        'potential = "k*(x1**2 + x2**2 + x3**2)/2"\npositive = ["m_e", "b1", "b2", "b3"]\n'
        "[parameters]\nm = 1.3\nm_e = 0.4\nR = 0.2\nb1 = 4\nb2 = 2.25\nb3 = 1\nk = 0.3\n"
        "[initial]\nomega = [0.3, -0.2, 0.9]\nx = [1.2, 0.9, \"sqrt(0.28)\"]\n"
        '[run]\nt_end = 2\nrtol = 1e-11\natol = 1e-11\nbackend = "numpy"\nmethod = "DOP853"\n'
    )
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    assert set(drift) == {"H", "F"}
    assert max(abs(float(v)) for v in drift.values()) < 1e3 * 1e-11
