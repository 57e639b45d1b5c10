"""``chaplygin run``: run scene files (a thin layer over :class:`chaplygin.verify.scene.Scene`).

Every problem with a scene is one line on stderr and exit status 2, and nothing is written:
all scenes are validated and resolved, and their output folders checked, before any runs;
each run writes into a temporary folder that is moved into place at the end.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..derive.errors import UserInputError
from .cli_common import EXIT_FAILED, EXIT_OK, add_quiet, json_text, printable

__all__ = ["add_parser", "run"]

#: Keys of ``--json`` (a subset of ``summary.json``).
JSON_KEYS = (
    "title",
    "system",
    "model",
    "effects",
    "states",
    "y",
    "drift",
    "status",
    "method",
    "precision",
    "steps",
    "wall_s",
    "analyses",
    "outputs",
    "separatrix_delta",  # when the scene asks for it
)


def _out_folders(paths: list[str], out: str | None) -> list[Path]:
    """The output folder of each scene: ``--out`` itself for one scene, else
    ``BASE/STEM`` (``BASE`` is ``--out`` or ``chaplygin-run``); stems made safe
    (:func:`~chaplygin.verify.output_folder.safe_name`: ``...toml`` has the stem ``..``)."""
    from .output_folder import safe_name

    if out is not None and not out.strip():
        raise UserInputError("--out needs a folder name, got an empty one")
    stems = [safe_name(Path(p).stem) for p in paths]
    if len(paths) == 1 and out:
        return [Path(out)]
    base = Path(out) if out else Path("chaplygin-run")
    return [base / s for s in stems]


def run(args: argparse.Namespace) -> int:
    """Run ``chaplygin run``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags of :func:`add_parser`.

    Returns
    -------
    int
        0 when every run reached its end, 1 otherwise (2 for a user error, raised).
    """
    from .scene import Scene, SceneError, prepare_output, scene_json_schema, write_atomically

    if args.schema:
        print(json_text(scene_json_schema(), indent=2, sort_keys=True))
        return EXIT_OK
    if not args.scenes:
        raise SceneError("give at least one scene file (or --schema)")
    scenes = [Scene.from_toml(path, args.set or ()) for path in args.scenes]
    if args.explain:
        from .scene import explain_text

        resolved = [scene.resolve() for scene in scenes]
        text = "\n\n".join(explain_text(s, r) for s, r in zip(scenes, resolved, strict=True))
        print(printable(text))
        return EXIT_OK
    # every user error before any work: the folders first (resolving may derive a model)
    folders = [prepare_output(f) for f in _out_folders(args.scenes, args.out)]
    if len({f.target for f in folders}) != len(folders):
        raise SceneError("two scenes have the same file name: their output folders would clash")
    resolved = [scene.resolve() for scene in scenes]
    status = EXIT_OK
    progress = not args.quiet and sys.stderr.isatty()
    from .scene import run_resolved

    documents = []  # --json: one object per scene, printed together at the end

    for scene, res, folder in zip(scenes, resolved, folders, strict=True):
        if res.code.note and not args.quiet:
            print(printable(f"note: {res.code.note}"), file=sys.stderr)
        result = run_resolved(scene, res, progress)
        written = write_atomically(result, folder)
        summary = result.summary([str(Path(folder.given) / w) for w in written])
        if not result.success:
            status = EXIT_FAILED
        if args.json:
            documents.append({k: summary[k] for k in JSON_KEYS if k in summary})
        elif not args.quiet and result.integration is None:
            print(
                printable(
                    f"{scene.source}: {', '.join(result.analyses)} in {summary['wall_s']:.2f} s "
                    f"-> {folder.given}/"
                )
            )
        elif not args.quiet:
            worst = max(summary["drift"].values(), key=lambda v: -1 if v is None else v)
            print(
                printable(
                    f"{scene.source}: {result.integration.message} (status "
                    f"{summary['status']}); {summary['steps']} steps, {summary['wall_s']:.2f} s, "
                    f"max drift {worst:.2e} -> {folder.given}/"
                )
            )
    if args.json:  # one valid JSON document: the object of one scene, a list for several
        print(json_text(documents[0] if len(documents) == 1 else documents, indent=2))
    return status


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``chaplygin run``.

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
        "run", help="run scene files (TOML): trajectory, summary and plots of one experiment"
    )
    p.add_argument("scenes", nargs="*", metavar="SCENE.toml", help="scene file(s)")
    p.add_argument(
        "--out",
        default=None,
        help="output folder (default chaplygin-run/STEM); with several scenes, their parent",
    )
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="override a key, e.g. --set run.t_end=100 --set initial.h=0.17 (TOML values)",
    )
    p.add_argument(
        "--json",
        action="store_true",
        help="print the summary as one JSON document: an object for one scene, a list of "
        "them (in the order given) for several",
    )
    p.add_argument("--explain", action="store_true", help="say what would run; run nothing")
    add_quiet(p, "no progress bar, no report line")
    p.add_argument(
        "--schema",
        action="store_true",
        help="print the JSON Schema of scene files (examples/scenes/scene.schema.json)",
    )
    return p
