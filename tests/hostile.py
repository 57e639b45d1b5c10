"""What the hostile suites share (issue 25): a canary tree of user files hashed before and after
every case, the command line run in-process with a time limit, and the invariant.

Every case of ``tests/verify/test_hostile_*.py`` (outputs, scenes, sweeps, caches) ends with
:func:`check_case`: no user file changed (the canary tree's digest is the same), no traceback,
an exit status of 0, 1 or 2 as the command line documents (2: exactly one line on stderr,
``chaplygin: error: ...``), no control character from user text on the terminal, and an
answer within :data:`HANG_SECONDS`. Each case is tallied per surface (:data:`TALLY`); the
numbers of the README's table are these tallies, printed at the end of a run
(``pytest -n 0 -p no:randomly tests/verify/test_hostile_*.py``) by ``tests/conftest.py``, and
appended as JSON lines to ``$CHAPLYGIN_HOSTILE_LOG`` when it is set (parallel runs).
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import math
import os
import signal
import stat
import time
import unicodedata
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from chaplygin.verify.cli import main

#: Longest a case may take before it counts as a hang (a run is well under a second; a sweep
#: with its Dask client a few).
HANG_SECONDS = 60

#: Cases per surface and outcome: ``TALLY[surface]["cases"]``, ``...["data loss"]``, ...
TALLY: dict[str, Counter] = {}

#: The failures a case is checked for (each must stay at 0).
FAILURES = ("data loss", "wrong success", "traceback", "hang")


class Hang(Exception):
    """The case took longer than :data:`HANG_SECONDS`."""


def _alarm(signum, frame):
    raise Hang(f"no answer within {HANG_SECONDS} s")


# ------------------------------------------------------------------------------- the canary
def tree_digest(root: Path, skip: Callable[[Path], bool] = lambda p: False) -> dict[str, str]:
    """Every entry under ``root`` (not followed through symbolic links): its kind and, for a
    file, the SHA-256 of its content, for a link its target, and its mode bits.

    Parameters
    ----------
    root : Path
    skip : callable
        Paths (and everything under them) left out: the folders a case may write into.
    """
    out: dict[str, str] = {}
    for dirpath, dirnames, filenames in os.walk(root, followlinks=False):
        here = Path(dirpath)
        for name in sorted(dirnames + filenames):
            path = here / name
            if skip(path):
                if name in dirnames:
                    dirnames.remove(name)
                continue
            st = os.lstat(path)
            rel = str(path.relative_to(root))
            mode = stat.S_IMODE(st.st_mode)
            if stat.S_ISLNK(st.st_mode):
                out[rel] = f"link {os.readlink(path)}"
            elif stat.S_ISREG(st.st_mode):
                out[rel] = f"file {mode:o} {hashlib.sha256(path.read_bytes()).hexdigest()}"
            elif stat.S_ISDIR(st.st_mode):
                out[rel] = f"dir {mode:o}"
            else:
                out[rel] = f"other {stat.S_IFMT(st.st_mode)}"
    return out


def changed(before: dict[str, str], after: dict[str, str]) -> list[str]:
    """The entries of ``before`` that are gone or different in ``after``."""
    return sorted(k for k, v in before.items() if after.get(k) != v)


# ----------------------------------------------------------------------------- the command
@dataclass
class Outcome:
    """What one command line did."""

    argv: list[str]
    code: int | None
    out: str
    err: str
    seconds: float
    hang: bool = False


def run_cli(argv: list[str], cwd: Path, seconds: int = HANG_SECONDS) -> Outcome:
    """``chaplygin argv`` in-process in ``cwd``, with its output captured and a time limit."""
    out, err = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(seconds)
    started = time.monotonic()
    code, hang = None, False
    try:
        with contextlib.chdir(cwd), contextlib.redirect_stdout(out), contextlib.redirect_stderr(
            err
        ):
            code = main(argv)
    except Hang:
        hang = True
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    return Outcome(argv, code, out.getvalue(), err.getvalue(), time.monotonic() - started, hang)


def _controls(text: str) -> list[str]:
    """Control and format characters in ``text`` other than the newline."""
    return [
        repr(ch)
        for ch in text
        if ch != "\n" and unicodedata.category(ch) in ("Cc", "Cf", "Zl", "Zp")
    ]


def _stderr_lines(err: str) -> list[str]:
    """stderr without Python's warnings (a warning is two lines: where, and the source line)
    and the distributed library's notes about a busy dashboard port on this machine."""
    lines, skip = [], False
    for line in err.splitlines():
        if skip:
            skip = False
            continue
        if "Warning: " in line and ".py:" in line:
            skip = True  # the source line follows
            continue
        if line.startswith(("Perhaps you already have a cluster", "Hosting the HTTP server")):
            continue
        lines.append(line)
    return lines


def check_case(
    surface: str,
    outcome: Outcome,
    before: dict[str, str],
    after: dict[str, str],
    expect: set[int] | None = None,
) -> None:
    """The invariant of every hostile case; tallies the case, then asserts.

    Parameters
    ----------
    surface : str
        The row of the README's table (``"run --out"``, ``"sweep store"``, ...).
    outcome : Outcome
    before, after : dict
        :func:`tree_digest` of the canary tree before and after.
    expect : set of int, optional
        The exit statuses this case may have (a refusal: ``{2}``); a 0 outside it is a
        wrong success.
    """
    tally = TALLY.setdefault(surface, Counter())
    tally["cases"] += 1
    lost = changed(before, after)
    lines = _stderr_lines(outcome.err)
    problems = {
        "hang": outcome.hang,
        "data loss": bool(lost),
        "traceback": "Traceback" in outcome.err or outcome.code not in (0, 1, 2),
        "wrong success": expect is not None and outcome.code == 0 and 0 not in expect,
    }
    for name, bad in problems.items():
        if bad:
            tally[name] += 1
    _log(surface, outcome, problems)
    what = f"{outcome.argv}: exit {outcome.code}, stderr {outcome.err[-600:]!r}"
    assert not outcome.hang, f"hang: {what}"
    assert not lost, f"user files changed: {lost}; {what}"
    assert not problems["traceback"], f"traceback or internal error: {what}"
    assert not problems["wrong success"], f"exit 0 where {expect} was expected: {what}"
    if expect is not None:
        assert outcome.code in expect, f"exit {outcome.code} not in {expect}: {what}"
    if outcome.code == 2:
        assert len(lines) == 1 and lines[0].startswith("chaplygin: error: "), what
    assert not _controls(outcome.out + "\n".join(lines)), f"control characters: {what}"


def tally_case(surface: str, problems: dict[str, bool]) -> None:
    """Tally a case checked by its own assertions (an API call, a cache fault)."""
    tally = TALLY.setdefault(surface, Counter())
    tally["cases"] += 1
    for name, bad in problems.items():
        if bad:
            tally[name] += 1
    _log(surface, None, problems)


def _log(surface: str, outcome: Outcome | None, problems: dict[str, bool]) -> None:
    path = os.environ.get("CHAPLYGIN_HOSTILE_LOG")
    if not path:
        return
    entry = {
        "surface": surface,
        "code": outcome.code if outcome else None,
        "seconds": round(outcome.seconds, 3) if outcome else None,
        **{k: bool(v) for k, v in problems.items()},
    }
    with open(path, "a", encoding="utf-8") as fh:
        fh.write(json.dumps(entry) + "\n")


def make_canary(root: Path, scene_text: str | None = None) -> None:
    """The user's files: a thesis, data in a subfolder, a summary.json of their own, notes,
    a copy of the scene, a link to a file outside and a read-only file."""
    root.mkdir(parents=True, exist_ok=True)
    (root / "thesis.tex").write_text("\\documentclass{article}\n% the user's thesis\n")
    (root / "sub").mkdir(exist_ok=True)
    (root / "sub" / "data.csv").write_text("t,x\n0,1\n1,2\n")
    (root / "summary.json").write_text('{"mine": true}\n')
    (root / "notes.txt").write_text("notes café — ✓\n")
    if scene_text is not None:
        (root / "scene-copy.toml").write_text(scene_text)
    with contextlib.suppress(FileExistsError):
        os.symlink("/etc/hostname", root / "link-outside")
    ro = root / "readonly.txt"
    if not ro.exists():
        ro.write_text("read-only\n")
        ro.chmod(0o444)


def read_only_place(sandbox: Path) -> Path:
    """A folder where nothing can be created: a read-only one (root may write anywhere, so
    for root a folder of /proc, where nobody can)."""
    if os.geteuid() == 0:
        return Path(f"/proc/{os.getpid()}")
    folder = sandbox / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    return folder


# ---------------------------------------------------------------------------------- scenes
#: The cheap scene of the hostile suites (the ball, 0.2 time units, 3 output points).
SCENE = """title = {title}
system = "chaplygin_ball"
[parameters]
I = [1, 1.5, 2]
D = 1
[initial]
M = [0.7, -0.4, 0.5]
gamma = [0.2, 0.3, "sqrt(0.87)"]
[run]
t_end = {t_end}
points = 3
{run}
[outputs]
{outputs}
"""


def scene_toml(title: str = "t", t_end: str = "0.2", run: str = "", outputs: str = "") -> str:
    """The suites' scene: ``run`` and ``outputs`` are extra lines of those tables."""
    return SCENE.format(title=toml_string(title), t_end=t_end, run=run, outputs=outputs)


def toml_string(text: str) -> str:
    """A TOML basic string holding ``text`` exactly (controls as ``\\uXXXX``, astral
    characters as they are: TOML has no surrogate pairs)."""
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return toml_string(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def to_toml(d: dict) -> str:
    """A minimal TOML writer: top-level keys, then one [table] per dict (nested tables
    inline)."""
    lines = [f"{json.dumps(k)} = {_toml_value(v)}" for k, v in d.items() if not isinstance(v, dict)]
    for k, v in d.items():
        if isinstance(v, dict):
            lines.append(f"[{json.dumps(k)}]")
            lines += [f"{json.dumps(kk)} = {_toml_value(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"
