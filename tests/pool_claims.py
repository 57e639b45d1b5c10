"""Claims that misbehave, for the worker-pool tests (importable by spawned workers)."""

from __future__ import annotations

import os
import time

from chaplygin.verify.claims import Claim
from chaplygin.verify.verdict import registered_claim


def _raises(model):
    raise ZeroDivisionError("a bug in a check")


def _hangs(model):
    time.sleep(3600)


def _dies(model):
    os._exit(7)


_BAD = {"pool/raises": _raises, "pool/hangs": _hangs, "pool/dies": _dies}


def lookup(claim_id: str) -> Claim:
    """A registered claim, or one of the misbehaving claims above."""
    if claim_id in _BAD:
        return Claim(
            id=claim_id,
            source="test",
            kind="integral",
            statement="misbehaves",
            system="chaplygin_ball",
            effects=(),
            build=_BAD[claim_id],
        )
    return registered_claim(claim_id)
