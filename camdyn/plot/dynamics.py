"""The dynamics drawn: contact force, follower displacement and vibration over a revolution, and the least
contact force against cam speed."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes

from .._core.kinds import kind_of_motion
from .._core.results import Unavailable
from .._core.units import RPM
from ..model.dynamics import Response
from ._common import C, deg_ticks, legend_above_data, legend_clear, mark_breaks, shade_separations
from .motion import display_scale, display_unit

if TYPE_CHECKING:  # the results' types: a command that draws one loads no other's design module
    from ..design.review import Review


def flights_by_gap(response: Response) -> list:
    """The response's separations, the largest gap first."""
    return sorted(response.separations, key=lambda s: -s.max_gap)


def plot_contact_force(
    ax: Axes,
    response: Response,
    *,
    colour: str = C["dyn"],
    title: str | None = None,
    breaks_deg: Sequence[float] = (),
    legend: bool = True,
    label: str | None = None,
    mark_least: bool = True,
) -> None:
    """The interface force (N) over a revolution, dynamic against kinematic, shaded exactly where the force is
    zero; marked: where the follower leaves the cam (a triangle per flight) and each impact's peak force, or the
    least force (``mark_least``: not where another model's least is the one judged, a valvetrain's). What the marks
    mean is in the legend (no label on the plot covers the curve). ``response``: forces in N (as
    :class:`~camdyn.design.checks.CheckReport` holds it); ``label``: the dynamic curve's. ``legend=False``: the
    caller places the legend (:func:`~camdyn.plot.legend_above_data` once the y limits are final)."""
    th = response.theta_deg
    ax.plot(th, response.kinematic_force, color=C["kin"], lw=1.0, ls="--", label="kinematic (rigid, never leaves)")
    ax.plot(th, response.force, color=colour, lw=1.3, label=label or f"dynamic ({response.model})")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    shade_separations(ax, response, label=True)
    mark_breaks(ax, breaks_deg)
    flights = response.flights
    if flights:
        _mark_flights(ax, response, colour)
    elif mark_least:
        i = int(np.argmin(response.force))
        ax.plot(
            th[i],
            response.force[i],
            "o",
            color=colour,
            ms=4,
            label=f"least {response.force[i]:.3g} N at {th[i]:.1f}\u00b0",
        )
    ax.set_ylabel("interface force (N)")
    ax.set_title(title if title is not None else f"interface force at {response.omega / RPM:.4g} rpm", fontsize=9)
    if legend:
        legend_above_data(ax, fontsize=7, ncol=2)


def flight_summary(response: Response) -> str:
    """Flights and impacts in words: "3 flights (leaves the cam first at 65.2\u00b0), 3 impacts up to 1533 N"."""
    flights, impacts = response.flights, response.impacts
    if not flights:
        return "none"
    first = min(flights, key=lambda f: f.leave_deg).leave_deg
    n = len(flights)
    text = f"{n} flight{'s' if n > 1 else ''} (first leaves the cam at {first:.1f}\u00b0)"
    if not impacts:
        return text + ", never back on the cam"
    peak = response.max_impact_force
    strength = f" up to {peak:.4g} N" if math.isfinite(peak) else " (rigid: impulsive)"
    return text + f", {len(impacts)} impact{'s' if len(impacts) > 1 else ''}{strength}"


def _mark_flights(ax, response: Response, colour: str) -> None:
    """A triangle on the zero line where each flight leaves the cam, a cross on each impact's peak force."""
    flights, impacts = response.flights, response.impacts
    n = len(flights)
    ax.plot(
        [f.leave_deg for f in flights],
        [0.0] * n,
        "v",
        color=colour,
        ms=5,
        zorder=6,
        clip_on=False,
        label=f"leaves the cam ({n} flight{'s' if n > 1 else ''})",
    )
    hits = [i for i in impacts if math.isfinite(i.peak_force)]
    if hits:
        top = max(hits, key=lambda i: i.peak_force)
        ax.plot(
            [i.peak_deg for i in hits],
            [i.peak_force for i in hits],
            "x",
            color=C["limit"],
            ms=5,
            mew=1.2,
            zorder=6,
            label=f"impact ({len(hits)}), largest {top.peak_force:.4g} N at {top.peak_deg:.1f}\u00b0",
        )


def plot_displacement(
    ax: Axes, response: Response, *, unit: str = "mm", speed_rpm: float | None = None, breaks_deg: Sequence[float] = ()
) -> None:
    """The follower's displacement x against the cam's s over a revolution (``unit``: the motion's, "mm" or
    "rad"; an arm's swing is drawn in degrees), the separations shaded."""
    k = display_scale(unit)
    rpm = speed_rpm if speed_rpm is not None else response.omega / RPM
    ax.plot(response.theta_deg, response.s * k, color=C["kin"], ls="--", lw=1.0, label="kinematic s (cam)")
    ax.plot(response.theta_deg, response.x * k, color=C["dyn"], lw=1.2, label=f"follower x at {rpm:g} rpm")
    shade_separations(ax, response)
    mark_breaks(ax, breaks_deg)
    ax.set_ylabel(f"{'swing' if kind_of_motion(unit).rotary else 'displacement'} ({display_unit(unit)})")
    ax.set_title("follower displacement, dynamic and kinematic", fontsize=9)
    legend_above_data(ax, fontsize=7, ncol=2)


def plot_vibration(
    ax: Axes,
    curves: Sequence[tuple[Response, str, str]],
    *,
    unit: str = "mm",
    breaks_deg: Sequence[float] = (),
) -> None:
    """The vibratory response x - s over a revolution; ``curves``: (response, colour, label) each, the first
    one's separations shaded. Translating: in um where it stays under half a millimetre."""
    k = display_scale(unit)
    peak = max(float(np.max(np.abs(r.x - r.s))) for r, _, _ in curves) * k
    if kind_of_motion(unit).rotary:
        scale, vu = k, display_unit(unit)
    else:
        scale, vu = (1000.0, "\u00b5m") if peak < 0.5 else (1.0, "mm")
    for r, col, lab in curves:
        ax.plot(r.theta_deg, (r.x - r.s) * scale, color=col, lw=1.1, label=lab)
    if peak == 0.0:
        ax.text(
            0.5,
            0.6,
            "rigid follower in contact all round: x = s, no vibratory response",
            transform=ax.transAxes,
            ha="center",
            va="center",
            size=8,
            color=C["grey"],
        )
    ax.axhline(0.0, color=C["ink"], lw=0.6)
    shade_separations(ax, curves[0][0], label=True)
    mark_breaks(ax, breaks_deg)
    ax.set_ylabel(f"x \u2212 s ({vu})")
    ax.set_title("vibratory response x \u2212 s (negative: the train is compressed)", fontsize=9)
    deg_ticks(ax, 30.0)
    legend_above_data(ax, fontsize=7, ncol=3)
    ax.set_xlabel("cam angle \u03b8 (deg)")


def plot_force_vs_speed(ax: Axes, review: Review) -> None:
    """The least contact force against cam speed (kinematic; the frequency-domain steady state of a compliant
    train), the jump speeds, speed_margin x speed, min_contact_force and the check's operating point."""
    sw, chk = review.force_vs_speed, review.check
    if isinstance(sw, Unavailable):  # a form-closed cam: it cannot jump, there is no speed to hold to
        ax.text(0.5, 0.5, sw.reason, ha="center", va="center", wrap=True, transform=ax.transAxes)
        ax.set_axis_off()
        return
    rpm = chk.speed_rpm
    v = sw.speeds_rpm
    ax.plot(v, sw.kinematic_N, color=C["kin"], ls="--", lw=1.0, label="kinematic (rigid)")
    jd, jk = chk.dynamic.jump_speed_rpm, chk.kinematic.jump_speed_rpm
    if sw.dynamic_N is not None:
        lin = sw.dynamic_N
        ok = v <= (jd if jd is not None else np.inf)
        ax.plot(v[ok], lin[ok], color=C["dyn"], lw=1.4, label="dynamic steady state (exact until separation)")
        if (~ok).any():
            ax.plot(
                v[~ok],
                lin[~ok],
                color=C["dyn"],
                lw=0.9,
                ls=":",
                alpha=0.7,
                label="linear model past the jump (not valid)",
            )
    if sw.valve_event is not None:  # what a valvetrain's contact_force and float speed are judged by
        ax.plot(*sw.valve_event, color=C["margin"], lw=1.4, label="two masses, valve event")
    ax.axhline(0.0, color=C["ink"], lw=0.8)
    mf = chk.case.limits.min_contact_force
    if mf:
        ax.axhline(mf, color=C["limit"], ls="--", lw=0.8, label=f"min_contact_force {mf:g} N")
    top = max(float(np.max(sw.kinematic_N)), mf) * 1.15
    floor = min(float(np.min(sw.kinematic_N)), float(np.min(sw.dynamic_N)) if sw.dynamic_N is not None else 0.0)
    ymin, ymax = max(floor, -0.8 * top) - 0.05 * top, top
    _jump_speeds(ax, jd, jk, v[-1], "dynamic jump speed" if sw.valve_event is None else "valve float speed")
    ax.axvline(
        review.margin_rpm,
        color=C["margin"],
        lw=0.9,
        ls="-.",
        label=f"speed_margin {review.case.limits.speed_margin:g} \u00d7 speed = {review.margin_rpm:g} rpm",
    )
    ax.plot(
        rpm,
        chk.dynamic.min_contact_force_N,
        "o",
        color=C["dyn"] if chk.verdict == "pass" else C["fail"],
        ms=6,
        zorder=5,
        label=f"operating point ({rpm:g} rpm, {chk.response.domain} domain)",
    )
    ax.set_ylim(ymin, ymax)
    ax.set_xlim(0.0, v[-1])
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel("least interface force (N)")
    ax.set_title("least interface force against cam speed", fontsize=9)
    legend_clear(ax, fontsize=6.5)


def _jump_speeds(ax, jd: float | None, jk: float | None, v_top: float, name: str = "dynamic jump speed") -> None:
    """The dynamic jump speed (the range past it shaded) and the rigid one where it differs, named in the legend
    (``name``: a valvetrain's is its float speed)."""
    if jd is not None and jd <= v_top:
        ax.axvspan(jd, v_top, color=C["limit"], alpha=0.08, lw=0)
        ax.axvline(jd, color=C["limit"], lw=1.0, label=f"{name} {jd:.0f} rpm (shaded past it)")
    if jk is not None and jk <= v_top and (jd is None or abs(jk - jd) > 0.02 * v_top):
        ax.axvline(jk, color=C["kin"], lw=0.8, ls="--", label=f"rigid jump speed {jk:.0f} rpm")
