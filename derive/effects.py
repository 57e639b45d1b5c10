"""Effects: structural options that declare what they add to a mechanical description.

An effect is an object: :meth:`Effect.declare` reads the description it is applied to
and returns a :class:`~.declaration.Declaration` — its kinetic-energy and potential
terms, constraints (those on omega alone with the invariant relations they are), Poisson
vectors, states, parameters, integrals, inertia, completion rules — as data;
:attr:`Effect.references` are the claims it cites. :meth:`Effect.apply` merges both into
the description; an effect that is off contributes nothing. The step that derives the
model (:func:`~.description.form_model`) reads only that data, never an effect's name.

Each system lists the effects it supports; :func:`parse_effects` checks the names, the
conflicts (``excludes``) and the requirements (``requires``) before any derivation
starts. Numeric parameter values are never part of an effect.

Adding an effect: write a subclass here with its ``declare`` (it returns a
``Declaration``; it never modifies the description), put an instance in :data:`EFFECTS`
(with the references it ``cites``) and its name in the ``SUPPORTED_EFFECTS`` of the
systems that take it (see "How to add an effect or a system" in docs/development/derivation.md).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import sympy as sp

from .declaration import Constraint, Declaration, StateGroup
from .errors import UserInputError
from .model import ParameterSpec
from .vectors import cross, dot, vector

if TYPE_CHECKING:  # pragma: no cover
    from .description import MechanicalDescription

__all__ = ["Effect", "EFFECTS", "parse_effects", "ellipsoid_potential"]


@dataclass(frozen=True)
class Effect:
    """A named structural option.

    Parameters
    ----------
    name : str
    description : str
    adds : str
        What it adds to a model (for help texts and the README).
    requires : tuple of str
        Effects it needs (checked by :func:`parse_effects`).
    excludes : tuple of str
        Effects it cannot be combined with (checked both ways by :func:`parse_effects`).
    cites : tuple of (str, str)
        Model references it sets (``("equations", "K01-4.1")`` ...), after those of the
        base description; a system may give its own (``effect_references``).
    """

    name: str
    description: str
    adds: str
    requires: tuple[str, ...] = ()
    excludes: tuple[str, ...] = ()
    cites: tuple[tuple[str, str], ...] = ()

    @property
    def references(self) -> dict[str, str]:
        """The references it sets, as a dict (see ``cites``)."""
        return dict(self.cites)

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """What this effect adds to ``desc`` (read, not modified).

        Parameters
        ----------
        desc : MechanicalDescription
            The description it is applied to (its ``omega``, vectors, states ...).

        Returns
        -------
        Declaration
        """
        raise NotImplementedError(f"effect {self.name!r} does not declare what it adds")

    def apply(self, desc: MechanicalDescription) -> None:
        """Merge :meth:`declare`'s data into ``desc``, then the references.

        The references are this effect's (:attr:`references`), then those the system
        gives for it (``desc.effect_references``).

        Parameters
        ----------
        desc : MechanicalDescription
            Modified in place (:meth:`~.description.MechanicalDescription.add`).
        """
        desc.add(self.declare(desc))
        desc.references.update(self.references)
        desc.references.update(desc.effect_references.get(self.name, {}))


# ------------------------------------------------------------------ the effects
#: The space-fixed horizontal axes (their symbols, before a description has them).
_ALPHA, _BETA = vector("alpha", real=True), vector("beta", real=True)


class Gyrostat(Effect):
    """Constant gyrostatic momentum: ``T += (K, omega)`` (K01 §4, BKM12 §2.3)."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The term ``(K, omega)`` of ``T`` and the parameter ``K`` (K01-4.1, K01-4.2).

        Parameters
        ----------
        desc : MechanicalDescription

        Returns
        -------
        Declaration

        References
        ----------
        K01-4.1, K01-4.2, BKM12 §2.3.
        """
        K = vector("K", real=True)
        return Declaration(
            kinetic_energy=dot(K, desc.omega),
            parameters=(
                ParameterSpec("K", tuple(K), "real", "constant gyrostatic momentum K1, K2, K3"),
            ),
        )


class ContactPoint(Effect):
    """The space-fixed horizontal frame and the contact point ``x, y`` (BKM12-6)."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The horizontal frame, the states ``x, y`` and the radius ``b`` (BKM12-6).

        Parameters
        ----------
        desc : MechanicalDescription
            With the centre velocity ``v``.

        Returns
        -------
        Declaration
            Poisson vectors ``alpha, beta``; states ``x, y`` moving with the centre
            velocity ``v`` projected on ``alpha`` and ``beta`` (put on the admissible
            velocities when the model is made); parameter ``b``; completion rules. On a
            fixed sphere (``desc.trace_on_normal``) the frame ``alpha, beta, zeta`` only
            (the contact point is ``trace_on_normal`` times the normal, in that frame;
            ``zeta`` starts as the normal unless the description has it).

        References
        ----------
        BKM12-6.
        """
        if desc.trace_on_normal is not None:  # on a fixed sphere: the fixed frame only
            # (the field's vertical is given; a convex body's zeta is a state its stage
            # derives; without a field it starts as a spherical body's normal gamma)
            has_zeta = "zeta" in desc.kinematics or any(g.name == "zeta" for g in desc.states)
            normal = not has_zeta and "gamma" in desc.kinematics
            return Declaration(
                poisson_vectors=("alpha", "beta") + (() if has_zeta else ("zeta",)),
                completion=((("alpha", "beta"), "frame_bkm12_7"),
                            *([(("zeta",), "normal")] if normal else [])),
            )  # fmt: skip
        b = sp.Symbol("b", positive=True)
        x, y = sp.symbols("x y", real=True)
        # The contact point lies under the centre: its horizontal coordinates move with
        # the centre velocity projected on the space-fixed axes (BKM12-6). The reference
        # point of v is the centre of mass; a body whose centre of mass is off the
        # sphere's centre adds omega x (centre - centre of mass).
        centre = desc.v
        if desc.centre_offset is not None:
            centre = desc.v + cross(desc.omega, desc.centre_offset)
        if desc.trace_velocity is not None:  # a convex body: the contact point's own
            centre = desc.trace_velocity
        # the radius is a parameter here unless the description has it already (or a
        # number): the ball's own parameters are I and D = m b^2 only
        contact = desc.contact_vector
        needs_b = contact is not None and b in contact.free_symbols and "b" not in desc.parameters
        radius = (ParameterSpec("b", (b,), "positive", "ball radius"),) if needs_b else ()
        # a state given without the frame gets BKM12-7's (from gamma, where there is one);
        # the contact point starts at 0
        frame = ((("alpha", "beta"), "frame_bkm12_7"),) if "gamma" in desc.kinematics else ()
        return Declaration(
            poisson_vectors=("alpha", "beta"),
            states=(
                StateGroup("x", (x,), (dot(centre, _ALPHA),)),
                StateGroup("y", (y,), (dot(centre, _BETA),)),
            ),
            parameters=radius + tuple(desc.trace_parameters),
            completion=(*frame, (("x",), "zero"), (("y",), "zero")),
        )


class Rubber(Effect):
    """No twist at the contact: the constraint ``(omega, gamma) = 0`` (BKM12 §3)."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The no-twist constraint ``(omega, gamma) = 0`` (BKM12 §3).

        Parameters
        ----------
        desc : MechanicalDescription
            With the Poisson vector ``gamma``.

        Returns
        -------
        Declaration
            The constraint, its reaction along ``gamma``: the invariant relation
            ``(omega,gamma)``.
        """
        no_twist = dot(desc.omega, desc.vectors["gamma"])
        return Declaration(constraints=(Constraint(no_twist, reacts_along="gamma"),))


class StraightLine(Effect):
    """Rolling along the space-fixed line ``alpha``: ``(omega, alpha) = 0`` (BKM12-57)."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The horizontal frame and the constraint ``(omega, alpha) = 0`` (BKM12-57).

        Parameters
        ----------
        desc : MechanicalDescription

        Returns
        -------
        Declaration
            Poisson vectors ``alpha, beta``; the constraint, its reaction along
            ``alpha``: the invariant relation ``(omega,alpha)``; the frame's completion.

        References
        ----------
        BKM12-57.
        """
        return Declaration(
            poisson_vectors=("alpha", "beta"),
            constraints=(Constraint(dot(desc.omega, _ALPHA), reacts_along="alpha"),),
            completion=((("alpha", "beta"), "frame_bkm12_7"),),
        )


#: What both periodic effects cite (no energy integral: T depends on time, BM20-2.6).
_PERIODIC_CITES = (("equations", "BM20-2.5"), ("omega", "BM20-2.5"), ("integrals", "BM20-2.5int"))


def _frequency(desc: MechanicalDescription) -> tuple[ParameterSpec, ...]:
    """The frequency ``Omega`` of both periodic effects (with BM20's laws)."""
    if desc.laws != "bm20":
        return ()
    return (
        ParameterSpec(
            "Omega",
            (sp.Symbol("Omega", positive=True),),
            "positive",
            "angular frequency of the periodic parameters (BM20-3.4, 3.5)",
        ),
    )


class VariableInertia(Effect):
    """``I(t) = diag(I1 + (J_off + delta sin(Omega t))^2, I2, I3 + (...)^2)`` (BM20-3.4)."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The inertia ``I(t)``, depending on time (BM20-3.4).

        With ``desc.laws == "generic"`` the moments are undefined functions ``I1(t),
        I2(t), I3(t)`` and the parameter ``I`` is removed; otherwise they follow BM20's
        moving mass pair, ``I`` is their constant part and the parameters ``J_off``,
        ``delta`` (and ``Omega``) are added. ``T`` then depends on time: the model has no
        energy integral, and the density ``det(X)^-1/2`` of the constant inertia, which
        would depend on time, is not shipped (see :class:`~.rigid_body.RigidBodyReduction`).

        Parameters
        ----------
        desc : MechanicalDescription

        Returns
        -------
        Declaration
            ``inertia``, ``moments``, the parameter ``I`` redeclared, new parameters.

        References
        ----------
        BM20-3.4, BM20-2.5, BM20-2.5int.
        """
        t = desc.time
        if desc.laws == "generic":  # every law: undefined functions of time
            moments = [sp.Function(f"I{i}", positive=True)(t) for i in (1, 2, 3)]
            return Declaration(inertia=sp.diag(*moments), moments=(), redeclared_parameters=("I",))
        # a pair of masses moving along C x2 (BM20-3.4)
        Iv = vector("I", positive=True)
        J_off, delta = sp.symbols("J_off delta", real=True)
        Omega = sp.Symbol("Omega", positive=True)
        offset = (J_off + delta * sp.sin(Omega * t)) ** 2
        constant_part = ParameterSpec(
            "I",
            tuple(Iv),
            "positive",
            "constant parts I1, I2, I3 of the principal moments of inertia "
            "I(t) = diag(I1 + (J_off + delta sin(Omega t))^2, I2, I3 + (...)^2)",
        )
        return Declaration(
            inertia=sp.diag(Iv[0] + offset, Iv[1], Iv[2] + offset),
            redeclared_parameters=("I",),
            parameters=(
                constant_part,
                ParameterSpec(
                    "J_off", (J_off,), "real", "offset J of the moving mass pair in I(t) (BM20-3.4)"
                ),
                ParameterSpec(
                    "delta", (delta,), "real", "amplitude of the mass pair's motion (BM20-3.4)"
                ),
                *_frequency(desc),
            ),
        )


class VariableGyrostat(Effect):
    """``T += (k(t), omega)``, ``k(t) = K sin(Omega t)`` (BM20-3.5); the state ``M`` is
    then BM20's total momentum ``I omega + D gamma x (omega x gamma) + k(t)``."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The term ``(k(t), omega)`` of ``T`` with ``k(t) = K sin(Omega t)`` (BM20-3.5).

        With ``desc.laws == "generic"`` ``k`` is three undefined functions of time. The
        state ``M`` includes ``k(t)`` (the total momentum); ``T`` depends on time, so the
        model has no energy integral.

        Parameters
        ----------
        desc : MechanicalDescription

        Returns
        -------
        Declaration
            The kinetic term, ``momentum_in_state = k(t)``, parameters.

        References
        ----------
        BM20-3.5, BM20-2.5, BM20-2.5int.
        """
        t = desc.time
        if desc.laws == "generic":
            k = sp.Matrix([sp.Function(f"k{i}", real=True)(t) for i in (1, 2, 3)])
            amplitude: tuple[ParameterSpec, ...] = ()
        else:  # rotors (BM20-3.5)
            K = vector("K", real=True)
            k = K * sp.sin(sp.Symbol("Omega", positive=True) * t)
            amplitude = (
                ParameterSpec(
                    "K",
                    tuple(K),
                    "real",
                    "amplitude K of the gyrostatic momentum k(t) = K sin(Omega t) (BM20-3.5)",
                ),
            )
        return Declaration(
            kinetic_energy=dot(k, desc.omega),
            momentum_in_state=k,
            parameters=(*amplitude, *_frequency(desc)),
        )


def ellipsoid_potential(x: sp.Matrix, k: sp.Expr, c: sp.Matrix) -> sp.Expr:
    """``U = k (x, x)/2 + (1/2) sum_i c_i/x_i^2`` (M03-1.6, with the 1/2 factors read).

    Parameters
    ----------
    x : sympy.Matrix, shape (3, 1)
        Position of the centre.
    k : sympy.Expr
        Stiffness of the quadratic term.
    c : sympy.Matrix, shape (3, 1)
        Coefficients of the ``1/x_i^2`` terms.

    Returns
    -------
    sympy.Expr
        The potential energy ``U``.

    References
    ----------
    M03-1.6
    """
    return k * dot(x, x) / 2 + sum((c[i] / x[i] ** 2 for i in range(3)), sp.S.Zero) / 2


class Potential(Effect):
    """``U = k (x, x)/2 + (1/2) sum_i c_i/x_i^2`` on the centre of the ball on the
    ellipsoid ``(x, B^-1 x) = 1`` (M03-1.6), and its term of the integral ``K`` (M03-1.7).
    """

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """The potential ``U`` on the centre (M03-1.6) and its term of ``K`` (M03-1.7).

        Parameters
        ----------
        desc : MechanicalDescription
            With the state group ``x`` and the parameters ``m, m_e, R, b`` of the
            ball-on-ellipsoid model.

        Returns
        -------
        Declaration
            The potential, the parameters ``k`` and ``c``, a term of the integral ``K``.

        References
        ----------
        M03-1.6, M03-1.7.
        """
        x = desc.state_group("x")
        b = desc.parameters["b"].symbols
        ((m,), (m_e,), (R,)) = (desc.parameters[n].symbols for n in ("m", "m_e", "R"))
        k = sp.Symbol("k", real=True)
        c = sp.Matrix(sp.symbols("c1:4", real=True))
        text = "U = k (x, x)/2 + sum_i c_i/(2 x_i^2)"
        # M03-1.7 with the factor fixed by the derivation (verify/claims/m03.py solves for
        # it): -1/((m + m_e) R^2) for U = k x^2/2 + sum c_i/(2 x_i^2).
        quadric = sum((x[i] ** 2 / b[i] for i in range(3)), sp.S.Zero)
        bracket = k - sum((c[i] / (b[i] * x[i] ** 2) for i in range(3)), sp.S.Zero) / quadric
        weighted = sum((x[i] ** 2 / b[i] ** 2 for i in range(3)), sp.S.Zero)
        return Declaration(
            potential=ellipsoid_potential(x, k, c),
            parameters=(
                ParameterSpec("k", (k,), "real", text),
                ParameterSpec("c", tuple(c), "real", text),
            ),
            integrals=(("K", -weighted * bracket / ((m + m_e) * R**2)),),
        )


class RubberBalls(Effect):
    """Supporting balls that roll without twisting: ``(omega - omega_k, n_k) = 0``
    (BKM12-39); their spins are no longer free quasi-velocities."""

    def declare(self, desc: MechanicalDescription) -> Declaration:
        """``(omega - omega_k, n_k) = 0`` for every supporting ball (BKM12-39).

        Parameters
        ----------
        desc : MechanicalDescription
            With the supporting balls in ``desc.bodies``.

        Returns
        -------
        Declaration
            One constraint per ball; it fixes the ball's spin, which the reduction then
            no longer takes as a free quasi-velocity.

        References
        ----------
        BKM12-39.
        """
        return Declaration(
            constraints=tuple(Constraint(dot(desc.omega - w, n)) for w, n, _, _ in desc.bodies)
        )


EFFECTS: dict[str, Effect] = {
    e.name: e
    for e in (
        Gyrostat(
            "gyrostat",
            "a rotor spinning at a constant relative rate: constant gyrostatic momentum K "
            "(K01 §4, BKM12 §2.3)",
            "parameters K1, K2, K3; the term (K, omega) in T",
            excludes=("variable_gyrostat",),
            cites=(("equations", "K01-4.1"), ("integrals", "K01-4.2")),
        ),
        VariableInertia(
            "variable_inertia",
            "periodically varying inertia I(t) = diag(I1 + (J_off + delta sin(Omega t))^2, I2, "
            "I3 + (J_off + delta sin(Omega t))^2) (BM20 (3.4): two masses moving along Cx2)",
            "parameters J_off, delta, Omega; I becomes the constant part",
            cites=_PERIODIC_CITES,
        ),
        VariableGyrostat(
            "variable_gyrostat",
            "periodically varying gyrostatic momentum k(t) = K sin(Omega t) (BM20 (3.5)); "
            "the state M is then BM20's total momentum I omega + D gamma x (omega x gamma) + k",
            "parameters K1, K2, K3, Omega; excludes the constant gyrostat",
            excludes=("gyrostat",),
            cites=_PERIODIC_CITES,
        ),
        ContactPoint(
            "contact_point",
            "track the space-fixed horizontal frame alpha, beta and the contact point x, y "
            "(BKM12-6, K01-2.4..2.6)",
            "states alpha, beta, x, y; parameter b (ball radius)",
        ),
        Rubber(
            "rubber",
            "no twist at the contact: the extra constraint (omega, gamma) = 0 (rubber ball, "
            "BKM12 §3); its multiplier is eliminated by the engine",
            "no new states or parameters; (M, M) is no longer an integral",
            cites=(("rubber", "BKM12 §3 (rubber ball)"),),
        ),
        StraightLine(
            "straight_line",
            "the ball rolls along a straight line of the plane: the extra constraint "
            "(omega, alpha) = 0 (Veselovs' system, BKM12 §3, (57)-(58))",
            "states alpha, beta (the space-fixed horizontal frame)",
            cites=(("straight_line", "BKM12-57"),),
        ),
        Potential(
            "potential",
            "the potential U = k (x, x)/2 + sum_i c_i/(2 x_i^2) acting on the centre "
            "(M03 (1.6)); the integral K takes its term (M03 (1.7))",
            "parameters k, c1, c2, c3",
            cites=(("integrals", "M03-1.7"),),
        ),
        RubberBalls(
            "rubber_balls",
            "the supporting balls roll without slipping and without twisting (BKM12 §2.2): "
            "the support tensor becomes sum_k lambda_k (1/r_k^2 - 1) n_k ⊗ n_k",
            "no new states; the support parameters keep their meaning (modified D tensor)",
            cites=(("rubber_balls", "BKM12-2.2"),),
        ),
    )
}


def parse_effects(effects: str | Iterable[str] | None, supported: Iterable[str]) -> frozenset[str]:
    """Validate a set of effect names against what a system supports.

    Checks names, conflicts and requirements only: nothing is derived, so a bad
    combination is refused at once.

    Parameters
    ----------
    effects : str or iterable of str or None
        Comma-separated string or names; None or "" means no effects.
    supported : iterable of str

    Returns
    -------
    frozenset of str

    Raises
    ------
    UserInputError
        For an unknown or unsupported effect (the message lists the valid names), two
        effects that exclude each other, or an effect without one it requires.
    """
    if effects is None:
        return frozenset()
    if isinstance(effects, str):
        names = [e.strip() for e in effects.split(",") if e.strip()]
    elif isinstance(effects, Iterable):
        names = [str(e).strip() for e in effects]
    else:
        raise UserInputError(f"effects = {effects!r}: give effect names (a list or 'a,b')")
    supported = sorted(supported)
    bad = [n for n in names if n not in supported]
    if bad:
        raise UserInputError(
            f"unknown effect {bad[0]!r}; this system supports: {', '.join(supported) or 'none'}"
        )
    chosen = frozenset(names)
    for name in sorted(chosen):
        effect = EFFECTS[name]
        for other in sorted(chosen & set(effect.excludes)):
            raise UserInputError(
                f"effects {name!r} ({effect.adds}) and {other!r} ({EFFECTS[other].adds}) "
                "exclude each other: choose one of them"
            )
        missing = [r for r in effect.requires if r not in chosen]
        if missing:
            raise UserInputError(
                f"effect {name!r} needs the effect(s) {', '.join(map(repr, missing))}: "
                f'add them (effects="{",".join(sorted(chosen | set(missing)))}")'
            )
    return chosen
