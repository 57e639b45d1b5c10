"""Complex arithmetic in an operation order the project fixes: the same bits everywhere.

numpy's complex ``*``, ``np.square`` and ``np.abs`` pick their loops by processor: on this
project's x86-64 machines the AVX2/FMA loops (``X86_V3``) give other last bits than the
baseline loops (``NPY_DISABLE_CPU_FEATURES=X86_V3``) -- the multiply fuses ``a b - c d``
into one rounding, the modulus is another ``hypot`` (measured in
``tests/arith/test_detcomplex.py``). ``np.angle`` and ``np.exp`` of complex numbers call libm
(``atan2``, ``exp``, ``sin``, ``cos``), whose code paths are chosen by processor too; Python's
``complex`` type calls libm's ``hypot`` for ``abs`` and may be compiled with fused
multiply-adds. Complex addition and subtraction are exact per component (one IEEE operation
each) and safe anywhere.

The functions here take the real and imaginary parts apart (exactly) and compute with
IEEE-754 basic operations on floats or numpy float64 arrays (each correctly rounded, never
fused) and the elementary functions of :mod:`.detmath`:

* :func:`make` -- ``re + i im`` without arithmetic;
* :func:`mul`, :func:`div` -- the textbook product, Smith's quotient;
* :func:`absolute`, :func:`phase` -- ``detmath.hypot`` and ``detmath.atan2``;
* :func:`cis`, :func:`exp` -- ``cos x + i sin x`` and ``e^re cis(im)``.

Inputs are Python numbers (a Python ``complex`` is returned) or array-likes (a complex128
ndarray is returned, broadcast as numpy does).

References
----------
R. L. Smith, "Algorithm 116: Complex division", Commun. ACM 5 (1962).
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from . import detmath

__all__ = ["make", "mul", "div", "absolute", "phase", "cis", "exp"]


def _scalar(*values: Any) -> bool:
    return all(isinstance(v, numbers.Number) and not isinstance(v, np.ndarray) for v in values)


def _parts(z: Any) -> tuple[np.ndarray, np.ndarray]:
    """Real and imaginary parts as float64 arrays (0-d for a number), exactly."""
    a = np.asarray(z)
    if np.iscomplexobj(a):
        return a.real.astype(np.float64), a.imag.astype(np.float64)
    return a.astype(np.float64), np.zeros(a.shape)


def _complex(re: np.ndarray, im: np.ndarray, scalar: bool) -> Any:
    out = make(np.asarray(re), np.asarray(im))
    return complex(out[()]) if scalar else out


def _real(x: np.ndarray, scalar: bool) -> Any:
    return float(x) if scalar else np.asarray(x, np.float64)


def make(re: Any, im: Any) -> Any:
    """``re + i im``, the parts copied as they are (no arithmetic, infinities kept).

    Parameters
    ----------
    re, im : float or array_like of float

    Returns
    -------
    complex or ndarray of complex128
    """
    if _scalar(re, im):
        return complex(float(re), float(im))
    r, i = np.broadcast_arrays(np.asarray(re, np.float64), np.asarray(im, np.float64))
    out = np.empty(r.shape, np.complex128)
    out.real = r
    out.imag = i
    return out


def mul(a: Any, b: Any) -> Any:
    """``a b = (a_r b_r - a_i b_i) + i (a_r b_i + a_i b_r)``, each product rounded.

    Parameters
    ----------
    a, b : complex or array_like

    Returns
    -------
    complex or ndarray of complex128
    """
    ar, ai = _parts(a)
    br, bi = _parts(b)
    return _complex(ar * br - ai * bi, ar * bi + ai * br, _scalar(a, b))


def div(a: Any, b: Any) -> Any:
    """``a / b`` by Smith's algorithm (no overflow of ``|b|^2``).

    Parameters
    ----------
    a, b : complex or array_like

    Returns
    -------
    complex or ndarray of complex128
        ``b = 0`` gives infinities or NaN, as the parts' IEEE divisions do.
    """
    ar, ai = _parts(a)
    br, bi = _parts(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        first = np.abs(br) >= np.abs(bi)
        r = np.where(first, br, bi)  # the larger part of b
        q = np.where(first, bi, br) / r  # the smaller over the larger
        den = r + np.where(first, bi, br) * q
        re = np.where(first, ar + ai * q, ar * q + ai) / den
        im = np.where(first, ai - ar * q, ai * q - ar) / den
    return _complex(re, im, _scalar(a, b))


def absolute(z: Any) -> Any:
    """``|z|`` (``detmath.hypot`` of the parts).

    Parameters
    ----------
    z : complex or array_like

    Returns
    -------
    float or ndarray of float64
    """
    re, im = _parts(z)
    return _real(detmath.hypot(re, im), _scalar(z))


def phase(z: Any) -> Any:
    """The argument of ``z`` in ``[-pi, pi]`` (``detmath.atan2(im, re)``).

    Parameters
    ----------
    z : complex or array_like

    Returns
    -------
    float or ndarray of float64
    """
    re, im = _parts(z)
    return _real(detmath.atan2(im, re), _scalar(z))


def cis(x: Any) -> Any:
    """``cos x + i sin x`` for real ``x``.

    Parameters
    ----------
    x : float or array_like of float

    Returns
    -------
    complex or ndarray of complex128
    """
    return make(detmath.cos(x), detmath.sin(x))


def exp(z: Any) -> Any:
    """``e^z = e^re (cos im + i sin im)``.

    Parameters
    ----------
    z : complex or array_like

    Returns
    -------
    complex or ndarray of complex128
    """
    re, im = _parts(z)
    scale = detmath.exp(re)
    return _complex(scale * detmath.cos(im), scale * detmath.sin(im), _scalar(z))
