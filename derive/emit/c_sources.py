"""The C sources numerics compiles: a model's emitted C with the project's templates.

Every translation unit the project compiles is put together here, from the emitted files
(``generated/``, or emitted on first use) and the templates of ``derive/templates``, by
concatenation and ``{{NAME}}`` placeholders -- never by rewriting C text; numerics only
compiles and loads what these functions return:

* :func:`model_library_source` -- a model's routines with their batch versions
  (``chaplygin_many_*``, ``templates/model_many.c``), the library of
  :func:`chaplygin.numerics.compiled.load_c_model`;
* :func:`taylor_source` -- a Taylor integrator in one arithmetic (the define that selects
  ``REAL``); :func:`~chaplygin.derive.emit.taylor_unroll.unrolled_source` adds the
  coefficients written out for fixed orders;
* :func:`variational_source` -- the DOP853 of the variational equations
  (``templates/variational.c``);
* :func:`batch_source` and :func:`taylor_batch_source` -- the stroboscopic map of many points
  (``templates/batch_map.c`` with the model's right-hand side in vector lanes,
  ``<model>_lanes.c``; ``templates/taylor_batch_map.c`` on the Taylor integrator in vector
  lanes, ``templates/taylor_lanes.c``) and Benettin's loop of many points
  (``templates/variational_batch.c``, with the Jacobian in the lanes too);
* :func:`fastcall_source` -- the CPython trampoline (``templates/fastcall.c``);
* :func:`inline_project_headers` -- the project's header ``detmath.h`` put in place of its
  ``#include`` line (done by :func:`chaplygin.numerics.ccompile.compile_c` for every source,
  so that the header is part of the compile cache's key).
"""

from __future__ import annotations

from collections.abc import Iterable
from importlib import resources

from .taylor_c import PrintedProgram
from .taylor_lanes import written_out_lanes

__all__ = [
    "TAYLOR_DEFINES",
    "MODEL_MANY_MARKER",
    "JACOBIAN_LANES",
    "model_library_source",
    "taylor_source",
    "variational_source",
    "batch_source",
    "taylor_batch_source",
    "fastcall_source",
    "inline_project_headers",
]

#: The line that selects the Taylor template's ``REAL`` for each arithmetic (none: double).
TAYLOR_DEFINES = {
    "double": "",
    "quad": "#define CHAPLYGIN_TAYLOR_QUAD 1\n",
    "dd": "#define CHAPLYGIN_TAYLOR_DD 1\n",
    "qd": "#define CHAPLYGIN_TAYLOR_QD 1\n",
}

#: First line of ``templates/model_many.c``: a source that has it has its batch routines.
MODEL_MANY_MARKER = "/* chaplygin.numerics.compiled batch shim v2 */"

#: The name of the Jacobian in vector lanes: a lanes source that defines it has the lanes of the
#: variational batch (``templates/variational_batch.c``).
JACOBIAN_LANES = "static void bm_rhs_jac_vec("

#: The ``#include`` line of emitted sources that :func:`inline_project_headers` replaces.
_PROJECT_INCLUDE = '#include "detmath.h"'


def _template(name: str) -> str:
    return resources.files("chaplygin.derive").joinpath("templates", name).read_text()


def model_library_source(c_source: str) -> str:
    """A model's emitted C with the batch versions of its routines.

    ``chaplygin_many_<routine>`` evaluate states stored column-wise in a strided
    ``(n_state, N)`` array (strides in elements), so that ``CompiledModel.*_many`` need no
    Python loop.

    Parameters
    ----------
    c_source : str
        A model's emitted C (``generated/<model>.c``).

    Returns
    -------
    str
        ``c_source`` and ``templates/model_many.c`` (``c_source`` itself when it already
        has them).
    """
    if MODEL_MANY_MARKER in c_source:
        return c_source
    return c_source + "\n" + _template("model_many.c")


def taylor_source(taylor_c_source: str, arithmetic: str) -> str:
    """A model's Taylor integrator in one arithmetic.

    Parameters
    ----------
    taylor_c_source : str
        The model's emitted Taylor C (``generated/<model>_taylor.c``).
    arithmetic : {"double", "quad", "dd", "qd"}
        IEEE double, binary128 (``__float128``), double-double or quad-double.

    Returns
    -------
    str

    Raises
    ------
    KeyError
        Another arithmetic.
    """
    return TAYLOR_DEFINES[arithmetic] + taylor_c_source


def variational_source(c_source: str) -> str:
    """The DOP853 of the variational equations (and Benettin's renormalisation) of a model.

    Parameters
    ----------
    c_source : str
        The model's emitted C (``chaplygin_rhs_jac``, ``chaplygin_integrals``).

    Returns
    -------
    str
        ``c_source`` and ``templates/variational.c``.
    """
    return c_source + "\n" + _template("variational.c")


def _batch_map() -> str:
    """``templates/batch_map.c`` with its time function (``templates/batch_time.c``)."""
    return _template("batch_map.c").replace("{{BM_TIME}}\n", _template("batch_time.c"), 1)


def batch_source(c_source: str, lanes_source: str | None) -> tuple[str, bool]:
    """The DOP853 batch of a time-periodic model, and whether it has the vector lanes.

    Parameters
    ----------
    c_source : str
        The model's emitted C.
    lanes_source : str or None
        Its right-hand side in vector lanes (``generated/<model>_lanes.c``); None for a model
        whose right-hand side the lanes cannot compute.

    Returns
    -------
    (str, bool)
        The source (the model's C, ``variational.c``'s DOP853, ``batch_map.c``,
        ``variational_batch.c`` and the lanes where there are some) and whether the map's lane
        driver is built (the variational lanes also need the Jacobian's,
        :data:`JACOBIAN_LANES`).
    """
    source = "\n".join(
        (
            c_source,
            _template("variational.c"),
            "#define BM_VEC_RHS 1" if lanes_source else "",
            "#define BM_VEC_JAC 1" if lanes_source and JACOBIAN_LANES in lanes_source else "",
            _batch_map(),
            _template("variational_batch.c"),
            lanes_source or "",
        )
    )
    return source, bool(lanes_source)


def taylor_batch_source(taylor_c_source: str, taylor_program: str,
                        orders: Iterable[int] = ()) -> str:  # fmt: skip
    """The Taylor batch of a model: its Taylor integrator (double), the lanes driver
    (``templates/taylor_lanes.c`` with the coefficients in vector lanes printed from its
    program, written out for ``orders``:
    :func:`~chaplygin.derive.emit.taylor_lanes.written_out_lanes`),
    ``templates/batch_time.c`` and ``templates/taylor_batch_map.c``.

    Parameters
    ----------
    taylor_c_source : str
        The model's emitted Taylor C.
    taylor_program : str
        Its printed Taylor program (``<model>_taylor_program.json``).
    orders : iterable of int, optional
        The orders to write out (the others run the loop).

    Returns
    -------
    str

    Raises
    ------
    ValueError
        ``taylor_program`` is not a printed program's JSON.
    """
    lanes = _template("taylor_lanes.c").replace(
        "{{COEFFICIENTS_LANES}}",
        written_out_lanes(PrintedProgram.from_json(taylor_program), orders), 1,
    )
    return "\n".join(
        (
            taylor_c_source,
            "#include <float.h>",
            lanes,
            _template("batch_time.c"),
            _template("taylor_batch_map.c"),
        )
    )


def fastcall_source(built_for: str) -> str:
    """The CPython extension that calls a model's routines (``templates/fastcall.c``).

    Parameters
    ----------
    built_for : str
        The interpreter and numpy it is built for, written into a closing comment (so that
        they are part of the compile cache's key).

    Returns
    -------
    str
    """
    return _template("fastcall.c") + f"/* {built_for} */\n"


def inline_project_headers(source: str) -> str:
    """``source`` with each ``#include "detmath.h"`` line replaced by the text of the header.

    Emitted C sources include the project's elementary functions
    (``chaplygin/arith/templates/detmath.h``) by name; the header's text goes into the
    translation unit here, so no include path depends on where the package is installed and
    a change of the header changes the compile cache's key.

    Parameters
    ----------
    source : str

    Returns
    -------
    str
    """
    if _PROJECT_INCLUDE not in source:
        return source
    from ...arith import c_header

    header = c_header()
    lines = source.split("\n")
    return "\n".join(header if line.startswith(_PROJECT_INCLUDE) else line for line in lines)
