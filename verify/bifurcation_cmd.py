"""``chaplygin bifurcation``: bifurcation diagrams of K01 Figs. 1-3 and BKM12 Figs. 2, 3, 5.

The curves are the derived ones (``derive/bifurcation.py``, proved in
``verify/claims/bifurcation.py``); each family is drawn solid when its Floquet multipliers
(``numerics/ball/bifurcation.py``) lie on the unit circle and dashed otherwise; random seeded
initial states on the levels are integrated for a short time and their integral values
drawn as dots: the region of motion (BKM12-Fig2region). The figures are
:func:`chaplygin.verify.plots.bifurcation_figure`'s.

References
----------
K01-Fig1, K01-Fig2, K01-Fig3, BKM12-24, BKM12-Fig3, BKM12-2.7c, BKM12-1.5stab8.
"""

from __future__ import annotations

import argparse
import math

from ..derive.errors import UserInputError
from .cli_common import EXIT_OK, check_output_file, key_values
from .figure_names import FIGURES

__all__ = ["add_parser", "run", "MAX_SAMPLES", "MAX_SEED", "MAX_MAGNITUDE", "MAX_RATIO"]

#: Largest I_max/I_min and D/I_min (D_iso for the support): the periodic orbits and samples
#: of a diagram take longer the further apart the moments are (a ratio of 100 takes about
#: 50 s, 1000 more than ten minutes).
MAX_RATIO = 100

#: Every --param value is 0 or of magnitude between 1/MAX_MAGNITUDE and MAX_MAGNITUDE
#: (the diagrams are computed in double precision: beyond, they overflow or lose all digits).
MAX_MAGNITUDE = 1e6

#: Most integrated states of one diagram (each is one short DOP853 integration, ~ms).
MAX_SAMPLES = 10_000

#: Largest --seed (seeds of numpy.random.default_rng are whole numbers >= 0).
MAX_SEED = 2**32 - 1


def _parse_params(items) -> dict:
    from ..numerics.inputs import parse_number

    out: dict[str, object] = {}
    for name, value in key_values(items, "--param").items():
        try:
            vals = [float(parse_number(v.strip())) for v in value.split(",")]
        except (ValueError, TypeError, ZeroDivisionError) as exc:
            raise UserInputError(f"--param {name}: {exc}") from None
        if not all(math.isfinite(v) for v in vals):
            raise UserInputError(f"--param {name}: values must be finite, got {value}")
        if any(v != 0 and not 1 / MAX_MAGNITUDE <= abs(v) <= MAX_MAGNITUDE for v in vals):
            raise UserInputError(
                f"--param {name}={value}: give 0 or magnitudes between {1 / MAX_MAGNITUDE:g} and "
                f"{MAX_MAGNITUDE:g} (the diagrams are drawn in double precision); rescale the units"
            )
        out[name] = tuple(vals) if name == "I" else vals[0]
        if name != "I" and len(vals) != 1:
            raise UserInputError(f"--param {name} takes one value, got {len(vals)}")
    return out


def _check_ratios(params: dict) -> None:
    """Refuse moments further apart than :data:`MAX_RATIO` (before any work)."""
    I = [float(v) for v in params["I"]]
    if len(I) != 3 or min(I) <= 0:
        return  # bifurcation_figure says what is wrong
    D = float(params.get("D", params.get("D_iso", 0)))
    if max(I) / min(I) > MAX_RATIO or D / min(I) > MAX_RATIO:
        raise UserInputError(
            f"I = {tuple(I)} and D = {D:g} are too far apart for a diagram: I_max/I_min and "
            f"D/I_min must be at most {MAX_RATIO} (the work grows with them); rescale or "
            "bring the moments closer"
        )


def _default_figure(system: str, params: dict) -> str:
    if system == "spherical_support":
        return "bkm12-5"
    if system == "chaplygin_ball":
        return "k01-1" if float(params.get("C", 1) or 0) == 0 else "k01-2"
    raise UserInputError(
        f"no bifurcation diagram for system {system!r}; valid: chaplygin_ball, spherical_support"
    )


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin bifurcation``: draw one diagram into a PNG file.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0.
    """
    from .plots import bifurcation_figure

    out = check_output_file(args.out, "--out", (".png",), "the diagram")
    if not 1 <= args.samples <= MAX_SAMPLES:
        raise UserInputError(
            f"--samples must be a whole number in 1..{MAX_SAMPLES}, got {args.samples}"
        )
    if not 0 <= args.seed <= MAX_SEED:
        raise UserInputError(f"--seed must be a whole number in 0..{MAX_SEED}, got {args.seed}")
    params = _parse_params(args.param)
    figure = args.figure or _default_figure(args.system, params)
    if figure not in FIGURES:
        raise UserInputError(f"unknown figure {figure!r}; valid: {', '.join(FIGURES)}")
    if FIGURES[figure][0] != args.system:
        raise UserInputError(
            f"figure {figure} is a diagram of {FIGURES[figure][0]}, not {args.system}"
        )
    _check_ratios({**FIGURES[figure][1], **params})
    fig, drift = bifurcation_figure(figure, params, samples=args.samples, seed=args.seed)
    fig.savefig(out, dpi=110, format="png")
    print(
        f"wrote {args.out} ({figure}; {args.samples} integrated states, "
        f"largest relative drift of their integrals {drift:.1e})"
    )
    return EXIT_OK


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin bifurcation``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    p = subparsers.add_parser(
        "bifurcation", help="draw a bifurcation diagram (K01 Figs. 1-3, BKM12 Figs. 2, 3, 5)"
    )
    p.add_argument("system", help="chaplygin_ball or spherical_support")
    p.add_argument(
        "--param",
        action="append",
        metavar="NAME=VALUE[,VALUE...]",
        help="I=1,1.5,3 D=1 C=1 (ball; C = (M, gamma) for K01 figures); "
        "I, D_iso, D_al, D_be (support)",
    )
    p.add_argument("--figure", default=None, help=", ".join(FIGURES))
    p.add_argument("--out", required=True, help="PNG file to write")
    p.add_argument(
        "--samples",
        type=int,
        default=60,
        help=f"integrated random states, 1..{MAX_SAMPLES} (default 60)",
    )
    p.add_argument("--seed", type=int, default=1, help=f"0..{MAX_SEED} (default 1)")
    return p
