"""The compile cache verifies what it loads (issue 11, item 7).

A library is loaded only when its size and SHA-256 match the record written after our own
successful build, and the record's MAC (made with the cache folder's secret key) checks out;
anything else (truncated, zeroed, replaced by a foreign library, a forged record: see
``tests/verify/test_hostile_cache.py``) is rebuilt before ``dlopen``. Each fault is exercised in a
separate process: a library that slipped through would crash it (SIGBUS/SIGSEGV), which the
exit status shows.
"""

from __future__ import annotations

import os
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest
from chaplygin.numerics import ccompile as compiled
from chaplygin.numerics.ccompile import CacheError, compile_c

pytestmark = pytest.mark.skipif(
    not hasattr(os, "getuid") or shutil.which(os.environ.get("CC", "cc")) is None,
    reason="needs POSIX and a C compiler",
)

CHECK = """
import sys, numpy as np, importlib
from chaplygin.numerics.compiled import load_c_model
from chaplygin.numerics.code import load_model_code
code = load_model_code("chaplygin_ball")
model = load_c_model(code.c_source, code.hash, cache_dir=sys.argv[1])
ref = importlib.import_module("chaplygin.generated.chaplygin_ball_numpy")
y = np.array([0.7, -0.4, 0.5, 0.2, 0.3, 0.87 ** 0.5]); p = np.array([1.1, 2.3, 3.7, 0.9])
assert np.allclose(model.rhs(0.0, y, p), ref.rhs(0.0, y, p), rtol=1e-13, atol=0)
print(model.path)
"""


def _library(cache: Path) -> Path:
    out = subprocess.run(
        [sys.executable, "-c", CHECK, str(cache)], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr[-2000:]
    return Path(out.stdout.strip().splitlines()[-1])


def _truncate(lib: Path) -> None:
    data = lib.read_bytes()
    lib.write_bytes(data[: len(data) // 2])


def _zero_4k(lib: Path) -> None:
    data = bytearray(lib.read_bytes())
    middle = len(data) // 2
    data[middle : middle + 4096] = bytes(min(4096, len(data) - middle))
    lib.write_bytes(bytes(data))


def _foreign(lib: Path) -> None:
    other = compile_c("int chaplygin_foreign(void) { return 42; }\n", cache_dir=lib.parent.parent)
    lib.write_bytes(other.read_bytes())


@pytest.mark.slow
@pytest.mark.parametrize("damage", [_truncate, _zero_4k, _foreign], ids=["truncated", "zeroed",
                                                                         "foreign"])
def test_a_damaged_library_is_rebuilt_not_loaded(tmp_path, damage):
    lib = _library(tmp_path)
    good = lib.read_bytes()
    damage(lib)
    assert lib.read_bytes() != good
    assert _library(tmp_path) == lib  # the same entry, rebuilt: the process did not crash
    assert compiled._record_matches(lib)


def test_a_library_without_record_is_rebuilt(tmp_path):
    src = "int chaplygin_answer(void) { return 41; }\n"
    lib = compile_c(src, cache_dir=tmp_path)
    record = compiled._record_path(lib)
    assert compiled._record_matches(lib)
    record.unlink()
    before = lib.stat().st_mtime_ns
    time.sleep(0.01)
    assert compile_c(src, cache_dir=tmp_path) == lib
    assert lib.stat().st_mtime_ns != before and compiled._record_matches(lib)


@pytest.mark.parametrize("mode", [0o777, 0o775, 0o757])
def test_a_cache_folder_others_can_write_is_refused(tmp_path, mode):
    cache = tmp_path / "c"
    cache.mkdir()
    cache.chmod(mode)
    with pytest.raises(CacheError, match="can be written by other users"):
        compile_c("int f(void) { return 1; }\n", cache_dir=tmp_path)
    assert list(cache.iterdir()) == []  # nothing written there


def test_a_shared_parent_with_the_sticky_bit_is_accepted(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777 | stat.S_ISVTX)  # like /tmp
    lib = compile_c("int g(void) { return 1; }\n", cache_dir=shared)
    assert lib.is_file()


def test_a_cache_folder_that_cannot_be_made_says_so(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(CacheError, match="cannot create the cache folder"):
        compile_c("int h(void) { return 1; }\n", cache_dir=blocker)


def test_a_read_only_cache_says_read_only_not_no_compiler(tmp_path, monkeypatch):
    (tmp_path / "c").mkdir()
    # root may write anywhere: the permission answer is what the code must act on
    monkeypatch.setattr(os, "access", lambda path, mode: not mode & os.W_OK)
    with pytest.raises(CacheError, match="read-only") as err:
        compile_c("int k(void) { return 1; }\n", cache_dir=tmp_path)
    assert "compiler" not in str(err.value)


def test_stale_temporaries_of_a_killed_build_are_removed(tmp_path):
    cache = tmp_path / "c"
    cache.mkdir()
    old, fresh = cache / ".tmp-0123456789abcdef-x.c", cache / ".tmp-fedcba9876543210-y.c"
    for f in (old, fresh):
        f.write_text("left behind")
    hours_ago = time.time() - 2 * compiled.STALE_SECONDS
    os.utime(old, (hours_ago, hours_ago))
    compile_c("int m(void) { return 1; }\n", cache_dir=tmp_path)
    assert not old.exists()
    assert fresh.exists()  # may belong to a build running right now


@pytest.mark.slow
def test_a_kill_during_compilation_leaves_a_usable_cache(tmp_path):
    """SIGKILL of a process while the compiler runs: the next build works, and its
    temporaries are cleaned once stale."""
    script = (
        "import sys; from chaplygin.numerics.code import load_model_code; "
        "from chaplygin.numerics.compiled import load_c_model; "
        "c = load_model_code('chaplygin_ball', ('contact_point',)); "
        "load_c_model(c.c_source, c.hash, cache_dir=sys.argv[1])"
    )
    # its own process group, so that the kill reaches the compiler too (as Ctrl-C would)
    proc = subprocess.Popen([sys.executable, "-c", script, str(tmp_path)], start_new_session=True)
    cache = tmp_path / "c"
    deadline = time.time() + 60
    while time.time() < deadline and not list(cache.glob(".tmp-*")):
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    leftovers = list(cache.glob(".tmp-*"))
    for f in leftovers:  # as if an hour had passed
        os.utime(f, (time.time() - 2 * compiled.STALE_SECONDS,) * 2)
    subprocess.run([sys.executable, "-c", script, str(tmp_path)], check=True, timeout=300)
    assert not any(f.exists() for f in leftovers)
    assert all(compiled._record_matches(lib) for lib in cache.glob("*.so"))
