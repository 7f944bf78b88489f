"""The look of a report: page size, PNG resolution, the matplotlib style and the palette."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import matplotlib
from matplotlib.figure import Figure
from matplotlib.ticker import ScalarFormatter
from matplotlib.typing import RcKeyType

from ..plot import PALETTE as C  # noqa: F401  (one meaning per colour, on every page)

A4 = (8.27, 11.69)  # portrait, inches
DPI = 150  # PNG resolution: 1240 x 1754 px per page, legible on a projector

LEFT = 0.11  # left edge of plot axes (figure fraction)
RIGHT = 0.87  # right edge of plot axes with time units on their right

# One style for every figure: legible on A4 when printed or shown full screen.
STYLE: dict[RcKeyType, Any] = {
    "font.family": "DejaVu Sans",
    "font.size": 8.5,
    "axes.titlesize": 9.5,
    "axes.titleweight": "bold",
    "axes.titlelocation": "left",
    "axes.labelsize": 8.5,
    "axes.linewidth": 0.7,
    "axes.edgecolor": "#444444",
    "axes.grid": True,
    "grid.color": "#cccccc",
    "grid.linewidth": 0.5,
    "grid.alpha": 0.8,
    "xtick.labelsize": 7.5,
    "ytick.labelsize": 7.5,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "legend.fontsize": 7.5,
    "legend.frameon": True,
    "legend.framealpha": 0.9,
    "legend.edgecolor": "#cccccc",
    "lines.linewidth": 1.2,
    "lines.solid_capstyle": "round",
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
    "path.simplify": True,
    "axes.formatter.use_mathtext": True,
    "axes.formatter.limits": (-4, 5),
    "svg.hashsalt": "camdyn",
}


_MATH = r"$\mathdefault{"  # how ScalarFormatter wraps a label it typesets as mathematics


class PlainTicks(ScalarFormatter):
    """The style's tick labels as plain text: ``axes.formatter.use_mathtext`` is for the offset's "x 10^n", but it
    typesets every tick label as mathematics too (a tenth of a report's drawing time), in the same glyphs."""

    def __call__(self, x: float, pos: int | None = None) -> str:
        label = super().__call__(x, pos)
        return label[len(_MATH) : -2] if label.startswith(_MATH) and label.endswith("}$") else label


def plain_ticks(fig: Figure) -> None:
    """Every axis of ``fig`` that labels its ticks with matplotlib's default formatter labels them with
    :class:`PlainTicks` (called within :func:`style`, whose settings the new formatters take)."""
    axes: list[Any] = list(fig.axes)  # Axes, and their children (matplotlib types those as its private base)
    while axes:
        ax = axes.pop()
        axes.extend(ax.child_axes)  # a secondary axis (another unit on the same scale)
        for axis in (ax.xaxis, ax.yaxis):
            if type(axis.get_major_formatter()) is ScalarFormatter:
                axis.set_major_formatter(PlainTicks())


@contextmanager
def style() -> Iterator[None]:
    """Draw in the report's style (matplotlib rc settings, restored on exit)."""
    with matplotlib.rc_context(STYLE):
        yield
