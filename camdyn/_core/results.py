"""What result types share: :class:`Unavailable`, a result that could not be had, in place of a value, and
:func:`finite_or_none`, a number as JSON writes it."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Unavailable:
    """A part of a result that could not be computed for this case, and why (one sentence a user can act on)."""

    reason: str

    def __str__(self) -> str:
        return self.reason


def finite_or_none(x: float | None) -> float | None:
    """``x`` as a result's JSON gives it: None (``null``) where it is not finite (no jump found: an unbounded speed)
    or not there."""
    return None if x is None or not math.isfinite(x) else float(x)
