"""An optimized cam against the one it was reshaped from: the motion before and after, and the least contact
force against cam speed of both with their jump speeds."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes

from .._core.results import Unavailable
from ._common import C, deg_ticks, mark_breaks
from .motion import display_scale, svaj_quantities

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.review import Original, Review


def _original(review: Review) -> Original:
    if review.original is None or isinstance(review.original, Unavailable):
        raise ValueError(f"no original to compare {review.case.name} with: {review.original}")
    return review.original


def plot_motion_before_after(axes: Sequence[Axes], review: Review) -> None:
    """s, s', s'', s''' of the original (dashed) and the optimized motion (solid) on four ``axes``."""
    original = _original(review)
    before, after = original.motion, review.motion
    names = svaj_quantities(after.unit)
    ends = tuple(seg.end % 360.0 for seg in getattr(review.case.motion, "segments", ()))  # segments, not knots
    k = display_scale(after.unit)
    for i, ax in enumerate(axes):
        ax.plot(
            before.theta_deg,
            before.values[i] * k,
            color=C["kin"],
            lw=1.0,
            ls="--",
            label=f"before ({original.case.name})",
        )
        ax.plot(after.theta_deg, after.values[i] * k, color=C["dyn"], lw=1.3, label=f"after ({review.case.name})")
        ax.axhline(0.0, color="#888888", lw=0.6, zorder=0.6)
        mark_breaks(ax, ends)
        ax.set_ylabel(f"{names[i][0]}\n({names[i][1]})")
    deg_ticks(axes[-1])
    axes[-1].set_xlabel("cam angle \u03b8 (deg)")
    axes[0].legend(loc="upper right", fontsize=7)


def plot_speed_before_after(ax: Axes, review: Review) -> None:
    """The least contact force against cam speed before (dashed) and after (solid), each up to its jump speed,
    with the jump speeds, the case speed and ``min_contact_force``."""
    original = _original(review)
    curves = (
        (original.force_vs_speed, original.check, "before", "--", C["kin"]),
        (review.force_vs_speed, review.check, "after", "-", C["dyn"]),
    )
    for sw, chk, label, ls, colour in curves:
        if isinstance(sw, Unavailable):  # a form-closed cam, which optimize refuses: nothing to compare
            continue
        speeds, force = sw.speeds_rpm, sw.dynamic_N if sw.dynamic_N is not None else sw.kinematic_N
        jump, what = chk.dynamic.jump_speed_rpm, "jump speed"
        if sw.valve_event is not None:  # a valvetrain: the two-mass model's, as its float speed
            (speeds, force), what = sw.valve_event, "float speed"
        held = speeds <= (jump if jump is not None and np.isfinite(jump) else np.inf)
        ax.plot(speeds[held], force[held], color=colour, ls=ls, lw=1.3, label=f"{label}: {what} {jump:.0f} rpm")
        if jump is not None and np.isfinite(jump):
            ax.axvline(jump, color=colour, lw=0.8, ls=ls)
    ax.axhline(review.case.limits.min_contact_force, color=C["limit"], lw=0.8, ls="--")
    ax.axvline(review.check.speed_rpm, color=C["margin"], lw=0.8, ls="-.")
    ax.text(
        review.check.speed_rpm,
        ax.get_ylim()[1],
        f" case speed {review.check.speed_rpm:g} rpm",
        color=C["margin"],
        size=7,
        va="top",
    )
    if not isinstance(review.force_vs_speed, Unavailable):
        ax.set_xlim(0.0, float(review.force_vs_speed.speeds_rpm[-1]))
    ax.set_xlabel("cam speed (rpm)")
    valvetrain = review.case.valvetrain is not None
    ax.set_ylabel("least cam force over the valve event (N)" if valvetrain else "least interface force (N)")
    what = "least cam force (two masses, valve event)" if valvetrain else "least interface force"
    ax.set_title(f"{what} against cam speed, before and after", fontsize=9)
    ax.legend(loc="lower left", fontsize=7)
