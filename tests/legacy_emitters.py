"""The text-rewriting emitters of issue 23's start, frozen: the reference for the tree ones.

Until the code generation moved into one layer (issue 23, deliverable 3) numerics rewrote the
generated C with regular expressions: ``numerics/taylor_unroll.py`` wrote the Taylor
coefficients out for fixed orders from the loop's text, and ``numerics/batch_source.py``'s
``vector_rhs_source`` turned ``chaplygin_rhs`` into the vector lanes' ``bm_rhs_vec``. They are
kept here unchanged (tests only: the package holds no regular expression over C) so that
``tests/derive/test_emit_sources.py`` can show that the emitters of ``derive/emit`` write the same
C. Delete this module with that comparison when the written-out text changes on purpose.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

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


#: an order-j coefficient in the written-out code
_TOKEN = re.compile(r"\ba(\d+)_(\d+)\b")
#: what a paired line may contain besides its coefficients: the C operators' macros (double:
#: plain operators, which GNU C applies lane by lane to vectors), integers, parameters
_VECTOR_SAFE = re.compile(r"^(?:[\s(),@0-9]|R_ADD|R_SUB|R_MUL|R_DIV|R_NEG|R_INT|_twice|p_\w+)*$")
#: the vector type and the doubling of the squares' sums, for the pairs
VECTOR_PRELUDE = (
    "#define TAYLOR_VREAL 1 /* the state update too, two components at a time */\n"
    "typedef double vreal __attribute__((vector_size(16)));\n"
    "static inline vreal _vtwice(vreal s) { return s + s; }\n"
)


class _Expressions:
    """The written-out right-hand side of every node at every order of one function:
    ``expr[node][k]`` for ``k = 1 .. p - 1`` (state nodes: ``k = 1 .. p``, their update), its
    shape (coefficients replaced by ``@``), the coefficients it reads in order, and the
    node's depth in the computation of one order (which nodes must come before it)."""

    def __init__(self, u: _Unrolled, assigned: list[tuple[str, str]],
                 state: list[tuple[str, str]], p: int):
        self.expr: dict[str, dict[int, str]] = {}
        for node, rhs in assigned:
            self.expr[node] = {}
            for k in range(1, p):
                e = u.expression(rhs, k)
                if e is None:
                    raise ValueError(rhs)
                self.expr[node][k] = e
        for node, src in state:
            self.expr[node] = {
                k: f"R_DIV({u.ref(src, k - 1)}, R_INT({k}))" for k in range(1, p + 1)
            }
        self.shape = {n: tuple(_TOKEN.sub("@", e) for e in es.values())
                      for n, es in self.expr.items()}
        self.tokens = {n: {k: _TOKEN.findall(e) for k, e in es.items()}
                       for n, es in self.expr.items()}
        self.level = {n: 0 for n, _ in state}
        for node, _ in assigned:  # in the order written: operands first
            same_order = {d for d, j in self.tokens[node].get(p - 1, []) if int(j) == p - 1}
            self.level[node] = 1 + max((self.level.get(d, 0) for d in same_order - {node}),
                                       default=0)
        self.state = {n for n, _ in state}
        self.safe = {n: all(_VECTOR_SAFE.match(t) for t in sh) for n, sh in self.shape.items()}
        self._pairs: dict[tuple[str, str], frozenset | None] = {}

    def operand_pairs(self, x: str, y: str) -> frozenset[tuple[str, str]] | None:
        """The node pairs (lane 0, lane 1) met in the operands of ``x`` and ``y`` written side
        by side; None if they cannot share a vector: other expressions, other depths (a pack
        must not wait for itself), a function GNU C does not apply to vectors."""
        key = (x, y)
        if key not in self._pairs:
            self._pairs[key] = self._operand_pairs(x, y)
        return self._pairs[key]

    def _operand_pairs(self, x: str, y: str) -> frozenset[tuple[str, str]] | None:
        if (self.level[x] != self.level[y] or self.shape[x] != self.shape[y]
                or (x in self.state) != (y in self.state) or not self.safe[x]):
            return None
        out = set()
        for k, tx in self.tokens[x].items():
            for (u, i), (v, j) in zip(tx, self.tokens[y][k], strict=True):
                if i != j:
                    return None
                if u != v:
                    out.add((u, v))
        return frozenset(out)


def _pairs(ex: _Expressions, state: list[str]) -> list[tuple[str, str]]:
    """The nodes computed two at a time, one per lane of a vector of 2 doubles.

    Pairs are followed from a pair of state components through the expressions that make
    them (the Chaplygin ball's ``M_i`` and ``gamma_i``: ``M' = M x w`` and
    ``gamma' = gamma x w`` are the same expressions of the same ``w``), the seed that pairs
    the most nodes first, then from the state left; last, the convolutions still alone, two
    of the same expression and depth at a time. Which nodes share a vector changes the
    speed only: every lane does its node's operations in the scalar code's order."""
    paired: dict[str, tuple[str, int]] = {}  # node -> (partner, lane)

    def follow(seed: tuple[str, str], into: dict[str, tuple[str, int]]) -> int:
        todo, added = [seed], 0
        while todo:
            x, y = todo.pop()
            if x == y or x in into or y in into or x not in ex.expr or y not in ex.expr:
                continue  # a shared operand, a node already paired, an order-0 constant
            ops = ex.operand_pairs(x, y)
            if ops is None:
                continue
            into[x], into[y] = (y, 0), (x, 1)
            added += 1
            todo.extend(sorted(ops, reverse=True))
        return added

    seeds = [(x, y) for x in state for y in state if x != y]
    while True:
        best, gain = None, 0
        for seed in seeds:
            trial = dict(paired)
            g = follow(seed, trial)
            if g > gain:
                best, gain = trial, g
        if best is None:
            break
        paired = best
    alone: dict[tuple, list[str]] = {}
    for node, es in ex.expr.items():
        if node not in paired and node not in ex.state and es and \
                es[max(es)].count("R_MUL(") >= 2:
            alone.setdefault((ex.level[node], ex.shape[node]), []).append(node)
    for group in alone.values():
        for x, y in zip(group[::2], group[1::2], strict=False):  # an odd one stays alone
            if ex.operand_pairs(x, y) is not None:
                paired[x], paired[y] = (y, 0), (x, 1)
    return [(x, y) for x, (y, lane) in paired.items() if lane == 0]


def _vector(ex: _Expressions, lane: dict[str, tuple[int, int]], x: str, y: str,
            k: int, gathered: set[str], before: list[str]) -> str:
    """Order ``k`` of the pair (``x``, ``y``): their shared expression with a vector for
    each operand (a pair's vector, else the two coefficients gathered, else the one
    coefficient both lanes read)."""
    parts = _TOKEN.split(ex.expr[x][k])  # text, node, order, text, node, order, ...
    out, shared = [parts[0]], True
    for i, ((u, j), (v, _)) in enumerate(zip(ex.tokens[x][k], ex.tokens[y][k], strict=True)):
        if u == v:
            out.append(f"a{u}_{j}")
        elif lane.get(u, (-1, 1))[1] == 0 and lane.get(v) == (lane[u][0], 1):
            out.append(f"v{lane[u][0]}_{j}")
            shared = False
        else:
            name = f"g{u}x{v}_{j}"
            if name not in gathered:
                gathered.add(name)
                before.append(f"    const vreal {name} = {{a{u}_{j}, a{v}_{j}}};")
            out.append(name)
            shared = False
        out.append(parts[3 * i + 3])
    if shared:  # both lanes the same scalar at this order (a copy of a shared node)
        return f"((vreal){{{ex.expr[x][k]}, {ex.expr[y][k]}}})"
    return "".join(out).replace("_twice(", "_vtwice(")


def _written_out(u: _Unrolled, assigned: list[tuple[str, str]],
                 state: list[tuple[str, str]], p: int, vectors: bool) -> list[str] | None:
    """The single assignments of orders ``0 .. p - 1`` and the state's orders ``1 .. p``;
    with ``vectors``, paired nodes two at a time in a GNU C vector of 2 doubles (a lane of
    a vector operation rounds as the scalar operation: the same bits). None if a line is
    not understood."""
    pairs: list[tuple[str, str]] = []
    if vectors:
        try:
            ex = _Expressions(u, assigned, state, p)
        except ValueError:
            return None
        pairs = _pairs(ex, [n for n, _ in state])
    lane = {n: (i, ln) for i, pair in enumerate(pairs) for ln, n in enumerate(pair)}
    rhs = dict(assigned)
    # one order's nodes, a pair where its later lane was: both lanes' operands come before
    # (equal depths), and by depth so that no pair's operand comes after it
    schedule = [n for n, _ in assigned]
    if pairs:
        schedule = sorted(schedule, key=lambda n: (ex.level[n], schedule.index(n)))
    out = [f"    const vreal v{i}_0 = {{a{x}_0, a{y}_0}};" for i, (x, y) in enumerate(pairs)]

    gathered: set[str] = set()

    def pair_lines(i: int, k: int) -> list[str]:
        x, y = pairs[i]
        before: list[str] = []
        value = _vector(ex, lane, x, y, k, gathered, before)
        return before + [f"    const vreal v{i}_{k} = {value};",
                         f"    const REAL a{x}_{k} = v{i}_{k}[0], a{y}_{k} = v{i}_{k}[1];"]

    for k in range(p):
        if k > 0:
            for node in schedule:
                if node in lane:
                    if lane[node][1] == 0:
                        out += pair_lines(lane[node][0], k)
                    continue
                expr = u.expression(rhs[node], k)
                if expr is None:
                    return None
                out.append(f"    const REAL a{node}_{k} = {expr};")
        for node, src in state:
            if node in lane:
                if lane[node][1] == 0:
                    out += pair_lines(lane[node][0], k + 1)
                continue
            out.append(
                f"    const REAL a{node}_{k + 1} = R_DIV({u.ref(src, k)}, R_INT({k + 1}));"
            )
    return out


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


def _order_zero_locals(head: str, time_node: str | None, state: set[str]) -> str | None:
    """The prologue with every order-0 value in a ``const`` local ``aN_0`` (kept in a
    register instead of being loaded again for every product), stored in ``X`` for the state
    nodes only (the rows the caller reads; the written-out code reads the locals, and a
    constant's higher orders are the literal 0); None if a node's order-0 value is not set
    by one line ``aN[0] = ...;``."""
    out = []
    for line in head.splitlines():
        stripped = line.strip()
        m = _ORDER0.fullmatch(stripped)
        zero = _ZERO.fullmatch(stripped)
        if time_node is not None and _TIME.fullmatch(stripped):
            kept = f" {stripped}" if time_node in state else ""
            line = f"    const REAL a{time_node}_0 = T0;{kept}"
        elif zero is not None:
            if zero[1] not in state:
                continue
        elif m is not None:
            rhs = _ORDER0_OPERAND.sub(lambda o: f"a{o[1]}_0", m[2])
            kept = f" a{m[1]}[0] = a{m[1]}_0;" if m[1] in state else ""
            line = f"    const REAL a{m[1]}_0 = {rhs};{kept}"
        elif _ORDER0_OPERAND.search(stripped) and not stripped.startswith("#"):
            return None
        out.append(line)
    return "\n".join(out) + "\n"


def unrolled_source(source: str, orders: Iterable[int], vectors: bool = True) -> str | None:
    """``source`` with ``taylor_coefficients`` written out for each of ``orders``.

    Parameters
    ----------
    source : str
        A generated Taylor C source (``ModelCode.taylor_c_source``).
    orders : iterable of int
        Orders to write out (each between 2 and :data:`UNROLL_MAX_ORDER`; others ignored).
    vectors : bool, default True
        Also write the functions with paired nodes computed two at a time in GNU C vectors
        of 2 doubles (taken by compilers that define ``__GNUC__``: gcc, clang; the scalar
        functions otherwise). Double only: the vector type is of doubles.

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
    head = _order_zero_locals(head, time_node, {n for n, _ in state})
    if head is None:
        return None
    u = _Unrolled(zero, time_node)
    def function(p: int, lines: list[str]) -> str:
        stores = [f"    a{node}[{k}] = a{node}_{k};" for node, _ in state for k in range(1, p + 1)]
        return (
            f"static void taylor_coefficients_{p}(REAL T0, const REAL *restrict Y,\n"
            "                                     const REAL *restrict P, REAL *restrict X)\n"
            "{\n"
            f"    const int order = {p};\n"
            + head
            + "\n".join(lines + stores)
            + "\n}\n"
        )

    functions = []
    for p in wanted:
        scalar = _written_out(u, assigned, state, p, vectors=False)
        paired = _written_out(u, assigned, state, p, vectors=True) if vectors else scalar
        if scalar is None or paired is None:
            return None
        if paired == scalar:
            functions.append(function(p, scalar))
        else:
            functions.append("#if defined(__GNUC__)\n" + function(p, paired)
                             + "#else\n" + function(p, scalar) + "#endif\n")
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
    prelude = ""
    if any(f.startswith("#if defined(__GNUC__)") for f in functions):
        prelude = "#if defined(__GNUC__)\n" + VECTOR_PRELUDE + "#endif\n"
    inserted = prelude + (
        f"/* written out for order(s) {', '.join(map(str, wanted))} by "
        "chaplygin.numerics.taylor_unroll */\n" + twice + "\n".join(functions) + dispatcher
    )
    return source.replace(MARKER, inserted, 1)


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
