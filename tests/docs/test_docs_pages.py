"""The documentation's generated pages and the README's promises (no Sphinx needed).

The pages come from ``docs/_ext/chaplygin_docs.py`` (loaded from its file: the extension is not
part of the package); the docs build itself runs in CI (``.ci/run``).
"""

from __future__ import annotations

import importlib.util
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def ext():
    spec = importlib.util.spec_from_file_location(
        "chaplygin_docs", ROOT / "docs" / "_ext" / "chaplygin_docs.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def verdicts():
    import chaplygin

    # BM20-2.6: the energy's corrected form and its literal reading (refuted: an erratum);
    # BKM12-4: the measure and its two controls (refuted, with their witnesses)
    return [chaplygin.check(c) for c in ("BM20-2.6", "BM20-2.6/literal")] + chaplygin.check(
        "BKM12-4*"
    )


def _rows(page: str, claim_id: str) -> list[list[str]]:
    """Cells of the table rows whose first cell names ``claim_id`` (as code or in bold)."""
    out = []
    for line in page.splitlines():
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
        if cells and (cells[0] == f"`{claim_id}`" or cells[0].startswith(f"**{claim_id}**:")):
            out.append(cells)
    return out


@pytest.mark.slow  # the verdicts: their models derived in this process (~10 s)
def test_json_round_trip(ext, verdicts):
    items = json.loads(json.dumps([v.to_json() for v in verdicts]))
    assert any("witness" not in item for item in items)  # to_json drops an empty witness
    assert ext.verdicts_of_json(items) == verdicts


@pytest.mark.slow  # the verdicts: their models derived in this process (~10 s)
def test_catalogue_lists_every_claim_with_its_evidence(ext, verdicts):
    page = ext.render_catalogue(verdicts, "a test")
    claims = page.split("## Claims")[1]
    for v in verdicts:
        (row,) = _rows(claims, v.id)
        assert v.statement.replace("|", "\\|")[:40] in row[1]
        assert row[2].startswith(v.verdict)
        assert row[3] == "yes"
        assert row[4] == v.method
        assert float(row[6]) == pytest.approx(v.seconds, abs=5e-4)
        if v.verdict == "refuted":
            assert f"residual {v.residual} at " in row[5]
    assert f"{len(verdicts)} claims" in page


@pytest.mark.slow  # the verdicts: their models derived in this process (~10 s)
def test_catalogue_errata_pair_each_literal_reading_with_its_correction(ext, verdicts):
    page = ext.render_catalogue(verdicts, "a test")
    errata = page.split("## Errata")[1].split("## Claims")[0]
    literal = [v for v in verdicts if v.id.endswith("/literal")]
    assert literal  # the selection holds one
    for v in literal:
        fix = next(f for f in verdicts if f.id == v.id.removesuffix("/literal"))
        (row,) = _rows(errata, v.id)
        assert row[1] == v.verdict == "refuted"
        assert row[2].startswith(f"**{fix.id}**:")
        assert row[3] == fix.verdict


@pytest.mark.slow  # the verdicts: their models derived in this process (~10 s)
def test_catalogue_marks_an_unexpected_verdict(ext, verdicts):
    import dataclasses

    wrong = [
        dataclasses.replace(v, verdict="proved", residual="0") if v.id.endswith("/literal") else v
        for v in verdicts
    ]
    page = ext.render_catalogue(wrong, "a test")
    bad = [v for v in wrong if not v.ok]
    assert bad and f"; {len(bad)} unexpected;" in page
    for v in bad:
        (row,) = _rows(page.split("## Claims")[1], v.id)
        assert row[3].startswith("**NO: proved, expected refuted")


def test_reference_sheet_entries_each_listed(ext):
    from chaplygin.verify.coverage import FORMULAS_ENTRIES

    page = ext.render_entries()
    for entry_id, *_ in FORMULAS_ENTRIES:
        assert len(_rows(page, entry_id)) == 1, entry_id


def test_api_page_documents_every_public_name(ext):
    import chaplygin

    page = ext.render_api()
    documented = re.findall(r"^\.\. (?:auto\w+|py:data):: chaplygin\.(\w+)$", page, re.M)
    assert documented == [n for n in chaplygin.__all__ if n != "__version__"]


# ------------------------------------------------------------------ README
README = ROOT / "README.md"


def test_readme_is_short_and_keeps_the_two_setup_commands():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 250
    # .ci/run greps the test command; the main job's command is the other
    assert [
        line for line in lines if re.match(r"^python3 -m venv .venv && .*\[test[],].*pytest", line)
    ]
    assert (
        "python3 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/chaplygin verify" in lines
    )


def test_readme_links_resolve_to_files_of_the_repository():
    text = README.read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text)
    local = [t for t in targets if not re.match(r"[a-z]+://", t)]
    assert len(local) > 20
    missing = [t for t in local if not (ROOT / t).exists()]
    assert not missing


def test_citation_and_licence_agree_with_pyproject():
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    cff = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    assert cff.startswith("cff-version: 1.2.0\n")
    assert f"\nversion: {project['version']}\n" in cff
    assert f"\nlicense: {project['license']['text']}\n" in cff
    assert (ROOT / "LICENSE").read_text(encoding="utf-8").startswith("BSD 3-Clause License")
    assert project["license"]["text"] == "BSD-3-Clause"
    assert cff.count("doi: ") == 4  # the four papers
