"""The Taylor coefficients of a model written out for fixed orders (heyoka's unrolled mode).

The generated C Taylor integrator (``generated/<model>_taylor.c``, :mod:`.taylor_c`) computes
the normalised Taylor coefficients in a loop over the order ``k`` whose convolutions are
loops over ``j``. For one order ``p`` everything is known at compile time: this module
writes the loop out from the model's :class:`~.taylor_c.PrintedProgram` (its nodes as data,
``generated/<model>_taylor_program.json``), every coefficient of order ``k >= 1`` a
``const`` local (single assignment, as heyoka's LLVM code), the sums in exactly the order of
operations of the template's ``tc_mul``, ``tc_sq``, ``tc_div``, ``tc_pow``, ``tc_exp`` and
``tc_sqrt`` (terms known before order ``k`` first, in increasing ``j``, then the two new
ones), so the written-out code gives **the same bits** as the loop: which of the two runs
changes the speed, never a result. The orders not written out fall back to the loop.

Each written-out value is an expression tree (:class:`_Tree`: a coefficient, an integer, or
one of the template's ``R_*`` operations on trees) built from the node's operation, then
printed; nothing is read back from C text. The trees also say which nodes can share a
vector: nodes of the same expression and depth are computed **two at a time** in a GNU C
vector of 2 doubles (``vreal``, the SSE2/NEON register; the double kind's ``R_ADD`` ...
``R_NEG`` are plain C operators, which GNU C applies lane by lane). The pairs are found by
following a pair of state components through the expressions that make them (the Chaplygin
ball's ``M' = M x w`` and ``gamma' = gamma x w`` are the same expressions of the same
``w``), then the convolutions left two by two. A lane does its node's operations in the
scalar order, and a vector operation rounds each lane as the scalar operation would (no FMA:
the library is compiled with ``-ffp-contract=off``), so the pairs too give **the same
bits**; they halve the multiplications of the paired convolutions (the ball at order 15:
2610 -> 1572). The scalar functions are kept for compilers without GNU C vectors
(``#if defined(__GNUC__)``).
"""

from __future__ import annotations

from collections.abc import Iterable

from .taylor_c import (
    PrintedNode,
    PrintedProgram,
    order_zero,
    prologue_lines,
    reciprocal_lines,
)

__all__ = ["UNROLL_MAX_ORDER", "MARKER", "VECTOR_PRELUDE", "unrolled_source"]

#: Orders written out at most (cost of the code grows as the order squared: a 57-node model
#: at order 15 is about 100 kB of C and half a second of compiling).
UNROLL_MAX_ORDER = 24

#: Where the template takes the written-out functions (derive/templates/taylor.c).
MARKER = "/* chaplygin: the coefficients written out for fixed orders go here */"

#: the vector type and the doubling of the squares' sums, for the pairs
VECTOR_PRELUDE = (
    "#define TAYLOR_VREAL 1 /* the state update too, two components at a time */\n"
    "typedef double vreal __attribute__((vector_size(16)));\n"
    "static inline vreal _vtwice(vreal s) { return s + s; }\n"
)

# ---------------------------------------------------------------------------- trees

#: A tree: ("a", node, k) the order-k coefficient of a node (node names are the decimal
#: indices, as in the C names ``a<node>_<k>``), ("n", i) the integer ``R_INT(i)``, or
#: ("f", name, args) the template operation ``name`` on trees.
_Tree = tuple

#: the operations GNU C applies lane by lane to vectors (the double kind's C operators)
_LANEWISE = frozenset({"R_ADD", "R_SUB", "R_MUL", "R_DIV", "R_DIV_INT", "R_NEG", "_twice"})


def _f(name: str, *args: _Tree) -> _Tree:
    return ("f", name, args)


def _n(value: int) -> _Tree:
    return ("n", value)


def _div_int(a: _Tree, i: int) -> _Tree:
    """``a / i`` for a positive integer ``i``: the template's ``R_DIV_INT`` (times the
    reciprocal in double and binary128)."""
    return _f("R_DIV_INT", a, ("i", i))


class _Printed:
    """A tree printed once: its C text with a hole ``{}`` for every coefficient (``{t}`` for
    the name of the doubling), the coefficients in the holes' order, whether GNU C vectors
    compute it (lane-wise operations on coefficients and non-negative integers) and its
    number of products.

    Two trees print to the same ``template`` exactly when they are the same expression of
    possibly other coefficients (their shape)."""

    __slots__ = ("template", "leaves", "lanewise", "products")

    def __init__(self, tree: _Tree):
        parts: list[str] = []
        self.leaves: list[tuple[str, int]] = []
        self.lanewise, self.products = True, 0
        self._walk(tree, parts)
        self.template = "".join(parts)

    def _walk(self, tree: _Tree, parts: list[str]) -> None:
        kind = tree[0]
        if kind == "a":
            parts.append("{}")
            self.leaves.append((tree[1], tree[2]))
        elif kind == "n":
            parts.append(f"R_INT({tree[1]})")
        elif kind == "i":  # the positive integer operand of R_DIV_INT, as C text
            parts.append(str(tree[1]))
            self.lanewise = self.lanewise and tree[1] >= 0
        else:
            name = tree[1]
            self.lanewise = self.lanewise and name in _LANEWISE
            self.products += name == "R_MUL"
            parts.append("{t}(" if name == "_twice" else name + "(")
            for i, arg in enumerate(tree[2]):
                if i:
                    parts.append(", ")
                self._walk(arg, parts)
            parts.append(")")

    def text(self, names: list[str] | None = None, twice: str = "_twice") -> str:
        """The C text, the coefficients named ``names`` (default ``a<node>_<k>``)."""
        if names is None:
            names = [f"a{node}_{k}" for node, k in self.leaves]
        return self.template.format(*names, t=twice)


# ---------------------------------------------------------------------------- recurrences


def _mul(a: _Tree, b: _Tree) -> _Tree:
    return _f("R_MUL", a, b)


class _Unrolled:
    """The order-``k`` coefficient of every node of one program as a tree."""

    def __init__(self, printed: PrintedProgram):
        self.nodes = {str(i): node for i, node in enumerate(printed.nodes)}
        # constants and the time: their higher orders are the literals 0 (the time's first 1)
        self.zero = {n for n, node in self.nodes.items() if node.op in ("const", "time")}
        self.time_node = next((n for n, node in self.nodes.items() if node.op == "time"), None)

    def ref(self, node: str, k: int) -> _Tree:
        if k == 0:
            return ("a", node, 0)
        if node == self.time_node:
            return _n(1 if k == 1 else 0)
        if node in self.zero:
            return _n(0)
        return ("a", node, k)

    def _sum(self, first: _Tree, terms: Iterable[_Tree]) -> _Tree:
        s = first
        for t in terms:
            s = _f("R_ADD", s, t)
        return s

    def mul(self, a: str, b: str, k: int) -> _Tree:
        r = self.ref
        last = _f("R_ADD", _mul(r(a, 0), r(b, k)), _mul(r(a, k), r(b, 0)))
        if k < 2:
            return last
        s = self._sum(_mul(r(a, 1), r(b, k - 1)), (_mul(r(a, j), r(b, k - j)) for j in range(2, k)))
        return _f("R_ADD", s, last)

    def sq(self, a: str, k: int) -> _Tree:
        r = self.ref
        s = _mul(r(a, 0), r(a, k))
        if k >= 3:
            o = self._sum(
                _mul(r(a, 1), r(a, k - 1)),
                (_mul(r(a, j), r(a, k - j)) for j in range(2, (k + 1) // 2)),
            )
            s = _f("R_ADD", o, s)
        s = _f("_twice", s)
        if k % 2 == 0:
            s = _f("R_ADD", s, _mul(r(a, k // 2), r(a, k // 2)))
        return s

    def div(self, ak: _Tree, b: str, c: str, k: int) -> _Tree:
        r = self.ref
        last = _f("R_SUB", ak, _mul(r(b, k), r(c, 0)))
        inverse = ("a", f"{c}r", 0)  # 1 / b_0 (taylor_c.reciprocal_lines)
        if k < 2:
            return _mul(last, inverse)
        s = self._sum(_mul(r(b, 1), r(c, k - 1)), (_mul(r(b, j), r(c, k - j)) for j in range(2, k)))
        return _mul(_f("R_SUB", last, s), inverse)

    def pow(self, a: str, c: str, p: int, q: int, k: int) -> _Tree:
        r = self.ref
        terms = (_mul(_mul(_n(p * (k - j) - q * j), r(a, k - j)), r(c, j)) for j in range(k))
        return _f("R_DIV", self._sum(_n(0), terms), _mul(_mul(_n(q), _n(k)), r(a, 0)))

    def exp(self, a: str, c: str, k: int) -> _Tree:
        r = self.ref
        terms = (_mul(_mul(_n(j), r(a, j)), r(c, k - j)) for j in range(1, k + 1))
        return _div_int(self._sum(_n(0), terms), k)

    def sqrt(self, a: str, c: str, k: int) -> _Tree:
        r = self.ref
        s = r(a, k)
        for j in range(1, k):
            s = _f("R_SUB", s, _mul(r(c, j), r(c, k - j)))
        return _f("R_DIV", s, _mul(_n(2), r(c, 0)))

    def expression(self, x: str, k: int) -> _Tree:
        """The order-``k`` coefficient (``k >= 1``) of the operation node ``x``."""
        node: PrintedNode = self.nodes[x]
        op, r = node.op, self.ref
        a = [str(i) for i in node.args]
        if op in ("add", "sub"):
            return _f("R_ADD" if op == "add" else "R_SUB", r(a[0], k), r(a[1], k))
        if op == "neg":
            return _f("R_NEG", r(a[0], k))
        if op == "addc":
            return r(a[0], k)
        if op == "mulc":
            return _mul(r(a[0], k), r(a[1], 0))
        if op == "mul":
            return self.mul(a[0], a[1], k)
        if op == "sq":
            return self.sq(a[0], k)
        if op in ("div", "cdiv"):
            return self.div(r(a[0], k) if op == "div" else _n(0), a[1], x, k)
        if op == "sqrt":
            return self.sqrt(a[0], x, k)
        if op == "pow":
            return self.pow(a[0], x, node.power[0], node.power[1], k)
        if op == "exp":
            return self.exp(a[0], x, k)
        if op in ("sin", "cos"):
            s = self.exp(a[0], a[1], k)
            return s if op == "sin" else _f("R_NEG", s)
        raise ValueError(f"no written-out recurrence for the operation {op!r}")


# ---------------------------------------------------------------------------- pairs


class _Expressions:
    """The written-out right-hand side of every node at every order of one function:
    ``expr[node][k]`` (printed) for ``k = 1 .. p - 1`` (state nodes: ``k = 1 .. p``, their
    update), its shape, the coefficients it reads in order, and the node's depth in the
    computation of one order (which nodes must come before it)."""

    def __init__(self, u: _Unrolled, assigned: list[str], state: list[tuple[str, str]], p: int):
        self.expr: dict[str, dict[int, _Printed]] = {}
        for node in assigned:
            self.expr[node] = {k: _Printed(u.expression(node, k)) for k in range(1, p)}
        for node, src in state:
            self.expr[node] = {k: _Printed(_div_int(u.ref(src, k - 1), k))
                               for k in range(1, p + 1)}
        self.shape = {n: tuple(e.template for e in es.values()) for n, es in self.expr.items()}
        self.tokens = {n: {k: e.leaves for k, e in es.items()} for n, es in self.expr.items()}
        self.level = {n: 0 for n, _ in state}
        for node in assigned:  # in the program's order: operands first
            same_order = {d for d, j in self.tokens[node].get(p - 1, []) if j == p - 1}
            self.level[node] = 1 + max((self.level.get(d, 0) for d in same_order - {node}),
                                       default=0)
        self.state = {n for n, _ in state}
        self.safe = {n: all(e.lanewise for e in es.values()) for n, es in self.expr.items()}
        self._pairs: dict[tuple[str, str], frozenset | None] = {}

    def operand_pairs(self, x: str, y: str) -> frozenset[tuple[str, str]] | None:
        """The node pairs (lane 0, lane 1) met in the operands of ``x`` and ``y`` written side
        by side; None if they cannot share a vector: other expressions, other depths (a pack
        must not wait for itself), an operation GNU C does not apply to vectors."""
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
    speed only: every lane does its node's operations in the scalar code's order. (Node
    names are compared as text, ``"10" < "9"``: the order the pairs were always found in.)"""
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
        if node not in paired and node not in ex.state and es and es[max(es)].products >= 2:
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
    names, shared = [], True
    for (u, j), (v, _) in zip(ex.tokens[x][k], ex.tokens[y][k], strict=True):
        if u == v:
            names.append(f"a{u}_{j}")
            continue
        shared = False
        if lane.get(u, (-1, 1))[1] == 0 and lane.get(v) == (lane[u][0], 1):
            names.append(f"v{lane[u][0]}_{j}")
            continue
        name = f"g{u}x{v}_{j}"
        if name not in gathered:
            gathered.add(name)
            before.append(f"    const vreal {name} = {{a{u}_{j}, a{v}_{j}}};")
        names.append(name)
    if shared:  # both lanes the same scalar at this order (a copy of a shared node)
        return f"((vreal){{{ex.expr[x][k].text()}, {ex.expr[y][k].text()}}})"
    return ex.expr[x][k].text(names, twice="_vtwice")


# ---------------------------------------------------------------------------- functions


def _written_out(ex: _Expressions, assigned: list[str], state: list[tuple[str, str]], p: int,
                 vectors: bool) -> list[str]:
    """The single assignments of orders ``0 .. p - 1`` and the state's orders ``1 .. p``;
    with ``vectors``, paired nodes two at a time in a GNU C vector of 2 doubles (a lane of
    a vector operation rounds as the scalar operation: the same bits)."""
    pairs = _pairs(ex, [n for n, _ in state]) if vectors else []
    lane = {n: (i, ln) for i, pair in enumerate(pairs) for ln, n in enumerate(pair)}
    # one order's nodes, a pair where its later lane was: both lanes' operands come before
    # (equal depths), and by depth so that no pair's operand comes after it
    schedule = list(assigned)
    if pairs:
        position = {n: i for i, n in enumerate(assigned)}
        schedule = sorted(schedule, key=lambda n: (ex.level[n], position[n]))
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
                out.append(f"    const REAL a{node}_{k} = {ex.expr[node][k].text()};")
        for node, _ in state:
            if node in lane:
                if lane[node][1] == 0:
                    out += pair_lines(lane[node][0], k + 1)
                continue
            out.append(f"    const REAL a{node}_{k + 1} = {ex.expr[node][k + 1].text()};")
    return out


def _order_zero_locals(printed: PrintedProgram) -> list[str]:
    """Every order-0 value in a ``const`` local ``aN_0`` (kept in a register instead of
    being loaded again for every product), stored in ``X`` for the state nodes only (the
    rows the caller reads; the written-out code reads the locals, and a constant's higher
    orders are the literal 0)."""
    out = []
    for i, node in enumerate(printed.nodes):
        if node.op == "var":
            out.append(f"    const REAL a{i}_0 = Y[{node.index}]; a{i}[0] = a{i}_0;")
        elif node.op == "time":
            out.append(f"    const REAL a{i}_0 = T0;")
        elif node.op == "const":
            out += ["#ifdef R_OPERATORS", f"    const REAL a{i}_0 = {node.c};", "#else",
                    f"    const REAL a{i}_0 = {node.c_macros};", "#endif"]  # fmt: skip
        else:
            out.append(f"    const REAL a{i}_0 = {order_zero(node, lambda j: f'a{j}_0')};")
    return out


def _function(printed: PrintedProgram, state: list[tuple[str, str]], p: int,
              lines: list[str]) -> str:
    """``taylor_coefficients_<p>``: the prologue, the order-0 locals, ``lines`` and the
    stores of the state's coefficients."""
    head = ["", *prologue_lines(printed), *_order_zero_locals(printed),
            *reciprocal_lines(printed, lambda j: f"a{j}_0")]
    stores = [f"    a{node}[{k}] = a{node}_{k};" for node, _ in state for k in range(1, p + 1)]
    return (
        f"static void taylor_coefficients_{p}(REAL T0, const REAL *restrict Y,\n"
        "                                     const REAL *restrict P, REAL *restrict X)\n"
        "{\n"
        f"    const int order = {p};\n"
        + "\n".join(head) + "\n"
        + "\n".join(lines + stores)
        + "\n}\n"
    )


def _dispatcher(wanted: list[int]) -> str:
    cases = "\n".join(
        f"    case {p}: taylor_coefficients_{p}(T0, Y, P, X); return;" for p in wanted
    )
    return (
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


def unrolled_source(source: str, program: PrintedProgram | str, orders: Iterable[int],
                    vectors: bool = True) -> str | None:
    """``source`` with ``taylor_coefficients`` written out for each of ``orders``.

    Parameters
    ----------
    source : str
        The model's generated Taylor C source (``generated/<model>_taylor.c``), with the
        template's :data:`MARKER` where the written-out functions go.
    program : PrintedProgram or str
        The model's printed program (or its JSON text, ``<model>_taylor_program.json``).
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
        loop), or None when ``source`` has no :data:`MARKER` or no order is in range.

    Raises
    ------
    ValueError
        ``program`` is not a printed program's JSON, or has an operation with no
        written-out recurrence.
    """
    wanted = sorted({int(p) for p in orders if 2 <= int(p) <= UNROLL_MAX_ORDER})
    if not wanted or MARKER not in source:
        return None
    printed = PrintedProgram.from_json(program) if isinstance(program, str) else program
    u = _Unrolled(printed)
    assigned = [n for n, node in u.nodes.items() if node.op not in ("var", "time", "const")]
    state = [(str(i), str(o)) for i, o in enumerate(printed.outputs)]
    functions = []
    for p in wanted:
        ex = _Expressions(u, assigned, state, p)
        scalar = _written_out(ex, assigned, state, p, vectors=False)
        paired = _written_out(ex, assigned, state, p, vectors=True) if vectors else scalar
        if paired == scalar:
            functions.append(_function(printed, state, p, scalar))
        else:
            functions.append("#if defined(__GNUC__)\n" + _function(printed, state, p, paired)
                             + "#else\n" + _function(printed, state, p, scalar) + "#endif\n")
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
        "chaplygin.derive.emit.taylor_unroll */\n" + twice + "\n".join(functions)
        + _dispatcher(wanted)
    )
    return source.replace(MARKER, inserted, 1)
