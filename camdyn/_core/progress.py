"""The one progress protocol of camdyn's long computations: ``progress(phase, done, total)``.

Library functions take an optional callable of this shape and call it as work completes; the command line
draws it (a rich bar on a terminal). Nothing here draws.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Protocol


class Progress(Protocol):
    def __call__(self, phase: str, done: int, total: int) -> None: ...


def silent(phase: str, done: int, total: int) -> None:
    """A progress callback that reports nothing."""


class Tick(Protocol):
    def __call__(self, n: int = 1) -> None: ...

    def finish(self) -> None: ...


class _Counter:
    def __init__(self, progress: Progress | None, phase: str, total: int) -> None:
        self.progress, self.phase, self.total, self.done = progress, phase, total, 0

    def __call__(self, n: int = 1) -> None:
        self.done += n
        if self.progress is not None:
            self.progress(self.phase, self.done, self.total)

    def finish(self) -> None:
        """The phase complete (a search that ends before its most steps), once."""
        if self.done < self.total:
            self(self.total - self.done)


def counter(progress: Progress | None, phase: str, total: int) -> Tick:
    """``tick(n)``: advance ``phase`` by n of ``total`` on ``progress`` (nothing when it is None); ``tick.finish()``:
    the phase complete."""
    return _Counter(progress, phase, total)


@contextmanager
def phase(progress: Progress | None, name: str) -> Iterator[None]:
    """A phase of no countable steps: reported started on entry and done on a normal exit."""
    if progress is not None:
        progress(name, 0, 1)
    yield
    if progress is not None:
        progress(name, 1, 1)
