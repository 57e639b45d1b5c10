"""The ``lyapunov`` scene output (verify/outputs/lyapunov.py): summary with units, arrays,
figure, ``--json``, and scene errors (one line, exit 2, nothing written)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from chaplygin.verify.cli import main
from chaplygin.verify.scene import Scene, SceneError

SCENE = Path(__file__).resolve().parents[3] / "examples" / "scenes" / "bm20-fig5-lyapunov.toml"
#: small runs: the numbers are checked for consistency, not against the paper (BM20-Lyap is)
SMALL = [
    "outputs.lyapunov.iterations=120",
    "outputs.lyapunov.transient=20",
    "outputs.lyapunov.states=2",
    "outputs.lyapunov.windows=4",
]


def _scene(overrides=()) -> Scene:
    return Scene.from_toml(SCENE, list(overrides))


def test_json_summary_carries_both_units_and_the_divergence_check(tmp_path, capsys):
    """Units, error bars and the divergence check of both spectra in ``--json``.

    Liouville's identity (sum of the exponents = mean divergence) is checked against a bound
    derived from the integration's tolerance, rtol per DOP853 step per unit time (the steps
    from the run's work counters: about 9e-10 here); measured differences were at most
    2.9e-12 on 20 starts perturbed by 1e-12 (a margin of 300). The old bound, 1e-6 of the
    mean divergence, depended on where the orbit went: 120 periods after 20 from Fig. 5's
    start average a divergence anywhere between -4e-3 and +2e-3 per unit time (1.3e-5 on one of
    those starts), so it could come arbitrarily close to the difference.
    """
    out = tmp_path / "run"
    status = main(["run", str(SCENE), "--out", str(out), "--json", "--quiet"]
                  + [a for s in SMALL for a in ("--set", s)])  # fmt: skip
    assert status == 0
    summary = json.loads(capsys.readouterr().out)
    block = summary["analyses"]["lyapunov"]
    period = 2 * math.pi / 1.07
    for kind, k in (("level_set", 3), ("full", 6)):
        per_time, per_iter = block[kind]["per_unit_time"], block[kind]["per_iteration"]
        assert per_time["units"] == "per unit time"
        assert per_iter["units"].startswith("per map iteration")
        assert len(per_time["exponents"]) == len(per_time["errors"]) == k
        np.testing.assert_allclose(
            per_iter["exponents"], np.multiply(per_time["exponents"], period), rtol=1e-14
        )
        assert all(e > 0 for e in per_time["errors"])
        assert per_time["difference"] == pytest.approx(
            per_time["sum_of_exponents"] - per_time["mean_divergence"], abs=1e-15
        )
        assert per_time["mean_divergence_error"] > 0
        run = block[kind]
        steps_per_time = run["work"]["steps"] / (
            run["initial_states"] * (run["intervals"] + run["transient"]) * run["interval"]
        )
        assert abs(per_time["difference"]) < run["rtol"] * steps_per_time
    assert len(block["full"]["per_unit_time"]["forced_zeros"]) == 3
    written = set(p.name for p in out.iterdir())
    assert {"lyapunov.nc", "lyapunov.png", "lyapunov.svg", "summary.json"} <= written
    assert "trajectory.nc" not in written  # an analysis-only scene integrates no trajectory


def test_arrays_hold_the_running_estimates():
    result = _scene(SMALL + ["outputs.lyapunov.spectrum='level_set'"]).run()
    done = result.analyses["lyapunov"]
    dims, running, attrs = done.arrays["level_set_running"]
    assert dims == ("state", "level_set_checkpoint", "level_set_exponent")
    assert running.shape[0] == 2 and running.shape[2] == 3
    assert attrs["units"] == "1/time"
    # the last running estimate of each state, averaged over the states, is the exponent
    _, exponents, _ = done.arrays["level_set_exponents"]
    np.testing.assert_allclose(running[:, -1, :].mean(axis=0), exponents, rtol=1e-12)
    assert "full" not in done.summary
    fig = done.figures["lyapunov"]()
    assert len(fig.axes) == 1


@pytest.mark.parametrize(
    ("override", "path"),
    [
        ("run.precision='quad'", "run.precision"),
        ("outputs.lyapunov.spectrum='partial'", "outputs.lyapunov.spectrum"),
        ("outputs.lyapunov.states=0", "outputs.lyapunov.states"),
        ("outputs.lyapunov.colour=1", "outputs.lyapunov"),
    ],
)
def test_bad_settings_are_scene_errors(override, path):
    with pytest.raises(SceneError, match=path.replace(".", r"\.")):
        _scene([override]).run()


def test_autonomous_model_needs_an_interval(tmp_path, capsys):
    text = """system = "chaplygin_ball"
[parameters]
I = [2.1, 3.3, 4.7]
D = 1.3
[initial]
M = [0.3, -0.7, 1.1]
gamma = [0.36, 0.48, 0.8]
[run]
t_end = 1
[outputs.lyapunov]
iterations = 40
transient = 0
states = 1
windows = 4
"""
    path = tmp_path / "ball.toml"
    path.write_text(text)
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "interval" in err
    assert not out.exists()
    path.write_text(text + "interval = 1.7\n")
    assert main(["run", str(path), "--out", str(out), "--quiet", "--json"]) == 0
    block = json.loads(capsys.readouterr().out)["analyses"]["lyapunov"]["level_set"]
    assert "per_iteration" not in block  # no forcing period: per unit time only
    assert block["per_unit_time"]["minus_mean_dlog_density_dt"] == pytest.approx(
        block["per_unit_time"]["mean_divergence"], abs=1e-7
    )
