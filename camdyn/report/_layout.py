"""Text on a page: the header and footer, a top-down text flow, number formatting."""

from __future__ import annotations

import math
import textwrap
from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ._style import C

if TYPE_CHECKING:
    from ._data import ReportData


def camdyn_version() -> str:
    try:
        return version("camdyn")
    except PackageNotFoundError:  # pragma: no cover
        return "0"


def hline(fig: Figure, y: float, x0: float = 0.06, x1: float = 0.94, **kw: Any) -> Line2D:
    """A horizontal rule across the page at height ``y`` (figure fraction)."""
    return Line2D(
        [x0, x1], [y, y], transform=fig.transFigure, color=kw.pop("color", "#bbbbbb"), linewidth=kw.pop("lw", 0.8), **kw
    )


def header(fig: Figure, data: ReportData, title: str, number: int, total: int) -> None:
    """The case name and page title on top, the source, speed and page number at the foot."""
    case = data.case
    src = case.source.name if case.source is not None else case.name
    sha = f"  \u00b7  sha256 {data.case_sha256[:12]}" if data.case_sha256 else ""
    foot = f"design review  \u00b7  {src}{sha}  \u00b7  {data.check.speed_rpm:g} rpm"
    page_frame(fig, case.name, title, number, total, foot, verdict=data.check.verdict)


def page_frame(
    fig: Figure, name: str, title: str, number: int, total: int, foot: str, verdict: str | None = None
) -> None:
    """A page's name and title on top (``verdict``, "pass" or "fail", in a badge beside the name), camdyn's
    version, ``foot`` and the page number at the foot."""
    text = fig.text(0.06, 0.975, name, size=15, weight="bold", va="top", color=C["ink"])
    if verdict is not None:  # the verdict on every page, just right of the name
        renderer = fig._get_renderer()  # pyright: ignore[reportAttributeAccessIssue] - matplotlib's, not in its stubs
        x = 0.06 + text.get_window_extent(renderer).width / (fig.dpi * fig.get_figwidth()) + 0.015
        passed = verdict == "pass"
        fig.text(
            x,
            0.9715,
            "PASS" if passed else "FAIL",
            size=10,
            weight="bold",
            va="top",
            color="white",
            bbox=dict(boxstyle="round,pad=0.25", fc=C["ok"] if passed else C["fail"], ec="none"),
        )
    fig.text(0.94, 0.973, f"{number}  {title}", size=12.5, ha="right", va="top", color=C["grey"])
    fig.add_artist(hline(fig, 0.948))
    fig.text(0.06, 0.014, f"camdyn {camdyn_version()} {foot}", size=7, color=C["grey"])
    fig.text(0.94, 0.014, f"page {number} of {total}", size=7, color=C["grey"], ha="right")


def fmt(v: float | None, digits: int = 4) -> str:
    """A value for a table: numbers to ``digits`` significant digits, inf and None as "unbounded"."""
    if v is None:
        return "unbounded"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float | int | np.floating):
        v = float(v)
        if not math.isfinite(v):
            return "unbounded"
        return f"{v:.{digits}g}"
    if isinstance(v, list | tuple):
        if len(v) > 4:
            return f"{len(v)} values"
        return "(" + ", ".join(fmt(x) for x in v) + ")"
    return str(v)


def pretty_unit(unit: str) -> str:
    """A unit as camdyn's text output writes it (N*m/rad) as a report prints it (N\u00b7m/rad)."""
    return unit.replace("*", "\u00b7")


class Flow:
    """Top-down text layout on a figure (figure coordinates); ``y`` is the top of the next line."""

    def __init__(self, fig, y: float, left: float = 0.06, right: float = 0.94) -> None:
        self.fig, self.y, self.left, self.right = fig, y, left, right

    def h(self, size: float, lines: float = 1.0) -> float:
        """The height (figure fraction) of ``lines`` lines of text of ``size`` points."""
        return lines * size * 1.45 / 72.0 / self.fig.get_figheight()

    def heading(self, text: str) -> None:
        self.y -= self.h(10.5) * 0.6
        self.fig.text(self.left, self.y, text, size=10.5, weight="bold", va="top", color=C["ink"])
        self.y -= self.h(10.5)
        self.fig.add_artist(
            hline(self.fig, self.y + self.h(10.5) * 0.12, self.left, self.right, color="#dddddd", lw=0.6)
        )
        self.y -= self.h(10.5) * 0.15

    def row(self, cells: list[tuple[float, str, dict]], size: float = 8.0) -> None:
        """cells: (x as a fraction of the flow width, text, text kwargs)."""
        for x, text, kw in cells:
            self.fig.text(self.left + x * (self.right - self.left), self.y, text, **({"size": size, "va": "top"} | kw))
        self.y -= self.h(size)

    def para(self, text: str, size: float = 8.0, width: int = 118, indent: float = 0.0, **kw: Any) -> None:
        lines = textwrap.wrap(text, width) or [""]
        self.fig.text(self.left + indent, self.y, "\n".join(lines), size=size, va="top", linespacing=1.3, **kw)
        self.y -= self.h(size, len(lines)) * 0.93


def verdict_block(fig: Figure, flow: Flow, passed: bool, headline: str, subline: str) -> None:
    """Page 1's large PASS or FAIL at the flow's left margin, a bold ``headline`` beside it and a grey ``subline``
    under that; the flow moves down past the block."""
    flow.y -= flow.h(10)
    fig.text(
        flow.left + 0.012,
        flow.y,
        "PASS" if passed else "FAIL",
        size=26,
        weight="bold",
        va="top",
        color="white",
        bbox={"boxstyle": "round,pad=0.35", "fc": C["ok"] if passed else C["fail"], "ec": "none"},
    )
    fig.text(flow.left + 0.2, flow.y + 0.002, headline, size=12, va="top", weight="bold", color=C["ink"])
    fig.text(flow.left + 0.2, flow.y - flow.h(12), subline, size=8.5, va="top", color=C["grey"])
    flow.y -= flow.h(26) * 1.35
