"""What result types share: :class:`Unavailable`, a result that could not be had, in place of a value."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Unavailable:
    """A part of a result that could not be computed for this case, and why (one sentence a user can act on)."""

    reason: str

    def __str__(self) -> str:
        return self.reason
