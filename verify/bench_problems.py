"""The problems of the work-precision study (:data:`PROBLEMS`), its rows (:class:`BenchRow`),
the cached reference solutions and the error of a final state against them."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import mpmath

from ..derive.errors import UserInputError
from ..numerics.ball.separatrix import separatrix_state as exact_separatrix_state
from ..numerics.code import load_model_code
from ..numerics.inputs import Precision
from ..numerics.integrate import integrate

__all__ = [
    "BenchProblem",
    "BenchRow",
    "PROBLEMS",
    "final_error",
    "reference_solution",
    "separatrix_state",
    "state_strings",
]

#: Part of the reference-cache key: bump when the inputs' meaning changes (2: decimal literals
#: are read with all their digits).
_CACHE_VERSION = 2


@dataclass(frozen=True)
class BenchProblem:
    """One initial-value problem of the study."""

    name: str
    params: dict
    y0: dict
    t_double: float
    t_digits: float
    description: str

    def key(self) -> str:
        """Cache key of the problem's reference solutions.

        Returns
        -------
        str
            The first 16 hex digits of the sha256 of the cache version, name, parameters
            and initial state (not of the spans: those are part of the file name).
        """
        data = [_CACHE_VERSION, self.name, self.params, self.y0]
        return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()[
            :16
        ]


def separatrix_state(
    I: Sequence[float | str] = (1, 2, 3),
    D: float | str = 1,
    C: float | str = 1,
    dps: int = 250,
) -> dict[str, tuple[str, ...]]:
    """``M`` and ``gamma`` at the separatrix point ``t = 0`` of K01-3.4 (C > 0 form).

    ``gamma = (-s32, 0, -s21)``, ``M = C gamma``, computed by
    :func:`chaplygin.numerics.ball.separatrix.separatrix_state` at ``dps + 10`` digits; values as
    decimal strings of ``dps`` digits (the inputs are parsed at the working precision of
    each run).

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia, ``I1 < I2 < I3``.
    D, C : number
        ``D = m b^2`` and ``C = (M, gamma)``.
    dps : int
        Digits of the strings.

    Returns
    -------
    dict of str to tuple of str
        ``{"M": (3 str), "gamma": (3 str)}``.

    Raises
    ------
    UserInputError
        Unless ``I1 < I2 < I3``.

    References
    ----------
    K01-3.4 (corrected for C > 0), K01-3.3seg.
    """
    with mpmath.workdps(dps + 10):
        I1, I2, I3 = (mpmath.mpf(str(v)) for v in I)
        if not I1 < I2 < I3:
            raise UserInputError("the separatrix point needs I1 < I2 < I3")
        y = exact_separatrix_state((I1, I2, I3), mpmath.mpf(str(D)), mpmath.mpf(str(C)))
        return {
            "M": tuple(mpmath.nstr(v, dps, strip_zeros=False) for v in y[:3]),
            "gamma": tuple(mpmath.nstr(v, dps, strip_zeros=False) for v in y[3:6]),
        }


PROBLEMS: dict[str, BenchProblem] = {
    "reference": BenchProblem(
        "reference",
        {"I": (1, 2, 3), "D": 1},
        {"M": ("0.7", "-0.4", "0.5"), "gamma": ("0.2", "0.3", "sqrt(0.87)")},
        1000.0,
        50.0,
        "I=(1,2,3), D=1, gamma0=(0.2,0.3,sqrt(0.87)), M0=(0.7,-0.4,0.5)",
    ),
    "separatrix": BenchProblem(
        "separatrix",
        {"I": (1, 2, 3), "D": 1},
        separatrix_state(),
        50.0,
        50.0,
        "I=(1,2,3), D=1, M = gamma on the separatrix h = h2 (K01-3.4, C=1)",
    ),
}


@dataclass
class BenchRow:
    """One measured (or unavailable) configuration.

    ``median_s`` is the integration alone (``IntegrationResult.wall_s``); for our rows
    ``call_s`` is the median of the whole public call ``integrate(...)`` and ``setup_s``,
    ``evidence_s`` its parts before and after the integration (reading the inputs, loading
    the compiled code; drift evidence and result), all medians of the same runs. For the
    Taylor rows ``propagate_s`` is the median of ``Propagator.propagate_until(T)`` (inputs
    checked and the integrator loaded once, as heyoka's ``taylor_adaptive``; the same steps
    and bits as the ``integrate`` call, drift evidence included).
    """

    problem: str
    method: str
    rhs: str
    precision: str
    rtol: float | None
    T: float
    error: float | None
    drift: dict = field(default_factory=dict)
    median_s: float | None = None
    runs: int = 0
    steps: int | None = None
    nfev: int | None = None
    note: str = ""
    call_s: float | None = None
    setup_s: float | None = None
    evidence_s: float | None = None
    propagate_s: float | None = None

    def to_json(self) -> dict[str, object]:
        """The row as a JSON-ready dict.

        Returns
        -------
        dict of str to object
            ``dataclasses.asdict`` of the row: one entry per field.
        """
        return asdict(self)


# --------------------------------------------------------------------------- reference


def _reference_file(out: Path, problem: BenchProblem, T: float, digits: int) -> Path:
    return out / f"reference_{problem.name}_{problem.key()}_T{T:g}_{digits}d.json"


def reference_solution(
    problem: BenchProblem, T: float, digits: int, out: Path | None
) -> list[mpmath.mpf]:
    """State at ``T`` with at least ``digits`` digits (Taylor; cached in ``out``).

    ``digits <= 34`` uses quad (C ``__float128``, 34 digits), else MPFR at ``digits``;
    the tolerance is the smallest the precision delivers.

    Parameters
    ----------
    problem : BenchProblem
        The initial-value problem (Chaplygin ball).
    T : float
        End time.
    digits : int
        Digits the reference must have at least.
    out : pathlib.Path or None
        Folder of the cached references (read when the file exists, written after a
        computation); None computes without caching.

    Returns
    -------
    list of mpmath.mpf
        The state at ``T`` in model order (six components).

    Raises
    ------
    RuntimeError
        When the Taylor integration fails.
    """
    path = None if out is None else _reference_file(out, problem, T, digits)
    if path is not None and path.exists():
        data = json.loads(path.read_text())
        with mpmath.workdps(data["digits"] + 5):
            return [mpmath.mpf(v) for v in data["y"]]
    prec: str | int = "quad" if digits <= Precision.QUAD_DIGITS else digits
    P = Precision(prec)
    r = integrate(
        "chaplygin_ball",
        problem.y0,
        T,
        problem.params,
        method="taylor",
        precision=prec,
        rtol=P.min_rtol,
        atol=P.min_rtol,
        t_eval=[0, T],
    )
    if not r.success:  # pragma: no cover - the reference problems integrate
        raise RuntimeError(f"reference integration failed: {r.message}")
    ys = list(r.y[:, -1])
    if path is not None:
        got = P.QUAD_DIGITS if P.is_quad else P.digits
        with mpmath.workdps(got + 5):
            text = [mpmath.nstr(v, got + 3, strip_zeros=False) for v in ys]
        path.write_text(
            json.dumps(
                {"problem": problem.name, "T": T, "digits": got, "precision": repr(P),
                 "y": text, "wall_s": r.wall_s},
                indent=1,
            )
        )
    return ys


def final_error(y_final: Sequence, ref: Sequence, digits: int) -> float:
    """The max-norm distance of a final state from the reference, evaluated at ``digits + 10``.

    Parameters
    ----------
    y_final : sequence of numbers
    ref : sequence of mpmath.mpf
    digits : int

    Returns
    -------
    float
    """
    with mpmath.workdps(digits + 10):
        return float(max(abs(mpmath.mpf(v) - r) for v, r in zip(y_final, ref, strict=True)))




def state_strings(problem: BenchProblem, digits: int) -> list[str]:
    """The problem's initial state (model order), as decimal strings of ``digits`` digits.

    Parameters
    ----------
    problem : BenchProblem
    digits : int

    Returns
    -------
    list of str
    """
    from ..numerics.inputs import pack_state

    code = load_model_code("chaplygin_ball")
    with mpmath.workdps(digits + 10):
        y = pack_state(code, problem.y0, Precision(digits + 10))
        return [mpmath.nstr(v, digits + 5, strip_zeros=False) for v in y]
