"""The project's own transcendental functions, bit for bit ``detmath.h``, for Python and numpy.

``arith/templates/detmath.h`` defines ``chaplygin_exp``, ``chaplygin_sin``, ... in C with IEEE-754
basic operations only (+ - * / sqrt, comparisons, exact scaling and bit manipulation), so that
every compiler and processor computes the same bits; this module performs *the same sequence of
operations* on Python floats (a scalar path) and on numpy float64 arrays (element-wise numpy
operations, which are correctly rounded per element and never fused), so the three agree bit for
bit (``tests/arith/test_detmath.py`` checks it).  Unlike :mod:`math` and numpy's ufuncs -- glibc and
numpy choose FMA/AVX2/AVX-512 code paths by processor -- the result does not depend on the
machine.

The constants (tables, splits of ln 2 and pi/2, the bits of 2/pi, polynomial coefficients) are
read from the header's generated block, the single source both ports use.

The kernels live by family, each module the Python twin of its C functions: the constants,
bit operations and error-free sums they share in :mod:`.detmath_core`; exp, log, log2, log10,
pow, sinh and cosh in :mod:`.detmath_explog`; sin and cos in :mod:`.detmath_trig`; atan, atan2,
asin and acos in :mod:`.detmath_inverse_trig`; cbrt and hypot in :mod:`.detmath_roots`. This
module is the one users import: the public functions (scalar or numpy by the argument) and
the header.

Accuracy, by design and measured (``tests/arith/test_detmath.py``, mpmath at 200 bits): every
function is faithful (error below 1 ulp, also for subnormal results) and almost always
correctly rounded; see the header's top comment for the numbers.

Each function accepts a Python float or int (returns a float) or anything :func:`numpy.asarray`
turns into float64 (returns an ndarray of the same shape; a 0-d input gives a numpy scalar).
Special values follow C99 Annex F; every NaN result is the positive quiet NaN
``0x7ff8000000000000`` (payloads of NaN inputs are not kept).

References
----------
T. J. Dekker, "A floating-point technique for extending the available precision", Numer. Math.
18 (1971) -- Fast2Sum and the exact product without FMA.
M. H. Payne and R. N. Hanek, "Radian reduction for trigonometric functions", SIGNUM Newsl. 18
(1983) -- reduction of huge arguments with the bits of 2/pi.
J.-M. Muller et al., *Handbook of Floating-Point Arithmetic*, 2nd ed., Birkhauser 2018.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .detmath_core import HEADER_NAME, header_text
from .detmath_core import Float as Float  # the numpy port's array type, importable from here
from .detmath_explog import (
    _cosh_s,
    _exp_s,
    _log_base_s,
    _log_s,
    _pow_s,
    _sinh_s,
    _vcosh,
    _vexp,
    _vlog,
    _vlog_base,
    _vpow,
    _vsinh,
)
from .detmath_inverse_trig import (
    _acos_s,
    _asin_s,
    _atan2_s,
    _atan_s,
    _vacos,
    _vasin,
    _vatan,
    _vatan2,
)
from .detmath_roots import _cbrt_s, _hypot_s, _vcbrt, _vhypot
from .detmath_trig import _cos_s, _sin_s, _vsincos

__all__ = [
    "HEADER_NAME",
    "header_text",
    "exp",
    "log",
    "log2",
    "log10",
    "pow",
    "sin",
    "cos",
    "atan",
    "atan2",
    "asin",
    "acos",
    "cbrt",
    "hypot",
    "sinh",
    "cosh",
]


# =========================================================================== public functions


#: Elements per numpy pass: the temporaries of a kernel stay in the cache (3-5x faster than one
#: pass over 10^6 elements); element-wise, so the bits do not depend on it.
_CHUNK = 16384


def _is_scalar(x: Any) -> bool:
    return isinstance(x, float | int) and not isinstance(x, bool | np.ndarray)


def _apply(vector: Any, *arrays: Any) -> Any:
    """``vector`` on broadcast float64 copies of ``arrays``, chunk by chunk, in the input shape."""
    flat = [np.ascontiguousarray(a).reshape(-1)
            for a in np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in arrays))]
    shape = np.broadcast_shapes(*(np.shape(a) for a in arrays))
    out = np.empty(flat[0].size)
    with np.errstate(all="ignore"):
        for start in range(0, out.size, _CHUNK):
            out[start : start + _CHUNK] = vector(*(f[start : start + _CHUNK] for f in flat))
    out = out.reshape(shape)
    return out[()] if out.ndim == 0 else out


def _unary(scalar: Any, vector: Any, x: Any) -> Any:
    return scalar(float(x)) if _is_scalar(x) else _apply(vector, x)


def _binary(scalar: Any, vector: Any, a: Any, b: Any) -> Any:
    if _is_scalar(a) and _is_scalar(b):
        return scalar(float(a), float(b))
    return _apply(vector, a, b)


def exp(x: float | ArrayLike) -> Any:
    """Exponential e^x, the bits of ``chaplygin_exp``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        e^x rounded faithfully (almost always correctly); +inf above 709.78, subnormal results
        rounded once, +0 below -745.14.
    """
    return _unary(_exp_s, _vexp, x)


def log(x: float | ArrayLike) -> Any:
    """Natural logarithm, the bits of ``chaplygin_log``.

    Parameters
    ----------
    x : float or array_like
        Argument(s); log(+-0) = -inf, log(x < 0) = NaN, log(+inf) = +inf.

    Returns
    -------
    float or numpy.ndarray
        log x.
    """
    return _unary(_log_s, _vlog, x)


def log2(x: float | ArrayLike) -> Any:
    """Base-2 logarithm, the bits of ``chaplygin_log2`` (exact at powers of two).

    Parameters
    ----------
    x : float or array_like
        Argument(s); special values as :func:`log`.

    Returns
    -------
    float or numpy.ndarray
        log2 x.
    """
    return _unary(lambda v: _log_base_s(v, "LOG2"), lambda v: _vlog_base(v, "LOG2"), x)


def log10(x: float | ArrayLike) -> Any:
    """Base-10 logarithm, the bits of ``chaplygin_log10``.

    Parameters
    ----------
    x : float or array_like
        Argument(s); special values as :func:`log`.

    Returns
    -------
    float or numpy.ndarray
        log10 x.
    """
    return _unary(lambda v: _log_base_s(v, "LOG10"), lambda v: _vlog_base(v, "LOG10"), x)


def pow(x: float | ArrayLike, y: float | ArrayLike) -> Any:
    """Power x^y, the bits of ``chaplygin_pow`` (special cases of C99 Annex F).

    Parameters
    ----------
    x, y : float or array_like
        Base and exponent (broadcast together).

    Returns
    -------
    float or numpy.ndarray
        x^y: e^(y log|x|) with log|x| as a double-double; negative x only for integer y
        (NaN otherwise).
    """
    return _binary(_pow_s, _vpow, x, y)


def sin(x: float | ArrayLike) -> Any:
    """Sine, the bits of ``chaplygin_sin``, right for every finite argument.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in radians; +-inf and NaN give NaN.

    Returns
    -------
    float or numpy.ndarray
        sin x (Cody-Waite reduction below 2^20, Payne-Hanek above).
    """
    return _unary(_sin_s, lambda v: _vsincos(v, 0), x)


def cos(x: float | ArrayLike) -> Any:
    """Cosine, the bits of ``chaplygin_cos``, right for every finite argument.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in radians; +-inf and NaN give NaN.

    Returns
    -------
    float or numpy.ndarray
        cos x.
    """
    return _unary(_cos_s, lambda v: _vsincos(v, 1), x)


def atan(x: float | ArrayLike) -> Any:
    """Arc tangent, the bits of ``chaplygin_atan``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        atan x in [-pi/2, pi/2].
    """
    return _unary(_atan_s, _vatan, x)


def atan2(y: float | ArrayLike, x: float | ArrayLike) -> Any:
    """Arc tangent of y/x in the right quadrant, the bits of ``chaplygin_atan2``.

    Parameters
    ----------
    y, x : float or array_like
        Coordinates (broadcast together); signed zeros and infinities as C99 Annex F.

    Returns
    -------
    float or numpy.ndarray
        The angle in [-pi, pi].
    """
    return _binary(_atan2_s, _vatan2, y, x)


def asin(x: float | ArrayLike) -> Any:
    """Arc sine, the bits of ``chaplygin_asin``.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in [-1, 1] (NaN outside).

    Returns
    -------
    float or numpy.ndarray
        asin x in [-pi/2, pi/2].
    """
    return _unary(_asin_s, _vasin, x)


def acos(x: float | ArrayLike) -> Any:
    """Arc cosine, the bits of ``chaplygin_acos``.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in [-1, 1] (NaN outside).

    Returns
    -------
    float or numpy.ndarray
        acos x in [0, pi].
    """
    return _unary(_acos_s, _vacos, x)


def cbrt(x: float | ArrayLike) -> Any:
    """Real cube root, the bits of ``chaplygin_cbrt`` (exact for exact cubes).

    Parameters
    ----------
    x : float or array_like
        Argument(s), any sign.

    Returns
    -------
    float or numpy.ndarray
        The real cube root.
    """
    return _unary(_cbrt_s, _vcbrt, x)


def hypot(x: float | ArrayLike, y: float | ArrayLike) -> Any:
    """sqrt(x^2 + y^2) without undue overflow or underflow, the bits of ``chaplygin_hypot``.

    Parameters
    ----------
    x, y : float or array_like
        Legs (broadcast together); an infinite leg gives +inf even with a NaN.

    Returns
    -------
    float or numpy.ndarray
        The hypotenuse.
    """
    return _binary(_hypot_s, _vhypot, x, y)


def sinh(x: float | ArrayLike) -> Any:
    """Hyperbolic sine, the bits of ``chaplygin_sinh``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        sinh x (+-inf beyond +-710.48).
    """
    return _unary(_sinh_s, _vsinh, x)


def cosh(x: float | ArrayLike) -> Any:
    """Hyperbolic cosine, the bits of ``chaplygin_cosh``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        cosh x (+inf beyond 710.48).
    """
    return _unary(_cosh_s, _vcosh, x)
