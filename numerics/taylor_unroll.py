"""The Taylor coefficients of a model written out for fixed orders (heyoka's unrolled mode).

The generated C Taylor integrator (``generated/<model>_taylor.c``, template
``derive/templates/taylor.c``) computes the normalised Taylor coefficients in a loop over the
order ``k`` whose convolutions are loops over ``j``. For one order ``p`` everything is known
at compile time: this module writes the loop out, every coefficient of order ``k >= 1`` a
``const`` local (single assignment, as heyoka's LLVM code), the sums in exactly the order of
operations of the template's ``tc_mul``, ``tc_sq``, ``tc_div``, ``tc_pow``, ``tc_exp`` and
``tc_sqrt`` (terms known before order ``k`` first, in increasing ``j``, then the two new
ones), so the written-out code gives **the same bits** as the loop: which of the two runs
changes the speed, never a result. The orders not written out fall back to the loop.

The text transformed is the loop body the emitter writes (``derive/emit/taylor.py``
``_c_lines``): one assignment per line, of a few fixed forms. A line of any other form makes
:func:`unrolled_source` return None (the caller keeps the loop): nothing is guessed.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

__all__ = ["UNROLL_MAX_ORDER", "unrolled_source"]

#: Orders written out at most (cost of the code grows as the order squared: a 57-node model
#: at order 15 is about 100 kB of C and half a second of compiling).
UNROLL_MAX_ORDER = 24

#: Where the template takes the written-out functions (derive/templates/taylor.c).
MARKER = "/* chaplygin: the coefficients written out for fixed orders go here */"

_FUNCTION = "static void taylor_coefficients(int order, REAL T0, const REAL *restrict Y,"
_LOOP = "    for (int k = 0; k < order; ++k) {\n        if (k > 0) {\n"
_ZERO = re.compile(r"for \(int k = 0; k < S; \+\+k\) a(\d+)\[k\] = R_INT\(0\);")
_TIME = re.compile(r"a(\d+)\[0\] = T0; if \(S > 1\) a\d+\[1\] = R_INT\(1\);")
_UPDATE = re.compile(r"a(\d+)\[k \+ 1\] = R_DIV\(a(\d+)\[k\], R_INT\(k \+ 1\)\);")
_ASSIGN = re.compile(r"a(\d+)\[k\] = (.*);")
_MUL = re.compile(r"tc_mul\(a(\d+), a(\d+), k\)")
_SQ = re.compile(r"tc_sq\(a(\d+), k\)")
_DIV = re.compile(r"tc_div\((a(\d+)\[k\]|R_INT\(0\)), a(\d+), a(\d+), k\)")
_POW = re.compile(r"tc_pow\(a(\d+), a(\d+), (-?\d+), (-?\d+), k\)")
_EXP = re.compile(r"tc_exp\(a(\d+), a(\d+), k\)")
_SQRT = re.compile(r"tc_sqrt\(a(\d+), a(\d+), k\)")
_OPERAND = re.compile(r"a(\d+)\[(k|0)\]")
_ORDER0 = re.compile(r"a(\d+)\[0\] = (.*);")
_ORDER0_OPERAND = re.compile(r"a(\d+)\[0\]")
#: what may remain of a line once the recurrences and operands are replaced
_ALLOWED = re.compile(r"^[\sA-Za-z0-9_(),.+\-*/]*$")


class _Unrolled:
    """Writes the order-``k`` coefficients of one order as single assignments."""

    def __init__(self, zero: set[str], time_node: str | None):
        self.zero, self.time_node = zero, time_node

    def ref(self, node: str, k: int) -> str:
        if k == 0:
            return f"a{node}_0"
        if node == self.time_node:
            return "R_INT(1)" if k == 1 else "R_INT(0)"
        if node in self.zero:
            return "R_INT(0)"
        return f"a{node}_{k}"

    def _sum(self, first: str, terms: Iterable[str]) -> str:
        s = first
        for t in terms:
            s = f"R_ADD({s}, {t})"
        return s

    def mul(self, a: str, b: str, k: int) -> str:
        r = self.ref
        last = f"R_ADD(R_MUL({r(a, 0)}, {r(b, k)}), R_MUL({r(a, k)}, {r(b, 0)}))"
        if k < 2:
            return last
        s = self._sum(
            f"R_MUL({r(a, 1)}, {r(b, k - 1)})",
            (f"R_MUL({r(a, j)}, {r(b, k - j)})" for j in range(2, k)),
        )
        return f"R_ADD({s}, {last})"

    def sq(self, a: str, k: int) -> str:
        r = self.ref
        s = f"R_MUL({r(a, 0)}, {r(a, k)})"
        if k >= 3:
            o = self._sum(
                f"R_MUL({r(a, 1)}, {r(a, k - 1)})",
                (f"R_MUL({r(a, j)}, {r(a, k - j)})" for j in range(2, (k + 1) // 2)),
            )
            s = f"R_ADD({o}, {s})"
        s = f"_twice({s})"
        if k % 2 == 0:
            s = f"R_ADD({s}, R_MUL({r(a, k // 2)}, {r(a, k // 2)}))"
        return s

    def div(self, ak: str, b: str, c: str, k: int) -> str:
        r = self.ref
        last = f"R_SUB({ak}, R_MUL({r(b, k)}, {r(c, 0)}))"
        if k < 2:
            return f"R_DIV({last}, {r(b, 0)})"
        s = self._sum(
            f"R_MUL({r(b, 1)}, {r(c, k - 1)})",
            (f"R_MUL({r(b, j)}, {r(c, k - j)})" for j in range(2, k)),
        )
        return f"R_DIV(R_SUB({last}, {s}), {r(b, 0)})"

    def pow(self, a: str, c: str, p: int, q: int, k: int) -> str:
        r = self.ref
        s = self._sum(
            "R_INT(0)",
            (f"R_MUL(R_MUL(R_INT({p * (k - j) - q * j}), {r(a, k - j)}), {r(c, j)})"
             for j in range(k)),
        )
        return f"R_DIV({s}, R_MUL(R_MUL(R_INT({q}), R_INT({k})), {r(a, 0)}))"

    def exp(self, a: str, c: str, k: int) -> str:
        r = self.ref
        s = self._sum(
            "R_INT(0)",
            (f"R_MUL(R_MUL(R_INT({j}), {r(a, j)}), {r(c, k - j)})" for j in range(1, k + 1)),
        )
        return f"R_DIV({s}, R_INT({k}))"

    def sqrt(self, a: str, c: str, k: int) -> str:
        r = self.ref
        s = r(a, k)
        for j in range(1, k):
            s = f"R_SUB({s}, R_MUL({r(c, j)}, {r(c, k - j)}))"
        return f"R_DIV({s}, R_MUL(R_INT(2), {r(c, 0)}))"

    def expression(self, rhs: str, k: int) -> str | None:
        """The right-hand side of a loop-body line at order ``k``, or None if not understood."""
        out = _MUL.sub(lambda m: self.mul(m[1], m[2], k), rhs)
        out = _SQ.sub(lambda m: self.sq(m[1], k), out)
        out = _DIV.sub(
            lambda m: self.div(self.ref(m[2], k) if m[2] else "R_INT(0)", m[3], m[4], k), out
        )
        out = _POW.sub(lambda m: self.pow(m[1], m[2], int(m[3]), int(m[4]), k), out)
        out = _EXP.sub(lambda m: self.exp(m[1], m[2], k), out)
        out = _SQRT.sub(lambda m: self.sqrt(m[1], m[2], k), out)
        if "tc_" in out:
            return None
        out = _OPERAND.sub(lambda m: self.ref(m[1], k if m[2] == "k" else 0), out)
        return out if _ALLOWED.match(out) else None


def _function(source: str) -> tuple[str, list[str], list[str]] | None:
    """(prologue and order-0 text, loop-body lines, update lines) of the
    generated ``taylor_coefficients``; None if the text is not of the emitter's shape."""
    start = source.find(_FUNCTION)
    if start < 0:
        return None
    end = source.find("\n}\n", start)
    loop = source.find(_LOOP, start, end)
    if loop < 0:
        return None
    head = source[source.index("{", start) + 1 : loop]
    rest = source[loop + len(_LOOP) : end].splitlines()
    try:
        close = rest.index("        }")
    except ValueError:
        return None
    body = [line.strip() for line in rest[:close]]
    updates = [line.strip() for line in rest[close + 1 :] if line.strip() != "}"]
    return head, body, updates


def _order_zero_locals(head: str, time_node: str | None) -> str | None:
    """The prologue with every order-0 value also in a ``const`` local ``aN_0`` (kept in a
    register instead of being loaded again for every product); None if a node's order-0
    value is not set by one line ``aN[0] = ...;``."""
    out, defined = [], set()
    for line in head.splitlines():
        stripped = line.strip()
        m = _ORDER0.fullmatch(stripped)
        if time_node is not None and _TIME.fullmatch(stripped):
            line = f"    const REAL a{time_node}_0 = T0; {stripped}"
            defined.add(time_node)
        elif m is not None:
            rhs = _ORDER0_OPERAND.sub(lambda o: f"a{o[1]}_0", m[2])
            line = f"    const REAL a{m[1]}_0 = {rhs}; a{m[1]}[0] = a{m[1]}_0;"
            defined.add(m[1])
        elif _ORDER0_OPERAND.search(stripped) and not stripped.startswith("#"):
            return None
        out.append(line)
    return "\n".join(out) + "\n"


def unrolled_source(source: str, orders: Iterable[int]) -> str | None:
    """``source`` with ``taylor_coefficients`` written out for each of ``orders``.

    Parameters
    ----------
    source : str
        A generated Taylor C source (``ModelCode.taylor_c_source``).
    orders : iterable of int
        Orders to write out (each between 2 and :data:`UNROLL_MAX_ORDER`; others ignored).

    Returns
    -------
    str or None
        The source with the written-out functions and a dispatcher (other orders run the
        loop), or None when ``source`` is not of the shape this module reads or no order is
        in range.
    """
    wanted = sorted({int(p) for p in orders if 2 <= int(p) <= UNROLL_MAX_ORDER})
    if not wanted or MARKER not in source:
        return None
    parts = _function(source)
    if parts is None:
        return None
    head, body, updates = parts
    zero = set(_ZERO.findall(head))
    time = _TIME.search(head)
    time_node = time[1] if time else None
    head = _order_zero_locals(head, time_node)
    if head is None:
        return None
    assigned = []
    for line in body:
        m = _ASSIGN.fullmatch(line)
        if m is None:
            return None
        assigned.append((m[1], m[2]))
    zero -= {n for n, _ in assigned}
    state = []
    for line in updates:
        m = _UPDATE.fullmatch(line)
        if m is None:
            return None
        state.append((m[1], m[2]))
    u = _Unrolled(zero, time_node)
    functions = []
    for p in wanted:
        lines = []
        for k in range(p):
            if k > 0:
                for node, rhs in assigned:
                    expr = u.expression(rhs, k)
                    if expr is None:
                        return None
                    lines.append(f"    const REAL a{node}_{k} = {expr};")
            for node, src in state:
                lines.append(
                    f"    const REAL a{node}_{k + 1} = R_DIV({u.ref(src, k)}, R_INT({k + 1}));"
                )
        stores = [f"    a{node}[{k}] = a{node}_{k};" for node, _ in state for k in range(1, p + 1)]
        functions.append(
            f"static void taylor_coefficients_{p}(REAL T0, const REAL *restrict Y,\n"
            "                                     const REAL *restrict P, REAL *restrict X)\n"
            "{\n"
            f"    const int order = {p};\n"
            + head
            + "\n".join(lines + stores)
            + "\n}\n"
        )
    cases = "\n".join(
        f"    case {p}: taylor_coefficients_{p}(T0, Y, P, X); return;" for p in wanted
    )
    dispatcher = (
        "static void taylor_coefficients_unrolled(int order, REAL T0, const REAL *restrict Y,\n"
        "                                         const REAL *restrict P, REAL *restrict X)\n"
        "{\n"
        "    switch (order) {\n"
        f"{cases}\n"
        "    default: taylor_coefficients(order, T0, Y, P, X);\n"
        "    }\n"
        "}\n"
        "#define TAYLOR_COEFFICIENTS taylor_coefficients_unrolled\n"
    )
    twice = (
        "/* 2 s as the loop writes it (s + s) */\n"
        "#define _twice(s) _twice_of(s)\n"
        "static inline REAL _twice_of(REAL s) { return R_ADD(s, s); }\n"
    )
    inserted = (
        f"/* written out for order(s) {', '.join(map(str, wanted))} by "
        "chaplygin.numerics.taylor_unroll */\n" + twice + "\n".join(functions) + dispatcher
    )
    return source.replace(MARKER, inserted, 1)
