"""Taylor integrator generated from the model: double and quad in C, any digits in Python.

The recurrences come from :mod:`chaplygin.derive.emit.taylor` (``generated/*_taylor.py`` and
``*_taylor.c``). Order and step follow Jorba and Zou (2005): with ``eps = atol`` when
``rtol |y|_inf <= atol`` (absolute control, scale 1) and ``eps = rtol`` otherwise (relative
control, scale ``|y|_inf``), the order is ``p = ceil(-ln(eps)/2 + 1)`` and the step
``h = rho e^-2 e^(-0.7/(p-1))``, ``rho = min((scale/|y_[p-1]|)^(1/(p-1)),
(scale/|y_[p]|)^(1/p))`` (the last two coefficients' norms; ``e^(-0.7/(p-1))`` is the
safety factor). Every step keeps its Taylor polynomial, so the solution is known at any
time inside it (dense output) and sign changes of user functions ``g(t, y)`` are located by
root finding on that polynomial to the working precision (event location, for Poincaré
maps).

Backends
--------
* ``double`` -- the C integrator in IEEE double; the whole loop (coefficients, step choice,
  polynomial evaluation, output at the requested times) runs in C, one call per
  integration (one call per step when events are requested);
* ``quad`` -- the same C code in ``__float128`` (libquadmath), values crossing the
  interface as exact binary128 bytes, converted to and from ``mpmath.mpf``;
* digits up to 31 (at most 106 bits) -- the same C code in double-double
  (``-DCHAPLYGIN_TAYLOR_DD``: two doubles, 106 bits, error-free transformations), and up to
  60 digits (203 bits) in quad-double (``-DCHAPLYGIN_TAYLOR_QD``, four doubles); the
  working numbers are split exactly into their limbs and the results rounded once back to
  the working precision;
* more digits -- C on MPFR (``generated/*_taylor_mpfr.c``, linked to gmpy2's own MPFR;
  backend ``c-mpfr``) at the precision's bits, numbers crossing as exact
  base-16 text; its order and step are those of the Python stepper to the bit (one call
  per step when events are asked for); ``lib="gmpy2"`` and a missing compiler or MPFR: the
  Python recurrences with ``gmpy2`` (MPFR) numbers (``mpmath`` numbers when
  ``lib="mpmath"``).

Without a C compiler double and quad fall back to the Python recurrences (floats, or MPFR at
113 bits) with a :class:`~chaplygin.numerics.compiled.CompilerUnavailableWarning`.

Which arithmetic a precision runs in, and everything else that depends on it, is read from
its :class:`~chaplygin.numerics.precision.Precision` (``precision.arithmetic``: one row of
:data:`~chaplygin.numerics.precision.ARITHMETICS`); :func:`taylor_solve` is given it and
enters its context itself. The integrations of the project reach this engine through the
``taylor`` integrator (:mod:`chaplygin.numerics.integrators`).

Modules
-------
* :mod:`~chaplygin.numerics.taylor.solve` -- :func:`taylor_solve`, the entry;
* :mod:`~chaplygin.numerics.taylor.control` -- the order rule and the limits;
* :mod:`~chaplygin.numerics.taylor.reals` -- how numbers cross the C interface
  (binary128, multi-double limbs, MPFR text);
* :mod:`~chaplygin.numerics.taylor.library` -- compiling and loading the generated C and
  MPFR code;
* :mod:`~chaplygin.numerics.taylor.c_run` -- the compiled loop in double, quad,
  double-double and quad-double;
* :mod:`~chaplygin.numerics.taylor.mpfr_run` -- the compiled MPFR loop;
* :mod:`~chaplygin.numerics.taylor.stepper` -- one step at a time, the Python loop and
  event location;
* :mod:`~chaplygin.numerics.taylor.dense` -- the dense double solution (:func:`taylor_dense`);
* :mod:`~chaplygin.numerics.taylor.solution` -- :class:`TaylorSolution`.
"""

from __future__ import annotations

from ..precision import DD_BITS, QD_BITS
from .c_run import _KEPT_OUTPUTS_MAX as _KEPT_OUTPUTS_MAX
from .c_run import CompiledTaylorRun as CompiledTaylorRun
from .c_run import _c_run as _c_run
from .control import MAX_STEPS as MAX_STEPS
from .control import PY_MAX_ORDER as PY_MAX_ORDER
from .control import jorba_zou_order, run_orders
from .dense import DENSE_CHUNK as DENSE_CHUNK
from .dense import TaylorDense, taylor_dense
from .library import UNROLLED_CFLAGS as UNROLLED_CFLAGS
from .library import (
    CompiledTaylor,
    CompiledTaylorMPFR,
    load_taylor_library,
    load_taylor_mpfr_library,
    mpfr_build_flags,
)
from .mpfr_run import MPFR_TAPER as MPFR_TAPER
from .reals import (
    REAL_TYPES,
    RealType,
    decode_binary128,
    decode_multi_double,
    encode_binary128,
    encode_multi_double,
)
from .reals import _fma_flags as _fma_flags
from .reals import _mpfr_text as _mpfr_text
from .reals import _parse_mpfr as _parse_mpfr
from .reals import _to_mpf as _to_mpf
from .solution import TaylorSolution
from .solve import taylor_solve
from .stepper import _from_mpf as _from_mpf
from .stepper import python_lib

__all__ = [
    "TaylorSolution",
    "TaylorDense",
    "taylor_dense",
    "CompiledTaylor",
    "load_taylor_library",
    "run_orders",
    "CompiledTaylorMPFR",
    "load_taylor_mpfr_library",
    "mpfr_build_flags",
    "taylor_solve",
    "jorba_zou_order",
    "encode_binary128",
    "decode_binary128",
    "encode_multi_double",
    "decode_multi_double",
    "DD_BITS",
    "QD_BITS",
    "python_lib",
    "RealType",
    "REAL_TYPES",
]

#: The docstring examples of the package's functions (doctest reads this module's).
__test__ = {"taylor_dense": taylor_dense}
