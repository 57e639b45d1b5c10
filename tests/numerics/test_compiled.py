"""Tests of chaplygin.numerics.compiled: compile emitted C on demand, cache it, load with cffi."""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from chaplygin.derive.emit.c_sources import model_library_source
from chaplygin.numerics.compiled import (
    CompilationError,
    CompiledModel,
    CompilerNotFoundError,
    CompilerUnavailableWarning,
    ModelHashMismatchError,
    c_cache_dir,
    compile_c,
    find_compiler,
    load_c_model,
)

GENERATED = Path(__file__).resolve().parents[2] / "generated"
VARIANTS = ["chaplygin_ball", "chaplygin_ball__contact_point__gyrostat"]
ROUTINES = ["rhs", "jac", "aux", "integrals", "density"]
N_STATES = 50

# The C code and the numpy module evaluate the same common-subexpression-eliminated
# formulas in IEEE double precision (eps = 2.2e-16); they differ only in how a few
# operations round (pow(x, -1/2) against 1/sqrt(x), 1.0/x against x**-1.0), each within
# about one ulp, and cancellation in sums amplifies that modestly.  1e-13 (~450 ulp),
# measured against the largest entry of each result, leaves ample margin while any real
# discrepancy (a wrong or missing term) would show up at O(1).
RTOL = 1e-13


def _real_compiler() -> str:
    try:
        return find_compiler()[0]
    except CompilerNotFoundError:
        pytest.skip("no C compiler available")


def _source(variant: str) -> str:
    return (GENERATED / f"{variant}.c").read_text()


def _numpy_module(variant: str):
    return importlib.import_module(f"chaplygin.generated.{variant}_numpy")


def _random_states(variant: str, rng: np.random.Generator, count: int) -> np.ndarray:
    """States (n_state, count) with unit gamma (an orthonormal frame when alpha, beta exist)."""
    state = _numpy_module(variant).STATE
    columns = []
    for _ in range(count):
        values = dict(zip(("M1", "M2", "M3"), rng.normal(size=3), strict=True))
        q, r = np.linalg.qr(rng.normal(size=(3, 3)))
        frame = q * np.sign(np.diag(r))
        for name, row in zip(("alpha", "beta", "gamma"), frame, strict=True):
            for i in range(3):
                values[f"{name}{i + 1}"] = row[i]
        values["x"], values["y"] = rng.normal(size=2)
        columns.append([values[name] for name in state])
    return np.array(columns).T


def _random_params(variant: str, rng: np.random.Generator) -> np.ndarray:
    ranges = {"I": (0.5, 3.0), "D": (0.2, 2.0), "b": (0.5, 2.0), "K": (-1.0, 1.0)}
    names = _numpy_module(variant).PARAMS
    return np.array([rng.uniform(*ranges[name.rstrip("123")]) for name in names])


def _write_wrapper(path: Path, real: str, count_file: Path, sleep: float = 0.0) -> str:
    """A fake compiler that logs each compilation (a call with -shared) and runs `real`."""
    sleep_line = f"sleep {sleep}" if sleep else ":"
    path.write_text(
        textwrap.dedent(
            f"""\
            #!/bin/sh
            case " $* " in
              *" -shared "*) echo compile >> '{count_file}'; {sleep_line};;
            esac
            exec '{real}' "$@"
            """
        )
    )
    path.chmod(0o755)
    return str(path)


def _count(count_file: Path) -> int:
    return len(count_file.read_text().split()) if count_file.exists() else 0


posix_only = pytest.mark.skipif(sys.platform == "win32", reason="uses a /bin/sh wrapper")


@pytest.fixture(scope="module")
def models(tmp_path_factory) -> dict[str, CompiledModel]:
    _real_compiler()
    cache = tmp_path_factory.mktemp("cache")
    result = {}
    for variant in VARIANTS:
        model = load_c_model(_source(variant), _numpy_module(variant).MODEL_HASH, cache_dir=cache)
        assert model is not None
        result[variant] = model
    return result


# --------------------------------------------------------------------------- agreement


@pytest.mark.parametrize("variant", VARIANTS)
def test_sizes_and_hash(models, variant):
    model, module = models[variant], _numpy_module(variant)
    assert model.model_hash == module.MODEL_HASH
    assert model.n_state == len(module.STATE)
    assert model.n_param == len(module.PARAMS)
    assert model.n_aux == len(module.AUX)
    assert model.n_integrals == len(module.INTEGRALS)


@pytest.mark.parametrize("routine", ROUTINES)
@pytest.mark.parametrize("variant", VARIANTS)
def test_matches_numpy_module(models, variant, routine):
    model, module = models[variant], _numpy_module(variant)
    rng = np.random.default_rng([VARIANTS.index(variant), ROUTINES.index(routine)])
    Y = _random_states(variant, rng, N_STATES)
    p = _random_params(variant, rng)
    t = 0.37
    reference = getattr(module, routine)(t, Y, p)  # shape (..., N_STATES)
    batch = getattr(model, f"{routine}_many")(t, Y, p)
    assert batch.shape == reference.shape
    for j in range(N_STATES):
        ref = reference[..., j]
        single = getattr(model, routine)(t, Y[:, j], p)
        assert single.shape == ref.shape
        scale = np.max(np.abs(ref))
        np.testing.assert_allclose(single, ref, rtol=0, atol=RTOL * scale)
        np.testing.assert_array_equal(batch[..., j], single)


def test_many_accepts_strided_and_transposed_states(models):
    model = models["chaplygin_ball"]
    rng = np.random.default_rng(1)
    Y = _random_states("chaplygin_ball", rng, 7)
    p = _random_params("chaplygin_ball", rng)
    expected = model.jac_many(0.0, Y, p)
    wide = np.zeros((6, 21))
    wide[:, ::3] = Y
    np.testing.assert_array_equal(model.jac_many(0.0, wide[:, ::3], p), expected)
    np.testing.assert_array_equal(model.jac_many(0.0, np.asfortranarray(Y), p), expected)
    np.testing.assert_array_equal(model.jac_many(0.0, Y[:, ::-1], p), expected[..., ::-1])
    assert model.rhs_many(0.0, np.zeros((6, 0)), p).shape == (6, 0)
    with pytest.raises(ValueError, match="shape"):
        model.rhs_many(0.0, Y[:5], p)


@pytest.mark.parametrize("routine", ROUTINES)
def test_many_with_a_parameter_set_per_state(models, routine):
    """A parameter set per state (columns, also strided): each column is the single-state
    routine's at that state and that set, bit for bit; a set of the wrong shape is refused."""
    model = models["chaplygin_ball"]
    rng = np.random.default_rng(ROUTINES.index(routine) + 40)
    Y = _random_states("chaplygin_ball", rng, 7)
    P = np.column_stack([_random_params("chaplygin_ball", rng) for _ in range(7)])
    many = getattr(model, f"{routine}_many")
    got = many(0.29, Y, P)
    for j in range(7):
        np.testing.assert_array_equal(got[..., j], getattr(model, routine)(0.29, Y[:, j], P[:, j]))
    wide = np.zeros((P.shape[0], 14))
    wide[:, ::2] = P
    np.testing.assert_array_equal(many(0.29, Y, wide[:, ::2]), got)
    np.testing.assert_array_equal(many(0.29, Y, np.asfortranarray(P)), got)
    assert not np.array_equal(many(0.29, Y, P[:, ::-1]), got)  # the sets do go by column
    with pytest.raises(ValueError, match="shape"):
        many(0.29, Y, P[:, :5])


# --------------------------------------------------------------------------- call conventions


def test_input_conversion_and_out(models):
    model = models["chaplygin_ball"]
    rng = np.random.default_rng(2)
    y = _random_states("chaplygin_ball", rng, 1)[:, 0]
    p = _random_params("chaplygin_ball", rng)
    expected = model.rhs(0.0, y, p)
    # lists, float32, non-contiguous views and integer times are converted
    np.testing.assert_array_equal(model.rhs(0, list(y), list(p)), expected)
    strided = np.zeros(12)
    strided[::2] = y
    np.testing.assert_array_equal(model.rhs(0.0, strided[::2], p), expected)
    np.testing.assert_array_equal(model.jac(0.0, strided[::2], p), model.jac(0.0, y, p))
    readonly = y.copy()
    readonly.flags.writeable = False
    np.testing.assert_array_equal(model.rhs(np.float64(0.0), readonly, p), expected)
    assert model.rhs(0.0, y.astype(np.float32), p).dtype == np.float64

    out = np.empty(6)
    assert model.rhs(0.0, y, p, out=out) is out
    np.testing.assert_array_equal(out, expected)
    jout = np.empty((6, 6))
    assert model.jac(0.0, y, p, out=jout) is jout

    # without out every call returns a fresh array (scipy keeps references to them)
    first = model.rhs(0.0, y, p)
    second = model.rhs(0.0, 2 * y, p)
    assert not np.shares_memory(first, second)
    np.testing.assert_array_equal(first, expected)


def test_bad_arguments_are_rejected(models):
    model = models["chaplygin_ball"]
    y, p = np.ones(6) / np.sqrt(3), np.array([1.0, 2.0, 3.0, 0.5])
    with pytest.raises(ValueError, match="y must have shape"):
        model.rhs(0.0, np.ones(5), p)
    with pytest.raises(ValueError, match="p must have shape"):
        model.rhs(0.0, y, np.ones(3))
    with pytest.raises(ValueError, match="out"):
        model.rhs(0.0, y, p, out=np.empty(6, dtype=np.float32))
    with pytest.raises(ValueError, match="out"):
        model.jac(0.0, y, p, out=np.empty(36))
    with pytest.raises(ValueError, match="out"):
        model.rhs(0.0, y, p, out=np.empty(12)[::2])


def test_parameter_array_changed_in_place_is_seen(models):
    model = models["chaplygin_ball"]
    y = np.array([0.3, -0.2, 0.5, 0.0, 0.6, 0.8])
    p = np.array([1.0, 2.0, 3.0, 0.5])
    before = model.rhs(0.0, y, p)
    p[2] = 5.0
    after = model.rhs(0.0, y, p)
    np.testing.assert_array_equal(after, model.rhs(0.0, y, p.copy()))
    assert not np.array_equal(before, after)


def test_library_without_batch_shim_falls_back(tmp_path):
    _real_compiler()
    path = compile_c(_source("chaplygin_ball"), cache_dir=tmp_path)
    model = CompiledModel(path, _numpy_module("chaplygin_ball").MODEL_HASH)
    rng = np.random.default_rng(3)
    Y = _random_states("chaplygin_ball", rng, 5)
    p = _random_params("chaplygin_ball", rng)
    batch = model.integrals_many(0.0, Y, p)
    for j in range(5):
        np.testing.assert_array_equal(batch[:, j], model.integrals(0.0, Y[:, j], p))


# --------------------------------------------------------------------------- cache


@posix_only
def test_second_load_reuses_cached_library(tmp_path):
    real = _real_compiler()
    count = tmp_path / "count"
    cc = _write_wrapper(tmp_path / "cc-wrapper", real, count)
    cache = tmp_path / "cache"
    source = _source("chaplygin_ball")

    first = load_c_model(source, cache_dir=cache, compiler=cc)
    assert first is not None and _count(count) == 1
    stat = os.stat(first.path)
    second = load_c_model(source, cache_dir=cache, compiler=cc)
    assert second is not None and _count(count) == 1
    assert second.path == first.path
    after = os.stat(second.path)
    assert (after.st_ino, after.st_mtime_ns) == (stat.st_ino, stat.st_mtime_ns)

    # compile_c is idempotent too, and force=True rebuilds
    assert compile_c(model_library_source(source), cache_dir=cache, compiler=cc) == first.path
    assert _count(count) == 1
    compile_c(model_library_source(source), cache_dir=cache, compiler=cc, force=True)
    assert _count(count) == 2

    # the cache holds the library, its source, its record (size, SHA-256, MAC) and the
    # folder's secret key, no temporary files
    names = sorted(p.name for p in (cache / "c").iterdir())
    lib = first.path
    assert names == sorted(
        [lib.with_suffix(".c").name, lib.name, lib.name + ".record", "cache.key"]
    )


def test_different_source_gives_different_library(tmp_path):
    _real_compiler()
    a = compile_c(_source("chaplygin_ball"), cache_dir=tmp_path)
    b = compile_c(_source("chaplygin_ball__contact_point__gyrostat"), cache_dir=tmp_path)
    c = compile_c(_source("chaplygin_ball") + "\n/* comment */\n", cache_dir=tmp_path)
    assert len({a, b, c}) == 3
    assert all(path.parent == tmp_path / "c" for path in (a, b, c))


def test_cache_dir_from_environment(tmp_path, monkeypatch):
    _real_compiler()
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "env-cache"))
    model = load_c_model(_source("chaplygin_ball"))
    assert model is not None
    assert model.path.parent == tmp_path / "env-cache" / "c"


def test_default_cache_dir_locations(tmp_path, monkeypatch):
    monkeypatch.delenv("CHAPLYGIN_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert c_cache_dir() == tmp_path / "xdg" / "chaplygin" / "c"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert c_cache_dir() == Path.home() / ".cache" / "chaplygin" / "c"
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "mine"))
    assert c_cache_dir() == tmp_path / "mine" / "c"
    assert c_cache_dir(tmp_path / "arg") == tmp_path / "arg" / "c"


_CHILD = """
import json, sys, time, warnings
from pathlib import Path
import numpy as np
from chaplygin.numerics.compiled import load_c_model
source, cache, cc, go = Path(sys.argv[1]).read_text(), sys.argv[2], sys.argv[3], Path(sys.argv[4])
Path(sys.argv[5]).touch()
deadline = time.monotonic() + 120
while not go.exists() and time.monotonic() < deadline:
    time.sleep(0.005)
warnings.simplefilter("error")
model = load_c_model(source, cache_dir=cache, compiler=cc)
y = np.array([0.3, -0.2, 0.5, 0.0, 0.6, 0.8])
p = np.array([1.0, 2.0, 3.0, 0.5])
print(json.dumps({"path": str(model.path), "rhs": model.rhs(0.0, y, p).tolist()}))
"""


@posix_only
def test_parallel_processes_build_the_same_library(tmp_path):
    real = _real_compiler()
    count = tmp_path / "count"
    # the wrapper sleeps so that the compilations overlap
    cc = _write_wrapper(tmp_path / "cc-slow", real, count, sleep=0.5)
    cache = tmp_path / "cache"
    source_file = tmp_path / "model.c"
    source_file.write_text(_source("chaplygin_ball") + "\n/* parallel test */\n")
    go = tmp_path / "go"
    ready = [tmp_path / f"ready{i}" for i in range(4)]
    children = [
        subprocess.Popen(
            [sys.executable, "-c", _CHILD, str(source_file), str(cache), cc, str(go), str(r)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for r in ready
    ]
    try:
        deadline = time.monotonic() + 120
        while not all(r.exists() for r in ready) and time.monotonic() < deadline:
            time.sleep(0.01)
        go.touch()  # all four start compiling at once
        results = [child.communicate(timeout=300) for child in children]
    finally:
        for child in children:
            if child.poll() is None:
                child.kill()
    for child, (_, stderr) in zip(children, results, strict=True):
        assert child.returncode == 0, stderr
    outputs = [json.loads(stdout) for stdout, _ in results]
    y = np.array([0.3, -0.2, 0.5, 0.0, 0.6, 0.8])
    p = np.array([1.0, 2.0, 3.0, 0.5])
    reference = _numpy_module("chaplygin_ball").rhs(0.0, y, p)
    for output in outputs:
        assert output["path"] == outputs[0]["path"]
        np.testing.assert_allclose(output["rhs"], reference, rtol=0, atol=RTOL)
    print("compilations:", _count(count))
    assert _count(count) >= 2  # the builds really did race
    libraries = [p for p in (cache / "c").iterdir() if p.suffix == ".so"]
    assert [str(p) for p in libraries] == [outputs[0]["path"]]
    assert not [p for p in (cache / "c").iterdir() if p.name.startswith(".tmp-")]


# --------------------------------------------------------------------------- failures


def test_missing_compiler_argument_warns_and_returns_none(tmp_path):
    with pytest.warns(CompilerUnavailableWarning, match="numpy implementation"):
        model = load_c_model(
            _source("chaplygin_ball"),
            cache_dir=tmp_path,
            compiler=str(tmp_path / "no-such-compiler"),
        )
    assert model is None
    assert not (tmp_path / "c").exists()


def test_cc_variable_is_honoured_exclusively(tmp_path, monkeypatch):
    monkeypatch.setenv("CC", "chaplygin-no-such-cc")
    with pytest.raises(CompilerNotFoundError, match="CC"):
        find_compiler()
    with pytest.warns(CompilerUnavailableWarning, match="CC"):
        assert load_c_model(_source("chaplygin_ball"), cache_dir=tmp_path) is None


def test_no_compiler_on_path(tmp_path, monkeypatch):
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    with pytest.raises(CompilerNotFoundError, match="no C compiler found"):
        find_compiler()
    with pytest.warns(CompilerUnavailableWarning, match="install"):
        assert load_c_model(_source("chaplygin_ball"), cache_dir=tmp_path) is None


def test_compilation_failure(tmp_path):
    _real_compiler()
    with pytest.raises(CompilationError, match="error"):
        compile_c("this is not C;\n", cache_dir=tmp_path)
    assert not list((tmp_path / "c").iterdir())  # temporary files removed
    with pytest.warns(CompilerUnavailableWarning, match="exited with status"):
        assert load_c_model("this is not C;\n", cache_dir=tmp_path) is None


def test_hash_mismatch_raises(tmp_path):
    _real_compiler()
    with pytest.raises(ModelHashMismatchError, match="regenerate"):
        load_c_model(_source("chaplygin_ball"), "0" * 64, cache_dir=tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = load_c_model(
            _source("chaplygin_ball"),
            _numpy_module("chaplygin_ball").MODEL_HASH,
            cache_dir=tmp_path,
        )
    assert model is not None


def test_damaged_cache_entry_is_rebuilt(tmp_path):
    _real_compiler()
    source = _source("chaplygin_ball")
    model = load_c_model(source, cache_dir=tmp_path)
    assert model is not None
    path = model.path
    del model
    fresh = tmp_path / "other"
    damaged = compile_c(model_library_source(source), cache_dir=fresh)
    damaged.write_bytes(b"not a shared library")
    rebuilt = load_c_model(source, cache_dir=fresh)
    assert rebuilt is not None and rebuilt.path == damaged
    assert damaged.name == path.name  # same key: the cache key is location-independent


def test_trampoline_and_cffi_paths_agree(models):
    """Single calls go through the CPython trampoline (numerics/fastcall.py) when it can be
    built; it must give exactly what the cffi path gives, and leave other inputs to it."""
    import sysconfig

    from chaplygin.numerics.fastcall import load_fastcall

    include = Path(sysconfig.get_paths()["include"]) / "Python.h"
    if include.exists():
        assert load_fastcall() is not None
    model = models["chaplygin_ball__contact_point__gyrostat"]
    assert (model._fast is not None) == (load_fastcall() is not None)
    rng = np.random.default_rng(11)
    y = _random_states("chaplygin_ball__contact_point__gyrostat", rng, 1)[:, 0].copy()
    p = _random_params("chaplygin_ball__contact_point__gyrostat", rng)
    calls = {
        name: (lambda name=name, **kw: getattr(model, name)(0.25, y, p, **kw))
        for name in ("rhs", "aux", "integrals", "density")
    }
    fast = {name: f() for name, f in calls.items()}
    fast_out = {name: f(out=np.empty_like(fast[name])) for name, f in calls.items()}
    saved, model._fast = model._fast, None
    try:
        slow = {name: f() for name, f in calls.items()}
    finally:
        model._fast = saved
    for name in calls:
        np.testing.assert_array_equal(fast[name], slow[name])
        np.testing.assert_array_equal(fast_out[name], slow[name])
    if model._fast is not None:
        address = model._address["rhs"]
        n, m = model.n_state, model.n_param
        # the trampoline declines what it cannot take as is (the caller then converts)
        assert model._fast(address, n, n, m, 0.25, list(y), p, None) is NotImplemented
        assert model._fast(address, n, n, m, 0.25, y[:-1], p, None) is NotImplemented
        assert model._fast(address, n, n, m, "0", y, p, None) is NotImplemented
        frozen = np.empty(n)
        frozen.flags.writeable = False
        assert model._fast(address, n, n, m, 0.25, y, p, frozen) is NotImplemented
        np.testing.assert_array_equal(model._fast(address, n, n, m, 0.25, y, p, None), slow["rhs"])
