"""The valvetrain page (cases with ``[valvetrain]``): the valve and the cam at the valve with the lash and its ramps,
the valve's velocity and the cam contact over the event, the seating velocity against cam speed with the float and
bounce speeds, and a rocker's ratio against cam angle, from ``check``'s two-mass model."""

from __future__ import annotations

from typing import TYPE_CHECKING

from matplotlib.figure import Figure

from ...plot import plot_rocker_ratio, plot_seating_velocity, plot_valve_lift, plot_valve_velocity
from .._data import ReportData
from .._layout import Flow, fmt
from .._style import LEFT, C

if TYPE_CHECKING:
    from ...design.valvetrain import ValvetrainResult


def draw_valvetrain(fig: Figure, data: ReportData) -> None:
    vt = data.check.valvetrain
    assert vt is not None  # the page applies to [valvetrain] cases only
    flow = Flow(fig, 0.94)
    flow.para(
        f"Rocker ratio {_ratio(vt)}, lash {vt.lash_mm:g} mm; valve lift {fmt(vt.response.max_valve_lift_mm)} mm, seats "
        f"at {fmt(vt.seating_velocity)} m/s; float at {fmt(vt.float_speed_rpm)} rpm, bounce at "
        f"{fmt(vt.bounce_speed_rpm)} rpm (searched to {vt.search_top_rpm:.0f} rpm); bounce height "
        f"{fmt(vt.response.bounce_height_mm)} mm at {data.check.speed_rpm:g} rpm{_coil_bind(vt)}.",
        size=8.5,
        width=115,
        color=C["ink"],
    )
    flow.para(
        "Two masses (the follower at the cam, the valve) on the train between them; the lash closes with the "
        "train's first compression, the valve lifts once the train's force passes the spring's preload, and lands "
        "on a rigid seat with its restitution. Float: the cam contact opens while the valve is off its seat.",
        size=7.5,
        width=140,
        color=C["grey"],
    )
    ax = fig.add_axes((LEFT, 0.6, 0.95 - LEFT, 0.24))
    plot_valve_lift(ax, vt)
    ax = fig.add_axes((LEFT, 0.32, 0.86 - LEFT, 0.2))
    plot_valve_velocity(ax, vt)
    rocker = vt.rocker_curves is not None  # its ratio against cam angle beside the seating velocity
    ax = fig.add_axes((LEFT, 0.06, (0.56 if rocker else 0.95) - LEFT, 0.19))
    plot_seating_velocity(ax, vt, data.case.limits.max_seating_velocity)
    if rocker:
        plot_rocker_ratio(fig.add_axes((0.66, 0.06, 0.29, 0.19)), vt)


def _coil_bind(vt: ValvetrainResult) -> str:
    """The spring's coil bind, where a designed spring gives it."""
    if vt.coil_bind_lift_mm is None:
        return ""
    return (
        f"; the spring goes solid at {fmt(vt.coil_bind_lift_mm)} mm of valve lift, "
        f"{fmt(vt.coil_bind_clearance_mm)} mm beyond the valve's largest"
    )


def _ratio(vt: ValvetrainResult) -> str:
    """The constant ratio, or a rocker's range over the lift and its value at peak lift."""
    if vt.rocker_curves is None:
        return f"{vt.ratio:g}"
    ratios = vt.ratios
    return f"{ratios.min():.4g} to {ratios.max():.4g} from the rocker's geometry ({vt.ratio:.4g} at peak lift)"
