"""``import chaplygin``: the public surface in one import (issue 10, item 5)."""

from __future__ import annotations

import subprocess
import sys
from importlib.metadata import version

import chaplygin
import pytest


@pytest.mark.quick
@pytest.mark.parametrize("name", [n for n in chaplygin.__all__ if n != "__version__"])
def test_every_public_name_resolves(name):
    value = getattr(chaplygin, name)
    assert value is not None
    assert name in dir(chaplygin)


@pytest.mark.quick
def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        chaplygin.nonexistent  # noqa: B018


@pytest.mark.quick
def test_version_is_the_installed_distribution():
    assert chaplygin.__version__ == version("chaplygin")


@pytest.mark.quick
def test_import_is_cheap():
    """The import loads no heavy dependency: they load when a function needs them."""
    code = (
        "import sys, chaplygin; "
        "print(','.join(m for m in ('sympy', 'scipy', 'matplotlib', 'numpy') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_check_one_claim_gives_its_verdict():
    v = chaplygin.check("BKM12-4")
    assert isinstance(v, chaplygin.Verdict)
    assert (v.id, v.verdict) == ("BKM12-4", "proved")


def test_check_a_pattern_gives_the_verdicts_in_order():
    vs = chaplygin.check("BKM12-4,BKM12-4/control-*")
    assert [v.id for v in vs][0] == "BKM12-4"
    assert {v.verdict for v in vs[1:]} == {"refuted"}  # the negative controls


@pytest.mark.quick
@pytest.mark.parametrize(
    ("claims", "kwargs", "match"),
    [
        ("NOPE-1", {}, "no claim matches"),
        ("", {}, "no claim given"),
        ("BKM12-4", {"method": "guess"}, "unknown method"),
        ("BKM12-4", {"jobs": 0}, "jobs must be"),
    ],
)
def test_check_refuses_bad_arguments_with_the_documented_error(claims, kwargs, match):
    with pytest.raises(chaplygin.UserInputError, match=match):
        chaplygin.check(claims, **kwargs)


def test_check_of_a_selection_shows_progress_on_stderr_only_when_asked(capsys):
    """``chaplygin.check`` of several claims (issue 28, 6): a tqdm bar on stderr with
    ``progress=True``, nothing with ``progress=False`` nor by default when stderr is not a
    terminal (as here); the verdicts the same either way."""
    shown = chaplygin.check("BKM12-4,BKM12-4/control-*", progress=True)
    err = capsys.readouterr().err
    n = len(shown)
    assert n >= 2 and f"{n}/{n}" in err and "claims" in err
    for progress in (False, None):
        quiet = chaplygin.check("BKM12-4,BKM12-4/control-*", progress=progress)
        assert capsys.readouterr().err == ""
        assert [(v.id, v.verdict) for v in quiet] == [(v.id, v.verdict) for v in shown]


@pytest.mark.quick
@pytest.mark.parametrize(("script", "pool"), [(None, True), ("/some/script.py", False)])
def test_check_runs_a_selection_in_the_verifiers_pool_where_spawning_is_safe(
    monkeypatch, script, pool
):
    """The default ``jobs``: the verifier's pool (``default_jobs()``, as ``chaplygin
    verify``) in an interactive session, this process in a script (spawned workers would
    re-import it); a given ``jobs`` is kept."""
    import types

    from chaplygin.verify import check as check_module
    from chaplygin.verify.verdict import default_jobs

    main = types.ModuleType("__main__")
    if script is not None:
        main.__file__ = script
    monkeypatch.setitem(sys.modules, "__main__", main)
    asked = []

    def record(claims, method, jobs, timeout):
        asked.append(jobs)
        return iter(())

    monkeypatch.setattr(check_module, "iter_verdicts", record)
    chaplygin.check("BKM12-4,BKM12-4/control-*")
    chaplygin.check("BKM12-4,BKM12-4/control-*", jobs=3)
    assert asked == [default_jobs() if pool else 1, 3]
