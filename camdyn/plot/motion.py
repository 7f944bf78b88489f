"""The follower motion drawn: lift, velocity, acceleration and jerk against the cam angle (SVAJ)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes

from .._core.kinds import kind_of_motion
from .._core.units import RPM
from ._common import C, deg_ticks, mark_breaks

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.review import MotionSamples
    from ..model.geometry import ContourFit
    from ..model.motion import MotionFit


def display_scale(unit: str) -> float:
    """Motion unit -> the unit figures show it in (the lift unit): mm stays mm, an arm's swing in rad is in deg."""
    return kind_of_motion(unit).lift_per_motion


def display_unit(unit: str) -> str:
    return kind_of_motion(unit).lift_unit


def svaj_quantities(unit: str) -> list[tuple[str, str]]:
    """(name, per-radian display unit) of s, s', s'', s''' for a motion in ``unit`` ("mm" or "rad")."""
    kind = kind_of_motion(unit)
    u, sym = kind.lift_unit, kind.lift_symbol
    return [
        (f"{kind.lift_word} {sym}", f"{u}"),
        (f"velocity d{sym}/d\u03b8", f"{u}/rad"),
        (f"acceleration d\u00b2{sym}/d\u03b8\u00b2", f"{u}/rad\u00b2"),
        (f"jerk d\u00b3{sym}/d\u03b8\u00b3", f"{u}/rad\u00b3"),
    ]


def _time_units(unit: str, speed_rpm: float) -> list:
    """Per-radian (left axes) -> time units at the cam speed (right axes): (label, factor), None for s."""
    w = speed_rpm * RPM
    if kind_of_motion(unit).rotary:
        return [
            None,
            ("rad/s", math.pi / 180 * w),
            ("rad/s\u00b2", math.pi / 180 * w**2),
            ("rad/s\u00b3", math.pi / 180 * w**3),
        ]
    return [None, ("mm/s", w), ("m/s\u00b2", w**2 / 1000.0), ("m/s\u00b3", w**3 / 1000.0)]


def plot_svaj(
    axes: Sequence[Axes], samples: MotionSamples, *, speed_rpm: float | None = None, headroom: float = 1.0
) -> None:
    """Draw s, s', s'', s''' (per radian of cam angle) on four ``axes`` sharing x, with the breaks dotted. With
    ``speed_rpm``: the same curves in time units on the right axes and the time along the top. ``headroom``:
    the space above the lift curve, in units of its margin (room for labels)."""
    th, vals = samples.theta_deg, samples.values * display_scale(samples.unit)
    names = svaj_quantities(samples.unit)
    right = _time_units(samples.unit, speed_rpm) if speed_rpm is not None else [None] * 4
    for i, ax in enumerate(axes):
        ax.plot(th, vals[i], color=C["dyn"], lw=1.3)
        ax.axhline(0.0, color="#888888", lw=0.6, zorder=0.6)
        mark_breaks(ax, samples.breaks_deg)
        ax.set_ylabel(f"{names[i][0]}\n({names[i][1]})")
        if (scale := right[i]) is not None:
            label, k = scale
            sec = ax.secondary_yaxis("right", functions=(lambda y, k=k: y * k, lambda y, k=k: y / k))
            sec.set_ylabel(f"at {speed_rpm:g} rpm ({label})", color=C["grey"])
            sec.tick_params(colors=C["grey"])
        if i < 3:
            ax.tick_params(labelbottom=False)
        lo, hi = float(np.min(vals[i])), float(np.max(vals[i]))
        pad = 0.12 * max(hi - lo, 1e-12)
        ax.set_ylim(lo - pad, hi + pad * (headroom if i == 0 else 1.0))
    deg_ticks(axes[-1], 30.0)
    axes[-1].set_xlabel("cam angle \u03b8 (deg)")
    if speed_rpm is not None:
        period_ms = 60000.0 / speed_rpm
        top = axes[0].secondary_xaxis(
            "top", functions=(lambda d: np.asarray(d) / 360.0 * period_ms, lambda t: np.asarray(t) / period_ms * 360.0)
        )
        top.set_xlabel(f"time at {speed_rpm:g} rpm (ms)", color=C["grey"])
        top.tick_params(colors=C["grey"])


def plot_fit(ax_lift: Axes, ax_residual: Axes, fit: MotionFit, contour: ContourFit | None = None) -> None:
    """A lift table's data points on the lift panel and the fit's residuals (data - fit) against cam angle, with
    the tolerance where one was asked for (``fit``: :class:`camdyn.model.motion.MotionFit`). With ``contour`` (a
    :class:`camdyn.model.geometry.ContourFit`, a contour case), the residual is the user's data's: the radial
    departure of the outline's points from its fit, against polar angle; the lift panel then marks the lift at
    exact contact with the fitted outline (derived, not measured)."""
    th = np.asarray(fit.theta_deg)
    every = max(1, th.size // 400)  # a few hundred markers: a 3600-point table would paint the curve over
    label = (
        f"{fit.source} data ({th.size} points)"
        if contour is None
        else f"lift at contact with the fitted outline ({th.size} angles)"
    )
    if fit.follower_data is not None:  # a valve's table, ramps added: at the follower
        label = f"{fit.source} data with its ramps, through the rocker ({th.size} points)"
    elif fit.follower_per_data != 1.0:
        label = f"{fit.source} data with its ramps / ratio ({th.size} points)"
    ax_lift.plot(
        th[::every],
        fit.data_at_follower[::every],
        ".",
        ms=2.2,
        color=C["limit"],
        alpha=0.7,
        label=label,
        zorder=4,
    )
    ax_lift.legend(fontsize=7, loc="upper right")
    shown_fit = fit if contour is None else contour  # whose residuals the panel draws
    if contour is not None:
        x, at, where = contour.angle_deg, contour.max_residual_at_polar_deg, "polar angle"
        what = f"outline ({contour.point_count} points) - fit, radial"
    else:
        x, at, what, where = th, fit.max_residual_at_deg, "data - fit", "cam angle"
    res, unit = shown_fit.residual, shown_fit.unit
    scale, shown = (1000.0, "\u00b5m") if unit == "mm" and np.max(np.abs(res)) < 0.5 else (1.0, unit)
    ax_residual.plot(x, res * scale, lw=0.7, color=C["limit"])
    ax_residual.axhline(0.0, color="#888888", lw=0.6)
    if contour is None and fit.tolerance is not None:
        for sign in (-1, 1):
            ax_residual.axhline(sign * fit.tolerance * scale, color=C["grey"], lw=0.8, ls="--")
    ax_residual.set_ylabel(f"{'data' if contour is None else 'radial'} - fit\n({shown})")
    ax_residual.set_title(
        f"{what}: largest {shown_fit.max_residual * scale:.3g} {shown} at {where} {at:.1f}\u00b0, rms "
        f"{shown_fit.rms_residual * scale:.3g} {shown}",
        fontsize=8,
    )
    deg_ticks(ax_residual, 45.0)
