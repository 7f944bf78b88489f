"""Text on a page: the header and footer, a top-down text flow, number formatting."""

from __future__ import annotations

import functools
import math
import textwrap
from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.lines import Line2D
from matplotlib.path import Path
from matplotlib.textpath import TextPath

from ._style import DPI, C

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
        """cells: (x as a fraction of the flow width, text, text kwargs). A left-aligned one-line cell that would
        run into the next cell (or past the flow's right edge) is wrapped to the room it has, a line under the
        other, and the row is as tall as its most lines."""
        width = self.right - self.left
        placed = [(self.left + x * width, text, {"size": size, "va": "top"} | kw) for x, text, kw in cells]
        spans = [_span(self.fig, x, text, kw) for x, text, kw in placed]
        step = self.h(size) * _LINESPACING / 1.45
        most = 1
        for (x, text, kw), (_, end) in zip(placed, spans, strict=True):
            lines = [text]
            room = min((lo - _GAP for lo, _ in spans if lo > x + 1e-9), default=self.right) - x
            if kw.get("ha", "left") == "left" and "\n" not in text and end - x > room:
                lines = fit_lines(self.fig, text, room, kw)
            for k, line in enumerate(lines):
                self.fig.text(x, self.y - k * step, line, **kw)
            most = max(most, len(lines))
        self.y -= self.h(size) + (most - 1) * step

    def para(self, text: str, size: float = 8.0, width: int = 118, indent: float = 0.0, **kw: Any) -> None:
        """``text`` wrapped at ``width`` characters, or narrower where a line would pass the flow's right edge."""
        lines = self._para_lines(text, size, width, indent, kw)
        self.fig.text(self.left + indent, self.y, "\n".join(lines), size=size, va="top", linespacing=1.3, **kw)
        self.y -= self._para_height(size, lines)

    def para_height(self, text: str, size: float = 8.0, width: int = 118, indent: float = 0.0, **kw: Any) -> float:
        """How far :meth:`para` with these arguments moves the flow down (figure fraction)."""
        return self._para_height(size, self._para_lines(text, size, width, indent, kw))

    def _para_lines(self, text: str, size: float, width: int, indent: float, kw: dict) -> list[str]:
        return fit_lines(self.fig, text, self.right - self.left - indent, {"size": size} | kw, width) or [""]

    def _para_height(self, size: float, lines: list[str]) -> float:
        return self.h(size, len(lines)) * 0.93


_GAP = 0.004  # of the figure's width: the least space between a cell and the next
_LINESPACING = 1.3  # of a wrapped cell's lines, as a paragraph's


def _font(kw: dict) -> FontProperties:
    """The font a ``fig.text`` with these keywords draws in."""
    return FontProperties(family=kw.get("family"), size=kw.get("size"), weight=kw.get("weight"), style=kw.get("style"))


@functools.cache
def _png_renderer() -> RendererAgg:
    """A renderer at the PNG pages' resolution, to measure text with."""
    return RendererAgg(1, 1, DPI)


def text_width(fig: Figure, text: str, kw: dict) -> float:
    """The width of one line of ``text`` drawn with the ``fig.text`` keywords ``kw``, a fraction of the figure's:
    the wider of the PDF's (the glyphs' outlines) and the PNG's (hinted to whole pixels at :data:`DPI`: a line of
    small text comes out up to 8 % wider or narrower than in the PDF, and another resolution differs again)."""
    if not text:
        return 0.0
    font = _font(kw)
    png, _, _ = _png_renderer().get_text_width_height_descent(text, font, ismath=False)
    # a TextPath reads $...$ as mathematics, which the pages never draw: the PNG's width alone there
    vector = 0.0 if "$" in text or not text.strip() else ink_width(TextPath((0.0, 0.0), text, prop=font)) / 72.0
    return max(vector, png / DPI) / fig.get_figwidth()


def ink_width(path: Path) -> float:
    """How wide a path's outline is (its unit): :meth:`matplotlib.path.Path.get_extents`' width to round-off,
    vectorized (the curves' extrema in x, the quadratic and cubic Beziers at once: matplotlib's goes segment by
    segment in Python, 11 ms for a line of text and a third of a report's time)."""
    x = np.asarray(path.vertices, dtype=float)[:, 0]
    if path.codes is None:
        return float(np.ptp(x))
    codes = np.asarray(path.codes)
    quad, cube = codes == Path.CURVE3, codes == Path.CURVE4
    in_quad, in_cube = _run_position(quad), _run_position(cube)
    # a curve's points: its control points, then its end; the point before the first is its start
    ends = np.isin(codes, (Path.MOVETO, Path.LINETO)) | (quad & (in_quad % 2 == 1)) | (cube & (in_cube % 3 == 2))
    xs = [x[ends]]
    i = np.nonzero(quad & (in_quad % 2 == 0))[0]
    p0, p1, p2 = x[i - 1], x[i], x[i + 1]
    xs += [_bezier(t, (p0, p1, p2)) for t in _unit_roots(np.zeros_like(p0), p0 - 2.0 * p1 + p2, p1 - p0)]
    i = np.nonzero(cube & (in_cube % 3 == 0))[0]
    p0, p1, p2, p3 = x[i - 1], x[i], x[i + 1], x[i + 2]
    # dB/dt / 3 = a t^2 + b t + c
    a, b, c = -p0 + 3.0 * p1 - 3.0 * p2 + p3, 2.0 * (p0 - 2.0 * p1 + p2), p1 - p0
    xs += [_bezier(t, (p0, p1, p2, p3)) for t in _unit_roots(a, b, c)]
    every = np.concatenate(xs)
    return float(np.ptp(every)) if every.size else 0.0


def _run_position(flag: np.ndarray) -> np.ndarray:
    """Each index's position within its run of consecutive ``True`` (where ``flag``; elsewhere meaningless)."""
    idx = np.arange(flag.size)
    starts = flag & ~np.concatenate([[False], flag[:-1]])
    return idx - np.maximum.accumulate(np.where(starts, idx, 0))


def _unit_roots(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The real roots in (0, 1) of ``a t^2 + b t + c`` (elementwise; linear where ``a`` is 0): (t, which) pairs,
    ``which`` the polynomials' indices."""
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(b * b - 4.0 * a * c)
        linear = np.where(b != 0.0, -c / b, np.nan)
        roots = [
            np.where(a != 0.0, (-b + disc) / (2.0 * a), linear),
            np.where(a != 0.0, (-b - disc) / (2.0 * a), np.nan),
        ]
    out = []
    for t in roots:
        which = np.nonzero((t > 0.0) & (t < 1.0))[0]
        out.append((t[which], which))
    return out


def _bezier(root: tuple[np.ndarray, np.ndarray], points: tuple[np.ndarray, ...]) -> np.ndarray:
    """The Bezier curves of control values ``points`` (each an array over the curves) at ``root`` = (t, which):
    de Casteljau, degree as many points less one."""
    t, which = root
    level = [p[which] for p in points]
    while len(level) > 1:
        level = [(1.0 - t) * u + t * v for u, v in zip(level[:-1], level[1:], strict=True)]
    return level[0]


def _span(fig: Figure, x: float, text: str, kw: dict) -> tuple[float, float]:
    """Where a text placed at ``x`` with these keywords starts and ends across the figure (its widest line)."""
    w = max(text_width(fig, line, kw) for line in text.split("\n"))
    ha = kw.get("ha", kw.get("horizontalalignment", "left"))
    return {"left": (x, x + w), "right": (x - w, x), "center": (x - w / 2, x + w / 2)}[ha]


def fit_lines(fig: Figure, text: str, room: float, kw: dict, width: int | None = None) -> list[str]:
    """``text`` wrapped at ``width`` characters (None: one line), then narrower until every line fits ``room``
    (a fraction of the figure's width) in the font of ``kw``; a word longer than the room stays whole."""
    lines = textwrap.wrap(text, width) if width else [text]
    chars = max((len(line) for line in lines), default=0)
    while chars > 1 and any(text_width(fig, line, kw) > room for line in lines):
        chars -= 1
        lines = textwrap.wrap(text, chars, break_long_words=False, break_on_hyphens=False)
    return lines


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
