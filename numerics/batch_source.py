"""The C sources of the batch integrators: the model's emitted C with the batch templates.

The DOP853 batch (``numerics/templates/variational.c``'s tableau and ``batch_map.c``, with the
model's right-hand side also in GCC vector lanes, :func:`vector_rhs_source`) and the Taylor
batch (the model's emitted Taylor C, ``bm_time`` of ``batch_map.c`` and
``taylor_batch_map.c``). Compiled and loaded by :mod:`chaplygin.numerics.integrators.c_batch`.
"""

from __future__ import annotations

import hashlib
import platform
import re
from importlib import resources
from pathlib import Path

from ..derive.errors import ComputationError
from .code import ModelCode

__all__ = [
    "BATCH_CFLAGS",
    "NATIVE_CFLAGS",
    "batch_source",
    "cpu_identity",
    "taylor_batch_source",
    "vector_rhs_source",
]

#: Functions the vector right-hand side applies lane by lane (batch_map.c BM_LANEWISE): the
#: project's elementary functions (arith/templates/detmath.h) and the exact sqrt, fabs.
_LANEWISE = frozenset(
    {"chaplygin_sin", "chaplygin_cos", "chaplygin_exp", "chaplygin_log", "sqrt", "fabs"}
)

#: Extra compiler flags of the batch library (part of the compile cache key), tried first:
#: -march=native lets the vector lanes use the CPU's widest instructions (AVX2: 4 doubles). The
#: CPU's identity (:func:`cpu_identity`) is added as a define, so that a cache shared by
#: machines of different CPUs keeps one library per CPU. No -ffast-math: ccompile's
#: -ffp-contract=off stays, so every lane computes the IEEE operations of the scalar code.
NATIVE_CFLAGS = ("-O3", "-march=native")
#: The flags used when the compiler refuses -march=native.
BATCH_CFLAGS = ("-O3",)

def cpu_identity() -> str:
    """A short hash of what ``-march=native`` depends on: the CPU's model and feature flags.

    Returns
    -------
    str
        16 hexadecimal digits (from ``/proc/cpuinfo`` on Linux, else
        :func:`platform.processor` and :func:`platform.machine`).
    """
    try:
        text = Path("/proc/cpuinfo").read_text()
        keys = ("model name", "flags", "Features", "CPU implementer", "CPU part")
        ident = "\n".join(sorted({ln for ln in text.splitlines() if ln.startswith(keys)}))
    except OSError:
        ident = ""
    ident = ident or f"{platform.processor()}|{platform.machine()}"
    return hashlib.sha256(ident.encode()).hexdigest()[:16]


def vector_rhs_source(c_source: str) -> str | None:
    """``bm_rhs_vec``: the generated ``chaplygin_rhs`` with every double a vector of lanes.

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
    head = "void chaplygin_rhs(double T, const double *restrict Y, const double *restrict P, "
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
        "static void bm_rhs_vec(bm_vec T, const bm_vec *restrict Y, const bm_vec *restrict P, "
        "bm_vec *restrict OUT)\n" + body
    )


def c_function(source: str, name: str) -> str:
    """The text of the C function ``name`` of ``source`` (from its declaration to the first
    ``}`` in column 0).

    Parameters
    ----------
    source : str
    name : str

    Returns
    -------
    str

    Raises
    ------
    ComputationError
        No such function.
    """
    start = re.search(rf"^static \w+ {name}\(", source, re.MULTILINE)
    if start is None:
        raise ComputationError(f"no C function {name} in the batch map templates")
    return source[start.start() : source.index("\n}\n", start.start()) + 3]


def _templates():
    return resources.files("chaplygin.numerics").joinpath("templates")


def batch_source(code: ModelCode) -> tuple[str, bool]:
    """The DOP853 batch library's source of ``code``, and whether it has the vector lanes.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    (str, bool)
        The source (the model's C, ``variational.c``, ``batch_map.c`` and the vector
        right-hand side where the model has one) and whether the lane driver can be built.
    """
    templates = _templates()
    vector_rhs = vector_rhs_source(code.c_source)
    source = "\n".join(
        (
            code.c_source,
            templates.joinpath("variational.c").read_text(),
            "#define BM_VEC_RHS 1" if vector_rhs else "",
            templates.joinpath("batch_map.c").read_text(),
            vector_rhs or "",
        )
    )
    return source, vector_rhs is not None


def taylor_batch_source(code: ModelCode) -> str | None:
    """The Taylor batch library's source of ``code``: the model's generated Taylor C source
    (double) + ``bm_time`` of ``batch_map.c`` + ``taylor_batch_map.c``; None without
    generated Taylor code.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    str or None
    """
    if not code.taylor_c_source:
        return None
    templates = _templates()
    return "\n".join(
        (
            code.taylor_c_source,
            "#include <float.h>",
            c_function(templates.joinpath("batch_map.c").read_text(), "bm_time"),
            templates.joinpath("taylor_batch_map.c").read_text(),
        )
    )
