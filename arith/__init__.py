"""Deterministic arithmetic: the lowest layer, imported by every other and importing none.

The same inputs give the same bits on every machine only if nothing on the way picks its code
by processor. Here live the project's own kernels for what libm, numpy's SIMD loops and
BLAS/LAPACK would otherwise decide:

* :mod:`.detmath` -- elementary functions (``exp``, ``log``, ``sin``, ...) from IEEE basic
  operations only, for Python floats and numpy arrays; ``templates/detmath.h`` is the same code
  in C, inlined into every generated C source (built with ``-ffp-contract=off``), bit for bit;
* :mod:`.detlinalg` -- small dense linear algebra in a fixed operation order.
"""

__all__ = ["c_header"]


def c_header() -> str:
    """Text of ``templates/detmath.h``, which emitters inline into every C source they write.

    Returns
    -------
    str
    """
    from .detmath import header_text

    return header_text()
