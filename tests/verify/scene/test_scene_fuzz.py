"""Malformed scenes (hypothesis): exit 2, one line on stderr, no traceback, output untouched.

Each example starts from a valid scene and breaks it in one way that is always an error: an
unknown key, a value of the wrong type, a hostile or malformed number, an impossible value of an
integral, a missing required key, a non-physical parameter; plus bad paths (missing file, a
folder, not UTF-8, broken TOML, ``--out`` a file).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
from pathlib import Path

import pytest
from chaplygin.verify.cli import main
from hostile import to_toml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

BASE = {
    "title": "fuzz",
    "system": "chaplygin_ball",
    "effects": [],
    "parameters": {"I": [1, 3, 5], "D": 1, "b": 1},
    "initial": {"C": 1, "parallel": True, "h": "0.1803189"},
    "run": {"t_end": 1, "rtol": 1e-10, "points": 5},
    "outputs": {"contact_trace": {"plot": False}},
}
ANDOYER = {
    **BASE,
    "effects": ["variable_inertia", "variable_gyrostat"],
    "parameters": {
        "I": [4, 3, 2],
        "D": 4.385,
        "b": 1,
        "J_off": 0,
        "delta": 2,
        "K": [-6, -3, -9],
        "Omega": 1.07,
    },
    "initial": {"G": 3, "z": 0.5, "l": 1, "g": 1},
}

VALID_KEYS = {
    (): {"title", "system", "effects", "parameters", "initial", "run", "outputs"},
    ("run",): {"t_end", "t_start", "precision", "method", "rtol", "atol", "points", "backend"},
    ("outputs",): {
        *("trajectory", "contact_trace", "body_trace", "series", "drift", "diagram"),
        "separatrix_delta",
    },
    ("initial",): {
        *("M", "gamma", "alpha", "beta", "x", "y", "h", "C", "n", "parallel", "point"),
        *("G", "z", "l", "g", "rest"),
    },
    ("parameters",): {"I", "D", "b"},
}
HOSTILE = [
    "9**9**9**9",
    "1e999999",
    "-1e999999",
    "nan",
    "inf",
    "__import__('os').system('true')",
    "().__class__",
    "(" * 200 + "1",
    "1/0",
    "sqrt(-1)",
    "log(0)",
    "exp(1e9)",
    "10**10**10",
    "lambda: 1",
    "[1, 2]",
    "1;2",
    "",
    "x" * 2000,
    "sin(" * 60 + "1" + ")" * 60,
]
NUMERIC_PATHS = [
    ("parameters", "D"),
    ("parameters", "b"),
    ("initial", "h"),
    ("initial", "C"),
    ("run", "t_end"),
]


def _copy(d):
    return json.loads(json.dumps(d))


scalars = st.one_of(
    st.booleans(),
    st.integers(-(10**30), 10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
)
values = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=5), inner, max_size=3)
    ),
    max_leaves=6,
)
key_names = st.text(
    alphabet="abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_-0123456789", min_size=1
)


@st.composite
def unknown_key(draw):
    d = _copy(draw(st.sampled_from([BASE, ANDOYER])))
    where = draw(st.sampled_from(sorted(VALID_KEYS)))
    name = draw(key_names.filter(lambda k, w=where: k not in VALID_KEYS[w] and k not in "KJ"))
    if where == ("parameters",) and name in ("J_off", "delta", "Omega"):
        name += "_x"
    node = d
    for part in where:
        node = node[part]
    node[name] = draw(values)
    return d


@st.composite
def wrong_type(draw):
    d = _copy(BASE)
    path, bad = draw(
        st.sampled_from(
            [
                (("system",), st.one_of(st.integers(), st.booleans(), st.lists(st.text()))),
                (("effects",), st.one_of(st.integers(), st.text(min_size=1))),
                (
                    ("parameters", "I"),
                    st.one_of(st.booleans(), st.lists(st.integers(), max_size=2)),
                ),
                (
                    ("parameters", "D"),
                    st.one_of(st.booleans(), st.dictionaries(st.text(), st.text())),
                ),
                (("initial", "parallel"), st.one_of(st.integers(), st.text())),
                (
                    ("initial", "point"),
                    st.one_of(st.text(), st.floats(), st.integers(max_value=-1)),
                ),
                (("run",), st.one_of(st.integers(), st.text(), st.lists(st.integers()))),
                (("run", "points"), st.one_of(st.integers(max_value=1), st.text(), st.booleans())),
                (
                    ("run", "rtol"),
                    st.one_of(st.text(), st.floats(max_value=0), st.floats(min_value=1)),
                ),
                (("outputs", "contact_trace"), st.one_of(st.integers(), st.text())),
                (("title",), st.one_of(st.integers(), st.lists(st.text()))),
            ]
        )
    )
    value = draw(bad)
    if isinstance(value, float) and not math.isfinite(value):
        value = -1.0
    node = d
    for part in path[:-1]:
        node = node[part]
    node[path[-1]] = value
    return d


@st.composite
def hostile_number(draw):
    d = _copy(BASE)
    table, key = draw(st.sampled_from(NUMERIC_PATHS))
    junk = st.text(alphabet="abcxyz_()*+-/.", min_size=1, max_size=30).map(lambda s: "_q" + s)
    d[table][key] = draw(st.one_of(st.sampled_from(HOSTILE), junk))
    return d


@st.composite
def impossible(draw):
    case = draw(st.sampled_from(["h_low", "h_high", "n", "z", "t", "D", "I"]))
    if case == "z":
        d = _copy(ANDOYER)
        d["initial"]["z"] = draw(st.one_of(st.floats(1.0001, 1e6), st.floats(-1e6, -1.0001)))
        return d
    d = _copy(BASE)
    if case == "h_low":
        d["initial"]["h"] = draw(st.floats(-1e6, 0.0999))
    elif case == "h_high":
        d["initial"]["h"] = draw(st.floats(0.5001, 1e6))
    elif case == "n":
        del d["initial"]["parallel"]
        d["initial"]["C"] = draw(st.floats(1.01, 10))
        d["initial"]["n"] = draw(st.floats(0, 1))
    elif case == "t":
        d["run"]["t_end"] = draw(st.floats(-1e6, 0))
    elif case == "D":
        d["parameters"]["D"] = draw(st.floats(-1e6, 0))
    else:
        d["parameters"]["I"] = [1, draw(st.floats(-1e6, 0)), 5]
    return d


@st.composite
def missing(draw):
    d = _copy(BASE)
    path = draw(
        st.sampled_from(
            [("system",), ("initial",), ("run",), ("run", "t_end"), ("parameters", "D"),
             ("initial", "h"), ("initial", "C")]
        )
    )  # fmt: skip
    node = d
    for part in path[:-1]:
        node = node[part]
    del node[path[-1]]
    return d


malformed = st.one_of(unknown_key(), wrong_type(), hostile_number(), impossible(), missing())


def _run_cli(args: list[str]) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main(args)
    return status, err.getvalue()


def _assert_refused(status: int, err: str, out: Path) -> None:
    assert status == 2, err
    assert err.count("\n") == 1 and err.startswith("chaplygin: error: "), err
    assert "Traceback" not in err
    assert not out.exists()


@settings(
    max_examples=500,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    derandomize=False,
)
@given(scene=malformed)
def test_malformed_scene_exit_2_one_line_nothing_written(scene):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "scene.toml"
        path.write_text(to_toml(scene))
        out = Path(tmp) / "out"
        status, err = _run_cli(["run", str(path), "--out", str(out), "--quiet"])
        _assert_refused(status, err, out)


def test_the_base_scenes_are_valid(tmp_path):
    """Control: the scenes the fuzzer breaks run (so a refusal is the mutation's doing)."""
    for i, scene in enumerate((BASE, ANDOYER)):
        path = tmp_path / f"s{i}.toml"
        path.write_text(to_toml(scene))
        status, err = _run_cli(["run", str(path), "--out", str(tmp_path / f"o{i}"), "--quiet"])
        assert status == 0, err


@pytest.mark.parametrize(
    "kind", ["missing", "folder", "not_utf8", "broken_toml", "out_is_file", "empty", "set"]
)
def test_bad_paths(tmp_path, kind):
    path = tmp_path / "scene.toml"
    path.write_text(to_toml(BASE))
    out = tmp_path / "out"
    extra: list[str] = []
    if kind == "missing":
        path = tmp_path / "nope.toml"
    elif kind == "folder":
        path = tmp_path
    elif kind == "not_utf8":
        path.write_bytes(b'title = "\xff\xfe"\n')
    elif kind == "broken_toml":
        path.write_text("system = [\n")
    elif kind == "empty":
        path.write_text("")
    elif kind == "set":
        extra = ["--set", "title.x=1"]
    else:
        out.write_text("mine")
    status, err = _run_cli(["run", str(path), "--out", str(out), "--quiet", *extra])
    assert status == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    if kind == "out_is_file":
        assert out.read_text() == "mine"
    else:
        assert not out.exists()
