"""The one progress protocol of camdyn's long computations: ``progress(phase, done, total)``.

Library functions take an optional callable of this shape and call it as work completes; the command line
draws it (a rich bar on a terminal). Nothing here draws.
"""

from __future__ import annotations

from typing import Protocol


class Progress(Protocol):
    def __call__(self, phase: str, done: int, total: int) -> None: ...


def silent(phase: str, done: int, total: int) -> None:
    """A progress callback that reports nothing."""


class Tick(Protocol):
    def __call__(self, n: int = 1) -> None: ...


def counter(progress: Progress | None, phase: str, total: int) -> Tick:
    """``tick(n)``: advance ``phase`` by n of ``total`` on ``progress`` (nothing when it is None)."""
    done = [0]

    def tick(n: int = 1) -> None:
        done[0] += n
        if progress is not None:
            progress(phase, done[0], total)

    return tick
