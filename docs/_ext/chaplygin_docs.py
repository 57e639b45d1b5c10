"""Pages generated from the package when the docs build (a Sphinx extension).

* ``results/catalogue.md``: every claim with its statement, verdict, method, time and
  evidence, the errata and the coverage of the reference sheet, from the output of
  ``chaplygin verify --json`` (the file ``CHAPLYGIN_VERIFY_JSON`` names, else a run of it);
* ``reference/_entries.md``: every entry of the reference sheet (``FORMULAS_ENTRIES``) and the
  claims that decide it;
* ``reference/api.rst``: the API reference of every name in ``chaplygin.__all__``.

Nothing here is typed in by hand: a claim added to the registry appears at the next build.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # sphinx is imported only when Sphinx runs the extension (tests need none)
    from chaplygin.verify.verdict import Verdict
    from sphinx.application import Sphinx

PAPERS = {
    "BKM12": "Borisov, Kilin, Mamaev 2012",
    "K01": "Kilin 2001",
    "BM20": "Borisov, Mikishanina 2020",
    "M03": "Mamaev 2003",
    "KANE": "the derived equations against sympy.physics.mechanics' KanesMethod",
    "chaplygin models": "the integrals and densities the built-in models ship",
}


def _cell(text: object) -> str:
    """Text for a Markdown table cell: pipes escaped, code spans kept on one line."""
    return str(text).replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")


def _code(text: object) -> str:
    """A code span holding ``text`` (backticks inside are replaced by quotes)."""
    return "`" + _cell(text).replace("`", "'") + "`"


def verify_json() -> tuple[list[Verdict], str]:
    """The verdicts of ``chaplygin verify --json`` and where they came from."""
    from sphinx.errors import ExtensionError
    from sphinx.util import logging

    given = os.environ.get("CHAPLYGIN_VERIFY_JSON")
    if given:
        path = Path(given)
        if not path.is_file():
            raise ExtensionError(f"CHAPLYGIN_VERIFY_JSON names {given}, which is not a file")
        items = json.loads(path.read_text(encoding="utf-8"))
        return verdicts_of_json(items), f"read from {path.name}"
    started = time.perf_counter()
    cmd = [sys.executable, "-m", "chaplygin.verify.cli", "verify", "--json"]
    logging.getLogger(__name__).info("chaplygin verify --json for the claims catalogue (~2 min)")
    run = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if run.returncode not in (0, 1):  # 1: some verdict is unexpected; it is shown as such
        raise ExtensionError(f"chaplygin verify --json failed: {run.stderr.strip()[-2000:]}")
    wall = time.perf_counter() - started
    return verdicts_of_json(json.loads(run.stdout)), f"run during this build, {wall:.0f} s wall"


def _evidence(v: Verdict) -> str:
    if v.witness:
        point = ", ".join(f"{k} = {x}" for k, x in v.witness.items())
        return f"residual {v.residual} at {point}"
    return "" if v.residual is None else f"residual {v.residual}"


def verdicts_of_json(items: list[dict]) -> list[Verdict]:
    """Verdicts from the JSON objects of ``chaplygin verify --json`` (``ok`` is recomputed).

    Parameters
    ----------
    items : list of dict
        As ``Verdict.to_json`` wrote them.

    Returns
    -------
    list of Verdict
        In the same order.
    """
    from chaplygin.verify.verdict import Verdict

    # to_json leaves out a witness there is none of, and adds ok
    return [
        Verdict(**{"witness": None, **{k: x for k, x in item.items() if k != "ok"}})
        for item in items
    ]


def render_catalogue(verdicts: list[Verdict], origin: str) -> str:
    """The claims catalogue page (MyST markdown).

    Parameters
    ----------
    verdicts : list of Verdict
        From ``chaplygin verify --json`` (:func:`verdicts_of_json`).
    origin : str
        Where they come from (said on the page).

    Returns
    -------
    str
        The page: counts, the summary per paper, the errata (each literal reading beside its
        correction) and one table per paper (ID, statement, verdict, ok, method, evidence,
        seconds).
    """
    from chaplygin.verify.claims import REGISTRY
    from chaplygin.verify.report import by_paper_of, errata, render_summary

    bad = [v for v in verdicts if not v.ok]
    by_paper = by_paper_of(verdicts)
    counts = Counter(v.verdict for v in verdicts)
    lines = [
        "# Claims catalogue",
        "",
        "Generated when these pages were built, from `chaplygin verify --json` "
        f"({origin}): {len(verdicts)} claims, "
        + ", ".join(f"{n} {k}" for k, n in sorted(counts.items()))
        + f"; {len(bad)} unexpected; {sum(v.seconds for v in verdicts):.1f} s of checking. "
        "A negative control or a literal reading of a garbled formula is expected to be "
        "refuted; `ok` says the verdict is the one expected, by the expected method, with its "
        "evidence. Verdicts and methods are explained in [Claims and verdicts](claims.md); the "
        "IDs are those of the [reference sheet](../reference/formulas.md).",
        "",
        "## Summary per paper",
        "",
        *render_summary(by_paper),
        "",
        "## Errata",
        "",
        "Each literal reading of a formula the text of a paper garbles, refuted, beside the "
        "corrected form and its verdict.",
        "",
        "| literal reading | verdict | correction | verdict |",
        "|---|---|---|---|",
    ]
    for v, fix in errata(verdicts):
        fixed = f"**{fix.id}**: {_code(fix.statement)}" if fix else "(not checked)"
        lines.append(
            f"| **{v.id}**: {_code(v.statement)} | {v.verdict} | {fixed} | "
            f"{fix.verdict if fix else '-'} |"
        )
    lines += ["", "## Claims", ""]
    for paper, vs in by_paper.items():
        lines += [
            f"### {paper}: {PAPERS.get(paper, paper)}",
            "",
            "| ID | statement | verdict | ok | method | evidence | s |",
            "|---|---|---|---|---|---|---|",
        ]
        for v in vs:
            claim = REGISTRY.get(v.id)
            note = f" ({_cell(claim.note)})" if claim is not None and claim.note else ""
            expected = " (expected)" if v.expected == "fails" else ""
            ok = "yes" if v.ok else f"**NO: {_cell(v.problem)}**"
            lines.append(
                f"| {_code(v.id)} | {_code(v.statement)}{note} | {v.verdict}{expected} | {ok} | "
                f"{_cell(v.method)} | {_code(_evidence(v))} | {v.seconds:.3f} |"
            )
        lines.append("")
    return "\n".join(lines) + "\n"


def render_entries() -> str:
    """The reference sheet's entries and the claims that decide each (MyST markdown).

    Returns
    -------
    str
        A page section: the coverage per section, then one table row per entry.
    """
    from chaplygin.verify.claims import select_claims
    from chaplygin.verify.coverage import SECTIONS, coverage
    from chaplygin.verify.report import render_coverage

    rows = coverage(select_claims())
    lines = ["## Coverage per section", "", *render_coverage(rows), "", "## Entries", ""]
    lines += ["| entry | section | checkable | claims | literal reading refuted by |"]
    lines += ["|---|---|---|---|---|"]
    for r in rows:
        title = SECTIONS[r.section][0]
        claims = ", ".join(f"`{c}`" for c in r.claims) or "-"
        literal = ", ".join(f"`{c}`" for c in r.literal_claims) or "-"
        lines.append(
            f"| `{r.id}` | {_cell(title)} | {'yes' if r.checkable else 'no'} | {claims} | "
            f"{literal} |"
        )
    return "\n".join(lines) + "\n"


def render_api() -> str:
    """The API reference page (reStructuredText: autodoc's output is reST, not Markdown).

    Returns
    -------
    str
        The page: one autodoc directive per name of ``chaplygin.__all__``.
    """
    import inspect

    import chaplygin

    title = "API reference"
    lines = [
        title,
        "=" * len(title),
        "",
        "Every public name of ``import chaplygin`` (``chaplygin.__all__``), with its numpydoc "
        "docstring. Errors a user can fix raise ``chaplygin.UserInputError`` (a ``ValueError``).",
        "",
    ]
    for name in chaplygin.__all__:
        if name == "__version__":
            continue
        obj = getattr(chaplygin, name)
        if inspect.isclass(obj):
            lines += [f".. autoclass:: chaplygin.{name}", ""]
        elif callable(obj):
            lines += [f".. autofunction:: chaplygin.{name}", ""]
        else:  # a registry: its keys (autodoc would show the docstring of its type)
            keys = ", ".join(f"``{k}``" for k in obj)
            lines += [
                f".. py:data:: chaplygin.{name}",
                f"   :type: {type(obj).__name__}",
                "",
                f"   The valid names, in order: {keys}.",
                "",
            ]
    return "\n".join(lines)


def _write(path: Path, text: str) -> None:
    """Write only when the text changed (Sphinx then rebuilds only what changed)."""
    if not path.is_file() or path.read_text(encoding="utf-8") != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def generate(app: Sphinx) -> None:
    """Write the generated pages into the source tree (git ignores them).

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application (its ``srcdir``).
    """
    src = Path(app.srcdir)
    _write(src / "reference" / "api.rst", render_api())
    _write(src / "reference" / "_entries.md", render_entries())
    _write(src / "results" / "catalogue.md", render_catalogue(*verify_json()))


def setup(app: Sphinx) -> dict[str, object]:
    """Register the generator.

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application.

    Returns
    -------
    dict
        Extension metadata.
    """
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
