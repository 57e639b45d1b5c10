"""The Taylor program in C on Arb balls and first-order jets, for the validated integrator.

:func:`taylor_arb_source` prints a model's printed Taylor program
(:class:`~chaplygin.derive.emit.taylor_c.PrintedProgram`, the ``*_taylor_program.json`` of
``generated/`` or of the first-use cache) into the template ``templates/taylor_arb.c``: the
recurrences of the Python module (``*_taylor.py``) as they run on
:class:`~chaplygin.numerics.validated.jets.ArbJet` numbers, each operation an in-place Arb
call (FLINT 3) on the value and on each gradient component. The source is emitted when the
validated integrator first needs it (it is not part of ``generated/``): its only input is the
program, which ``chaplygin derive --check`` keeps in sync.

A node carries a gradient when it depends on the state (``var`` nodes, and every node with
such an argument); constants, the time and what depends only on them keep none, so their
series cost one ball per coefficient whatever the number of seeds.
"""

from __future__ import annotations

import re
from importlib import resources

from .taylor_c import PrintedProgram

__all__ = ["TAYLOR_ARB_TEMPLATE", "taylor_arb_source"]

TAYLOR_ARB_TEMPLATE = "taylor_arb.c"

_TOKEN = re.compile(r"\s*(?:(?P<name>[A-Za-z_][A-Za-z_0-9]*)|(?P<int>-?\d+)|(?P<punct>[(),]))")
_CALLS = {
    "R_ADD": ("arb_add", 2),
    "R_SUB": ("arb_sub", 2),
    "R_MUL": ("arb_mul", 2),
    "R_DIV": ("arb_div", 2),
    "R_POW": ("arb_pow", 2),
    "R_NEG": ("neg", 1),
    "R_SQRT": ("arb_sqrt", 1),
    "R_EXP": ("arb_exp", 1),
    "R_SIN": ("sin", 1),
    "R_COS": ("cos", 1),
    "R_INT": ("int", 1),
}


def _parse(text: str) -> tuple:
    """The tree of a constant in the template's ``R_*`` macros (``PrintedNode.c_macros``):
    ``("name", "p_x")``, ``("int", n)``, ``("pi",)`` or ``(macro, *arguments)``; the text is
    only tokenised, never run."""
    tokens: list[tuple[str, str]] = []
    pos = 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None or match.end() == pos:
            if text[pos:].strip() == "":
                break
            raise ValueError(f"not a constant of the R_* macros: {text!r}")
        kind = match.lastgroup or ""
        tokens.append((kind, match.group(kind)))
        pos = match.end()

    def expr(i: int) -> tuple[tuple, int]:
        kind, value = tokens[i]
        if kind == "int":
            return ("int", int(value)), i + 1
        if kind != "name":
            raise ValueError(f"unexpected {value!r} in {text!r}")
        if value == "R_PI":
            return ("pi",), i + 1
        if value not in _CALLS:
            return ("name", value), i + 1
        if tokens[i + 1] != ("punct", "("):
            raise ValueError(f"{value} without arguments in {text!r}")
        args, i = [], i + 2
        while True:
            arg, i = expr(i)
            args.append(arg)
            if tokens[i] == ("punct", ")"):
                break
            if tokens[i] != ("punct", ","):
                raise ValueError(f"unexpected {tokens[i][1]!r} in {text!r}")
            i += 1
        if len(args) != _CALLS[value][1]:
            raise ValueError(f"{value} takes {_CALLS[value][1]} arguments in {text!r}")
        return (value, *args), i + 1

    try:
        tree, end = expr(0)
    except IndexError:
        raise ValueError(f"not a constant of the R_* macros: {text!r}") from None
    if end != len(tokens):
        raise ValueError(f"trailing text in {text!r}")
    return tree


class _ConstPrinter:
    """A constant's tree as in-place Arb calls into a target ball, with temporaries
    ``w->c + d`` (``d`` the nesting depth); every operation rounded at the run's precision."""

    def __init__(self, params: tuple[str, ...]):
        self._index = {f"p_{name}": i for i, name in enumerate(params)}
        self.depth = 0

    def lines(self, tree: tuple, target: str) -> list[str]:
        out: list[str] = []
        self._emit(tree, target, 0, out)
        return out

    def _tmp(self, d: int) -> str:
        self.depth = max(self.depth, d + 1)
        return f"w->c + {d}"

    def _emit(self, tree: tuple, target: str, d: int, out: list[str]) -> None:
        head = tree[0]
        if head == "name":
            if tree[1] not in self._index:
                raise ValueError(f"unknown parameter {tree[1]!r}")
            out.append(f"arb_set({target}, w->P[{self._index[tree[1]]}]);")
        elif head == "int":
            n = tree[1]
            if not abs(n) < 2**62:
                raise ValueError(f"integer {n} too large for arb_set_si")
            out.append(f"arb_set_si({target}, {n}L);")
        elif head == "pi":
            out.append(f"arb_const_pi({target}, PREC);")
        elif head == "R_INT":
            self._emit(tree[1], target, d, out)
        elif head in ("R_NEG", "R_SQRT", "R_EXP", "R_SIN", "R_COS"):
            self._emit(tree[1], target, d, out)
            if head == "R_NEG":
                out.append(f"arb_neg({target}, {target});")
            elif head in ("R_SIN", "R_COS"):
                t = self._tmp(d)
                pair = f"{target}, {t}" if head == "R_SIN" else f"{t}, {target}"
                out.append(f"arb_set({t}, {target}); arb_sin_cos({pair}, {t}, PREC);")
            else:
                out.append(f"{_CALLS[head][0]}({target}, {target}, PREC);")
        else:
            self._emit(tree[1], target, d, out)
            t = self._tmp(d)
            self._emit(tree[2], t, d + 1, out)
            out.append(f"{_CALLS[head][0]}({target}, {target}, {t}, PREC);")


def _gradients(prog: PrintedProgram) -> list[bool]:
    """Which nodes depend on the state (carry a gradient)."""
    has: list[bool] = []
    for node in prog.nodes:
        if node.op == "var":
            has.append(True)
        elif node.op in ("time", "const"):
            has.append(False)
        elif node.op in ("sin", "cos"):
            has.append(has[node.args[0]])
        else:
            has.append(any(has[a] for a in node.args))
    return has


def _node_lines(prog: PrintedProgram, printer: _ConstPrinter) -> tuple[list[str], list[str]]:
    """(order 0, order k >= 1) statements of every node."""
    g = [int(x) for x in _gradients(prog)]
    zero: list[str] = []
    body: list[str] = []
    fn0 = {"sqrt": "F_SQRT", "exp": "F_EXP", "sin": "F_SIN", "cos": "F_COS"}
    for x, node in enumerate(prog.nodes):
        op, ar = node.op, node.args
        if op == "var":
            zero.append(f"arb_set(V({x}, 0), Y[{node.index}]);")
            zero.append(
                f"for (c = 0; c < w->m; ++c) arb_set(G({x}, c, 0), YG[{node.index} * w->m + c]);"
            )
        elif op == "time":
            zero.append(f"arb_set(V({x}, 0), T0); if (w->S > 1) arb_one(V({x}, 1));")
        elif op == "const":
            zero.extend(printer.lines(_parse(node.c_macros or ""), f"V({x}, 0)"))
        elif op in ("add", "sub", "neg"):
            s = 1 if op == "add" else -1
            b, gb = (ar[1], g[ar[1]]) if op != "neg" else (-1, 0)
            for k, out in (("0", zero), ("k", body)):
                out.append(f"j_lin(w, {x}, {ar[0]}, {b}, {s}, {k}, {g[ar[0]]}, {gb});")
        elif op == "addc":
            zero.append(f"j_lin(w, {x}, {ar[0]}, {ar[1]}, 1, 0, {g[ar[0]]}, 0);")
            body.append(f"j_lin(w, {x}, {ar[0]}, -1, 1, k, {g[ar[0]]}, 0);")
        elif op == "mulc":
            for k, out in (("0", zero), ("k", body)):
                out.append(f"j_scale(w, {x}, {ar[0]}, {ar[1]}, {k}, {g[ar[0]]});")
        elif op in ("mul", "sq"):
            b = ar[1] if op == "mul" else ar[0]
            zero.append(f"j_mul0(w, {x}, {ar[0]}, {b}, {g[ar[0]]}, {g[b]});")
            body.append(f"j_conv(w, {ar[0]}, {b}, 0, k, k, 0, {g[ar[0]]}, {g[b]});")
            body.append(f"j_store(w, {x}, k, {g[x]});")
        elif op in ("div", "cdiv"):
            a, b = ar
            zero.append(f"j_div0(w, {x}, {a}, {b}, {g[a]}, {g[b]});")
            body.append(f"j_conv(w, {b}, {x}, 1, k, k, 0, {g[b]}, {g[x]});")
            body.append(f"j_from(w, {a if op == 'div' else -1}, k, {g[a]}, {g[x]});")
            body.append(f"j_divisor(w, {b}, 1, {g[b]});")
            body.append(f"j_div_store(w, {x}, k, {g[x]}, {g[b]});")
        elif op == "sqrt":
            a = ar[0]
            zero.append(f"j_fn0(w, {x}, {a}, F_SQRT, 0, 1, {g[a]});")
            body.append(f"j_conv(w, {x}, {x}, 1, k - 1, k, 0, {g[x]}, {g[x]});")
            body.append(f"j_from(w, {a}, k, {g[a]}, {g[x]});")
            body.append(f"j_divisor(w, {x}, 2, {g[x]});")
            body.append(f"j_div_store(w, {x}, k, {g[x]}, {g[x]});")
        elif op == "pow":
            p, q = node.power or (1, 1)
            zero.append(f"j_fn0(w, {x}, {ar[0]}, F_POW, {p}L, {q}L, {g[ar[0]]});")
            body.append(f"j_pow(w, {x}, {ar[0]}, {p}L, {q}L, k, {g[ar[0]]});")
        elif op in ("exp", "sin", "cos"):
            a = ar[0]
            partner = x if op == "exp" else ar[1]
            zero.append(f"j_fn0(w, {x}, {a}, {fn0[op]}, 0, 1, {g[a]});")
            body.append(f"j_conv(w, {a}, {partner}, 1, k, k, 1, {g[a]}, {g[partner]});")
            if op == "cos":
                body.append(f"j_from(w, -1, k, 0, {g[x]});")
            body.append(f"j_div_k(w, {x}, k, {g[x]});")
        else:  # pragma: no cover - OPS is closed
            raise ValueError(op)
    return zero, body


def _check_program(program: PrintedProgram) -> None:
    """Refuse a program whose C would not be what it says: the state components first and
    in order, every operand an earlier node (the C indexes arrays with them), the outputs
    nodes, the hash hexadecimal (it is printed into a C string)."""
    nodes, n = program.nodes, program.n_state
    if any(nodes[i].op != "var" or nodes[i].index != i for i in range(min(n, len(nodes)))):
        raise ValueError("the program's first nodes must be the state components in order")
    arity = {"sqrt": 1, "pow": 1, "exp": 1, "neg": 1, "sq": 1, "var": 0, "time": 0, "const": 0}
    for x, node in enumerate(nodes):
        if len(node.args) != arity.get(node.op, 2) or any(
            not 0 <= a < len(nodes) for a in node.args
        ):
            raise ValueError(f"node {x} ({node.op}) has operands {node.args}")
        partner = node.op in ("sin", "cos")
        if any(a >= x for a in node.args[: 1 if partner else None]):
            raise ValueError(f"node {x} ({node.op}) reads a later node")
    if len(nodes) < n or any(not 0 <= o < len(nodes) for o in program.outputs):
        raise ValueError("the program's outputs are not its nodes")
    if re.fullmatch(r"[0-9a-f]{64}", program.model_hash) is None:
        raise ValueError("the program's model hash is not a sha256 in hex")


def taylor_arb_source(program: PrintedProgram | str, header: str = "") -> str:
    """The C source of the model's Taylor coefficients on Arb balls and jets.

    Parameters
    ----------
    program : PrintedProgram or str
        The model's printed Taylor program, or its JSON text.
    header : str, optional
        Lines for the file's leading comment (the program's own ``about`` lines when the
        JSON text is given and this is empty).

    Returns
    -------
    str
        A C99 translation unit for the template ``templates/taylor_arb.c``.

    Raises
    ------
    ValueError
        The program's first nodes are not the state components in order, or a constant is
        not in the ``R_*`` macros.
    """
    if isinstance(program, str):
        import json

        about = json.loads(program).get("about", [])
        header = header or "\n".join(str(line) for line in about)
        program = PrintedProgram.from_json(program)
    header = header.replace("*/", "* /")  # inside the file's leading comment
    _check_program(program)
    n = program.n_state
    printer = _ConstPrinter(program.params)
    zero, body = _node_lines(program, printer)
    g = _gradients(program)
    update = []
    for i, o in enumerate(program.outputs):
        update.append(f"arb_div_si(V({i}, k + 1), V({o}, k), k + 1, PREC);")
        if g[o]:
            update.append(
                f"for (c = 0; c < w->m; ++c) "
                f"arb_div_si(G({i}, c, k + 1), G({o}, c, k), k + 1, PREC);"
            )
    fn = [
        *["    " + ln for ln in zero],
        "    for (int k = 0; k < order; ++k) {",
        "        if (k > 0) {",
        *["            " + ln for ln in body],
        "        }",
        *["        " + ln for ln in update],
        "    }",
    ]
    text = resources.files("chaplygin.derive").joinpath("templates", TAYLOR_ARB_TEMPLATE)
    text = text.read_text()
    for key, value in {
        "HEADER": header,
        "N_STATE": str(n),
        "N_PARAM": str(len(program.params)),
        "N_NODES": str(len(program.nodes)),
        "N_CONST_TMP": str(printer.depth),
        "MODEL_HASH": program.model_hash,
        "COEFFICIENTS": "\n".join(fn),
    }.items():
        text = text.replace("{{" + key + "}}", value)
    return text
