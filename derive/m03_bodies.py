"""M03's bodies on a sphere as models of :func:`~.body_on_sphere.body_on_sphere_model`: a
generic surface with a scalar inertia, and the ellipsoid ``(r, B^-1 r) = 1`` with the
inertia of M03-2.4 or another (the claims of M03 §2 run on them)."""

from __future__ import annotations

import sympy as sp

from .ball_on_surface import ellipsoid_sampler
from .body_on_sphere import body_on_sphere_model
from .model import Model, ParameterSpec
from .vectors import vector

__all__ = ["ellipsoid_body_model", "generic_body_model"]


def generic_body_model() -> Model:
    """Scalar inertia ``mu Id`` and a generic surface ``f`` (undefined Function of ``r``).

    Returns
    -------
    Model
        :func:`body_on_sphere_model` with effects ``generic_surface``, ``scalar`` and no
        phase-space constraint.
    """
    r = vector("r", real=True)
    mu = sp.Symbol("mu", positive=True)
    f = sp.Function("f")(*r)
    spec = ParameterSpec("mu", (mu,), "positive", "scalar central inertia I = mu Id")
    return body_on_sphere_model(f, mu * sp.eye(3), (spec,), ("generic_surface", "scalar"))


def ellipsoid_body_model(inertia: str = "special", on_surface: bool = True) -> Model:
    """The ellipsoid ``(r, B^-1 r) = 1`` on a sphere.

    Parameters
    ----------
    inertia : {"special", "general", "scalar", "double"}
        ``I = mu Id + m B`` (M03-2.4), ``diag(I1, I2, I3)``, ``mu Id``, or
        ``mu Id + 2 m B`` (not special: a negative control).
    on_surface : bool
        Carry the ellipsoid's equation as the phase-space constraint (with an exact
        sampler); without it identities are checked for every ``r`` (every level set).

    Returns
    -------
    Model
        :func:`body_on_sphere_model` with effects ``ellipsoid`` and ``inertia``.

    Raises
    ------
    ValueError
        For an unknown ``inertia``.

    References
    ----------
    M03-2.4, M03-2.5
    """
    r = vector("r", real=True)
    b = sp.Matrix(sp.symbols("b1:4", positive=True))
    m, mu = sp.Symbol("m", positive=True), sp.Symbol("mu", positive=True)
    surface = sum((r[i] ** 2 / b[i] for i in range(3)), sp.S.Zero) - 1
    specs = [ParameterSpec("b", tuple(b), "positive", "ellipsoid (r, B^-1 r) = 1")]
    if inertia in ("special", "double"):
        factor = 1 if inertia == "special" else 2
        I = mu * sp.eye(3) + factor * m * sp.diag(*b)
        specs.append(ParameterSpec("mu", (mu,), "positive", f"I = mu Id + {factor} m B"))
    elif inertia == "general":
        Iv = sp.symbols("I1:4", positive=True)
        I = sp.diag(*Iv)
        specs.append(ParameterSpec("I", Iv, "positive", "central principal moments"))
    elif inertia == "scalar":
        I = mu * sp.eye(3)
        specs.append(ParameterSpec("mu", (mu,), "positive", "I = mu Id"))
    else:
        raise ValueError(f"unknown inertia {inertia!r}")
    return body_on_sphere_model(
        surface,
        I,
        tuple(specs),
        ("ellipsoid", inertia),
        constraints=(sp.expand(b[0] * b[1] * b[2] * surface),) if on_surface else (),
        sampler=ellipsoid_sampler(b, r) if on_surface else None,
    )
