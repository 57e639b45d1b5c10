"""A rolling system a researcher describes: body, support, contact, fields — no code to edit.

:class:`RollingSystem` is the public description. It names the body (mass, inertia
tensor in body axes — any symmetric positive-definite matrix, symbolic or numeric —,
centre of mass anywhere inside it, a spherical surface of radius ``b``), the support,
the contact condition and the fields (gravity, a potential of the orientation, a
constant gyrostatic momentum). :meth:`RollingSystem.mechanical_description` turns it into
the same :class:`~.description.MechanicalDescription` the built-in ball is made of, and
:func:`~.description.form_model` derives the reduced equations by the same
Lagrange–d'Alembert route (:class:`~.rigid_body.RigidBodyReduction`): nothing of the
equations is typed in.

The body frame is the frame of the given inertia tensor, with origin at the centre of
mass; ``gamma`` is the upward normal of the support in body axes; the contact point is
``r = -a - b gamma`` from the centre of mass (``a`` the centre of mass seen from the
sphere's centre). The state is the angular momentum ``M`` about the contact point and
``gamma``. Gravity ``g`` adds ``V = m g (a, gamma)`` (the height of the centre of mass
above the plane, less the constant ``m g b``).

What it derives today: a body with a spherical surface on a fixed plane, on a plane
rotating about a fixed vertical axis at a constant or prescribed rate ``Omega(t)``
(``support="rotating_plane"``), on a plane moving horizontally with a prescribed velocity
``(V1(t), V2(t))`` in the fixed frame (``support="moving_plane"``), or on a fixed sphere of
radius ``R`` (``support="sphere"``, the body ``side="outside"`` or ``"inside"`` it), rolling
without slipping (``contact="rolling"``) or without slipping and twisting (``"rubber"``).

``gamma`` is the support's normal at the contact, pointing into the body (on a plane: up;
outside a sphere: away from its centre; inside: towards it). On a sphere it is no longer
fixed in space but turns at ``s = R/(R + b)`` (outside) or ``R/(R - b)`` (inside) of
Poisson's rate, ``gamma' = s gamma x omega`` (the body's geometric centre moves on the
sphere of radius ``R +- b`` and rolls without slipping). A field on a sphere needs the
vertical: the state gains ``zeta``, the upward unit vector in body axes (fixed in space,
Poisson's equation); the body's centre is at ``c gamma`` from the sphere's centre (``c = R +
b`` outside, ``-(R - b)`` inside), so gravity's potential is ``m g (c (gamma, zeta) + (a,
zeta))`` and a potential may use ``zeta`` beside ``gamma``. The effect ``contact_point``
there adds the fixed frame ``alpha, beta, zeta`` (``zeta`` starts as ``gamma`` unless a
field put it in the state): the contact point is ``+-R ((gamma, alpha), (gamma, beta),
(gamma, zeta))`` from the centre.

On a rotating plane the constraint is affine: the body's contact point moves with the
plane, ``v + omega x r = Omega gamma x rho``, ``rho`` the contact point's position from
the axis in body axes (a state group, ``rho' = Omega gamma x rho + b omega x gamma +
rho x omega``; ``(rho, gamma) = 0`` on the phase space, the invariant relation
``(rho,gamma)``); the energy is not an integral (the plane does work); a rubber body
does not twist relative to the plane, ``(omega, gamma) = Omega`` (an affine constraint on
omega alone). On a moving plane ``v + omega x r = V1 alpha + V2 beta``: the state gains
the fixed horizontal axes ``alpha, beta`` (Poisson vectors, with ``gamma`` a frame).
The rates and velocities are expressions of the time ``t`` and the parameters.

A convex body ``f(x) = 0`` (``surface="..."``, an expression of ``x1, x2, x3`` in body axes
from the point ``centre_of_mass`` is measured from) rolls without slipping, or without
slipping and twisting, on a plane — fixed, rotating (``Omega`` constant or of ``t``) or
moving (``V(t)``) —, with gravity and a gyrostat: the body-frame stage of a body on a sphere
(:mod:`.body_on_sphere`) with curvature ``0``; the state is ``omega`` and the contact point
``r`` from the centre of mass (``(dn/dr + n n^T) r' = n x omega``, ``n = -grad f/|grad f|``
the upward normal), the integrals the energy (on the fixed plane) and the surface's level
``f`` (the contact point stays on it). On a rotating plane the state gains the contact's
position ``rho`` from the axis (``rho' = Omega n x rho + r' + rho x omega``, the relation
``(rho, grad f) = 0``) and, at a constant rate, rolling or rubber, the energy in the plane's
frame ``J = E - Omega (n, I omega + K + m (rho - r) x v)`` is an integral; on a moving plane
the fixed axes ``alpha, beta`` (a constant velocity changes nothing: only ``V'`` enters). A
rubber body ships ``(omega, n) - Omega`` (zero on the phase space).

The gyrostat may be prescribed, ``K(t)`` (rotors whose motors set the spin), and the
inertia may change with time, ``I(t)`` (masses moving in symmetric pairs along lines
through the centre of mass): ``T`` depends on ``t``, there is no energy integral, and the
momentum integrals are kept where ``P' = P x omega`` still holds.

A ball rolls without slipping on a fixed support surface ``F(p) = 0``
(``support="surface"``, with gravity), in the fixed frame: a homogeneous one by
:mod:`.ball_on_support` (state ``omega`` and the contact point ``p``), any other (any
inertia, also ``I(t)``, any rotor, also ``K(t)``, any centre of mass, a potential of ``p``
and the axes, rubber rolling) by :mod:`.ball_on_support_general` (with the body axes ``e1,
e2, e3``); a convex body ``f(x) = 0`` (``surface=``) rolls or rubber rolls on it with the
same fields by :mod:`.body_on_support` (the state gains its contact point ``r``, body axes;
the integrals ``H``, ``F`` and ``f``; the body or the support a quadric). In a spherical
support of balls (``support="balls"``, BKM12 §2.1-2.3): :mod:`.rolling_balls`.

A convex body also rolls, or rubber rolls (``(omega, n) = 0``), on a fixed sphere: M03
§2's stage with the signed curvature ``k = -1/R`` outside, ``1/R`` inside, ``(k Id +
dn/dr) r' = n x omega``. A field there adds the vertical ``zeta`` to the state (``zeta' =
zeta x omega``), the weight ``-m g zeta`` at the centre of mass and ``-m g (r + n/k,
zeta)`` to the energy (the centre of mass's height above the sphere's centre); a
potential may use ``zeta`` beside ``gamma = n(r)``, its torque ``-d(dV/dt)/d omega``
along the motion, ``n' = n x omega - k r'``. The effect ``contact_point`` adds the fixed
frame ``alpha, beta, zeta`` (``zeta`` given): the contact point is ``+-R ((n, alpha), (n,
beta), (n, zeta))`` from the sphere's centre.

Rolling along a line ``alpha`` of the plane (``contact="line"``, ``(omega, alpha) = 0``,
BKM12-57's constraint) is derived on every plane, for a spherical or a convex body. On a
fixed or a moving plane the line is fixed in space (a translated plane keeps it): ``alpha,
beta`` are Poisson vectors. A rotating plane carries it: a horizontal vector turning at
``Omega`` about the vertical has, in body axes, ``alpha' = alpha x omega + Omega gamma x
alpha`` (``beta`` likewise), and the body does not spin about the line relative to the
plane, ``(omega - Omega gamma, alpha) = (omega, alpha) = 0`` (``alpha`` is horizontal);
``Omega`` constant or of ``t``. Shipped there: the constraint ``(omega,alpha)`` and
``(rho,gamma)`` (zero on the phase space), the frame's relations; no energy (the plane does
work); at a constant rate a spherical body's ``J`` (the line's reaction does no work in the
turning frame on ``(omega, alpha) = 0``, a relation of its momentum; a convex body's ``J``
holds there too, but its ``omega`` is state and off that level ``J`` changes: not shipped).
The contact trace is not taken there (its space-fixed axes are not the carried ``alpha,
beta``): ``(rho, alpha), (rho, beta)`` are the contact's place in the plane's frame.
A line on a sphere, and every other support, contact and surface the issue lists, is
refused with a message that says so — before any work.

Every text a user types is read by :func:`~.expression_text.parse_expression` (no ``eval``);
the checks of :meth:`RollingSystem.__post_init__` run before anything is derived: a singular
or indefinite inertia tensor, a non-positive mass or radius, a centre of mass outside the
body, a potential of anything but the orientation, names that clash with the state, an
unknown support or contact.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from .description import MechanicalDescription, apply_effects, form_model
from .effects import parse_effects
from .errors import UserInputError
from .expression_text import parse_expression
from .model import Model
from .model_store import described_model
from .rigid_body import RigidBodyReduction
from .rolling_balls import ball_values, balls_description, read_balls
from .rolling_centre import _centre_surface_description, _read_centre_surface
from .rolling_surfaces import (
    CENTRE,
    SUPPORT_CONFIGURATION,
    _convex_body_description,
    _declare_parameters,
    _jacobi_integral,
    _line_frame,
    _normal_rate_factor,
    _read_support_surface,
    _read_surface,
    _support_surface_description,
    _trace_on_normal,
    _used_parameters,
)
from .vectors import cross, dot, vector

__all__ = ["RollingSystem", "SUPPORTS", "SIDES", "CONTACTS", "RESERVED_NAMES", "SUPPORTED_EFFECTS"]

#: Effects a described system may take (the contact trace; rolling along the line alpha);
#: which of them a description takes depends on its support (:attr:`RollingSystem.effects_taken`).
SUPPORTED_EFFECTS = ("contact_point", "straight_line")

#: Supports a description may name, and whether this version derives them.
SUPPORTS = {
    "plane": True,
    "rotating_plane": True,
    "moving_plane": True,
    "sphere": True,
    "surface": True,
    "balls": True,
}
#: Sides of a fixed sphere the body may roll on.
SIDES = ("outside", "inside")
#: Contact conditions, and whether this version derives them.
CONTACTS = {"rolling": True, "rubber": True, "line": True}
#: The space-fixed vectors a contact forbids spinning about (rubber: the normal).
_NO_SPIN_ABOUT = {"rolling": (), "rubber": ("gamma",), "line": ("alpha",)}
#: The effects a described spherical body takes, by support (a convex body: none; along a
#: line the contact already is BKM12's straight_line).
_EFFECTS_BY_SUPPORT = {
    "plane": SUPPORTED_EFFECTS,
    "rotating_plane": ("contact_point",),
    "moving_plane": ("contact_point",),
    "sphere": ("contact_point",),
}
#: Names a parameter cannot take: the state, the velocities, time and the functions.
RESERVED_NAMES = frozenset(
    {
        f"{n}{i}"
        for n in ("M", "gamma", "omega", "v", "alpha", "beta", "rho", "zeta", "p")
        for i in (1, 2, 3)
    }
    | {"x", "y"}
    | {f"Adj{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3)}
    | {f"e{i}_{j}" for i in (1, 2, 3) for j in (1, 2, 3)}  # a ball's axes on a surface
    | {"t", "Delta", "Z", "pi", "E", "I"}
)


def _entries(value: Any, shape: int, what: str) -> list[Any]:
    if isinstance(value, (str, bytes)) or not isinstance(value, (Sequence, sp.MatrixBase)):
        raise UserInputError(f"{what}: expected {shape} entries, got {value!r}")
    items = list(value)
    if len(items) != shape:
        raise UserInputError(f"{what}: expected {shape} entries, got {len(items)}")
    return items


def _inertia_entries(value: Any) -> list[list[Any]]:
    """3 moments (principal axes) or a 3 x 3 matrix, as rows."""
    if isinstance(value, sp.MatrixBase):
        if value.shape != (3, 3):
            raise UserInputError(f"inertia: expected a 3 x 3 matrix, got shape {value.shape}")
        return [list(value.row(i)) for i in range(3)]
    rows = _entries(value, 3, "inertia")
    if all(isinstance(r, (Sequence, sp.MatrixBase)) and not isinstance(r, str) for r in rows):
        return [_entries(r, 3, f"inertia row {i + 1}") for i, r in enumerate(rows)]
    return [[rows[i] if i == j else 0 for j in range(3)] for i in range(3)]


def _names_in(value: Any) -> set[str]:
    """The names a typed value uses (read with free names, nothing evaluated)."""
    if value is None:
        return set()
    if isinstance(value, (list, tuple)) or isinstance(value, sp.MatrixBase):
        return set().union(*(_names_in(v) for v in value)) if len(value) else set()
    expr = parse_expression(value, {"pi": sp.pi}, "description", free_names=True)
    return {s.name for s in expr.free_symbols}


@dataclass(frozen=True)
class RollingSystem:
    """A rigid body rolling on a support, described by its mechanics alone.

    Every number or expression may be given as a Python number, a string (read exactly:
    ``"0.1"`` is 1/10; names become parameters) or a sympy expression.

    Parameters
    ----------
    name : str
        The system's name (a Python identifier, not a built-in system's name).
    inertia : 3 numbers/expressions or a 3 x 3 matrix
        Inertia tensor about the centre of mass, in body axes (3 entries: principal
        moments). Symmetric and positive definite. It may change with the time ``t``:
        ``T = (omega, I(t) omega)/2 + ...``, the Lagrangian of masses moving inside the
        body in symmetric pairs along lines through the centre of mass (BM20's ball);
        then there is no energy integral.
    mass : number or str, default "m"
    radius : number or str, default "b"
        Radius of the body's spherical surface (not read with ``surface``).
    centre_of_mass : 3 numbers/expressions, default (0, 0, 0)
        Position of the centre of mass from the sphere's centre (from the origin of
        ``surface``'s coordinates), body axes.
    surface : str or sympy.Expr, optional
        A convex body ``f(x1, x2, x3) = 0`` instead of a sphere (``f < 0`` inside), on a
        plane (fixed, rotating or moving) or a fixed sphere, rolling or rubber, or rolling
        on a support surface. The equations hold on every level set of ``f`` (the contact
        point ``r`` chooses it): a name only in ``f``'s constant term (a sphere's radius) is
        not a parameter, nor is a constant plane velocity.
    gravity : number or str, optional
        Strength ``g`` of a constant field along ``-gamma``; None: no field.
    gyrostat : 3 numbers/expressions, optional
        A gyrostatic momentum ``K`` (body axes): ``T`` gains ``(K, omega)``; constant, or
        prescribed as expressions of the time ``t`` (rotors whose spin motors set:
        ``M' = (M + K) x omega - K' + ...``, no energy integral then).
    potential : str or sympy.Expr, optional
        A potential of the orientation: an expression of ``gamma1, gamma2, gamma3`` and
        the parameters (on a sphere also of the vertical ``zeta1, zeta2, zeta3``); with
        ``centre_surface`` a potential of the centre's position ``x1, x2, x3``; with
        ``support_surface`` of the contact point ``p1, p2, p3`` and the body axes'
        fixed-frame components ``e1_1 .. e3_3``.
    contact : {"rolling", "rubber", "line"}
        Rolling without slipping, without slipping and twisting (``(omega, gamma) =
        0``), or without slipping along the line ``alpha`` (``(omega, alpha) = 0``, the
        effect ``straight_line``: the frame ``alpha, beta`` joins the state, fixed in space
        or, on a rotating plane, carried by it; a rubber body on a line is
        ``contact="rubber"`` with the effect).
    support : {"plane", "rotating_plane", "moving_plane", "sphere", "surface"}
        The fixed horizontal plane, a horizontal plane rotating about a vertical axis or
        moving horizontally, a fixed sphere, or a fixed support surface (``support_surface``).
    support_radius : number or str, optional
        Radius ``R`` of the fixed sphere (``support="sphere"`` only).
    rotation_rate : number or str, optional
        ``Omega``, the angular velocity of a rotating plane about its vertical axis, a
        constant or an expression of the time ``t`` (``support="rotating_plane"`` only).
    plane_velocity : 2 numbers/expressions, optional
        The horizontal velocity ``(V1, V2)`` of a moving plane along the fixed axes,
        constants or expressions of ``t`` (``support="moving_plane"`` only).
    support_surface : str or sympy.Expr, optional
        ``F(p1, p2, p3)`` of a fixed support surface ``F = 0`` in the fixed frame (``p3``
        up, ``F < 0`` inside the support; ``support="surface"`` only): a ball rolls on it,
        with gravity along ``-p3`` and a potential; the state is ``omega`` and the contact
        point ``p`` in the fixed frame, and unless the ball is homogeneous (and free of a
        potential and of ``I(t)``) its body axes ``e1, e2, e3`` (fixed-frame components); a
        convex body (``surface``) also its contact point ``r`` (body axes).
    centre_surface : str or sympy.Expr, optional
        Instead of ``support_surface``: ``F(x1, x2, x3)``, the surface a homogeneous ball's
        centre moves on (the support is its parallel surface at the radius, M03 §1); the
        state is ``omega`` and the centre ``x`` in the fixed frame (``x3`` up), gravity
        along ``-x3`` and ``potential`` a function of ``x``.
    balls : sequence of mappings, optional
        ``support="balls"`` (only): a body in a spherical support, each ball ``{"moment":
        lambda_k, "ratio": R_k/R0, "direction": n_k}`` (``n_k`` three exact numbers, the
        space-fixed contact direction); see :mod:`.rolling_balls`.
    side : {"outside", "inside"}
        The body rolls on the outside of the fixed sphere (support surface), or inside it
        (a spherical shell; then ``R > b``).
    positive : sequence of str, optional
        Parameters known positive beyond those that are (mass, radius, the diagonal
        moments and ``g`` when each is a single name).
    description : str
        One line saying what the system is.

    Raises
    ------
    UserInputError
        For any of the refusals listed in the module docstring, on construction.

    Examples
    --------
    >>> s = RollingSystem("routh_sphere", inertia=("A", "A", "C"), centre_of_mass=(0, 0, "a"),
    ...                   gravity="g")
    >>> s.parameter_names
    ('m', 'b', 'A', 'C', 'a', 'g')
    """

    name: str
    inertia: Any
    mass: Any = "m"
    radius: Any = "b"
    centre_of_mass: Any = (0, 0, 0)
    gravity: Any = None
    gyrostat: Any = None
    potential: Any = None
    contact: str = "rolling"
    support: str = "plane"
    support_radius: Any = None
    side: str = "outside"
    rotation_rate: Any = None
    plane_velocity: Any = None
    support_surface: Any = None
    balls: Any = None
    centre_surface: Any = None
    surface: Any = None
    positive: Sequence[str] = ()
    description: str = ""
    _parsed: dict = field(default=None, init=False, repr=False, compare=False)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise UserInputError(f"system name must be an identifier, got {self.name!r}")
        _check_choice("support", self.support, SUPPORTS)
        _check_choice("contact", self.contact, CONTACTS)
        if self.side not in SIDES:
            raise UserInputError(f"unknown side {self.side!r}; valid: {', '.join(SIDES)}")
        object.__setattr__(self, "_parsed", _parse(self))

    # ------------------------------------------------------------------ parsed data
    @property
    def effects_taken(self) -> tuple[str, ...]:
        """The effects this description takes (:data:`SUPPORTED_EFFECTS` on a fixed
        plane; the contact trace on a moving plane or a fixed sphere and for a convex body
        there; none on a support surface, nor along the line a turntable carries: its frame
        is the state's ``alpha, beta``)."""
        if self.contact == "line" and self.support == "rotating_plane":
            return ()
        if self._parsed["surface"] is not None:  # the trace on a plane or a fixed sphere
            return () if self.support == "surface" else ("contact_point",)
        if self.contact == "line":
            return ("contact_point",)
        return _EFFECTS_BY_SUPPORT.get(self.support, ())

    @property
    def parameter_conditions(self) -> tuple[tuple[sp.Expr, str], ...]:
        """What the parameters' values must satisfy for the description to be a body, where
        the exact checks on construction could not decide it (symbolic values): each
        expression must be positive (checked when values are given, by
        :func:`~chaplygin.numerics.inputs.pack_params`).

        Returns
        -------
        tuple of (sympy.Expr, str)
            The expression and what it says: a leading minor of the inertia tensor, the
            centre of mass inside the ball (``b^2 - |a|^2``) or the convex body (``-f`` at
            it), the body inside the fixed sphere (``R - b``).
        """
        return self._parsed["conditions"]

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """The parameters, in order of first appearance (mass, radius, inertia, ...)."""
        return tuple(s.name for s in self._parsed["parameters"])

    @property
    def inertia_matrix(self) -> sp.Matrix:
        """The inertia tensor about the centre of mass (exact sympy)."""
        return self._parsed["inertia"]

    def fingerprint(self) -> str:
        """A hash of the parsed description: the key of its derived files in the caches.

        Returns
        -------
        str
            64 hexadecimal digits; equal for descriptions that derive the same model.
        """
        p = self._parsed
        text = "|".join(
            [
                self.name,
                self.support,
                self.contact,
                self.side if self.support in ("sphere", "surface") else "",
                sp.srepr(p["support_radius"]),
                sp.srepr(p["rotation_rate"]),
                sp.srepr(p["plane_velocity"]),
                sp.srepr(p["surface"]),
                sp.srepr(p["inertia"]),
                sp.srepr(p["mass"]),
                sp.srepr(p["radius"]),
                sp.srepr(p["centre"]),
                sp.srepr(p["rotor_momentum"]),
                sp.srepr(p["potential"]),
                ",".join(f"{s.name}:{s.is_positive}" for s in p["parameters"]),
            ]
            # (absent unless given: the other descriptions keep their fingerprints)
            + ([] if p["support_surface"] is None else [sp.srepr(p["support_surface"])])
            + ([] if p["centre_surface"] is None else ["centre", sp.srepr(p["centre_surface"])])
            + ([] if p["balls"] is None else ["balls", sp.srepr(p["balls"])])
            + ([] if p["field"] == 0 else ["field", sp.srepr(p["field"])])
        )
        return hashlib.sha256(text.encode()).hexdigest()

    # ------------------------------------------------------------------ derivation
    def mechanical_description(
        self, effects: frozenset[str] | Sequence[str] = ()
    ) -> MechanicalDescription:
        """The description the reduction stage derives the equations of.

        ``T = (omega, I omega)/2 + m (v, v)/2 + (K, omega)`` with ``v`` the centre of
        mass's velocity; no slip ``v + omega x r = 0`` with ``r = -a - b gamma``; with
        ``"rubber"`` also ``(omega, gamma) = 0``; ``V = m g (a, gamma) + potential``.
        On a sphere ``gamma' = s gamma x omega`` (see the module docstring).

        Parameters
        ----------
        effects : iterable of str, optional
            Any of :attr:`effects_taken` (``"contact_point"``: the space-fixed frame
            ``alpha, beta`` and the contact point ``x, y``, for traces in the plane;
            ``"straight_line"``: rolling along ``alpha``).

        Returns
        -------
        MechanicalDescription

        Raises
        ------
        UserInputError
            An effect a described system does not take.
        """
        effects = parse_effects(effects, self.effects_taken)
        if self.support == "balls":
            return balls_description(self, _principal_symbols(self._parsed["inertia"]))
        if self._parsed["surface"] is not None:
            return _convex_body_description(self, effects)
        if self.support == "surface":
            return (
                _support_surface_description(self)
                if self._parsed["centre_surface"] is None
                else _centre_surface_description(self)
            )
        p = self._parsed
        t = sp.Symbol("t", real=True)
        omega, v = vector("omega", real=True), vector("v", real=True)
        gamma = vector("gamma", real=True)
        names = tuple(s.name for s in p["parameters"])
        desc = MechanicalDescription(
            system=self.name,
            effects=effects,
            time=t,
            omega=omega,
            reduction=RigidBodyReduction(momentum="M", gyrostatic="K"),
            parameter_order=names,
            v=v,
            inertia=p["inertia"],
            moments=_principal_symbols(p["inertia"]),
        )
        m, b, a, K = p["mass"], p["radius"], p["centre"], p["rotor_momentum"]
        desc.add_kinetic_energy(m * dot(v, v) / 2 + dot(K, omega))
        desc.contact_vector, desc.centre_offset = -a - b * gamma, -a
        desc.trace_on_normal = _trace_on_normal(self, p)
        desc.add_state("M", tuple(vector("M", real=True)), None)
        desc.add_poisson_vector("gamma", _normal_rate_factor(self, p))
        # the body's contact point moves with the support (zero but on a rotating plane)
        support_velocity = sp.zeros(3, 1)
        if self.support == "rotating_plane":
            rho, Omega = vector("rho", real=True), p["rotation_rate"]
            support_velocity = Omega * cross(gamma, rho)
            # the geometric contact point moves as the sphere's centre O: v_O = Omega gamma
            # x rho + b omega x gamma; in body axes rho' = v_O - omega x rho
            rate = support_velocity + b * cross(omega, gamma) + cross(rho, omega)
            desc.add_position("rho", rho, rate)
            # horizontal: zero on the phase space (the verifier projects rho onto it)
            desc.add_invariant_relation("(rho,gamma)", dot(rho, gamma))
        if self.support == "moving_plane":
            desc.add_frame()  # the fixed axes the plane's velocity is given along
            desc.add_completion(("alpha", "beta"), "frame_bkm12_7")
            V = p["plane_velocity"]
            support_velocity = V[0] * desc.vectors["alpha"] + V[1] * desc.vectors["beta"]
        for c in v + cross(omega, desc.contact_vector) - support_velocity:
            desc.add_constraint(c)
        if self.contact == "line":  # along the line alpha (BKM12-57), a turntable's: carried
            _line_frame(desc, p["rotation_rate"])
        # no twist about gamma (relative to the plane: a turntable turns at Omega about
        # gamma), no spin about alpha
        for along in _NO_SPIN_ABOUT[self.contact]:
            twist = p["rotation_rate"] if along == "gamma" else sp.S.Zero
            desc.add_constraint(dot(omega, desc.vectors[along]) - twist, reacts_along=along)
        desc.add_potential(_potential_energy(self, desc))
        _jacobi_integral(self, desc)
        _declare_parameters(desc, p)
        apply_effects(desc, effects, SUPPORTED_EFFECTS)
        return desc

    def model(self, effects: frozenset[str] | Sequence[str] = ()) -> Model:
        """The model, derived once, then kept in the process and on disk
        (:func:`~.model_store.described_model`: keyed by :meth:`fingerprint`).

        Parameters
        ----------
        effects : iterable of str, optional
            Any of :attr:`effects_taken`.

        Returns
        -------
        Model
        """
        return described_model(self, effects)

    def derive(self, effects: frozenset[str] | Sequence[str] = ()) -> Model:
        """Derive the model now, no cache read or written.

        Parameters
        ----------
        effects : iterable of str, optional
            As for :meth:`model`.

        Returns
        -------
        Model
        """
        return form_model(self.mechanical_description(effects))


def _potential_energy(s: RollingSystem, desc: MechanicalDescription) -> sp.Expr:
    """``m g`` times the centre of mass's height, plus the given potential. On a plane the
    vertical is ``gamma`` (the height ``(a, gamma)`` less the constant ``b``); on a sphere it
    is the state ``zeta`` (added here when a field or the potential needs it) and the
    body's centre is at ``c gamma`` from the sphere's centre (``c = R + b`` outside,
    ``-(R - b)`` inside; ``d/dt c (gamma, zeta) = (b omega x gamma, zeta)``, the centre's
    rise)."""
    p = s._parsed
    gamma, a, potential = desc.vectors["gamma"], p["centre"], p["potential"]
    if s.support != "sphere":
        return p["field"] * p["mass"] * dot(a, gamma) + potential
    zeta = vector("zeta", real=True)
    if p["field"] == 0 and not potential.free_symbols & set(zeta):
        return potential
    desc.add_poisson_vector("zeta")
    R, b = p["support_radius"], p["radius"]
    c = R + b if s.side == "outside" else -(R - b)
    return p["field"] * p["mass"] * (c * dot(gamma, zeta) + dot(a, zeta)) + potential


def _check_choice(what: str, value: object, choices: Mapping[str, bool]) -> None:
    if value not in choices:
        raise UserInputError(f"unknown {what} {value!r}; valid: {', '.join(choices)}")
    if not choices[value]:
        done = ", ".join(k for k, ok in choices.items() if ok)
        raise UserInputError(
            f"{what} {value!r} is not derived by this version of chaplygin (it derives: {done})"
        )


def _parse(s: RollingSystem) -> dict:
    """Read every field exactly, choose the parameters' assumptions, check the physics."""
    rows = _inertia_entries(s.inertia)
    radius = None if s.surface is not None else s.radius  # a convex body has no radius
    typed = [s.mass, radius, rows, s.centre_of_mass, s.gravity, s.support_radius]
    typed += [s.rotation_rate, s.plane_velocity]  # these two may use the time t
    typed += [s.gyrostat, s.potential, s.surface, s.support_surface, s.centre_surface]
    typed += (balls := ball_values(s))  # the balls' moments and ratios
    names: list[str] = []
    for value in typed:
        for n in sorted(_names_in(value)):
            if n not in names and n not in _STATE_NAMES:
                names.append(n)
    uses_time = {"t"} & set().union(
        *(_names_in(v) for v in (s.rotation_rate, s.plane_velocity, s.gyrostat, rows))
    )
    names = [n for n in names if n not in uses_time]
    # a convex body's contact point r and its rate are state (a ball's r1.. are radii)
    convex = {f"{n}{i}" for n in ("r", "rdot") for i in (1, 2, 3)} if s.surface else set()
    clash = sorted(set(names) & (RESERVED_NAMES | convex))
    if clash:
        raise UserInputError(f"parameter names {clash} are reserved (state, velocities, time)")
    positive = set(s.positive) | {
        str(v).strip()
        for v in (s.mass, radius, s.gravity, s.support_radius, *balls,
                  *(rows[i][i] for i in range(3)))  # fmt: skip
        if isinstance(v, str) and str(v).strip().isidentifier()
    }
    unknown = sorted(set(s.positive) - set(names))
    if unknown:
        raise UserInputError(f"positive names {unknown} are not parameters of the description")
    symbols = {
        n: sp.Symbol(n, positive=True) if n in positive else sp.Symbol(n, real=True) for n in names
    }
    scope = {**symbols, "pi": sp.pi}
    read = lambda v, what: parse_expression(v, scope, what)  # noqa: E731
    timed = {**scope, "t": sp.Symbol("t", real=True)}
    read_timed = lambda v, what: parse_expression(v, timed, what)  # noqa: E731
    # constant, or I(t): masses moving inside the body in symmetric pairs along lines
    # through the centre of mass (it stays; their relative motion carries no momentum)
    inertia = sp.Matrix(3, 3, lambda i, j: read_timed(rows[i][j], f"inertia[{i + 1},{j + 1}]"))
    mass = read(s.mass, "mass")
    radius = read(s.radius, "radius") if s.surface is None else None
    centre = sp.Matrix(
        [read(x, "centre_of_mass") for x in _entries(s.centre_of_mass, 3, "centre_of_mass")]
    )
    field_strength = sp.S.Zero if s.gravity is None else read(s.gravity, "gravity")
    vectors = ("gamma", "zeta") if s.support == "sphere" else ("gamma",)
    gamma = {f"{n}{i}": sp.Symbol(f"{n}{i}", real=True) for n in vectors for i in (1, 2, 3)}
    if s.centre_surface is not None:  # a potential of the centre's position
        gamma = dict(CENTRE)
    elif s.support == "surface":  # of the contact point and the body axes (fixed frame)
        gamma = dict(SUPPORT_CONFIGURATION)
    potential = (
        sp.S.Zero
        if s.potential is None
        else parse_expression(s.potential, {**scope, **gamma}, "potential")
    )
    surface = _read_surface(s, scope, centre)
    _check_physics(inertia, mass, radius, centre)
    support_radius = _check_support(s, read, radius)
    rotation_rate = _check_rotation(s, read_timed)
    gyrostat = (  # constant, or prescribed: a rotor whose spin the motors set
        sp.zeros(3, 1)
        if s.gyrostat is None
        else sp.Matrix([read_timed(x, "gyrostat") for x in _entries(s.gyrostat, 3, "gyrostat")])
    )
    plane_velocity = _check_moving(s, read_timed)
    parsed = {"inertia": inertia, "centre": centre, "rotor_momentum": gyrostat,
              "potential": potential, "surface": surface}  # fmt: skip
    centre_surface = _read_centre_surface(s, scope, parsed)
    support_surface = None if centre_surface is not None else _read_support_surface(
        s, scope, parsed
    )
    parsed = {
        "inertia": inertia,
        "mass": mass,
        "radius": radius,
        "centre": centre,
        "rotor_momentum": gyrostat,
        "field": field_strength,
        "support_radius": support_radius,
        "rotation_rate": rotation_rate,
        "plane_velocity": plane_velocity,
        "surface": surface,
        "support_surface": support_surface,
        "centre_surface": centre_surface,
        "potential": potential,
        "no_spin_about": _NO_SPIN_ABOUT[s.contact],  # the contact's forbidden spins
        "balls": read_balls(s, read, parsed),
    }
    parameters = _used_parameters(tuple(symbols[n] for n in names), parsed)
    inside = support_radius if s.side == "inside" and s.support == "sphere" else None
    conditions = _parameter_conditions(inertia, radius, centre, inside, surface, parameters)
    roles = {
        "mass": mass,
        "radius": radius,
        "gravity": field_strength,
        "radius of the fixed sphere": support_radius,
        "angular velocity of the plane": rotation_rate,
    }
    return {**parsed, "parameters": parameters, "conditions": conditions, "roles": roles}


def _check_rotation(s: RollingSystem, read) -> sp.Expr:
    """The rotating plane's angular velocity (zero otherwise); what it refuses."""
    if not _moving_support(s, "rotating_plane", "rotation_rate", "its Omega"):
        return sp.S.Zero
    return read(s.rotation_rate, "rotation_rate")


def _moving_support(s: RollingSystem, support: str, key: str, meaning: str) -> bool:
    """Whether ``s`` rolls on ``support``, a plane moving by the law given as ``key``:
    the law is refused on another support and required on this one."""
    value = getattr(s, key)
    if s.support != support:
        if value is not None:
            raise UserInputError(f"{key} is given but the support is a {s.support}")
        return False
    if value is None:
        raise UserInputError(f"support {support!r} needs {key} ({meaning})")
    return True


#: Names a description's texts use for the state (not parameters).
_STATE_NAMES = (
    *("gamma1", "gamma2", "gamma3", "zeta1", "zeta2", "zeta3", "x1", "x2", "x3"),
    *SUPPORT_CONFIGURATION,  # p1 .. p3 and the body axes e1_1 .. e3_3
)


def _check_moving(s: RollingSystem, read) -> sp.Matrix:
    """The moving plane's velocity along the fixed axes (zero otherwise)."""
    if not _moving_support(s, "moving_plane", "plane_velocity", "its V1, V2"):
        return sp.zeros(2, 1)
    entries = _entries(s.plane_velocity, 2, "plane_velocity")
    return sp.Matrix([read(x, "plane_velocity") for x in entries])


def _check_support(s: RollingSystem, read, radius) -> sp.Expr:
    """The fixed sphere's radius (zero on a plane); what a sphere support refuses."""
    if s.support != "sphere":
        if s.support_radius is not None:
            raise UserInputError(f"support_radius is given but the support is a {s.support}")
        return sp.S.Zero
    if s.support_radius is None:
        raise UserInputError("support 'sphere' needs support_radius (the fixed sphere's R)")
    R = read(s.support_radius, "support_radius")
    if R.is_positive is False or R.is_zero:
        raise UserInputError(f"support_radius must be positive, got {R}")
    if s.side == "inside" and radius is not None and (R - radius).is_number and R - radius <= 0:
        raise UserInputError(
            f"side 'inside': the body of radius {radius} does not fit in a sphere of radius {R}"
        )
    if s.contact == "line":
        raise UserInputError(
            "rolling along a line is derived on a plane only (fixed or moving), not on a sphere"
        )
    return R


def _check_physics(inertia: sp.Matrix, mass: sp.Expr, radius: sp.Expr, centre: sp.Matrix) -> None:
    """Refuse what no body is: every test is exact, and decided only where it can be."""
    for what, value in (("mass", mass), ("radius", radius)):
        if value is None:  # a convex body: its surface is checked by _read_surface
            continue
        if value.is_positive is False or value.is_zero:
            raise UserInputError(f"{what} must be positive, got {value}")
    asym = (inertia - inertia.T).applyfunc(sp.simplify)
    if not asym.is_zero_matrix:
        raise UserInputError("inertia: the tensor is not symmetric")
    minors = [inertia[:k, :k].det() for k in (1, 2, 3)]
    if all(sp.sympify(d).is_number for d in minors):
        if minors[2] == 0:
            raise UserInputError("inertia: the tensor is singular (determinant 0)")
        if not inertia.is_positive_definite:
            raise UserInputError(
                f"inertia: the tensor is not positive definite (leading minors {minors})"
            )
    else:
        for k, d in enumerate(minors, start=1):
            if sp.sympify(d).is_nonpositive:
                raise UserInputError(f"inertia: the leading {k} x {k} minor {d} is never positive")
    distance2 = dot(centre, centre)
    if radius is not None and distance2.is_number and radius.is_number and distance2 >= radius**2:
        raise UserInputError(
            f"centre_of_mass: at distance {sp.sqrt(distance2)} from the centre it is not "
            f"inside the body of radius {radius}"
        )


def _parameter_conditions(
    inertia: sp.Matrix, radius: sp.Expr | None, centre: sp.Matrix, inside: sp.Expr | None,
    surface: sp.Expr | None, parameters: tuple[sp.Symbol, ...],
) -> tuple[tuple[sp.Expr, str], ...]:  # fmt: skip
    """The conditions :func:`_check_physics` and the support's checks leave to the values:
    expressions of the parameters alone (not of time) that must be positive."""
    found = [
        (sp.factor(inertia[:k, :k].det()), f"inertia: its leading {k} x {k} minor")
        for k in (1, 2, 3)
    ]
    if radius is not None and not centre.is_zero_matrix:
        found.append((sp.expand(radius**2 - dot(centre, centre)), "the centre of mass inside "
                      "the ball: b^2 - |centre_of_mass|^2"))  # fmt: skip
    if surface is not None:
        at_centre = surface.xreplace(dict.fromkeys(vector("r", real=True), 0))
        found.append((-at_centre, "the centre of mass inside the convex body: -f there"))
    if inside is not None and radius is not None:
        found.append((inside - radius, "side 'inside': the fixed sphere's radius less the body's"))
    t, names = sp.Symbol("t", real=True), set(parameters)
    return tuple(
        (e, text) for e, text in found
        if not e.is_number and not e.has(t) and e.free_symbols <= names and not e.is_positive
    )  # fmt: skip


def _principal_symbols(inertia: sp.Matrix) -> tuple[sp.Symbol, ...]:
    """The moments as parameters (``A_i = 1/J_ii`` for exact checks) when the tensor is
    ``diag(I1, I2, I3)`` of three distinct symbols."""
    diagonal = [inertia[i, i] for i in range(3)]
    if inertia.is_diagonal() and all(isinstance(d, sp.Symbol) for d in diagonal):
        if len(set(diagonal)) == 3:
            return tuple(diagonal)
    return ()
