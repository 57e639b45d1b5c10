"""``docs/browser_check.py`` on a small site whose pages each break one thing.

The check must pass a sound page and fail each broken one for its own reason; it needs
Debian's ``chromium`` (skipped without it, except under CI, which requires it: ``.ci/run``).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _load():
    spec = importlib.util.spec_from_file_location(
        "browser_check", ROOT / "docs" / "browser_check.py"
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up while it loads
    try:
        spec.loader.exec_module(module)
    finally:
        del sys.modules[spec.name]
    return module


@pytest.fixture(scope="module")
def browser_check():
    return _load()


@pytest.fixture(scope="module")
def chromium():
    path = shutil.which("chromium")
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is needed for the browser check (CI: apt-get install chromium)")
        pytest.skip("no chromium")
    return path


PAGES = {
    "sound.html": '<h1>sound</h1><img src="dot.png" alt="dot"><img src="sub/dot.png" alt="">',
    "missing-image.html": '<img src="dot.png" alt=""><img src="nowhere.png" alt="">',
    "console-error.html": "<script>console.error('boom from the page')</script>",
    "uncaught.html": "<script>undefinedFunction()</script>",
    # the served image by another name of the loopback address: only 127.0.0.1 resolves
    "other-host.html": (
        '<img id="x" alt=""><script>document.getElementById("x").src = '
        '"http://localhost:" + location.port + "/dot.png"</script>'
    ),
}


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    from PIL import Image

    root = tmp_path_factory.mktemp("site")
    (root / "sub").mkdir()
    for folder in (root, root / "sub"):
        Image.new("RGB", (3, 2), (200, 30, 30)).save(folder / "dot.png")
    head = '<!doctype html><html><head><link rel="icon" href="data:,"></head><body>'
    for name, body in PAGES.items():
        (root / name).write_text(head + body + "</body></html>", encoding="utf-8")
    return root


@pytest.fixture(scope="module")
def reports(browser_check, chromium, site, tmp_path_factory):
    shots = tmp_path_factory.mktemp("shots")
    return {r.path: r for r in browser_check.check_site(site, list(PAGES), shots, chromium)}


def test_a_sound_page_passes_with_its_images_and_screenshot(reports):
    r = reports["sound.html"]
    assert r.ok, r.errors
    assert [ok for _, ok in r.images] == [True, True]
    assert r.screenshot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_missing_image_fails(reports):
    r = reports["missing-image.html"]
    assert not r.ok
    assert [(src.rsplit("/", 1)[1], ok) for src, ok in r.images] == [
        ("dot.png", True),
        ("nowhere.png", False),
    ]
    assert any("nowhere.png" in e for e in r.errors)


def test_a_console_error_fails(reports):
    r = reports["console-error.html"]
    assert not r.ok
    assert any("boom from the page" in e for e in r.errors)


def test_an_uncaught_exception_fails(reports):
    r = reports["uncaught.html"]
    assert not r.ok
    assert any("undefinedFunction" in e for e in r.errors)


def test_no_host_name_resolves(reports):
    r = reports["other-host.html"]
    assert not r.ok
    assert [ok for _, ok in r.images] == [False]
    assert any("ERR_NAME_NOT_RESOLVED" in e for e in r.errors)


def test_no_build_is_bad_input(browser_check, tmp_path, capsys):
    assert browser_check.main([str(tmp_path / "nothing")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "build the docs first" in err
