"""``chaplygin sweep`` under hostile conditions (issue 25, items 2-3): damaged stores, grids
beyond the machine, scheduler addresses that are malformed or answer HTTP, junk or nothing,
worker counts, store paths among the user's files, and plots of every kind of store.

Everything runs in this process through :func:`chaplygin.verify.cli.main` against one
LocalCluster (its scheduler's loopback address is passed as ``--scheduler``); the hostile
"schedulers" are sockets on 127.0.0.1 started by the tests. No other address is contacted.
After every case the invariant of :func:`hostile.check_case` holds, and a store the command
reports as complete is bit-identical to an undamaged run (anything else is a wrong success).
"""

from __future__ import annotations

import contextlib
import os
import random
import shutil
import socket
import struct
import tempfile
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from hostile import check_case, make_canary, read_only_place, run_cli, tree_digest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

if os.environ.get("CI"):  # CI installs the dask extra (README's test command): never skip there
    import distributed
    import xarray as xr
    import zarr
else:
    distributed = pytest.importorskip("distributed")
    xr = pytest.importorskip("xarray")
    zarr = pytest.importorskip("zarr")

from chaplygin.verify.scene import Scene  # noqa: E402
from chaplygin.verify.sweep import run_sweep  # noqa: E402
from chaplygin.verify.sweep_checks import usable_cpus  # noqa: E402
from chaplygin.verify.sweep_store import DIGEST, PARTIAL_MARKER  # noqa: E402

pytestmark = pytest.mark.slow

EXAMPLES = int(os.environ.get("CHAPLYGIN_HOSTILE_EXAMPLES", 60))


def _settings(share: float) -> settings:
    return settings(
        max_examples=max(5, int(EXAMPLES * share)),
        deadline=None,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
    )


SWEEP = """title = "hostile sweep"
system = "chaplygin_ball"
effects = {effects}
[parameters]
I = [1, 1.5, 2]
D = 1
{b}
[initial]
M = [0.7, -0.4, 0.5]
gamma = [0.2, 0.3, "sqrt(0.87)"]
[run]
t_end = 0.2
points = 5
rtol = 1e-9
atol = 1e-9
[sweep]
grid = "{grid}"
chunk = {chunk}
reduce = {reduce}
[sweep.axes]
{axes}
"""

REFERENCE_AXES = '"parameters.D" = [0.7, 1.1, "sqrt(2)", 1.9, 2.3]'


def sweep_text(
    axes: str = REFERENCE_AXES,
    chunk: int = 2,
    reduce: str = '["final_state", "drift"]',
    grid: str = "product",
    contact: bool = False,
) -> str:
    return SWEEP.format(
        effects='["contact_point"]' if contact else "[]",
        b="b = 1" if contact else "",
        grid=grid,
        chunk=chunk,
        reduce=reduce,
        axes=axes,
    )


@pytest.fixture(scope="module")
def cluster():
    c = distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=50,
    )
    with distributed.Client(c) as client:
        yield client
    c.close()


@pytest.fixture(scope="module")
def reference(cluster, tmp_path_factory) -> Path:
    """The sweep, undamaged: 5 points in 3 chunks."""
    folder = tmp_path_factory.mktemp("reference")
    (folder / "sweep.toml").write_text(sweep_text())
    store = folder / "ref.zarr"
    run_sweep(Scene.from_toml(folder / "sweep.toml"), store, client=cluster)
    return store


def _load(store: Path) -> xr.Dataset:
    with xr.open_zarr(store, consolidated=False) as ds:
        return ds.load()


def _identical(a: Path, b: Path) -> bool:
    da, db = _load(a), _load(b)
    return set(da.data_vars) == set(db.data_vars) and all(
        np.array_equal(da[n].values, db[n].values, equal_nan=da[n].dtype.kind == "f")
        for n in da.data_vars
    )


def _sweep(argv: list[str], cwd: Path, scheduler: str, seconds: int = 120):
    return run_cli(["sweep", *argv, "--scheduler", scheduler, "--quiet"], cwd, seconds)


# ------------------------------------------------------------------------- store damage
#: Damage that leaves the store repairable (``repair``) or not (``refuse``: it cannot be
#: told whose it is, and it is left as it is).
DAMAGE = {
    "delete a chunk file": "repair",
    "garble a chunk file": "repair",
    "truncate a chunk file": "repair",
    "empty a chunk file": "repair",
    "delete an array": "repair",
    "garble an array's metadata": "repair",
    "delete an array's metadata": "repair",
    "change an array's dimensions": "repair",
    "delete the consolidated metadata": "repair",
    "garble the consolidated metadata": "repair",
    "overwrite values of a chunk marked done": "repair",
    "unmark a chunk": "repair",
    "change a coordinate": "repair",
    "a user's file inside the store": "repair",
    "garble the store's attributes": "refuse",
    "delete the store's attributes": "refuse",
    "remove the fingerprint": "refuse",
    "delete the group metadata": "refuse",
}

#: Damage done through zarr's own API (the others edit the files).
THROUGH_ZARR = ("overwrite values of a chunk marked done", "unmark a chunk", "change a coordinate")

ARRAYS = ["final_state", "drift", "status", "computed", DIGEST, "D", "state", "integral"]


def _damage(store: Path, kind: str, rng: random.Random) -> None:
    """Do the damage ``kind``; FileNotFoundError when an earlier damage removed its target
    (then nothing is changed)."""
    name = rng.choice(ARRAYS)
    folder = store / name
    chunks = sorted(p for p in folder.iterdir() if not p.name.startswith(".")) if (
        folder.is_dir()) else []  # fmt: skip
    chunk = rng.choice(chunks) if chunks else None
    if kind in ("delete a chunk file", "garble a chunk file", "truncate a chunk file",
                "empty a chunk file") and chunk is None:  # fmt: skip
        kind = "delete an array"
    if kind == "delete a chunk file":
        chunk.unlink()
    elif kind == "garble a chunk file":
        chunk.write_bytes(rng.randbytes(rng.randint(1, 300)))
    elif kind == "truncate a chunk file":
        data = chunk.read_bytes()
        chunk.write_bytes(data[: rng.randint(0, max(0, len(data) - 1))])
    elif kind == "empty a chunk file":
        chunk.write_bytes(b"")
    elif kind == "delete an array":
        shutil.rmtree(store / name)
    elif kind == "garble an array's metadata":
        (store / name / ".zarray").write_bytes(rng.randbytes(40))
    elif kind == "delete an array's metadata":
        (store / name / ".zarray").unlink()
    elif kind == "change an array's dimensions":
        (store / name / ".zattrs").write_text('{"_ARRAY_DIMENSIONS": ["nope"]}')
    elif kind == "delete the consolidated metadata":
        (store / ".zmetadata").unlink()
    elif kind == "garble the consolidated metadata":
        (store / ".zmetadata").write_bytes(rng.randbytes(100))
    elif kind == "overwrite values of a chunk marked done":
        group = zarr.open_group(str(store), mode="r+", zarr_format=2, use_consolidated=False)
        var = rng.choice(["final_state", "drift", "status"])
        k = rng.randrange(group[var].shape[0])
        group[var][k] = 0 if var == "status" else rng.choice([np.nan, 0.0, 1e300])
    elif kind == "unmark a chunk":
        group = zarr.open_group(str(store), mode="r+", zarr_format=2, use_consolidated=False)
        group["computed"][rng.randrange(group["computed"].shape[0])] = 0
    elif kind == "change a coordinate":
        group = zarr.open_group(str(store), mode="r+", zarr_format=2, use_consolidated=False)
        group["D"][0] = 42.0
    elif kind == "a user's file inside the store":
        (store / "my-notes.txt").write_text("the user's\n")
    elif kind == "garble the store's attributes":
        (store / ".zattrs").write_bytes(rng.randbytes(60))
    elif kind == "delete the store's attributes":
        (store / ".zattrs").unlink()
    elif kind == "remove the fingerprint":
        data = (store / ".zattrs").read_bytes().replace(b'"fingerprint"', b'"fingerprint_was"')
        (store / ".zattrs").write_bytes(data)
    elif kind == "delete the group metadata":
        (store / ".zgroup").unlink()


@_settings(0.5)
@given(
    st.lists(st.sampled_from(sorted(DAMAGE)), min_size=1, max_size=3),
    st.integers(0, 2**32 - 1),
)
# found by the search: the array chosen for the last damage was the one the first deleted
@example(["delete an array", "a user's file inside the store", "delete the group metadata"], 8)
def test_a_damaged_store_is_repaired_or_refused_never_trusted(cluster, reference, kinds, seed):
    rng = random.Random(seed)
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        make_canary(sandbox / "user")
        (sandbox / "sweep.toml").write_text(sweep_text())
        store = sandbox / "s.zarr"
        shutil.copytree(reference, store)
        # the damage made through zarr first (it needs the store readable), then the files
        done = []  # the damage done: a target already gone by another damage is not
        for kind in sorted(kinds, key=lambda k: k not in THROUGH_ZARR):
            with contextlib.suppress(FileNotFoundError):
                _damage(store, kind, rng)
                done.append(kind)
        refuse = any(DAMAGE[k] == "refuse" for k in done)
        user_file = store / "my-notes.txt"
        keep = {user_file} if user_file.exists() else set()
        before = tree_digest(sandbox, lambda p: p.is_relative_to(store) and p not in keep)
        frozen = tree_digest(store)
        outcome = _sweep(["sweep.toml", "--out", "s.zarr"], sandbox, cluster.scheduler.address)
        after = tree_digest(sandbox, lambda p: p.is_relative_to(store) and p not in keep)
        wrong = outcome.code == 0 and not _identical(store, reference)
        check_case("sweep store", outcome, before, after, {2} if refuse else {0})
        assert not wrong, f"reported complete but differs from the undamaged run: {kinds}"
        if refuse:
            assert tree_digest(store) == frozen  # left exactly as it was
        else:
            again = _sweep(["sweep.toml", "--out", "s.zarr", "--json"], sandbox,
                           cluster.scheduler.address)  # fmt: skip
            assert again.code == 0 and '"computed": 0' in again.out  # verified, nothing to do
            assert not outcome.err.strip(), outcome.err  # a repair is quiet (--quiet)


def test_a_users_file_in_the_store_is_left_alone_without_a_word(cluster, reference, tmp_path):
    """A file of the user's inside a store: kept, unlisted, and zarr's note that it is not
    part of the hierarchy (made when the store's arrays are listed) does not reach the user
    (warnings shown always: the run is in this process, where a repeat would be hidden)."""
    (tmp_path / "sweep.toml").write_text(sweep_text())
    store = tmp_path / "s.zarr"
    shutil.copytree(reference, store)
    shutil.rmtree(store / "drift")  # an array to make again: the arrays are listed
    (store / "my-notes.txt").write_text("the user's\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_sweep(Scene.from_toml(tmp_path / "sweep.toml"), store, client=cluster)
    notes = [str(w.message) for w in caught if "not recognized as a component" in str(w.message)]
    assert notes == []  # (other libraries' warnings are not this test's concern)
    assert (store / "my-notes.txt").read_text() == "the user's\n" and _identical(store, reference)


def test_partial_folders_of_others_are_left_alone(cluster, tmp_path):
    """Beside a new store: the user's ``.<store>.partial-*`` folder, one of ours whose
    process is alive (this one), one of ours whose process is gone (removed)."""
    (tmp_path / "sweep.toml").write_text(sweep_text(chunk=5))
    user = tmp_path / ".s.zarr.partial-mine"
    make_canary(user)
    alive = tmp_path / ".s.zarr.partial-alive"
    alive.mkdir()
    (alive / PARTIAL_MARKER).write_text(
        f'{{"pid": {os.getpid()}, "host": "{socket.gethostname()}"}}'
    )
    gone = tmp_path / ".s.zarr.partial-gone"
    gone.mkdir()
    dead = _dead_pid()
    (gone / PARTIAL_MARKER).write_text(f'{{"pid": {dead}, "host": "{socket.gethostname()}"}}')
    before = tree_digest(tmp_path, lambda p: p.name in ("s.zarr", ".s.zarr.partial-gone"))
    outcome = _sweep(["sweep.toml", "--out", "s.zarr"], tmp_path, cluster.scheduler.address)
    after = tree_digest(tmp_path, lambda p: p.name in ("s.zarr", ".s.zarr.partial-gone"))
    check_case("sweep store", outcome, before, after, {0})
    assert user.exists() and alive.exists() and not gone.exists()


def _dead_pid() -> int:
    import subprocess
    import sys

    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


# ------------------------------------------------------------------------------------ grids
@st.composite
def grids(draw) -> tuple[str, str, int, set[int]]:
    """``(axes, grid, chunk, expected statuses)``: small grids that run, grids beyond the
    machine (refused before any work), malformed ones."""
    kind = draw(st.sampled_from(["small", "huge", "malformed"]))
    keys = ["parameters.D", "run.t_end", "run.rtol", "initial.M"]
    if kind == "small":
        n_axes = draw(st.integers(1, 2))
        axes = []
        for key in draw(st.permutations(keys[:3]))[:n_axes]:
            lo = {"parameters.D": 0.5, "run.t_end": 0.05, "run.rtol": 1e-10}[key]
            num = draw(st.integers(1, 3))
            axes.append(f'"{key}" = {{ start = {lo}, stop = {lo * 2}, num = {num} }}')
        return "\n".join(axes), "product", draw(st.integers(1, 4)), {0}
    if kind == "huge":  # 100000 x 100000 (the issue's), or 3-4 axes: at least 10^12 points
        n_axes = draw(st.integers(2, 4))
        if n_axes == 2:
            nums = [100_000, 100_000]
        else:
            nums = [draw(st.integers(10_000, 100_000)) for _ in range(n_axes)]
        names = ["parameters.D", "run.t_end", "run.rtol", "run.atol"][:n_axes]
        lows = {"parameters.D": (0.5, 2), "run.t_end": (0.1, 1), "run.rtol": (1e-10, 1e-8),
                "run.atol": (1e-10, 1e-8)}  # fmt: skip
        axes = [f'"{k}" = {{ start = {lows[k][0]}, stop = {lows[k][1]}, num = {n} }}'
                for k, n in zip(names, nums, strict=True)]  # fmt: skip
        return "\n".join(axes), "product", draw(st.integers(1, 100_000)), {2}
    bad = draw(
        st.sampled_from(
            ['"parameters.D" = []', '"nope.D" = [1]', '"parameters.Q" = [1, 2]',
             '"parameters.D" = { start = 1, stop = 2, num = 0 }',
             '"parameters.D" = { start = 1, stop = 2, num = 100001 }',
             '"parameters.D" = [1, 2]\n"run.t_end" = [1]', '"parameters.D" = ["nan"]',
             '"parameters.D" = [1e400]', '"a.b.c" = [1]', '"parameters.D" = [[[[1]]]]']
        )
    )  # fmt: skip
    grid = "list" if "run.t_end" in bad else "product"
    return bad, grid, 1, {2}


@_settings(0.5)
@given(grids())
def test_grids_run_or_are_refused_before_any_work(cluster, case):
    axes, grid, chunk, expect = case
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        make_canary(sandbox / "user")
        (sandbox / "sweep.toml").write_text(sweep_text(axes=axes, chunk=chunk, grid=grid))
        before = tree_digest(sandbox, lambda p: p.name == "g.zarr")
        outcome = _sweep(["sweep.toml", "--out", "g.zarr"], sandbox, cluster.scheduler.address)
        after = tree_digest(sandbox, lambda p: p.name == "g.zarr")
        wrong = False
        if outcome.code == 0:  # every point done holds finite numbers
            ds = _load(sandbox / "g.zarr")
            done = ds["status"].values == 0
            wrong = not bool(np.isfinite(ds["final_state"].values[done]).all()) or not bool(
                (ds["computed"].values == 1).all()
            )
        check_case("sweep grids", outcome, before, after, expect)
        assert not wrong
        if outcome.code == 2:
            assert not (sandbox / "g.zarr").exists()
            assert outcome.seconds < 30, f"refused after {outcome.seconds:.1f} s"


# -------------------------------------------------------------------------------- schedulers
class FakeScheduler:
    """A loopback socket that answers each connection as :attr:`mode` says."""

    def __init__(self):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(64)
        self.port = self.sock.getsockname()[1]
        self.mode, self.payload = "silent", b""
        self.stop = threading.Event()
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        self.sock.settimeout(0.2)
        while not self.stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except OSError:
                continue
            threading.Thread(target=self._answer, args=(conn, self.mode, self.payload),
                             daemon=True).start()  # fmt: skip

    def _answer(self, conn, mode, payload):
        with conn:
            try:
                if mode == "close":
                    return
                if mode == "http":  # as a web server (the dashboard) does: waits for a request
                    conn.settimeout(5)
                    conn.recv(65536)
                    conn.sendall(b"HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\n\r\n")
                elif mode == "http-eager":
                    conn.sendall(b"HTTP/1.1 400 Bad Request\r\n\r\n")
                elif mode == "junk":
                    conn.sendall(payload)
                elif mode == "drip":
                    for byte in payload:
                        conn.sendall(bytes([byte]))
                        time.sleep(0.3)
                time.sleep(3)
            except OSError:
                pass

    def close(self):
        self.stop.set()
        self.sock.close()


@pytest.fixture(scope="module")
def fake():
    server = FakeScheduler()
    yield server
    server.close()


def _no_other_host(text: str) -> bool:
    """Only addresses that are refused as written, or name the loopback: no test resolves or
    contacts any other host."""
    from chaplygin.derive.errors import UserInputError
    from chaplygin.verify.sweep_checks import parse_scheduler_address

    try:
        address = parse_scheduler_address(text)
    except UserInputError:
        return True
    return address.host in ("127.0.0.1", "::1")


def _handshake_like(rng: random.Random) -> bytes:
    """Frames with a plausible length and a wrong body, or a huge announced length."""
    body = rng.randbytes(rng.randint(0, 80))
    choice = rng.randrange(3)
    if choice == 0:
        return struct.pack("<Q", rng.randint(2**32, 2**63)) + body
    if choice == 1:
        return struct.pack("<Q", len(body) + 8) + struct.pack("<Q", 1) + body
    return struct.pack("<Q", 58) + body[:20]  # cut short


@_settings(0.5)
@given(
    st.one_of(
        st.sampled_from(["silent", "close", "http", "http-eager", "junk", "drip", "frames"]),
        st.text(max_size=60).filter(_no_other_host).map(lambda t: f"address:{t}"),
        st.sampled_from(["address:notanaddress", "address:tcp://:::::", "address:http://127.0.0.1:80",
                         "address:tcp://127.0.0.1:0", "address:tcp://127.0.0.1:65536",
                         "address:tls://127.0.0.1:8786", "address:tcp://[::1", "address:",
                         "address:tcp://127.0.0.1:8786/path", "address:inproc://x/1/2",
                         "address:tcp://[zz::1]:8786"]),
    ),
    st.binary(max_size=200),
    st.integers(0, 2**32 - 1),
)  # fmt: skip
def test_scheduler_addresses_are_checked_before_any_work(fake, mode, junk, seed):
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        make_canary(sandbox / "user")
        (sandbox / "sweep.toml").write_text(sweep_text())
        if mode.startswith("address:"):
            address = mode.removeprefix("address:")
        else:
            fake.mode = "junk" if mode == "frames" else mode
            fake.payload = _handshake_like(random.Random(seed)) if mode == "frames" else junk
            address = f"tcp://127.0.0.1:{fake.port}"
        before = tree_digest(sandbox)
        argv = ["sweep", "sweep.toml", "--out", "s.zarr", "--scheduler", address,
                "--connect-timeout", "0.5", "--quiet"]  # fmt: skip
        outcome = run_cli(argv, sandbox, 60)
        after = tree_digest(sandbox)
        check_case("scheduler addresses", outcome, before, after, {2})
        assert set(after) == set(before)  # no store made
        assert outcome.seconds < 20, f"refused after {outcome.seconds:.1f} s"


def test_a_closed_loopback_port_and_the_real_scheduler(cluster, tmp_path):
    (tmp_path / "sweep.toml").write_text(sweep_text())
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        closed = s.getsockname()[1]
    before = tree_digest(tmp_path)
    outcome = _sweep(["sweep.toml", "--out", "s.zarr"], tmp_path, f"tcp://127.0.0.1:{closed}")
    check_case("scheduler addresses", outcome, before, tree_digest(tmp_path), {2})
    assert "connection refused" in outcome.err
    outcome = _sweep(["sweep.toml", "--out", "s.zarr"], tmp_path, cluster.scheduler.address)
    check_case("scheduler addresses", outcome, before, tree_digest(tmp_path), {0})


@_settings(0.3)
@given(st.integers(-(10**6), 10**6).filter(lambda n: not 1 <= n <= usable_cpus()))
def test_worker_counts_beyond_the_machine_are_refused(workers):
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        (sandbox / "sweep.toml").write_text(sweep_text())
        before = tree_digest(sandbox)
        outcome = run_cli(["sweep", "sweep.toml", "--workers", str(workers), "--quiet"], sandbox)
        check_case("workers", outcome, before, tree_digest(sandbox), {2})
        assert outcome.seconds < 20


# -------------------------------------------------------------------------- store paths, plots
STORE_PATHS = {
    "a foreign folder": {2},
    "a file": {2},
    "the current folder": {2},
    "a parent of the current folder": {2},
    "a link to an empty folder": {0},
    "a broken link": {2},
    "an empty folder": {0},
    "a new nested path": {0},
    "a read-only place": {2},
}


@_settings(0.3)
@given(
    st.sampled_from(sorted(STORE_PATHS)),
    st.sampled_from(
        ['["final_state"]', '["drift"]', '["final_state", "drift"]', '["integrals"]',
         '["trace"]', '["trace", "drift", "integrals"]']
    ),
    st.sampled_from(["p.png", "P.PNG", "p.svg", "p.pdf", "sub/p.png"]),
)  # fmt: skip
def test_store_paths_and_plots(cluster, where, reduce, plot):
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        make_canary(sandbox / "user")
        (sandbox / "sub").mkdir()
        text = sweep_text(reduce=reduce, contact="trace" in reduce, chunk=3)
        (sandbox / "sweep.toml").write_text(text)
        cwd, out = sandbox, "s.zarr"
        if where == "a foreign folder":
            out = "user"
        elif where == "a file":
            out = "user/thesis.tex"
        elif where == "the current folder":
            cwd, out = sandbox / "user", "."
        elif where == "a parent of the current folder":
            cwd, out = sandbox / "user" / "sub", ".."
        elif where == "a link to an empty folder":
            (sandbox / "empty").mkdir()
            (sandbox / "link").symlink_to(sandbox / "empty")
            out = "link"
        elif where == "a broken link":
            (sandbox / "link").symlink_to(sandbox / "nowhere")
            out = "link/s.zarr"
        elif where == "an empty folder":
            (sandbox / "empty").mkdir()
            out = "empty"
        elif where == "a new nested path":
            out = "a/b/c.zarr"
        elif where == "a read-only place":
            out = str(read_only_place(sandbox) / "s.zarr")
        plot_path = sandbox / plot
        argv = [str(sandbox / "sweep.toml"), "--out", out, "--plot", str(plot_path)]
        ours = {"s.zarr", "empty", "a", plot_path.name}
        before = tree_digest(sandbox, lambda p: p.name in ours)
        outcome = _sweep(argv, cwd, cluster.scheduler.address)
        after = tree_digest(sandbox, lambda p: p.name in ours)
        check_case("sweep paths and plots", outcome, before, after, STORE_PATHS[where])
        if outcome.code == 0:
            assert plot_path.stat().st_size > 1000
        else:
            assert not plot_path.exists()
