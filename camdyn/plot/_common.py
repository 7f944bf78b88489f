"""What every figure shares: the palette (one meaning per colour), angle axes, breaks and separations."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.legend import Legend
from matplotlib.ticker import MultipleLocator

if TYPE_CHECKING:
    from ..model.drive import DriveTorque
    from ..model.dynamics import Response

# Colours with one meaning each, on every figure.
PALETTE = {
    "kin": "#7f7f7f",  # kinematic (rigid follower, never leaves the cam)
    "dyn": "#1f5fa8",  # dynamic at the case speed
    "margin": "#e07b00",  # dynamic at speed_margin x speed
    "limit": "#c0392b",  # limits, failures, separations
    "ok": "#2e8540",
    "fail": "#c0392b",
    "break": "#999999",  # segment boundaries
    "cam": "#dfe4ea",
    "ink": "#222222",
    "grey": "#666666",
    "warn": "#a86800",
    "advice": "#1b6e75",
    "path": "#9ecae1",
    "traced": "#d62728",
    "constraint": "#b3b3b3",  # one cam angle's constraint on the spring
    "iso": "#7b4fa0",  # iso-lines of the peak spring force
}
C = PALETTE


def deg_ticks(ax: Axes, every: float = 45.0) -> None:
    """A cam-angle x axis: one revolution, a tick every ``every`` degrees."""
    ax.set_xlim(0.0, 360.0)
    ax.xaxis.set_major_locator(MultipleLocator(every))


def mark_breaks(ax: Axes, breaks_deg: Iterable[float]) -> None:
    """Dotted lines at the motion's breaks (segment boundaries), behind the curves."""
    for b in breaks_deg:
        ax.axvline(b, color=C["break"], lw=0.7, ls=":", zorder=0.5)


def flight_spans(response: Response) -> list[tuple[float, float]]:
    """The cam-angle spans (deg, within [0, 360]) where the interface force is zero: one per flight, two where a
    flight wraps through 0 deg."""
    out = []
    for f in response.flights:
        out += [(f.leave_deg, f.land_deg)] if f.land_deg >= f.leave_deg else [(f.leave_deg, 360.0), (0.0, f.land_deg)]
    return out


def shade_separations(ax: Axes, response: Response, label: bool = False) -> None:
    """Shade the cam angles where the follower is off the cam: exactly where the interface force is zero (a
    separation that bounces is several flights, the impacts between them left unshaded)."""
    for k, (a, b) in enumerate(flight_spans(response)):
        ax.axvspan(
            a,
            b,
            color=C["limit"],
            alpha=0.13,
            lw=0,
            zorder=0.4,
            label="separated (force 0)" if (label and k == 0) else None,
        )


def legend_above_data(
    ax: Axes, margin: float = 0.04, also: Iterable[float] = (), twins: Iterable[Axes] = (), **kw: Any
) -> Legend:
    """A legend in the upper right, with the y axis raised so that no line's data (within the x limits) reaches
    up into it: a legend never covers a curve. ``also``: more heights (data units) to keep clear, e.g. of
    horizontal reference lines; ``twins``: axes drawn over ``ax`` (``twinx``), whose lines are kept clear too.
    ``kw``: the legend's keywords (ncol, fontsize, ...)."""
    leg = ax.legend(**({"loc": "upper right"} | kw))
    fig = ax.figure
    renderer = fig._get_renderer()  # pyright: ignore[reportAttributeAccessIssue] - matplotlib's, not in its stubs
    box, frame = leg.get_window_extent(renderer), ax.get_window_extent(renderer)
    below = (box.y0 - frame.y0) / max(frame.height, 1.0)  # the legend's lower edge, a fraction of the axes' height
    _clear_below(ax, below - margin, max(also, default=-math.inf))
    for twin in twins:
        _clear_below(twin, below - margin, -math.inf)
    return leg


def _clear_below(ax: Axes, fraction: float, top: float) -> None:
    """Raise ``ax``'s upper y limit so that its lines' data (within the x limits) and ``top`` stay under
    ``fraction`` of its height."""
    lo, hi = ax.get_ylim()
    x0, x1 = ax.get_xlim()
    for line in ax.lines:
        if line.get_transform() != ax.transData:  # axhline, axvline: not data
            continue
        x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
        if x.size == y.size and x.size:
            inside = (x >= min(x0, x1)) & (x <= max(x0, x1)) & np.isfinite(y)
            if inside.any():
                top = max(top, float(y[inside].max()))
    if math.isfinite(top) and fraction > 0.2:
        need = lo + (top - lo) / fraction
        if need > hi:
            ax.set_ylim(lo, need)


def rotate(angle_rad: float, xy: np.ndarray) -> np.ndarray:
    """Points (2, ...) turned by ``angle_rad`` about the origin."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s], [s, c]]) @ xy


def _data_points(ax) -> np.ndarray:
    """The display coordinates (k, 2) of every point of the axes' data lines (not of axhline or axvline)."""
    pts = [
        np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)])
        for line in ax.lines
        if line.get_transform() == ax.transData and np.size(line.get_xdata()) == np.size(line.get_ydata())
    ]
    pts = [p[np.all(np.isfinite(p), axis=1)] for p in pts if p.size]
    return ax.transData.transform(np.concatenate(pts)) if pts else np.zeros((0, 2))


LEGEND_PLACES = (
    "lower left",
    "upper right",
    "lower right",
    "upper left",
    "center left",
    "center right",
    "lower center",
    "upper center",
)


def legend_clear(ax: Axes, places: Sequence[str] = LEGEND_PLACES, **kw: Any) -> Legend:
    """A legend in the first of ``places`` where it covers no point of a data curve (the one covering the fewest
    where none is clear). ``kw``: the legend's keywords."""
    renderer = ax.figure._get_renderer()  # pyright: ignore[reportAttributeAccessIssue] - matplotlib's, not in its stubs
    pts = _data_points(ax)
    best, best_n = places[0], None
    for loc in places:
        leg = ax.legend(**({"loc": loc} | kw))
        box = leg.get_window_extent(renderer)
        n = int(
            np.count_nonzero(
                (pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)
            )
        )
        if n == 0:
            return leg
        if best_n is None or n < best_n:
            best, best_n = loc, n
    return ax.legend(**({"loc": best} | kw))


def mark_mean_and_peak_torque(ax: Axes, theta_deg: np.ndarray, drive: DriveTorque, mean_colour: str) -> None:
    """A drive torque's mean (dashed, with the mean power) and its peak (a dot), both named in the legend."""
    # a mean within the peak's round-off (a drive that stores and returns all it takes: no damper, no external load)
    # is named 0, not 1.26e-16 N*m
    zero = abs(drive.mean_torque) <= 1e-12 * drive.peak_torque
    mean, power = (0.0, 0.0) if zero else (drive.mean_torque, drive.mean_power)
    ax.axhline(mean, color=mean_colour, lw=0.8, ls="--", label=f"mean {mean:.3g} N\u00b7m ({power:.3g} W)")
    i = int(np.argmax(np.abs(drive.torque)))
    ax.plot(
        [theta_deg[i]],
        [drive.torque[i]],
        "o",
        color=C["limit"],
        ms=5,
        label=f"peak {drive.peak_torque:.3g} N\u00b7m at {drive.peak_torque_at_deg:.1f}\u00b0",
    )
    ax.axhline(0.0, color="0.6", lw=0.5)


def sample_histogram(
    ax: Axes,
    values: np.ndarray,
    limit: tuple[float, str],
    marks: Sequence[tuple[float, str, str]],
    title: str,
    xlabel: str,
) -> None:
    """A tolerance study's histogram of ``values`` (the samples'), the ``limit`` (x, label) as a red line and each
    of ``marks`` (x, line style, label: its percentiles) as a black one; NaN or infinite samples are left out."""
    shown = values[np.isfinite(values)]
    if shown.size:
        ax.hist(shown, bins=min(60, max(10, int(np.sqrt(shown.size)))), color=PALETTE["dyn"], alpha=0.8)
    ax.axvline(limit[0], color=PALETTE["limit"], lw=1.5, label=limit[1])
    for x, style, label in marks:
        ax.axvline(x, color=PALETTE["ink"], ls=style, lw=1, label=label)
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("samples")
    ax.legend(fontsize=8)
