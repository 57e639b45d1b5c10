"""``chaplygin derive --out DIR`` never deletes or overwrites a file it did not write."""

from __future__ import annotations

import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.writer import MANIFEST, is_ours, write_generated


def _snapshot(folder):
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def test_a_folder_of_the_users_files_is_refused_and_left_alone(tmp_path):
    users = {"analysis.py": "x = 1\n", "results.json": "{}", "solver.c": "int m;"}
    for name, text in users.items():
        (tmp_path / name).write_text(text)
    before = _snapshot(tmp_path)
    with pytest.raises(UserInputError, match="not empty and was not written by chaplygin"):
        write_generated(tmp_path)
    assert _snapshot(tmp_path) == before


def test_our_folder_is_rewritten_and_the_users_extra_file_kept(tmp_path):
    out = tmp_path / "gen"
    written = write_generated(out)
    assert MANIFEST in written and all(is_ours(out / n) for n in written)
    (out / "mine.py").write_text("keep me\n")
    stale = out / "chaplygin_ball__old_numpy.py"
    stale.write_text((out / "chaplygin_ball_numpy.py").read_text())  # stamped: ours
    assert write_generated(out) == [stale.name]  # only our stale file goes
    assert (out / "mine.py").read_text() == "keep me\n"
    assert not stale.exists()


def test_a_users_file_with_a_generated_name_is_not_overwritten(tmp_path):
    out = tmp_path / "gen"
    write_generated(out)
    (out / "chaplygin_ball.c").write_text("/* my own solver */\n")
    with pytest.raises(UserInputError, match="chaplygin_ball.c is not a file chaplygin derive"):
        write_generated(out)
    assert (out / "chaplygin_ball.c").read_text() == "/* my own solver */\n"


def test_an_output_path_that_is_a_file_is_refused(tmp_path):
    f = tmp_path / "file"
    f.write_text("data")
    with pytest.raises(UserInputError, match="not a folder"):
        write_generated(f)
    assert f.read_text() == "data"
