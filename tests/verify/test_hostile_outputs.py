"""``chaplygin run --out`` never deletes or overwrites what it did not write (issue 25, item 1).

Each case builds a sandbox holding the user's files (a canary tree: a thesis, data in a
subfolder, a ``summary.json`` of their own, notes, a copy of the scene, a link to a file
outside, a read-only file) and points ``--out`` at it in one of the ways a user does by
mistake or on purpose: the folder itself, ``results/..``, ``x/../..``, ``.``, a symbolic link,
a file, a scene stem such as ``..`` (``...toml``), a previous run's folder with the user's
additions (or with one of our files changed), a new nested folder, an empty one. The
invariant (:func:`hostile.check_case`) holds after every case: no user file changed, no
traceback, exit 0/1/2 (2 with one line, and then nothing created); a refusal where the
folder is not ours (a 0 there is a wrong success); a success leaves our marker listing
exactly the files written.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
from pathlib import Path

import pytest
from chaplygin.verify.output_folder import MARKER, safe_name
from hostile import (
    check_case,
    make_canary,
    read_only_place,
    run_cli,
    scene_toml,
    tree_digest,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

#: How ``--out`` is pointed at the sandbox (each with the statuses it may end with).
KINDS = {
    "foreign folder": {2},
    "results/..": {2},
    "x/../..": {2},
    "dot in a foreign folder": {2},
    "a file": {2},
    "link to a foreign folder": {2},
    "link to an empty folder": {0},
    "broken link on the way": {2},
    "scene inside a foreign folder": {2},
    "stem without --out": {0},
    "previous run with the user's additions": {0},
    "previous run, one of ours changed": {2},
    "previous run, marker damaged": {2},
    "previous run, rerun refused": {2},
    "new nested folder": {0},
    "empty folder": {0},
    "two scenes whose stems clash": {2},
    "a read-only place": {2},
}

#: Scene file names a user may have (stems ``..``, ``.``, empty, control characters...).
STEMS = ["...toml", "..toml", ".toml", "a b.toml", "café — x.toml", "x\x1b[2J.toml",
         "-rf.toml", "~.toml", "x\ny.toml", "normal.toml"]  # fmt: skip

TITLES = st.one_of(
    st.sampled_from(["", "café — ünïcode", "$x^$", "\x1b[31mred\x07", "a\u202eb", "t" * 500]),
    st.text(max_size=40),
)


def _scene_text(title: str, fmt: str) -> str:
    fmt_line = f'trajectory = {{ format = "{fmt}" }}'
    return scene_toml(title, run="rtol = 1e-8\natol = 1e-8", outputs=fmt_line)


def _ours(folder: Path) -> set[Path]:
    """The files our marker in ``folder`` lists (they may be replaced), and the marker."""
    try:
        data = json.loads((folder / MARKER).read_text())
        names = set(data["files"]) | set(data.get("pending", {}))
    except (OSError, ValueError, KeyError, TypeError):
        return set()
    return {folder / n for n in names} | {folder / MARKER}


def _previous_run(sandbox: Path, scene: Path, folder: Path) -> None:
    out = run_cli(["run", str(scene), "--out", str(folder), "--quiet"], sandbox)
    assert out.code == 0, out.err


@st.composite
def output_cases(draw):
    kind = draw(st.sampled_from(sorted(KINDS)))
    title = draw(TITLES)
    fmt = draw(st.sampled_from(["netcdf", "csv", "both"]))
    stem = draw(st.sampled_from(STEMS))
    change = draw(st.sampled_from(["edit", "delete-and-link", "replace-by-folder"]))
    return kind, title, fmt, stem, change


@settings(
    max_examples=int(os.environ.get("CHAPLYGIN_HOSTILE_EXAMPLES", 60)),
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(output_cases())
def test_run_out_never_touches_what_is_not_ours(case):
    kind, title, fmt, stem, change = case
    with tempfile.TemporaryDirectory() as tmp:
        sandbox = Path(tmp) / "sandbox"
        text = _scene_text(title, fmt)
        make_canary(sandbox, text)
        user = sandbox / "user"
        make_canary(user, text)
        scene = sandbox / "scene.toml"
        scene.write_text(text)
        cwd, argv, target = sandbox, None, None
        if kind == "foreign folder":
            target = user
        elif kind == "results/..":
            cwd, argv = user, ["run", str(scene), "--out", "results/.."]
        elif kind == "x/../..":
            inner = user / "inner"
            make_canary(inner)
            cwd, argv = inner, ["run", str(scene), "--out", "x/../.."]
        elif kind == "dot in a foreign folder":
            cwd, argv = user, ["run", str(scene), "--out", "."]
        elif kind == "a file":
            target = user / "thesis.tex"
        elif kind == "link to a foreign folder":
            (sandbox / "link").symlink_to(user)
            target = sandbox / "link"
        elif kind == "link to an empty folder":
            (sandbox / "empty").mkdir()
            (sandbox / "link").symlink_to(sandbox / "empty")
            target = sandbox / "link"
        elif kind == "broken link on the way":
            (sandbox / "broken").symlink_to(sandbox / "nowhere")
            target = sandbox / "broken" / "out"
        elif kind == "scene inside a foreign folder":
            inside = user / stem.replace("\n", "_")
            inside.write_text(text)
            argv = ["run", str(inside), "--out", str(user)]
        elif kind == "stem without --out":
            named = user / stem
            named.write_text(text)
            cwd, argv = user, ["run", f"./{stem}"]
        elif kind.startswith("previous run"):
            target = sandbox / "previous"
            _previous_run(sandbox, scene, target)
            make_canary(target / "user-additions", text)
            (target / "notes.txt").write_text("the user's notes in our folder\n")
            shutil.copy(scene, target / "scene-copy.toml")
            if kind == "previous run, one of ours changed":
                victim = target / "summary.json"
                if change == "edit":
                    victim.write_text('{"edited by": "the user"}\n')
                elif change == "delete-and-link":
                    victim.unlink()
                    victim.symlink_to(user / "thesis.tex")
                else:
                    victim.unlink()
                    make_canary(victim)
            elif kind == "previous run, marker damaged":
                (target / MARKER).write_text(change)
            elif kind == "previous run, rerun refused":
                bad = sandbox / "bad.toml"
                bad.write_text(text.replace("D = 1", "D = -1"))
                argv = ["run", str(bad), "--out", str(target)]
        elif kind == "new nested folder":
            target = sandbox / "new" / "a" / "b"
        elif kind == "empty folder":
            target = sandbox / "empty"
            target.mkdir()
        elif kind == "a read-only place":
            target = read_only_place(sandbox) / "out"
        elif kind == "two scenes whose stems clash":
            a, b = sandbox / "a b.toml", sandbox / "a_b.toml"
            a.write_text(text)
            b.write_text(text)
            argv = ["run", str(a), str(b), "--out", str(sandbox / "gallery")]
        if argv is None:
            argv = ["run", str(scene), "--out", str(target)]
        argv.append("--quiet")
        folder = target if target is not None else None
        mine = _ours(folder) if folder is not None and folder.is_dir() else set()
        skip = mine.__contains__
        before = tree_digest(sandbox, skip)
        outcome = run_cli(argv, cwd)
        after = tree_digest(sandbox, skip)
        check_case("run --out", outcome, before, after, KINDS[kind])
        if outcome.code == 2:  # refused before any work: nothing new anywhere
            assert set(after) == set(before), sorted(set(after) - set(before))
        if outcome.code == 0:  # our marker lists exactly what we wrote, as we wrote it
            where = folder
            if kind == "stem without --out":
                where = user / "chaplygin-run" / safe_name(Path(stem).stem)
            real = Path(os.path.realpath(where))
            marker = json.loads((real / MARKER).read_text())
            assert marker["pending"] == {} and "summary.json" in marker["files"]
            for name, digest in marker["files"].items():
                assert hashlib.sha256((real / name).read_bytes()).hexdigest() == digest, name
            new = {p for p in real.iterdir() if str(p.relative_to(sandbox)) not in before}
            assert {p.name for p in new} <= {*marker["files"], MARKER}, new


def test_a_failed_write_leaves_the_previous_results(tmp_path, monkeypatch):
    """A rerun that fails while writing (here: the figure cannot be drawn) leaves the previous
    run's files as they were, and no temporary folder."""
    from chaplygin.verify import scene as scene_module

    text = _scene_text("t", "netcdf")
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    out = tmp_path / "out"
    assert run_cli(["run", str(scene), "--out", str(out), "--quiet"], tmp_path).code == 0
    before = tree_digest(out)

    def broken(self, folder):
        (Path(folder) / "trajectory.nc").write_text("half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(scene_module.SceneResult, "write", broken)
    outcome = run_cli(["run", str(scene), "--out", str(out), "--quiet"], tmp_path)
    assert outcome.code == 1 and "No space left" in outcome.err
    assert tree_digest(out) == before


@pytest.mark.parametrize("stem", ["..", ".", "...", "", "a/../b", "\x1b[2J", "x" * 300])
def test_safe_name_is_a_plain_name(stem):
    name = safe_name(stem)
    assert name and name not in (".", "..") and "/" not in name and not name.startswith(".")
    assert len(name) <= 100 and name.isascii() and name.isprintable()
