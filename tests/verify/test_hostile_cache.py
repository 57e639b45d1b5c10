"""The caches under hostile conditions (issue 25, item 4): made private whatever the umask,
and a compiled library loaded only with our keyed MAC.

* Fresh caches under umask 002 and 000 (in a subprocess: the umask is the process's) are
  made 0700, accepted by the project's own check, and ``chaplygin run`` succeeds.
* A cached library is changed, replaced or planted with a forged record (right size and
  SHA-256, a MAC made without our key, a MAC of another library, a record of an older version,
  garbage); ``compile_c`` never returns it: it builds the genuine library again, with a
  :class:`LibraryRebuiltWarning` where a record was forged or does not match. End to end, a
  planted library whose constructor writes a file is never loaded by ``chaplygin run``.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import stat
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import pytest
from chaplygin.numerics.ccompile import (
    LibraryRebuiltWarning,
    _record_matches,
    compile_c,
    find_compiler,
)
from hostile import scene_toml, tally_case
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

try:
    find_compiler()
except Exception:  # noqa: BLE001 - no compiler: nothing is compiled, nothing to authenticate
    pytest.skip("no C compiler", allow_module_level=True)

pytestmark = pytest.mark.slow

SOURCE = "double chaplygin_hostile_{n}(double x) {{ return 2.0 * x + {n}; }}\n"

SCENE = scene_toml("cache")


def _run_in_subprocess(code: str, env: dict, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code], env={**os.environ, **env}, cwd=cwd, capture_output=True,
        text=True, timeout=600,
    )  # fmt: skip


@pytest.mark.parametrize("umask", [0o002, 0o000])
def test_fresh_caches_are_private_whatever_the_umask(tmp_path, umask):
    root = tmp_path / "deep" / "cache"  # parents made too
    (tmp_path / "scene.toml").write_text(SCENE)
    code = textwrap.dedent(
        f"""
        import os, sys
        os.umask({umask})
        from chaplygin.derive.cachefiles import write_signed
        from pathlib import Path
        assert write_signed(Path({str(root)!r}) / "models" / "x.bin", b"M1\\n", b"data")
        from chaplygin.verify.cli import main
        sys.exit(main(["run", "scene.toml", "--out", "out", "--quiet"]))
        """
    )
    proc = _run_in_subprocess(code, {"CHAPLYGIN_CACHE_DIR": str(root)}, tmp_path)
    assert proc.returncode == 0, proc.stderr
    from chaplygin.derive.cachefiles import check_private_dir

    bad = []
    for folder in [root, *[p for p in root.rglob("*") if p.is_dir()]]:
        mode = stat.S_IMODE(folder.stat().st_mode)
        if mode != 0o700:
            bad.append((str(folder), oct(mode)))
        check_private_dir(folder)  # the project's own check accepts it
    for path in root.rglob("*"):
        if path.is_file() and path.stat().st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            bad.append((str(path), oct(stat.S_IMODE(path.stat().st_mode))))
    tally_case("caches", {"wrong success": bool(bad), "traceback": proc.returncode != 0})
    assert not bad


# ----------------------------------------------------------------------- authenticated code
FORGERIES = [
    "planted library, record with its size and SHA-256 and a MAC made without our key",
    "planted library, record with its size and SHA-256 and no MAC (an older version's)",
    "planted library, the record of another library of ours",
    "one byte of the library changed",
    "library truncated",
    "record garbage",
    "record deleted",
    "our key replaced",
    "record's MAC flipped",
    "record made a symbolic link to another library's record",
]


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _forge(kind: str, lib: Path, other: Path, planted: bytes, flip: int) -> None:
    record = lib.with_name(lib.name + ".record")
    if kind.startswith("planted library"):
        lib.write_bytes(planted)
        if "without our key" in kind:
            record.write_text(json.dumps({"size": len(planted), "sha256": _digest(lib),
                                          "mac": f"{flip:064x}"}))  # fmt: skip
        elif "no MAC" in kind:
            record.write_text(json.dumps({"size": len(planted), "sha256": _digest(lib)}))
        else:
            shutil.copy(other.with_name(other.name + ".record"), record)
    elif kind == "one byte of the library changed":
        data = bytearray(lib.read_bytes())
        data[flip % len(data)] ^= 0x01
        lib.write_bytes(bytes(data))
    elif kind == "library truncated":
        lib.write_bytes(lib.read_bytes()[: flip % lib.stat().st_size])
    elif kind == "record garbage":
        record.write_bytes(os.urandom(1 + flip % 100))
    elif kind == "record deleted":
        record.unlink()
    elif kind == "our key replaced":
        (lib.parent / "cache.key").write_bytes(os.urandom(32))
    elif kind == "record's MAC flipped":
        data = json.loads(record.read_text())
        mac = bytearray.fromhex(data["mac"])
        mac[flip % 32] ^= 0x80
        data["mac"] = mac.hex()
        record.write_text(json.dumps(data))
    elif kind == "record made a symbolic link to another library's record":
        record.unlink()
        record.symlink_to(other.with_name(other.name + ".record"))


@settings(
    max_examples=max(5, int(os.environ.get("CHAPLYGIN_HOSTILE_EXAMPLES", 60)) // 3),
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(st.sampled_from(FORGERIES), st.integers(0, 2**31 - 1))
def test_a_library_is_loaded_only_with_our_mac(tmp_path_factory, kind, flip):
    cache = tmp_path_factory.mktemp("cache")
    os.chmod(cache, 0o700)
    lib = compile_c(SOURCE.format(n=1), cache_dir=cache)
    genuine = _digest(lib)
    other = compile_c(SOURCE.format(n=2), cache_dir=cache)
    planted = other.read_bytes()  # a working library of someone else's choosing
    _forge(kind, lib, other, planted, flip)
    tampered = _digest(lib) if lib.exists() else None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        again = compile_c(SOURCE.format(n=1), cache_dir=cache)
    warned = any(issubclass(w.category, LibraryRebuiltWarning) for w in caught)
    # what compile_c returns is a build of ours (its record verifies), never the changed file
    # (a build embeds its temporary file's name: builds differ in bytes, not in what they do)
    loaded_forgery = (
        again != lib
        or not _record_matches(again)
        or (tampered != genuine and _digest(again) == tampered)
    )
    quiet = kind in (
        "planted library, record with its size and SHA-256 and no MAC (an older version's)",
        "record deleted",
    )
    tally_case("caches", {"wrong success": loaded_forgery, "traceback": False})
    assert not loaded_forgery, kind
    assert warned != quiet, (kind, [str(w.message) for w in caught])


def test_a_planted_library_never_runs_its_constructor(tmp_path):
    """End to end (as in the issue): ``chaplygin run`` fills a cache; every library in it is
    replaced by one whose constructor writes a file, with a forged record; the next run
    rebuilds instead of loading them, and the file is never written."""
    cache, flag = tmp_path / "cache", tmp_path / "PWNED"
    (tmp_path / "scene.toml").write_text(SCENE)
    env = {"CHAPLYGIN_CACHE_DIR": str(cache)}
    run = "import sys; from chaplygin.verify.cli import main; sys.exit(main(sys.argv[1:]))"
    first = subprocess.run(
        [sys.executable, "-c", run, "run", "scene.toml", "--out", "a", "--quiet"],
        env={**os.environ, **env}, cwd=tmp_path, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert first.returncode == 0, first.stderr
    evil = tmp_path / "evil.c"
    evil.write_text(
        "#include <stdio.h>\n__attribute__((constructor)) static void pwn(void) {\n"
        f'  FILE *f = fopen("{flag}", "w"); if (f) {{ fputs("ran", f); fclose(f); }}\n}}\n'
    )
    libraries = sorted((cache / "c").glob("*.so"))
    assert libraries
    for lib in libraries:
        subprocess.run([*find_compiler(), "-shared", "-fPIC", "-o", str(lib), str(evil)],
                       check=True, timeout=120)  # fmt: skip
        lib.with_name(lib.name + ".record").write_text(
            json.dumps({"size": lib.stat().st_size, "sha256": _digest(lib), "mac": "0" * 64})
        )
    second = subprocess.run(
        [sys.executable, "-c", run, "run", "scene.toml", "--out", "b", "--quiet"],
        env={**os.environ, **env}, cwd=tmp_path, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    tally_case("caches", {"wrong success": flag.exists(), "traceback": second.returncode != 0})
    assert second.returncode == 0, second.stderr
    assert not flag.exists(), "a planted library was loaded"
    assert "does not match its record" in second.stderr
