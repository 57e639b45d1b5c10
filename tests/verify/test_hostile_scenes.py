"""Scene files, long spans, titles on the terminal and the API's errors (issue 25, items 3-4).

Scene files are generated hostile: nested thousands deep (arrays, inline tables, table
headers, ``--set`` values), larger than the limit, not regular files (a FIFO with no writer,
``/dev/zero``, ``/dev/urandom``, a folder, a link to a device), not UTF-8, with spans no run
can finish (``t_end = 1e9``, ``1e308``), and with titles full of terminal escapes, bidi
overrides and mathtext. Each is run through ``chaplygin run`` (or ``--explain``) in a sandbox
with the user's files: refused in one line before any work, within the time limit, with no
control character echoed (:func:`hostile.check_case`). The public API gets the same treatment:
every call raises a documented exception (:class:`UserInputError`), never a library's own.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import chaplygin
import pytest
from chaplygin.derive.errors import ChaplyginError
from chaplygin.verify.scene import MAX_SCENE_BYTES, Scene
from hostile import check_case, make_canary, run_cli, scene_toml, tally_case, tree_digest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

EXAMPLES = int(os.environ.get("CHAPLYGIN_HOSTILE_EXAMPLES", 60))
SETTINGS = settings(
    max_examples=EXAMPLES,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

def scene_text(title: str = "t", t_end: str = "0.2", extra: str = "", plot: bool = False) -> str:
    return scene_toml(
        title, t_end, run=extra, outputs=f"drift = {{ plot = {'true' if plot else 'false'} }}"
    )


def _nested(depth: int, kind: str) -> str:
    if kind == "array":
        return "[" * depth + "1" + "]" * depth
    if kind == "inline table":
        return "{a = " * depth + "1" + "}" * depth
    return "[" + ".".join(["a"] * depth) + "]\nb = 1"  # a table header


def _deep_list(depth: int) -> list:
    out: list = [1]
    for _ in range(depth):
        out = [out]
    return out


@st.composite
def hostile_scene_files(draw) -> tuple[str, object, list[str]]:
    """``(kind, content or a maker, extra flags)``: bytes for a file, or a special path."""
    kind = draw(
        st.sampled_from(
            ["deep", "deep --set", "large", "special", "not utf-8", "junk", "long span",
             "long title"]
        )
    )  # fmt: skip
    if kind == "deep":
        depth = draw(st.integers(17, 30_000))
        how = draw(st.sampled_from(["array", "inline table", "header"]))
        where = draw(st.sampled_from(["top", "parameters"]))
        text = scene_text()
        value = _nested(depth, how)
        if how == "header":
            text += "\n" + value + "\n"
        elif where == "top":
            text = f"zz = {value}\n" + text
        else:
            text = text.replace("D = 1\n", f"D = 1\nX = {value}\n")
        return kind, text.encode(), []
    if kind == "deep --set":
        depth = draw(st.integers(17, 30_000))
        return kind, scene_text().encode(), ["--set", f"run.t_end={_nested(depth, 'array')}"]
    if kind == "large":
        size = MAX_SCENE_BYTES + draw(st.integers(1, 4 * MAX_SCENE_BYTES))
        filler = draw(st.sampled_from(["# c\n", 'unknownkey = "x"\n', "k = 1\n"]))
        text = scene_text() + filler * (size // len(filler) + 1)
        return kind, text.encode(), []
    if kind == "special":
        specials = ["fifo", "/dev/zero", "/dev/urandom", "/dev/null", "folder",
                    "link to /dev/zero", "broken link"]  # fmt: skip
        return kind, draw(st.sampled_from(specials)), []
    if kind == "not utf-8":
        raw = scene_text().encode()
        at = draw(st.integers(0, len(raw)))
        return kind, raw[:at] + draw(st.sampled_from([b"\xff", b"\xc3\x28", b"\xed\xa0\x80"])) + raw[at:], []  # noqa: E501
    if kind == "junk":
        return kind, draw(st.binary(min_size=0, max_size=4096)), []
    if kind == "long span":
        t_end = draw(st.sampled_from(["1e7", "1e9", "1e12", "1e308", '"1e400"', '"10**9"',
                                      '"1e9"']))  # fmt: skip
        extra = draw(
            st.sampled_from(["", 'method = "RK45"', 'rtol = 1e-13', "max_steps = 1000",
                             'precision = 30', 'method = "taylor"'])
        )  # fmt: skip
        return kind, scene_text(t_end=t_end, extra=extra).encode(), []
    title = draw(st.text(min_size=501, max_size=2000))
    return kind, scene_text(title=title).encode(), []


def _place(sandbox: Path, content: object) -> str:
    path = sandbox / "scene.toml"
    if isinstance(content, bytes):
        path.write_bytes(content)
        return str(path)
    if content == "fifo":
        os.mkfifo(path)
        return str(path)
    if content == "folder":
        path.mkdir()
        return str(path)
    if content == "link to /dev/zero":
        path.symlink_to("/dev/zero")
        return str(path)
    if content == "broken link":
        path.symlink_to(sandbox / "nowhere")
        return str(path)
    return str(content)


@SETTINGS
@given(hostile_scene_files(), st.booleans())
def test_hostile_scene_files_are_refused_before_any_work(case, explain):
    kind, content, flags = case
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        make_canary(sandbox / "user")
        path = _place(sandbox, content)
        argv = ["run", path, *flags, *(["--explain"] if explain else ["--out", "out"])]
        before = tree_digest(sandbox, lambda p: p.name == "scene.toml")
        outcome = run_cli(argv, sandbox, seconds=60)
        after = tree_digest(sandbox, lambda p: p.name == "scene.toml")
        check_case("scene files", outcome, before, after, {2})
        assert set(after) == set(before)  # nothing written
        assert outcome.seconds < 30, f"{kind} took {outcome.seconds:.1f} s to refuse"


#: Titles with what a terminal would act on: escapes, bell, carriage return, C1 controls,
#: bidi overrides, line separators, mathtext.
NASTY_TITLES = st.one_of(
    st.text(alphabet=st.characters(categories=["Cc", "Cf", "Zl", "Zp"]), max_size=20),
    st.text(max_size=120),
    st.sampled_from(["\x1b]0;pwned\x07", "\x1b[2J\x1b[H", "\x9b31m", "a\u202eb\u2066",
                     "$x^$", "$$", r"$\frac{$", "café — ok", "\r\roverwrite"]),  # fmt: skip
)


@SETTINGS
@given(NASTY_TITLES, st.booleans())
def test_titles_reach_no_terminal_raw_and_draw_literally(title, plot):
    """``--explain`` and a run with a plot: exit 0, no control character on stdout or
    stderr (:func:`hostile.check_case`), the title in the summary as written."""
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp)
        make_canary(sandbox / "user")
        scene = sandbox / "scene.toml"
        scene.write_text(scene_text(title=title, plot=plot))
        before = tree_digest(sandbox, lambda p: p.name == "out")
        explain = run_cli(["run", str(scene), "--explain"], sandbox)
        check_case("titles on the terminal", explain, before, before, {0})
        outcome = run_cli(["run", str(scene), "--out", "out"], sandbox)
        after = tree_digest(sandbox, lambda p: p.name == "out")
        check_case("titles on the terminal", outcome, before, after, {0})
        import json

        assert json.loads((sandbox / "out" / "summary.json").read_text())["title"] == title


# ---------------------------------------------------------------------------------- the API
Y0 = {"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")}
P0 = {"I": (1, 2, 3), "D": 1}


def _refused(call) -> None:
    """``call()`` raises a documented exception; the case is tallied."""
    try:
        call()
    except ChaplyginError:
        tally_case("API", {"traceback": False, "wrong success": False})
        return
    except Exception:
        tally_case("API", {"traceback": True, "wrong success": False})
        raise
    tally_case("API", {"traceback": False, "wrong success": True})
    pytest.fail("accepted")


_OUTSIDE = st.one_of(
    st.floats(min_value=10.000001, max_value=1e300),
    st.floats(max_value=-1e-9, min_value=-1e300),
)


@SETTINGS
@given(st.lists(st.floats(0, 10), max_size=3), _OUTSIDE, st.sampled_from(["DOP853", "taylor"]))
def test_integrate_refuses_output_times_outside_the_span(inside, outside, method):
    times = sorted([*inside, outside])
    _refused(
        lambda: chaplygin.integrate("chaplygin_ball", Y0, 10, P0, method=method, t_eval=times)
    )


@SETTINGS
@given(
    st.one_of(st.floats(1e9, 1e308), st.sampled_from(["1e400", "1e9", "10**12"])),
    st.sampled_from(["DOP853", "RK45", "taylor"]),
)
def test_integrate_refuses_a_span_that_could_only_end_at_the_step_limit(t_end, method):
    _refused(lambda: chaplygin.integrate("chaplygin_ball", Y0, t_end, P0, method=method))


@pytest.fixture(scope="module")
def propagator():
    return chaplygin.Propagator("chaplygin_ball", Y0, P0, rtol=1e-12, atol=1e-12)


@SETTINGS
@given(
    st.one_of(
        st.floats(1e9, 1e308), st.floats(-1e308, -1e9),
        st.sampled_from(["1e400", math.nan, math.inf, None, [1], "abc", 0.0]),
    )
)  # fmt: skip
def test_propagator_refuses_hopeless_or_bad_ends(propagator, t):
    _refused(lambda: propagator.propagate_until(t))
    _refused(lambda: propagator.propagate_for(t))


@pytest.mark.parametrize(
    "args",
    [
        (None,), (5,), ({},), (b"BKM12-4",), (3.5,), (object(),), ([None],), ([""],),
        ("",), ("no-such-claim",), ("BKM12-4", {"timeout": -1}), ("BKM12-4", {"jobs": 0}),
        ("BKM12-4", {"timeout": math.nan}), ("BKM12-4", {"method": None}),
        ("BKM12-4", {"timeout": "soon"}), ("BKM12-4", {"jobs": 2.5}),
    ],
)  # fmt: skip
def test_check_refuses_what_is_not_a_claim(args):
    kwargs = args[-1] if isinstance(args[-1], dict) and len(args) == 2 else {}
    _refused(lambda: chaplygin.check(args[0], **kwargs))


@pytest.mark.parametrize(
    "data",
    [None, 5, "x", [], {"system": "chaplygin_ball", "parameters": {"X": _deep_list(3000)}},
     {"title": "x" * 501}, "long span"],
)  # fmt: skip
def test_scene_from_dict_refuses_hostile_data(data):
    if data == "long span":
        import tomllib

        data = tomllib.loads(scene_text(t_end="1e9"))
    _refused(lambda: Scene.from_dict(data).resolve())


def test_scene_from_toml_refuses_a_fifo_without_blocking(tmp_path):
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)
    _refused(lambda: Scene.from_toml(fifo))
    _refused(lambda: Scene.from_toml("/dev/zero"))
