"""An effect combination that is not in ``generated/`` is derived and emitted on first use (its
mpmath, C and vector-lane code when first asked for), says so and how long it took, and is
cached: a later process (simulated by emptying the in-process caches) loads it without deriving
and gives bit-identical output."""

from __future__ import annotations

import dataclasses
import json
import re

import pytest
from chaplygin.derive import systems
from chaplygin.numerics import code as code_module
from chaplygin.numerics.code import generated_manifest
from chaplygin.verify.cli import main

VARIANT = "chaplygin_ball__contact_point__rubber"

# a rubber ball (no twist: (omega, gamma) = 0) and its contact trace: M = (I + D) omega with
# omega orthogonal to gamma (BKM12 §3); the effects are not a shipped combination
SCENE = """title = "rubber ball, contact trace (first-use code)"
system = "chaplygin_ball"
effects = ["rubber"]
[parameters]
I = [1.3, 2.1, 2.9]
D = 0.7
b = 1
[initial]
M = [0.6, -0.56, 0]
gamma = [0, 0, 1]
[run]
t_end = 4
rtol = 1e-12
atol = 1e-12
points = 41
[outputs]
contact_trace = { plot = false }
"""


def _fresh_process(monkeypatch):
    """Forget what this process derived or loaded (as a new process would)."""
    monkeypatch.setattr(code_module, "_LOADED", {})
    monkeypatch.setattr(systems, "_CACHE", {})


@pytest.mark.slow
def test_first_use_derives_compiles_says_so_and_the_second_run_uses_the_cache(
    tmp_path, monkeypatch, capsys
):
    assert VARIANT not in generated_manifest()
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("CHAPLYGIN_MODEL_CACHE", raising=False)
    scene = tmp_path / "rubber.toml"
    scene.write_text(SCENE)
    _fresh_process(monkeypatch)
    assert main(["run", str(scene), "--out", str(tmp_path / "first"), "--json"]) == 0
    captured = capsys.readouterr()
    first = json.loads(captured.out)
    message = re.search(
        rf"note: {VARIANT} is not in generated/: derived and emitted on first use in "
        r"([0-9.]+) s \(cached in (\S+)\); c, c_lanes when first needed",
        captured.err,
    )
    assert message, captured.err
    assert float(message.group(1)) > 0
    summary = json.loads((tmp_path / "first" / "summary.json").read_text())
    assert summary["code_origin"] == "derived on first use"
    assert summary["code_note"] in captured.err
    assert list((tmp_path / "cache" / "emitted").glob(f"{VARIANT}-*.src"))

    # a new process: the builder must not run again
    _fresh_process(monkeypatch)

    def refuse(*args, **kwargs):
        raise AssertionError("derived again although the first use cached it")

    monkeypatch.setattr(systems, "build_model", refuse)
    ball = dataclasses.replace(systems.SYSTEMS["chaplygin_ball"], builder=refuse)
    monkeypatch.setitem(systems.SYSTEMS, "chaplygin_ball", ball)
    assert main(["run", str(scene), "--out", str(tmp_path / "second"), "--json"]) == 0
    captured = capsys.readouterr()
    second = json.loads(captured.out)
    assert f"note: {VARIANT} is not in generated/: loaded from the first-use cache" in captured.err
    summary2 = json.loads((tmp_path / "second" / "summary.json").read_text())
    assert summary2["code_origin"] == "cache of first-use code"
    assert summary2["model_hash"] == summary["model_hash"]
    assert second["y"] == first["y"]  # decimal strings of every digit: bit-identical
    assert second["drift"] == first["drift"]
    traj1 = (tmp_path / "first" / "trajectory.nc").read_bytes()
    traj2 = (tmp_path / "second" / "trajectory.nc").read_bytes()
    assert traj1 == traj2


def test_a_cache_file_that_is_not_ours_is_not_loaded(tmp_path, monkeypatch):
    from chaplygin.numerics.first_use import SOURCE_KINDS, _load, _store, emitted_cache_file

    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    path = emitted_cache_file("chaplygin_ball", frozenset({"rubber", "contact_point"}))
    sources = {k: f"# {k}\n" for k in SOURCE_KINDS}
    assert _store(path, sources) == path
    assert _load(path) == sources
    blob = path.read_bytes()
    path.write_bytes(blob.replace(b"# numpy", b"# nuMpy"))  # changed by someone else
    assert _load(path) is None
    monkeypatch.setenv("CHAPLYGIN_MODEL_CACHE", "0")
    assert emitted_cache_file("chaplygin_ball", frozenset({"rubber"})) is None


def test_the_mpmath_c_and_lane_code_are_emitted_when_first_needed(tmp_path, monkeypatch):
    """A first use emits the numpy, mpmath and Taylor code; a run on the numpy backend emits
    nothing more; the C and lane code are emitted when first asked for, each the text the
    all-at-once emission writes (another cache), and kept in the cache file for the next
    process, where the compiled C agrees with the numpy module."""
    import numpy as np
    from chaplygin.numerics import integrate
    from chaplygin.numerics.first_use import (
        LAZY_KINDS,
        SOURCE_KINDS,
        _load,
        emitted_cache_file,
        emitted_sources,
    )

    effects = frozenset({"rubber", "contact_point"})
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "lazy"))
    monkeypatch.delenv("CHAPLYGIN_MODEL_CACHE", raising=False)
    _fresh_process(monkeypatch)
    code = code_module.load_model_code("chaplygin_ball", effects)
    path = emitted_cache_file("chaplygin_ball", effects)
    assert code._pending == set(LAZY_KINDS) and not set(_load(path)) & set(LAZY_KINDS)
    assert "c, c_lanes when first needed" in code.note
    y0 = {"M": (0.6, -0.56, 0.0), "gamma": (0.0, 0.0, 1.0)}
    p = {"I": (1.3, 2.1, 2.9), "D": 0.7, "b": 1}
    r = integrate(code, y0, 0.5, p, method="DOP853", backend="numpy", rtol=1e-10, atol=1e-10)
    assert r.success and code._pending == set(LAZY_KINDS)
    lazy = {"c": code.c_source, "c_lanes": code.lanes_c_source}
    assert not code._pending and set(_load(path)) == set(SOURCE_KINDS)
    # the same texts as the emission of every kind at once, from another cache
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "all"))
    _fresh_process(monkeypatch)
    whole = emitted_sources("chaplygin_ball", effects, SOURCE_KINDS).sources
    assert lazy["c"] == whole["c"] and (lazy["c_lanes"] or "") == whole["c_lanes"]
    # a new process reads the lazily emitted C from the first cache: it compiles and agrees
    # with the numpy module
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "lazy"))
    _fresh_process(monkeypatch)
    again = code_module.load_model_code("chaplygin_ball", effects)
    assert not again._pending and again.c_source == lazy["c"]
    compiled = again.compiled()
    if compiled is not None:  # a machine with a C compiler
        y = np.asarray(r.y[:, -1], dtype=float)
        pv = np.array([float(r.params[name]) for name in again.params])
        assert np.allclose(compiled.integrals(0.5, y, pv), again.numpy.integrals(0.5, y, pv),
                           rtol=64 * np.finfo(float).eps, atol=0.0)
