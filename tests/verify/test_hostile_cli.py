"""Hostile input, generated: every subcommand and the public API refuse it cleanly.

Valid command lines of every subcommand are mutated (unknown flags, wrong types, huge, NaN or
negative numbers, hostile number expressions, output paths that are folders, empty, missing
or unwritable, unknown systems, effects, figures, claims, problems) and run in-process
through :func:`chaplygin.verify.cli.main` in a fresh working folder. A hostile command line
must exit 2 with exactly one line on stderr, no traceback, nothing on stdout and no file
created; no example may take longer than :data:`HANG_SECONDS`. Each family fails at
validation, before any work, so about 1,100 examples run in well under a minute; a few
subprocess runs check the real exit status of the console entry point.

The fixed cases and the public API's examples are in the developers' quick loop (``pytest -m
quick``); the generated command-line families and the unmutated bifurcation command (it draws
a figure) only in the default run.
"""

from __future__ import annotations

import contextlib
import io
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.verify import cli, integrate_cmd
from chaplygin.verify.cli import main
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

#: Longest an example may run before it counts as a hang.
HANG_SECONDS = 20

_SETTINGS = dict(
    deadline=None,  # a first call imports sympy/scipy; hangs are caught by HANG_SECONDS
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


class _Hang(Exception):
    pass


def _alarm(signum, frame):
    raise _Hang(f"no answer within {HANG_SECONDS} s")


def _files(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*")}


def run_cli(argv: list[str]) -> tuple[int, str, str, set[str]]:
    """Run ``main(argv)`` in a fresh folder holding ``sub/`` and ``file.txt``.

    Returns the exit status, stdout, stderr and the names of the files it created.
    """
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "sub").mkdir()
        (root / "file.txt").write_text("not a folder\n")
        before = _files(root)
        out, err = io.StringIO(), io.StringIO()
        previous = signal.signal(signal.SIGALRM, _alarm)
        signal.alarm(HANG_SECONDS)
        try:
            with (
                contextlib.chdir(root),
                contextlib.redirect_stdout(out),
                contextlib.redirect_stderr(err),
            ):
                code = main(argv)
        finally:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, previous)
        return code, out.getvalue(), err.getvalue(), _files(root) - before


def assert_refused(argv: list[str]) -> str:
    """``argv`` exits 2 with one line on stderr, no traceback, no output, no file."""
    code, out, err, created = run_cli(argv)
    assert "Traceback" not in err, (argv, err)
    assert code == 2, (argv, code, err, out[:300])
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("chaplygin: error: "), (argv, err)
    assert out == "", (argv, out[:300])
    assert not created, (argv, created)
    return lines[0]


# -- hostile values ---------------------------------------------------------------------

#: Number texts no command may accept: non-finite, non-real, overflowing, malformed,
#: code, too long or too deep.
HOSTILE_NUMBERS = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e309",
    "-1e309",
    "9**9**9**9",
    "10**100000",
    "sqrt(-1)",
    "log(0)",
    "log(-1)",
    "1/0",
    "0/0",
    "exp(1e6)",
    "",
    " ",
    "abc",
    "1..2",
    "1e",
    "0x10",
    "1j",
    "__import__('os').system('true')",
    "open('x','w')",
    "(lambda: 1)()",
    "[1]",
    "1 if 1 else 2",
    "x",
    "pi()",
    "sqrt",
    "sqrt(1,2)",
    "1;2",
    "7" * 5000,
    "sqrt(" * 100 + "1" + ")" * 100,
    "1+" * 2000 + "1",
    "-" * 500 + "1",
]

hostile_number = st.sampled_from(HOSTILE_NUMBERS)

#: Whole-number flags given something that is not a whole number (argparse refuses it).
not_an_int = st.sampled_from(["abc", "1.5", "nan", "inf", "", "1e3", "0x10", "--", "1_0_"])

_name = st.text(alphabet="abcxyz_-0189", min_size=1, max_size=12)

#: Output file paths that are refused (relative to the fresh folder): empty, folders,
#: missing parents, a file as parent, a place where nothing can be written.
bad_file_paths = st.one_of(
    st.sampled_from(["", " ", ".", "sub", "sub/", "/proc/x.png", "/"]),
    _name.map(lambda n: f"missing-{n}/x.png"),
    _name.map(lambda n: f"file.txt/{n}.png"),
    _name.map(lambda n: f"sub/{n}/"),
)

#: Output folder paths that are refused.
bad_dir_paths = st.one_of(
    st.sampled_from(["", " ", "file.txt", "/proc/x"]),
    _name.map(lambda n: f"missing-{n}/deeper"),
    _name.map(lambda n: f"file.txt/{n}"),
)

unknown_flag = st.one_of(
    st.sampled_from(["--frobnicate", "--x=1", "-Z", "--json=yes", "--outt", "---"]),
    _name.map(lambda n: f"--no-such-{n}"),
)


def _with(argv: list[str], flag: str, value: str) -> list[str]:
    """``argv`` with ``flag value`` replacing an existing ``flag`` or appended."""
    argv = list(argv)
    if flag in argv:
        argv[argv.index(flag) + 1] = value
        return argv
    return [*argv, flag, value]


@st.composite
def with_unknown_flag(draw, base: list[str]) -> list[str]:
    argv = list(base)
    argv.insert(draw(st.integers(1, len(argv))), draw(unknown_flag))
    return argv


# -- integrate ---------------------------------------------------------------------------

INTEGRATE = (
    "integrate chaplygin_ball --param I=1,2,3 --param D=1 --y0 M=0.7,-0.4,0.5 "
    "--y0 gamma=0,0,1 --t-end 0.5"
).split()


@st.composite
def integrate_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 9))
    argv = list(INTEGRATE)
    if kind == 0:  # a hostile number in a parameter, a state component or the start time
        where = draw(st.sampled_from([3, 5, 7, 9, "t-start"]))
        bad = draw(hostile_number)
        if where == "t-start":
            return [*argv, "--t-start", bad]
        name, _, values = argv[where].partition("=")
        parts = values.split(",")
        parts[draw(st.integers(0, len(parts) - 1))] = bad
        argv[where] = f"{name}={','.join(parts)}"
        return argv
    if kind == 1:
        return draw(with_unknown_flag(argv))
    if kind == 2:  # non-physical: non-positive inertia or D, a gamma off the unit sphere
        return draw(
            st.sampled_from(
                [
                    [*argv[:3], "I=1,2,-3", *argv[4:]],
                    [*argv[:5], "D=0", *argv[6:]],
                    [*argv[:5], "D=-1e-300", *argv[6:]],
                    [*argv[:9], "gamma=0,0,2", *argv[10:]],
                    [*argv[:9], "gamma=0,0,0", *argv[10:]],
                    [*argv[:3], "I=1,2", *argv[4:]],
                    [*argv[:7], "M=1,2,3,4", *argv[8:]],
                ]
            )
        )
    if kind == 3:  # unknown names
        return draw(
            st.sampled_from(
                [
                    ["integrate", "no_such_system", *argv[2:]],
                    [*argv, "--effects", "magnetic"],
                    [*argv, "--effects", "gyrostat,magnetic"],
                    [*argv, "--method", "euler"],
                    [*argv, "--backend", "fortran"],
                    [*argv, "--param", "Q=1"],
                    [*argv, "--y0", "omega=1,2,3"],
                    [*argv, "--param", "I=1,2,3"],
                    [*argv, "--param", "I"],
                    [*argv, "--y0", "=1"],
                ]
            )
        )
    if kind == 4:  # a span beyond the step budget (refused before any work), or a fast spin
        if draw(st.booleans()):
            spin = draw(st.sampled_from(["1e8", "1e12", "-3e9"]))
            return [*argv[:7], f"M={spin},1,0", *argv[8:]]
        big = draw(st.sampled_from(["1e308", "1e300", "1e20", "1e12", "2e6", "10**9"]))
        return _with(argv, "--t-end", big)
    if kind == 5:
        return _with(argv, "--max-steps", draw(st.sampled_from(["0", "-1", "-10**9"])))
    if kind == 6:  # tolerances: non-positive, not a number, below what double delivers
        flag = draw(st.sampled_from(["--rtol", "--atol"]))
        value = draw(st.sampled_from(["0", "-1", "nan", "inf", "abc", "-1e-300"]))
        if flag == "--rtol" and draw(st.booleans()):
            value = draw(st.sampled_from(["1e-17", "1e-30", "1e-300"]))
        return _with(argv, flag, value)
    if kind == 7:
        bad = draw(st.sampled_from(["5", "0", "-1", "15", "10001", "10**9", "single", "", "nan"]))
        return _with(argv, "--precision", bad)
    if kind == 8:
        return _with(argv, "--max-steps", draw(not_an_int))
    return _with(argv, "--t-end", draw(hostile_number))


@settings(max_examples=260, **_SETTINGS)
@given(integrate_hostile())
def test_integrate_refuses_hostile_input(argv):
    assert_refused(argv)


# -- verify ------------------------------------------------------------------------------


#: Valid flags of verify that change nothing about a refusal (added in any subset).
VERIFY_EXTRAS = [["--json"], ["--method", "auto"], ["--timeout", "30"], ["--jobs", "1"]]


@st.composite
def verify_hostile(draw) -> list[str]:
    argv = draw(_verify_hostile())
    for extra in draw(st.lists(st.sampled_from(VERIFY_EXTRAS), unique_by=lambda x: x[0])):
        if extra[0] not in argv:
            argv = [*argv, *extra]
    return argv


@st.composite
def _verify_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 5))
    base = ["verify", "--claims", "BKM12-4"]
    if kind == 0:
        return ["verify", "--claims", draw(st.sampled_from(["", " ", ",", " , ,", "NOPE-*"]))]
    if kind == 1:  # a report path that cannot be written, with a claim that would pass
        return ["verify", "--claims", "BKM12-4", "--report", draw(bad_file_paths)]
    if kind == 2:
        jobs = draw(st.sampled_from(["0", "-1", "257", "100000", "10**9"]))
        return ["verify", "--claims", "BKM12-4", "--jobs", jobs]
    if kind == 3:
        bad = draw(st.sampled_from(["nan", "-1", "inf", "-inf", "abc", ""]))
        return ["verify", "--claims", "BKM12-4", "--timeout", bad]
    if kind == 4:
        return ["verify", "--claims", "BKM12-4", "--method", draw(st.sampled_from(["x", ""]))]
    return draw(with_unknown_flag(base))


@settings(max_examples=120, **_SETTINGS)
@given(verify_hostile())
def test_verify_refuses_hostile_input(argv):
    assert_refused(argv)


# -- derive ------------------------------------------------------------------------------


@st.composite
def derive_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 2))
    if kind == 0:
        return ["derive", "--out", draw(bad_dir_paths)]
    if kind == 1:  # a folder that holds files chaplygin derive did not write
        return ["derive", "--out", "."]
    return draw(with_unknown_flag(["derive", "--check"]))


@settings(max_examples=60, **_SETTINGS)
@given(derive_hostile())
def test_derive_refuses_hostile_input(argv):
    assert_refused(argv)


# -- bench -------------------------------------------------------------------------------


@st.composite
def bench_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 4))
    base = ["bench", "--quick", "--problems", "reference", "--out", "b"]
    if kind == 0:
        return _with(base, "--out", draw(bad_dir_paths))
    if kind == 1:
        bad = draw(st.sampled_from(["0", "-1", "101", "10**6", "1000000000"]))
        return [*base, "--repeats", bad]
    if kind == 2:
        bad = draw(st.sampled_from(["", ",", "nope", "reference,nope", " , "]))
        return _with(base, "--problems", bad)
    if kind == 3:
        return [*base, "--repeats", draw(not_an_int)]
    return draw(with_unknown_flag(base))


@settings(max_examples=100, **_SETTINGS)
@given(bench_hostile())
def test_bench_refuses_hostile_input(argv):
    assert_refused(argv)


# -- bifurcation -------------------------------------------------------------------------


@st.composite
def bifurcation_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 6))
    base = ["bifurcation", "chaplygin_ball", "--samples", "1", "--out", "d.png"]
    if kind == 0:
        return _with(base, "--out", draw(st.one_of(bad_file_paths, st.just("d.jpg"))))
    if kind == 1:
        bad = draw(st.sampled_from(["0", "-1", "10001", "1000000000", "10**12"]))
        return _with(base, "--samples", bad)
    if kind == 2:
        return _with(base, "--seed", draw(st.sampled_from(["-1", "4294967296", "10**30"])))
    if kind == 3:
        name = draw(st.sampled_from(["I", "D", "C"]))
        return [*base, "--param", f"{name}={draw(hostile_number)}"]
    if kind == 4:
        return draw(
            st.sampled_from(
                [
                    ["bifurcation", "no_such", *base[2:]],
                    [*base, "--figure", "k01-9"],
                    [*base, "--figure", "bkm12-5"],
                    [*base, "--param", "I=1,2"],
                    [*base, "--param", "I=1,2,-3"],
                    [*base, "--param", "D=-1"],
                    [*base, "--param", "Q=1"],
                    [*base, "--param", "I=1,1000,2"],  # hours of work: beyond MAX_RATIO
                    [*base, "--param", "D=1e6"],
                    [*base, "--param", "I=1e300,2e300,3e300"],
                    [*base, "--param", "C=1e300"],
                ]
            )
        )
    if kind == 5:
        flag = draw(st.sampled_from(["--samples", "--seed"]))
        return _with(base, flag, draw(not_an_int))
    return draw(with_unknown_flag(base))


@settings(max_examples=150, **_SETTINGS)
@given(bifurcation_hostile())
def test_bifurcation_refuses_hostile_input(argv):
    assert_refused(argv)


# -- delta -------------------------------------------------------------------------------

DELTA = ["delta", "--param", "I=1,3,5", "--param", "D=1", "--param", "b=1", "--digits", "5"]


@st.composite
def delta_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 6))
    if kind == 0:
        return [*DELTA, "--plot", draw(st.one_of(bad_file_paths, st.sampled_from(["p", "p.gif"])))]
    if kind == 1:
        return [*DELTA, "--figures", draw(bad_dir_paths)]
    if kind == 2:
        bad = draw(st.sampled_from(["4", "0", "-1", "201", "10**6", "1000000"]))
        return _with(DELTA, "--digits", bad)
    if kind == 3:
        where = draw(st.sampled_from([2, 4, 6]))
        argv = list(DELTA)
        argv[where] = argv[where].split("=")[0] + "=" + draw(hostile_number)
        return argv
    if kind == 4:
        return draw(
            st.sampled_from(
                [
                    [*DELTA[:2], "I=1,3", *DELTA[3:]],
                    [*DELTA[:2], "I=3,1,5", *DELTA[3:]],
                    [*DELTA[:2], "I=1,3,-5", *DELTA[3:]],
                    [*DELTA[:4], "D=-1", *DELTA[5:]],
                    [*DELTA[:6], "b=0", *DELTA[7:]],
                    [*DELTA[:6], "b=-1", *DELTA[7:]],
                    [*DELTA, "--param", "C=0"],
                    [*DELTA[:4], "D=1e3", *DELTA[5:]],  # mu = 501: 7,000 steps
                    [*DELTA[:4], "D=1e300", *DELTA[5:]],
                    [*DELTA, "--param", "Z=1"],
                    ["delta", "--param", "I=1,3,5", "--digits", "5"],
                    [*DELTA, "--engine", "euler"],
                ]
            )
        )
    if kind == 5:
        return _with(DELTA, "--digits", draw(not_an_int))
    return draw(with_unknown_flag(DELTA))


@settings(max_examples=150, **_SETTINGS)
@given(delta_hostile())
def test_delta_refuses_hostile_input(argv):
    assert_refused(argv)


# -- rotation ----------------------------------------------------------------------------

ROTATION = "rotation --I 1,2,3 --D 1 --M 0.5,0.5,0 --gamma 0,0,1 --digits 15".split()


@st.composite
def rotation_hostile(draw) -> list[str]:
    kind = draw(st.integers(0, 5))
    if kind == 0:
        where = draw(st.sampled_from([2, 4, 6, 8]))
        parts = ROTATION[where].split(",")
        parts[draw(st.integers(0, len(parts) - 1))] = draw(hostile_number)
        argv = list(ROTATION)
        argv[where] = ",".join(parts)
        return argv
    if kind == 1:
        bad = draw(st.sampled_from(["14", "0", "-1", "1001", "10**6", "1000000"]))
        return _with(ROTATION, "--digits", bad)
    if kind == 2:
        bad = draw(st.sampled_from(["0", "-1", "nan", "inf", "1e6", "1e300", "abc"]))
        return [*ROTATION, "--simulate", bad]
    if kind == 3:
        return draw(
            st.sampled_from(
                [
                    _with(ROTATION, "--I", "1,2"),
                    _with(ROTATION, "--I", "3,2,1"),
                    _with(ROTATION, "--I", "1,2,-3"),
                    _with(ROTATION, "--D", "-1"),
                    _with(ROTATION, "--D", "1,2"),
                    _with(ROTATION, "--M", "0,0,0"),
                    _with(ROTATION, "--gamma", "0,2,0"),
                    _with(ROTATION, "--gamma", "0,0,0"),
                    _with(ROTATION, "--M", "1,0"),
                    _with(ROTATION, "--D", "1e30"),
                    _with(ROTATION, "--I", "1e30,2e30,3e30"),
                ]
            )
        )
    if kind == 4:
        return _with(ROTATION, "--digits", draw(not_an_int))
    return draw(with_unknown_flag(ROTATION))


@settings(max_examples=150, **_SETTINGS)
@given(rotation_hostile())
def test_rotation_refuses_hostile_input(argv):
    assert_refused(argv)


# -- the public API: hostile values raise UserInputError ---------------------------------


def _api_calls() -> list[Callable[[str], object]]:
    import chaplygin

    state = {"M": (0.7, -0.4, 0.5), "gamma": (0, 0, 1)}
    params = {"I": (1, 2, 3), "D": 1}
    return [
        lambda v: chaplygin.integrate("chaplygin_ball", {**state, "M": (v, 0, 0)}, 1, params),
        lambda v: chaplygin.integrate("chaplygin_ball", state, 1, {**params, "D": v}),
        lambda v: chaplygin.integrate("chaplygin_ball", state, (v, 1), params),
        lambda v: chaplygin.integrate("chaplygin_ball", state, 1, params, precision=v),
        lambda v: chaplygin.integrate(v or "?", state, 1, params),
        lambda v: chaplygin.Precision(v),
        lambda v: chaplygin.build_model(v or "?"),
        lambda v: chaplygin.build_model("chaplygin_ball", effects=[v or "?"]),
    ]


@pytest.mark.quick  # in-process API calls only: a fraction of a second
@settings(max_examples=120, **_SETTINGS)
@given(st.integers(0, 7), hostile_number)
def test_public_api_raises_user_input_error(which, value):
    call = _api_calls()[which]
    if which == 3 and value.strip().isdigit():  # a number of digits is a precision
        value = "5"
    with pytest.raises(UserInputError) as info:
        call(value)
    assert "\n" not in str(info.value).strip()


# -- fixed cases: the known bugs of issue 11, internal errors, real processes ------------


@pytest.mark.parametrize(
    "argv",
    [
        pytest.param(INTEGRATE, marks=pytest.mark.quick),
        pytest.param(ROTATION, marks=pytest.mark.quick),
        pytest.param(DELTA, marks=pytest.mark.quick),
        ["bifurcation", "chaplygin_ball", "--samples", "1", "--out", "d.png"],  # a figure: slower
    ],
    ids=lambda argv: argv[0],
)
def test_the_mutated_command_lines_are_valid(argv):
    """The hostile families mutate these: unmutated, they run (so a refusal is the mutation's)."""
    code, out, err, created = run_cli(argv)
    assert code == 0, err
    assert out and "error" not in err
    assert created == ({"d.png"} if argv[0] == "bifurcation" else set())


@pytest.mark.quick
@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["verify", "--claims", ""], "names no claim"),
        (["bench", "--out", ""], "empty"),
        (["derive", "--out", ""], "empty"),
        (["bifurcation", "chaplygin_ball", "--out", "x.png", "--samples", "1000000000"], "10000"),
        ([*DELTA, "--plot", "sub"], "is a folder"),
        ([*DELTA, "--plot", "p"], ".png"),
        (_with(INTEGRATE, "--t-end", "1e308"), "--max-steps"),
        (["verify", "--claims", "BKM12-4", "--report", "/proc/r.md"], "cannot write"),
        (["verify", "--claims", "BKM12-4", "--report", "nope/r.md"], "does not exist"),
    ],
)
def test_known_cases_are_refused_before_any_work(argv, message):
    start = time.perf_counter()
    line = assert_refused(argv)
    assert message in line
    assert time.perf_counter() - start < 5  # refused at validation, not after the work


@pytest.mark.quick
def test_step_budget_can_be_raised():
    assert "--max-steps" in assert_refused(_with(INTEGRATE, "--t-end", "2e6"))
    from chaplygin.numerics.step_budget import estimated_steps

    estimate = estimated_steps(2e6, None, None, double=True)
    assert estimate > integrate_cmd.DEFAULT_MAX_STEPS
    # a budget above the estimate passes the pre-check (the span itself is then integrated,
    # so only the pre-check is run here)
    ns = cli.build_parser().parse_args(
        [*_with(INTEGRATE, "--t-end", "2e6"), "--max-steps", str(int(estimate) + 1)]
    )
    from chaplygin.numerics.inputs import Precision

    integrate_cmd._check_step_budget(ns, Precision("double"))


@pytest.mark.quick
def test_internal_error_is_one_line_exit_3(monkeypatch):
    def broken(args):
        raise KeyError("a bug")

    monkeypatch.setattr(integrate_cmd, "run", broken)
    code, out, err, created = run_cli(INTEGRATE)
    assert code == 3 and out == "" and not created
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert err.startswith("chaplygin: internal error: KeyError") and "report" in err
    assert "--debug" in err
    code, _, err, _ = run_cli(["--debug", *INTEGRATE])
    assert code == 3 and "Traceback" in err and "KeyError" in err
    code, _, err, _ = run_cli([*INTEGRATE, "--debug"])
    assert code == 3 and "Traceback" in err


@pytest.mark.quick
def test_os_error_while_working_is_one_line(monkeypatch):
    def full_disk(args):
        raise OSError(28, "No space left on device", "out.png")

    monkeypatch.setattr(integrate_cmd, "run", full_disk)
    code, out, err, _ = run_cli(INTEGRATE)
    assert code == 1 and out == ""
    assert err.strip() == "chaplygin: error: out.png: No space left on device"


@pytest.mark.quick
@pytest.mark.parametrize(
    "argv",
    [
        _with(INTEGRATE, "--t-end", "9**9**9**9"),
        ["bench", "--out", "file.txt"],
        ["frobnicate"],
    ],
)
def test_real_process_exit_status(tmp_path: Path, argv):
    (tmp_path / "file.txt").write_text("x")
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    proc = subprocess.run(
        [sys.executable, "-m", "chaplygin.verify.cli", *argv],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "Traceback" not in proc.stderr
    assert proc.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.txt"]
