"""The C sources written in one layer (derive/emit): the same text as the rewriting they replace.

The vector lanes are printed from the sympy right-hand side; before, they were regular
expressions over the generated C (``tests/legacy_emitters.py``, frozen). Same text means same
bits; the bits themselves are compared between the batch drivers in
``tests/numerics/dynamics/test_batch_map.py``. (The coefficients written out for fixed orders
were compared with the old rewriter's text here too, until issue 26 changed their arithmetic on
purpose; their bits are compared with the loop in ``tests/numerics/test_taylor_unroll.py``.)
The translation units are put together from the templates in the order numerics compiled
them before; what keeps a right-hand side out of the lanes is read from its tree.
"""

from __future__ import annotations

import json

import legacy_emitters as legacy
import pytest
import sympy as sp
from chaplygin.derive.emit.base import Routine
from chaplygin.derive.emit.c_emitter import lanes_obstacle
from chaplygin.derive.emit.c_sources import (
    batch_source,
    inline_project_headers,
    model_library_source,
    taylor_batch_source,
    taylor_source,
)
from chaplygin.derive.emit.taylor_c import PrintedProgram
from chaplygin.derive.systems import builtin_variants
from chaplygin.numerics import load_model_code

VARIANTS = [(s, tuple(sorted(e))) for s, e in builtin_variants()]


@pytest.mark.parametrize("system,effects", VARIANTS)
def test_the_lanes_are_the_function_the_rewriting_wrote(system, effects):
    """The emitted lanes (right-hand side, then with the Jacobian) are the scalar functions
    rewritten as text by the legacy rewriter; the variational lanes are switched on by them."""
    code = load_model_code(system, effects)
    old_rhs = legacy.vector_rhs_source(code.c_source)
    old_jac = legacy.vector_rhs_source(code.c_source, "rhs_jac")
    assert old_rhs is not None and code.lanes_c_source is not None
    # after the file's comment header; a Jacobian with a power the lanes lack has none
    tail = old_rhs if old_jac is None else old_rhs.rstrip("\n") + "\n\n" + old_jac
    assert code.lanes_c_source.endswith("\n" + tail)
    source, lanes = batch_source(code.c_source, code.lanes_c_source)
    assert lanes and source.endswith(code.lanes_c_source)
    assert source.index("#define BM_VEC_RHS 1") < source.index("typedef double bm_vec")
    assert ("#define BM_VEC_JAC 1" in source) == (old_jac is not None)


def test_the_program_round_trips_and_is_the_models():
    code = load_model_code("chaplygin_ball", ("gyrostat",))
    program = PrintedProgram.from_json(code.taylor_program)
    assert program.model_hash == code.hash and program.params == code.params
    assert program.to_json(json.loads(code.taylor_program)["about"]) == code.taylor_program
    assert [n.op for n in program.nodes[: len(code.state)]] == ["var"] * len(code.state)


def test_a_right_hand_side_the_lanes_cannot_compute_is_left_out():
    x, y = sp.symbols("x y")
    lanewise = Routine("rhs", ((sp.Symbol("x0"), sp.sin(x) * y**2),),
                       (sp.sqrt(x) / y, sp.exp(-x) + abs(y), sp.log(y) ** -1), (3,))
    assert lanes_obstacle(lanewise) is None
    for expr, obstacle in ((sp.atan2(x, y), "atan2"), (x ** sp.Rational(1, 3), "chaplygin_pow"),
                           (sp.Piecewise((x, y > 0), (y, True)), "Piecewise")):
        routine = Routine("rhs", (), (x + y, expr), (2,))
        assert obstacle in lanes_obstacle(routine)


def test_the_sources_are_put_together_from_the_templates():
    code = load_model_code("chaplygin_ball", ("variable_gyrostat", "variable_inertia"))
    many = model_library_source(code.c_source)
    assert many.startswith(code.c_source) and "CHAPLYGIN__MANY(rhs, s[0])" in many
    assert model_library_source(many) == many  # once
    quad = taylor_source(code.taylor_c_source, "quad")
    assert quad == "#define CHAPLYGIN_TAYLOR_QUAD 1\n" + code.taylor_c_source
    with pytest.raises(KeyError):
        taylor_source(code.taylor_c_source, "octuple")
    batch = taylor_batch_source(code.taylor_c_source, code.taylor_program)
    assert batch.count("static double bm_time(") == 1
    dop853, _ = batch_source(code.c_source, None)
    assert dop853.count("static double bm_time(") == 1 and "{{" not in dop853
    assert "#define BM_VEC_RHS 1" not in dop853
    inlined = inline_project_headers(code.c_source)
    assert '#include "detmath.h"' in code.c_source and '#include "detmath.h"' not in inlined
    assert "chaplygin_sin" in inlined and inlined.count("\n") > code.c_source.count("\n") + 100
