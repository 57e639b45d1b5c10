"""The text-rewriting emitter of issue 23's start, frozen: the reference for the tree one.

Until the code generation moved into one layer (issue 23, deliverable 3) numerics rewrote the
generated C with regular expressions: ``numerics/batch_source.py``'s ``vector_rhs_source``
turned ``chaplygin_rhs`` into the vector lanes' ``bm_rhs_vec``. It is kept here unchanged
(tests only: the package holds no regular expression over C) so that
``tests/derive/test_emit_sources.py`` can show that the emitter of ``derive/emit`` writes the
same C. Delete this module with that comparison when the written-out text changes on purpose.

(The Taylor coefficients written out for fixed orders, ``numerics/taylor_unroll.py``, were
compared here too until issue 26 changed that text on purpose: divisions by the order and by a
divisor's order 0 became products with reciprocals.)
"""

from __future__ import annotations

import re

#: Functions the vector right-hand side applies lane by lane (batch_map.c BM_LANEWISE): the
#: project's elementary functions (arith/templates/detmath.h) and the exact sqrt, fabs.
_LANEWISE = frozenset(
    {"chaplygin_sin", "chaplygin_cos", "chaplygin_exp", "chaplygin_log", "sqrt", "fabs"}
)


def vector_rhs_source(c_source: str, routine: str = "rhs") -> str | None:
    """``bm_rhs_vec``: the generated ``chaplygin_rhs`` with every double a vector of lanes
    (``routine="rhs_jac"``: ``bm_rhs_jac_vec`` from ``chaplygin_rhs_jac``).

    The emitted function is straight-line code (``const double x = expression;`` and
    ``OUT[i] = expression;``); with GCC's vector types the same text computes every lane with
    the same IEEE operations, libm calls being applied lane by lane. None when the function
    calls anything else (then only the one-point-at-a-time driver is built).

    Parameters
    ----------
    c_source : str
        A model's emitted C source.

    Returns
    -------
    str or None
    """
    head = f"void chaplygin_{routine}(double T, const double *restrict Y, const double *restrict "
    head += "P, "
    start = c_source.find(head)
    if start < 0:
        return None
    open_brace = c_source.index("{", start)
    end = c_source.index("\n}\n", open_brace) + 3
    body = c_source[open_brace:end]
    called = set(re.findall(r"\b([A-Za-z_]\w*)\s*\(", body))
    if not called <= _LANEWISE or re.search(r"\b(int|long|float|if|for|while)\b", body):
        return None
    body = re.sub(r"\bconst double\b", "const bm_vec", body)
    if "double" in body:
        return None
    for name in called:
        body = re.sub(rf"\b{name}\s*\(", f"bm_v_{name}(", body)
    return (
        f"static void bm_{routine}_vec(bm_vec T, const bm_vec *restrict Y, "
        "const bm_vec *restrict P, bm_vec *restrict OUT)\n" + body
    )
