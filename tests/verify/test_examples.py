"""The examples run as shipped (short times)."""

from __future__ import annotations

import runpy
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_reference_problem_example_runs(capsys):
    namespace = runpy.run_path(str(EXAMPLES / "reference_problem.py"))
    namespace["main"](3.0)
    out = capsys.readouterr().out
    assert "drift H" in out and "40 digits" in out
