"""The Markdown report of ``chaplygin verify --report FILE.md``: cite-able verdicts.

Per claim: ID, statement in LaTeX, verdict, method, residual or witness, time; an
**Errata** section with every literal reading of a garbled formula that was refuted, next
to its correction; counts per paper.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence

from .claims import REGISTRY
from .coverage import SECTIONS, CoverageRow, coverage
from .latex import plain_to_latex
from .verdict import Verdict

__all__ = [
    "plain_to_latex",
    "render_report",
    "render_coverage",
    "render_summary",
    "by_paper_of",
    "errata",
    "paper_of",
]


def paper_of(claim_id: str) -> str:
    """``BKM12-4/control-...`` -> ``BKM12``; ``MODEL:...`` -> ``chaplygin models``.

    Parameters
    ----------
    claim_id : str
        A claim ID.

    Returns
    -------
    str
        The paper's key (the part before the first ``-``), or ``"chaplygin models"``
        for the claims about our own models.
    """
    if claim_id.startswith("MODEL:"):
        return "chaplygin models"
    return claim_id.split("-", 1)[0]


def _evidence(v: Verdict) -> str:
    if v.verdict == "refuted":
        witness = ", ".join(f"{k} = {val}" for k, val in (v.witness or {}).items())
        return f"residual {v.residual} at {witness}" if witness else f"residual {v.residual}"
    return f"residual {v.residual}"


def render_coverage(rows: Sequence[CoverageRow]) -> list[str]:
    """Markdown lines: per FORMULAS.md section, checkable entries with a verdict and the
    ones without (a FAILED entry needs its ``/literal`` claim too).

    Parameters
    ----------
    rows : sequence of CoverageRow
        One per FORMULAS.md entry (:func:`~.coverage.coverage`).

    Returns
    -------
    list of str
        A Markdown table: header, separator and one line per section (in the order of
        ``rows``).
    """
    lines = [
        "| FORMULAS.md section | issue | checkable | covered | not covered yet |",
        "|---|---|---|---|---|",
    ]
    by_section: dict[str, list[CoverageRow]] = {}
    for r in rows:
        by_section.setdefault(r.section, []).append(r)
    for section, rs in by_section.items():
        checkable = [r for r in rs if r.checkable]
        missing = [
            r.id + (" (/literal)" if r.claims and not r.literal_claims else "")
            for r in checkable
            if not r.covered
        ]
        title, issue = SECTIONS[section]
        lines.append(
            f"| {section} {title} | {issue} | {len(checkable)} | "
            f"{len(checkable) - len(missing)} | {', '.join(missing) or '-'} |"
        )
    return lines


def by_paper_of(verdicts: Sequence[Verdict]) -> dict[str, list[Verdict]]:
    """The verdicts grouped by paper (:func:`paper_of`), in the order first met.

    Parameters
    ----------
    verdicts : sequence of Verdict
        The verdicts, in the order the report lists them.

    Returns
    -------
    dict of str to list of Verdict
        Paper key -> its verdicts, each list in the order given.
    """
    by_paper: dict[str, list[Verdict]] = {}
    for v in verdicts:
        by_paper.setdefault(paper_of(v.id), []).append(v)
    return by_paper


def render_summary(by_paper: Mapping[str, Sequence[Verdict]]) -> list[str]:
    """Markdown lines of the summary per paper: how many claims got each verdict.

    Parameters
    ----------
    by_paper : mapping of str to sequence of Verdict
        What :func:`by_paper_of` returns.

    Returns
    -------
    list of str
        A Markdown table: header, separator and one line per paper.
    """
    lines = [
        "| paper | claims | proved | proved by computation | exact-sampled | numeric | refuted "
        "| unexpected |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for paper, vs in by_paper.items():
        c = Counter(v.verdict for v in vs)
        lines.append(
            f"| {paper} | {len(vs)} | {c['proved']} | {c['proved by computation']} | "
            f"{c['exact-sampled']} | {c['numeric']} | {c['refuted']} | "
            f"{sum(not v.ok for v in vs)} |"
        )
    return lines


def errata(verdicts: Sequence[Verdict]) -> list[tuple[Verdict, Verdict | None]]:
    """Each literal reading of a garbled formula (``.../literal``) with its correction.

    Parameters
    ----------
    verdicts : sequence of Verdict
        The verdicts of a run, literal readings and corrections among them.

    Returns
    -------
    list of (Verdict, Verdict or None)
        The literal reading's verdict and the verdict of the claim it corrects (the ID
        without ``/literal``; None when that claim is not among ``verdicts``), in order.
    """
    index = {v.id: v for v in verdicts}
    return [(v, index.get(v.id[: -len("/literal")])) for v in verdicts if v.id.endswith("/literal")]


def render_report(verdicts: Sequence[Verdict]) -> str:
    """Markdown text of the report.

    Parameters
    ----------
    verdicts : sequence of Verdict
        The verdicts to report, in the order they are listed per paper.

    Returns
    -------
    str
        The report: overall count, summary per paper, errata (literal readings next to
        their corrections), coverage of FORMULAS.md and one table of claims per paper;
        it ends with a newline.
    """
    lines = ["# chaplygin verification report", ""]
    by_paper = by_paper_of(verdicts)
    bad = [v for v in verdicts if not v.ok]
    lines += [
        f"{len(verdicts)} claims, {sum(v.seconds for v in verdicts):.1f} s of checking; "
        + (
            "every verdict is the expected one."
            if not bad
            else f"**{len(bad)} unexpected verdicts**."
        ),
        "",
        "Verdicts: `proved` (Gröbner normal form of the numerator modulo the phase-space "
        "constraints is zero), `exact-sampled` (exactly zero in rational arithmetic at random "
        "rational points of the phase space; probabilistic), `proved by computation` (decided by "
        "enclosures in ball arithmetic: a validated integrator, the Krawczyk and Schur-Cohn "
        "tests), `numeric` (below a stated bound at "
        "50 digits), `refuted` (an exact rational witness point). Negative controls and literal "
        "readings of garbled formulas are expected to be refuted.",
        "",
        "## Summary per paper",
        "",
        *render_summary(by_paper),
    ]
    lines += ["", "## Errata", ""]
    pairs = errata(verdicts)
    if not pairs:
        lines.append("No literal reading among the checked claims.")
    else:
        lines += ["| literal reading | verdict | correction | verdict |", "|---|---|---|---|"]
        for v, fix in pairs:
            fix_text = f"{fix.id}: ${fix.latex}$" if fix else "(not checked)"
            lines.append(
                f"| {v.id}: ${v.latex}$ | {v.verdict} ({_evidence(v)}) | {fix_text} | "
                f"{fix.verdict if fix else '-'} |"
            )
    lines += ["", "## Coverage of FORMULAS.md", ""]
    lines += render_coverage(coverage(REGISTRY[v.id] for v in verdicts if v.id in REGISTRY))
    lines += ["", "## Claims", ""]
    for paper, vs in by_paper.items():
        lines += [
            f"### {paper}",
            "",
            "| ID | statement | verdict | method | evidence | s |",
            "|---|---|---|---|---|---|",
        ]
        for v in vs:
            mark = "" if v.ok else " **(unexpected)**"
            expected = " (expected: refuted)" if v.expected == "fails" else ""
            lines.append(
                f"| {v.id} | ${v.latex}$ | {v.verdict}{expected}{mark} | {v.method} | "
                f"{_evidence(v)} | {v.seconds:.3f} |"
            )
        lines.append("")
    return "\n".join(lines) + "\n"
