"""Open the built documentation in headless chromium and check what a reader would see.

Usage: ``python docs/browser_check.py [BUILD_DIR] [--shots DIR] [--page PATH ...]``

The built site (``docs/_build/html`` by default) is served by ``http.server`` on a loopback
port; chromium (Debian's ``chromium``) opens each page through the DevTools protocol over a
pipe (``--remote-debugging-pipe``: no socket of its own) with every host but the loopback address
unresolvable, so nothing is fetched from the network. A page passes when it loads, every ``<img>``
on it has loaded (complete, with a non-zero natural width), the console shows no error, no
script raised and no request failed. A full-page screenshot of each page is written to the
screenshots folder (``<BUILD_DIR>/../screenshots`` by default) as evidence; CI keeps them as
build artifacts.

Exit status: 0 every page passes, 1 some page fails (one line per problem), 2 bad input
(no build, no chromium: one line on stderr).
"""

from __future__ import annotations

import argparse
import base64
import functools
import http.server
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

#: The pages checked by default: the home page, the gallery and one executed notebook.
DEFAULT_PAGES = ("index.html", "results/gallery.html", "tutorials/scene.html")

#: Seconds to wait for a page's load event, and for its images after it.
LOAD_TIMEOUT_S = 60.0

_IMAGES_JS = """
(async () => {
  const imgs = Array.from(document.images);
  imgs.forEach(i => { i.loading = "eager"; });
  await Promise.all(imgs.map(i => i.complete ? null :
      new Promise(r => { i.addEventListener("load", r); i.addEventListener("error", r); })));
  return imgs.map(i => ({src: i.currentSrc || i.src, ok: i.complete && i.naturalWidth > 0}));
})()
"""


@dataclass
class PageReport:
    """What one page showed.

    Attributes
    ----------
    path : str
        The page, relative to the build folder.
    images : list of (str, bool)
        Every image's URL and whether it loaded.
    errors : list of str
        Console errors, uncaught exceptions and failed requests.
    screenshot : Path or None
        The screenshot written.
    """

    path: str
    images: list[tuple[str, bool]] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    screenshot: Path | None = None

    @property
    def ok(self) -> bool:
        """True when every image loaded and nothing went wrong."""
        return (
            bool(self.images or self.path) and not self.errors and all(ok for _, ok in self.images)
        )


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:
        pass


class DevTools:
    """A chromium process driven through the DevTools protocol over its pipe (fds 3 and 4).

    Parameters
    ----------
    chromium : str
        The browser's executable.
    profile : Path
        An empty folder for the browser's profile.
    """

    def __init__(self, chromium: str, profile: Path) -> None:
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        args = [
            chromium,
            "--headless=new",
            "--remote-debugging-pipe",
            "--no-sandbox",  # CI runs as root, where chromium's sandbox refuses to start
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--no-first-run",
            "--no-default-browser-check",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1",
            f"--user-data-dir={profile}",
            "--window-size=1280,900",
            "about:blank",
        ]

        def fds() -> None:  # the child's fds 3 and 4 are the protocol's pipe
            os.dup2(to_browser_r, 3)
            os.dup2(from_browser_w, 4)

        self.proc = subprocess.Popen(
            args,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            preexec_fn=fds,  # before any thread of ours starts (check_site)
            pass_fds=(3, 4, to_browser_r, from_browser_w),  # 3 and 4 kept open after the dup2
        )
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._buffer = b""
        self._next_id = 0
        self.events: list[dict] = []

    def _read_message(self, deadline: float) -> dict:
        while b"\0" not in self._buffer:
            if time.monotonic() > deadline:
                raise TimeoutError("chromium did not answer in time")
            chunk = os.read(self._from_browser, 1 << 16)
            if not chunk:
                raise RuntimeError("chromium closed its DevTools pipe (it exited)")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method: str, session: str | None = None, **params: object) -> dict:
        """Send one command and return its result (events meanwhile go to :attr:`events`).

        Parameters
        ----------
        method : str
            A DevTools method (``"Page.navigate"``).
        session : str, optional
            The target's session (flat mode).
        **params
            The method's parameters.

        Returns
        -------
        dict
            The result.
        """
        self._next_id += 1
        message: dict[str, object] = {"id": self._next_id, "method": method, "params": params}
        if session is not None:
            message["sessionId"] = session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + LOAD_TIMEOUT_S
        while True:
            reply = self._read_message(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error'].get('message')}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_for(self, method: str, timeout: float = LOAD_TIMEOUT_S) -> None:
        """Wait for an event (kept in :attr:`events` as any other).

        Parameters
        ----------
        method : str
            The event's name (``"Page.loadEventFired"``).
        timeout : float
            Seconds.
        """
        deadline = time.monotonic() + timeout
        while not any(e.get("method") == method for e in self.events):
            self.events.append(self._read_message(deadline))

    def close(self) -> None:
        """Close the browser."""
        try:
            self.call("Browser.close")
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._to_browser)
        os.close(self._from_browser)


def _problems(events: Sequence[dict]) -> list[str]:
    """Console errors, uncaught exceptions and failed requests among DevTools events."""
    out = []
    for e in events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in params["args"])
            out.append(f"console.{params['type']}: {text}")
        elif method == "Runtime.exceptionThrown":
            details = params.get("exceptionDetails", {})
            exc = details.get("exception", {}).get("description") or details.get("text")
            out.append(f"uncaught exception: {exc}")
        elif method == "Log.entryAdded" and params["entry"].get("level") == "error":
            entry = params["entry"]
            out.append(
                f"console error ({entry.get('source')}): {entry.get('text')} {entry.get('url', '')}"
            )
        elif method == "Network.loadingFailed" and not params.get("canceled"):
            out.append(f"request failed: {params.get('errorText')} ({params.get('requestId')})")
    return out


def check_page(browser: DevTools, base_url: str, path: str, shots: Path) -> PageReport:
    """Open one page in a new tab, wait for it and its images, screenshot it, close the tab.

    Parameters
    ----------
    browser : DevTools
        The browser.
    base_url : str
        The served site (``http://127.0.0.1:PORT/``).
    path : str
        The page, relative to the site.
    shots : Path
        The folder for the screenshot.

    Returns
    -------
    PageReport
        What the page showed.
    """
    report = PageReport(path)
    target = browser.call("Target.createTarget", url="about:blank")["targetId"]
    session = browser.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
    for domain in ("Page", "Runtime", "Log", "Network"):
        browser.call(f"{domain}.enable", session)
    browser.events.clear()
    nav = browser.call("Page.navigate", session, url=base_url + path)
    if nav.get("errorText"):
        report.errors.append(f"navigation failed: {nav['errorText']}")
    else:
        browser.wait_for("Page.loadEventFired")
        images = browser.call(
            "Runtime.evaluate",
            session,
            expression=_IMAGES_JS,
            awaitPromise=True,
            returnByValue=True,
        )["result"].get("value", [])
        report.images = [(i["src"], bool(i["ok"])) for i in images]
        report.errors += [f"image did not load: {src}" for src, ok in report.images if not ok]
        metrics = browser.call("Page.getLayoutMetrics", session)["cssContentSize"]
        shot = browser.call(
            "Page.captureScreenshot",
            session,
            format="png",
            captureBeyondViewport=True,
            clip={
                "x": 0,
                "y": 0,
                "width": metrics["width"],
                "height": min(metrics["height"], 16000),
                "scale": 1,
            },
        )
        report.screenshot = shots / (path.replace("/", "_").removesuffix(".html") + ".png")
        report.screenshot.write_bytes(base64.b64decode(shot["data"]))
    report.errors += _problems(browser.events)
    browser.call("Target.closeTarget", targetId=target)
    return report


def check_site(build: Path, pages: Sequence[str], shots: Path, chromium: str) -> list[PageReport]:
    """Serve ``build`` on a loopback port and check each page in headless chromium.

    Parameters
    ----------
    build : Path
        The HTML build folder.
    pages : sequence of str
        Pages relative to ``build``.
    shots : Path
        The folder for the screenshots (created).
    chromium : str
        The browser's executable.

    Returns
    -------
    list of PageReport
        One per page, in order.
    """
    shots.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="chaplygin-browser-") as profile:
        browser = DevTools(chromium, Path(profile))  # forked before the server's thread starts
        handler = functools.partial(_Quiet, directory=str(build))
        server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
        threading.Thread(target=server.serve_forever, daemon=True).start()
        base_url = f"http://127.0.0.1:{server.server_address[1]}/"
        try:
            return [check_page(browser, base_url, page, shots) for page in pages]
        finally:
            browser.close()
            server.shutdown()
            server.server_close()


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: check the pages, print one line per page, return the exit status.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 all pass, 1 a page fails, 2 bad input.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build", nargs="?", default=str(Path(__file__).parent / "_build/html"))
    parser.add_argument("--shots", default=None, help="screenshots folder")
    parser.add_argument("--page", action="append", default=None, help="a page to check")
    parser.add_argument("--chromium", default=os.environ.get("CHROMIUM", "chromium"))
    args = parser.parse_args(argv)
    build = Path(args.build)
    pages = args.page or list(DEFAULT_PAGES)
    missing = [p for p in pages if not (build / p).is_file()]
    if missing:
        print(
            f"browser_check: {build} has no {missing[0]}; build the docs first "
            "(sphinx-build -W -b html docs docs/_build/html)",
            file=sys.stderr,
        )
        return 2
    chromium = shutil.which(args.chromium)
    if chromium is None:
        print(
            f"browser_check: no {args.chromium} on PATH (apt-get install chromium)", file=sys.stderr
        )
        return 2
    shots = Path(args.shots) if args.shots else build.parent / "screenshots"
    started = time.perf_counter()
    reports = check_site(build, pages, shots, chromium)
    for r in reports:
        loaded = sum(ok for _, ok in r.images)
        print(
            f"{'ok  ' if r.ok else 'FAIL'} {r.path}: {loaded}/{len(r.images)} images loaded, "
            f"{len(r.errors)} errors; screenshot {r.screenshot}"
        )
        for e in r.errors:
            print(f"     {e}")
    print(
        f"{sum(r.ok for r in reports)}/{len(reports)} pages pass "
        f"({time.perf_counter() - started:.1f} s)"
    )
    return 0 if all(r.ok for r in reports) else 1


if __name__ == "__main__":
    sys.exit(main())
