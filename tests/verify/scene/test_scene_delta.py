"""The ``separatrix_delta`` scene output: Delta measured between the two asymptotic centres of
the contact-point trace agrees with the closed form K01-3.7 within ``b rtol^(3/4)``, and the
same comparison refutes a state off the separatrix and the wrong formula ``pi b/ch(pi mu)``."""

from __future__ import annotations

import json
import math
from pathlib import Path

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.ball.frame_turn import spiral_centre
from chaplygin.numerics.ball.separatrix import delta_closed_form, mu_of
from chaplygin.verify.cli import main
from chaplygin.verify.outputs.separatrix_delta import delta_agrees, delta_tolerance
from chaplygin.verify.scene import Scene, SceneError

SCENES = Path(__file__).resolve().parents[3] / "examples" / "scenes"


def _separatrix_scene(I, D, b, C, rtol, t_end, offset=0, points=None):
    middle = sorted(range(3), key=lambda i: float(mpmath.mpf(I[i])))[1] + 1
    run = {"t_end": t_end, "rtol": rtol, "atol": rtol}
    if points:
        run["points"] = points
    return Scene.from_dict(
        {
            "system": "chaplygin_ball",
            "parameters": {"I": I, "D": D, "b": b},
            "initial": {"C": C, "separatrix": middle, "offset": offset},
            "run": run,
            "outputs": {"separatrix_delta": {"plot": False}},
        }
    )


def _closed(I, D, b):
    with mpmath.workdps(30):
        I = sorted(mpmath.mpf(v) for v in I)
        return float(delta_closed_form(mu_of(I, mpmath.mpf(D)), mpmath.mpf(b), 30))


def test_fig4a_delta_measured_on_the_trace_is_the_closed_form():
    scene = Scene.from_toml(SCENES / "k01-fig4a.toml")
    report = scene.run().separatrix_delta()
    rtol = 1e-12  # the scene's
    assert report["tolerance"] == pytest.approx(1.0 * rtol**0.75)
    closed = _closed([1, 1.5, 2], 1, 1)  # K01-3.7, evaluated here independently
    assert report["closed_form"] == pytest.approx(closed, rel=1e-15)
    assert abs(report["measured"] - closed) <= report["tolerance"]
    assert report["agrees"] and "note" not in report
    # the other two references of numerics/ball/separatrix.py agree with the measurement too
    for key in ("full_equations", "quadrature"):
        assert abs(report["measured"] - report[key]) <= report["tolerance"]
    # the paper's printed value (truncated) K01-Fig4
    assert math.floor(report["measured"] * 1e6) == 2858


def test_generic_body_delta_agrees_within_the_tolerance_from_rtol():
    I, D, b, C, rtol = ["2.41", "1.37", "0.83"], "0.7", "0.6", "0.9", 1e-11
    report = _separatrix_scene(I, D, b, C, rtol, 160).run().separatrix_delta()
    closed = _closed(I, D, b)
    tol = delta_tolerance(0.6, rtol)
    assert "note" not in report, report.get("note")
    assert abs(report["measured"] - closed) <= tol
    assert report["agrees"]


def test_off_the_separatrix_is_refuted_by_the_same_comparison():
    # the energy 1e-6 above h2: two spirals no more, the "centres" do not give Delta
    report = _separatrix_scene([1, 3, 5], 1, 1, 1, 1e-12, 200, offset="1e-6").run()
    report = report.separatrix_delta()
    assert report["energy_offset"] == pytest.approx(1e-6, rel=1e-6)
    assert not report["agrees"]
    assert abs(report["measured"] - report["closed_form"]) > report["tolerance"]


def test_wrong_formula_is_refuted_by_the_same_comparison():
    scene = Scene.from_toml(SCENES / "k01-fig4b.toml")
    report = scene.run().separatrix_delta()
    with mpmath.workdps(30):
        wrong = float(mpmath.pi / mpmath.cosh(mpmath.pi * mu_of([1, 3, 5], 1)))  # ch(pi xi)
    assert not delta_agrees(report["measured"], wrong, report["tolerance"])
    assert delta_agrees(report["measured"], report["closed_form"], report["tolerance"])


def test_spiral_centre_of_a_known_spiral():
    # z(t) = z_oo + A e^{(-lam + i kap) t} + B e^{(-3 lam + i kap) t}: the centre is z_oo
    lam, kap, z_oo = 0.37, 1.13, 0.29 - 0.61j
    t = np.linspace(0, 40, 4001)
    z = (
        z_oo
        + (0.7 + 0.2j) * np.exp((-lam + 1j * kap) * t)
        + 0.3 * np.exp((-3 * lam + 1j * kap) * t)
    )
    centre, spread, k = spiral_centre(z, round(1 / (lam * (t[1] - t[0]))))
    assert abs(centre - z_oo) < 1e-13
    # the plain end point is much further off (the reason for the extrapolation)
    assert abs(z[1000] - z_oo) > 1e-3
    with pytest.raises(UserInputError):
        spiral_centre(z[:10], 5)
    with pytest.raises(UserInputError):
        spiral_centre(z, 0)


def test_separatrix_delta_refused_where_there_is_no_separatrix():
    data = {
        "system": "chaplygin_ball",
        "effects": ["gyrostat"],
        "parameters": {"I": [1, 3, 5], "D": 1, "b": 1, "K": [0.1, 0.1, 0.2]},
        "initial": {"C": 1, "n": 2, "h": "0.25"},
        "run": {"t_end": 10},
        "outputs": {"separatrix_delta": {}},
    }
    with pytest.raises(SceneError, match=r"outputs\.separatrix_delta: .*gyrostat"):
        Scene.from_dict(data).resolve()
    equal = {**data, "effects": [], "parameters": {"I": [1, 3, 3], "D": 1, "b": 1}}
    equal["initial"] = {"M": [0.1, 0.2, 0.3], "gamma": [0, 0, 1]}
    with pytest.raises(SceneError, match="three different moments"):
        Scene.from_dict(equal).resolve()


def test_cli_json_reports_delta(tmp_path, capsys):
    out = tmp_path / "fig4b"
    status = main(["run", str(SCENES / "k01-fig4b.toml"), "--out", str(out), "--json"])
    assert status == 0
    printed = json.loads(capsys.readouterr().out)
    delta = printed["separatrix_delta"]
    assert delta["agrees"] and delta["closed_form_text"].startswith("0.41182942258217")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["separatrix_delta"]["measured"] == delta["measured"]
    assert (out / "separatrix_delta.png").stat().st_size > 0
