"""``chaplygin sweep``: run a scene's ``[sweep]`` grid on Dask into a Zarr store (resumable).

``chaplygin sweep SCENE.toml [--out STORE] [--scheduler tcp://HOST:PORT] [--workers N]``: every
point of the grid reduced to numbers (:mod:`chaplygin.verify.sweep`), chunk by chunk; the same
command started again continues a sweep that was stopped, and refuses a store made by another
scene, grid or code version. Needs the ``dask`` extra (``pip install 'chaplygin[dask]'``).
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

from .cli_common import (
    EXIT_FAILED,
    EXIT_OK,
    add_quiet,
    check_output_file,
    json_text,
    positive_float,
    printable,
)
from .output_folder import safe_name
from .sweep_checks import CONNECT_TIMEOUT_S, check_workers, parse_scheduler_address

__all__ = ["add_parser", "run"]


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin sweep``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0 when every point was computed, 1 when some failed (2 for a user error, raised).

    Raises
    ------
    UserInputError
        A bad scene, a missing dask extra, a store of another sweep, a bad flag.
    """
    from ..derive.errors import ComputationError, UserInputError
    from .scene import Scene
    from .sweep import require_dask, run_sweep

    require_dask()
    # Dask logs a lost connection as tracebacks; the command says it in one line
    import distributed.client  # noqa: F401  (its loggers exist from here on)

    for name in list(logging.root.manager.loggerDict):
        if name.split(".")[0] in ("distributed", "asyncio"):
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)
    if args.workers is not None and args.scheduler is not None:
        raise UserInputError("--workers is for the local cluster; not with --scheduler")
    if args.workers is not None:
        check_workers(args.workers)
    if args.scheduler is not None:
        parse_scheduler_address(args.scheduler)
    plot = check_output_file(args.plot, "--plot", (".png", ".svg", ".pdf")) if args.plot else None
    if args.out is not None and not args.out.strip():
        raise UserInputError("--out needs a store name (a folder), got an empty one")
    stem = safe_name(Path(args.scene).stem, "sweep")
    out = Path(args.out) if args.out else Path("chaplygin-sweep") / f"{stem}.zarr"
    scene = Scene.from_toml(args.scene, args.set or ())
    progress = not args.quiet and sys.stderr.isatty()
    try:
        summary = run_sweep(
            scene, out, args.scheduler, args.workers, progress,
            connect_timeout=args.connect_timeout,
        )  # fmt: skip
    except ComputationError as exc:  # the finished chunks are stored: the same command continues
        print(
            printable(
                f"chaplygin: error: {' '.join(str(exc).split())}; the chunks finished are "
                f"stored in {out}: run the same command again to continue",
                keep="",
            ),
            file=sys.stderr,
        )
        return EXIT_FAILED
    summary["store"] = str(out)
    if plot is not None:
        import xarray as xr

        from .sweep_plots import save_figure, sweep_figure

        with xr.open_zarr(out, consolidated=False) as ds:
            save_figure(sweep_figure(ds.load()), plot)
        summary["plot"] = str(plot)
    if args.json:
        print(json_text(summary, indent=2))
    elif not args.quiet:
        fixes = []
        if summary["repaired"]:
            n = summary["repaired"]
            fixes.append(f"{n} chunk{'s' if n > 1 else ''} marked done did not verify")
        if summary["recreated"]:
            fixes.append(f"arrays made again: {', '.join(summary['recreated'])}")
        repaired = f"; the store was repaired ({'; '.join(fixes)})" if fixes else ""
        line = (
            f"{args.scene}: {summary['points']} points in {summary['chunks']} chunks "
            f"({summary['computed']} computed now, {summary['skipped']} already stored and "
            f"verified); {summary['refused']} refused, {summary['failed']} failed -> {out}"
            f"{repaired}"
        )
        print(printable(line, keep=""))
        if "refined" in summary:
            print(f"zeros of {scene.sweep.refine.variable}: {', '.join(summary['refined'])}")
    return EXIT_OK if summary["failed"] == 0 else EXIT_FAILED


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin sweep``.

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
        "sweep",
        help="run a scene's [sweep] grid on Dask into a Zarr store (resumable)",
    )
    p.add_argument("scene", metavar="SCENE.toml", help="a scene file with a [sweep] table")
    p.add_argument("--out", default=None, help="the Zarr store (default chaplygin-sweep/STEM.zarr)")
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="a running Dask scheduler, e.g. tcp://HOST:8786 (default: a local cluster)",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        help="worker processes of the local cluster (default and most: one per usable CPU)",
    )
    p.add_argument(
        "--connect-timeout",
        type=positive_float,
        default=CONNECT_TIMEOUT_S,
        metavar="SECONDS",
        help=f"time to connect to --scheduler, get its handshake and see a worker "
        f"(default {CONNECT_TIMEOUT_S:g})",
    )
    p.add_argument(
        "--set", action="append", metavar="KEY=VALUE", help="override a key of the scene"
    )
    p.add_argument(
        "--plot", default=None, metavar="FILE.png", help="draw the store (.png/.svg/.pdf)"
    )
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    add_quiet(p, "no progress bar, no report line")
    return p
