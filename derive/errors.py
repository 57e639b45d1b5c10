"""Exceptions shared by every layer.

`UserInputError` is the one exception the command line turns into a single line on
stderr and exit code 2: raise it for anything a user typed wrong (unknown system,
effect or parameter, a non-physical value, a malformed number).
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

__all__ = [
    "ChaplyginError",
    "UserInputError",
    "DerivationError",
    "CacheError",
    "ComputationError",
    "did_you_mean",
]


class ChaplyginError(Exception):
    """Base class of the toolkit's exceptions."""


class UserInputError(ChaplyginError, ValueError):
    """Input that a user can fix: the message says what is wrong and how to fix it."""


class DerivationError(ChaplyginError):
    """A mechanical description the derivation engine cannot turn into a model."""


class CacheError(UserInputError):
    """A cache folder cannot be used safely (others can write to it, it is not ours, or it
    is read-only); the message says how to fix it (CHAPLYGIN_CACHE_DIR, chmod)."""


class ComputationError(ChaplyginError, RuntimeError):
    """A numerical computation did not reach its result (an integration that failed, a return
    to the initial state that was not found); the message says what happened."""


def did_you_mean(word: object, choices: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the choice closest to ``word``, or ``""`` if none is close
    (for the messages of :class:`UserInputError` that list the valid names).

    Parameters
    ----------
    word : object
        What the user typed.
    choices : iterable of str
        The valid names.

    Returns
    -------
    str
    """
    close = difflib.get_close_matches(str(word), list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""
