"""An effect combination that is not in ``generated/`` is derived, emitted and compiled on first
use, says so and how long it took, and is cached: a later process (simulated by emptying the
in-process caches) loads it without deriving and gives bit-identical output."""

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
        rf"note: {VARIANT} is not in generated/: derived, emitted and compiled on first use in "
        r"([0-9.]+) s \(cached in (\S+)\)",
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
