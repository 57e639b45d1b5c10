"""The result of an integration, with its evidence and a short display."""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass, field

import mpmath
import numpy as np
from mpmath.libmp import prec_to_dps, repr_dps, to_str

__all__ = ["IntegrationResult", "RunNumber", "shown_at"]


class RunNumber(mpmath.mpf):
    """An ``mpmath.mpf`` that shows itself at the precision of the run that computed it.

    ``str`` and ``repr`` of a plain ``mpf`` use the global ``mpmath.mp.dps`` (15 digits unless
    the user changed it), so a 30-digit result would print 15 digits; this subclass keeps the
    run's bits and prints at them, without touching mpmath's global state. It is an ``mpf``
    in every other respect (arithmetic returns plain ``mpf`` at the working precision).

    Parameters
    ----------
    value : mpmath.mpf
    bits : int
        The run's significand bits (:attr:`~chaplygin.numerics.precision.Precision.prec`).

    Examples
    --------
    >>> from mpmath.libmp import dps_to_prec
    >>> with mpmath.workdps(30):
    ...     third = mpmath.mpf(1) / 3
    >>> print(third, RunNumber(third, dps_to_prec(30)))
    0.333333333333333 0.333333333333333333333333333333
    """

    __slots__ = ("_bits",)

    def __new__(cls, value: mpmath.mpf, bits: int) -> RunNumber:
        number = object.__new__(cls)
        number._mpf_ = value._mpf_
        number._bits = int(bits)
        return number

    def __str__(self) -> str:
        return to_str(self._mpf_, prec_to_dps(self._bits))

    def __repr__(self) -> str:
        return f"mpf('{to_str(self._mpf_, repr_dps(self._bits))}')"

    def __reduce__(self):
        return (_run_number, (self._mpf_, self._bits))

    def __getstate__(self):  # (mpf's own drops the bits; __reduce__ keeps them)
        return None


def _run_number(mpf_tuple: tuple, bits: int) -> RunNumber:
    number = object.__new__(RunNumber)
    number._mpf_, number._bits = mpf_tuple, bits
    return number


def shown_at(values: object, bits: int) -> object:
    """``values`` (an mpf, or an object array of them) with every mpf as a
    :class:`RunNumber` of ``bits``; other values (floats, float arrays) as they are.

    Parameters
    ----------
    values : mpmath.mpf, ndarray, list or object
        A list (an event's states) is converted item by item.
    bits : int

    Returns
    -------
    object
    """
    if isinstance(values, np.ndarray) and values.dtype == object:
        out = np.empty(values.shape, dtype=object)
        flat, src = out.reshape(-1), values.reshape(-1)
        for i, v in enumerate(src):
            flat[i] = RunNumber(v, bits) if isinstance(v, mpmath.mpf) else v
        return out
    if isinstance(values, list):
        return [shown_at(v, bits) for v in values]
    if isinstance(values, mpmath.mpf):
        return RunNumber(values, bits)
    return values


def _short(value: object, digits: int = 6) -> str:
    """A number in a few significant digits (float or mpmath.mpf)."""
    if isinstance(value, mpmath.mpf):
        return mpmath.nstr(value, digits)
    try:
        return f"{float(value):.{digits}g}"
    except (TypeError, ValueError):
        return repr(value)


def _short_array(values: Sequence, edge: int = 2) -> str:
    """``[a b ... y z] (n)``: the first and last ``edge`` entries of a 1-d sequence."""
    items = list(values)
    if len(items) <= 2 * edge + 1:
        return "[" + " ".join(_short(v) for v in items) + "]"
    shown = [_short(v) for v in items[:edge]] + ["..."] + [_short(v) for v in items[-edge:]]
    return "[" + " ".join(shown) + f"] ({len(items)})"


@dataclass
class IntegrationResult:
    """Outcome of :func:`integrate`, with its error evidence.

    Attributes
    ----------
    status : int
        0: reached the end; negative: failed (see ``message``).
    message : str
        What happened and, on failure, what to do.
    t : ndarray, shape (n_points,)
    y : ndarray, shape (n_state, n_points)
        ``float64`` in double precision, ``object`` (mpmath.mpf) at higher precision.
    state_names : tuple of str
    drift : dict of str to float
        ``max_t |F(t) - F(0)| / |F(0)|`` over the output points, for every first integral
        of the model; where ``|F(0)|`` is below the square root of the working precision
        (``(alpha, beta) = 0``) the absolute change, and the name is in ``drift_absolute``.
    nfev, njev, nsteps : int
        Work counters.
    wall_s : float
        Wall time of the integration (compilation and set-up excluded, see ``setup_s``).
    precision : str
    method, backend : str
    t_events, y_events : list
        For each event function, the times (array) and states (rows) where it fired.
    info : dict
        Method-specific evidence (the Taylor method: ``order_min``, ``order_max``,
        ``rtol``, ``atol``, ``taylor_backend``).
    rtol, atol : float or None
        The tolerances the run asked for (the defaults filled in).
    """

    status: int
    message: str
    t: np.ndarray
    y: np.ndarray
    state_names: tuple[str, ...]
    drift: dict[str, float]
    drift_absolute: tuple[str, ...]
    nfev: int
    njev: int
    nsteps: int
    wall_s: float
    setup_s: float
    precision: str
    method: str
    backend: str
    model: str
    params: dict[str, object] = field(default_factory=dict)
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)
    info: dict[str, object] = field(default_factory=dict)
    rtol: float | None = None
    atol: float | None = None

    @property
    def success(self) -> bool:
        """``status == 0``."""
        return self.status == 0

    @property
    def y_final(self) -> dict[str, object]:
        """Final state by name."""
        return dict(zip(self.state_names, self.y[:, -1], strict=True))

    def _summary(self) -> list[tuple[str, str]]:
        """``(key, short text)`` rows shared by ``__repr__`` and ``_repr_html_``."""
        message = self.message if len(self.message) <= 72 else self.message[:69] + "..."
        final = self.y_final if self.y.shape[-1] else {}
        shown = list(final.items())[:4]
        more = f", ... ({len(final)})" if len(final) > len(shown) else ""
        rows = [
            ("model", f"{self.model}: {self.method} ({self.backend}), {self.precision}"),
            ("success", f"{self.success} (status {self.status}): {message}"),
            ("t", _short_array(self.t)),
            ("y_final", ", ".join(f"{k}={_short(v)}" for k, v in shown) + more),
            ("drift", ", ".join(f"{k} {_short(v, 2)}" for k, v in self.drift.items())),
            (
                "work",
                f"nfev {self.nfev}, njev {self.njev}, nsteps {self.nsteps}; "
                f"wall {self.wall_s:.3g} s, setup {self.setup_s:.3g} s",
            ),
        ]
        if self.t_events:
            rows.append(("t_events", ", ".join(f"{len(te)} times" for te in self.t_events)))
        return rows

    def __repr__(self) -> str:
        width = max(len(k) for k, _ in self._summary())
        lines = [f"{k.rjust(width)}: {v}" for k, v in self._summary()]
        return "IntegrationResult(\n  " + "\n  ".join(lines) + "\n)"

    def _repr_html_(self) -> str:
        cells = "".join(
            f"<tr><th style='text-align:right'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(v)}</td></tr>"
            for k, v in self._summary()
        )
        return f"<table><caption>IntegrationResult</caption>{cells}</table>"
