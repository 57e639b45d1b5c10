"""Which statements of FORMULAS.md have a verdict: the coverage of the claim registry.

:data:`FORMULAS_ENTRIES` lists every entry of the project's reference sheet
(``shared/FORMULAS.md``, the four papers in one notation): its ID, its section, whether
the sheet calls it checkable, and whether the sheet marks its literal reading as FAILED.
It is transcribed by :func:`parse_formulas` (a test keeps it in sync with the sheet when
the sheet is at hand). A registered claim *covers* the longest entry ID that is a prefix
of its own ID followed by ``.``, ``/``, a letter or nothing (``BKM12-2.1M.N3`` covers
``BKM12-2.1M``, ``K01-2.3.h`` covers ``K01-2.3``, ``BKM12-2.3E/literal`` covers
``BKM12-2.3``); negative controls cover nothing, except the entries they name in
``Claim.covers`` (a refutation that is what the paper asserts).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

__all__ = [
    "FORMULAS_ENTRIES",
    "SECTIONS",
    "CoverageRow",
    "coverage",
    "covered_entry",
    "parse_formulas",
]

#: (ID, section of FORMULAS.md, checkable, literal reading marked FAILED)
FORMULAS_ENTRIES: tuple[tuple[str, str, bool, bool], ...] = (
    ("BKM12-1", "1.1", True, False),
    ("BKM12-2", "1.1", True, False),
    ("BKM12-3", "1.1", True, False),
    ("BKM12-4", "1.1", True, False),
    ("BKM12-5", "1.1", True, False),
    ("BKM12-6", "1.1", True, False),
    ("BKM12-7", "1.1", True, False),
    ("BKM12-8", "1.2", True, False),
    ("BKM12-9", "1.2", True, False),
    ("BKM12-10", "1.2", True, False),
    ("BKM12-1.2a", "1.2", True, False),
    ("BKM12-1.2b", "1.2", True, False),
    ("BKM12-11", "1.2", True, False),
    ("BKM12-RemEis", "1.2", True, False),
    ("BKM12-12", "1.3", True, False),
    ("BKM12-13", "1.3", False, False),
    ("BKM12-14", "1.3", True, False),
    ("BKM12-15", "1.3", True, False),
    ("BKM12-16", "1.3", False, False),
    ("BKM12-17", "1.3", True, False),
    ("BKM12-proofT1", "1.3", True, False),
    ("BKM12-18", "1.3", True, True),
    ("BKM12-19", "1.3", True, True),
    ("BKM12-1.3a", "1.3", True, False),
    ("BKM12-20", "1.3", True, False),
    ("BKM12-21", "1.3", True, False),
    ("BKM12-RemT1", "1.3", True, False),
    ("BKM12-1.4a", "1.4", True, False),
    ("BKM12-22", "1.4", True, False),
    ("BKM12-23", "1.4", True, False),
    ("BKM12-1.5R", "1.5", True, False),
    ("BKM12-24", "1.5", True, False),
    ("BKM12-25", "1.5", True, False),
    ("BKM12-1.5stab", "1.5", True, False),
    ("BKM12-1.5a", "1.5", True, False),
    ("BKM12-26", "1.5", True, False),
    ("BKM12-Sigma_i", "1.5", True, False),
    ("BKM12-crit", "1.5", True, False),
    ("BKM12-Sigma45", "1.5", True, False),
    ("BKM12-Fig3", "1.5", True, False),
    ("BKM12-1.5stab8", "1.5", True, False),
    ("BKM12-Fig2region", "1.5", True, False),
    ("BKM12-27", "1.6", False, False),
    ("BKM12-28", "1.6", False, False),
    ("BKM12-29", "1.6", False, False),
    ("BKM12-30", "1.6", True, False),
    ("BKM12-31", "1.6", True, False),
    ("BKM12-2.1M", "1.6", True, False),
    ("BKM12-32", "1.6", True, False),
    ("BKM12-33", "1.6", True, False),
    ("BKM12-34", "1.6", True, False),
    ("BKM12-35", "1.6", True, False),
    ("BKM12-36", "1.6", True, False),
    ("BKM12-37", "1.6", True, False),
    ("BKM12-Rem2", "1.6", True, False),
    ("BKM12-38", "1.6", True, False),
    ("BKM12-39", "1.7", False, False),
    ("BKM12-40", "1.7", False, False),
    ("BKM12-41", "1.7", True, False),
    ("BKM12-42", "1.7", True, False),
    ("BKM12-2.2", "1.7", True, False),
    ("BKM12-2.3", "1.7", True, True),
    ("BKM12-Rem3", "1.7", False, False),
    ("BKM12-43", "1.8", True, False),
    ("BKM12-44", "1.8", True, False),
    ("BKM12-2.4Rem", "1.8", True, False),
    ("BKM12-45", "1.9", False, False),
    ("BKM12-46", "1.9", False, False),
    ("BKM12-47", "1.9", True, False),
    ("BKM12-48", "1.9", True, True),
    ("BKM12-T2", "1.9", True, False),
    ("BKM12-49", "1.10", True, False),
    ("BKM12-50", "1.10", False, False),
    ("BKM12-51", "1.10", True, False),
    ("BKM12-52", "1.10", True, False),
    ("BKM12-53", "1.10", True, False),
    ("BKM12-54", "1.10", True, False),
    ("BKM12-55", "1.10", True, False),
    ("BKM12-56", "1.11", False, False),
    ("BKM12-2.7a", "1.11", True, False),
    ("BKM12-2.7a-sol", "1.11", True, True),
    ("BKM12-2.7b", "1.11", True, False),
    ("BKM12-2.7c", "1.11", True, False),
    ("BKM12-57", "1.12", True, False),
    ("BKM12-58", "1.12", True, False),
    ("BKM12-3.1", "1.12", True, False),
    ("BKM12-3.2", "1.12", True, False),
    ("BKM12-3.3", "1.12", False, False),
    ("K01-2.1", "2.1", True, False),
    ("K01-2.2", "2.1", True, False),
    ("K01-2.3", "2.1", True, False),
    ("K01-2.4", "2.1", True, False),
    ("K01-2.5", "2.1", True, False),
    ("K01-2.6", "2.1", True, False),
    ("K01-2.7", "2.2", True, False),
    ("K01-2.8", "2.2", True, False),
    ("K01-2.9", "2.2", True, False),
    ("K01-2.10", "2.2", True, False),
    ("K01-2.11", "2.2", True, False),
    ("K01-2.12", "2.2", True, False),
    ("K01-2.13", "2.2", True, False),
    ("K01-2.14", "2.2", True, False),
    ("K01-2.15", "2.2", True, True),
    ("K01-2.16", "2.2", True, True),
    ("K01-2.17", "2.2", True, False),
    ("K01-2.18", "2.2", True, False),
    ("K01-2.19", "2.2", False, False),
    ("K01-2.20", "2.2", False, False),
    ("K01-2.21", "2.2", False, False),
    ("K01-2.22", "2.2", True, False),
    ("K01-2.23", "2.2", True, True),
    ("K01-2.24", "2.2", False, False),
    ("K01-2.25", "2.2", False, False),
    ("K01-2.26", "2.2", True, True),
    ("K01-2.27", "2.2", True, True),
    ("K01-2.28", "2.2", False, False),
    ("K01-2.29", "2.3", True, False),
    ("K01-2.30", "2.3", True, False),
    ("K01-2.31", "2.3", True, False),
    ("K01-2.32", "2.3", True, False),
    ("K01-2.33", "2.3", True, False),
    ("K01-Rem1", "2.3", True, False),
    ("K01-2.34", "2.3", True, False),
    ("K01-2.35", "2.3", False, False),
    ("K01-3.1", "2.4", True, False),
    ("K01-Fig1", "2.4", False, False),
    ("K01-3.2a", "2.4", True, False),
    ("K01-3.2b", "2.4", True, False),
    ("K01-3.2c", "2.4", True, False),
    ("K01-Fig2", "2.4", False, False),
    ("K01-3.2", "2.4", True, True),
    ("K01-3.3", "2.4", True, False),
    ("K01-3.2stab", "2.4", True, False),
    ("K01-3.2y", "2.4", True, False),
    ("K01-Fig3", "2.4", False, False),
    ("K01-3.3seg", "2.4", True, True),
    ("K01-3.4", "2.4", True, True),
    ("K01-3.5", "2.4", True, False),
    ("K01-3.6", "2.4", True, False),
    ("K01-3.7", "2.4", True, False),
    ("K01-Fig4", "2.4", True, False),
    ("K01-Rem2", "2.4", False, False),
    ("K01-Fig6", "2.4", True, False),
    ("K01-Fig6f", "2.4", True, False),
    ("K01-3.3q", "2.4", False, False),
    ("K01-4.1", "2.5", False, False),
    ("K01-4.2", "2.5", True, False),
    ("K01-4.2m", "2.5", True, False),
    ("K01-4.3", "2.5", True, False),
    ("K01-4.4", "2.5", True, False),
    ("K01-Fig7", "2.5", False, False),
    ("BM20-ns", "3", False, False),
    ("BM20-2.1", "3", False, False),
    ("BM20-2.2", "3", True, False),
    ("BM20-d0", "3", False, False),
    ("BM20-2.3", "3", False, False),
    ("BM20-2.4", "3", True, False),
    ("BM20-2.5", "3", True, False),
    ("BM20-2.5int", "3", True, False),
    ("BM20-2.6", "3", True, True),
    ("BM20-2.7", "3", True, False),
    ("BM20-2.8", "3", True, False),
    ("BM20-3.0", "3", False, False),
    ("BM20-3.1", "3", True, False),
    ("BM20-3.2/3.3", "3", True, False),
    ("BM20-3.4", "3", False, False),
    ("BM20-3.5", "3", False, False),
    ("BM20-3.6", "3", True, False),
    ("BM20-map", "3", True, False),
    ("BM20-3.1obs", "3", False, False),
    ("BM20-3.7", "3", True, False),
    ("BM20-3.2rem", "3", True, False),
    ("BM20-Lyap", "3", False, False),
    ("M03-1.1", "4.1", True, False),
    ("M03-1.2", "4.1", True, False),
    ("M03-1.3", "4.1", True, False),
    ("M03-1Y", "4.1", True, False),
    ("M03-1.4", "4.1", True, False),
    ("M03-1.5", "4.1", True, True),
    ("M03-1.6", "4.1", False, False),
    ("M03-1.7", "4.1", True, True),
    ("M03-Rem2", "4.1", False, False),
    ("M03-2.1", "4.2", True, False),
    ("M03-2.2", "4.2", True, True),
    ("M03-2.2rho", "4.2", True, False),
    ("M03-2.3", "4.2", True, False),
    ("M03-2.4", "4.2", True, False),
    ("M03-2.5", "4.2", True, False),
)

#: Section of FORMULAS.md -> (paper and section, the issue that covers it).
SECTIONS: dict[str, tuple[str, int]] = {
    "1.1": ("BKM12 §1.1 ball: equations, integrals, measure", 2),
    "1.2": ("BKM12 §1.2 explicit integration at zero constant of areas", 4),
    "1.3": ("BKM12 §1.3 Theorem 1", 4),
    "1.4": ("BKM12 §1.4 Chaplygin's transformation", 4),
    "1.5": ("BKM12 §1.5 bifurcations, periodic solutions", 4),
    "1.6": ("BKM12 §2.1 spherical support", 3),
    "1.7": ("BKM12 §2.2-2.3 rubber balls, gyrostat in a support", 3),
    "1.8": ("BKM12 §2.4 Proposition 1", 4),
    "1.9": ("BKM12 §2.5 Theorem 2", 4),
    "1.10": ("BKM12 §2.6 Proposition 2", 4),
    "1.11": ("BKM12 §2.7 bifurcations of the support", 4),
    "1.12": ("BKM12 §3 ball along a straight line", 3),
    "2.1": ("K01 §2.1 equations and integrals", 2),
    "2.2": ("K01 §2.2 Hamiltonian form, separation", 4),
    "2.3": ("K01 §2.3 reduction of C != 0 to C = 0", 4),
    "2.4": ("K01 §3 bifurcations, periodic solutions, separatrix, Delta", 4),
    "2.5": ("K01 §4 ball with a gyroscope", 3),
    "3": ("BM20 variable parameters", 3),
    "4.1": ("M03 §1 ball on a surface", 3),
    "4.2": ("M03 §2 body on a sphere", 3),
}


def parse_formulas(text: str) -> list[tuple[str, str, bool, bool]]:
    """Entries of FORMULAS.md: ``(ID, section, checkable, literal FAILED)`` in order.

    An entry is a bullet ``- **ID** ...`` with its continuation lines; it is checkable
    when it says "checked numerically/symbolically" or "FAILED", not when it says only
    "not checkable here".

    Parameters
    ----------
    text : str
        The text of FORMULAS.md.

    Returns
    -------
    list of (str, str, bool, bool)
        ``(ID, section number, checkable, literal reading FAILED)`` per entry.
    """
    items: list[list[str]] = []
    section = ""
    current: list[str] | None = None
    for line in text.splitlines():
        head = re.match(r"^(##|###) (\d+(\.\d+)?)[ .]", line)
        if head:
            section, current = head.group(2), None
            continue
        entry = re.match(r"^- \*\*((BKM12|K01|BM20|M03)-[^*]+)\*\*(.*)", line)
        if entry:
            current = [entry.group(1), section, entry.group(3)]
            items.append(current)
        elif current is not None and line.startswith("  "):
            current[2] += " " + line.strip()
        else:
            current = None
    out = []
    for entry_id, sec, rest in items:
        plain = rest.replace("**", "")
        failed = "FAILED" in plain
        checked = bool(re.search(r"(?<!not )checked (numerically|symbolically)", plain))
        out.append((entry_id, sec, checked or failed, failed))
    return out


_IDS = sorted((e[0] for e in FORMULAS_ENTRIES), key=len, reverse=True)


def covered_entry(claim_id: str) -> str | None:
    """The FORMULAS.md entry a claim ID speaks about (longest prefix at a boundary).

    Parameters
    ----------
    claim_id : str
        A claim ID (``BKM12-4/control-...``, ``K01-2.22a`` ...).

    Returns
    -------
    str or None
        The longest entry ID that is a prefix of ``claim_id`` followed by nothing,
        ``.``, ``/`` or a letter; None when there is none.
    """
    for entry_id in _IDS:
        if claim_id.startswith(entry_id):
            rest = claim_id[len(entry_id) :]
            if not rest or rest[0] in "./" or rest[0].isalpha():
                return entry_id
    return None


@dataclass(frozen=True)
class CoverageRow:
    """One FORMULAS.md entry and the claims that speak about it."""

    id: str
    section: str
    checkable: bool
    literal_failed: bool
    claims: tuple[str, ...]
    literal_claims: tuple[str, ...]

    @property
    def covered(self) -> bool:
        """A claim expected to hold speaks about it (and a /literal one, if FAILED).

        Returns
        -------
        bool
            True for an entry that is not checkable.
        """
        if not self.checkable:
            return True
        return bool(self.claims) and (not self.literal_failed or bool(self.literal_claims))

    @property
    def issue(self) -> int:
        """Number of the project issue the entry's section belongs to.

        Returns
        -------
        int
            From :data:`SECTIONS`.
        """
        return SECTIONS[self.section][1]


def coverage(claims: Iterable[object]) -> list[CoverageRow]:
    """Coverage of every FORMULAS.md entry by the given claims.

    Parameters
    ----------
    claims : iterable of Claim
        Objects with ``id``, ``expected`` and optionally ``covers``.

    Returns
    -------
    list of CoverageRow
        One row per entry of :data:`FORMULAS_ENTRIES`, in the sheet's order.
    """
    holds: dict[str, list[str]] = {}
    literal: dict[str, list[str]] = {}
    for c in claims:
        for entry in getattr(c, "covers", ()):
            holds.setdefault(entry, []).append(c.id)
        entry = covered_entry(c.id)
        if entry is None:
            continue
        if c.id.endswith("/literal"):
            literal.setdefault(entry, []).append(c.id)
        elif c.expected == "holds":
            holds.setdefault(entry, []).append(c.id)
    return [
        CoverageRow(i, s, chk, fail, tuple(holds.get(i, ())), tuple(literal.get(i, ())))
        for i, s, chk, fail in FORMULAS_ENTRIES
    ]
