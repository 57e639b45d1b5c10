"""Plain-text math of ``FORMULAS.md`` as LaTeX (claims' statements in the report and in
a notebook's display of a verdict)."""

from __future__ import annotations

import re

__all__ = ["plain_to_latex"]

_GREEK = [
    "alpha",
    "beta",
    "gamma",
    "delta",
    "omega",
    "Omega",
    "lambda",
    "mu",
    "nu",
    "rho",
    "sigma",
    "phi",
    "psi",
    "Psi",
    "Phi",
    "Delta",
    "Sigma",
    "tau",
    "theta",
    "xi",
    "kappa",
]
_KEEP = {"sqrt", "const", "diag"}
_GREEK_RE = re.compile(r"\b(" + "|".join(_GREEK) + r")\b")


def plain_to_latex(text: str) -> str:
    """Render the plain-text math of ``FORMULAS.md`` as inline LaTeX (best effort).

    Greek names become letters, ``x`` between operands becomes ``\\times``, ``^-1/2`` and
    similar exponents are braced, ``sqrt(...)`` becomes ``\\sqrt{...}`` and ``'`` marks
    stay time derivatives.

    Parameters
    ----------
    text : str
        A statement in the plain notation of FORMULAS.md.

    Returns
    -------
    str
        The same statement as inline LaTeX (no surrounding ``$``).
    """
    s = text
    s = re.sub(r"sqrt\(([^()]*(?:\([^()]*\)[^()]*)*)\)", r"\\sqrt{\1}", s)
    s = re.sub(r"\^\(([^()]*)\)", r"^{\1}", s)
    s = re.sub(r"\^(-?[0-9.]+(?:/[0-9]+)?)", r"^{\1}", s)
    s = re.sub(r"(?<=[\w)\]}]) x (?=[\w(\\])", r" \\times ", s)
    s = _GREEK_RE.sub(lambda m: "\\" + m.group(1) + " ", s)
    s = s.replace("Id", r"\mathrm{Id}")
    # runs of plain words (not commands, not one- or two-letter symbols) become text
    s = re.sub(
        r"(?<![\\\w])((?:[A-Za-z]{3,}|is|it|of|on|in|or|as|by)"
        r"(?:[ :;,]+(?:[A-Za-z]{2,}|a))*)(?![\w{])",
        lambda m: m.group(0) if m.group(1) in _KEEP else r"\text{" + m.group(1) + "}",
        s,
    )
    s = s.replace("<=", r"\le ").replace(">=", r"\ge ").replace("!=", r"\ne ")
    return s.replace("\\ ,", "\\,")
