"""Page 2, the follower motion: lift, velocity, acceleration and jerk, with the jumps at the breaks flagged."""

from __future__ import annotations

import dataclasses
import textwrap

import numpy as np
from matplotlib.figure import Figure

from ...plot import plot_fit, plot_svaj, svaj_quantities
from .._data import ReportData
from .._style import LEFT, RIGHT, C


def draw_svaj(fig: Figure, data: ReportData) -> None:
    segs = getattr(data.case.motion, "segments", ())
    fit = data.case.fit  # a lift table or a contour: its data and the fit's residuals are shown too
    if fit is None:
        gs = fig.add_gridspec(4, 1, left=LEFT, right=RIGHT, top=0.885, bottom=0.12, hspace=0.12)
        rows = [0, 1, 2, 3]
    else:
        gs = fig.add_gridspec(
            5, 1, left=LEFT, right=RIGHT, top=0.885, bottom=0.12, hspace=0.3, height_ratios=[3, 1.4, 3, 3, 3]
        )
        rows = [0, 2, 3, 4]
    axes = [fig.add_subplot(gs[rows[0]])]
    axes += [fig.add_subplot(gs[i], sharex=axes[0]) for i in rows[1:]]
    samples = dataclasses.replace(data.review.motion, breaks_deg=data.breaks_deg)  # dotted: segment boundaries only
    plot_svaj(axes, samples, speed_rpm=data.check.speed_rpm, headroom=2.2 if segs else 1.0)
    if fit is not None:
        plot_fit(axes[0], fig.add_subplot(gs[1], sharex=axes[0]), fit, data.case.contour)
    _segment_laws(axes[0], segs)
    compact = _mark_jumps(axes, data)
    _note(fig, data, compact)


def _segment_laws(ax, segs) -> None:
    """The law of each segment along the top of the lift panel, shortened where the whole name does not fit
    between the segment's boundaries, and left out where neither does (a boundary's line would strike it)."""
    ymax = ax.get_ylim()[1]
    renderer = ax.figure._get_renderer()  # pyright: ignore[reportAttributeAccessIssue] - matplotlib's, not in its stubs
    to_deg = ax.transData.inverted()
    for seg in segs:
        short = seg.law.replace("polynomial-", "poly-").replace("modified-", "mod-").replace("polynomial", "poly")
        for label in dict.fromkeys((seg.law, short)):
            t = ax.text(0.5 * (seg.start + seg.end), ymax, label, ha="center", va="top", size=7.2, color=C["grey"])
            box = t.get_window_extent(renderer)
            width = float(np.ptp(to_deg.transform([[box.x0, box.y0], [box.x1, box.y0]])[:, 0]))
            if width <= 0.9 * (seg.end - seg.start):
                break
            t.remove()


def _is_compact(jumps) -> bool:
    """Many jumps or close ones: values only on the plot, listed in the note (a label in words takes about 100 deg
    of the page's width: closer jumps would run into each other)."""
    degs = sorted({d for d, _, _ in jumps})
    gaps = np.diff(degs + [degs[0] + 360.0]) if degs else np.array([360.0])
    return len(degs) > 4 or float(gaps.min()) < 100.0


def _mark_jumps(axes, data: ReportData) -> bool:
    """Velocity jumps (infinite acceleration) and acceleration jumps (infinite jerk) in red; returns whether
    they are shown compact (values only)."""
    jumps = data.jumps
    names = svaj_quantities(data.case.motion.unit)
    compact = _is_compact(jumps)
    for k, (deg, order, jump) in enumerate(jumps):
        ax = axes[order]
        y_lo, y_hi = ax.get_ylim()
        at = (0.0, 360.0) if deg == 0.0 else (deg,)
        x_txt = deg + (2.5 if deg < 300 else -2.5)
        what = "velocity" if order == 1 else "acceleration"
        text = f"{jump:+.3g}" if compact else f"{what} jumps {jump:+.3g} {names[order][1]}"
        height = (0.9, 0.76, 0.62)[k % 3] if compact else 0.86
        ax.text(
            x_txt,
            y_lo + height * (y_hi - y_lo),
            text,
            size=7 if not compact else 6.5,
            color=C["limit"],
            ha="left" if deg < 300 else "right",
            va="center",
        )
        for ax_k in axes[order : order + 2]:
            for a in at:
                ax_k.axvline(a, color=C["limit"], lw=1.1, alpha=0.5, zorder=0.7)
        if order + 1 < 4 and not compact:
            nxt = axes[order + 1]
            ny_lo, ny_hi = nxt.get_ylim()
            nxt.text(
                x_txt,
                ny_lo + 0.68 * (ny_hi - ny_lo),
                f"infinite {'acceleration' if order == 1 else 'jerk'}",
                size=7,
                color=C["limit"],
                ha="left" if deg < 300 else "right",
                va="center",
            )
    if compact:
        for order in sorted({o for _, o, _ in jumps}):
            if order + 1 < 4:
                axes[order + 1].text(
                    0.995,
                    0.96,
                    f"red lines: infinite {'acceleration' if order == 1 else 'jerk'}",
                    transform=axes[order + 1].transAxes,
                    size=7,
                    color=C["limit"],
                    ha="right",
                    va="top",
                    bbox=dict(fc="white", ec="none", alpha=0.85, pad=0.8),
                )
    return compact


def _note(fig, data: ReportData, compact: bool) -> None:
    jumps = data.jumps
    names = svaj_quantities(data.case.motion.unit)
    what = "segment boundaries" if getattr(data.case.motion, "segments", ()) else "breaks of the path's curvature"
    if data.breaks_deg:
        note = f"Dotted: {what}."
    else:
        note = "No segment boundaries: the motion is smooth all round."
    note += f" Right axes: the same curves in time units at {data.check.speed_rpm:g} rpm."
    if jumps:
        note += " Red: a velocity or acceleration jump at a boundary, and the infinite acceleration or jerk it causes."
        if compact:
            for order, what in ((1, "Velocity"), (2, "Acceleration")):
                listed = [f"{d:.1f}\u00b0 {j:+.3g}" for d, o, j in jumps if o == order]
                if listed:
                    note += f" {what} jumps ({names[order][1]}): " + ", ".join(listed) + "."
    elif data.breaks_deg:
        note += f" Velocity and acceleration are continuous at every one of the {what}."
    if data.case.fit is not None:
        method = data.case.fit.method
        if data.case.contour is not None:
            note += (
                f" Red dots: the lift at exact contact with the outline fitted to the {data.case.contour.point_count} "
                f"points of {data.case.contour.file}; the curves are its fit ({method}). The residual panel is the "
                "outline's (radial, against polar angle)."
            )
        else:
            note += f" Red dots: the {data.case.fit.source}'s points; the curves are its fit ({method})."
    if data.case.kind.rotary:
        note += " The swing is in degrees per radian of cam angle."
    fig.text(
        0.06, 0.068, "\n".join(textwrap.wrap(note, 128)[:4]), size=7.3, color=C["grey"], va="top", linespacing=1.25
    )
