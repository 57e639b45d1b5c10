"""One vocabulary: the API's argument names in error messages, the command line's flags.

The layers below speak of arguments (``params["I"]=(V1, V2, V3)``, ``precision="quad"``,
``method="taylor"``, ``rtol=1e-20``); the command line prints the same message with its own
flags (``--param I=V1,V2,V3``, ``--precision quad``, ``--method taylor``, ``--rtol 1e-20``).

One spelling per concept across the commands (issue 28): :data:`RENAMED_FLAGS` lists the old
spellings (still accepted, hidden from the help, where scripts may use them) and
:data:`RENAMED_JSON_KEYS` the keys no ``--json`` document uses any more. In JSON, ``system``
is the system as named (``chaplygin_ball``), ``effects`` its effects, ``model`` the code's
name (``chaplygin_ball__contact_point``), ``steps`` the solver's accepted steps and
``precision`` a structured value (:meth:`~chaplygin.numerics.precision.Precision.to_json`:
``{"kind": "digits", "digits": 30, "bits": 103}``), never prose such as ``"30 digits"``.
"""

from __future__ import annotations

import re

__all__ = ["to_cli", "RENAMED_FLAGS", "RENAMED_JSON_KEYS", "PROGRESS_COMMANDS"]

#: Old flag spellings -> the one each concept has on every command (the old ones are kept as
#: hidden aliases where they existed).
RENAMED_FLAGS = {
    "--output": "--out",
    "--t-eval": "--points",
    "--digits": "--precision",
    "--I": "--param",
    "--D": "--param",
    "--M": "--y0",
    "--gamma": "--y0",
}

#: JSON keys retired -> the key every command's ``--json`` uses for the concept.
RENAMED_JSON_KEYS = {
    "nsteps": "steps",
    "digits": "precision",
    "digits_requested": "precision",
}

#: The commands that print progress while they work; each takes ``--quiet``.
PROGRESS_COMMANDS = ("run", "sweep", "bench", "verify")

#: ``params["I"]=(V1, V2, V3)`` or ``y0["x"]=V``
_MAPPED = re.compile(r'\b(params|y0)\["(\w+)"\]=(\([^)]*\)|[^\s,;)]+)')
#: ``precision="quad"``, ``method="taylor"``, ``effects="a,b"``, ``backend="c"``
_QUOTED = re.compile(r'\b(precision|method|backend|effects)="([^"]*)"')
#: ``precision=30``, ``rtol=1e-20``, ``t_end=5``
_BARE = re.compile(r"\b(precision|rtol|atol|t_end|t_start|max_steps)=(?=[-+.\w])")
_FLAG = {"params": "--param", "y0": "--y0"}


def _mapped(match: re.Match) -> str:
    values = match.group(3)
    if values.startswith("("):
        values = ",".join(v.strip() for v in values[1:-1].split(","))
    return f"{_FLAG[match.group(1)]} {match.group(2)}={values}"


def to_cli(message: str) -> str:
    """The message of an API error with the command line's flags for the arguments.

    Parameters
    ----------
    message : str
        A :class:`~chaplygin.derive.errors.UserInputError` message in the API's words.

    Returns
    -------
    str
        The same message for a command-line user.

    Examples
    --------
    >>> to_cli('missing parameter I: give params["I"]=(VALUE1, VALUE2, VALUE3)')
    'missing parameter I: give --param I=VALUE1,VALUE2,VALUE3'
    >>> to_cli('rtol=1e-20 is below ...; ask for precision="quad" (method="taylor")')
    '--rtol 1e-20 is below ...; ask for --precision quad (--method taylor)'
    """
    message = _MAPPED.sub(_mapped, message)
    message = _QUOTED.sub(lambda m: f"--{m.group(1)} {m.group(2)}", message)
    message = _BARE.sub(lambda m: f"--{m.group(1).replace('_', '-')} ", message)
    return message
