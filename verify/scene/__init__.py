"""Scenes: one TOML file names one experiment (system, effects, parameters, initial state, run,
outputs); :meth:`Scene.run` simulates only what it calls for.

The package, by role:

* the file format and schema: :mod:`.schema` (pydantic models, the JSON Schema shipped as
  ``examples/scenes/scene.schema.json``), :mod:`.reading` (the file read with limits, TOML,
  ``--set``, title placeholders), :mod:`.errors` (:class:`SceneError` with key path and line);
* resolution: :mod:`.resolution` (the model, parameters and time span; the initial state is the
  system's own, :func:`chaplygin.numerics.ball.initial_state.initial_state`, shared with the API);
* outputs registered by name: :mod:`.registry` (which outputs a scene asks for; analyses by key,
  imported by name from :mod:`chaplygin.verify.outputs`) behind :mod:`.outputs`, the public
  interface an output module imports (and nothing else of this package);
* running: :mod:`.running` (the trajectory and the analyses), :mod:`.result`
  (:class:`SceneResult`: arrays, figures, ``summary.json``, files written atomically),
  :mod:`.explain` (``--explain``).

Every problem with a scene is one :class:`SceneError` (a :class:`UserInputError`): its message
names the file, the key path and, where it can be found, the line; unknown keys and names list the
valid choices with a "did you mean". Numbers may be written as text (``"sqrt(0.87)"``); they go
through the project's safe number parser (:func:`chaplygin.numerics.inputs.parse_number`), never
``eval``.

The model is built from the scene's effects plus those its outputs need
(:data:`OUTPUT_EFFECTS`), and nothing else: a parameter of an effect that is not on is refused.

Examples
--------
>>> scene = Scene.from_toml("examples/scenes/k01-fig6f.toml")      # doctest: +SKIP
>>> result = scene.run()                                          # doctest: +SKIP
>>> result.contact_trace_figure().savefig("trace.png")            # doctest: +SKIP
"""

from __future__ import annotations

from .errors import SceneError, did_you_mean
from .explain import explain_text
from .reading import (
    MAX_SCENE_BYTES,
    MAX_SCENE_DEPTH,
    apply_overrides,
    read_scene_file,
    render_title,
)
from .registry import OUTPUT_EFFECTS, needs_trajectory
from .resolution import Resolved, quantity_names
from .result import (
    SceneResult,
    package_version,
    prepare_output,
    software_versions,
    write_atomically,
)
from .running import integrate_trajectory, run_resolved
from .schema import Initial, Outputs, Run, Scene, load_scene, scene_json_schema

__all__ = [
    "Scene",
    "SceneError",
    "SceneResult",
    "Resolved",
    "Initial",
    "Outputs",
    "Run",
    "OUTPUT_EFFECTS",
    "scene_json_schema",
    "apply_overrides",
    "render_title",
    "load_scene",
    "explain_text",
    "run_resolved",
    "integrate_trajectory",
    "needs_trajectory",
    "quantity_names",
    "prepare_output",
    "write_atomically",
    "read_scene_file",
    "did_you_mean",
    "package_version",
    "software_versions",
    "MAX_SCENE_BYTES",
    "MAX_SCENE_DEPTH",
]
