"""A valvetrain's figures (``result``: :class:`camdyn.design.valvetrain.ValvetrainResult`): the valve and the cam
at the valve over the event, the valve's velocity, its seating velocity against cam speed, and a rocker's ratio
against cam angle."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes

from .._core.units import TWO_PI
from ._common import C, deg_ticks, legend_above_data

if TYPE_CHECKING:
    from ..design.valvetrain import ValvetrainResult


def _event_window(resp, pad_deg: float = 30.0) -> tuple[float, float]:
    """The cam angles (deg) from ``pad_deg`` before the valve lifts to ``pad_deg`` after it last is off its seat,
    within [0, 360] (the whole turn for an event through 0 deg)."""
    lifted = resp.valve_lift > 0.0
    if not lifted.any() or lifted[0] or lifted[-1]:
        return 0.0, 360.0
    th = resp.theta_deg[lifted]
    return max(0.0, float(th.min()) - pad_deg), min(360.0, float(th.max()) + pad_deg)


def plot_valve_lift(ax: Axes, result: ValvetrainResult) -> None:
    """The valve's lift against the cam's lift at the valve (through the rocker, less the lash: where the valve would
    be on a rigid train), the lash and the ramps that take it up, around the valve event; opening and closing marked,
    and the lift at which a designed spring goes solid."""
    resp = result.response
    th = resp.theta_deg
    cam_label = "cam at the valve (through the rocker) - lash"
    ax.plot(th, result.cam_at_valve, color=C["kin"], ls="--", lw=1.0, label=cam_label)
    ax.plot(th, result.follower_at_valve, color=C["margin"], lw=0.9, label="follower at the valve")
    ax.plot(th, resp.valve_lift, color=C["dyn"], lw=1.3, label=f"valve at {resp.omega * 60 / TWO_PI:g} rpm")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    ax.axhline(-result.lash_mm, color=C["grey"], lw=0.6, ls=":", label=f"lash {result.lash_mm:g} mm")
    if result.coil_bind_lift_mm is not None:  # a designed spring's solid height: a stop the valve must not reach
        solid = result.coil_bind_lift_mm
        ax.axhline(solid, color=C["limit"], lw=0.8, ls="--", label=f"spring solid at {solid:.3g} mm valve lift")
    for deg in result.timing_deg:
        if math.isfinite(deg):
            ax.axvline(deg, color=C["grey"], lw=0.6)
    ax.set_ylabel("lift at the valve (mm)")
    ax.set_xlabel("cam angle (deg)")
    deg_ticks(ax, 30.0)
    ax.set_xlim(*_event_window(resp))
    opening, closing = result.timing_deg
    ax.set_title(
        f"valve lift: {resp.max_valve_lift_mm:.3g} mm, open {opening:.1f} to {closing:.1f} deg at 0.05 mm", fontsize=9
    )
    legend_above_data(ax, fontsize=7, ncol=2)


def plot_valve_velocity(ax: Axes, result: ValvetrainResult) -> None:
    """The valve's velocity (m/s) and the cam contact's force (N, right axis) around the valve event, the
    seating marked."""
    resp = result.response
    th = resp.theta_deg
    ax.plot(th, resp.valve_velocity, color=C["dyn"], lw=1.2, label="valve velocity")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    if math.isfinite(resp.seating_velocity):
        ax.plot(
            resp.seating_deg,
            -resp.seating_velocity,
            "v",
            color=C["limit"],
            ms=5,
            label=f"seats at {resp.seating_velocity:.3g} m/s, {resp.seating_deg:.1f} deg",
        )
    ax.set_ylabel("valve velocity (m/s)")
    ax.set_xlabel("cam angle (deg)")
    twin = ax.twinx()
    force = np.where(resp.in_event, resp.cam_force, np.nan)
    twin.plot(th, force, color=C["margin"], lw=0.9, label="cam contact force over the event")
    twin.set_ylabel("cam contact force (N)", color=C["margin"])
    twin.set_ylim(bottom=min(0.0, float(np.nanmin(force)) if np.isfinite(force).any() else 0.0))
    deg_ticks(ax, 30.0)
    ax.set_xlim(*_event_window(resp))
    ax.set_title("valve velocity and cam contact force", fontsize=9)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = twin.get_legend_handles_labels()
    legend_above_data(ax, fontsize=7, twins=(twin,), handles=h1 + h2, labels=l1 + l2)


def plot_event_cam_force(ax: Axes, result: ValvetrainResult) -> None:
    """The two-mass model's cam contact force (N) over the valve event, its least marked: what a valvetrain's
    contact force and float speed are judged by, drawn over a plot of the equivalent single follower's force."""
    resp = result.response
    if not resp.in_event.any():
        return
    force = np.where(resp.in_event, resp.cam_force, np.nan)
    ax.plot(resp.theta_deg, force, color=C["margin"], lw=1.3, label="two masses, valve event")
    i = int(np.nanargmin(force))
    least = resp.least_event_force
    ax.plot(
        resp.theta_deg[i],
        least,
        "o",
        color=C["margin"],
        ms=4,
        label=f"least {least:.3g} N at {resp.theta_deg[i]:.1f}\u00b0",
    )


def plot_seating_velocity(ax: Axes, result: ValvetrainResult, max_seating_velocity: float | None = None) -> None:
    """The valve's seating velocity against cam speed (the speeds the float and bounce searches marched, and their
    scan on to the result's ``seating_curve_top_rpm``), the limit, the case speed and the float and bounce speeds
    marked."""
    rpm = np.asarray(result.speeds_rpm)
    v = np.asarray(result.seating_velocities)
    ax.plot(rpm, v, ".-", color=C["dyn"], lw=1.0, ms=3, label="seating velocity")
    if max_seating_velocity is not None:
        ax.axhline(max_seating_velocity, color=C["limit"], lw=0.8, ls="--", label=f"limit {max_seating_velocity:g} m/s")
    speed = result.response.omega * 60 / TWO_PI
    ax.axvline(speed, color=C["ink"], lw=0.8, label=f"case speed {speed:g} rpm")
    for what, at, colour in (
        ("float", result.float_speed_rpm, C["limit"]),
        ("bounce", result.bounce_speed_rpm, C["warn"]),
    ):
        if math.isfinite(at):
            ax.axvline(at, color=colour, lw=1.0, ls=":", label=f"{what} at {at:.0f} rpm")
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel("seating velocity (m/s)")
    top = result.seating_curve_top_rpm
    top = min(top, float(rpm.max()) if rpm.size else top)
    ax.set_xlim(0.0, top)
    shown = v[(rpm <= top) & np.isfinite(v)]
    if shown.size:
        ax.set_ylim(0.0, 1.15 * max(float(shown.max()), max_seating_velocity or 0.0))
    ax.set_title("the valve landing on its seat, against cam speed", fontsize=9)
    legend_above_data(ax, fontsize=7, ncol=2)


def plot_rocker_ratio(ax: Axes, result: ValvetrainResult) -> None:
    """The rocker's instantaneous ratio (d valve lift / d follower lift at the cam's lift) against cam angle, around
    the valve event, its least and largest marked."""
    resp = result.response
    ratios = result.ratios
    ax.plot(resp.theta_deg, ratios, color=C["dyn"], lw=1.2, label="ratio at the cam's lift")
    ax.axhline(result.ratio, color=C["kin"], lw=0.8, ls="--", label=f"at peak lift {result.ratio:.4g}")
    lo, hi = float(ratios.min()), float(ratios.max())
    pad = max(0.02, 0.15 * (hi - lo))
    ax.set_ylim(lo - pad, hi + pad)
    ax.set_ylabel("rocker ratio")
    ax.set_xlabel("cam angle (deg)")
    deg_ticks(ax, 60.0)
    ax.set_xlim(*_event_window(resp))
    ax.set_title(f"rocker ratio: {lo:.4g} to {hi:.4g}", fontsize=9)
    legend_above_data(ax, fontsize=7)
