"""Sweeps (verify/sweep.py, ``chaplygin sweep``): reducers against independent routes, the store's
identity checks, and nothing lost when the client, a worker or the disk fails.

The cluster tests share one LocalCluster (two worker processes); the kill tests run the CLI in
its own process group and end that group (client, scheduler and workers) with SIGKILL.
"""

from __future__ import annotations

import math
import os
import random
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.verify.scene import Scene, SceneError
from chaplygin.verify.sweep import (
    REDUCERS,
    period_of_orbit,
    plan_sweep,
    run_sweep,
    zeros_along_axis,
)

if os.environ.get("CI"):  # CI installs the dask extra (README's test command): never skip there
    import distributed
    import xarray as xr
    import zarr  # noqa: F401
else:
    distributed = pytest.importorskip("distributed")
    xr = pytest.importorskip("xarray")
    pytest.importorskip("zarr")

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "sweeps"

#: A cheap sweep: the ball with its contact point over a 3 x 4 grid of (D, h), 12 chunks.
TINY = """
title = "tiny sweep"
system = "chaplygin_ball"
effects = ["contact_point"]

[parameters]
I = [1, 1.5, 2]
D = 1
b = 1

[initial]
C = 1
parallel = true
h = 0.3

[run]
t_end = 6
rtol = 1e-10
atol = 1e-10
points = 61

[sweep]
chunk = 1
reduce = ["final_state", "drift", "trace"]

[sweep.axes]
"parameters.D" = [0.7, "sqrt(2)", 1.9]
"initial.h" = { start = 0.27, stop = 0.47, num = 4 }
"""


def _scene(tmp_path: Path, text: str = TINY, name: str = "tiny.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def _load(store: Path) -> xr.Dataset:
    return xr.open_zarr(store, consolidated=False).load()


def _assert_identical(a: Path, b: Path) -> None:
    da, db = _load(a), _load(b)
    assert set(da.data_vars) == set(db.data_vars)
    for name in da.data_vars:
        # bit-identical (NaN where both are NaN)
        assert np.array_equal(da[name].values, db[name].values, equal_nan=True), name
    assert int(da["computed"].min()) == 1


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=50,
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


@pytest.fixture(scope="module")
def reference(client, tmp_path_factory) -> Path:
    """The tiny sweep, uninterrupted."""
    folder = tmp_path_factory.mktemp("ref")
    store = folder / "ref.zarr"
    run_sweep(Scene.from_toml(_scene(folder)), store, client=client)
    return store


# ---------------------------------------------------------------------------------- units
def test_period_of_orbit_finds_the_period_and_refutes_a_wrong_one():
    rng = np.random.default_rng(7)
    cycle = rng.normal(size=(6, 5))
    orbit = np.tile(cycle, (40, 1)) + 1e-10 * rng.normal(size=(240, 5))
    assert period_of_orbit(orbit, 14, 1e-8) == 6
    # negative control: the same orbit read with a period bound below 6 has none
    assert period_of_orbit(orbit, 5, 1e-8) == 0
    # a rotation by an irrational angle (quasi-periodic) has no period
    k = np.arange(300)
    quasi = np.c_[np.cos(k * math.sqrt(2)), np.sin(k * math.sqrt(2))]
    assert period_of_orbit(quasi, 14, 1e-6) == 0
    # noise above the tolerance is not a period
    assert (
        period_of_orbit(np.tile(cycle, (40, 1)) + 1e-5 * rng.normal(size=(240, 5)), 14, 1e-8) == 0
    )
    with pytest.raises(UserInputError):
        period_of_orbit(orbit[:10], 14, 1e-8)


def test_zeros_along_axis_skips_the_wrap_of_an_angle():
    x = np.linspace(0, 1, 6)
    phi = np.array([-0.5, -0.1, 0.2, 3.0, -3.0, -2.0])
    assert zeros_along_axis(phi, x, math.pi) == [(x[1], x[2])]
    assert len(zeros_along_axis(phi, x)) == 2  # without wrap the jump counts


def test_sweep_table_is_checked(tmp_path):
    bad_key = TINY.replace('"initial.h" =', '"outputs.h" =')
    with pytest.raises(SceneError, match="TABLE.NAME"):
        Scene.from_toml(_scene(tmp_path, bad_key))
    unequal = TINY.replace("[sweep]\n", '[sweep]\ngrid = "list"\n')
    with pytest.raises(SceneError, match="same length"):
        Scene.from_toml(_scene(tmp_path, unequal))
    unknown = TINY.replace('"trace"]', '"traec"]')
    with pytest.raises(SceneError, match="did you mean"):
        plan_sweep(Scene.from_toml(_scene(tmp_path, unknown)))


def test_plan_grid_and_chunks(tmp_path):
    plan = plan_sweep(Scene.from_toml(_scene(tmp_path)))
    assert plan.dims == ("D", "h") and plan.shape == (3, 4)
    assert len(plan.chunks) == 12
    # values reach the scene as written: text stays text, a range is 30-digit text
    points = [p for region in plan.chunks for p in plan.points(region)]
    assert points[4] == {"parameters.D": "sqrt(2)", "initial.h": "0.27"}
    assert float(points[1]["initial.h"]) == pytest.approx(0.27 + 0.2 / 3, abs=1e-15)
    assert plan.coords["D"][1] == math.sqrt(2)


# ------------------------------------------------------------------------ through a cluster
def test_final_state_matches_a_single_run_by_another_method(client, reference, tmp_path):
    from chaplygin.verify.sweep import point_scene

    ds = _load(reference)
    assert (ds["status"].values == 0).all()
    plan = plan_sweep(Scene.from_toml(_scene(tmp_path)))
    base = dict(plan.base, run={**plan.base["run"], "method": "taylor"})
    for i, j in [(1, 0), (2, 3)]:
        point = {"parameters.D": plan.axes[0][2][i], "initial.h": plan.axes[1][2][j]}
        direct = point_scene(base, point).run().integration  # Taylor, not DOP853
        want = np.array([float(v) for v in direct.y_final.values()])
        got = ds["final_state"].values[i, j]
        # two integrators at rtol = atol = 1e-10 over t = 6: within a few hundred times rtol
        assert (np.abs(got - want) <= 500 * 1e-10 * (1 + np.abs(want))).all(), (got, want)
        drift = ds["drift"].values[i, j]
        assert np.nanmax(drift) < 1e-8  # the integrals of the ball hold at rtol = 1e-10
    # the radius of the trace is the largest distance from the start (the origin): never below
    # the final one
    x, y = np.moveaxis(ds["final_state"].sel(state=["x", "y"]).values, -1, 0)
    assert (ds["trace_radius"].values >= np.hypot(x, y) - 1e-12).all()


def test_delta_sweep_matches_the_closed_form_at_every_point(client, tmp_path):
    text = (EXAMPLES / "k01-fig5-delta.toml").read_text()
    text = text.replace("num = 24", "num = 3").replace("digits = 12", "digits = 10")
    store = tmp_path / "delta.zarr"
    run_sweep(Scene.from_toml(_scene(tmp_path, text)), store, client=client)
    ds = _load(store)
    for D, measured in zip(ds["D"].values, ds["delta_measured"].values, strict=True):
        # K01-3.7, computed here from its formula: mu = 1/(J2 sqrt(a21 a32)), Delta = pi/ch(pi mu/2)
        J1, J2, J3 = 1 + D, 1.5 + D, 2 + D
        mu = 1 / (J2 * math.sqrt((1 / J1 - 1 / J2) * (1 / J2 - 1 / J3)))
        closed = math.pi / math.cosh(math.pi * mu / 2)
        assert measured == pytest.approx(closed, rel=1e-9)
    assert (ds["delta_digits"].values >= 9).all()


def test_critical_energy_refined_to_ten_digits(client, tmp_path):
    text = (EXAMPLES / "k01-fig6f-critical-135.toml").read_text()
    text = text.replace(
        "start = 0.101, stop = 0.499, num = 100", "start = 0.176, stop = 0.184, num = 3"
    )
    roots = {}
    for rtol in ("1e-12", "1e-13"):
        path = _scene(
            tmp_path, text.replace("t_end = 1 ", f"t_end = 1\nrtol = {rtol} "), f"{rtol}.toml"
        )
        out = run_sweep(Scene.from_toml(path), tmp_path / f"{rtol}.zarr", client=client)
        assert len(out["refined"]) == 1
        roots[rtol] = float(out["refined"][0])
    # two tolerances, one zero: ten digits
    assert abs(roots["1e-12"] - roots["1e-13"]) <= 1e-10 * roots["1e-13"]
    assert roots["1e-13"] == pytest.approx(0.1803189, abs=5e-8)  # examples/scenes/k01-fig6f


def test_store_of_another_sweep_is_refused(client, reference, tmp_path):
    other_scene = TINY.replace("b = 1\n", "b = 2\n")
    with pytest.raises(UserInputError, match="different scene"):
        run_sweep(Scene.from_toml(_scene(tmp_path, other_scene)), reference, client=client)
    other_grid = TINY.replace("num = 4", "num = 5")
    with pytest.raises(UserInputError, match="different grid"):
        run_sweep(Scene.from_toml(_scene(tmp_path, other_grid)), reference, client=client)
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "notes.txt").write_text("mine")  # a folder of the user's
    with pytest.raises(UserInputError, match="not a chaplygin sweep store"):
        run_sweep(Scene.from_toml(_scene(tmp_path)), tmp_path / "junk", client=client)
    assert [p.name for p in (tmp_path / "junk").iterdir()] == ["notes.txt"]


def test_a_worker_killed_mid_chunk_loses_nothing(client, reference, tmp_path):
    store = tmp_path / "worker.zarr"
    killed = []

    def kill_a_busy_worker():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            busy = [w for w, tasks in client.processing().items() if tasks]
            if busy:
                pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
            time.sleep(0.05)

    thread = threading.Thread(target=kill_a_busy_worker)
    thread.start()
    run_sweep(Scene.from_toml(_scene(tmp_path)), store, client=client)
    thread.join()
    assert killed, "no worker was busy"
    _assert_identical(store, reference)
    client.wait_for_workers(2, timeout=60)  # the nanny restarts it


# ---------------------------------------------------------------- the CLI, killed and resumed
def _cli(args: list[str], **kw) -> subprocess.Popen:
    env = dict(os.environ)
    return subprocess.Popen(
        [sys.executable, "-m", "chaplygin.verify.cli", "sweep", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,  # its own process group: client, scheduler and workers
        **kw,
    )


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_sweep_killed_at_a_random_moment_resumes_bit_identical(seed, reference, tmp_path):
    scene = _scene(tmp_path)
    store = tmp_path / "killed.zarr"
    proc = _cli([str(scene), "--out", str(store), "--workers", "1", "--quiet"])
    time.sleep(random.Random(seed).uniform(2.0, 9.0))
    os.killpg(proc.pid, signal.SIGKILL)  # the whole group at once: client, scheduler, workers
    proc.communicate()
    again = _cli([str(scene), "--out", str(store), "--workers", "1", "--json"])
    out, err = again.communicate(timeout=300)
    assert again.returncode == 0, err
    _assert_identical(store, reference)


@pytest.mark.slow
def test_full_disk_is_a_clear_error_and_the_store_stays_valid(client, reference, tmp_path):
    import resource

    from chaplygin.verify.sweep import open_store

    scene = _scene(tmp_path)
    store = tmp_path / "full.zarr"
    open_store(plan_sweep(Scene.from_toml(scene)), store)  # the store exists, nothing computed

    def tiny_files():  # in the child: files may hold 8 bytes, writes beyond fail with EFBIG
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (8, 8))

    # the client (which writes the store) is limited; the workers (the test's cluster) are not
    args = [str(scene), "--out", str(store), "--scheduler", client.scheduler.address, "--quiet"]
    proc = subprocess.run(
        [sys.executable, "-m", "chaplygin.verify.cli", "sweep", *args],
        capture_output=True,
        text=True,
        preexec_fn=tiny_files,
        timeout=300,
    )
    assert proc.returncode == 1, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "too large" in lines[0].lower(), proc.stderr
    assert int(_load(store)["computed"].max()) == 0  # nothing half-stored counts as done
    again = _cli([str(scene), "--out", str(store), "--workers", "1", "--quiet"])
    _, err = again.communicate(timeout=300)
    assert again.returncode == 0, err
    _assert_identical(store, reference)


def test_registry_names():
    assert {"final_state", "drift", "trace", "period", "delta", "frame_turn"} <= set(REDUCERS)


def test_bm20_regimes_example_on_a_tiny_grid(client, tmp_path):
    """The chart of regimes' example (BM20 Fig. 6) on 2 lines of 2 points, both carry
    directions, through Dask and Zarr: inside the period-7 tongue (Omega = 1.06675, d = 4.385
    and 4.3854) every point reaches the 7-cycle whichever way the start is carried (the cycle
    is the attractor there; the continuation's route finds it stable, README); the store has
    the leading 'carry' dimension and the picture is drawn."""
    from chaplygin.verify.sweep_plots import sweep_figure

    text = (EXAMPLES / "bm20-fig6-regimes.toml").read_text()
    axes = text.index("[sweep.axes]")
    text = text[:axes] + (
        '[sweep.axes]\n"parameters.Omega" = [1.06675, 1.0668]\n"parameters.D" = [4.385, 4.3854]\n'
    )
    text = text.replace("chunk = 41", "chunk = 2").replace("intervals = 2000", "intervals = 200")
    # a start in the 7-cycle's basin (3e-3 from a point of it), not Fig. 5's: when a chaotic
    # transient is captured depends on the last bits; from here the cycle's own contraction
    text = text.replace("z = 0.5\nl = 1\ng = 1", "z = -0.44\nl = 1.46\ng = -1.01")
    text = text.replace("transient = 8000", "transient = 3000")
    run_sweep(Scene.from_toml(_scene(tmp_path, text, "regimes.toml")), tmp_path / "r.zarr",
              client=client)  # fmt: skip
    ds = _load(tmp_path / "r.zarr")
    assert ds["regime"].dims == ("carry", "Omega", "D") and ds["regime"].shape == (2, 2, 2)
    assert (ds["status"].values == 0).all()
    assert (ds["period"].values == 7).all() and (ds["regime"].values == 1).all()
    assert ds["carried"].values.tolist() == [[[0, 1], [0, 1]], [[1, 0], [1, 0]]]
    assert sweep_figure(ds) is not None


def test_bm20_tongue_example_finds_the_continued_period_seven_cycle(client, tmp_path):
    """The tongue example on a 2-point list: the batch map's period reducer finds period 7 at
    Fig. 7A's Omega = 1.06675 and none at Fig. 5's 1.07, as the periodic-orbit route says
    independently (Newton on P^7 with the variational equations, stable multipliers at 1.06675;
    unstable beyond the Neimark-Sacker at 1.06707).

    Not from the example's own start, Fig. 5's (0.5, 1, 1): from there the cycle (or its
    gamma -> -gamma mirror) is reached after a chaotic transient of 825 to 8112 periods on 48
    starts perturbed by 1e-12, and one of them read period 28 after the example's 8000. The
    start here is 3e-3 from a point of the cycle, in its basin (no chaos on the way): after
    3000 periods every |y[k+7] - y[k]| over the 200 recorded is below 1.5e-4 of the reducer's
    tolerance (1e-4 of max |y|; periods 14, 21, 28: below 3e-4), every period that is not a
    multiple of 7 stays 8000 tolerances open; at 1.07 no period <= 32 closes within 1000
    tolerances (48 perturbed starts each). Margins over 1000 both ways.
    """
    from chaplygin.numerics.ball.bm20_map import bm20_map_with_jacobian, bm20_point, bm20_state
    from chaplygin.numerics.dynamics.periodic_orbits import refine_periodic_orbit

    # (z, l, g), tests/verify/scene/test_periodic_output.py's NEAR_CYCLE
    near_cycle = (-0.44, 1.46, -1.01)
    text = (EXAMPLES / "bm20-fig6-tongue.toml").read_text()
    axes = text.index("[sweep.axes]")
    text = text[:axes] + '[sweep.axes]\n"parameters.Omega" = [1.06675, 1.07]\n'
    text = text.replace('grid = "product"', 'grid = "list"').replace("chunk = 41", "chunk = 2")
    text = text.replace("z = 0.5\nl = 1\ng = 1", "z = {}\nl = {}\ng = {}".format(*near_cycle))
    text = text.replace("transient = 8000", "transient = 3000")
    assert "z = -0.44" in text and "transient = 3000" in text
    run_sweep(Scene.from_toml(_scene(tmp_path, text, "tongue.toml")), tmp_path / "t.zarr",
              client=client)  # fmt: skip
    ds = _load(tmp_path / "t.zarr")
    assert (ds["status"].values == 0).all()
    assert ds["period"].values.tolist() == [7, 0]
    # the independent route: the refined cycle through a late point of the same orbit
    params = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.06675]
    smap = bm20_map_with_jacobian(params, 3.0, rtol=1e-10)
    x = bm20_point(bm20_state(list(near_cycle), 3.0))
    for _ in range(3000):
        x = smap.f(x, 1.06675)
    orbit = refine_periodic_orbit(smap, x, 7, 1.06675)
    assert orbit.converged and orbit.stable


def test_the_lyapunov_chart_example_gives_the_one_point_exponents(client, tmp_path):
    """examples/sweeps/bm20-fig6-lyapunov.toml on 2 x 2 of its points, shorter runs, on the
    Dask cluster: every point's exponent (through the chunk's one call of the Lyapunov batch)
    is lyapunov_spectrum's for that point alone with one tangent vector, bit for bit, in the
    store's units per iteration; the store draws as the Lyapunov chart."""
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.dynamics.lyapunov import lyapunov_spectrum
    from chaplygin.verify.sweep_plots import sweep_figure

    text = (EXAMPLES / "bm20-fig6-lyapunov.toml").read_text()
    axes = text.index("[sweep.axes]")
    text = text[:axes] + (
        '[sweep.axes]\n"parameters.Omega" = [1.0671, 1.0753]\n"parameters.D" = [4.3733, 4.3871]\n'
    )
    text = text.replace("transient = 200, intervals = 2000", "transient = 10, intervals = 60")
    text = text.replace("chunk = 101", "chunk = 4")
    assert "intervals = 60" in text and "chunk = 4" in text
    run_sweep(Scene.from_toml(_scene(tmp_path, text, "lyap.toml")), tmp_path / "l.zarr",
              client=client)  # fmt: skip
    ds = _load(tmp_path / "l.zarr")
    assert (ds["status"].values == 0).all()
    code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
    single = text[: text.index("[sweep]")]
    for i, omega in enumerate(ds["Omega"].values):
        for j, d in enumerate(ds["D"].values):
            point = single.replace("D = 4.385", f"D = {float(d)!r}")
            point = point.replace("Omega = 1.07", f"Omega = {float(omega)!r}")
            res = Scene.from_toml(_scene(tmp_path, point, "point.toml")).resolve()
            p = [float(res.params[k]) for k in code.params]
            assert p[3] == d and p[9] == omega
            y0 = [float(v) for v in res.y0]
            one = lyapunov_spectrum(code, p, y0, intervals=60, transient=10, count=1)
            assert ds["lyapunov_max"].values[i, j] == one.exponents[0]
            assert ds["lyapunov_max_per_iteration"].values[i, j] == one.exponents[0] * one.period
    assert "Lyapunov" in sweep_figure(ds).axes[0].get_title()


def test_cli_without_the_dask_extra_says_how_to_get_it(tmp_path, monkeypatch, capsys):
    from chaplygin.verify.cli import main

    monkeypatch.setitem(sys.modules, "zarr", None)  # import zarr raises ImportError
    assert main(["sweep", str(_scene(tmp_path)), "--out", str(tmp_path / "s.zarr")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "chaplygin[dask]" in err[0]
    assert not (tmp_path / "s.zarr").exists()


def test_cli_bad_scene_is_one_line_and_writes_nothing(tmp_path, capsys):
    from chaplygin.verify.cli import main

    bad = _scene(tmp_path, TINY.replace('"trace"]', '"nonsense"]'))
    assert main(["sweep", str(bad), "--out", str(tmp_path / "s.zarr")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert not (tmp_path / "s.zarr").exists()


def test_region_of_motion_example_matches_the_lines_p1_p3(client, tmp_path):
    """BKM12 Fig. 2 on a tiny grid: a state exists between p1: h = n/(2 J1) and
    p3: h = n/(2 J3) (K01-3.2c at C = 0, J_i = I_i + D), none outside; the integrals at the
    states found are the prescribed ones."""
    text = (EXAMPLES / "bkm12-fig2-region.toml").read_text()
    text = text.replace("start = 0.05, stop = 2, num = 40", "start = 0.7, stop = 1.3, num = 2")
    text = text.replace("start = 0.005, stop = 0.6, num = 41", "start = 0.05, stop = 0.45, num = 9")
    store = tmp_path / "region.zarr"
    run_sweep(Scene.from_toml(_scene(tmp_path, text)), store, client=client)
    ds = _load(store)
    J1, J3 = 1 + 1, 3 + 1
    n, h = np.meshgrid(ds["n"].values, ds["h"].values, indexing="ij")
    inside = (h > n / (2 * J3) * (1 + 1e-3)) & (h < n / (2 * J1) * (1 - 1e-3))
    outside = (h < n / (2 * J3) * (1 - 1e-3)) | (h > n / (2 * J1) * (1 + 1e-3))
    status = ds["status"].values
    assert inside.any() and outside.any()
    assert (status[inside] == 0).all() and (status[outside] == 1).all()
    values = ds["initial_integrals"].sel(integral=["H", "(M,M)", "(M,gamma)"]).values
    np.testing.assert_allclose(values[inside][:, 0], h[inside], rtol=1e-12)
    np.testing.assert_allclose(values[inside][:, 1], n[inside], rtol=1e-12)
    assert np.abs(values[inside][:, 2]).max() < 1e-12


def test_an_axis_the_model_does_not_have_is_refused(tmp_path):
    with pytest.raises(SceneError, match="did you mean 'D'"):
        plan_sweep(
            Scene.from_toml(_scene(tmp_path, TINY.replace('"parameters.D"', '"parameters.DD"')))
        )


@pytest.mark.slow
def test_scheduler_killed_then_restarted_resumes_bit_identical(reference, tmp_path):
    """An external scheduler (``dask scheduler``) killed mid-sweep: the client stops with one
    line and exit 1, the finished chunks stay; a new scheduler and the same command finish."""
    import socket

    import zarr

    dask = str(Path(sys.executable).with_name("dask"))
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    started = []

    def start(*args):
        proc = subprocess.Popen(
            [dask, *args],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        started.append(proc)
        return proc

    def cluster():
        scheduler = start("scheduler", "--port", str(port), "--no-dashboard")
        start("worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard")
        return scheduler

    scene = _scene(tmp_path, TINY.replace("t_end = 6", "t_end = 40"))
    store = tmp_path / "sched.zarr"
    try:
        scheduler = cluster()
        client = _cli([str(scene), "--out", str(store), "--scheduler", address, "--quiet"])
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline:
            try:
                done = int(np.asarray(zarr.open_group(str(store), mode="r")["computed"][...]).sum())
            except Exception:
                done = 0
            if done >= 2:
                break
            time.sleep(0.2)
        os.killpg(scheduler.pid, signal.SIGKILL)
        _, err = client.communicate(timeout=120)
        if client.returncode != 0:  # it may have finished just before the kill
            assert client.returncode == 1
            assert len(err.strip().splitlines()) == 1 and "run the same command" in err, err
        for proc in started:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        started.clear()
        cluster()
        again = _cli([str(scene), "--out", str(store), "--scheduler", address, "--json"])
        out, err = again.communicate(timeout=300)
        assert again.returncode == 0, err
    finally:
        for proc in started:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    # the reference ran t_end = 6; run the t_end = 40 scene uninterrupted to compare
    plain = tmp_path / "plain.zarr"
    ref = _cli([str(scene), "--out", str(plain), "--workers", "1", "--quiet"])
    _, err = ref.communicate(timeout=300)
    assert ref.returncode == 0, err
    _assert_identical(store, plain)


def test_trace_bounded_where_the_frame_turns_and_not_at_a_critical_energy(client, tmp_path):
    """K01-Fig6f by two routes: the trace reducer (the contact point over a long run) says
    unbounded at the zero of the frame turn Phi found by the frame_turn reducer's refinement,
    bounded where Phi is far from 0 (I = (1, 3, 5), M || gamma, C = 1)."""
    text = (EXAMPLES / "k01-fig6f-critical-135.toml").read_text()
    text = text.replace(
        "start = 0.101, stop = 0.499, num = 100", "start = 0.176, stop = 0.184, num = 3"
    )
    found = run_sweep(
        Scene.from_toml(_scene(tmp_path, text, "phi.toml")), tmp_path / "phi.zarr", client=client
    )
    (critical,) = found["refined"]
    trace = TINY.replace("I = [1, 1.5, 2]", "I = [1, 3, 5]").replace("t_end = 6", "t_end = 1500")
    trace = trace.replace("points = 61", "points = 3001").replace(
        '"parameters.D" = [0.7, "sqrt(2)", 1.9]\n'
        '"initial.h" = { start = 0.27, stop = 0.47, num = 4 }',
        f'"initial.h" = [0.25, "{critical}"]',
    )
    trace = trace.replace('reduce = ["final_state", "drift", "trace"]', 'reduce = ["trace"]')
    store = tmp_path / "trace.zarr"
    run_sweep(Scene.from_toml(_scene(tmp_path, trace, "trace.toml")), store, client=client)
    ds = _load(store)
    assert list(ds["trace_bounded"].values) == [1, 0]
    assert ds["trace_radius"].values[1] > 10 * ds["trace_radius"].values[0]


def test_period_without_a_forcing_parameter_is_refused(tmp_path):
    text = TINY.replace('reduce = ["final_state", "drift", "trace"]', 'reduce = ["period"]')
    with pytest.raises(SceneError, match="forcing frequency 'Omega'"):
        plan_sweep(Scene.from_toml(_scene(tmp_path, text)))


def test_list_grid_pairs_the_values(tmp_path):
    text = TINY.replace("[sweep]\n", '[sweep]\ngrid = "list"\n').replace(
        '"parameters.D" = [0.7, "sqrt(2)", 1.9]', '"parameters.D" = [0.7, "sqrt(2)", 1.9, 2.5]'
    )
    plan = plan_sweep(Scene.from_toml(_scene(tmp_path, text)))
    assert plan.dims == ("point",) and plan.shape == (4,) and len(plan.chunks) == 4
    points = [p for region in plan.chunks for p in plan.points(region)]
    assert [p["parameters.D"] for p in points] == [0.7, "sqrt(2)", 1.9, 2.5]
    assert [float(p["initial.h"]) for p in points] == pytest.approx(
        [0.27, 0.27 + 0.2 / 3, 0.27 + 0.4 / 3, 0.47]
    )


def test_frame_turn_reducer_refuses_the_gyrostat():
    """The plain ball's frame turn would silently ignore K: the reducer refuses the gyrostat."""
    from types import SimpleNamespace

    from chaplygin.verify.sweep import REDUCERS

    ctx = SimpleNamespace(
        resolved=SimpleNamespace(effects={"gyrostat": "named", "contact_point": "named"}),
        scene=None,
        sweep=None,
    )
    with pytest.raises(UserInputError, match="with the gyrostat"):
        REDUCERS["frame_turn"].run(ctx)


#: Routh's sphere described in the scene (examples/systems/routh_sphere.toml), a line of a.
ROUTH = """
title = "Routh's sphere over a"

[system]
name = "routh_sphere"
inertia = ["A", "A", "C"]
centre_of_mass = [0, 0, "a"]
gravity = "g"

[parameters]
m = 1
b = 1
A = 0.4
C = 0.55
a = 0.3
g = 1

[initial]
M = [0.3, -0.2, 0.9]
gamma = [0.28, 0.3, "sqrt(1 - 0.28**2 - 0.3**2)"]

[run]
t_end = 5
rtol = 1e-10
atol = 1e-10
backend = "numpy"
method = "DOP853"

[sweep]
chunk = 1
reduce = ["final_state", "drift"]

[sweep.axes]
"parameters.a" = ["0.13", "0.3", "-0.21"]
"""


def _jellett(state: np.ndarray, a: float, b: float) -> float:
    """Jellett's integral (I omega, a e3 + b gamma) = (M, a e3 + b gamma): M is the momentum
    about the contact point, I omega + m r x (omega x r), and r = a e3 + b gamma (contact ->
    centre of mass) is perpendicular to its second term (Routh 1884; typed here, not derived)."""
    M, gamma = state[:3], state[3:6]
    return float(M @ (b * gamma + np.array([0.0, 0.0, a])))


def test_a_described_system_sweeps_as_a_single_run_does(client, tmp_path):
    """``chaplygin sweep`` of a [system] table: the Dask workers read the description again
    from the scene. Each point's final state equals the same point run alone by another
    integrator (Radau against the sweep's DOP853), Jellett's integral (typed from the
    literature) is the same at the start and the end of every point, and the points differ
    (the grid really reaches the model's parameter)."""
    from chaplygin.verify.sweep import point_scene

    store = tmp_path / "routh.zarr"
    run_sweep(Scene.from_toml(_scene(tmp_path, ROUTH, "routh.toml")), store, client=client)
    ds = _load(store)
    assert ds.attrs["model"] == "routh_sphere" and (ds["status"].values == 0).all()
    plan = plan_sweep(Scene.from_toml(_scene(tmp_path, ROUTH, "routh.toml")))
    base = dict(plan.base, run={**plan.base["run"], "method": "Radau"})
    rtol = 1e-10
    finals = ds["final_state"].values
    for i, a in enumerate(plan.axes[0][2]):
        alone = point_scene(base, {"parameters.a": a}).run()
        want = np.array([float(v) for v in alone.integration.y_final.values()])
        # two integrators at rtol = atol = 1e-10 over t = 5: within a few hundred times rtol
        assert (np.abs(finals[i] - want) <= 500 * rtol * (1 + np.abs(want))).all(), (a, want)
        start = np.array([float(v) for v in alone.resolved.y0])
        j0, j1 = _jellett(start, float(a), 1.0), _jellett(finals[i], float(a), 1.0)
        assert abs(j1 - j0) <= 500 * rtol * (1 + abs(j0))
        assert np.nanmax(ds["drift"].values[i]) < 1e-8  # H and (gamma, gamma)
    assert np.abs(finals[0] - finals[1]).max() > 1e3 * 500 * rtol
