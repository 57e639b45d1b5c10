"""The ``diagram`` output for the ball with a gyrostat (K01 Fig. 7's setting), and its refusal
where no diagram exists.

The curves are the steady rotations ``J omega + K = lam omega`` (numerics/ball/gyrostat_diagram.py).
Checked by independent routes: (1) the generated equations keep such a state's ``omega``
constant; (2) the least and largest energy on a level ``(C, n)``, found by minimising the
generated energy over the level, are energies of the curves (extreme values are critical
values), and the plain ball's curves (K ignored) are refuted by the same comparison; (3) with
``K = 0`` the curves are the ball's derived ``Sigma_i`` (BKM12-Sigma_i, K01-3.2c).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from chaplygin.numerics import integrate
from chaplygin.numerics.ball.bifurcation import sigma
from chaplygin.numerics.ball.gyrostat_diagram import (
    level_integrals,
    steady_rotation_branches,
    steady_rotation_energies,
)
from chaplygin.verify.cli import main
from chaplygin.verify.scene import Scene, SceneError
from scipy.optimize import minimize

SCENES = Path(__file__).resolve().parents[3] / "examples" / "scenes"
FIG7 = {"I": (1.0, 3.0, 5.0), "D": 1.0, "K": (0.1, 0.1, 0.2), "C": 1.0}
GENERIC = {"I": (0.83, 1.37, 2.41), "D": 0.7, "K": (0.13, -0.29, 0.17), "C": 0.9}


def test_curve_states_are_steady_rotations():
    p = GENERIC
    for branch in steady_rotation_branches(p["I"], p["D"], p["K"], p["C"], 3.0)[:4]:
        y = branch["states"][:, len(branch["n"]) // 2]
        r = integrate(
            "chaplygin_ball",
            {"M": tuple(y[:3]), "gamma": tuple(y[3:])},
            20.0,
            {"I": p["I"], "D": p["D"], "K": p["K"]},
            effects=("gyrostat",),
            rtol=1e-12,
            atol=1e-12,
            t_eval=np.linspace(0, 20, 21),
        )
        from chaplygin.numerics.code import load_model_code

        code = load_model_code("chaplygin_ball", ("gyrostat",))
        params = np.array([*p["I"], p["D"], *p["K"]])
        aux = np.asarray(code.numpy.aux(r.t, r.y, params), float)
        omega = aux[[code.aux_names.index(f"omega{i}") for i in (1, 2, 3)]]
        change = np.max(np.abs(omega - omega[:, :1])) / np.linalg.norm(omega[:, 0])
        assert change < 1e-8, (branch["axis"], change)


def _extreme_energies(p, n, starts=2):
    """Least and largest energy on the level (C, n): the generated energy on a grid of the
    level (angles of gamma and of M + K - C gamma about it), refined by Nelder-Mead from the
    best grid points."""
    I, D, K, C = p["I"], p["D"], np.asarray(p["K"]), p["C"]
    ref = np.array([0.31, 0.52, 0.79])
    # a generic tilt of the angles' pole: no extremum sits where the angles degenerate
    TILT = np.linalg.qr(np.array([[0.9, 0.2, -0.3], [0.1, 0.8, 0.4], [0.35, -0.25, 0.7]]))[0]

    def states(q):
        th, ph, a = np.asarray(q, float).reshape(-1, 3).T
        g = TILT @ np.array([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
        e1 = np.cross(g, ref[:, None], axis=0)
        e1 /= np.linalg.norm(e1, axis=0)
        e2 = np.cross(g, e1, axis=0)
        u = np.sqrt(n - C**2) * (np.cos(a) * e1 + np.sin(a) * e2)
        return np.vstack([C * g + u - K[:, None], g])

    def energy(q):
        return level_integrals(states(q), I, D, K)["h"]

    th, ph, a = np.meshgrid(
        np.linspace(0, np.pi, 61), np.linspace(0, 2 * np.pi, 121), np.linspace(0, 2 * np.pi, 61)
    )
    grid = np.column_stack([th.ravel(), ph.ravel(), a.ravel()])
    h = energy(grid)
    out = []
    for sign in (1.0, -1.0):
        best = min(
            minimize(
                lambda q, sign=sign: sign * energy(q)[0],
                grid[k],
                method="Nelder-Mead",
                options={"xatol": 1e-10, "fatol": 1e-16, "maxiter": 4000},
            ).fun
            for k in np.argsort(sign * h)[:starts]
        )
        out.append(sign * best)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("p, n", [(FIG7, 2.0), (GENERIC, 1.73)], ids=["fig7", "generic"])
def test_extreme_energies_of_a_level_lie_on_the_curves(p, n):
    h_min, h_max = _extreme_energies(p, n)
    curves = steady_rotation_energies(p["I"], p["D"], p["K"], p["C"], n)
    # the optimiser meets a quadratic extremum: its energy is good to ~ sqrt(eps) squared
    tol = 1e-10 * max(abs(h_min), abs(h_max))
    assert abs(curves[0] - h_min) < tol and abs(curves[-1] - h_max) < tol, (curves, h_min, h_max)
    # negative control: the plain ball's curves (K ignored) fail the same comparison
    plain = sorted(sigma(i, n, p["C"], p["I"], p["D"]) / 2 for i in range(3))
    assert abs(plain[0] - h_min) > 1e3 * tol or abs(plain[-1] - h_max) > 1e3 * tol


def test_without_gyrostatic_momentum_the_curves_are_the_balls_sigma():
    p = GENERIC
    for n in (1.1, 2.3):
        curves = steady_rotation_energies(p["I"], p["D"], (0.0, 0.0, 0.0), p["C"], n)
        ball = sorted(sigma(i, n, p["C"], p["I"], p["D"]) / 2 for i in range(3))
        # each family p_i appears twice (both senses of rotation)
        assert np.allclose(curves[::2], ball, rtol=1e-12, atol=0)
        assert np.allclose(curves[1::2], ball, rtol=1e-12, atol=0)


def test_gyrostat_scene_draws_its_diagram(tmp_path, capsys):
    out = tmp_path / "fig7d"
    argv = ["run", str(SCENES / "k01-fig7d.toml"), "--out", str(out), "--quiet"]
    argv += ["--set", "run.t_end=5", "--set", "outputs.diagram={plot=true}"]
    assert main(argv) == 0, capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert {"diagram.png", "diagram.svg"} <= {Path(f).name for f in summary["outputs"]}
    # the scene's point (n = 2, h = 0.25) lies between the least and largest energy at its n
    curves = steady_rotation_energies(FIG7["I"], FIG7["D"], FIG7["K"], FIG7["C"], 2.0)
    assert curves[0] < 0.25 < curves[-1]


def test_diagram_refused_where_none_exists(tmp_path, capsys):
    data = {
        "system": "chaplygin_ball",
        "effects": ["variable_inertia"],
        "parameters": {"I": [4, 3, 2], "D": 1, "J_off": 0, "delta": 2, "Omega": 0.4},
        "initial": {"M": [0.1, 0.2, 0.3], "gamma": [0, 0, 1]},
        "run": {"t_end": 1},
        "outputs": {"diagram": {}},
    }
    with pytest.raises(SceneError) as err:
        Scene.from_dict(data).resolve()
    text = str(err.value)
    assert "outputs.diagram: no energy diagram exists for chaplygin_ball__variable_inertia" in text
    assert "chaplygin_ball with effects [gyrostat]" in text and "[none]" in text
    # the CLI: one line, exit 2, nothing written
    scene = tmp_path / "vi.toml"
    scene.write_text(
        'system = "chaplygin_ball"\neffects = ["variable_inertia"]\n[parameters]\n'
        "I = [4, 3, 2]\nD = 1\nJ_off = 0\ndelta = 2\nOmega = 0.4\n[initial]\n"
        "M = [0.1, 0.2, 0.3]\ngamma = [0, 0, 1]\n[run]\nt_end = 1\n[outputs]\n"
        "diagram = { plot = true }\n"
    )
    out = tmp_path / "o"
    assert main(["run", str(scene), "--out", str(out)]) == 2
    err_text = capsys.readouterr().err
    assert err_text.count("\n") == 1 and "vi.toml:15: outputs.diagram" in err_text
    assert not out.exists()


def test_support_scene_marks_its_point_on_bkm12_fig5():
    c, s = np.cos(0.4), np.sin(0.4)
    alpha, beta, gamma = [1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]
    M = [0.3, -0.7, 0.45]
    scene = Scene.from_dict(
        {
            "system": "spherical_support",
            "parameters": {"I": [1, 1.5, 3], "D_iso": 0.5, "D_al": 0.3, "D_be": -0.2},
            "initial": {"M": M, "alpha": alpha, "beta": beta, "gamma": gamma},
            "run": {"t_end": 1, "rtol": 1e-10},
            "outputs": {"diagram": {}},
        }
    )
    fig = scene.run().diagram_figure()
    Mv = np.array(M)
    g = [Mv @ v / np.linalg.norm(Mv) for v in map(np.array, (alpha, beta, gamma))]
    for ax in fig.axes[:4]:
        star = ax.lines[-1]
        assert star.get_marker() == "*"
        assert np.allclose([star.get_xdata()[0], star.get_ydata()[0]], g[:2], rtol=1e-12)


@pytest.mark.parametrize("p", [FIG7, GENERIC], ids=["fig7", "generic"])
def test_curves_end_on_the_segment_where_gamma_is_parallel_to_omega(p):
    # at the end of a family gamma || omega, so M + K = lam omega - D s gamma || gamma: n = C^2
    n_max = 3.0
    branches = steady_rotation_branches(p["I"], p["D"], p["K"], p["C"], n_max)
    on_segment = 0
    for b in branches:
        step = np.max(np.abs(np.diff(b["n"])))
        for end in (b["n"][0], b["n"][-1]):
            # an end is where the family stops existing (then on n = C^2) or the clip at n_max
            if end == pytest.approx(p["C"] ** 2, rel=1e-12):
                on_segment += 1
            else:
                assert end > n_max - step, (b["axis"], end)
    assert on_segment >= 2


def test_steady_rotation_stability_without_k_is_the_balls():
    """K = 0: the multipliers of a branch state (J omega = lam omega, numerics) are those of
    the ball's derived steady rotation on the same level (numerics.ball.stability, derive)."""
    from chaplygin.numerics.ball.gyrostat_diagram import steady_rotation_stability
    from chaplygin.numerics.ball.stability import steady_rotation_floquet

    p = GENERIC
    K0 = (0.0, 0.0, 0.0)
    checked = set()
    for b in steady_rotation_branches(p["I"], p["D"], K0, p["C"], 3.0):
        k = len(b["n"]) // 2
        state = b["states"][:, k]
        M, g = state[:3], state[3:]
        r = steady_rotation_stability(p["I"], p["D"], K0, state)
        ball = steady_rotation_floquet(tuple(p["I"]), p["D"], float(M @ M), float(M @ g))
        axis = int(np.argmax(np.abs(M)))
        assert r.stable == ball[axis].stable
        assert r.max_abs == pytest.approx(ball[axis].max_abs, rel=1e-6)
        checked.add((axis, r.stable))
    # the middle axis (I2) is the unstable one, the others stable
    assert {(0, True), (1, False), (2, True)} <= checked


def test_a_hyperbolic_rotation_separates_neighbours_by_its_multiplier():
    """K01 Fig. 7 at n = 2: the rotation at h = 0.260845 has max|mu| = 38.2; a neighbouring
    state separates from it by that factor per period (the variational equations are not
    used: two integrations of the full equations)."""
    from chaplygin.numerics.ball.gyrostat_diagram import steady_rotations_on_level

    p = FIG7
    level = steady_rotations_on_level(p["I"], p["D"], p["K"], p["C"], 2.0)
    unstable = [r for r in level if not r["stable"]]
    assert [round(r["h"], 6) for r in unstable] == [0.260845, 0.341014]
    rot = unstable[0]
    T = rot["period"]
    y0 = np.asarray(rot["state"], float)
    dy = 1e-10 * np.array([0.3, -0.7, 0.2, 0.5, 0.1, -0.4])
    runs = [
        integrate("chaplygin_ball", y, 4 * T, {"I": p["I"], "D": p["D"], "K": p["K"]},
                  effects=("gyrostat",), rtol=1e-13, atol=1e-15, t_eval=[3 * T, 4 * T]).y
        for y in (y0, y0 + dy)
    ]  # fmt: skip
    gap = np.linalg.norm(runs[1] - runs[0], axis=0)
    assert gap[1] / gap[0] == pytest.approx(rot["max_abs"], rel=0.05)
    # the elliptic ones do not separate so
    stable = next(r for r in level if r["stable"])
    ys = [
        integrate("chaplygin_ball", y, 4 * stable["period"], {"I": p["I"], "D": p["D"],
                  "K": p["K"]}, effects=("gyrostat",), rtol=1e-13, atol=1e-15).y[:, -1]
        for y in (stable["state"], np.asarray(stable["state"]) + dy)
    ]  # fmt: skip
    assert np.linalg.norm(ys[1] - ys[0]) < 100 * np.linalg.norm(dy)


def test_gyrostat_diagram_draws_stability():
    from chaplygin.verify.outputs.diagram import gyrostat_diagram_figure

    p = FIG7
    fig = gyrostat_diagram_figure(p["I"], p["D"], p["K"], p["C"], 2.7, 0.3, "t", samples=50)
    ax = fig.axes[0]
    styles = {
        (line.get_color(), line.get_linestyle()) for line in ax.lines if len(line.get_xdata()) > 2
    }
    # the branches with lam near J2 (red) are dashed (hyperbolic), the others solid
    assert ("tab:red", "--") in styles and ("tab:red", "-") not in styles
    assert ("tab:green", "-") in styles and ("tab:blue", "-") in styles
    assert "stability by Floquet multipliers" in ax.get_title()
