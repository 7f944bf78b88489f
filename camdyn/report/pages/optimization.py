"""The optimization page of a case ``camdyn optimize`` wrote: its motion and its holding against the original's."""

from __future__ import annotations

import textwrap

from matplotlib.figure import Figure

from ...design.review import Original
from ...plot import plot_motion_before_after, plot_speed_before_after
from .._data import ReportData
from .._style import LEFT, RIGHT, C


def draw_optimization(fig: Figure, data: ReportData) -> None:
    review = data.review
    gs = fig.add_gridspec(
        6, 1, left=LEFT, right=RIGHT, top=0.885, bottom=0.1, hspace=0.35, height_ratios=[2, 2, 2, 2, 0.3, 3.2]
    )
    axes = [fig.add_subplot(gs[0])]
    axes += [fig.add_subplot(gs[i], sharex=axes[0]) for i in (1, 2, 3)]
    plot_motion_before_after(axes, review)
    plot_speed_before_after(fig.add_subplot(gs[5]), review)
    assert isinstance(review.original, Original)  # the page is drawn for a loaded original only (pages.PAGES)
    b, a = review.original.check, review.check
    speed = "dynamic jump speed" if data.case.valvetrain is None else "valve float speed (two masses)"
    note = (
        f"Reshaped from {data.case.spec.optimized_from} by camdyn optimize: {speed} "
        f"{b.dynamic.jump_speed_rpm:.1f} -> {a.dynamic.jump_speed_rpm:.1f} rpm, least force at {a.speed_rpm:g} "
        f"rpm {b.dynamic.min_contact_force_N:.3g} -> {a.dynamic.min_contact_force_N:.3g} N, verdict {b.verdict} "
        f"-> {a.verdict}. The segment boundaries, lifts and dwells are the original's."
    )
    fig.text(LEFT, 0.05, "\n".join(textwrap.wrap(note, 125)), size=7.5, color=C["grey"], va="top")
