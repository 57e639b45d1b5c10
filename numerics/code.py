"""Generated code of one model variant, as numerics uses it (no sympy work at run time).

Built-in variants load the modules committed in ``generated/``; any other variant is
derived and emitted in memory (registered in :mod:`linecache`, so tracebacks show it).
"""

from __future__ import annotations

import importlib
import json
import threading
import time
import types
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from typing import TYPE_CHECKING, Any

from ..derive.effects import parse_effects
from ..derive.emit.functions import module_from_source
from ..derive.systems import get_system, variant_name

if TYPE_CHECKING:  # the compiled model is loaded lazily by ModelCode.compiled
    from .compiled import CompiledModel

__all__ = ["ModelCode", "load_model_code", "generated_manifest"]


def generated_manifest() -> dict[str, dict]:
    """``generated/manifest.json``: variant -> hash, system, effects, files.

    Returns
    -------
    dict of str to dict
        Variant name -> ``{"hash", "system", "effects", "generator", "files"}``
        (``files`` maps each of ``numpy``, ``mpmath``, ``c``, ``taylor_py``, ``taylor_c``
        to its file name in ``generated/``).
    """
    text = resources.files("chaplygin.generated").joinpath("manifest.json").read_text()
    return json.loads(text)


#: The name the periodic effects give their angular frequency (``derive.effects``).
FORCING_FREQUENCY = "Omega"


@dataclass
class ModelCode:
    """Everything numerics needs about a model variant.

    Attributes
    ----------
    name : str
        Variant name (``chaplygin_ball__gyrostat``).
    numpy : module
        Vectorised numpy functions ``rhs, jac, aux, integrals, density (t, y, p)``.
    mpmath : module
        The same for mpmath values.
    c_source : str
        C99 source (compiled lazily by :meth:`compiled`).
    taylor : module
        Taylor-coefficient recurrences ``taylor_coefficients(t0, y, p, order, lib)``.
    taylor_c_source : str
        C Taylor integrator (``double``; ``__float128`` with ``CHAPLYGIN_TAYLOR_QUAD``).
    taylor_mpfr_source : str or None
        C Taylor integrator on MPFR numbers (precisions past quad-double).
    taylor_program : str or None
        The Taylor program as data (JSON), from which the coefficients are written out for
        fixed orders (:func:`chaplygin.derive.emit.taylor_unroll.unrolled_source`).
    lanes_c_source : str or None
        The right-hand side in vector lanes (``bm_rhs_vec``) for the DOP853 batch; None when
        the lanes cannot compute it.
    origin : str
        ``"generated/"``, ``"derived on first use"`` or ``"cache of first-use code"``.
    note : str or None
        For a variant not in ``generated/``: how it was obtained and how long it took.
    """

    name: str
    numpy: types.ModuleType
    _mpmath: types.ModuleType | None
    _c_source: str | None
    origin: str
    taylor: types.ModuleType | None = None
    taylor_c_source: str | None = None
    taylor_mpfr_source: str | None = None
    taylor_program: str | None = None
    _lanes_c_source: str | None = None
    note: str | None = None
    _compiled: Any = field(default=None, repr=False)
    _compile_tried: bool = field(default=False, repr=False)
    #: the kinds of source still to be emitted on first access (a variant outside
    #: ``generated/``: ``"mpmath"``, ``"c"``, ``"c_lanes"``) and what emits one
    _pending: frozenset = field(default=frozenset(), repr=False, compare=False)
    _emit: Callable[[str], str] | None = field(default=None, repr=False, compare=False)
    _lock: Any = field(default_factory=threading.Lock, init=False, repr=False, compare=False)

    def _source(self, kind: str) -> None:
        """The source of ``kind``, emitted now if it is still pending (once, under a lock)."""
        if kind not in self._pending:  # the common case: nothing to do, no lock taken
            return
        with self._lock:
            if kind in self._pending and self._emit is not None:
                text = self._emit(kind)
                if kind == "mpmath":
                    self._mpmath = module_from_source(f"{self.name}_mpmath", text)
                elif kind == "c":
                    self._c_source = text
                else:
                    self._lanes_c_source = text or None
                self._pending = self._pending - {kind}
        return None

    @property
    def mpmath(self) -> types.ModuleType:
        """The mpmath module (emitted when first asked for, for a variant outside
        ``generated/``)."""
        self._source("mpmath")
        return self._mpmath

    @property
    def c_source(self) -> str:
        """The C99 source (emitted when first asked for, for a variant outside
        ``generated/``)."""
        self._source("c")
        return self._c_source

    @property
    def lanes_c_source(self) -> str | None:
        """The right-hand side in vector lanes, or None (emitted when first asked for, for a
        variant outside ``generated/``)."""
        self._source("c_lanes")
        return self._lanes_c_source

    # metadata straight from the generated module
    @property
    def hash(self) -> str:
        return self.numpy.MODEL_HASH

    @property
    def system(self) -> str:
        return self.numpy.SYSTEM

    @property
    def effects(self) -> tuple[str, ...]:
        return tuple(self.numpy.EFFECTS)

    @property
    def state(self) -> tuple[str, ...]:
        return tuple(self.numpy.STATE)

    @property
    def params(self) -> tuple[str, ...]:
        return tuple(self.numpy.PARAMS)

    @property
    def forcing(self) -> str | None:
        """The parameter that is the angular frequency of a time-periodic model (its forcing
        period is ``2 pi/value``), or None for an autonomous one.

        The periodic effects declare it (BM20's ``variable_inertia`` and
        ``variable_gyrostat``: ``Omega``); the generic dynamics read it here.

        Returns
        -------
        str or None
        """
        return FORCING_FREQUENCY if FORCING_FREQUENCY in self.params else None

    @property
    def state_groups(self) -> dict[str, tuple[str, ...]]:
        return {name: tuple(g) for name, g in self.numpy.STATE_GROUPS}

    @property
    def parameter_groups(self) -> dict[str, tuple[tuple[str, ...], str, str]]:
        """``name -> (symbols, domain, description)``."""
        return {n: (tuple(s), d, desc) for n, s, d, desc in self.numpy.PARAMETERS}

    @property
    def integral_names(self) -> tuple[str, ...]:
        return tuple(self.numpy.INTEGRALS)

    @property
    def relation_names(self) -> tuple[str, ...]:
        """Integrals that must vanish on the phase space (constraints on omega alone)."""
        return tuple(getattr(self.numpy, "RELATIONS", ()))

    @property
    def geometry(self) -> tuple[tuple[str, tuple[str, ...]], ...]:
        """Poisson groups as ``(kind, names)``: ``("unit_vector", ("gamma",))`` or a frame.

        Returns
        -------
        tuple of (str, tuple of str)
        """
        return tuple(self.numpy.GEOMETRY)

    @property
    def constraint_names(self) -> tuple[str, ...]:
        """The phase-space constraints as text (``"gamma1**2 + ... - 1 = 0"``).

        Returns
        -------
        tuple of str
        """
        return tuple(getattr(self.numpy, "CONSTRAINTS", ()))

    @property
    def completion(self) -> tuple[tuple[tuple[str, ...], str], ...]:
        """How omitted state groups are completed (``derive.model.Model.completion``).

        Returns
        -------
        tuple of ((str, ...), str)
        """
        return tuple(getattr(self.numpy, "COMPLETION", ()))

    @cached_property
    def aux_names(self) -> tuple[str, ...]:
        return tuple(self.numpy.AUX)

    def compiled(self) -> CompiledModel | None:
        """The compiled C model (cached per user), or None without a C compiler.

        Compiled on the first call only (:func:`chaplygin.numerics.compiled.load_c_model`);
        later calls return the same object, or None again.

        Returns
        -------
        CompiledModel or None
            None, after a :class:`CompilerUnavailableWarning`, without a usable compiler.

        Raises
        ------
        ModelHashMismatchError
            If the compiled library reports another model hash than ``self.hash``.
        """
        if not self._compile_tried:
            from .compiled import load_c_model

            self._compile_tried = True
            self._compiled = load_c_model(self.c_source, expected_hash=self.hash)
        return self._compiled


_LOADED: dict[str, ModelCode] = {}


def load_model_code(system: str, effects: str | Iterable[str] | None = None) -> ModelCode:
    """Code of ``system`` with ``effects``: from ``generated/`` when built in, else emitted.

    Loaded once per variant and cached for the process.

    Parameters
    ----------
    system : str
        System name (``chaplygin_ball``).
    effects : str or iterable of str, optional
        Comma-separated string or names of the effects (``"gyrostat,contact_point"``);
        None or ``""`` for none.

    Returns
    -------
    ModelCode
        The variant's generated modules and sources.

    Raises
    ------
    UserInputError
        Unknown system or effect.
    """
    sysdef = get_system(system)
    chosen = parse_effects(effects, sysdef.effects)
    name = variant_name(system, chosen)
    if name in _LOADED:
        return _LOADED[name]
    manifest = generated_manifest()
    if name in manifest:
        files = manifest[name]["files"]
        generated = resources.files("chaplygin.generated")

        def text(kind: str) -> str | None:
            return generated.joinpath(files[kind]).read_text() if kind in files else None

        code = ModelCode(
            name=name,
            numpy=importlib.import_module(f"chaplygin.generated.{files['numpy'][:-3]}"),
            _mpmath=importlib.import_module(f"chaplygin.generated.{files['mpmath'][:-3]}"),
            _c_source=text("c"),
            origin="generated/",
            taylor=importlib.import_module(f"chaplygin.generated.{files['taylor_py'][:-3]}"),
            taylor_c_source=text("taylor_c"),
            taylor_mpfr_source=text("taylor_mpfr"),
            taylor_program=text("taylor_program"),
            _lanes_c_source=text("c_lanes"),
        )
    else:  # derived, emitted and compiled on first use; cached on disk (numerics.first_use)
        code = _first_use_code(system, chosen, name)
    _LOADED[name] = code
    return code


def _first_use_code(system: str, chosen: frozenset[str], name: str) -> ModelCode:
    """A variant not in ``generated/``: from the first-use cache, else derived and emitted now
    (:mod:`chaplygin.numerics.first_use`); its mpmath, C and vector-lane code when first asked
    for (:data:`~chaplygin.numerics.first_use.LAZY_KINDS`); its ``note`` says which and how
    long."""
    from .first_use import LAZY_KINDS, emitted_sources

    start = time.perf_counter()
    first = emitted_sources(system, chosen)
    src = first.sources

    def emit(kind: str) -> str:
        return emitted_sources(system, chosen, (kind,)).sources[kind]

    code = ModelCode(
        name=name,
        numpy=module_from_source(f"{name}_numpy", src["numpy"]),
        _mpmath=module_from_source(f"{name}_mpmath", src["mpmath"]) if "mpmath" in src else None,
        _c_source=src.get("c"),
        origin="derived on first use" if first.derived else "cache of first-use code",
        taylor=module_from_source(f"{name}_taylor", src["taylor_py"]),
        taylor_c_source=src["taylor_c"],
        taylor_mpfr_source=src["taylor_mpfr"],
        taylor_program=src["taylor_program"],
        _lanes_c_source=(src["c_lanes"] or None) if "c_lanes" in src else None,
        _pending=frozenset(k for k in LAZY_KINDS if k not in src),
        _emit=emit,
    )
    where = f"cached in {first.cache_file.parent}" if first.cache_file else "not cached"
    if first.derived:
        later = sorted(code._pending)
        code.note = (
            f"{name} is not in generated/: derived and emitted on first use in "
            f"{time.perf_counter() - start:.1f} s ({where})"
            + (f"; {', '.join(later)} when first needed" if later else "")
        )
    else:
        code.note = (
            f"{name} is not in generated/: loaded from the first-use cache in "
            f"{time.perf_counter() - start:.2f} s ({where})"
        )
    return code
