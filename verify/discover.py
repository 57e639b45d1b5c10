"""``chaplygin.discover``: first integrals found in a stated class, each then proved.

The search is :func:`chaplygin.derive.discovery.find_polynomial_integrals` (exact linear
algebra modulo the phase-space ideal; its rank proves that the class holds no other
integral). Each integral found is then decided independently by the verifier's own
machinery: its Lie derivative along the model (:func:`.identity.lie_derivative`, which
expands the auxiliary symbols such as ``omega``) is decided by :func:`.identity.decide`
(a Groebner normal form modulo the phase-space constraints).
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from dataclasses import dataclass

import sympy as sp
from chaplygin.derive.densities import DensitySearch, find_invariant_densities
from chaplygin.derive.discovery import IntegralSearch, find_polynomial_integrals
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.rolling_system import RollingSystem

from .identity import Domain, Outcome, decide, lie_derivative, measure_residual

__all__ = ["Discovery", "discover"]


@dataclass(frozen=True)
class Discovery:
    """The integrals found in a class and the verdict on each.

    Attributes
    ----------
    search : IntegralSearch
        The basis found, the class searched, the rank and the time of the search.
    proofs : tuple of Outcome
        One verdict per integral of ``search.integrals`` (``proved`` expected).
    seconds : float
        Wall time of the search and the proofs.
    """

    search: IntegralSearch
    proofs: tuple[Outcome, ...]
    seconds: float
    densities: DensitySearch | None = None
    density_proof: Outcome | None = None

    @property
    def all_proved(self) -> bool:
        """True when every integral found (and the density found) is proved."""
        proofs = (*self.proofs, *(() if self.density_proof is None else (self.density_proof,)))
        return all(p.verdict == "proved" for p in proofs)

    def density_dict(self) -> dict | None:
        """The density search as plain data (None when it was not asked for).

        Returns
        -------
        dict or None
            ``family`` (the factors), ``density`` and its verdict, or ``none`` with the
            certificate (``rank`` and ``augmented_rank``), the free ``directions`` and the
            time.
        """
        d = self.densities
        if d is None:
            return None
        out = {
            "family": [sp.sstr(g) for g in d.factors],
            "rank": d.rank,
            "augmented_rank": d.augmented_rank,
            "directions": [[sp.sstr(e) for e in v] for v in d.directions],
            "seconds": round(d.seconds, 3),
        }
        if d.found:
            proof = self.density_proof
            out["density"] = sp.sstr(d.density())
            out["verdict"] = proof.verdict
            out["method"] = proof.method
        else:
            out["density"] = None
            out["none"] = (
                f"rank {d.rank} < augmented rank {d.augmented_rank}: no density of the form "
                "prod |g_j|^(a_j) in this family"
            )
        return out

    def as_dict(self) -> dict:
        """The discovery as plain data (JSON-ready).

        Returns
        -------
        dict
            ``model``, ``class`` (words and data), ``integrals`` (each with its verdict,
            method and seconds), ``unknowns``, ``rank``, ``dimension``, ``equations``,
            ``seconds`` and ``stage_seconds``.
        """
        s = self.search
        return {
            "model": s.model,
            "class": {"description": s.search_class.describe(), **s.search_class.as_dict()},
            "integrals": [
                {
                    "expression": sp.sstr(F),
                    "verdict": p.verdict,
                    "method": p.method,
                    "seconds": round(p.seconds, 3),
                }
                for F, p in zip(s.integrals, self.proofs, strict=True)
            ],
            "no_other": (
                f"rank {s.rank} of {s.unknowns} unknowns: the class holds exactly "
                f"{s.dimension} independent integrals modulo constants and the ideal"
            ),
            "unknowns": s.unknowns,
            "rank": s.rank,
            "dimension": s.dimension,
            "equations": s.equations,
            "monomials": s.monomials,
            "seconds": round(self.seconds, 3),
            "stage_seconds": {k: round(v, 3) for k, v in s.stage_seconds.items()},
            "density_search": self.density_dict(),
        }


def discover(
    system: str | RollingSystem,
    effects: Iterable[str] | str = (),
    *,
    degree: int = 2,
    coefficient_degree: int = 2,
    momentum: str | None = None,
    in_parameters: bool = False,
    densities: bool = False,
) -> Discovery:
    """Find every first integral of a system in a polynomial class, and prove each.

    Parameters
    ----------
    system : str or RollingSystem
        A system's name (``chaplygin_ball`` ..., or one registered), or a description
        (registered under its name).
    effects : iterable of str or str, optional
        Effects of the variant (``gyrostat``, ``rubber`` ...; a string is comma-separated).
    degree : int, optional
        Largest degree in the momentum group.
    coefficient_degree : int, optional
        Largest degree of the coefficients in the other state variables.
    momentum : str, optional
        The group the integrals are polynomial in (a state group, or ``"omega"``).
    in_parameters : bool, optional
        Coefficients rational functions of the parameters (default rational numbers).
    densities : bool, optional
        Also search the invariant densities of the family of powers of the right-hand
        side's denominator factors (:func:`~chaplygin.derive.densities.find_invariant_densities`)
        and prove the one found by Liouville's equation (:func:`.identity.measure_residual`).

    Returns
    -------
    Discovery

    Raises
    ------
    UserInputError
        An unknown system or effect, a bad degree or group, a time-dependent model, a
        class too large for the machine (with its size).

    Examples
    --------
    >>> import chaplygin
    >>> found = chaplygin.discover("chaplygin_ball", degree=1, coefficient_degree=1)
    >>> [sympy.sstr(F) for F in found.search.integrals], found.all_proved  # doctest: +SKIP
    (['M1*gamma1 + M2*gamma2 + M3*gamma3'], True)
    """
    from chaplygin.derive.systems import build_model, register_system

    start = time.perf_counter()
    if isinstance(system, RollingSystem):
        system = register_system(system).name
    if not isinstance(system, str):
        raise UserInputError(f"the system must be a name or a RollingSystem, not {system!r}")
    model = build_model(system, effects if isinstance(effects, str) else list(effects))
    search = find_polynomial_integrals(
        model,
        degree,
        momentum=momentum,
        coefficient_degree=coefficient_degree,
        in_parameters=in_parameters,
    )
    proofs = tuple(decide([lie_derivative(F, model)], Domain(model)) for F in search.integrals)
    density_search = density_proof = None
    if densities:
        density_search = find_invariant_densities(model)
        if density_search.found:
            residual = measure_residual(density_search.density(), model)
            density_proof = decide([residual], Domain(model))
    return Discovery(
        search, proofs, time.perf_counter() - start, density_search, density_proof
    )
