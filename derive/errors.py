"""Exceptions shared by every layer.

`UserInputError` is the one exception the command line turns into a single line on
stderr and exit code 2: raise it for anything a user typed wrong (unknown system,
effect or parameter, a non-physical value, a malformed number).
"""

from __future__ import annotations

__all__ = ["ChaplyginError", "UserInputError", "DerivationError", "CacheError", "ComputationError"]


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
