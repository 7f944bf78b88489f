"""What the command line shows: rich tables, coloured notes, and the progress bar of long computations."""

from __future__ import annotations

import json
import math
import sys
import time
from collections.abc import Iterable, Iterator
from contextlib import contextmanager

from rich.console import Console, JustifyMethod
from rich.markup import escape
from rich.table import Table

from .._core.errors import NumericalError
from .._core.progress import Progress as ProgressFn


def console() -> Console:
    return Console(highlight=False, soft_wrap=True)


def table(*columns: tuple[str, JustifyMethod]) -> Table:
    """An aligned table without borders; columns as (header, justify)."""
    t = Table(show_edge=False, pad_edge=False, box=None, header_style="bold")
    for name, just in columns:
        t.add_column(name, justify=just, no_wrap=just == "right")
    return t


def notes(con: Console, kind: str, colour: str, texts: Iterable[str]) -> None:
    """One line per note: ``kind: text`` (the text escaped, never read as markup)."""
    for text in texts:
        con.print(f"[{colour}]{kind}:[/{colour}] {escape(text)}")


@contextmanager
def progress_bar(quiet: bool = False) -> Iterator[ProgressFn]:
    """Yields the ``progress(phase, done, total)`` callback that camdyn's long computations take: a rich bar per
    phase on a terminal; where stderr is a pipe or a log, one line as each phase starts and one as it ends, so a
    long run is never silent; nothing with ``quiet`` (``--quiet``)."""
    if quiet:
        yield lambda phase, done, total: None
    elif sys.stderr.isatty():
        # rich's progress (live display, spinners) loads only for a bar: every command imports this module
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

        columns = (
            SpinnerColumn(),
            TextColumn("{task.description:<34}"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
        )
        with Progress(*columns, console=Console(stderr=True)) as bar:
            tasks: dict = {}

            def progress(phase: str, done: int, total: int) -> None:
                if phase not in tasks:
                    tasks[phase] = bar.add_task(phase, total=total)
                bar.update(tasks[phase], completed=done, total=total)

            yield progress
    else:
        yield _phase_lines()


def _phase_lines():
    """The progress callback for a pipe: ``camdyn: <phase> ...`` when a phase starts, ``... done in N s`` at its end."""
    started: dict[str, float] = {}
    ended: set[str] = set()
    last = [time.perf_counter()]  # a phase first heard of at its end began when the one before it ended

    def progress(phase: str, done: int, total: int) -> None:
        now = time.perf_counter()
        finished = bool(total) and done >= total
        if phase not in started:
            started[phase] = now if not finished else last[0]
            if not finished:
                print(f"camdyn: {phase} ...", file=sys.stderr, flush=True)
        if finished and phase not in ended:
            ended.add(phase)
            print(f"camdyn: {phase} done in {now - started[phase]:.1f} s", file=sys.stderr, flush=True)
        last[0] = now

    return progress


def _finite(value, where: str):
    """``value`` with infinities as None (the contract's "unbounded"); a NaN is a failure naming its key."""
    if isinstance(value, dict):
        return {k: _finite(v, f"{where}.{k}" if where else str(k)) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if hasattr(value, "item") and not isinstance(value, str):  # numpy scalars
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        if math.isnan(value):
            raise NumericalError(f"json {where}", "is not a number (NaN): the computation behind it failed")
        return None
    return value


def json_text(doc: dict) -> str:
    """A JSON document for scripts: strict JSON (no NaN or Infinity tokens), infinities written as null."""
    return json.dumps(_finite(doc, ""), indent=2, allow_nan=False)
