"""The parts page: the camshaft's drive torque, the Hertz contact stress (with a contact width), and the case's
own return spring as a part."""

from __future__ import annotations

import textwrap

from matplotlib.figure import Figure

from ..._core.results import Unavailable
from ...plot import plot_contact, plot_drive, plot_spring
from .._data import ReportData
from .._style import LEFT, C


def draw_parts(fig: Figure, data: ReportData) -> None:
    chk, part = data.check, data.review.spring_part
    if chk.contact is not None:
        gs = fig.add_gridspec(
            3, 1, left=LEFT, right=0.95, top=0.925, bottom=0.06, hspace=0.42, height_ratios=[1, 1, 1.5]
        )
        plot_contact(fig.add_subplot(gs[1]), chk.contact, data.case.limits.max_contact_stress)
    else:  # no width: a line says how to get the contact stress, the spring takes the room
        gs = fig.add_gridspec(
            3, 1, left=LEFT, right=0.95, top=0.925, bottom=0.06, hspace=0.3, height_ratios=[1, 0.15, 1.8]
        )
        _say(
            fig.add_subplot(gs[1]),
            "Contact stress: give [follower] width (or [mechanism] width for a path case), the contact's length along "
            "the camshaft in mm, and [materials] if not steel on steel.",
        )
    assert chk.drive is not None  # check computes the camshaft drive of every case (design.checks.check)
    plot_drive(fig.add_subplot(gs[0]), chk.drive)
    ax_s = fig.add_subplot(gs[2])
    if chk.closure is not None:
        _say(ax_s, f"return spring: none ({part})")
    elif isinstance(part, Unavailable):
        _say(ax_s, f"return spring: no spring of the case's rate and preload can be built within [spring]: {part}")
    else:
        plot_spring(ax_s, part)


def _say(ax, text: str) -> None:
    ax.axis("off")
    ax.text(
        0.0, 0.5, "\n".join(textwrap.wrap(text, 110)), transform=ax.transAxes, size=8.5, color=C["grey"], va="center"
    )
