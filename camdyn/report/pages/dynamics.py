"""Page 4, the dynamics: the contact force at the case speed and at speed_margin x speed, the follower's
displacement and vibration, and the least contact force against cam speed."""

from __future__ import annotations

from matplotlib.figure import Figure

from ..._core.results import Unavailable
from ...plot import (
    legend_above_data,
    plot_contact_force,
    plot_displacement,
    plot_event_cam_force,
    plot_force_vs_speed,
    plot_vibration,
)
from .._data import ReportData
from .._style import LEFT, C


def draw_dynamics(fig: Figure, data: ReportData) -> None:
    gs = fig.add_gridspec(5, 1, left=LEFT, right=0.95, top=0.925, bottom=0.06, hspace=0.38)
    ax_f = fig.add_subplot(gs[0])
    ax_m = fig.add_subplot(gs[1], sharex=ax_f)
    ax_x = fig.add_subplot(gs[2], sharex=ax_f)
    ax_v = fig.add_subplot(gs[3], sharex=ax_f)
    ax_w = fig.add_subplot(gs[4])
    _force_panels(ax_f, ax_m, data)
    for ax in (ax_f, ax_m, ax_x):
        ax.tick_params(labelbottom=False)
    chk, rv, unit = data.check, data.review, data.case.motion.unit
    rpm = chk.speed_rpm
    plot_displacement(ax_x, chk.response, unit=unit, speed_rpm=rpm, breaks_deg=data.breaks_deg)
    curves = [(chk.response, C["dyn"], f"{rpm:g} rpm")]
    if not isinstance(rv.margin_response, Unavailable):
        curves.append((rv.margin_response, C["margin"], f"{rv.margin_rpm:g} rpm"))
    plot_vibration(ax_v, curves, unit=unit, breaks_deg=data.breaks_deg)
    plot_force_vs_speed(ax_w, rv)


_TWO_MASSES = ": two masses over the valve event, one equivalent mass all round"


def _force_panels(ax_f, ax_m, data: ReportData) -> None:
    """The contact force at the case speed and at speed_margin x speed, on one force scale."""
    rpm, rv, valve = data.check.speed_rpm, data.review, data.check.valvetrain
    osc = " (contact force: torque / lever arm)" if data.case.kind.rotary else ""
    # a valvetrain is judged by its two-mass model over the valve event (page 1, the valvetrain page): its force and
    # least over the equivalent single follower's, whose own least is not marked (it is not the one judged)
    equivalent = None if valve is None else f"one equivalent mass ({data.check.response.model})"
    plot_contact_force(
        ax_f,
        data.check.response,
        colour=C["dyn"],
        title=f"interface force at {rpm:g} rpm{osc}" + ("" if valve is None else _TWO_MASSES),
        breaks_deg=data.breaks_deg,
        legend=False,
        label=equivalent,
        mark_least=valve is None,
    )
    if valve is not None:
        plot_event_cam_force(ax_f, valve)
    m = data.case.limits.speed_margin
    if isinstance(rv.margin_response, Unavailable):
        ax_m.text(
            0.5,
            0.5,
            f"no steady state at {rv.margin_rpm:g} rpm:\n{rv.margin_response}",
            transform=ax_m.transAxes,
            ha="center",
            va="center",
            color=C["fail"],
            size=8,
            wrap=True,
        )
        ax_m.set_title(f"interface force at {m:g} \u00d7 speed = {rv.margin_rpm:g} rpm", fontsize=9)
        ax_m.set_yticks([])
        ax_m.grid(False)
        legend_above_data(ax_f, fontsize=7, ncol=2)
        return
    plot_contact_force(
        ax_m,
        rv.margin_response,
        colour=C["margin"],
        title=f"interface force at speed_margin {m:g} \u00d7 speed = {rv.margin_rpm:g} rpm"
        + ("" if valve is None else ", one equivalent mass"),
        breaks_deg=data.breaks_deg,
        legend=False,
        label=equivalent,
        mark_least=valve is None,
    )
    for _ in range(2):  # one force scale, raised until neither legend covers its curve
        lo = min(ax_f.get_ylim()[0], ax_m.get_ylim()[0])
        hi = max(ax_f.get_ylim()[1], ax_m.get_ylim()[1])
        ax_f.set_ylim(lo, hi)
        ax_m.set_ylim(lo, hi)
        for ax in (ax_f, ax_m):
            legend_above_data(ax, fontsize=7, ncol=2)
