"""Every example scene runs at reduced length, writes its outputs and keeps its integrals; every
effect it uses is needed (dropping it changes an output or is refused) and no other is on."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest
from chaplygin.verify.cli import main
from chaplygin.verify.scene import OUTPUT_EFFECTS, Scene, SceneError

SCENES = sorted((Path(__file__).resolve().parents[3] / "examples" / "scenes").glob("*.toml"))
T_END = 10.0
#: Analyses shortened like t_end (their own counts; their numbers are tested elsewhere).
SHORT_ANALYSES = {
    "lyapunov": ("iterations=40", "transient=10", "windows=4", "states=2"),
    "poincare": ("iterations=4", "transient=1"),  # maps count iterations, not time
    "periodic_orbits": ("continuation.max_points=3",),
}


def test_there_is_a_scene_per_trajectory_figure():
    names = {p.stem for p in SCENES}
    wanted = {"k01-fig2b", "k01-fig4a", "k01-fig4b", "bm20-fig3", "bm20-fig5"}
    wanted |= {f"k01-fig3{c}" for c in "abcd"} | {f"k01-fig6{c}" for c in "abcdef"}
    wanted |= {f"k01-fig7{c}" for c in "abcdf"}
    assert wanted <= names


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_example_scene_runs(path, tmp_path, capsys):
    text = path.read_text()
    assert "omits" in text  # every example says what the paper omits
    out = tmp_path / path.stem
    scene = tomllib.loads(text)
    shorter = [
        a
        for key, settings in SHORT_ANALYSES.items()
        if key in scene.get("outputs", {})
        for item in settings
        for a in ("--set", f"outputs.{key}.{item}")
    ]
    if "mark_rotations" in scene.get("outputs", {}).get("poincare", {}):
        shorter += ["--set", "outputs.poincare.vary={}"]
    argv = ["run", str(path), "--out", str(out), "--set", f"run.t_end={T_END}", "--quiet"]
    status = main(argv + shorter)
    assert status == 0, capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    for name in summary["outputs"]:
        assert (out / name).stat().st_size > 0
    plots = [k for k, v in scene.get("outputs", {}).items() if k != "trajectory" and v.get("plot")]
    for key in plots:
        assert {f"{key}.png", f"{key}.svg"} <= set(summary["outputs"])
    # drift bound from the tolerance: global error grows at most about linearly in time
    rtol = scene["run"].get("rtol", 1e-10)
    bound = 1000 * rtol * max(1.0, T_END)
    drift = dict(summary.get("drift", {}))
    if "poincare" in summary.get("analyses", {}):  # along the map
        done = summary["analyses"]["poincare"]
        assert done["complete"] and done["points"] >= 4
        drift.update(done["drift_max"])
    if "drift" not in summary:  # analyses only: no trajectory
        assert set(summary["analyses"]) and set(summary["analyses"]) <= set(SHORT_ANALYSES)
    assert all(v is not None and v <= bound for v in drift.values()), (drift, bound)
    # prescribed integrals hold at the start to the working precision
    for name, r in summary["resolved"]["residuals"].items():
        assert abs(r) < 1e-14, name


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_every_effect_is_needed_and_no_other_is_on(path):
    data = tomllib.loads(path.read_text())
    scene = Scene.from_dict(data)
    res = scene.resolve()
    needed = {e for key, es in OUTPUT_EFFECTS.items() if key in data.get("outputs", {}) for e in es}
    # no unused effect: the model has exactly the named effects and those the outputs need
    assert set(res.code.effects) == set(data.get("effects", [])) | needed
    for effect in data.get("effects", []):
        dropped = {**data, "effects": [e for e in data["effects"] if e != effect]}
        with pytest.raises(SceneError):  # its parameters (or states) are then refused
            Scene.from_dict(dropped).resolve()
    if any(k in OUTPUT_EFFECTS for k in data.get("outputs", {})):
        # without the output that needs it, the effect (and its states) is gone
        outputs = {k: v for k, v in data["outputs"].items() if k not in OUTPUT_EFFECTS}
        params = {k: v for k, v in data["parameters"].items() if k != "b"}
        less = Scene.from_dict({**data, "outputs": outputs, "parameters": params}).resolve()
        assert set(less.code.effects) == set(data.get("effects", []))
        assert "x" not in less.code.state and len(less.code.state) < len(res.code.state)
        # and b (a parameter of contact_point only) is then refused
        with pytest.raises(SceneError, match="no parameter 'b'"):
            Scene.from_dict({**data, "outputs": outputs}).resolve()


def test_bm20_fig3_only_I3_crosses_I2():
    """BM20 Fig. 3 (I = diag(4, 3, 2), J = 0, delta = 2): I2 = 3 is constant, I3(t) = 2 +
    4 sin^2(Omega t) crosses it twice per half period, I1(t) = 4 + 4 sin^2(Omega t) stays
    above it (and I1 - I3 = 2: they never cross). The series of the example scene against
    (3.4) evaluated here (BM20-3.4)."""
    import numpy as np

    path = next(p for p in SCENES if p.stem == "bm20-fig3")
    result = Scene.from_toml(str(path)).run()
    t = np.asarray(result.t, dtype=float)
    I1, I2, I3 = (np.asarray(result.quantity(f"I{i}(t)"), dtype=float) for i in (1, 2, 3))
    s2 = np.sin(0.4 * t) ** 2
    assert np.max(np.abs(I1 - (4 + 4 * s2))) < 1e-13 and np.max(np.abs(I3 - (2 + 4 * s2))) < 1e-13
    assert np.all(I2 == 3)
    assert np.min(I1 - I2) >= 1 - 1e-13  # I1 never reaches I2
    crossings = np.count_nonzero(np.diff(np.sign(I3 - I2)))
    # I3 = I2 where sin^2(Omega t) = 1/4: Omega t = k pi +- pi/6 inside (0, Omega t_end)
    end = 0.4 * t[-1]
    roots = [x for k in range(5) for x in (k * np.pi - np.pi / 6, k * np.pi + np.pi / 6)]
    assert crossings == sum(0 < x < end for x in roots) > 0
